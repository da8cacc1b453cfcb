"""One plan, one run: the offline machine moves what the compile planned.

The machine's step runs through tests/harness (no threads, one 100 us step at a time)
and is checked against closed forms, ruckig and the simulation's run time
(GetGCodeRunTime): each part takes its planned time; a run started away from where
the program was compiled plans its first moves from where the machine stands; a feed
override above 100 % stays under every hard limit (axis speeds, centripetal
acceleration, arc feed table); continuous M functions cost no look-ahead slot; the
arc feed table as the vendor's manual gives it. Through the exports: the first move
after a restart, and a connection moving at motion[3]."""
import ctypes
import math

import pytest

from sf_tch import abi
from test_machine import (ARCS, DT, LINES, SQUARE_G42, api, circle_chords, compile_on, get_pos,  # noqa: F401
                          load, params, poll_run, run_at_override, run_time_of, set_params, start, wait)
from test_planner import AS_WRITTEN, ruckig_time


@pytest.fixture(scope="module")
def mh():
    import harness
    module = harness.load()
    yield module
    module.destroy_all()


def part_times(run):
    """Machine seconds spent in each part (steps counted where they end)."""
    times = {}
    for step in run["steps"]:
        times[step[1]] = times.get(step[1], 0.0) + run["dt"]
    return times


def peak_in(run, part):
    return max(s[3] for s in run["steps"] if s[1] == part)


def axis_speeds(run, part, axis):
    """|d axis / dt| between consecutive steps that both lie in `part`."""
    steps = run["steps"]
    return [abs(b[5 + axis] - a[5 + axis]) / run["dt"] for a, b in zip(steps, steps[1:])
            if a[1] == part and b[1] == part]


# ------------------------------------------------------------------ the plan is the run

@pytest.mark.parametrize("text, window", [(LINES, 0), (ARCS, 0), (circle_chords(), 0), (circle_chords(), 20),
                                          ("G1 X0 F6000\n" + "".join(f"G1 X{0.5 * (k + 1)} M1001\n"
                                                                     for k in range(120)), 0)],
                         ids=["lines", "arcs", "chords", "chords_window20", "continuous_m"])
def test_every_part_takes_its_planned_time(mh, text, window):
    """With nothing changed by the host the machine's profile of each part is the
    plan's: the time it spends in each motion part is the plan's time (to the step)."""
    load(mh, text, window=window)
    plan = mh.plan(0)
    run = mh.run(0, 30)
    assert run["finish"] == "done"
    spent = part_times(run)
    for k, (v_peak, v_exit, seconds) in enumerate(plan):
        if seconds > 0.0 or k in spent:
            assert spent.get(k, 0.0) == pytest.approx(seconds, abs=2 * DT), k
        if k in spent and seconds > 0.0:
            assert peak_in(run, k) <= v_peak * (1 + 1e-9)


def test_the_plan_holds_what_the_run_needs(mh):
    """PartPlan: the limits of each part beside its profile (F3000 line, an arc under
    the centripetal limit, a waiting M function that stops the machine)."""
    load(mh, "G1 X50 F3000\nM7\nG3 X50 Y20 I0 J10\n", rezerva1=abi.GCODE_REZERVA1_APPLY_UNIMPLEMENTED, centripetalAcc=100.0)
    line, m7, arc = mh.part_plans(0)
    assert line["v_cap"] == 50.0 and line["v_ceiling"] == math.inf and line["v_junction"] == 0.0
    assert line["acc"] == line["dec"] == 500.0 and line["ramp"] == 1
    assert m7["v_exit"] == 0.0 and m7["v_junction"] == 0.0
    limit = math.sqrt(100.0 * 10.0)                 # centripetal: v^2 / r <= 100
    assert arc["v_ceiling"] == pytest.approx(limit, rel=1e-7) and arc["v_ceiling"] <= limit
    assert arc["v_cap"] == arc["v_ceiling"] and arc["v_junction"] == 0.0


# ------------------------------------------------------------------ a run from elsewhere

RESTART = "G0 X0 Y0\nG1 X100 F6000\n"
RESTART_CLASSES = dict(motion=[(6000.0, 1000.0, 1000.0, 1)] * 6, startAngle=10.0, endAngle=90.0,
                       minAngleFeed=0.0)        # the reversal at the origin stops


@pytest.mark.parametrize("compiled_at, restart_at", [(0.0, None), (0.0, 50.0), (2.0, None)],
                         ids=["from_the_end", "from_50_50", "compiled_2mm_away"])
def test_the_first_move_after_a_restart_runs_at_its_feed(mh, compiled_at, restart_at):
    """Compiled with the machine at (compiled_at, 0), run to the end (X100), started
    again from there (ResetCNC keeping the position) or from (50, 50): the rapid back
    to the program's start runs at motion[0]'s 100 mm/s, rest to rest with 1000 mm/s^2,
    as the simulation from there says."""
    p = params(mh, **RESTART_CLASSES)
    assert mh.compile_text(0, RESTART, p, 0, [compiled_at] + [0.0] * 9) is None
    assert mh.run(0, 30)["finish"] == "done"
    mh.reset(0, None if restart_at is None else [restart_at, restart_at] + [0.0] * 8)
    start = (100.0, 0.0) if restart_at is None else (restart_at, restart_at)
    expected = mh.simulated_run_time(0)
    run = mh.run(0, 30, max_time=60.0)
    assert run["finish"] == "done"
    first = math.hypot(*start)
    closed = first / 100.0 + 0.1 + 100.0 / 100.0 + 0.1       # each: L / v + v / a
    assert expected == pytest.approx(closed, rel=1e-6)           # the plan keeps floats
    assert run["run_time"] == pytest.approx(expected, abs=2 * DT)
    assert peak_in(run, 0) == pytest.approx(100.0, rel=1e-6)
    assert run["steps"][0][5:7] == pytest.approx(start, abs=0.01)     # it starts where it stood


@pytest.mark.parametrize("text, radius", [(LINES, 0.0), (ARCS, 0.0), (SQUARE_G42, 2.0), (circle_chords(), 0.0)],
                         ids=["lines", "arcs", "square_g42", "chords"])
@pytest.mark.parametrize("at", [(30.0, -20.0, 0.0), (-15.0, 7.0, 5.0)], ids=["aside", "above"])
def test_a_run_from_elsewhere_takes_GetGCodeRunTime(mh, text, radius, at):
    """Compiled at the origin, started from `at`: the simulation from there
    (GetGCodeRunTime) and the machine's run take the same time; the first move is
    the placed one (not the compile's)."""
    load(mh, text, radius=radius)
    at_origin = mh.simulated_run_time(0)
    mh.reset(0, list(at) + [0.0] * 7)
    expected = mh.simulated_run_time(0)
    assert abs(expected - at_origin) > 0.01
    run = mh.run(0, 30)
    assert run["finish"] == "done"
    assert run["run_time"] == pytest.approx(expected, rel=0.005)
    assert run["steps"][0][5:8] == pytest.approx(at, abs=0.01)


# ------------------------------------------------------------------ the override and hard limits

HARD = "G1 X60 F6000\nG4 H0.05\nG3 X60 Y20 I0 J10 F6000\nG1 Y80 F1500\n"


def hard_params(mh, **fields):
    p = abi.GCODE_PARAMETERS.from_buffer_copy(params(mh, **fields))
    p.axisLimits[0].maxFeed = 3000.0                # X: 50 mm/s
    p.centripetalAcc = 200.0                        # on R10: sqrt(2000) = 44.7 mm/s
    p.rezerva1 |= abi.GCODE_REZERVA1_APPLY_UNIMPLEMENTED
    return bytes(p)


def test_an_override_of_200_percent_stays_under_every_hard_limit(mh):
    """SetRelFeed(2.0): X never passes its maxFeed (the line runs rest to rest at
    its 50 mm/s: 60 / 50 + 50 / 500 s, ruckig's time-optimal move), the arc never its
    centripetal acceleration (nor X's speed); where no hard limit binds, the Y line
    of F1500, the override doubles the feed."""
    assert mh.compile_text(0, HARD, hard_params(mh), 0, [0.0] * 10) is None
    run = run_at_override(mh, 2.0)
    assert run["finish"] == "done"
    assert max(axis_speeds(run, 0, 0)) <= 50.0 * (1 + 1e-6)
    assert peak_in(run, 0) == pytest.approx(50.0, rel=1e-6)
    spent = part_times(run)
    assert spent[0] == pytest.approx(60.0 / 50.0 + 50.0 / 500.0, abs=2 * DT)
    assert spent[0] == pytest.approx(ruckig_time(60.0, 0.0, 0.0, 50.0, 500.0, 500.0, 1e9), abs=2 * DT)
    arc_peak = peak_in(run, 2)
    assert arc_peak ** 2 / 10.0 <= 200.0 * (1 + 1e-6)
    assert arc_peak == pytest.approx(math.sqrt(2000.0), rel=1e-6)
    assert max(axis_speeds(run, 2, 0)) <= 50.0 * (1 + 1e-6)
    assert peak_in(run, 3) == pytest.approx(50.0, rel=1e-6)     # 2 x F1500


def test_an_override_of_200_percent_stays_under_the_arc_feed_table(mh):
    """(0, 0.5): every arc at 50 % of its feed, a limit the override does not pass;
    the line before it runs at twice its feed."""
    p = params(mh, motion=[None, (1000.0, 5000.0, 5000.0, 1)])
    p = abi.GCODE_PARAMETERS.from_buffer_copy(p)
    p.arcFeedTable[0].m_r, p.arcFeedTable[0].m_relFeed = 0.0, 0.5
    assert mh.compile_text(0, "G1 X60 F3000\nG4 H0.05\nG3 X60 Y20 I0 J10 F6000\n", bytes(p), 0,
                           [0.0] * 10) is None
    run = run_at_override(mh, 2.0)
    assert run["finish"] == "done"
    assert peak_in(run, 0) == pytest.approx(100.0, rel=1e-6)
    assert peak_in(run, 2) == pytest.approx(50.0, rel=1e-6)


def test_an_override_that_scales_time_stops_at_100_percent(mh):
    """interpolatorConfig0 bit 0: the override scales time, speeds and ramps alike;
    above 100 % it would pass every limit the plan keeps: it stays at 1."""
    assert mh.compile_text(0, HARD, hard_params(mh, interpolatorConfig0=1), 0, [0.0] * 10) is None
    run = run_at_override(mh, 2.0)
    assert run["finish"] == "done"
    assert max(s[4] for s in run["steps"]) <= 1.0
    assert max(axis_speeds(run, 0, 0)) <= 50.0 * (1 + 1e-6)


# ------------------------------------------------------------------ the window and the arc feed table

def test_continuous_m_functions_cost_no_window_slot(mh):
    """100 lines G1 X{i} F6000 M1001 run as long as the same lines without M1001
    (the window counts motion parts), each as long as its simulation."""
    plain = "".join(f"G1 X{i} F6000\n" for i in range(1, 101))
    with_m = "".join(f"G1 X{i} F6000 M1001\n" for i in range(1, 101))
    times = []
    for text in (plain, with_m):
        load(mh, text, **AS_WRITTEN)    # the collinear lines as written (tolerance[2] 0)
        expected = mh.simulated_run_time(0)
        run = mh.run(0, 30)
        assert run["finish"] == "done"
        assert run["run_time"] == pytest.approx(expected, rel=0.005)
        times.append(run["run_time"])
    assert times[1] == pytest.approx(times[0], rel=0.005)


@pytest.mark.parametrize("table, expected", [([(0.0, 0.5)], 2 * math.pi * 20 / 25 + 25 / 500),
                                             ([(10.0, 1.25), (0.9, 0.1)], 2 * math.pi * 20 / 62.5 + 62.5 / 500)],
                         ids=["all_arcs_50", "r10_and_up_125"])
def test_the_vendors_arc_feed_table_examples_run(mh, table, expected):
    """The full circle G3 X0 Y0 I20 J0 F3000 (R20): 5.077 s with (0, 0.5), 2.136 s with
    (10, 1.25), (0.9, 0.1) -- the simulation and the machine."""
    p = abi.GCODE_PARAMETERS.from_buffer_copy(params(mh))
    for k, (r, rel) in enumerate(table):
        p.arcFeedTable[k].m_r, p.arcFeedTable[k].m_relFeed = r, rel
    assert mh.compile_text(0, "G3 X0 Y0 I20 J0 F3000\n", bytes(p), 0, [0.0] * 10) is None
    assert mh.simulated_run_time(0) == pytest.approx(expected, rel=1e-6)
    run = mh.run(0, 30)
    assert run["finish"] == "done"
    assert run["run_time"] == pytest.approx(expected, abs=2 * DT)


# ------------------------------------------------------------------ enhancedInterpolatorParameters bits 20, 21

def test_the_knife_axis_stops_the_machine_where_the_plan_does(mh):
    """The tangential knife of test_planner (C turns in place between the XY cuts,
    C in bits 0-9) with bit 20: the machine comes to rest where C starts from rest
    (after the X cut, after the Y cut), runs on where C comes to rest, and takes the
    three trapezoids' time, as the simulation says."""
    from test_planner import C_AXIS, FROM_REST, KNIFE, rest_to_rest
    try:
        mh.set_machine_bits(0, C_AXIS | FROM_REST)
        load(mh, KNIFE, motion=[None, (6000.0, 500.0, 500.0, 1)])
        expected = rest_to_rest(10.0, 100.0, 500.0, 500.0) + 2 * rest_to_rest(100.0, 100.0, 500.0, 500.0)
        assert mh.simulated_run_time(0) == pytest.approx(expected, rel=1e-6)
        run = mh.run(0, 30)
    finally:
        mh.set_machine_bits(0, 0)
    assert run["finish"] == "done"
    assert run["run_time"] == pytest.approx(expected, abs=2 * DT)
    steps = run["steps"]
    at_junction = {}
    for a, b in zip(steps, steps[1:]):
        if a[1] != b[1] and a[1] >= 0:
            at_junction[a[1]] = min(a[3], b[3])
    assert at_junction[0] <= 500.0 * 2 * DT         # rest before C turns
    assert at_junction[2] <= 500.0 * 2 * DT
    assert at_junction[1] == pytest.approx(100.0, rel=1e-3)     # C comes to rest, Y goes on


def test_the_machine_passes_an_inserted_m_function_where_the_plan_put_it(mh):
    """mFuncInsertTable[0] 5 mm before the arc's slow-down (test_planner: X43.9): the
    machine runs the split line at the plan's time, and the rest of the line after
    the M function begins at X43.9, already braking."""
    from test_planner import INTO_ARC
    p = abi.GCODE_PARAMETERS.from_buffer_copy(params(mh, motion=[None, (6000.0, 500.0, 500.0, 1)]))
    p.arcFeedTable[0].m_r, p.arcFeedTable[0].m_relFeed = 0.0, 0.5
    p.MfuncInsertType = 1
    p.mFuncInsertTable[0].mFunc, p.mFuncInsertTable[0].relFeed, p.mFuncInsertTable[0].distance = 1100, 0.6, 5.0
    assert mh.compile_text(0, INTO_ARC, bytes(p), 0, [0.0] * 10) is None
    expected = mh.simulated_run_time(0)
    run = mh.run(0, 30)
    assert run["finish"] == "done"
    assert run["run_time"] == pytest.approx(expected, abs=2 * DT)
    rest = [s for s in run["steps"] if s[1] == 2]           # line 1's rest, after the M function (part 1)
    assert 43.9 <= rest[0][5] <= 43.9 + 100.0 * 2 * DT
    # braking for the arc began at X42.5: at X43.9 the speed is sqrt(50^2 + 2 * 500 * 6.1)
    assert rest[0][3] == pytest.approx(math.sqrt(8600.0), abs=500.0 * 2 * DT)


# ------------------------------------------------------------------ through the exports

def test_the_first_move_after_ResetCNC_through_the_api(api):
    """The reproducer's program through the exports, the machine on its stepped clock:
    the run after ResetCNC(0, 0, NULL) ends (-32) with the run time its simulation
    gives, not crawling back at 1 mm/min."""
    lib = api
    set_params(lib, 0, motion=(abi.GCODE_FEED * 8)(*[abi.GCODE_FEED(6000.0, 1000.0, 1000.0, 1)] * 8),
               startAngle=10.0, endAngle=90.0, minAngleFeed=0.0)     # the reversal stops
    compile_on(lib, 0, RESTART)
    start(lib, 0)
    assert poll_run(lib, 0)[1] == -32
    assert lib.ToolChainCore_ResetCNC(0, 0, 0, None) == 0
    expected = run_time_of(lib, 0)
    assert expected == pytest.approx(2 * (1.0 + 0.1), rel=1e-6)     # 100 mm back, 100 mm on
    start(lib, 0)
    assert poll_run(lib, 0, limit=20.0)[1] == -32
    assert get_pos(lib, 0)[1].m_cncRunTime == pytest.approx(expected, rel=0.005)


@pytest.mark.parametrize("force_mode", [0, 1])
def test_a_connection_moves_at_motion_3(api, force_mode):
    """ConnectCNCEx_Plane's way onto the trajectory runs at motion[3] ("connect to the
    trajectory"), not at GoToPosition's motion[5]: 30 mm at 10 mm/s with 500 mm/s^2,
    3 s + 0.02 s of machine time."""
    lib = api
    classes = (abi.GCODE_FEED * 8)(*[abi.GCODE_FEED(6000.0, 500.0, 500.0, 1)] * 8)
    classes[3] = abi.GCODE_FEED(600.0, 500.0, 500.0, 1)
    set_params(lib, 0, motion=classes, forceMode=force_mode, maxConnectionDistance=1000.0)
    compile_on(lib, 0, "G1 X100 F6000\n")
    start(lib, 0)
    assert poll_run(lib, 0)[1] == -32
    assert lib.ToolChainCore_GoToPosition(0, 2, (ctypes.c_double * 2)(50.0, 30.0)) == 0
    assert poll_run(lib, 0, running=(50,))[1] == -50
    assert lib.ToolChainCore_ConnectCNCEx_Plane(0, 0, 2, (ctypes.c_double * 2)(50.0, 30.0), None, 0, 0, 0) == 0
    assert poll_run(lib, 0, running=(40, 41))[1] == -31
    pos, enh = get_pos(lib, 0)
    assert (pos.m_calcS.x, pos.m_calcS.y) == pytest.approx((50.0, 0.0), abs=1e-9)
    assert enh.m_cncRunTime == pytest.approx(30.0 / 10.0 + 10.0 / 500.0, rel=1e-3)


def test_cam_programs_from_elsewhere_take_GetGCodeRunTime(api):
    """The CAM corpus (tests/cam_corpus.py, one program per style, the ISO mode on)
    compiled at the origin and run from (7, -5, 3), the machine stepped a second at a
    time: each run's machine time is its simulation's from there (GetGCodeRunTime)
    within 0.5 %."""
    import cam_corpus
    lib = api
    set_params(lib, 0, rezerva1=1)
    away = (ctypes.c_double * 10)(7.0, -5.0, 3.0)
    ran = 0
    for style, name, text, _ in cam_corpus.corpus(variants=1):
        assert lib.ToolChainCore_ResetCNC(0, 0, 10, (ctypes.c_double * 10)()) == 0
        assert lib.ToolChainCore_CompileFromMemory(0, b"m.nc", text.encode()) == 0
        assert wait(lib, 0, lambda s: s != 1) == -1
        info = abi.CALLBACK_INFO()
        if lib.ToolChainCore_GetLastError(0, ctypes.byref(info)) != 0:
            continue                            # the styles the ISO mode does not read
        assert lib.ToolChainCore_ResetCNC(0, 0, 10, away) == 0
        expected = run_time_of(lib, 0)
        start(lib, 0)
        while (status := poll_run(lib, 0, dt=1.0)[1]) == -33:
            start(lib, 0)                       # M0 / M1: go on
        assert status == -32, style
        assert get_pos(lib, 0)[1].m_cncRunTime == pytest.approx(expected, rel=0.005), style
        ran += 1
    assert ran >= 10
