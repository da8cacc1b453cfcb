"""Inputs of the core runtime: files the host names (only regular files, never
blocking, bounded), the INI (read whole, parsed without the core's lock, validated),
numbers under a decimal-comma locale, parameter bounds, numbers of a program that
overflow, the tool number in m_planeTool, and the names of statuses in error texts.
Risky calls (FIFOs, locales) run in a subprocess with a timeout: a defect shows as a
failure, never as a hung suite."""
import ctypes
import math
import os
import re
import subprocess
import textwrap
from ctypes import byref
from pathlib import Path

import pytest

from compiler_host import Host, last_error
from sf_tch import abi

ERR_FILE_OPEN, ERR_INI_OPEN, ERR_BAD_STATUS, ERR_FILE_TOO_LARGE = 1, 3, 9, 12
ERR_NOT_REGULAR_FILE, ERR_NOT_FINITE, ERR_OUT_OF_RANGE, ERR_INI_VALUE = 13, 14, 15, 16
ERR_NUMBER_OVERFLOW, ERR_MATH_DOMAIN, ERR_NOT_FINITE_RESULT = 108, 204, 207

HANG_TIMEOUT = 30       # seconds: far beyond any of these calls, short for a hung one


@pytest.fixture
def host(tmp_path):
    h = Host(2, tmp_path)
    yield h
    h.close()


def _error(lib, core):
    """The error of the call just refused."""
    err = last_error(lib, core, refused_call=True)
    assert err is not None, "no error recorded"
    return err


def _run_isolated(run_python, code, **kw):
    """Runs code in a fresh interpreter with a timeout; a hang is a failure."""
    try:
        return run_python(code, timeout=HANG_TIMEOUT, **kw)
    except subprocess.TimeoutExpired:
        pytest.fail(f"the call did not return within {HANG_TIMEOUT} s")


# ------------------------------------------------------------------ files

def test_compile_from_fifo_is_refused_at_once(run_python, tmp_path):
    """A FIFO without a writer neither blocks the caller nor the worker; the error names
    the file."""
    fifo = tmp_path / "prog.nc"
    os.mkfifo(fifo)
    out = _run_isolated(run_python, f"""
        import ctypes
        from sf_tch import abi, library
        lib = library.load(LIB_PATH)
        rc = lib.ToolChainCore_CompileFromFile(0, {str(fifo).encode()!r})
        info = abi.CALLBACK_INFO()
        print(rc, lib.ToolChainCore_GetLastCallError(0, ctypes.byref(info)), info.stringId)
        print(info.m_fullError.decode())
        print(lib.ToolChainCore_StatusCNC(0), lib.ToolChainCore_DestroyCNC(0))
    """).stdout.splitlines()
    assert out[0].split() == ["-1", "1", str(ERR_NOT_REGULAR_FILE)]
    assert out[1] == f"'{fifo}' is not a regular file"
    assert out[2].split() == ["0", "0"]


@pytest.mark.parametrize("make", ["directory", "device"])
def test_compile_from_other_file_types_is_refused(fresh_core, tmp_path, make):
    lib = fresh_core
    path = tmp_path if make == "directory" else Path("/dev/null")
    assert lib.ToolChainCore_CompileFromFile(0, str(path).encode()) == -1
    err = _error(lib, 0)
    assert err[0] == ERR_NOT_REGULAR_FILE and str(path) in err[3]
    assert lib.ToolChainCore_StatusCNC(0) == 0


def test_compile_from_file_larger_than_1_gib_is_refused(fresh_core, tmp_path):
    big = tmp_path / "big.nc"
    with open(big, "wb") as f:          # sparse: no disk space used
        f.truncate((1 << 30) + 1)
    assert fresh_core.ToolChainCore_CompileFromFile(0, str(big).encode()) == -1
    err = _error(fresh_core, 0)
    assert err[0] == ERR_FILE_TOO_LARGE and str(big) in err[3]


def test_compile_from_file_reads_every_byte(fresh_core, tmp_path):
    """A file far larger than one read of the loop: its last line is compiled."""
    lines = [f"G1 X{i % 97}.{i % 10} Y{i % 89}\n" for i in range(40000)] + ["G1 X1234.5 Y-77\n"]
    path = tmp_path / "long.nc"
    path.write_text("".join(lines))
    lib = fresh_core
    assert lib.ToolChainCore_CompileFromFile(0, str(path).encode()) == 0
    while lib.ToolChainCore_StatusCNC(0) == 1:
        pass
    assert last_error(lib, 0) is None
    info = abi.GCODE_INFO()
    assert lib.ToolChainCore_GetGCodeSizeInfo(0, byref(info)) == 0
    size = info.m_size[0]
    assert (size.m_endPos.x, size.m_endPos.y) == (1234.5, -77.0)
    assert (size.m_minimalPos.y, size.m_maximalPos.y) == (-77.0, 88.0)


# ------------------------------------------------------------------ INI

def _load_ini(lib, path, core=0):
    return lib.ToolChainCore_LoadFromIni(core, str(path).encode(), None)


@pytest.mark.parametrize("kind", ["missing", "directory", "device"])
def test_load_from_ini_of_what_is_not_a_file_returns_1(fresh_core, tmp_path, kind):
    path = {"missing": tmp_path / "none.ini", "directory": tmp_path, "device": Path("/dev/null")}[kind]
    assert _load_ini(fresh_core, path) == abi.TOOL_CHAIN_XEXEC
    err = _error(fresh_core, 0)
    assert str(path) in err[3]
    assert err[0] == (ERR_INI_OPEN if kind == "missing" else ERR_NOT_REGULAR_FILE)


def test_load_from_ini_on_a_fifo_neither_blocks_nor_holds_the_lock(run_python, tmp_path):
    """LoadFromIni on a FIFO returns 1 at once, and GetPos / GetLastError never wait
    meanwhile."""
    fifo = tmp_path / "cnc.ini"
    os.mkfifo(fifo)
    out = _run_isolated(run_python, f"""
        import ctypes, threading
        from sf_tch import abi, library
        lib = library.load(LIB_PATH)
        result = {{}}
        loader = threading.Thread(target=lambda: result.setdefault(
            'ini', lib.ToolChainCore_LoadFromIni(0, {str(fifo).encode()!r}, None)), daemon=True)
        loader.start()
        def poll():
            pos = abi.SIMPLE_GM_PARAMS()
            result['getpos'] = lib.ToolChainCore_GetPos(0, 0, ctypes.byref(pos), None)
            result['lasterr'] = lib.ToolChainCore_GetLastError(0, ctypes.byref(abi.CALLBACK_INFO()))
        poller = threading.Thread(target=poll, daemon=True)
        poller.start()
        poller.join(10)
        loader.join(10)
        info = abi.CALLBACK_INFO()
        lib.ToolChainCore_GetLastCallError(0, ctypes.byref(info))
        print(result.get('getpos'), result.get('ini'), info.stringId)
        print(info.m_fullError.decode())
        import os; os._exit(0)         # a blocked thread must not keep the process
    """).stdout.splitlines()
    assert out[0].split() == ["0", "1", str(ERR_NOT_REGULAR_FILE)]
    assert out[1] == f"'{fifo}' is not a regular file"


def test_ini_line_longer_than_any_buffer_stays_one_line(fresh_core, tmp_path):
    """The old reader cut lines at 4095 bytes and read the rest as a line of its own:
    a value ending in 'correction0=0.7' must not set correction0."""
    ini = tmp_path / "long.ini"
    head = "comment = "
    ini.write_text("[GCodeParameters]\n" + head + "x" * (4095 - len(head)) + "correction0=0.7\ncorrection1 = 0.25\n")
    assert _load_ini(fresh_core, ini) == 0
    p = abi.GCODE_PARAMETERS()
    fresh_core.ToolChainCore_GetGCodeParameters(0, byref(p))
    assert p.correction[0].size == 0.0
    assert p.correction[1].size == 0.25


@pytest.mark.parametrize("value, number, why", [
    ("nan", ERR_INI_VALUE, "correction0 = 'nan' is not a number"),
    ("0,5", ERR_INI_VALUE, "correction0 = '0,5' is not a number"),
    ("abc", ERR_INI_VALUE, "correction0 = 'abc' is not a number"),
    ("1e300", ERR_INI_VALUE, "GCODE_PARAMETERS.correction[0].size = 1e+300 is outside <-1e+06, 1e+06>"),
])
def test_bad_ini_value_names_key_and_line_and_applies_nothing(fresh_core, tmp_path, value, number, why):
    ini = tmp_path / "bad.ini"
    ini.write_text(f"[CNC]\nDriver=other\n[GCodeParameters]\ncorrection1 = 0.25\ncorrection0 = {value}\n")
    before = abi.GCODE_PARAMETERS()
    fresh_core.ToolChainCore_GetGCodeParameters(0, byref(before))
    assert _load_ini(fresh_core, ini) == abi.TOOL_CHAIN_XEXEC
    err = _error(fresh_core, 0)
    assert err[0] == number and err[1] == 5
    assert err[3].startswith(f"INI file '{ini}' line 5: [GCodeParameters] correction0")
    assert why in err[3]
    after = abi.GCODE_PARAMETERS()
    fresh_core.ToolChainCore_GetGCodeParameters(0, byref(after))
    assert bytes(after) == bytes(before)        # correction1 of line 4 not applied either


def test_bad_ini_integer_is_refused(fresh_core, tmp_path):
    ini = tmp_path / "bad.ini"
    ini.write_text("[GCodeParameters]\nabsMode = 1.5\n")
    assert _load_ini(fresh_core, ini) == abi.TOOL_CHAIN_XEXEC
    assert "absMode = '1.5' is not a number" in _error(fresh_core, 0)[3]


# ------------------------------------------------------------------ parameter bounds

def _params(lib, core=0):
    p = abi.GCODE_PARAMETERS()
    assert lib.ToolChainCore_GetGCodeParameters(core, byref(p)) == 0
    return p


@pytest.mark.parametrize("radius, shown", [(math.nan, "nan is not a finite number"),
                                           (-math.inf, "-inf is not a finite number"),
                                           (1e300, "1e+300 is outside <-1e+06, 1e+06>")])
def test_set_gcode_parameters_refuses_a_bad_radius(fresh_core, radius, shown):
    """A NaN or infinite radius: refused, error naming the field, nothing changed; the
    compilation then runs with the radius from before."""
    lib = fresh_core
    before = _params(lib)
    p = _params(lib)
    for k in range(8):
        p.correction[k].size = radius
    assert lib.ToolChainCore_SetGCodeParameters(0, byref(p)) == -1
    err = _error(lib, 0)
    assert err[0] in (ERR_NOT_FINITE, ERR_OUT_OF_RANGE)
    assert err[3] == f"GCODE_PARAMETERS.correction[0].size = {shown}"
    assert bytes(_params(lib)) == bytes(before)


def _set(path, value):
    """A setter of GCODE_PARAMETERS field `path` (e.g. 'motion[0].feed', 'tolerance[4]')."""
    def change(p):
        obj, parts = p, path.split(".")
        for part in parts[:-1]:
            base, index = re.fullmatch(r"(\w+)\[(\d+)\]", part).groups()
            obj = getattr(obj, base)[int(index)]
        last = re.fullmatch(r"(\w+)(?:\[(\d+)\])?", parts[-1]).groups()
        if last[1] is None:
            setattr(obj, last[0], value)
        else:
            getattr(obj, last[0])[int(last[1])] = value
    return change


@pytest.mark.parametrize("field, value, text", [
    ("motion[0].feed", 0.0, "GCODE_PARAMETERS.motion[0].feed = 0 is outside <0, 1e+09>"),
    ("motion[3].acc", -1.0, "GCODE_PARAMETERS.motion[3].acc = -1 is outside <0, 1e+09>"),
    ("motion[7].dec", 2e9, "GCODE_PARAMETERS.motion[7].dec = 2e+09 is outside <0, 1e+09>"),
    ("tolerance[4]", -0.001, "GCODE_PARAMETERS.tolerance[4] = -0.001 is outside <0, 1e+06>"),
    ("startAngle", 400.0, "GCODE_PARAMETERS.startAngle = 400 is outside <0, 360>"),
    ("axisLimits[9].maxDec", math.inf, "GCODE_PARAMETERS.axisLimits[9].maxDec = inf is not a finite number"),
    ("overrideInc", math.nan, "GCODE_PARAMETERS.overrideInc = nan is not a finite number"),
])
def test_set_gcode_parameters_bounds(fresh_core, field, value, text):
    lib = fresh_core
    p = _params(lib)
    _set(field, value)(p)
    assert lib.ToolChainCore_SetGCodeParameters(0, byref(p)) == -1
    assert _error(lib, 0)[3] == text


def test_set_gcode_parameters_accepts_the_edges_of_the_bounds(fresh_core):
    lib = fresh_core
    p = _params(lib)
    p.correction[2].size = -1e6
    p.motion[1].feed = 1e9
    p.tolerance[9] = 0.0
    p.endAngle = 360.0
    assert lib.ToolChainCore_SetGCodeParameters(0, byref(p)) == 0
    assert bytes(_params(lib)) == bytes(p)


@pytest.mark.parametrize("field, axis, value, text", [
    ("minCoords", "x", math.nan, "MACHINE_PARAMETERS.minCoords.x = nan is not a finite number"),
    ("maxCoords", "o", 2e6, "MACHINE_PARAMETERS.maxCoords.o = 2e+06 is outside <-1e+06, 1e+06>"),
    ("backlash", "z", -0.5, "MACHINE_PARAMETERS.backlash.z = -0.5 is outside <0, 1e+06>"),
])
def test_set_machine_parameters_bounds(fresh_core, field, axis, value, text):
    lib = fresh_core
    m = abi.MACHINE_PARAMETERS()
    lib.ToolChainCore_GetMachineParameters(0, byref(m))
    before = bytes(m)
    setattr(getattr(m, field), axis, value)
    assert lib.ToolChainCore_SetMachineParameters(0, byref(m)) == -1
    assert _error(lib, 0)[3] == text
    lib.ToolChainCore_GetMachineParameters(0, byref(m))
    assert bytes(m) == before


def test_reset_cnc_refuses_non_finite_coordinates(fresh_core):
    lib = fresh_core
    coords = (ctypes.c_double * 10)(*([1.0] * 9 + [math.inf]))
    assert lib.ToolChainCore_ResetCNC(0, 0, 10, coords) == -1
    assert lib.ToolChainCore_ResetCNC(0, 0, 9, coords) == 0       # the tenth is not taken
    assert lib.ToolChainCore_ResetCNC(0, 1, 10, coords) == 0      # regime 1 takes none


def test_set_gcode_run_time_refuses_non_finite(fresh_core):
    lib = fresh_core
    idx = lib.ToolChainCore_FileToIdx(0, b"timed.nc")
    assert lib.ToolChainCore_SetGCodeRunTime(0, idx, math.inf) == -1
    assert lib.ToolChainCore_SetGCodeRunTime(0, idx, math.nan) == -1
    assert lib.ToolChainCore_SetGCodeRunTime(0, idx, 12.5) == 0
    assert lib.ToolChainCore_GetGCodeRunTime(0, idx) == 12.5


def test_set_user_params_refuses_non_finite(fresh_core):
    values = (ctypes.c_double * 100)(*([1.0] * 99 + [math.nan]))
    assert fresh_core.ToolChainCore_SetUserParams(0, values, 100) == -1
    values[99] = 2.0
    assert fresh_core.ToolChainCore_SetUserParams(0, values, 100) == 0


# ------------------------------------------------------------------ numbers in programs

def test_number_that_overflows_is_an_error_on_its_line_and_column(host):
    """A number too large for a double: error 108 on its line, at its column."""
    r = host.compile("G1 X1 F100\nG0 X1" + "0" * 320 + "\n", run=False)
    assert r.error is not None and r.error[0] == ERR_NUMBER_OVERFLOW and r.error[1] == 2
    assert "at column 5 is too large" in r.error[3]
    r = host.compile("G1 X1 F100\nG1 Y(2 + 1" + "0" * 320 + ")\n", run=False)
    assert r.error[0] == ERR_NUMBER_OVERFLOW and r.error[1] == 2
    assert "at column 10 is too large" in r.error[3]


@pytest.mark.parametrize("code, number", [
    ("P1 = 10^200 * 10^200\n", ERR_NOT_FINITE_RESULT),
    ("P1 = 10^308 + 10^308\n", ERR_NOT_FINITE_RESULT),
    ("P1 = -10^308 - 10^308\n", ERR_NOT_FINITE_RESULT),
    ("P1 = 10^200\nG1 X(P1 * P1)\n", ERR_NOT_FINITE_RESULT),
    ("G1 X(10^400)\n", ERR_MATH_DOMAIN),
])
def test_expression_without_a_finite_value_is_an_error(host, code, number):
    r = host.compile("G1 X1 F100\n" + code, run=False)
    assert r.error is not None and r.error[0] == number
    assert r.error[1] == code.count("\n") + 1         # the last line of the program


@pytest.mark.parametrize("value", [math.nan, math.inf])
def test_non_finite_plc_double_is_an_error(host, value):
    """The PLC memory is the host's: a NaN or infinity read from it is refused."""
    from sf_tch.library import plc_memory
    memory = plc_memory(host.lib)
    address = 4000
    saved = bytes(memory[address:address + 8])
    ctypes.memmove(ctypes.addressof(memory) + address, ctypes.byref(ctypes.c_double(value)), 8)
    try:
        r = host.compile(f"G1 X1 F100\nG1 X(ReadPLCDouble({address}))\n", run=False)
    finally:
        ctypes.memmove(ctypes.addressof(memory) + address, saved, 8)
    assert r.error is not None and r.error[0] == ERR_NOT_FINITE_RESULT and r.error[1] == 2
    assert "ReadPLCDouble" in r.error[3]


def test_large_finite_values_still_compile(host):
    r = host.compile("P1 = 10^200 * 10^100\nG1 X1 F100\n")
    assert r.error is None


def _all_finite(value):
    """Every number of a numpy record (nested structures included) is finite."""
    import numpy as np
    if value.dtype.names:
        return all(_all_finite(value[name]) for name in value.dtype.names)
    return bool(np.all(np.isfinite(value))) if value.dtype.kind == "f" else True


def test_largest_words_give_only_finite_numbers():
    """Words up to 1e30 compile; every number the driver, GetPos and the size info
    see is finite (floats of m_pars, arc radii, summed lengths)."""
    from sf_tch.core import Core
    code = ("G1 X(10^30) Y0 F(10^30)\n"
            "G2 X(-10^30) Y0 I(-10^30) J0\n"
            "G1 X(-10^30) Y(-10^30)\nG0 X(10^30)\n")
    with Core(1) as core:
        core.compile_text(code)
        run = core.simulate()
        assert len(run.parts) == 4 and all(_all_finite(part) for part in run.parts)
        pos, enh = core.position()
        info = core.size_info()
    import numpy as np
    for struct in (pos, enh, info):
        assert _all_finite(np.frombuffer(bytes(struct), np.dtype(type(struct)))[0]), type(struct).__name__
    assert enh.m_actPartsLen > 4e30


@pytest.mark.parametrize("tool, high", [(0, 0), (32767, 32767), (32768, 32768), (65535, 65535),
                                        (70000, 65535), (10 ** 9, 65535)])
def test_tool_number_fills_the_high_16_bits_of_m_plane_tool(host, tool, high):
    """m_planeTool (docs/structures.md): low 16 bits the plane (17), high 16 bits the
    tool number (saturated to 16 bits), without an undefined shift."""
    r = host.compile(f"T{tool} M6\nG1 X1 F100\n")
    assert r.error is None
    g = r.g[-1]
    raw = (g.tool << 16 | (g.plane & 0xFFFF)) & 0xFFFFFFFF
    assert raw & 0xFFFF == 17
    assert raw >> 16 == high


# ------------------------------------------------------------------ locale

def test_numbers_do_not_follow_a_decimal_comma_locale(run_python, tmp_path, comma_locale):
    name, env = comma_locale
    ini = tmp_path / "comma.ini"
    ini.write_text("[CNC]\nDriver=offline\n[GCodeParameters]\ncorrection0=0.5\ntolerance0 = 0.0125\n")
    out = _run_isolated(run_python, f"""
        import ctypes, locale, math
        locale.setlocale(locale.LC_ALL, {name!r})
        # the locale is in force for C: libc's own strtod reads only '0'
        libc = ctypes.CDLL(None)
        libc.strtod.restype = ctypes.c_double
        libc.strtod.argtypes = [ctypes.c_char_p, ctypes.c_void_p]
        assert locale.localeconv()['decimal_point'] == ',' and libc.strtod(b"0.5", None) == 0.0
        from sf_tch import abi
        from sf_tch.core import Core, CncError
        with Core(0, ini={str(ini)!r}) as core:
            p = core.params
            print(repr(p.correction[0].size), repr(p.tolerance[0]))
            core.compile_text("G1 X0.30000000000000004 Y12.345678901234567 F1000\\n")
            run = core.simulate()
            print(repr(float(run.parts[-1]['m_e']['x'])), repr(float(run.parts[-1]['m_e']['y'])))
            try:
                core.compile_text("G1 X0 Y0 F100\\nG2 X10 Y0 R2.5\\n")
            except CncError as e:
                print(e.text)
            bad = core.params
            bad.correction[3].size = 2.5e6
            print(core.lib.ToolChainCore_SetGCodeParameters(0, ctypes.byref(bad)))
            print(core.last_error(refused_call=True).text)
    """, env=env).stdout.splitlines()
    assert out[0] == "0.5 0.0125"
    assert out[1] == "0.30000000000000004 12.345678901234567"
    assert out[2] == "Arc radius 2.5 too small for chord 10"
    assert out[3] == "-1"
    assert out[4] == "GCODE_PARAMETERS.correction[3].size = 2.5e+06 is outside <-1e+06, 1e+06>"


# ------------------------------------------------------------------ status names

def _documented_statuses():
    """Every value of enum cnc_status in the installed header."""
    from sf_tch import header_path
    header = Path(header_path()).read_text()
    body = re.search(r"enum cnc_status\s*\{(.*?)\}", header, re.S).group(1)
    return {m.group(1): int(m.group(2)) for m in re.finditer(r"(CNC_STATUS_\w+)\s*=\s*(-?\d+)", body)}


def test_every_documented_status_has_a_name(harness):
    statuses = _documented_statuses()
    assert len(statuses) == 27
    names = {value: harness.cnc_status_name(value) for value in statuses.values()}
    assert all(name and name != "unknown" and "?" not in name for name in names.values()), names
    assert len(set(names.values())) == len(names)        # no two statuses read alike
    assert harness.cnc_status_name(12345) == "unknown"


def test_refused_call_names_the_status(fresh_core):
    """Seen on main: 'StopCNCEx not allowed in status ?'."""
    lib = fresh_core
    assert lib.ToolChainCore_StopCNCEx(0, None) == -1
    err = _error(lib, 0)
    assert err[0] == ERR_BAD_STATUS
    assert err[3] == "StopCNCEx not allowed in status 0 (nothing loaded)"
    assert err[4].split("\n") == ["StopCNCEx", "0", "nothing loaded"]
