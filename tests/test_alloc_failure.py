"""Allocation failure survived everywhere (SQLite's malloc test): for a compile with
compensation, a simulation, a run of the offline machine, a table load and a smoothing
run, the library's nth allocation is made to fail (ToolChain_TestAllocFail, test-only)
for n = 1, 2, 3, ... until the operation makes fewer than n allocations. Each failure
is survived: the call returns or the activity ends with error 4 "Out of memory (stage)" on the
operation's channel (or succeeds where the stage goes without), no worker thread is
left, and afterwards the core gives the operation's known result again.

Each operation runs in a subprocess of its own (runtime_host.script): a crash or a hang
is reported as a failure, with the failure point it happened at. Every library
allocation goes through one allocator (platform.h: tc_malloc, tc_calloc, tc_realloc,
tc_strdup); a test below keeps it so. The leak check is the slow test at the end: the
same sweeps against the ASan build (docs/testing.md, "Allocation failure")."""
import json
import os
import re
import shutil
from pathlib import Path

import pytest

from runtime_host import run_script

ROOT = Path(__file__).resolve().parents[1]

# What every subprocess defines: sweep(op) fails allocation n = 1, 2, ... of op() and
# checks each result; op() returns None (success) or (number, text) of its error.
PRELUDE = r"""
import json
from sf_tch import abi, library
from ctypes import byref, c_double, c_uint64, c_char_p, POINTER
ALLOC_KEY = abi.TC_TEST_ALLOC_KEY
# error 4 names the stage the failing thread worked in (toolchain/includes/platform.h tc_set_stage)
STAGES = ("compiling", "the compensation", "the automatic arcs", "the plan", "the extent", "the simulation",
          "the offline machine", "the connection search", "reading a tool table", "reading an axis table",
          "reading an INI file", "the smoothing", "a call of the library")

def is_oom(result):
    return (result is not None and result[0] == 4 and result[1].startswith("Out of memory (")
            and result[1][len("Out of memory ("):-1] in STAGES and result[1].endswith(")"))
DEMO = (Path(library.__file__).parent / "data" / "demo.nc").read_bytes()

def call_error(core=0):
    info = abi.CALLBACK_INFO()
    assert lib.ToolChainCore_GetLastCallError(core, byref(info)) == 1, "a refused call without its error"
    return info.stringId, (info.m_fullError or b"").decode()

def refused_or_ok(rc, core=0):
    return None if rc == 0 else call_error(core)

def threads_back(base, what):
    '''No more threads than base: a worker just joined may still be leaving the kernel
    (polled for up to two seconds), and one counted in base may have left meanwhile.'''
    deadline = time.monotonic() + 2.0
    while thread_count() > base and time.monotonic() < deadline:
        time.sleep(0.005)
    assert thread_count() <= base, f"{thread_count()} threads, {base} {what}"

def sweep(name, op, known, before=lambda: None, limit=100000):
    '''Fails allocation n of op() (after before()) for n = 1, 2, ... until op() makes fewer than n; every
    result is None (it went without) or error 4 naming a stage; afterwards known() holds (the core works).
    Prints one JSON line: the failure points and the results seen.'''
    base = thread_count()
    known()
    results = {}
    n = 1
    while n < limit:
        before()
        assert lib.ToolChain_TestAllocFail(ALLOC_KEY, n) == 0
        print(f"{name}: failing allocation {n}", file=sys.stderr, flush=True)
        result = op()
        left = lib.ToolChain_TestAllocFail(ALLOC_KEY, 0)
        threads_back(base, f"before {name} (allocation {n} failed)")
        if left > 0:                          # fewer than n allocations: nothing failed
            assert result is None, f"{name}: {result} without a failed allocation"
            break
        assert result is None or is_oom(result), f"{name}, allocation {n} failed: {result}"
        results[str(result)] = results.get(str(result), 0) + 1
        known()
        n += 1
    print(json.dumps({"operation": name, "points": n - 1, "results": results}))
"""

# ------------------------------------------------------------------ the operations

COMPILE = r"""
load_ini(lib, 0)
# the sample (G41, G42, helices) and a compensated contour long enough to grow every array
CONTOUR = b"G41 G1 X0 Y0 F3000\n" + b"".join(b"G1 X%d Y%d\n" % (i, 5 * (i % 2)) for i in range(1, 3000)) + b"G40 G1 X0 Y-20\n"
# the ISO mode (GCODE_PARAMETERS.rezerva1 bit 0): parameters, an O-word loop, a canned cycle
ISO = (b"#1 = 0\nG21 G90 G17\nG0 X0 Y0 Z5\no100 while [#1 LT 5]\nG1 X[#1 * 10] Y[#1 MOD 2] F600\n"
       b"#1 = [#1 + 1]\no100 endwhile\nG81 X10 Y10 Z-2 R1 F100\nG80\nG41 D0 G1 X0 Y0\nG40\nM2\n")
PROGRAMS = [(b"demo.nc", DEMO), (b"contour.nc", CONTOUR)]
FILE = Path(tempfile.mkdtemp()) / "demo_file.nc"
FILE.write_bytes(DEMO)
state = {}
variant = [""]                  # what else the core has: a prefix, the ISO mode

def result(name):
    '''What the compiled program is: its size info and its records.'''
    info = abi.GCODE_INFO()
    assert lib.ToolChainCore_GetGCodeSizeInfo(0, byref(info)) == 0
    total = c_uint64()
    assert lib.ToolChainCore_GetToolpath(0, None, 0, 0, byref(total)) == 0
    records = (abi.TC_TOOLPATH_RECORD * total.value)()
    assert lib.ToolChainCore_GetToolpath(0, records, total.value, 0, byref(total)) == 0
    got = json.dumps([info.to_dict(), [r.to_dict() for r in records]])
    key = (variant[0], name)
    assert state.setdefault(key, got) == got, f"{key}: another program than without a failure"

def known():
    for name, text in PROGRAMS:
        reset_to(lib, 0, 0.0, 0.0, 0.0)
        assert compile_wait(lib, 0, text, name) is None
        result(name)

def origin():
    reset_to(lib, 0, 0.0, 0.0, 0.0)

def compile_one(name, text):
    rc = lib.ToolChainCore_CompileFromMemory(0, name, text)
    if rc != 0:
        return call_error()
    assert wait_status(lib, 0, lambda s: s != 1, 20.0) == -1
    err = last_error(lib, 0)
    if err is None:
        result(name)
    return None if err is None else (err[0], err[2])

for name, text in PROGRAMS:
    sweep(f"compile {name.decode()}", lambda: compile_one(name, text), known, origin)

def from_file():
    rc = lib.ToolChainCore_CompileFromFile(0, str(FILE).encode())
    if rc != 0:
        return call_error()
    assert wait_status(lib, 0, lambda s: s != 1, 20.0) == -1
    err = last_error(lib, 0)
    if err is None:
        result("from file")
    return None if err is None else (err[0], err[2])

def file_known():
    known()
    reset_to(lib, 0, 0.0, 0.0, 0.0)
    assert lib.ToolChainCore_CompileFromFile(0, str(FILE).encode()) == 0
    assert wait_status(lib, 0, lambda s: s != 1, 20.0) == -1 and last_error(lib, 0) is None
    result("from file")

sweep("compile from a file", from_file, file_known, origin)

# a prefix and a postfix: their copies are the compilation's too
def set_fixes():
    return refused_or_ok(lib.ToolChainCore_GCodePrefixPostfix(0, b"G1 X1 Y1 F1000", b"G1 X2 Y2"))

def fixes_known():
    assert set_fixes() is None
    known()

def set_fixes_once():
    '''Sets them (refused: a second time, the fault spent): the compilations after it
    (known) show whether a call that succeeded did set them.'''
    result = set_fixes()
    if result is not None:
        assert set_fixes() is None
    return result

variant[0] = "fixes"
assert set_fixes() is None
sweep("prefix and postfix", set_fixes_once, known, before=lambda: lib.ToolChainCore_GCodePrefixPostfix(0, None, None))
sweep("compile demo.nc with a prefix and a postfix", lambda: compile_one(b"demo.nc", DEMO), fixes_known, origin)
assert lib.ToolChainCore_GCodePrefixPostfix(0, None, None) == 0

# the ISO mode
params = abi.GCODE_PARAMETERS()
assert lib.ToolChainCore_GetGCodeParameters(0, byref(params)) == 0
params.rezerva1 |= 1
assert lib.ToolChainCore_SetGCodeParameters(0, byref(params)) == 0
PROGRAMS = [(b"iso.ngc", ISO)]
variant[0] = "iso"
sweep("compile iso.ngc (ISO mode)", lambda: compile_one(b"iso.ngc", ISO), known, origin)
"""

SIMULATE = r"""
load_ini(lib, 0)
reset_to(lib, 0, 0.0, 0.0, 0.0)
assert compile_wait(lib, 0, DEMO, b"demo.nc") is None
def known():
    status, driver = simulate(lib, 0)
    assert status == -10, status
    if "parts" not in state:
        state["parts"] = driver.parts
    assert driver.parts == state["parts"]
state = {}

def op():
    driver = Driver(lib, 0).install()
    assert lib.ToolChainCore_ResetCNC(0, 1, 0, None) == 0
    rc = lib.ToolChainCore_StartCNCEx(0, abi.RUN_SIMULATION, None)
    if rc != 0:
        driver.remove()
        return call_error()
    status = wait_status(lib, 0, lambda s: s not in (abi.RUN_SIMULATION, 1), 20.0)
    driver.remove()
    if status == -10:
        assert driver.parts == state["parts"], "another simulation than without a failure"
        return None
    err = last_error(lib, 0)
    return (err[0], err[2]) if err is not None else ("status", status)

sweep("simulate", op, known)
"""

MACHINE = r"""
KEY = abi.TC_TEST_CLOCK_KEY
load_ini(lib, 0)
assert lib.ToolChainCore_SetTimeScale(0, 1.0) == 0
assert lib.ToolChainCore_TestClock(0, KEY, 0.0) == 0          # the stepped clock
PROGRAM = b"G1 X20 F6000\nG1 Y10\nG2 X30 Y20 I10 J0\nM3\nG4 H0.01\nG1 X0 Y0\nM30\n"
reset_to(lib, 0, 0.0, 0.0, 0.0)
assert compile_wait(lib, 0, PROGRAM, b"m.nc") is None

def run():
    '''StartCNCEx 30 from the origin, stepped until it ends: its status and GetPos.'''
    reset_to(lib, 0, 0.0, 0.0, 0.0)
    driver = Driver(lib, 0).install()
    rc = lib.ToolChainCore_StartCNCEx(0, 30, None)
    if rc != 0:
        driver.remove()
        return call_error(), None
    t = 0.0
    while lib.ToolChainCore_StatusCNC(0) in (30, 70, 80):
        assert t < 60.0, "the run does not end"
        assert lib.ToolChainCore_TestClock(0, KEY, 0.05) == 0
        t += 0.05
    status = lib.ToolChainCore_StatusCNC(0)
    driver.remove()
    pos, enh = abi.SIMPLE_GM_PARAMS(), abi.GM_PARAMS_ENHANCED()
    assert lib.ToolChainCore_GetPos(0, 0, byref(pos), byref(enh)) == 0
    return status, (round(pos.m_calcS.x, 9), round(pos.m_calcS.y, 9))

def known():
    status, end = run()
    assert (status, end) == (abi.STATUS_AT_END, (0.0, 0.0)), (status, end)

def op():
    status, end = run()
    if status == abi.STATUS_AT_END:
        assert end == (0.0, 0.0), end
        return None
    if isinstance(status, tuple):
        return status
    err = last_error(lib, 0)
    return (err[0], err[2]) if err is not None else ("status", status)

sweep("machine", op, known)
assert lib.ToolChainCore_TestClock(0, KEY, -1.0) == 0
"""

TABLES = r"""
import struct
folder = Path(tempfile.mkdtemp())
tool = folder / "TAB0.KOR"
tool.write_text("$KOR\n01: R=10.0 X=20.0 Y=30.0 Z=40.0\n02: R=0.8 X=0.0 2=0.0\n95: R=0.0 1=12.55\n")
axis = folder / "ACHS3D01.KOR"
header = b"ZXY\0".ljust(127, b"\0") + bytes([1])
axis.write_bytes(header + struct.pack("<ffIffI", 0, 10, 3, 0, 20, 5)
                 + struct.pack("<15f", *[0.01 * i for i in range(15)]))
names = (c_char_p * 1)(str(axis).encode())

def correction(entry):
    values = (c_double * abi.TC_TOOL_VALUES)()
    assert lib.ToolChainCore_GetToolCorrection(0, entry, values) == 0
    return list(values)

def corrected():
    pos, out = (c_double * 10)(10.0, 20.0), (c_double * 10)()
    assert lib.ToolChainCore_CorrectPosition(0, pos, out) == 0
    return out[2]

def clear():
    empty = folder / "EMPTY.KOR"
    empty.write_text("$KOR\n")
    assert lib.ToolChainCore_LoadToolTable(0, str(empty).encode()) == 0
    assert lib.ToolChainCore_LoadAxisCorrections(0, 0, None) == 0

def known():
    clear()
    assert lib.ToolChainCore_LoadToolTable(0, str(tool).encode()) == 0
    assert lib.ToolChainCore_LoadAxisCorrections(0, 1, names) == 0
    assert correction(1)[:4] == [10.0, 20.0, 30.0, 40.0]
    assert abs(corrected() - 0.14) < 1e-6, corrected()

def tool_op():
    result = refused_or_ok(lib.ToolChainCore_LoadToolTable(0, str(tool).encode()))
    assert correction(1)[0] == (10.0 if result is None else 0.0), "a refused table changed the core's"
    return result

def axis_op():
    result = refused_or_ok(lib.ToolChainCore_LoadAxisCorrections(0, 1, names))
    assert (abs(corrected() - 0.14) < 1e-6) if result is None else corrected() == 0.0
    return result

ini = folder / "tables.ini"
ini.write_text(f"[Corrections]\nToolTable={tool}\nAxisTable1={axis}\n")

def ini_op():
    rc = lib.ToolChainCore_LoadFromIni(0, str(ini).encode(), None)
    return refused_or_ok(rc)

sweep("tool table", tool_op, known, clear)
sweep("axis table", axis_op, known, clear)
sweep("tables by INI", ini_op, known, clear)
"""

SMOOTHING = r"""
import numpy as np
Pd = POINTER(c_double)
assert lib.ToolChainCore_SetSmoothing(0, abi.TC_SMOOTHING_SPLINE, (c_double * 4)(50, 1e6, 0, 0)) == 0
assert lib.ToolChainCore_SetSmoothing(0, abi.TC_SMOOTHING_IIR, (c_double * 4)(2e6, 1e6, 5e3, 3)) == 0
x = np.zeros((400, 10))
x[:200, 0] = np.linspace(0.0, 2.0, 200)
x[200:, 0] = 2.0

def smooth():
    out = np.zeros_like(x)
    settled = c_uint64()
    rc = lib.ToolChainCore_SmoothSamples(0, x.ctypes.data_as(Pd), len(x), out.ctypes.data_as(Pd), byref(settled))
    return rc, out, settled.value

def known():
    rc, out, settled = smooth()
    assert rc == 0
    if "out" not in state:
        state["out"] = (out.copy(), settled)
    assert np.array_equal(out, state["out"][0]) and settled == state["out"][1]
state = {}

def op():
    rc, out, settled = smooth()
    if rc == 0:
        assert np.array_equal(out, state["out"][0]) and settled == state["out"][1]
    return refused_or_ok(rc)

sweep("smoothing", op, known)
"""

ENDING = r"""
# An ending call never fails: ResetCNC to a new start moves GetPos there and measures the
# program from there, whatever allocation fails.
load_ini(lib, 0)
reset_to(lib, 0, 0.0, 0.0, 0.0)
assert compile_wait(lib, 0, DEMO, b"demo.nc") is None
START = (c_double * 10)(5.0, -3.0, 1.0)

def size_info():
    info = abi.GCODE_INFO()
    assert lib.ToolChainCore_GetGCodeSizeInfo(0, byref(info)) == 0
    return json.dumps(info.to_dict())

def position():
    pos, enh = abi.SIMPLE_GM_PARAMS(), abi.GM_PARAMS_ENHANCED()
    assert lib.ToolChainCore_GetPos(0, 0, byref(pos), byref(enh)) == 0
    return (pos.m_calcS.x, pos.m_calcS.y, pos.m_calcS.z)

assert lib.ToolChainCore_ResetCNC(0, 0, 10, START) == 0
MOVED = size_info()
reset_to(lib, 0, 0.0, 0.0, 0.0)
AT_ORIGIN = size_info()
assert MOVED != AT_ORIGIN

def known():
    reset_to(lib, 0, 0.0, 0.0, 0.0)
    assert position() == (0.0, 0.0, 0.0) and size_info() == AT_ORIGIN

def op():
    assert lib.ToolChainCore_ResetCNC(0, 0, 10, START) == 0
    assert position() == (5.0, -3.0, 1.0), position()
    assert size_info() == MOVED, "GetGCodeSizeInfo not measured from the new start"
    return None

sweep("ResetCNC to a new start", op, known)

# the extent a reset could not measure: GetGCodeSizeInfo measures it, or says why not
assert lib.ToolChain_TestAllocFail(ALLOC_KEY, 1) == 0
assert lib.ToolChainCore_ResetCNC(0, 0, 10, START) == 0
assert lib.ToolChain_TestAllocFail(ALLOC_KEY, 1) == 0               # the reset's failed
info = abi.GCODE_INFO()
assert lib.ToolChainCore_GetGCodeSizeInfo(0, byref(info)) == -1
assert is_oom(call_error())
assert lib.ToolChain_TestAllocFail(ALLOC_KEY, 0) == 0               # so did this one
assert size_info() == MOVED
"""

OPERATIONS = {"ending calls": ENDING, "compile": COMPILE, "simulate": SIMULATE, "machine": MACHINE, "tables": TABLES,
              "smoothing": SMOOTHING}


def sweep_results(run_python, body: str, seconds: float = 240.0) -> list:
    out = run_script(run_python, "from pathlib import Path\nimport tempfile\n" + PRELUDE + body, seconds,
                     what="allocation failure sweep")
    return [json.loads(line) for line in out.splitlines() if line.startswith("{")]


@pytest.mark.parametrize("operation", sorted(OPERATIONS))
def test_every_allocation_failure_is_survived(run_python, operation):
    results = sweep_results(run_python, OPERATIONS[operation])
    assert results, "the sweep printed nothing"
    for r in results:
        print(r)
        assert r["points"] > 0, f"{r['operation']}: no allocation to fail"


# ------------------------------------------------------------------ one allocator

RAW = re.compile(r"(?<![\w.])(malloc|calloc|realloc|strdup|_strdup|strndup|posix_memalign|aligned_alloc)\s*\(")


def test_every_allocation_goes_through_the_one_allocator():
    """No stage calls the C library's allocators: only platform.h's tc_malloc,
    tc_calloc, tc_realloc and tc_strdup do, once each (so the fault reaches them all)."""
    calls = []
    for path in sorted((ROOT / "toolchain").rglob("*")):
        if path.suffix not in (".pyx", ".pxd", ".pxi", ".h"):
            continue
        for number, line in enumerate(path.read_text().splitlines(), 1):
            code = line.split("#")[0] if path.suffix != ".h" else re.sub(r"/\*.*?\*/|^\s*\*.*", "", line)
            for m in RAW.finditer(code):
                calls.append(f"{path.relative_to(ROOT)}:{number}: {line.strip()}")
    expected = ["toolchain/includes/platform.h: return tc_alloc_fails() ? NULL : malloc(n);",
                "toolchain/includes/platform.h: return tc_alloc_fails() ? NULL : calloc(count, n);",
                "toolchain/includes/platform.h: return tc_alloc_fails() ? NULL : realloc(p, n);"]
    assert [re.sub(r":\d+:", ":", c) for c in calls] == expected, "\n".join(calls)


# ------------------------------------------------------------------ leaks: the ASan build (slow)

from test_sanitizers import asan_library, cache_dir, runtime  # noqa: E402,F401  (fixtures)

# LeakSanitizer reports at the end of each sweep's process. CPython does not free
# everything at exit, so only a leak allocated by the library counts: one whose
# allocation stack passes through libSF_TCh (the interpreter's own never does).
LEAK = re.compile(r"^(Direct|Indirect) leak of .*?(?=^\s*$)", re.M | re.S)


@pytest.mark.slow
@pytest.mark.timeout(1800)
@pytest.mark.parametrize("operation", sorted(OPERATIONS))
def test_no_allocation_failure_leaks_under_address_sanitizer(asan_library, run_python, operation, tmp_path,
                                                             monkeypatch):
    reports = tmp_path / "asan"
    monkeypatch.setenv("SF_TCH_LIBRARY", str(asan_library))
    env = {"LD_PRELOAD": f"{runtime('libasan.so')} {runtime('libubsan.so')}",
           "ASAN_OPTIONS": f"detect_leaks=1:halt_on_error=1:log_path={reports}",
           "LSAN_OPTIONS": "exitcode=0:max_leaks=0",
           "UBSAN_OPTIONS": f"halt_on_error=1:print_stacktrace=1:log_path={reports}"}
    out = run_script(lambda code, **kw: run_python(code, env=env, **kw), "from pathlib import Path\nimport tempfile\n"
                     + PRELUDE + OPERATIONS[operation], 1200.0, what="allocation failure sweep under ASan")
    assert any(line.startswith("{") for line in out.splitlines()), out[-2000:]
    problems = []
    for path in sorted(reports.parent.glob(reports.name + "*")):
        text = path.read_text(errors="replace")
        leaks = [m.group(0) for m in LEAK.finditer(text)]
        ours = [leak for leak in leaks if "libSF_TCh" in leak]
        others = LEAK.sub("", text)
        if ours or "ERROR:" in others.replace("ERROR: LeakSanitizer", "") or "runtime error" in others:
            problems.append(f"--- {path.name}\n" + "\n".join(ours)[:6000] + others[:3000])
    assert not problems, "\n".join(problems)
