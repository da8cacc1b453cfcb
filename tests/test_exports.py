"""Every exported function of tgm_cnc.h: present with the prototypes of sf_tch.abi,
and every argument check of docs/api.md and the header (core index, NULL pointers, counts, names,
callback numbers, statuses), defaults, round trips, logging."""
import ctypes
import shutil
import subprocess
from ctypes import byref

import pytest

from sf_tch import abi

BAD_CORES = (3, 99, 0xFFFFFFFF)

VENDOR_INI = ("[Modules]\nCompiler0=SF_Compiler\nExecutor0=SF_Executor\nCalculator0=SF_Calc\nCNC0=SF_CNC\n"
              "[CNC]\nDriver=offline\n")


def last_error(lib, idx=0):
    """The error of the last refused call (GetLastCallError); GetLastError keeps the
    error of the last compilation or run."""
    info = abi.CALLBACK_INFO()
    rc = lib.ToolChainCore_GetLastCallError(idx, byref(info))
    return rc, info


def other_error(lib, idx=0):
    """Records an error that is not 'not implemented' (nothing compiled to start)."""
    assert lib.ToolChainCore_StartCNCEx(idx, abi.RUN_SIMULATION, None) == -1
    rc, info = last_error(lib, idx)
    assert rc == 1 and b"not implemented" not in info.m_fullError


# ------------------------------------------------------------------ exports

def test_every_export_is_a_dynamic_symbol(lib_path):
    names = {name for name, _, _ in abi.FUNCTIONS}
    assert len(names - set(abi.EXTENSION_FUNCTIONS)) == 40
    nm = shutil.which("nm")
    if nm is None:
        pytest.skip("nm not available")
    out = subprocess.run([nm, "-D", "--defined-only", lib_path], capture_output=True, text=True, check=True).stdout
    functions = {line.split()[-1] for line in out.splitlines() if line.split()[-2:-1] == ["T"]}
    assert names <= functions, names - functions


def test_loader_applies_the_prototypes(lib):
    for name, restype, argtypes in abi.FUNCTIONS:
        fn = getattr(lib, name)
        assert fn.restype is restype, name
        assert tuple(fn.argtypes) == tuple(argtypes), name


# ------------------------------------------------------------------ bad core index

def _bad_index_calls(lib, idx):
    """(name, result) of every function taking intIdx, with otherwise valid arguments."""
    p, m = abi.GCODE_PARAMETERS(), abi.MACHINE_PARAMETERS()
    info, size, gm, enh = abi.CALLBACK_INFO(), abi.GCODE_INFO(), abi.SIMPLE_GM_PARAMS(), abi.GM_PARAMS_ENHANCED()
    users = (ctypes.c_double * 100)()
    coords = (ctypes.c_double * 10)()
    n = ctypes.c_uint32(77)
    L = lib
    return [
        ("LoadFromIni", L.ToolChainCore_LoadFromIni(idx, b"/nonexistent.ini", byref(n))),
        ("DestroyCNC", L.ToolChainCore_DestroyCNC(idx)),
        ("SetGCodeParameters", L.ToolChainCore_SetGCodeParameters(idx, byref(p))),
        ("GetGCodeParameters", L.ToolChainCore_GetGCodeParameters(idx, byref(p))),
        ("GetMachineParameters", L.ToolChainCore_GetMachineParameters(idx, byref(m))),
        ("SetMachineParameters", L.ToolChainCore_SetMachineParameters(idx, byref(m))),
        ("SetUserParams", L.ToolChainCore_SetUserParams(idx, users, 100)),
        ("GCodePrefixPostfix", L.ToolChainCore_GCodePrefixPostfix(idx, b"G90", b"M30")),
        ("CompileFromFile", L.ToolChainCore_CompileFromFile(idx, b"/nonexistent.nc")),
        ("CompileFromMemory", L.ToolChainCore_CompileFromMemory(idx, b"mem.nc", b"G1 X1\n")),
        ("IsBusy", L.ToolChainCore_IsBusy(idx)),
        ("GetLastError", L.ToolChainCore_GetLastError(idx, byref(info))),
        ("FileToIdx", L.ToolChainCore_FileToIdx(idx, b"bad_core.nc")),
        ("GetGCodeSizeInfo", L.ToolChainCore_GetGCodeSizeInfo(idx, byref(size))),
        ("SetGCodeRunTime", L.ToolChainCore_SetGCodeRunTime(idx, 0, 1.0)),
        ("ResetCNC", L.ToolChainCore_ResetCNC(idx, 0, 10, coords)),
        ("StartCNCEx", L.ToolChainCore_StartCNCEx(idx, abi.RUN_SIMULATION, None)),
        ("StopCNCEx", L.ToolChainCore_StopCNCEx(idx, None)),
        ("ConnectCNCEx_Plane", L.ToolChainCore_ConnectCNCEx_Plane(idx, 0, 10, coords, None, 0, 0, 0)),
        ("GoToPosition", L.ToolChainCore_GoToPosition(idx, 10, coords)),
        ("GoToPositionEx", L.ToolChainCore_GoToPositionEx(idx, byref(gm))),
        ("MFunc", L.ToolChainCore_MFunc(idx, byref(gm), 0)),
        ("SetRelFeed", L.ToolChainCore_SetRelFeed(idx, 0.5)),
        ("SetBreakpoint", L.ToolChainCore_SetBreakpoint(idx, 1, 0)),
        ("ResetStatusCNC", L.ToolChainCore_ResetStatusCNC(idx, 0)),
        ("GetPos", L.ToolChainCore_GetPos(idx, 0, byref(gm), byref(enh))),
        ("SetCallBack", L.ToolChainCore_SetCallBack(idx, abi.CB_ADD_OUTPUT_LOG, 0, None)),
    ], n


@pytest.mark.parametrize("idx", BAD_CORES)
def test_bad_core_index(fresh_core, idx):
    lib = fresh_core
    before = [abi.GCODE_PARAMETERS() for _ in range(3)]
    for core, p in enumerate(before):
        lib.ToolChainCore_GetGCodeParameters(core, byref(p))
    results, n = _bad_index_calls(lib, idx)
    assert {name: rc for name, rc in results if rc != -2} == {}
    assert n.value == 77                                   # nothing written
    assert lib.ToolChainCore_StatusCNC(idx) == abi.STATUS_INVALID
    assert lib.ToolChainCore_GetVersionString(idx) == b""
    assert lib.ToolChainCore_IdxToFile(idx, 0) == b"__unknown__"
    assert lib.ToolChainCore_GetGCodeRunTime(idx, 0) < 0
    # and nothing changed on the real cores
    for core, p in enumerate(before):
        now = abi.GCODE_PARAMETERS()
        lib.ToolChainCore_GetGCodeParameters(core, byref(now))
        assert bytes(now) == bytes(p)
        assert lib.ToolChainCore_StatusCNC(core) == 0


def test_good_core_indexes(fresh_core):
    for idx in range(abi.TOOL_CHAIN_MAX_CORES):
        assert fresh_core.ToolChainCore_IsBusy(idx) == 0
        assert fresh_core.ToolChainCore_StatusCNC(idx) == 0
        assert fresh_core.ToolChainCore_GetVersionString(idx) != b""


# ------------------------------------------------------------------ NULL pointers and counts

def test_null_structure_pointers(fresh_core):
    lib = fresh_core
    assert lib.ToolChainCore_Init(None) == -1
    assert lib.ToolChainCore_SetGCodeParameters(0, None) == -1
    assert lib.ToolChainCore_GetGCodeParameters(0, None) == -1
    assert lib.ToolChainCore_GetMachineParameters(0, None) == -1
    assert lib.ToolChainCore_SetMachineParameters(0, None) == -1
    assert lib.ToolChainCore_GetLastError(0, None) == -1
    assert lib.ToolChain_GetLastError(None) == -1
    assert lib.ToolChainCore_GetGCodeSizeInfo(0, None) == -1
    assert lib.ToolChainCore_GoToPositionEx(0, None) == -1
    assert lib.ToolChainCore_MFunc(0, None, 0) == -1
    assert lib.ToolChainCore_SetUserParams(0, None, 100) == -1
    assert lib.ToolChainCore_ResetCNC(0, 0, 3, None) == -1
    assert lib.ToolChainCore_GoToPosition(0, 3, None) == -1


def test_get_pos_pointers(fresh_core):
    lib = fresh_core
    pos, enh = abi.SIMPLE_GM_PARAMS(), abi.GM_PARAMS_ENHANCED()
    assert lib.ToolChainCore_GetPos(0, 0, None, None) == -1
    assert lib.ToolChainCore_GetPos(0, 0, byref(pos), None) == 0
    enh.m_statusCNC = 99
    assert lib.ToolChainCore_GetPos(0, 0, None, byref(enh)) == 0
    assert enh.m_statusCNC == 0 and enh.m_relFeed == 1.0
    assert lib.ToolChainCore_GetPos(0, 0, byref(pos), byref(enh)) == 0
    assert pos.m_fileIdx == -1


def test_set_user_params_counts(fresh_core):
    lib = fresh_core
    values = (ctypes.c_double * 100)(*range(100))
    for n in (1, 10, 99, 101, 1000, 0xFFFFFFFF):
        assert lib.ToolChainCore_SetUserParams(0, values, n) == -1, n
    assert lib.ToolChainCore_SetUserParams(0, values, 100) == 0
    assert lib.ToolChainCore_SetUserParams(0, None, 0) == 0
    assert lib.ToolChainCore_SetUserParams(0, values, 0) == 0


def test_reset_cnc_counts(fresh_core):
    coords = (ctypes.c_double * 11)()
    assert fresh_core.ToolChainCore_ResetCNC(0, 0, 11, coords) == -1
    assert fresh_core.ToolChainCore_ResetCNC(0, 0, 10, coords) == 0
    assert fresh_core.ToolChainCore_ResetCNC(0, 0, 0, None) == 0
    assert fresh_core.ToolChainCore_StatusCNC(0) == 0        # nothing compiled: stays 0


# ------------------------------------------------------------------ file indexes

def test_file_indexes(run_python):
    out = run_python("""
        import ctypes
        from sf_tch import library
        lib = library.load(LIB_PATH)
        f, i = lib.ToolChainCore_FileToIdx, lib.ToolChainCore_IdxToFile
        print([f(0, n) for n in (b"__unknown__", b"__end__", b"__stop__", b"__exec__")])
        print([f(0, n) for n in (b"a" * 252, b"a" * 300, b"", None)])
        print([f(0, b"first.nc"), f(0, b"second.nc"), f(0, b"first.nc"), f(0, b"b" * 251), f(0, b"third.nc")])
        print([i(0, k).decode() for k in (0, 1, 3, 4, 5, 63, 1000, -1, -2, -3, -4, -5)])
        print([f(1, b"other.nc"), i(1, 0).decode(), i(1, 1).decode()])
        print([lib.ToolChain_IdxToFile(k).decode() for k in (0, 1, 5, -2)])
    """).stdout.splitlines()
    assert out[0] == "[-1, -2, -3, -4]"
    assert out[1] == "[-1, -1, -1, -1]"
    assert out[2] == "[0, 1, 0, 2, 3]"
    assert out[3] == str(["first.nc", "second.nc", "third.nc", "__unknown__", "__unknown__", "__unknown__",
                          "__unknown__", "__unknown__", "__end__", "__stop__", "__exec__", "__unknown__"])
    assert out[4] == "[0, 'other.nc', '__unknown__']"        # per core
    assert out[5] == str(["first.nc", "second.nc", "__unknown__", "__end__"])


def test_legacy_get_last_error_is_core_0(run_python):
    out = run_python("""
        import ctypes
        from sf_tch import abi, library
        lib = library.load(LIB_PATH)
        info, legacy = abi.CALLBACK_INFO(), abi.CALLBACK_INFO()
        legacy.stringId = info.stringId = 4321
        print(lib.ToolChain_GetLastError(ctypes.byref(legacy)), lib.ToolChainCore_GetLastError(0, ctypes.byref(info)),
              legacy.stringId, info.stringId)   # no error yet: info untouched
        def compile_bad(core):
            assert lib.ToolChainCore_CompileFromMemory(core, b"bad.nc", b"G2 X10 Y0") == 0
            while lib.ToolChainCore_StatusCNC(core) == 1:
                pass
        compile_bad(1)                                           # an error on core 1 only
        print(lib.ToolChain_GetLastError(ctypes.byref(legacy)))
        compile_bad(0)                                           # an error on core 0
        print(lib.ToolChain_GetLastError(ctypes.byref(legacy)), lib.ToolChainCore_GetLastError(0, ctypes.byref(info)))
        print(legacy.stringId == info.stringId != 0, legacy.m_fullError == info.m_fullError, legacy.m_fullError)
    """).stdout.splitlines()
    assert out[:3] == ["0 0 4321 4321", "0", "1 1"]
    assert out[3].startswith("True True b'")


# ------------------------------------------------------------------ callbacks

def test_set_callback_numbers(run_python, tmp_path):
    ini = tmp_path / "vendor.ini"
    ini.write_text(VENDOR_INI)
    out = run_python(f"""
        import ctypes
        from sf_tch import abi, library
        lib = library.load(LIB_PATH)
        fn = ctypes.cast(abi.DriverEnd(lambda user: 0), ctypes.c_void_p)
        documented = abi.CALLBACK_NUMBERS
        undocumented = (0, 8, 9, 15, 16, 19, 30, 33, 1000, 1008, 2000, 2002, 0xFFFFFFFF)
        print([n for n in documented if lib.ToolChainCore_SetCallBack(0, n, 0, fn) != (0 if n <= 1000 else -1)])
        print([n for n in undocumented if lib.ToolChainCore_SetCallBack(0, n, 0, fn) != -1])
        print([n for n in undocumented if lib.ToolChainCore_SetCallBack(0, n, 0, None) != -1])
        maxcores = ctypes.c_uint32(0)
        print(lib.ToolChainCore_LoadFromIni(0, {str(ini).encode()!r}, ctypes.byref(maxcores)), maxcores.value)
        print([n for n in documented if lib.ToolChainCore_SetCallBack(0, n, 7, fn) != 0])
        print([n for n in documented if lib.ToolChainCore_SetCallBack(1, n, 7, fn) != (0 if n <= 1000 else -1)])
        print([n for n in documented if lib.ToolChainCore_SetCallBack(0, n, 0, None) != 0])
    """).stdout.splitlines()
    assert out == ["[]", "[]", "[]", "0 3", "[]", "[]", "[]"]


def test_null_removes_a_callback(fresh_core):
    lib = fresh_core
    texts = []
    cb = abi.AddOutputLog(lambda user, tab, text, info: texts.append((user, tab, text)) or 0)
    assert lib.ToolChainCore_SetCallBack(0, abi.CB_ADD_OUTPUT_LOG, 42, ctypes.cast(cb, ctypes.c_void_p)) == 0
    assert lib.ToolChainCore_StartCNCEx(0, abi.RUN_SIMULATION, None) == -1
    assert len(texts) == 1 and texts[0][:2] == (42, 0)
    assert lib.ToolChainCore_SetCallBack(0, abi.CB_ADD_OUTPUT_LOG, 42, None) == 0
    assert lib.ToolChainCore_StartCNCEx(0, abi.RUN_SIMULATION, None) == -1
    assert len(texts) == 1


# ------------------------------------------------------------------ INI

def test_load_from_vendor_ini(fresh_core, tmp_path):
    ini = tmp_path / "TGM.ini"
    ini.write_text(VENDOR_INI)
    n = ctypes.c_uint32(0)
    assert fresh_core.ToolChainCore_LoadFromIni(0, str(ini).encode(), byref(n)) == 0
    assert n.value == 3
    assert fresh_core.ToolChainCore_LoadFromIni(1, str(ini).encode(), None) == 0


def test_load_from_missing_ini(fresh_core, tmp_path):
    lib = fresh_core
    missing = str(tmp_path / "missing.ini").encode()
    seen = {}
    disp = abi.DispAndLocateError(lambda user, line, idx, text, info: seen.setdefault("disp", (user, text)) and 0)
    out = abi.AddOutputLog(lambda user, tab, text, info: seen.setdefault("out", (user, tab, text)) and 0)
    assert lib.ToolChainCore_SetCallBack(0, abi.CB_DISP_AND_LOCATE_ERROR, 5, ctypes.cast(disp, ctypes.c_void_p)) == 0
    assert lib.ToolChainCore_SetCallBack(0, abi.CB_ADD_OUTPUT_LOG, 6, ctypes.cast(out, ctypes.c_void_p)) == 0
    n = ctypes.c_uint32(77)
    assert lib.ToolChainCore_LoadFromIni(0, missing, byref(n)) == abi.TOOL_CHAIN_XEXEC
    assert n.value == 77
    rc, info = last_error(lib)
    assert rc == 1 and missing in info.m_fullError and info.stringId != 0
    assert missing in info.m_errorArguments
    assert seen["disp"] == (5, info.m_fullError)
    assert seen["out"] == (6, 0, info.m_fullError)


# ------------------------------------------------------------------ parameters

M_NUMBERS = (2, 30, 3, 4, 5, 6, 7, 8, 9, 17, 29, 80, 81, 82, 83, 84, 85, 86, 87, 99)


def check_default_parameters(p):
    assert p.absMode == 1 and p.swapG2G3 == 0 and p.forceMode == 0
    assert p.correctionStrategy == 0x600
    assert [getattr(p, name) for name in abi.M_FUNCTION_FIELDS] == list(M_NUMBERS)
    assert p.startAngle == 360.0 and p.endAngle == 360.0
    assert p.overrideInc == 0.001
    assert p.insertArcMode == 0 and p.insertArcToleranceRMax == 0.03 and p.insertArcToleranceRMin == 0.03
    assert p.insertArcMinAngle == 0.0 and p.calcTime == 0 and p.MfuncInsertType == 0
    assert list(p.tolerance)[:7] == [0.005, 0.001, 0.03, 0.005, 0.0, 3.0, 0.01]
    assert [p.arcFeedTable[i].m_r for i in range(5)] == [0.0] * 5       # off


def test_default_gcode_parameters(fresh_core, fresh_defaults):
    check_default_parameters(fresh_defaults[0])           # as read in a fresh process
    for idx in range(3):
        p = abi.GCODE_PARAMETERS()
        assert fresh_core.ToolChainCore_GetGCodeParameters(idx, byref(p)) == 0
        check_default_parameters(p)


def _distinct_parameters():
    p = abi.GCODE_PARAMETERS()
    raw = (ctypes.c_ubyte * ctypes.sizeof(p)).from_buffer(p)
    for i in range(len(raw)):
        raw[i] = (i * 7 + 3) & 0xFF
    # the doubles: distinct and within the bounds SetGCodeParameters checks
    doubles = iter(0.001 * k for k in range(1, 1000))

    def fill(struct):           # ctypes hands out views: assignments reach p
        for name, ctype in struct._fields_:
            value = getattr(struct, name)
            if ctype is ctypes.c_double:
                setattr(struct, name, next(doubles))
            elif isinstance(value, ctypes.Structure):
                fill(value)
            elif isinstance(value, ctypes.Array) and value._type_ is ctypes.c_double:
                for k in range(len(value)):
                    value[k] = next(doubles)
            elif isinstance(value, ctypes.Array) and issubclass(value._type_, ctypes.Structure):
                for item in value:
                    fill(item)
    fill(p)
    return p


def test_gcode_parameters_round_trip(fresh_core):
    lib = fresh_core
    p = _distinct_parameters()
    assert lib.ToolChainCore_SetGCodeParameters(1, byref(p)) == 0
    back = abi.GCODE_PARAMETERS()
    assert lib.ToolChainCore_GetGCodeParameters(1, byref(back)) == 0
    assert bytes(back) == bytes(p)
    # other cores untouched
    assert lib.ToolChainCore_GetGCodeParameters(0, byref(back)) == 0
    check_default_parameters(back)


def test_override_inc_zero_means_default(fresh_core):
    p = abi.GCODE_PARAMETERS()
    fresh_core.ToolChainCore_GetGCodeParameters(0, byref(p))
    p.overrideInc = 0.0
    assert fresh_core.ToolChainCore_SetGCodeParameters(0, byref(p)) == 0
    fresh_core.ToolChainCore_GetGCodeParameters(0, byref(p))
    assert p.overrideInc == 0.001


def test_machine_parameters_round_trip(fresh_core):
    lib = fresh_core
    m = abi.MACHINE_PARAMETERS()
    for i, axis in enumerate(abi.AXES):
        setattr(m.minCoords, axis, -100.0 - i)
        setattr(m.maxCoords, axis, 200.0 + i)
        setattr(m.refCoords, axis, 0.5 * i)
        setattr(m.enableMask, axis, i % 2)
        setattr(m.backlash, axis, 0.01 * i)
        setattr(m.backlashInc, axis, 0.001 * i)
    m.backlashValuesSource = 1
    m.enhancedInterpolatorParameters = 0x300401
    assert lib.ToolChainCore_SetMachineParameters(2, byref(m)) == 0
    back = abi.MACHINE_PARAMETERS()
    assert lib.ToolChainCore_GetMachineParameters(2, byref(back)) == 0
    assert bytes(back) == bytes(m)


def test_prefix_postfix(fresh_core):
    lib = fresh_core
    assert lib.ToolChainCore_GCodePrefixPostfix(0, None, None) == 0
    assert lib.ToolChainCore_GCodePrefixPostfix(0, b"G90", None) == 0
    assert lib.ToolChainCore_GCodePrefixPostfix(0, None, b"M30") == 0
    assert lib.ToolChainCore_GCodePrefixPostfix(0, b"", b"") == 0


# ------------------------------------------------------------------ structures size, version

def test_structures_size(lib):
    expected = [8] + [ctypes.sizeof(abi.STRUCTURES[n]) for n in abi.STRUCTURES_SIZE_ORDER]
    assert expected == [8, 1112, 616, 112, 32, 1280, 52, 448, 32]
    for n_items in (0, 1, 3, 8, 9, 12):
        items = (ctypes.c_uint32 * 12)(*([0xDEADBEEF] * 12))
        assert lib.ToolChainCore_GetStructuresSize(0, n_items, items) == 0
        k = min(n_items, 9)
        assert list(items)[:k] == expected[:k]
        assert list(items)[k:] == [0xDEADBEEF] * (12 - k), n_items
    assert lib.ToolChainCore_GetStructuresSize(0, 9, None) == 0


def test_version_string(lib):
    version = lib.ToolChainCore_GetVersionString(0)
    assert version and b"SF_TCh" in version
    assert lib.ToolChainCore_GetVersionString(2) == version


def test_fresh_process_status(run_python):
    out = run_python("""
        from sf_tch import library
        lib = library.load(LIB_PATH)
        print([lib.ToolChainCore_StatusCNC(i) for i in range(3)], [lib.ToolChainCore_IsBusy(i) for i in range(3)])
    """).stdout.strip()
    assert out == "[0, 0, 0] [0, 0, 0]"


# ------------------------------------------------------------------ running without a program

def test_set_rel_feed_clamps(fresh_core):
    """The interpolator manual: Rel_Speed is a coefficient of 0.01 .. 2 (1 % .. 200 %); a
    panel that writes 0 as "hold" gets 1 %, as with the vendor's library."""
    lib = fresh_core
    enh = abi.GM_PARAMS_ENHANCED()
    for value, expected in ((0.5, 0.5), (100.0, 2.0), (2.0, 2.0), (0.0, 0.01), (0.005, 0.01), (-3.0, 0.01),
                            (0.01, 0.01), (1.0, 1.0)):
        assert lib.ToolChainCore_SetRelFeed(0, value) == 0
        assert lib.ToolChainCore_GetPos(0, 0, None, byref(enh)) == 0
        assert enh.m_relFeed == pytest.approx(expected), value


def test_status_errors_without_program(fresh_core):
    lib = fresh_core
    assert lib.ToolChainCore_ResetStatusCNC(0, 0) == -1
    assert lib.ToolChainCore_ResetStatusCNC(0, 1) == -1
    assert lib.ToolChainCore_StartCNCEx(0, abi.RUN_SIMULATION, None) == -1
    assert lib.ToolChainCore_StartCNCEx(0, abi.RUN_TEST, b"M3") == -1
    assert lib.ToolChainCore_StopCNCEx(0, None) == -1
    assert lib.ToolChainCore_GetGCodeSizeInfo(0, byref(abi.GCODE_INFO())) == -1
    assert lib.ToolChainCore_StatusCNC(0) == 0


def test_reset_status_after_compilation(run_python):
    out = run_python("""
        import time
        from sf_tch import library
        lib = library.load(LIB_PATH)
        def compiled():
            assert lib.ToolChainCore_CompileFromMemory(0, b"prog.nc", b"G1 X10\\n") == 0
            deadline = time.time() + 10
            while lib.ToolChainCore_StatusCNC(0) == 1 and time.time() < deadline:
                time.sleep(0.005)
            return lib.ToolChainCore_StatusCNC(0)
        print(compiled(), lib.ToolChainCore_ResetStatusCNC(0, 2), lib.ToolChainCore_StatusCNC(0))
        print(lib.ToolChainCore_ResetStatusCNC(0, 0), lib.ToolChainCore_StatusCNC(0))
        compiled()
        print(lib.ToolChainCore_ResetStatusCNC(0, 1), lib.ToolChainCore_StatusCNC(0), lib.ToolChainCore_IsBusy(0))
    """).stdout.splitlines()
    assert out == ["-1 -1 -1", "0 0", "0 -50 0"]


NOT_IMPLEMENTED = {
    "LoadCNCCalcPlugIn": lambda lib: lib.ToolChainCore_LoadCNCCalcPlugIn(b"kinematics.so", 0, 0),
}


@pytest.mark.parametrize("name", sorted(NOT_IMPLEMENTED))
def test_not_implemented(fresh_core, name):
    other_error(fresh_core)
    assert NOT_IMPLEMENTED[name](fresh_core) == -1
    rc, info = last_error(fresh_core)
    assert rc == 1
    assert b"not implemented" in info.m_fullError
    assert name.split()[0].encode() in info.m_fullError
    assert fresh_core.ToolChainCore_StatusCNC(0) == 0


def test_unload_plugin_is_success(lib):
    assert lib.ToolChainCore_LoadCNCCalcPlugIn(b"", 0, 0) == 1
    assert lib.ToolChainCore_LoadCNCCalcPlugIn(None, 0, 0) == -1


def test_run_time(fresh_core):
    lib = fresh_core
    assert lib.ToolChainCore_GetGCodeRunTime(0, -1) < 0
    assert lib.ToolChainCore_GetGCodeRunTime(0, 10000) < 0
    assert lib.ToolChainCore_SetGCodeRunTime(0, -1, 1.0) == -1
    idx = lib.ToolChainCore_FileToIdx(0, b"run_time_test.nc")
    assert idx >= 0
    assert lib.ToolChainCore_SetGCodeRunTime(0, idx, -1.0) == -1
    assert lib.ToolChainCore_SetGCodeRunTime(0, idx, 12.5) == 0
    assert lib.ToolChainCore_GetGCodeRunTime(0, idx) == 12.5


# ------------------------------------------------------------------ lifecycle

def test_init(run_python, tmp_path):
    out = run_python(f"""
        import ctypes
        from sf_tch import abi, library
        lib = library.load(LIB_PATH)
        d = {str(tmp_path).encode()!r}
        ok = abi.DLL_INIT_STRUCT(d, d, d, 2)
        print(lib.ToolChainCore_Init(None),
              lib.ToolChainCore_Init(ctypes.byref(abi.DLL_INIT_STRUCT(None, d, d, 2))),
              lib.ToolChainCore_Init(ctypes.byref(abi.DLL_INIT_STRUCT(d, d, None, 2))),
              lib.ToolChainCore_Init(ctypes.byref(abi.DLL_INIT_STRUCT(d, d, d, 3))),
              lib.ToolChainCore_Init(ctypes.byref(ok)))
    """).stdout.strip()
    assert out == "-1 -1 -1 -1 0"


def test_destroy_twice(lib):
    for idx in range(3):
        assert lib.ToolChainCore_DestroyCNC(idx) == 0
        assert lib.ToolChainCore_DestroyCNC(idx) == 0
        assert lib.ToolChainCore_StatusCNC(idx) == 0


# ------------------------------------------------------------------ logging

def test_log_value_round_trip(lib):
    old = lib.ToolChainCore_GetLogValue()
    try:
        for value in (0x1 | 0x20, 0xFF, 0x10000000 | 0x8, 0):
            assert lib.ToolChainCore_SetLogValue(value) == 0
            assert lib.ToolChainCore_GetLogValue() == value
    finally:
        lib.ToolChainCore_SetLogValue(old)


def test_log_file(run_python, tmp_path):
    run_python("""
        from sf_tch import library
        lib = library.load(LIB_PATH)
        lib.ToolChain_LogANSI(b"not logged: no output bit")
        lib.ToolChain_FlushLogFile()
        assert lib.ToolChainCore_SetLogValue(0x20000000) == 0
        lib.ToolChain_LogANSI(b"hello")
        lib.ToolChain_LogANSI(None)
        lib.ToolChain_FlushLogFile()
        import os
        assert os.path.exists(os.path.join(os.environ["SF_TCH_LOG_DIR"], "SF_TCh.log"))
    """, env={"SF_TCH_LOG_DIR": str(tmp_path)}, cwd=str(tmp_path))
    text = (tmp_path / "SF_TCh.log").read_text()
    assert "hello" in text
    assert "not logged" not in text
    assert len(text.splitlines()) == 1
