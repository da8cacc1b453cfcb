"""A bounded concurrency storm on the three cores (issues 9 and 11): a host thread per core
compiles, simulates and runs the offline machine (forward, backward) in a loop while other threads call every ending, starting,
setting and polling function at random, and the driver callbacks call back into the
library (StopCNCEx, DestroyCNC, ResetCNC, GetPos, a refused StartCNCEx). Afterwards
every core gives the known result of known programs, and no thread is left.

Runs in a subprocess (a crash or hang is a failure with every thread's stack); the
random seed is printed so that a failing storm can be replayed (SF_TCH_STORM_SEED)."""
import os
import random

import pytest

from runtime_host import TIME_SCALE, run_script

SLOW_SCALE = float(os.environ.get("SF_TCH_SLOW_SCALE", "1"))

STORM = """
import random

SECONDS, SEED = {seconds!r}, {seed!r}
CORES = (0, 1, 2)
PROGRAMS = [lines_program(n, seed) for n, seed in ((40, 1), (400, 2), (2500, 3))] + [
    b"G1 X10 F1000\\nG2 X20 Y0 I5 J0\\nM8\\nG0 Z5\\nG1 X0 Y0\\nM30\\n",
    b"G1 X1\\nQQ\\n",                                   # a compile error
    lines_program(3000, 4) + b"M8\\n" + lines_program(3000, 5),   # planned in two threads (a stop to split at)
    # compensated (r = 0.3, set below), a square wave of 20,000 parts: the extent is measured
    # beside the compensation's merge
    b"G0 X0 Y0\\nG41 G1 X1 Y0 F3000\\n" + b"".join(b"G1 Y2\\nG1 X%d\\nG1 Y0\\nG1 X%d\\n" % (2 * k + 2, 2 * k + 3)
                                                for k in range(5000)) + b"G40 G1 Y-2\\n",
]
stop = threading.Event()
calls = {{}}
failures = []
for core in CORES:
    load_ini(lib, core)
    assert lib.ToolChainCore_SetTimeScale(core, 1e5) == 0     # the offline machine's runs end quickly
    tool = abi.GCODE_PARAMETERS()
    assert lib.ToolChainCore_GetGCodeParameters(core, ctypes.byref(tool)) == 0
    tool.correction[0].size = 0.3
    assert lib.ToolChainCore_SetGCodeParameters(core, ctypes.byref(tool)) == 0
defaults = abi.GCODE_PARAMETERS()
assert lib.ToolChainCore_GetGCodeParameters(0, ctypes.byref(defaults)) == 0
base_threads = thread_count()


def count(name):
    calls[name] = calls.get(name, 0) + 1


def guarded(body):
    # an exception in a storm thread is a failure of the test, reported at the end
    def run():
        try:
            body()
        except BaseException as exc:               # noqa: BLE001 (reported below)
            import traceback
            failures.append(traceback.format_exc())
            stop.set()
    return threading.Thread(target=run)


def on_g(core, part):
    # ctypes only prints an exception raised in a callback: record it as a failure
    try:
        reenter(core)
    except BaseException:                          # noqa: BLE001 (reported below)
        import traceback
        failures.append(traceback.format_exc())
        stop.set()
    return 0


def reenter(core):
    # the driver of a core: sometimes calls back into the library from the worker
    roll = callback_rng.random()
    if roll < 0.002:
        count("cb DestroyCNC"); assert lib.ToolChainCore_DestroyCNC(core) == 0
    elif roll < 0.004:
        count("cb StopCNCEx"); lib.ToolChainCore_StopCNCEx(core, None)
    elif roll < 0.006:
        count("cb ResetCNC"); assert lib.ToolChainCore_ResetCNC(core, 0, 0, None) == 0
    elif roll < 0.008:
        count("cb StartCNCEx")
        rc = lib.ToolChainCore_StartCNCEx(core, 10, None)
        assert rc == -1, f"StartCNCEx from DriverGFunc -> {{rc}}"
    elif roll < 0.05:
        count("cb GetPos"); lib.ToolChainCore_GetPos(core, 0, ctypes.byref(abi.SIMPLE_GM_PARAMS()), None)


callback_rng = random.Random(SEED)
g_callback = abi.DriverGFunc(on_g)
m_callback = abi.DriverMFunc(lambda core, part: 0)      # kept alive for the whole process
for core in CORES:
    set_callback(lib, core, abi.CB_DRIVER_G_FUNC, g_callback, user=core)


RUNNING = (10, 20, 30, 31, 32, 33, 40, 41, 50)


def wait_not(core, statuses, limit):
    # an activity of this program's size never takes seconds: a status stuck is a hang
    deadline = time.monotonic() + limit
    while lib.ToolChainCore_StatusCNC(core) in statuses and not stop.is_set():
        assert time.monotonic() < deadline, f"core {{core}}: status stuck at {{lib.ToolChainCore_StatusCNC(core)}}"
        time.sleep(0.0005)


def worker_host(core):
    rng = random.Random(SEED * 10 + core)
    while not stop.is_set():
        code = rng.choice(PROGRAMS)
        if lib.ToolChainCore_CompileFromMemory(core, b"storm%d.nc" % rng.randrange(100), code) == 0:
            count("compile ok")
        wait_not(core, (1,), 20 * {time_scale!r})
        regime = rng.choice((10, 20, 30, 31, 33))
        lib.ToolChainCore_ResetCNC(core, 1, 0, None)
        if lib.ToolChainCore_StartCNCEx(core, regime, None) == 0:
            count("run ok")
        wait_not(core, RUNNING, 20 * {time_scale!r})
        if rng.random() < 0.3 and lib.ToolChainCore_StartCNCEx(core, 32, None) == 0:
            count("backward ok")
        wait_not(core, RUNNING, 20 * {time_scale!r})


def chaos(index):
    rng = random.Random(SEED * 100 + index)
    params = abi.GCODE_PARAMETERS.from_buffer_copy(bytes(defaults))
    pos, enh, info, size = abi.SIMPLE_GM_PARAMS(), abi.GM_PARAMS_ENHANCED(), abi.CALLBACK_INFO(), abi.GCODE_INFO()
    coords = (ctypes.c_double * 10)(*[1.5 * k for k in range(10)])
    actions = {{
        "StopCNCEx": lambda c: lib.ToolChainCore_StopCNCEx(c, None),
        "ResetCNC": lambda c: lib.ToolChainCore_ResetCNC(c, rng.choice((0, 1)), rng.choice((0, 3, 10)), coords),
        "ResetStatusCNC": lambda c: lib.ToolChainCore_ResetStatusCNC(c, rng.choice((0, 1))),
        "DestroyCNC": lambda c: lib.ToolChainCore_DestroyCNC(c),
        "CompileFromMemory": lambda c: lib.ToolChainCore_CompileFromMemory(c, b"chaos.nc", rng.choice(PROGRAMS)),
        "StartCNCEx": lambda c: lib.ToolChainCore_StartCNCEx(c, rng.choice((10, 20, 30, 31, 32, 33)), b"M3"),
        "StopCNCEx M": lambda c: lib.ToolChainCore_StopCNCEx(c, b"M5"),
        "ConfirmMFunc": lambda c: lib.ToolChainCore_ConfirmMFunc(c),
        "MFunc": lambda c: lib.ToolChainCore_MFunc(c, ctypes.byref(abi.SIMPLE_GM_PARAMS(m_func=8)), 0),
        "GoToPosition": lambda c: lib.ToolChainCore_GoToPosition(c, 2, coords),
        "SetBreakpoint": lambda c: lib.ToolChainCore_SetBreakpoint(c, rng.randrange(0, 60), rng.randrange(-1, 3)),
        "SetTimeScale": lambda c: lib.ToolChainCore_SetTimeScale(c, rng.choice((1e3, 1e5))),
        "SetGCodeParameters": lambda c: (setattr(params.motion[1], "feed", rng.uniform(100, 9000)),
                                         lib.ToolChainCore_SetGCodeParameters(c, ctypes.byref(params))),
        "SetCallBack": lambda c: set_callback(lib, c, abi.CB_DRIVER_G_FUNC, rng.choice((g_callback, None)), user=c),
        "SetCallBack M": lambda c: set_callback(lib, c, abi.CB_DRIVER_M_FUNC, rng.choice((m_callback, None)), user=c),
        "GetPos": lambda c: lib.ToolChainCore_GetPos(c, 0, ctypes.byref(pos), ctypes.byref(enh)),
        "StatusCNC": lambda c: lib.ToolChainCore_StatusCNC(c),
        "IsBusy": lambda c: lib.ToolChainCore_IsBusy(c),
        "GetLastError": lambda c: lib.ToolChainCore_GetLastError(c, ctypes.byref(info)),
        "FileToIdx": lambda c: lib.ToolChainCore_FileToIdx(c, b"chaos%d.nc" % rng.randrange(300)),
        "IdxToFile": lambda c: lib.ToolChainCore_IdxToFile(c, rng.randrange(-4, 70)),
        "GetGCodeSizeInfo": lambda c: lib.ToolChainCore_GetGCodeSizeInfo(c, ctypes.byref(size)),
        "GetGCodeRunTime": lambda c: lib.ToolChainCore_GetGCodeRunTime(c, rng.randrange(-1, 70)),
        "SetRelFeed": lambda c: lib.ToolChainCore_SetRelFeed(c, rng.uniform(0.1, 2.0)),
    }}
    names = sorted(actions)
    while not stop.is_set():
        name = rng.choice(names)
        actions[name](rng.choice(CORES))
        count(name)
        time.sleep(rng.choice((0, 0, 0.0002, 0.002)))


def poller():
    pos, enh = abi.SIMPLE_GM_PARAMS(), abi.GM_PARAMS_ENHANCED()
    while not stop.is_set():
        for core in CORES:
            assert lib.ToolChainCore_StatusCNC(core) != -1234
            lib.ToolChainCore_GetPos(core, 0, ctypes.byref(pos), ctypes.byref(enh))
        count("poll")


threads = ([guarded(lambda c=c: worker_host(c)) for c in CORES] + [guarded(lambda i=i: chaos(i)) for i in range(3)]
           + [guarded(poller)])
for t in threads:
    t.start()
stop.wait(SECONDS)
stop.set()
for t in threads:
    t.join(30 * {time_scale!r})
    assert not t.is_alive(), "a storm thread did not end (a call blocked)"
print(f"seed {{SEED}}: {{dict(sorted(calls.items()))}}", flush=True)
assert not failures, "\\n".join(failures)

# every core ends cleanly and gives the known results again
for core in CORES:
    assert lib.ToolChainCore_DestroyCNC(core) == 0
    assert lib.ToolChainCore_StatusCNC(core) == 0
    set_callback(lib, core, abi.CB_DRIVER_G_FUNC, None)
    set_callback(lib, core, abi.CB_DRIVER_M_FUNC, None)
    as_written = abi.GCODE_PARAMETERS.from_buffer_copy(bytes(defaults))
    as_written.tolerance[2] = 0.0       # collinear lines not joined: the known results part for part
    assert lib.ToolChainCore_SetGCodeParameters(core, ctypes.byref(as_written)) == 0
    assert lib.ToolChainCore_SetRelFeed(core, 1.0) == 0
    check_usable(lib, core)
    reset_to(lib, core, 0.0, 0.0, 0.0)
    assert compile_wait(lib, core, PROGRAMS[2]) is None
    status, driver = simulate(lib, core)
    assert status == -10 and len(driver.g_parts) == 2500, (status, len(driver.g_parts))
    assert driver.g_parts[-1][4][:2] == ((2499 * 7 + 3) % 50, (2499 * 13 + 3) % 70), driver.g_parts[-1]
    assert lib.ToolChainCore_DestroyCNC(core) == 0
assert_threads_back(base_threads, "before the storm")
"""


def run_storm(run_python, seconds: float, seed: int) -> str:
    body = STORM.format(seconds=seconds, seed=seed, time_scale=TIME_SCALE)
    return run_script(run_python, body, seconds + 60, f"storm (seed {seed}, {seconds} s)")


def storm_seed() -> int:
    return int(os.environ.get("SF_TCH_STORM_SEED") or random.randrange(1 << 30))


def test_concurrency_storm(run_python):
    out = run_storm(run_python, 3.0, storm_seed())
    assert "compile ok" in out and "run ok" in out, out


@pytest.mark.slow
def test_concurrency_storm_long(run_python):
    out = run_storm(run_python, 10.0 * SLOW_SCALE, storm_seed())
    assert "compile ok" in out and "run ok" in out, out
