"""The offline machine from a panel's side, in real time: regimes 30–33, the stop
distance, M functions and their handshake, breakpoints, the override, manual moves
and connections (docs/machine.md, docs/api.md, docs/structures.md). Programs are
short (about a second of machine time in all); GetPos and StatusCNC are polled."""
import ctypes
import threading
import time
from ctypes import c_double

from .. import abi
from .checks import Differs, check, expect, near, near_point
from .host import Recorder

M, A, S = "machine.md", "api.md", "structures.md"
FEED = 6000.0          # mm/min: 100 mm/s
ACC = 2000.0           # mm/s²


def setup(host, code, coords=(0.0, 0.0, 0.0), stop_dec=1000.0, **params):
    """Fast, short moves; compiled from coords; the machine at the program start (-30)."""
    def edit(p):
        for k in (0, 1, 2, 3, 4, 5):
            p.motion[k].feed, p.motion[k].acc, p.motion[k].dec, p.motion[k].rampType = FEED, ACC, ACC, 1
        p.motion[6].dec = stop_dec
        p.motion[6].rampType = 1
    host.set_params(0, edit=edit, **params)
    host.machine(code, coords=coords)


def xy(host):
    """GetPos's current position (m_calcS) in x and y."""
    part, _ = host.pos(0)
    return (part.m_calcS.x, part.m_calcS.y)


def watch(host, until, timeout=5.0, every=None):
    """Polls until the status is in until; (final status, samples of (status, x, actFeed,
    relFeed)); every(status) is called on each poll."""
    samples, deadline = [], time.monotonic() + timeout
    while True:
        part, enh = host.pos(0)
        s = host.status(0)
        samples.append((s, part.m_calcS.x, enh.m_actFeed, enh.m_relFeed))
        if every:
            every(s)
        if s in until:
            return s, samples
        if time.monotonic() > deadline:
            raise Differs(f"a status in {tuple(until)}", s, f"status after {timeout:g} s")
        time.sleep(0.001)


@check("machine", "forward_to_end", A, "How the status moves",
       "-30 -StartCNCEx 30-> 30 -> -32 at the end of the trajectory, standing at the program's end")
def _(host):
    setup(host, "G1 X10 Y5 F6000\nG1 X20 Y5\n")
    host.start(0, 30)
    s, samples = watch(host, (-32,))
    if not any(st == 30 for st, *_ in samples):
        raise Differs("status 30 while it moves", sorted({st for st, *_ in samples}), "statuses seen")
    near_point((20, 5), xy(host), 1e-6, "GetPos m_calcS at the end")


@check("machine", "forward_from_compiled", A, "How the status moves",
       "StartCNCEx 30 also starts from -1 (a compiled program) without ResetCNC")
def _(host):
    setup(host, "G1 X10 F6000\n")
    host.compiled("G1 X10 F6000\n")
    host.start(0, 30)
    watch(host, (-32,))
    near_point((10, 0), xy(host), 1e-6, "the end")


@check("machine", "getpos_moves", S, "GM_PARAMS_ENHANCED — GetPos",
       "while it runs, GetPos shows the position moving forward, status 30, the feed at most the programmed one")
def _(host):
    setup(host, "G1 X30 F3000\n")
    host.start(0, 30)
    _, samples = watch(host, (-32,))
    running = [smp for smp in samples if smp[0] == 30]
    xs = [smp[1] for smp in running]
    if len(set(round(x, 6) for x in xs)) < 3 or any(b < a - 1e-9 for a, b in zip(xs, xs[1:])):
        raise Differs("x rising through several values", xs[:8], "positions while running")
    top = max(smp[2] for smp in running)
    if top > 3000 * 1.001:
        raise Differs("m_actFeed <= 3000", top, "the highest feed")


@check("machine", "counters", S, "GM_PARAMS_ENHANCED — GetPos",
       "GetPos counts cuts and rapids and their lengths so far")
def _(host):
    setup(host, "G0 X5\nG1 X10 F6000\nG1 X15\n")
    host.start(0, 30)
    watch(host, (-32,))
    _, enh = host.pos(0)
    expect((2, 1), (enh.m_nWorkCounter, enh.m_nG00Counter), "(m_nWorkCounter, m_nG00Counter)")
    near(10.0, enh.m_actWorkPartsLen, 1e-6, "m_actWorkPartsLen")
    near(5.0, enh.m_actG00PartsLen, 1e-6, "m_actG00PartsLen")
    near(15.0, enh.m_actPartsLen, 1e-6, "m_actPartsLen")


@check("machine", "stop_distance", M, "Commands while it runs",
       "StopCNCEx: a stop on the path with motion[6].dec, standing after v²/2d; then -31")
def _(host):
    setup(host, "G1 X100 F6000\n", stop_dec=1000.0)
    host.start(0, 30)
    deadline = time.monotonic() + 2
    while True:
        part, enh = host.pos(0)
        if enh.m_actFeed >= FEED * 0.999 and part.m_calcS.x > 10:
            break
        if time.monotonic() > deadline:
            raise Differs("cruising at 6000 mm/min", enh.m_actFeed, "feed")
        time.sleep(0.001)
    x0 = part.m_calcS.x                       # the stop begins after this …
    rc = host.lib.ToolChainCore_StopCNCEx(0, None)
    x1 = xy(host)[0]                          # … and not after this (braking, it is short of it)
    expect(0, rc, "StopCNCEx")
    expect(-31, watch(host, (-31, -32))[0], "status after the stop")
    v = FEED / 60
    d = v * v / (2 * 1000.0)
    end = xy(host)[0]
    tol = 0.15                                # GetPos is published every millisecond or so
    if not x0 + d - tol <= end <= x1 + d + tol:
        raise Differs(f"{d:g} mm (± {tol:g}) after the call", round(end - x0, 4) if end - x0 > d else
                      round(end - x1, 4), "distance from the stop call to standstill")


@check("machine", "continue_after_stop", M, "Regimes",
       "StartCNCEx 30 after a stop continues from the stop point to the end")
def _(host):
    setup(host, "G1 X40 F6000\nG1 X40 Y5\n")
    host.start(0, 30)
    time.sleep(0.1)
    host.lib.ToolChainCore_StopCNCEx(0, None)
    expect(-31, watch(host, (-31, -32))[0], "status after the stop")
    stopped = xy(host)
    host.start(0, 30)
    expect(-32, watch(host, (-32,))[0], "status at the end")
    near_point((40, 5), xy(host), 1e-6, "the end")
    if not 0 < stopped[0] < 40:
        raise Differs("a stop on the first line", stopped, "stop point")


@check("machine", "backward", M, "Regimes",
       "regime 32 after a stop goes back along the path run, ending at -30 at the program's start")
def _(host):
    setup(host, "G1 X20 F6000\nG1 X20 Y10\n")
    host.start(0, 30)
    watch(host, (-32,))
    host.start(0, 32)
    s, samples = watch(host, (-30, -31))
    expect(-30, s, "status after backward")
    if not any(st == 32 for st, *_ in samples):
        raise Differs("status 32 while it moves back", sorted({st for st, *_ in samples}), "statuses")
    near_point((0, 0), xy(host), 1e-6, "the program's start")


@check("machine", "regime31_feed", A, "Regimes of StartCNCEx",
       "regime 31: forward at most at motion[4].feed, no M functions")
def _(host):
    rec = Recorder(host, 0)
    def edit(p):
        p.motion[4].feed = 1200.0
    setup(host, "G1 X5 F6000\nM51\nG1 X10\n")
    host.set_params(0, edit=edit)
    host.compiled("G1 X5 F6000\nM51\nG1 X10\n")
    host.reset_cnc(0, (0.0, 0.0, 0.0))
    host.start(0, 31)
    s, samples = watch(host, (-32,))
    top = max(smp[2] for smp in samples)
    if top > 1200 * 1.001:
        raise Differs("m_actFeed <= 1200", top, "the highest feed in regime 31")
    expect([], [m["func"] for m in rec.of("M")], "M functions sent")


@check("machine", "regime33_skips_first_m", A, "Regimes of StartCNCEx",
       "regime 33: forward without the M functions before the first G function")
def _(host):
    rec = Recorder(host, 0)
    setup(host, "M51\nG1 X5 F6000\nM52\nG1 X10\n")
    host.start(0, 33)
    watch(host, (-32,))
    expect([52], [m["func"] for m in rec.of("M")], "M functions sent")


@check("machine", "m0_pause", A, "cnc_status",
       "M0 stops the program at -33; the next start goes on after it")
def _(host):
    setup(host, "G1 X5 F6000\nM0\nG1 X10\n")
    host.start(0, 30)
    expect(-33, watch(host, (-33, -32))[0], "status at M0")
    near_point((5, 0), xy(host), 1e-6, "position at M0")
    host.start(0, 30)
    expect(-32, watch(host, (-32,))[0], "status at the end")
    near_point((10, 0), xy(host), 1e-6, "the end")


@check("machine", "waiting_m_stops", M, "Commands while it runs",
       "a waiting M function stops the machine: DriverMFunc is called with the machine standing at its place")
def _(host):
    seen = []
    rec = Recorder(host, 0)
    inner = rec.fns[abi.CB_DRIVER_M_FUNC]

    def m(user, part):
        p, e = host.pos(0)
        seen.append((part.contents.m_func, p.m_calcS.x, e.m_actFeed))
        return 0
    rec.fns[abi.CB_DRIVER_M_FUNC] = fn = abi.DriverMFunc(m)
    host.lib.ToolChainCore_SetCallBack(0, abi.CB_DRIVER_M_FUNC, 0, ctypes.cast(fn, ctypes.c_void_p))
    del inner
    setup(host, "G1 X5 F6000\nM51\nG1 X10\n")
    host.start(0, 30)
    watch(host, (-32,))
    if len(seen) != 1:
        raise Differs("one DriverMFunc call (M51)", seen, "calls")
    expect(51, seen[0][0], "m_func")
    near(5.0, seen[0][1], 1e-6, "position during the call")
    near(0.0, seen[0][2], 1e-6, "feed during the call")


@check("machine", "m_handshake_later", M, "Commands while it runs",
       "DriverMFunc answering TC_MFUNC_LATER holds the machine (GetPos m_func = M + 10000, cell M) "
       "until ConfirmMFunc")
def _(host):
    confirm = host.need("ToolChainCore_ConfirmMFunc")
    rec = Recorder(host, 0, m_answer=abi.TC_MFUNC_LATER)
    setup(host, "G1 X5 F6000\nM51\nG1 X10\n")
    host.start(0, 30)
    deadline = time.monotonic() + 3
    while not rec.of("M"):
        if time.monotonic() > deadline:
            raise Differs("a DriverMFunc call", rec.kinds(), "callbacks")
        time.sleep(0.001)
    time.sleep(0.15)
    part, _ = host.pos(0)
    got = (host.status(0), part.m_func, part.m_pars.M, round(part.m_calcS.x, 6))
    expect((30, 10051, 51.0, 5.0), got, "(status, m_func, cell M, x) while it waits")
    expect(0, confirm(0), "ConfirmMFunc")
    expect(-32, watch(host, (-32,))[0], "status after the confirmation")


@check("machine", "start_add_code", M, "Commands while it runs",
       "the M functions of StartCNCEx 30's addCode go to DriverMFunc before anything moves")
def _(host):
    positions = []
    rec = Recorder(host, 0)
    setup(host, "G1 X5 F6000\n")
    host.start(0, 30, b"M61")
    watch(host, (-32,))
    parts = [(k, v["func"]) for k, v in rec.events if k in ("G", "M")]
    expect(("M", 61), parts[0] if parts else None, "the first part to the driver")
    del positions


@check("machine", "stop_add_code", A, "Running",
       "StopCNCEx's addCode: its M functions are sent once stopped (regime 30), then -31")
def _(host):
    rec = Recorder(host, 0)
    setup(host, "G1 X50 F6000\n")
    host.start(0, 30)
    time.sleep(0.1)
    expect(0, host.lib.ToolChainCore_StopCNCEx(0, b"M62"), "StopCNCEx")
    expect(-31, watch(host, (-31, -32))[0], "status")
    expect([62], [m["func"] for m in rec.of("M")], "M functions sent")


@check("machine", "breakpoint", A, "Running",
       "SetBreakpoint(line, file): a run stops just before the first part of that line (-31); the next start passes it")
def _(host):
    setup(host, "G1 X5 F6000\nG1 X10\nG1 X15\n")
    idx = host.lib.ToolChainCore_FileToIdx(0, host.texts.arg("prog.nc"))
    expect(0, host.lib.ToolChainCore_SetBreakpoint(0, 3, idx), "SetBreakpoint")
    host.start(0, 30)
    expect(-31, watch(host, (-31, -32))[0], "status at the breakpoint")
    near_point((10, 0), xy(host), 1e-6, "position at the breakpoint")
    host.start(0, 30)
    expect(-32, watch(host, (-31, -32))[0], "status after the next start")


@check("machine", "is_breakpoint_callback", A, "Callbacks",
       "the IsBreakpoint callback answering 1 for a line stops the run before it (-31)")
def _(host):
    Recorder(host, 0, breakpoint=lambda line, fidx: line == 2)
    setup(host, "G1 X5 F6000\nG1 X10\nG1 X15\n")
    host.start(0, 30)
    expect(-31, watch(host, (-31, -32))[0], "status")
    near_point((5, 0), xy(host), 1e-6, "position at the breakpoint")


@check("machine", "override", M, "Commands while it runs",
       "SetRelFeed: the override is reached by overrideInc per 100 µs and scales the feed (GetPos m_relFeed)")
def _(host):
    setup(host, "G1 X30 F6000\n", overrideInc=0.01)
    expect(0, host.lib.ToolChainCore_SetRelFeed(0, 0.5), "SetRelFeed(0.5)")
    host.start(0, 30)
    _, samples = watch(host, (-32,))
    running = [smp for smp in samples if smp[0] == 30]
    near(0.5, running[-1][3] if running else None, 1e-6, "m_relFeed")
    top = max(smp[2] for smp in running)
    near(3000.0, top, 3000 * 0.01, "the highest feed at 50 %")


@check("machine", "destroy_while_running", A, "Lifecycle",
       "DestroyCNC ends a run at any moment: status 0 once it returns")
def _(host):
    setup(host, "G1 X100 F6000\n")
    host.start(0, 30)
    time.sleep(0.05)
    expect(0, host.lib.ToolChainCore_DestroyCNC(0), "DestroyCNC")
    expect(0, host.status(0), "status")


@check("machine", "reset_while_running", A, "How the status moves",
       "ResetCNC while it runs gives -30 (a program is compiled)")
def _(host):
    setup(host, "G1 X100 F6000\n")
    host.start(0, 30)
    time.sleep(0.05)
    host.reset_cnc(0, (0.0, 0.0, 0.0))
    expect(-30, host.status(0), "status")


@check("machine", "goto_position", A, "Running",
       "GoToPosition: a manual straight move at motion[5], status 50, then -50 at the target")
def _(host):
    setup(host, "G1 X10 F6000\n")
    coords = (c_double * 3)(4.0, 3.0, 0.0)
    expect(0, host.lib.ToolChainCore_GoToPosition(0, 3, coords), "GoToPosition")
    s, samples = watch(host, (-50,))
    near_point((4, 3), xy(host), 1e-6, "position")


@check("machine", "goto_position_ex", A, "Running",
       "GoToPositionEx with m_func 1: a manual line to m_calcE, then -50")
def _(host):
    setup(host, "G1 X10 F6000\n")
    dest = abi.SIMPLE_GM_PARAMS()
    dest.m_func = 1
    dest.m_calcE.x, dest.m_calcE.y = 2.0, -3.0
    dest.m_planeTool = 17
    expect(0, host.lib.ToolChainCore_GoToPositionEx(0, ctypes.byref(dest)), "GoToPositionEx")
    watch(host, (-50,))
    near_point((2, -3), xy(host), 1e-6, "position")


def _off_path(host):
    # a run from the origin first: the program's first part starts where the machine
    # stands when it first runs (behaviour.md), so it is placed there before going off
    setup(host, "G1 X20 Y0 Z0 F6000\nG1 X20 Y10\n")
    host.start(0, 30)
    watch(host, (-32,))
    coords = (c_double * 3)(8.0, 3.0, 0.0)
    expect(0, host.lib.ToolChainCore_GoToPosition(0, 3, coords), "GoToPosition")
    watch(host, (-50,))


@check("machine", "connect_nearest", A, "Connect types of ConnectCNCEx_Plane",
       "connect type 0: to the trajectory's point nearest the coordinates (40, 41), then -31")
def _(host):
    _off_path(host)
    coords = (c_double * 3)(8.0, 3.0, 0.0)
    rc = host.lib.ToolChainCore_ConnectCNCEx_Plane(0, 0, 3, coords, None, 0x3, 0, 0)
    expect(0, rc, "ConnectCNCEx_Plane(0)")
    expect(-31, watch(host, (-31, -50))[0], "status")
    near_point((8, 0), xy(host), 1e-6, "position")


@check("machine", "connect_continue", A, "Connect types of ConnectCNCEx_Plane",
       "connect type 10: as 0, then on forward to the end (-32)")
def _(host):
    _off_path(host)
    coords = (c_double * 3)(8.0, 3.0, 0.0)
    expect(0, host.lib.ToolChainCore_ConnectCNCEx_Plane(0, 10, 3, coords, None, 0x3, 0, 0), "ConnectCNCEx_Plane(10)")
    expect(-32, watch(host, (-32, -31, -50))[0], "status")
    near_point((20, 10), xy(host), 1e-6, "position")


@check("machine", "connect_line_start", A, "Connect types of ConnectCNCEx_Plane",
       "connect type 1: to the start of the part on line coords[0] of file coords[1]")
def _(host):
    _off_path(host)
    idx = host.lib.ToolChainCore_FileToIdx(0, host.texts.arg("prog.nc"))
    coords = (c_double * 2)(2.0, float(idx))
    expect(0, host.lib.ToolChainCore_ConnectCNCEx_Plane(0, 1, 2, coords, None, 0, 0, 0), "ConnectCNCEx_Plane(1)")
    expect(-31, watch(host, (-31, -50))[0], "status")
    near_point((20, 0), xy(host), 1e-6, "position")


@check("machine", "mfunc_standing", A, "Running",
       "MFunc while standing: DriverMFunc gets the caller's M function on the caller's thread")
def _(host):
    rec = Recorder(host, 0)
    setup(host, "G1 X5 F6000\n")
    fun = abi.SIMPLE_GM_PARAMS()
    fun.m_func = 64
    rec.threads.clear()
    expect(0, host.lib.ToolChainCore_MFunc(0, ctypes.byref(fun), 0), "MFunc")
    expect([64], [m["func"] for m in rec.of("M")], "DriverMFunc calls")
    expect({threading.get_ident()}, rec.threads, "the thread of the call")


@check("machine", "driver_calls_of_a_run", A, "Callbacks",
       "a run of the machine: DriverInitialize (the regime 30) first, each part to DriverGFunc as it begins, "
       "DriverEnd at the end")
def _(host):
    rec = Recorder(host, 0)
    setup(host, "G1 X5 F6000\nG1 X10\n")
    host.start(0, 30)
    watch(host, (-32,))
    expect(["init", "G", "G", "end"], [k for k in rec.kinds() if k in ("init", "G", "M", "end")], "callbacks")
    expect(30, rec.of("init")[0][1], "runMode")


@check("machine", "connect_callbacks", A, "Callbacks",
       "a connection calls ConnectPointCalcStart first (nType, the coordinates), ConnectPointCalcEnd with the point found")
def _(host):
    _off_path(host)
    seen = []
    start = abi.ConnectPointCalcStart(
        lambda u, n_type, n, coords, axes: seen.append(("start", n_type, tuple(coords[i] for i in range(n)))) or 0)
    end = abi.ConnectPointCalcEnd(lambda u, part, point: seen.append(("end", point.contents.x, point.contents.y)) or 0)
    for number, fn in ((abi.CB_CONNECT_POINT_CALC_START, start), (abi.CB_CONNECT_POINT_CALC_END, end)):
        expect(0, host.lib.ToolChainCore_SetCallBack(0, number, 0, ctypes.cast(fn, ctypes.c_void_p)), "SetCallBack")
    coords = (c_double * 2)(8.0, 3.0)
    expect(0, host.lib.ToolChainCore_ConnectCNCEx_Plane(0, 0, 2, coords, None, 0x3, 0x3, 0), "ConnectCNCEx_Plane(0)")
    watch(host, (-31, -50))
    if not seen or seen[0][:2] != ("start", 0) or seen[-1][0] != "end":
        raise Differs("ConnectPointCalcStart(0, …) … ConnectPointCalcEnd", seen, "callbacks")
    near_point((8, 3), seen[0][2], 1e-12, "the coordinates ConnectPointCalcStart gets")
    near_point((8, 0), seen[-1][1:], 1e-6, "the point ConnectPointCalcEnd gets")


def _feed_of(host, k, feed):
    def edit(p):
        p.motion[k].feed = feed
    host.set_params(0, edit=edit)


@check("machine", "backward_feed", A, "Regimes of StartCNCEx", "regime 32 runs back at motion[2]")
def _(host):
    setup(host, "G1 X10 Y0 Z0 F6000\n")
    host.start(0, 30)
    watch(host, (-32,))
    _feed_of(host, 2, 1200.0)
    host.start(0, 32)
    _, samples = watch(host, (-30, -31))
    top = max(smp[2] for smp in samples if smp[0] == 32)
    near(1200.0, top, 12.0, "the highest feed backward")


@check("machine", "goto_feed", A, "Running", "GoToPosition moves at motion[5]")
def _(host):
    setup(host, "G1 X10 F6000\n")
    _feed_of(host, 5, 1200.0)
    expect(0, host.lib.ToolChainCore_GoToPosition(0, 2, (c_double * 2)(10.0, 0.0)), "GoToPosition")
    _, samples = watch(host, (-50,))
    top = max(smp[2] for smp in samples if smp[0] == 50)
    near(1200.0, top, 12.0, "the highest feed of the manual move")


@check("machine", "stop_add_code_regime31", A, "Running",
       "StopCNCEx's addCode is not sent in regime 31")
def _(host):
    rec = Recorder(host, 0)
    setup(host, "G1 X50 F6000\n")
    host.start(0, 31)
    time.sleep(0.1)
    expect(0, host.lib.ToolChainCore_StopCNCEx(0, b"M62"), "StopCNCEx")
    expect(-31, watch(host, (-31, -32))[0], "status")
    expect([], [m["func"] for m in rec.of("M")], "M functions sent")


@check("machine", "getpos_cells", S, "SIMPLE_GM_PARAMS — one part",
       "GetPos's cells: G the current part's G number, N the cut length so far, T the rapid length so far")
def _(host):
    setup(host, "G0 X5\nG1 X10 F6000\nG1 X15\n")
    seen = set()

    def sample(status):
        part, _ = host.pos(0)
        if status == 30 and part.m_func in (0, 1):
            seen.add((part.m_func, part.m_pars.G))
    host.start(0, 30)
    watch(host, (-32,), every=sample)
    written = {(func, cell) for func, cell in seen if cell < 1e37}   # the marker: no part published yet
    if (1, 1.0) not in written or any(float(func) != cell for func, cell in written):
        raise Differs("cell G = m_func of the current part", sorted(seen), "(m_func, cell G) while moving")
    part, _ = host.pos(0)
    expect((10.0, 5.0), (round(part.m_pars.N, 4), round(part.m_pars.T, 4)), "cells (N, T) at the end")
