"""The core's state machine end to end, as an HMI drives it through ctypes:
compilation in the background thread, errors, simulation with the driver
callbacks, stop, reset, run time and size info."""
import ctypes
import math
import random
import threading
import time

import pytest

import sf_tch
from sf_tch import abi
from sf_tch.core import CncError, Core

CORE = 1


@pytest.fixture
def core():
    with Core(CORE) as c:
        saved = c.params
        c.update_params(absMode=1, calcTime=1)
        c.reset([0.0] * 10)                 # the machine position outlives DestroyCNC
        yield c
        c.lib.ToolChainCore_DestroyCNC(CORE)
        c.params = saved


def big_program(lines: int) -> str:
    body = []
    for i in range(lines // 2):
        body.append(f"G1 X{i % 500}.5 Y{(i * 7) % 300}.25 F2000")
        body.append(f"G2 X{i % 500}.5 Y{(i * 7) % 300 + 10}.25 I0 J5")
    return "\n".join(body) + "\n"


def wait_status(lib, core, predicate, timeout=60.0):
    deadline = time.monotonic() + timeout
    while True:
        status = lib.ToolChainCore_StatusCNC(core)
        if predicate(status):
            return status
        assert time.monotonic() < deadline, f"status stuck at {status}"
        time.sleep(0.001)


def test_compile_returns_at_once_with_running_status(core):
    lib = core.lib
    code = big_program(200_000).encode()
    assert lib.ToolChainCore_CompileFromMemory(CORE, b"big.nc", code) == 0
    first = lib.ToolChainCore_StatusCNC(CORE)
    assert first in (1, -1)                     # never the status from before
    # a second compilation while the first runs is refused
    if first == 1:
        assert lib.ToolChainCore_CompileFromMemory(CORE, b"other.nc", b"G1 X1\n") in (-1, 0)
    assert wait_status(lib, CORE, lambda s: s != 1) == -1
    info = abi.CALLBACK_INFO()
    assert lib.ToolChainCore_GetLastError(CORE, ctypes.byref(info)) == 0


def test_busy_core_refuses_a_second_compilation(core):
    lib = core.lib
    assert lib.ToolChainCore_CompileFromMemory(CORE, b"big.nc", big_program(600_000).encode()) == 0
    refused = lib.ToolChainCore_CompileFromMemory(CORE, b"x.nc", b"G1 X1\n")
    if lib.ToolChainCore_StatusCNC(CORE) == 1 or refused == -1:
        assert refused == -1
        assert lib.ToolChainCore_IsBusy(CORE) in (0, 1)
    wait_status(lib, CORE, lambda s: s != 1)


def test_reset_interrupts_a_compilation_and_the_core_stays_usable(core):
    lib = core.lib
    assert lib.ToolChainCore_CompileFromMemory(CORE, b"huge.nc", big_program(2_000_000).encode()) == 0
    started = time.monotonic()
    assert lib.ToolChainCore_ResetCNC(CORE, 0, 0, None) == 0
    assert lib.ToolChainCore_StatusCNC(CORE) != 1
    assert time.monotonic() - started < 30
    core.compile_text("G1 X10 Y0 F1000\n", "after.nc")
    assert core.status == -1


def test_destroy_while_compiling_is_safe_twice(core):
    lib = core.lib
    assert lib.ToolChainCore_CompileFromMemory(CORE, b"huge.nc", big_program(1_000_000).encode()) == 0
    assert lib.ToolChainCore_DestroyCNC(CORE) == 0
    assert lib.ToolChainCore_DestroyCNC(CORE) == 0
    assert lib.ToolChainCore_StatusCNC(CORE) == 0


def test_compile_error_reaches_every_channel_with_file_and_line(core):
    located, logged = [], []
    core.set_callback(abi.CB_DISP_AND_LOCATE_ERROR,
                      abi.DispAndLocateError(lambda u, line, f, text, info: located.append((line, f, text)) or 0))
    core.set_callback(abi.CB_ADD_OUTPUT_LOG,
                      abi.AddOutputLog(lambda u, tab, text, info: logged.append((tab, text)) or 0))
    with pytest.raises(CncError) as caught:
        core.compile_text("G1 X10 F100\nG1 Y10\nG1 X0 QQQ\nG1 Y0\n", "bad.nc")
    error = caught.value
    assert error.line == 3
    assert error.file == "bad.nc"
    assert error.number != 0 and error.text
    index = core.file_index("bad.nc")
    assert located and located[0][0] == 3 and located[0][1] == index
    info = abi.CALLBACK_INFO()
    assert core.lib.ToolChainCore_GetLastError(CORE, ctypes.byref(info)) == 1
    assert (info.nLines, info.actLine, info.fileIdx) == (4, 3, index)
    assert any(tab == 0 for tab, _ in logged)
    # still usable
    core.compile_text("G1 X10 F100\n", "good.nc")
    assert core.last_error() is None


def test_simulation_calls_the_driver_in_program_order(core):
    events = []
    core.set_callback(abi.CB_DRIVER_INITIALIZE,
                      abi.DriverInitialize(lambda u, params, n, mode: events.append(("init", mode)) or 0))
    core.set_callback(abi.CB_DRIVER_END, abi.DriverEnd(lambda u: events.append(("end",)) or 0))
    core.compile_text("G0 X10 Y10\nM51\nG1 X20 F1000\nG2 X30 Y10 I5 J0\nM50\nG0 X0 Y0\nM30\n", "order.nc")
    g_parts, m_parts = [], []
    core.set_callback(abi.CB_DRIVER_G_FUNC, abi.DriverGFunc(
        lambda u, p: events.append(("G", p.contents.m_func, p.contents.m_editorLine)) or 0))
    core.set_callback(abi.CB_DRIVER_M_FUNC, abi.DriverMFunc(
        lambda u, p: events.append(("M", p.contents.m_func, p.contents.m_editorLine)) or 0))
    core.lib.ToolChainCore_ResetCNC(CORE, 1, 0, None)
    assert core.status == -30
    assert core.lib.ToolChainCore_StartCNCEx(CORE, 10, None) == 0
    assert core.wait() == -10
    assert events[0] == ("init", 10)
    assert events[-1] == ("end",)
    assert events[1:-1] == [("G", 0, 1), ("M", 51, 2), ("G", 1, 3), ("G", 2, 4), ("M", 50, 5),
                            ("G", 0, 6), ("M", 30, 7)]


def test_parts_carry_positions_centres_and_indexes(core):
    core.compile_text("G0 X10 Y0\nG1 X20 Y0 F1500\nG3 X30 Y10 I0 J10\n", "parts.nc")
    run = core.simulate()
    parts = run.parts
    assert list(parts["m_func"]) == [0, 1, 3]
    indexes = list(parts["m_gCodeIndex"])
    assert indexes == sorted(indexes) and len(set(indexes)) == 3
    arc = parts[2]
    assert arc["m_s"]["x"] == pytest.approx(20) and arc["m_e"]["y"] == pytest.approx(10)
    assert (arc["m_cc"]["x"], arc["m_cc"]["y"], arc["m_cc"]["c"]) == pytest.approx((20, 10, 10))
    assert arc["m_pars"]["N"] == pytest.approx(math.pi * 10 / 2, rel=1e-6)
    assert arc["m_pars"]["F"] == pytest.approx(1500)
    assert arc["m_planeTool"] & 0xFFFF == 17
    assert parts[1]["m_bFeedIsMin"] & 0xFFFF == 1
    assert (parts[1]["m_calcE"]["x"], parts[1]["m_calcE"]["y"]) == pytest.approx((20, 0))


def test_stop_during_simulation_gives_minus_11(core):
    core.compile_text("".join(f"G1 X{i} Y{i % 7} F1000\n" for i in range(2000)), "slow.nc")
    gate = threading.Event()

    def slow_driver(user, part):
        gate.set()
        time.sleep(0.002)
        return 0

    core.set_callback(abi.CB_DRIVER_G_FUNC, abi.DriverGFunc(slow_driver))
    core.lib.ToolChainCore_ResetCNC(CORE, 1, 0, None)
    assert core.lib.ToolChainCore_StartCNCEx(CORE, 10, None) == 0
    assert core.status in (10, -10)
    assert gate.wait(10)
    assert core.lib.ToolChainCore_StopCNCEx(CORE, None) == 0
    assert core.wait() == -11
    assert core.lib.ToolChainCore_StopCNCEx(CORE, None) == -1      # nothing runs now


def test_getpos_answers_while_compiling(core):
    lib = core.lib
    assert lib.ToolChainCore_CompileFromMemory(CORE, b"big.nc", big_program(400_000).encode()) == 0
    pos, enh = abi.SIMPLE_GM_PARAMS(), abi.GM_PARAMS_ENHANCED()
    answers = 0
    while lib.ToolChainCore_StatusCNC(CORE) == 1:
        assert lib.ToolChainCore_GetPos(CORE, 0, ctypes.byref(pos), ctypes.byref(enh)) == 0
        assert enh.m_statusCNC in (1, -1)
        answers += 1
    assert answers >= 0
    assert lib.ToolChainCore_GetPos(CORE, 0, None, None) == -1


def test_progress_reaches_100(core):
    seen = []
    core.set_callback(abi.CB_SET_STATUS_BAR_PROGRESS,
                      abi.SetStatusBarProgress(lambda u, percent: seen.append(percent) or 0))
    core.compile_text(big_program(20_000), "progress.nc")
    assert seen and seen[-1] == 100
    assert seen == sorted(seen)


def test_run_time_of_a_single_line_is_its_trapezoid(core):
    p = core.params
    p.motion[1].acc = p.motion[1].dec = 500.0
    core.params = p
    core.compile_text("G1 X100 F6000\n", "time.nc")
    core.simulate()
    # 100 mm at 100 mm/s with 500 mm/s^2: 1 s cruising + 0.1 s up + 0.1 s down
    assert core.run_time(core.file_index("time.nc")) == pytest.approx(1.2, rel=1e-7)     # the plan keeps floats
    assert core.run_time() == pytest.approx(1.2, rel=1e-7)


def test_size_info_counts_true_arc_extremes(core):
    core.compile_text("G0 X10 Y0\nG3 X-10 Y0 I-10 J0\n", "arc.nc")
    size = core.size_info().m_size[0]
    assert size.m_maximalPos.y == pytest.approx(10)
    assert size.m_minimalPos.x == pytest.approx(-10)
    assert size.m_minimalPos.y == pytest.approx(0)
    assert (size.m_endPos.x, size.m_endPos.y) == pytest.approx((-10, 0))


def _random_arcs(rng, count):
    """A chain of random arcs (G40): most of them small, inside the others' extent."""
    lines = ["G0 X0 Y0", "G1 X1 Y0 F3000"]
    x, y = 1.0, 0.0
    for _ in range(count):
        r = rng.uniform(0.6, 12.0) if rng.random() < 0.9 else rng.uniform(20.0, 40.0)
        a = rng.uniform(0, 2 * math.pi)
        cx, cy = x - r * math.cos(a), y - r * math.sin(a)          # (x, y) lies on the circle
        sweep = rng.uniform(0.2, 1.9 * math.pi) * rng.choice((1, -1))
        ex, ey = cx + r * math.cos(a + sweep), cy + r * math.sin(a + sweep)
        lines.append(f"G{3 if sweep > 0 else 2} X{ex:.6f} Y{ey:.6f} I{cx - x:.6f} J{cy - y:.6f}")
        x, y = ex, ey
    return "\n".join(lines) + "\n"


def _random_circles(rng, count):
    """Separate full circles cut clockwise under G41 (the tool outside, r + radius)."""
    lines = []
    for _ in range(count):
        r = rng.uniform(0.5, 8.0)
        cx, cy = rng.uniform(-60, 60), rng.uniform(-60, 60)
        lines += [f"G0 X{cx + r + 2:.6f} Y{cy:.6f}", f"G41 G1 X{cx + r:.6f} Y{cy:.6f} F3000",
                  f"G2 X{cx + r:.6f} Y{cy:.6f} I{-r:.6f} J0", f"G40 G1 X{cx + r + 2:.6f} Y{cy:.6f}"]
    return "\n".join(lines) + "\n"


def _dense_xy(toolpath, tool):
    """x y of every move's ends and of its arcs sampled at 20,000 points (the sagitta
    under 1e-6 mm for r <= 40 mm): the oracle of the extent."""
    import numpy as np
    rec = toolpath.records[toolpath.records["kind"] == sf_tch.PartKind.MOTION]
    start = (toolpath.tool_start()[toolpath.records["kind"] == sf_tch.PartKind.MOTION] if tool
             else rec["start"])[:, :2]
    end = rec["tool_end" if tool else "end"][:, :2]
    out = [start, end]
    for s, e, c, number in zip(start, end, rec["centre"][:, :2], rec["number"]):
        if number not in (2, 3):
            continue
        a0 = math.atan2(s[1] - c[1], s[0] - c[0])
        sweep = math.atan2(e[1] - c[1], e[0] - c[0]) - a0
        sweep = sweep % (2 * math.pi) if number == 3 else -((-sweep) % (2 * math.pi))
        if abs(sweep) < 1e-12:
            sweep = 2 * math.pi if number == 3 else -2 * math.pi
        t = a0 + sweep * np.linspace(0.0, 1.0, 20001)
        r = math.hypot(s[0] - c[0], s[1] - c[1])
        out.append(np.column_stack([c[0] + r * np.cos(t), c[1] + r * np.sin(t)]))
    return np.concatenate(out)


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_size_info_holds_every_point_of_random_arcs(seed):
    """The extents, programmed and compensated, against the toolpath sampled densely
    (every arc at 20,000 points): each side of the extent within 1e-6 mm of the
    samples' own. Most arcs lie inside the extent of the others (extent.pyx skips
    them), some widen it."""
    rng = random.Random(seed)
    for text, radius, kind in ((_random_arcs(rng, 200), None, 0), (_random_circles(rng, 60), 0.1, 1)):
        with sf_tch.compile(text, radius=radius, params={"absMode": 1}, start=[0.0] * 10) as program:
            program.check()
            size = program.size_info.m_size[kind]
            pts = _dense_xy(program.toolpath, kind == 1)
        assert pts[:, 0].min() == pytest.approx(size.m_minimalPos.x, abs=1e-6)
        assert pts[:, 0].max() == pytest.approx(size.m_maximalPos.x, abs=1e-6)
        assert pts[:, 1].min() == pytest.approx(size.m_minimalPos.y, abs=1e-6)
        assert pts[:, 1].max() == pytest.approx(size.m_maximalPos.y, abs=1e-6)


def _exact_xy_extent(toolpath, tool):
    """min and max of x y over every move, arcs by their ends and the axis points
    (0, 90, 180, 270 degrees) their sweep passes: vectorised closed forms."""
    import numpy as np
    motion = toolpath.records["kind"] == sf_tch.PartKind.MOTION
    rec = toolpath.records[motion]
    start = (toolpath.tool_start()[motion] if tool else rec["start"])[:, :2]
    end = rec["tool_end" if tool else "end"][:, :2]
    points = [start, end]
    arc = np.isin(rec["number"], (2, 3)) & (rec["plane"] == 17)
    s, e, c = start[arc], end[arc], rec["centre"][arc][:, :2]
    r = np.hypot(*(s - c).T)
    a0 = np.arctan2(*(s - c).T[::-1])
    sweep = np.arctan2(*(e - c).T[::-1]) - a0
    ccw = rec["number"][arc] == 3
    sweep = np.where(ccw, np.mod(sweep, 2 * np.pi), -np.mod(-sweep, 2 * np.pi))
    sweep[np.abs(sweep) < 1e-12] = 2 * np.pi        # a full circle
    for k in range(4):
        ahead = np.mod(k * np.pi / 2 - a0, 2 * np.pi)
        passed = np.where(ccw, ahead <= sweep, np.mod(-ahead, 2 * np.pi) <= -sweep)
        direction = np.array([math.cos(k * np.pi / 2), math.sin(k * np.pi / 2)]).round()
        points.append((c + r[:, None] * direction)[passed])
    pts = np.concatenate(points)
    return pts.min(axis=0), pts.max(axis=0)


@pytest.mark.parametrize("rotated", [False, True])
def test_size_info_of_a_large_compensated_program(rotated):
    """A compensated program large enough that its extent is measured beside the
    compensation's merge (pipeline.pyx ExtentBeside: ranges of MERGE_WATCH_STEP moved
    parts), with the outer corners' inserted arcs: the library's extents against the
    closed forms over its own toolpath; with a G168 rotation both the extents as
    written and as run."""
    rng = random.Random(7)
    lines = ["G0 X0 Y0", "G168 X5 Y5 R30" if rotated else "G0 X0 Y0"]
    for k in range(5000):
        x, y, w, h = rng.uniform(-200, 200), rng.uniform(-200, 200), rng.uniform(1, 8), rng.uniform(1, 8)
        lines += [f"G0 X{x:.3f} Y{y - 1:.3f}", f"G42 G1 X{x:.3f} Y{y:.3f} F3000", f"G1 X{x + w:.3f}",
                  f"G3 X{x + w:.3f} Y{y + h:.3f} I0 J{h / 2:.3f}", f"G1 X{x:.3f}", f"G1 Y{y:.3f}",
                  f"G40 G1 X{x:.3f} Y{y - 1:.3f}"]
    with sf_tch.compile("\n".join(lines) + "\n", radius=0.2, params={"absMode": 1},
                        start=[0.0] * 10) as program:
        program.check()
        assert len(program.toolpath.records) > 2 * 16384        # enough moved parts for the thread
        info = program.size_info
        tp = program.toolpath
        for kind, tool in ((2, False), (3, True)):              # as the machine runs it
            lo, hi = _exact_xy_extent(tp, tool)
            size = info.m_size[kind]
            assert (size.m_minimalPos.x, size.m_minimalPos.y) == pytest.approx(tuple(lo), abs=1e-9)
            assert (size.m_maximalPos.x, size.m_maximalPos.y) == pytest.approx(tuple(hi), abs=1e-9)
        last = tp.records[tp.records["kind"] == sf_tch.PartKind.MOTION][-1]
        assert (info.m_size[3].m_endPos.x, info.m_size[3].m_endPos.y) == pytest.approx(tuple(last["tool_end"][:2]))
        if rotated:     # as written: the rotation undone, another extent
            assert info.m_size[0].m_maximalPos.x != pytest.approx(info.m_size[2].m_maximalPos.x, abs=1e-3)
        else:
            assert info.m_size[0].m_maximalPos.x == info.m_size[2].m_maximalPos.x


@pytest.mark.parametrize("middle_y", [300.001, 0.001])
def test_size_info_after_the_joins_of_a_program_measured_beside_its_merge(middle_y):
    """The extent measured beside the merge stays the program's when the joins that
    follow leave out no end point on one of its bounds, and is measured again when
    they do: a large compensated program (its extent measured beside the merge) ends
    with three nearly collinear uncompensated lines the joins make one (tolerance[2]
    0.03 degrees, [3] 0.005 mm); the end point they leave out is the program's
    highest (300.001) or lies inside (0.001). The extents against the closed forms
    over the toolpath, which no longer holds that point."""
    import numpy as np
    rng = random.Random(11)
    lines = ["G0 X0 Y0"]
    for k in range(5000):
        x, y, w, h = rng.uniform(-200, 200), rng.uniform(-200, 200), rng.uniform(1, 8), rng.uniform(1, 8)
        lines += [f"G0 X{x:.3f} Y{y - 1:.3f}", f"G42 G1 X{x:.3f} Y{y:.3f} F3000", f"G1 X{x + w:.3f}",
                  f"G1 Y{y + h:.3f}", f"G1 X{x:.3f}", f"G1 Y{y:.3f}", f"G40 G1 X{x:.3f} Y{y - 1:.3f}"]
    base = 300.0 if middle_y > 1 else 0.0
    lines += [f"G0 X-50 Y{base}", f"G1 X0 Y{middle_y} F3000", f"G1 X50 Y{base}"]
    with sf_tch.compile("\n".join(lines) + "\n", radius=0.2, params={"absMode": 1},
                        start=[0.0] * 10) as program:
        program.check()
        tp = program.toolpath
        assert len(tp.records) > 16384                          # the merge's thread measured
        assert not (np.abs(tp.records["end"][:, 1] - middle_y) < 1e-9).any()    # joined away
        info = program.size_info
        for kind, tool in ((2, False), (3, True)):
            lo, hi = _exact_xy_extent(tp, tool)
            size = info.m_size[kind]
            assert (size.m_minimalPos.x, size.m_minimalPos.y) == pytest.approx(tuple(lo), abs=1e-9)
            assert (size.m_maximalPos.x, size.m_maximalPos.y) == pytest.approx(tuple(hi), abs=1e-9)
        if middle_y > 1:
            assert info.m_size[2].m_maximalPos.y == 300.0       # the point left out was the highest


def test_test_regime_reports_machine_limit_violations(core):
    machine = abi.MACHINE_PARAMETERS()
    machine.minCoords.x, machine.maxCoords.x = 0.0, 50.0
    machine.enableMask.x = 1
    assert core.lib.ToolChainCore_SetMachineParameters(CORE, ctypes.byref(machine)) == 0
    try:
        core.compile_text("G1 X10 F1000\nG1 X100\nG1 X0\n", "limits.nc")
        with pytest.raises(CncError) as caught:
            core.simulate(regime=20)
        assert caught.value.line == 2
        assert "X" in caught.value.text and "100" in caught.value.text
        assert core.status == -20
    finally:
        assert core.lib.ToolChainCore_SetMachineParameters(CORE, ctypes.byref(abi.MACHINE_PARAMETERS())) == 0


def test_reset_moves_a_relative_program_with_its_start(core):
    core.update_params(absMode=0)
    core.compile_text("G1 X10 Y0 F1000\nG1 X0 Y10\n", "rel.nc")
    core.reset([5.0, 5.0])
    run = core.simulate()
    ends = [(p["m_e"]["x"], p["m_e"]["y"]) for p in run.parts]
    assert ends == [pytest.approx((15, 5)), pytest.approx((15, 15))]


def test_the_seven_other_axes_through_parts_size_info_and_reset(core):
    # axes c b u v w a o are kept apart from x y z (an entry per change): every part
    # still reports all ten, the size info covers them, a relative program moves them
    core.compile_text("G1 X1 C5 F1000\nG1 X2\nG1 U-3 O7\nG1 X3\nG1 C0 U0 O0\n", "axes.nc")
    run = core.simulate()
    ends = [(p["m_e"]["x"], p["m_e"]["c"], p["m_e"]["u"], p["m_e"]["o"]) for p in run.parts]
    starts = [(p["m_s"]["x"], p["m_s"]["c"], p["m_s"]["u"], p["m_s"]["o"]) for p in run.parts]
    assert ends == [(1, 5, 0, 0), (2, 5, 0, 0), (2, 5, -3, 7), (3, 5, -3, 7), (3, 0, 0, 0)]
    assert starts == [(0, 0, 0, 0)] + ends[:-1]
    size = core.size_info().m_size[0]
    assert (size.m_minimalPos.c, size.m_maximalPos.c) == (0, 5)
    assert (size.m_minimalPos.u, size.m_maximalPos.u) == (-3, 0)
    assert (size.m_minimalPos.o, size.m_maximalPos.o) == (0, 7)
    assert (size.m_endPos.x, size.m_endPos.c) == (3, 0)
    core.update_params(absMode=0)
    core.compile_text("G1 X1 C5 F1000\nG1 U-3\n", "axes_rel.nc")
    core.reset([10.0, 0, 0, 100.0, 0, 50.0])
    run = core.simulate()
    ends = [(p["m_e"]["x"], p["m_e"]["c"], p["m_e"]["u"]) for p in run.parts]
    assert ends == [(11, 105, 50), (11, 105, 47)]


def test_compensated_size_info_under_a_rotation(core):
    # a square compensated outside (corner arcs inserted) and turned by G168: as
    # written, [1] is the square grown by the radius; as run, [3] is that turned
    p = core.params
    for i in range(8):
        p.correction[i].size = 2.0
    core.params = p
    core.compile_text("G168 X0 Y0 R30\nG0 X0 Y-20\nG42 G1 X0 Y-10 F1000\nX10\nY10\nX-10\nY-10\nX0\n"
                      "G40 X0 Y-20\n", "rotsq.nc")
    size = core.size_info().m_size
    written = size[1]
    assert (written.m_minimalPos.x, written.m_maximalPos.x) == pytest.approx((-12, 12))
    assert (written.m_minimalPos.y, written.m_maximalPos.y) == pytest.approx((-20, 12))
    # as run: the corner arc about (10, -10), turned by 30 degrees, reaches furthest in x
    c, s30 = math.cos(math.radians(30)), math.sin(math.radians(30))
    assert size[3].m_maximalPos.x == pytest.approx(10 * (c + s30) + 2)


def test_size_info_original_and_rotated(core):
    # G168: the program turned by 90 degrees about (0, 0); [0]/[1] are the program as
    # written, [2]/[3] as the machine runs it
    core.compile_text("G0 X0 Y0\nG168 X0 Y0 R90\nG1 X10 Y0 F1000\nG1 X10 Y5\nG169\nG1 X20 Y0\n", "rot.nc")
    size = core.size_info().m_size
    original, rotated = size[0], size[2]
    assert (original.m_minimalPos.x, original.m_maximalPos.x) == pytest.approx((0, 20))
    assert (original.m_minimalPos.y, original.m_maximalPos.y) == pytest.approx((0, 5))
    assert (rotated.m_minimalPos.x, rotated.m_maximalPos.x) == pytest.approx((-5, 20))
    assert (rotated.m_minimalPos.y, rotated.m_maximalPos.y) == pytest.approx((0, 10))
    assert (size[3].m_maximalPos.y, size[1].m_maximalPos.y) == pytest.approx((10, 5))


def test_the_plan_beside_the_joins_is_the_plan_after_them():
    """A program of squares cut one after the other, each between two waiting M
    functions (where the machine stands), none of whose lines join another: with the
    joins on (tolerance[2], the default) the plan is made beside them, range by range
    from both ends (pipeline.pyx PlanAhead); with them off it is made after them
    (plan_beside_extent). The same parts, so the same plan: the same run time, the same
    extents and tool path. Under the thread sanitizer (tests/test_sanitizers.py) the
    ranges' threads are checked for races."""
    rng = random.Random(11)
    lines = ["G90 G17"]
    for k in range(12000):
        x, y, w = (k % 60) * 30.0, (k // 60) * 30.0, rng.uniform(5, 20)
        lines += [f"G0 X{x - 2:.3f} Y{y - 2:.3f}", "M51", f"G1 X{x:.3f} Y{y:.3f} F{rng.choice((1500, 3000))}",
                  f"G1 X{x + w:.3f}", f"G1 Y{y + w:.3f}", f"G1 X{x:.3f}", f"G1 Y{y:.3f}", "M50"]
    text = "\n".join(lines) + "\n"
    with sf_tch.Core() as c:
        tolerance = list(c.params.tolerance)
    assert 0.0 < tolerance[2] < 90.0                # the joins are on by default
    results = []
    for joins in (tolerance[2], 0.0):
        tolerance[2] = joins
        with sf_tch.compile(text, params={"calcTime": 1, "tolerance": tuple(tolerance)}, start=[0.0] * 10,
                            keep_core=True) as program:
            program.check()
            records = program.toolpath.records
            assert len(records) > 2 * 32768          # ranges of both threads (PLAN_AHEAD_STEP), and then some
            results.append((records.tobytes(), bytes(program.size_info), program.run_time))
    assert results[0] == results[1]


def test_settings_records_are_compared_as_the_words_they_are(harness):
    """program.pxd compares a PartSettings byte for byte (settings_equal's memcmp) and
    hashes it as SETTINGS_HASH_WORDS 32-bit words (copied out, not read through a cast
    pointer): the record must be exactly that long, without padding a field could
    leave undefined."""
    size, words = harness.settings_layout()
    assert size == words == 24
