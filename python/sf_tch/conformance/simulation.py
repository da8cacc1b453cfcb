"""Simulation and test runs: the driver callbacks, their order and contents, the dry
run, stopping, the soft limits (docs/api.md, docs/structures.md, docs/behaviour.md)."""
import ctypes
import threading

from .. import abi
from .checks import Differs, check, expect, near, near_point
from .host import Recorder

A, S, B = "api.md", "structures.md", "behaviour.md"
PROGRAM = "G0 X5 Y5\nG1 X10 Y5 F1000\nM51\nG2 X20 Y5 I5 J0\nG1 X20 Y0\n"


@check("simulation", "order", A, "Callbacks",
       "DriverInitialize before every run, then every part in program order to DriverGFunc / DriverMFunc, "
       "DriverEnd at the end")
def _(host):
    rec = host.simulate(PROGRAM)
    expect(["init", "G", "G", "M", "G", "G", "end"],
           [k for k in rec.kinds() if k in ("init", "G", "M", "end")], "callbacks")


@check("simulation", "initialize_args", A, "Callbacks",
       "DriverInitialize gets the start position (10 values) and the regime")
def _(host):
    rec = host.simulate(PROGRAM, coords=(1.0, 2.0, 3.0))
    (values, mode), = rec.of("init")[:1] or [((), None)]
    expect(10, len(values), "nParams")
    near_point((1, 2, 3), values[:3], 1e-9, "start position")
    expect(10, mode, "runMode")
    rec = host.simulate(PROGRAM, regime=20)
    expect(20, rec.of("init")[-1][1], "runMode of a test")


@check("simulation", "continuity", S, "SIMPLE_GM_PARAMS — one part",
       "each part starts where the one before ended (m_s, m_e), the first at the start position")
def _(host):
    g = host.simulate(PROGRAM, coords=(1.0, 2.0, 0.0)).of("G")
    near_point((1, 2, 0), g[0]["s"], 1e-9, "first start")
    for a, b in zip(g, g[1:]):
        near_point(a["e"], b["s"], 1e-9, "start after an end")


@check("simulation", "cells", S, "SIMPLE_GM_PARAMS — one part",
       "cells a driver relies on: F the feed, G a copy of m_func, N the part's length")
def _(host):
    g = host.simulate(PROGRAM).of("G")
    expect([p["func"] for p in g], [int(p["G"]) for p in g], "cell G")
    expect(1000.0, g[1]["F"], "cell F of G1 … F1000")
    near(5.0, g[1]["N"], 1e-4, "cell N of a 5 mm line")
    near(5.0 * 3.141592653589793, g[2]["N"], 1e-3, "cell N of a half circle of radius 5")


@check("simulation", "file_and_index", S, "SIMPLE_GM_PARAMS — one part",
       "m_fileIdx is the compiled file's index; m_gCodeIndex increases part by part")
def _(host):
    rec = host.simulate(PROGRAM)
    idx = host.lib.ToolChainCore_FileToIdx(0, host.texts.arg("prog.nc"))
    parts = [v for k, v in rec.events if k in ("G", "M")]
    expect({idx}, {p["file"] for p in parts}, "m_fileIdx")
    indexes = [p["index"] for p in parts]
    if any(b <= a for a, b in zip(indexes, indexes[1:])):
        raise Differs("increasing", indexes, "m_gCodeIndex")


@check("simulation", "dry_run", B, "Behaviour worth knowing",
       "a simulation is a dry run: simulating a relative program again starts from the same place")
def _(host):
    host.set_params(0, absMode=0)
    host.reset_cnc(0, (0.0, 0.0, 0.0))
    host.compiled("G1 X10 Y5 F1000\n")
    rec = Recorder(host, 0)
    ends = []
    for _ in range(2):
        host.reset_cnc(0)
        host.start(0, 10)
        host.wait(0, lambda s: s != 10)
        ends.append(rec.of("G")[-1]["e"][:2])
    expect([(10.0, 5.0)] * 2, [tuple(round(v, 9) for v in e) for e in ends], "ends of two simulations")


@check("simulation", "getpos_after", S, "SIMPLE_GM_PARAMS — one part",
       "GetPos after a simulation shows the last part standing at its end")
def _(host):
    host.simulate(PROGRAM)
    part, enh = host.pos(0)
    near_point((20, 0), (part.m_e.x, part.m_e.y), 1e-9, "m_e")
    expect(-10, enh.m_statusCNC, "m_statusCNC")


@check("simulation", "add_code", A, "Running",
       "StartCNCEx's addCode: its M functions go to DriverMFunc before the program's parts, file __exec__")
def _(host):
    host.reset_cnc(0, (0.0, 0.0, 0.0))
    host.compiled(PROGRAM)
    rec = Recorder(host, 0)
    host.reset_cnc(0)
    host.start(0, 10, b"M52")
    host.wait(0, lambda s: s != 10)
    parts = [(k, v["func"], v["file"]) for k, v in rec.events if k in ("G", "M")]
    expect(("M", 52, -4), parts[0] if parts else None, "first part")


@check("simulation", "progress", A, "Callbacks",
       "SetStatusBarProgress reports a simulation's progress in percent (0 … 100, never falling)")
def _(host):
    rec = host.simulate(PROGRAM * 20)
    pct = rec.of("progress")
    if not pct or any(not 0 <= p <= 100 for p in pct) or any(b < a for a, b in zip(pct, pct[1:])):
        raise Differs("percentages rising within 0 … 100", pct[:20], "SetStatusBarProgress")


@check("simulation", "stop", A, "cnc_status",
       "StopCNCEx while a simulation runs: -11 (a test: -21)")
def _(host):
    for regime in (10, 20):
        host.reset_cnc(0, (0.0, 0.0, 0.0))
        host.compiled(PROGRAM)
        entered, release = threading.Event(), threading.Event()

        def hold(user, part):
            entered.set()
            release.wait(5)
            return 0
        fn = abi.DriverGFunc(hold)
        host.load_ini(0)
        host.lib.ToolChainCore_SetCallBack(0, abi.CB_DRIVER_G_FUNC, 0, ctypes.cast(fn, ctypes.c_void_p))
        host.reset_cnc(0)
        host.start(0, regime)
        entered.wait(5)
        rc = host.lib.ToolChainCore_StopCNCEx(0, None)
        release.set()
        expect(0, rc, f"StopCNCEx in {regime}")
        expect(-regime - 1, host.wait(0, lambda s: s != regime), "status")
        host.lib.ToolChainCore_SetCallBack(0, abi.CB_DRIVER_G_FUNC, 0, None)


@check("simulation", "test_soft_limits", S, "MACHINE_PARAMETERS — Get/SetMachineParameters",
       "the test regime (20) checks each part against the soft limits: a part beyond them is an error on its line")
def _(host):
    m = abi.MACHINE_PARAMETERS()
    expect(0, host.lib.ToolChainCore_GetMachineParameters(0, ctypes.byref(m)), "GetMachineParameters")
    old = abi.MACHINE_PARAMETERS.from_buffer_copy(m)
    for i in range(10):
        m.minCoords.__setattr__(abi.AXES[i], -100.0)
        m.maxCoords.__setattr__(abi.AXES[i], 100.0)
        m.refCoords.__setattr__(abi.AXES[i], 0.0)
        m.enableMask.__setattr__(abi.AXES[i], 1)
    expect(0, host.lib.ToolChainCore_SetMachineParameters(0, ctypes.byref(m)), "SetMachineParameters")
    try:
        host.simulate("G1 X50 F1000\nG1 X150\nG1 X0\n", regime=20)
        err = host.last_error(0)
        if err is None:
            raise Differs("an error on line 2", None, "GetLastError after the test")
        expect(2, err[1], "actLine")
        host.simulate("G1 X50 F1000\nG1 X150\nG1 X0\n", regime=10)
        expect(None, host.last_error(0), "GetLastError after a simulation (no limits)")
    finally:
        host.lib.ToolChainCore_SetMachineParameters(0, ctypes.byref(old))


@check("simulation", "no_driver_no_calls", A, "Callbacks",
       "a simulation without driver callbacks still ends at -10")
def _(host):
    host.reset_cnc(0, (0.0, 0.0, 0.0))
    host.compiled(PROGRAM)
    host.reset_cnc(0)
    host.start(0, 10)
    expect(-10, host.wait(0, lambda s: s != 10), "status")
