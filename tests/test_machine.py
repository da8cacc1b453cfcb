"""The offline machine (StartCNCEx 30-33, toolchain/machine/).

Part one drives the pure step through tests/harness (no threads, one 100 us
step at a time, every step recorded) and checks it against geometry and closed forms:
positions on the compensated path, speeds under the plan and the programmed feed,
the stop distance v^2 / 2d, continue and backward, the run time.

Part two drives the real machine, its threads included, through the exported
functions on its stepped clock (ToolChainCore_TestClock, test-only): a test runs the
machine time it needs and reads GetPos and the driver's calls after exactly that
much, never sleeping to let it move: the statuses, breakpoints, the M-function
handshakes, M0, the override ramp, three cores at once. In real time (the wall clock
at a large time scale): the largest time scale, DestroyCNC / ResetCNC at random
moments."""
import ctypes
import math
import os
import random
import threading
import time

import pytest

from sf_tch import abi, default_ini
from test_planner import AS_WRITTEN

DT = 1e-4                                   # the machine's step, s
EPS = 1e-6                                  # mm: sampled positions on the path
SLOW_SCALE = int(os.environ.get("SF_TCH_SLOW_SCALE", "1"))


@pytest.fixture(scope="session")
def mh(harness):
    yield harness
    harness.destroy_all()


def params(mh, radius=0.0, **fields):
    """Default GCODE_PARAMETERS, calcTime on, tool radius `radius` in every slot;
    motion=[(feed, acc, dec, ramp) or None, ...] from index 0; other fields by name."""
    p = abi.GCODE_PARAMETERS.from_buffer_copy(mh.default_params())
    p.calcTime = 1
    for k in range(8):
        p.correction[k].size = radius
    for k, m in enumerate(fields.pop("motion", ())):
        if m is not None:
            p.motion[k].feed, p.motion[k].acc, p.motion[k].dec, p.motion[k].rampType = m
    for name, value in fields.items():
        setattr(p, name, value)
    return bytes(p)


def load(mh, text, core=0, window=0, **fields):
    """Compiles `text` on the harness's core from the origin; its toolpath records."""
    err = mh.compile_text(core, text, params(mh, **fields), window, [0.0] * 10)
    assert err is None, err
    raw = mh.toolpath(core)
    n = len(raw) // ctypes.sizeof(abi.TC_TOOLPATH_RECORD)
    return list((abi.TC_TOOLPATH_RECORD * n).from_buffer_copy(raw))


# ------------------------------------------------------------------ geometry oracles

def tool_start(records, k):
    """Where the tool centre's path of part k starts (the previous record's tool_end)."""
    return tuple(records[k - 1].tool_end) if k > 0 else tuple(records[0].start)


def point_at(records, k, s):
    """The closed-form point s mm along part k's tool path (lines, and arcs in XY)."""
    r = records[k]
    a, b = tool_start(records, k), tuple(r.tool_end)
    if r.number in (0, 1):
        length = math.dist(a, b)
        f = s / length if length > 0 else 0.0
        return tuple(a[i] + f * (b[i] - a[i]) for i in range(3))
    assert r.number in (2, 3) and r.plane == 17, "the oracle knows XY arcs only"
    cx, cy = r.centre[0], r.centre[1]
    phi = math.atan2(a[1] - cy, a[0] - cx) + (s / r.radius) * (1 if r.number == 3 else -1)
    z = a[2] + (b[2] - a[2]) * s / r.length if r.length > 0 else a[2]
    return (cx + r.radius * math.cos(phi), cy + r.radius * math.sin(phi), z)


def distance_to_part(records, k, p):
    """Distance of point p from part k's tool path (brute force: 20,000 samples + the
    exact foot of the perpendicular on a line)."""
    r = records[k]
    a, b = tool_start(records, k), tuple(r.tool_end)
    if r.number in (0, 1):
        ab = [b[i] - a[i] for i in range(3)]
        ll = sum(c * c for c in ab)
        f = 0.0 if ll == 0 else max(0.0, min(1.0, sum((p[i] - a[i]) * ab[i] for i in range(3)) / ll))
        return math.dist(p, [a[i] + f * ab[i] for i in range(3)])
    # arcs: the exact radial distance when the point is inside the swept angle
    cx, cy = r.centre[0], r.centre[1]
    sweep = r.length / r.radius
    phi0 = math.atan2(a[1] - cy, a[0] - cx)
    phi = math.atan2(p[1] - cy, p[0] - cx)
    turn = ((phi - phi0) * (1 if r.number == 3 else -1)) % (2 * math.pi)
    if turn <= sweep + 1e-12 or turn >= 2 * math.pi - 1e-12:
        return math.hypot(math.hypot(p[0] - cx, p[1] - cy) - r.radius, p[2] - a[2])
    return min(math.dist(p, a), math.dist(p, b))


def distance_to_square(p, half):
    """Distance of p (x, y) from the boundary of the square |x|, |y| <= half, outside it."""
    dx, dy = max(abs(p[0]) - half, 0.0), max(abs(p[1]) - half, 0.0)
    return math.hypot(dx, dy)


# programs: F3000 = 50 mm/s, F6000 = 100 mm/s
LINES = "G1 X100 Y0 F6000\nG1 X100 Y50\nG1 X0 Y50\n"
ARCS = ("G1 X50 Y0 F3000\nG3 X50 Y40 I0 J20\nM5\nG2 X50 Y80 I0 J20\nG4 H0.2\n"
        "G1 X0 Y80\nG1 X0 Y0 Z-5\n")
SQUARE_G42 = ("G0 X0 Y-20\nG42 G1 X0 Y-10 F3000\nG1 X10 Y-10\nG1 X10 Y10\nG1 X-10 Y10\n"
              "G1 X-10 Y-10\nG1 X0 Y-10\nG40 G1 X0 Y-20\n")


def circle_chords(n=400, r=20.0, feed=6000):
    """A circle of radius r in n chords (a dense path: the look-ahead window limits it)."""
    pts = [(r * math.cos(2 * math.pi * i / n), r * math.sin(2 * math.pi * i / n)) for i in range(n + 1)]
    return f"G0 X{pts[0][0]:.6f} Y{pts[0][1]:.6f}\n" + "".join(
        f"G1 X{x:.6f} Y{y:.6f} F{feed}\n" for x, y in pts[1:])


def motion_steps(run, records):
    """The steps inside a motion part: (t, part, d, v, xyz)."""
    return [(s[0], s[1], s[2], s[3], s[5:8]) for s in run["steps"]
            if s[1] >= 0 and records[s[1]].kind == abi.TC_TOOLPATH_MOTION]


# ------------------------------------------------------------------ the step

@pytest.mark.parametrize("text, radius", [(LINES, 0.0), (ARCS, 0.0), (SQUARE_G42, 2.0)],
                         ids=["lines", "arcs", "square_g42"])
def test_sampled_positions_lie_on_the_compensated_path(mh, text, radius):
    records = load(mh, text, radius=radius)
    run = mh.run(0, 30)
    assert run["finish"] == "done"
    samples = motion_steps(run, records)
    assert len(samples) > 1000
    for t, k, d, v, xyz in samples:
        assert math.dist(xyz, point_at(records, k, d)) <= EPS, (t, k, d, xyz)
        assert distance_to_part(records, k, xyz) <= EPS, (t, k, xyz)
    if radius:
        # G42 around the CCW square of half side 10: the tool centre keeps the radius
        # from the square on every part between the lead-in and the lead-out
        inner = [k for k, r in enumerate(records) if r.compensation == 42][1:-1]
        assert len(inner) >= 7                      # four sides (one split) and corner arcs
        on_contour = [xyz for t, k, d, v, xyz in samples if k in inner]
        assert len(on_contour) > 500
        for xyz in on_contour:
            assert abs(distance_to_square(xyz, 10.0) - radius) <= EPS, xyz
    # the run ends where the program does
    assert math.dist(run["steps"][-1][5:8], tuple(records[-1].tool_end)) <= EPS


def test_the_arcs_records_are_the_programmed_circles(mh):
    """The oracle's own input against the program: the two arcs' centres and radii."""
    records = load(mh, ARCS)
    arcs = [r for r in records if r.kind == abi.TC_TOOLPATH_MOTION and r.number in (2, 3)]
    assert [(tuple(r.centre[:2]), r.radius) for r in arcs] == [((50.0, 20.0), 20.0), ((50.0, 60.0), 20.0)]
    assert [r.length for r in arcs] == pytest.approx([20 * math.pi] * 2)


@pytest.mark.parametrize("text, radius", [(LINES, 0.0), (ARCS, 0.0), (SQUARE_G42, 2.0),
                                          (circle_chords(), 0.0)],
                         ids=["lines", "arcs", "square_g42", "chords"])
def test_speed_never_above_the_plan_nor_the_feed(mh, text, radius):
    records = load(mh, text, radius=radius)
    plan = mh.plan(0)
    run = mh.run(0, 30)
    steps = run["steps"]
    acc = 500.0                                  # motion[1..].acc / dec defaults, trapezoid
    prev_len, prev_v, prev_k = 0.0, 0.0, 0
    for t, k, d, v, ovr, x, y, z, state, length in steps:
        if k >= 0 and records[k].kind == abi.TC_TOOLPATH_MOTION:
            feed = records[k].feed / 60.0
            assert v <= plan[k][0] + 1e-9, (t, k, v, plan[k])
            assert v <= feed + 1e-9, (t, k, v)
            # the distance covered in the step: never faster than the feed (of the
            # faster part where the step crossed from one part into the next)
            if k != prev_k and records[prev_k].kind == abi.TC_TOOLPATH_MOTION:
                feed = max(feed, records[prev_k].feed / 60.0)
            assert (length - prev_len) / DT <= feed * (1 + 1e-9) + 1e-9, (t, k)
            prev_k = k
        # the speed changes at most by the acceleration over a step
        assert abs(v - prev_v) <= acc * DT * (1 + 1e-9) + 1e-9, (t, v, prev_v)
        prev_len, prev_v = length, v


def test_a_feeder_that_lags_never_makes_the_machine_jump_or_brake_hard(mh):
    """The ring (64 entries, ~0.5 s of chords) refilled only every second. The pacer
    holds time while the window is not in the ring; the step itself, driven on, runs
    the ring empty safely: it brakes to rest at its end within the deceleration,
    waits, goes on; on the path throughout, and it takes longer than with a feeder
    that keeps up."""
    records = load(mh, circle_chords())
    keeping_up = mh.run(0, 30)
    mh.forget(0)
    load(mh, circle_chords())
    run = mh.run(0, 30, feed_every=10000)
    assert run["finish"] == "done"
    states = [s[8] for s in run["steps"]]
    assert states.count("starved") > 100
    prev_v = 0.0
    for t, k, d, v, ovr, x, y, z, state, length in run["steps"]:
        assert abs(v - prev_v) <= 500.0 * DT * (1 + 1e-9) + 1e-9, (t, v, prev_v)
        if state == "starved":
            assert v <= 1e-6, (t, v)           # at rest at the ring's end
        prev_v = v
    for t, k, d, v, xyz in motion_steps(run, records):
        assert distance_to_part(records, k, xyz) <= EPS
    assert run["steps"][-1][9] == pytest.approx(keeping_up["steps"][-1][9], abs=1e-6)
    assert run["run_time"] > keeping_up["run_time"] + 0.1


def test_a_single_line_takes_its_closed_form_time(mh):
    """100 mm at 100 mm/s with 500 mm/s^2 up and down: 1 s + 2 x 0.1 s / 2 x 2 = 1.2 s."""
    load(mh, "G1 X100 F6000\n")
    run = mh.run(0, 30)
    assert run["finish"] == "done"
    assert run["steps"][-1][0] == pytest.approx(1.2, abs=DT)
    peak = max(s[3] for s in run["steps"])
    assert peak == pytest.approx(100.0)


@pytest.mark.parametrize("text, radius, window", [(LINES, 0.0, 0), (ARCS, 0.0, 0), (SQUARE_G42, 2.0, 0),
                                                  (circle_chords(), 0.0, 0), (circle_chords(), 0.0, 32)],
                         ids=["lines", "arcs", "square_g42", "chords", "chords_window32"])
def test_the_run_takes_GetGCodeRunTime(mh, text, radius, window):
    load(mh, text, radius=radius, window=window)
    expected = mh.simulated_run_time(0)
    assert expected > 0
    run = mh.run(0, 30)
    assert run["finish"] == "done"
    assert run["steps"][-1][0] == pytest.approx(expected, rel=0.005)
    assert run["run_time"] == pytest.approx(expected, rel=0.005)


def travelled_since(steps, t0):
    """Path length covered after machine time t0 (the cumulative length's increase)."""
    before = [s[9] for s in steps if s[0] <= t0 + 1e-12]
    return steps[-1][9] - (before[-1] if before else 0.0)


def speed_at(steps, t0):
    return [s[3] for s in steps if s[0] <= t0 + 1e-12][-1]


@pytest.mark.parametrize("text, stop_at, dec, ramp", [
    ("G1 X500 F6000\n", 2.0, 1000.0, 1),                    # cruising at 100 mm/s: 5 mm
    ("G1 X500 F6000\n", 0.1, 1000.0, 1),                    # accelerating, at 50 mm/s: 1.25 mm
    ("G1 X500 F6000\n", 2.0, 250.0, 1),                     # 20 mm
    ("G1 X500 F6000\n", 2.0, 1000.0, 2),                    # sine: pi v^2 / 4d = 7.85 mm
    ("G1 X250 F6000\nG1 X500\n", 2.48, 1000.0, 1),          # across the junction of two parts
    ("G1 X100 F6000\nG1 X100 Y100\n", 0.9, 1000.0, 1),      # before a corner: it slows anyway
], ids=["cruise", "accelerating", "soft", "sine", "across_parts", "before_corner"])
def test_a_stop_ends_after_v2_over_2d(mh, text, stop_at, dec, ramp):
    """A trapezoid ramp brakes at d: v^2 / 2d. A sine ramp whose deceleration peaks at
    d, v(t) = v (1 + cos(pi t / T)) / 2, has T = pi v / 2d and covers v T / 2."""
    records = load(mh, text, motion=[None] * 6 + [(1000.0, 500.0, dec, ramp)])
    run = mh.run(0, 30, stop_at=stop_at)
    steps = run["steps"]
    assert run["finish"] == "stopped" and run["state"] == "stopped"
    v = speed_at(steps, run["stop_time"])
    assert v > 10.0
    # the path the machine would take with no stop: the stop can only be shorter
    # where the path itself slows down (a corner), never longer
    expected = v * v / (2 * dec) if ramp == 1 else math.pi * v * v / (4 * dec)
    covered = travelled_since(steps, run["stop_time"])
    if "Y100" in text:
        assert covered <= expected + v * DT
    else:
        assert covered == pytest.approx(expected, abs=v * DT)
    # braking: the speed never rises after the stop and falls by at most dec per step
    after = [s[3] for s in steps if s[0] > run["stop_time"]]
    assert all(b <= a + 1e-9 for a, b in zip(after, after[1:]))
    assert all(a - b <= dec * DT * (1 + 1e-9) + 1e-9 for a, b in zip(after, after[1:]))
    assert after[-1] == 0.0
    # it stands on the path
    k = steps[-1][1]
    assert distance_to_part(records, k, steps[-1][5:8]) <= EPS


def uninterrupted(mh, text, **fields):
    load(mh, text, **fields)
    run = mh.run(0, 30)
    assert run["finish"] == "done"
    return run


@pytest.mark.parametrize("stop_times", [(0.3,), (0.05, 1.0, 2.5), (1.55,), (3.9,)],
                         ids=["one", "three", "at_the_m", "in_the_dwell"])
def test_continue_after_a_stop_reaches_the_same_end(mh, stop_times):
    whole = uninterrupted(mh, ARCS)
    mh.forget(0)
    entries, last, total_time = [], None, 0.0
    for stop_at in stop_times:
        run = mh.run(0, 30, stop_at=stop_at)
        assert run["finish"] in ("stopped", "done")
        entries += [p for p in run["entries"] if not entries or p != entries[-1] or p != run["entries"][0]]
        last = run
        if run["finish"] == "done":
            break
    while last["finish"] != "done":
        last = mh.run(0, 30)
        entries += [p for p in last["entries"] if not entries or p != entries[-1] or p != last["entries"][0]]
    # the same end, the same path length, every part once in the program's order
    assert math.dist(last["steps"][-1][5:8], whole["steps"][-1][5:8]) <= EPS
    assert last["steps"][-1][9] == pytest.approx(whole["steps"][-1][9], abs=1e-9)
    assert sorted(set(entries)) == sorted(set(whole["entries"]))
    assert entries == sorted(entries)


@pytest.mark.parametrize("stop_at", [0.5, 1.7, 3.0, 4.3, 60.0],
                         ids=["first_line", "first_arc", "second_arc", "last", "from_the_end"])
def test_backward_retraces_the_executed_path_to_the_start(mh, stop_at):
    records = load(mh, ARCS, motion=[None, None, (1500.0, 400.0, 400.0, 1)])
    forward = mh.run(0, 30, stop_at=stop_at)
    assert forward["finish"] == ("done" if stop_at > 30 else "stopped")
    f_motion = [p for p in dict.fromkeys(forward["entries"]) if records[p].kind == abi.TC_TOOLPATH_MOTION]
    back = mh.run(0, 32)
    assert back["finish"] == "done"                        # -30: back at the program's start
    samples = motion_steps(back, records)
    for t, k, d, v, xyz in samples:
        assert distance_to_part(records, k, xyz) <= EPS, (t, k, xyz)
        assert v <= 1500.0 / 60.0 + 1e-9
    # the parts in the reverse order of the forward run, the same length, the start
    b_parts = list(dict.fromkeys(s[1] for s in samples))
    assert b_parts == f_motion[::-1]
    forward_len = forward["steps"][-1][9]
    assert back["steps"][-1][9] - forward_len == pytest.approx(forward_len, abs=1e-6)
    assert math.dist(back["steps"][-1][5:8], tuple(records[0].start)) <= EPS
    # forward again from the start: the whole program
    again = mh.run(0, 30)
    assert again["finish"] == "done"
    assert math.dist(again["steps"][-1][5:8], tuple(records[-1].tool_end)) <= EPS


def test_backward_then_forward_is_one_continuous_path(mh):
    """Forward, stopped, back for a while, stopped again, forward to the end: the
    machine never jumps (no step longer than the fastest feed allows) and stays on
    the path."""
    records = load(mh, ARCS)
    runs = [mh.run(0, 30, stop_at=2.2), mh.run(0, 32, stop_at=0.8), mh.run(0, 30)]
    assert [r["finish"] for r in runs] == ["stopped", "stopped", "done"]
    path = [s[5:8] for r in runs for s in r["steps"]]
    fastest = max(r.feed for r in records if r.kind == abi.TC_TOOLPATH_MOTION) / 60.0
    jumps = [(i, math.dist(a, b)) for i, (a, b) in enumerate(zip(path, path[1:]))
             if math.dist(a, b) > fastest * DT + EPS]
    assert not jumps, jumps[:3]
    for r in runs:
        for t, k, d, v, xyz in motion_steps(r, records):
            assert distance_to_part(records, k, xyz) <= EPS


@pytest.mark.parametrize("text, radius", [(ARCS, 0.0), (SQUARE_G42, 2.0), (circle_chords(), 0.0)],
                         ids=["arcs", "square_g42", "chords"])
def test_the_place_keeps_its_invariants(mh, text, radius):
    """After every run the machine's place on the program (machine.pxd Place) holds
    what the face says of it: forward runs stopped anywhere (in a move, at the waiting
    M5, in the dwell), backward ones stopped and run to the start, one that breaks off
    where the remembered path ends, one that runs to the end."""
    load(mh, text, radius=radius)
    sequences = [[(30, 1.55), (30, 0.01), (32, 0.3)],
                 [(30, 3.9), (32, 0.5), (32, -1.0)],
                 [(30, 0.05), (30, 0.7), (32, 0.3), (30, 2.2), (33, 0.4), (31, 0.6), (32, 0.8), (30, -1.0),
                  (32, 0.2), (32, -1.0)]]
    for runs in sequences:
        mh.forget(0)
        assert mh.place(0) == (0, 0.0, False, []) and mh.place_violations(0) == []
        for regime, stop_at in runs:
            mh.run(0, regime, stop_at=stop_at)
            assert mh.place_violations(0) == [], (regime, stop_at, mh.place(0)[:3])


@pytest.mark.parametrize("timing", [0, 1], ids=["feed_cap", "time_scale"])
def test_the_override_moves_by_overrideInc_per_step(mh, timing):
    load(mh, "G1 X300 F6000\n", interpolatorConfig0=timing)
    run = mh.run(0, 30, overrides=[(1.0, 0.5)])
    ovr = [s[4] for s in run["steps"]]
    assert ovr[int(1.0 / DT) - 2] == 1.0
    moving = [(a, b) for a, b in zip(ovr, ovr[1:]) if a != b]
    assert len(moving) == pytest.approx(500, abs=1)         # 0.5 in steps of 0.001
    assert all(a - b == pytest.approx(0.001, abs=1e-12) for a, b in moving[:-1])
    assert ovr[-1] == 0.5
    # cruising afterwards at half the feed: the distance covered per step says so
    steps = run["steps"]
    k = int(1.3 / DT)
    assert (steps[k + 100][9] - steps[k][9]) / (100 * DT) == pytest.approx(50.0, rel=1e-6)


def run_at_override(mh, rel_feed, core=0):
    """A forward run (30) of the harness's machine at feed override `rel_feed`, the
    override set back to 1.0 afterwards."""
    mh.set_rel_feed(core, rel_feed)
    try:
        return mh.run(core, 30)
    finally:
        mh.set_rel_feed(core, 1.0)


@pytest.mark.parametrize("timing, expected", [(0, 100 / 50 + 50 / 500), (1, 2 * (100 / 100 + 100 / 500))],
                         ids=["feed_cap", "time_scale"])
def test_a_constant_override_by_interpolatorConfig0(mh, timing, expected):
    """100 mm at F6000, 500 mm/s^2, override 0.5 throughout. Bit 0 clear: the feed is
    capped at 50 mm/s, the ramps keep 500 mm/s^2: L / v + v / a. Bit 0 set: the whole
    profile runs at half speed in time, ramps included: twice 1.2 s."""
    load(mh, "G1 X100 F6000\n", interpolatorConfig0=timing)
    run = run_at_override(mh, 0.5)
    assert run["finish"] == "done"
    assert run["run_time"] == pytest.approx(expected, abs=2 * DT)
    steps = run["steps"]
    top = max((b[9] - a[9]) / DT for a, b in zip(steps, steps[1:]))
    assert top == pytest.approx(50.0, rel=1e-6)


@pytest.mark.parametrize("off_in_rapids", [0, 1])
def test_disableG0FeedOverride_keeps_rapids_at_full_speed(mh, off_in_rapids):
    """Override 0.5 from the start: the rapid (motion[0].feed 6000 mm/min here) at half
    or full speed; in the cut the override returns to 0.5 by overrideInc per step and
    the speed stays under the feed times the override of the moment."""
    load(mh, "G0 X200\nG1 X400 F3000\n", disableG0FeedOverride=off_in_rapids,
         motion=[(6000.0, 500.0, 500.0, 1)])
    run = mh.run(0, 30, overrides=[(0.0, 0.5)])
    assert run["finish"] == "done"
    rapid = [s for s in run["steps"] if s[1] == 0]
    cut = [s for s in run["steps"] if s[1] == 1]
    assert max(s[3] for s in rapid) == pytest.approx(100.0 if off_in_rapids else 50.0, rel=1e-6)
    assert {s[4] for s in rapid[1000:]} == {1.0 if off_in_rapids else 0.5}
    assert all(v <= 50.0 * ovr + 1e-6 for t, k, d, v, ovr, *rest in cut)
    assert max(s[3] for s in cut[1000:]) == pytest.approx(25.0, rel=1e-6)


def test_a_breakpoint_stops_before_its_line_and_the_next_start_passes(mh):
    records = load(mh, LINES)
    mh.set_breakpoint(0, 3)
    try:
        run = mh.run(0, 30)
        assert run["finish"] == "stopped"
        # it stands at the end of line 2 (the start of line 3), having braked within dec
        assert math.dist(run["steps"][-1][5:8], (100.0, 50.0, 0.0)) <= EPS
        speeds = [s[3] for s in run["steps"]]
        assert all(abs(a - b) <= 500.0 * DT * (1 + 1e-9) for a, b in zip(speeds, speeds[1:]))
        rest = mh.run(0, 30)
        assert rest["finish"] == "done"
        assert math.dist(rest["steps"][-1][5:8], tuple(records[-1].tool_end)) <= EPS
    finally:
        mh.set_breakpoint(0, 0)


# ------------------------------------------------------------------ through the API

INI = default_ini().encode()         # the bundled INI, wherever SF_TCH_LIBRARY points
FWD, FWD_NO_M, BACK, FWD_SKIP_M = 30, 31, 32, 33
MFUNC_LATER = abi.TC_MFUNC_LATER           # DriverMFunc's "the host confirms later"
KEY = abi.TC_TEST_CLOCK_KEY                 # ToolChainCore_TestClock's key


@pytest.fixture
def api(fresh_core):
    """Every core fresh, its INI loaded (driver callbacks allowed), known motion
    classes: F as programmed, 500 mm/s^2 trapezoid ramps, stop dec 1000 mm/s^2;
    afterwards the machine back at the origin (runs move it, and it outlives
    DestroyCNC: later tests compile from it)."""
    lib = fresh_core
    for core in range(abi.TOOL_CHAIN_MAX_CORES):
        assert lib.ToolChainCore_LoadFromIni(core, INI, None) == 0
        set_params(lib, core)
        assert lib.ToolChainCore_TestClock(core, KEY, 0.0) == 0       # the stepped clock
    yield lib
    for core in range(abi.TOOL_CHAIN_MAX_CORES):
        assert lib.ToolChainCore_ResetCNC(core, 0, 10, (ctypes.c_double * 10)()) == 0
        assert lib.ToolChainCore_DestroyCNC(core) == 0
        assert lib.ToolChainCore_TestClock(core, KEY, -1.0) == 0      # the wall clock again


def set_params(lib, core, **fields):
    p = abi.GCODE_PARAMETERS()
    assert lib.ToolChainCore_GetGCodeParameters(core, ctypes.byref(p)) == 0
    p.calcTime = 1
    for k in range(1, 6):
        p.motion[k].acc = p.motion[k].dec = 500.0
        p.motion[k].rampType = 1
    p.motion[0].feed, p.motion[0].acc, p.motion[0].dec = 10000.0, 500.0, 500.0
    p.motion[6].dec, p.motion[6].rampType = 1000.0, 1
    for name, value in fields.items():
        setattr(p, name, value)
    assert lib.ToolChainCore_SetGCodeParameters(core, ctypes.byref(p)) == 0


def wait(lib, core, accept, timeout=20.0):
    """Polls a compilation or a simulation (no clock of the machine) until accept(status)."""
    deadline = time.monotonic() + timeout
    while not accept(lib.ToolChainCore_StatusCNC(core)):
        assert time.monotonic() < deadline, f"core {core}: status stuck at {lib.ToolChainCore_StatusCNC(core)}"
        time.sleep(0.0005)
    return lib.ToolChainCore_StatusCNC(core)


def step(lib, core, seconds):
    """Runs `seconds` of the core's machine time on the stepped clock; returns once they
    ran, GetPos shows them and the driver callbacks they caused returned."""
    assert lib.ToolChainCore_TestClock(core, KEY, seconds) == 0


def compile_on(lib, core, text, origin=True):
    """Compiles text from the origin (ResetCNC 0); -1 and no error, else the test fails."""
    if origin:
        assert lib.ToolChainCore_ResetCNC(core, 0, 10, (ctypes.c_double * 10)()) == 0
    assert lib.ToolChainCore_CompileFromMemory(core, b"m.nc", text.encode()) == 0
    assert wait(lib, core, lambda s: s != 1) == -1
    info = abi.CALLBACK_INFO()
    assert lib.ToolChainCore_GetLastError(core, ctypes.byref(info)) == 0, info.m_fullError


def records_of(lib, core):
    total = ctypes.c_uint64()
    assert lib.ToolChainCore_GetToolpath(core, None, 0, 0, ctypes.byref(total)) == 0
    out = (abi.TC_TOOLPATH_RECORD * total.value)()
    assert lib.ToolChainCore_GetToolpath(core, out, total.value, 0, ctypes.byref(total)) == 0
    return list(out)


def run_time_of(lib, core):
    """GetGCodeRunTime after a simulation (10) of the compiled program; -10 after it."""
    assert lib.ToolChainCore_StartCNCEx(core, 10, None) == 0
    assert wait(lib, core, lambda s: s != 10) == -10
    seconds = lib.ToolChainCore_GetGCodeRunTime(core, lib.ToolChainCore_FileToIdx(core, b"m.nc"))
    assert seconds > 0
    return seconds


def get_pos(lib, core):
    pos, enh = abi.SIMPLE_GM_PARAMS(), abi.GM_PARAMS_ENHANCED()
    assert lib.ToolChainCore_GetPos(core, 0, ctypes.byref(pos), ctypes.byref(enh)) == 0
    return pos, enh


def xyz(pos):
    return (pos.m_calcS.x, pos.m_calcS.y, pos.m_calcS.z)


def start(lib, core, regime=FWD, add_code=None):
    rc = lib.ToolChainCore_StartCNCEx(core, regime, add_code)
    assert rc == 0, f"StartCNCEx({regime}) -> {rc} in status {lib.ToolChainCore_StatusCNC(core)}"


def poll_run(lib, core, running=(30, 31, 32, 33, 70, 80), dt=0.01, limit=600.0):
    """Steps the machine `dt` at a time while the core runs (at most `limit` seconds of
    machine time); GetPos (pos, enh) after every step, and the final status. A run
    sending its start's or stop's M functions (70, 80: the worker, not the stepped
    clock, does it) still runs."""
    samples, t = [], 0.0
    while lib.ToolChainCore_StatusCNC(core) in running:
        assert t < limit, f"the run does not end in {limit} s of machine time"
        step(lib, core, dt)
        t += dt
        samples.append(get_pos(lib, core))
    return samples, lib.ToolChainCore_StatusCNC(core)


class Driver:
    """Driver callbacks recording (what, data, native thread id); `m_answer(m)` gives
    DriverMFunc's answer. Keeps the ctypes thunks alive."""

    def __init__(self, lib, core, m_answer=lambda m: 0):
        self.lib, self.core, self.m_answer = lib, core, m_answer
        self.calls = []
        self.fns = {
            abi.CB_DRIVER_INITIALIZE: abi.DriverInitialize(
                lambda user, params, n, mode: self._record("init", mode)),
            abi.CB_DRIVER_G_FUNC: abi.DriverGFunc(
                lambda user, part: self._record("G", (part.contents.m_editorLine, part.contents.m_func))),
            abi.CB_DRIVER_M_FUNC: abi.DriverMFunc(self._m),
            abi.CB_DRIVER_END: abi.DriverEnd(lambda user: self._record("end", None)),
        }
        for number, fn in self.fns.items():
            assert lib.ToolChainCore_SetCallBack(core, number, 0, ctypes.cast(fn, ctypes.c_void_p)) == 0

    def _record(self, what, data):
        self.calls.append((what, data, threading.get_native_id()))
        return 0

    def _m(self, user, part):
        m = part.contents.m_func
        self._record("M", m)
        return self.m_answer(m)

    def what(self, kind=None):
        return [(w, d) for w, d, _ in self.calls if kind is None or w == kind]


def on_path(records, p):
    """Distance of p from the nearest motion part's tool path."""
    return min(distance_to_part(records, k, p) for k, r in enumerate(records)
               if r.kind == abi.TC_TOOLPATH_MOTION)


def test_a_forward_run_shows_itself_in_GetPos_and_ends_at_minus_32(api):
    lib = api
    compile_on(lib, 0, ARCS)
    records = records_of(lib, 0)
    driver = Driver(lib, 0)
    start(lib, 0)
    samples, status = poll_run(lib, 0)
    assert status == -32
    assert len(samples) > 50
    calls, threads = driver.what(), {t for _, _, t in driver.calls}
    lines, times = [], []
    for pos, enh in samples:
        p = xyz(pos)
        assert on_path(records, p) <= EPS, p
        assert (pos.m_pars.X, pos.m_pars.Y, pos.m_pars.Z) == pytest.approx(p, abs=1e-3)   # floats
        assert 0.0 <= enh.m_actFeed <= 3000.0 * (1 + 1e-9)
        assert 0.0 <= enh.m_actPartRemain <= enh.m_actPartLen + 1e-9
        if pos.m_editorLine:
            lines.append(pos.m_editorLine)
        times.append(enh.m_cncRunTime)
    assert lines == sorted(lines) and set(lines) >= {1, 2, 4, 6, 7}
    assert times == sorted(times)
    # at the end: the program's end, its lengths and its run time
    pos, enh = get_pos(lib, 0)
    assert math.dist(xyz(pos), tuple(records[-1].tool_end)) <= EPS
    assert enh.m_cncRunTime == pytest.approx(run_time_of(lib, 0), rel=0.005)
    cut = sum(r.length for r in records if r.kind == abi.TC_TOOLPATH_MOTION and r.number != 0)
    assert enh.m_actWorkPartsLen == pytest.approx(cut, abs=1e-6)
    assert enh.m_actG00PartsLen == pytest.approx(0.0, abs=1e-9)
    # the driver: initialised for regime 30, every motion part and the M in order, the end;
    # all from one thread that is not the host's
    assert calls[0] == ("init", 30) and calls[-1] == ("end", None)
    assert [d for w, d in calls if w in ("G", "M")] == [(1, 1), (2, 3), 5, (4, 2), (5, 4), (6, 1), (7, 1)]
    assert len(threads) == 1 and threading.get_native_id() not in threads


def test_stop_then_continue_reaches_the_same_end(api):
    lib = api
    compile_on(lib, 0, LINES)
    records = records_of(lib, 0)
    stops = []
    for _ in range(3):
        start(lib, 0)
        step(lib, 0, 0.25)
        assert lib.ToolChainCore_StopCNCEx(0, None) == 0
        assert poll_run(lib, 0)[1] == -31
        pos, enh = get_pos(lib, 0)
        assert on_path(records, xyz(pos)) <= EPS
        assert enh.m_actFeed == 0.0
        stops.append(xyz(pos))
    assert len(set(stops)) == 3 and sorted(stops) == stops[:1] + sorted(stops[1:])     # it moved on
    while lib.ToolChainCore_StatusCNC(0) != -32:
        start(lib, 0)
        poll_run(lib, 0)
    pos, enh = get_pos(lib, 0)
    assert math.dist(xyz(pos), (0.0, 50.0, 0.0)) <= EPS
    assert enh.m_actWorkPartsLen == pytest.approx(250.0, abs=1e-6)
    # at the end: forward is refused, StopCNCEx too (nothing moves)
    assert lib.ToolChainCore_StartCNCEx(0, FWD, None) == -1
    assert lib.ToolChainCore_StopCNCEx(0, None) == -1


def test_stop_distance_through_the_api(api):
    """StopCNCEx at cruise: the machine stands v^2 / 2 dec further on (v = 100 mm/s,
    dec = 1000 mm/s^2: 5 mm), 0.1 s later: after 0.5 s at 500 mm/s^2 it is at
    10 mm + 0.3 s x 100 mm/s = 40 mm, and stands at 45 mm."""
    lib = api
    compile_on(lib, 0, "G1 X1000 F6000\n")
    start(lib, 0)
    step(lib, 0, 0.5)
    before, enh = get_pos(lib, 0)
    assert enh.m_actFeed == pytest.approx(6000.0)
    assert before.m_calcS.x == pytest.approx(40.0, abs=1e-9)
    assert lib.ToolChainCore_StopCNCEx(0, None) == 0
    samples, status = poll_run(lib, 0, dt=0.001)
    assert status == -31
    stood, enh = get_pos(lib, 0)
    assert stood.m_calcS.x == pytest.approx(45.0, abs=1e-9)
    assert enh.m_cncRunTime == pytest.approx(0.6, abs=2e-4)


def test_stop_add_code_goes_to_the_driver_once_it_stands(api):
    lib = api
    compile_on(lib, 0, "G1 X1000 F6000\n")
    seen = []
    driver = Driver(lib, 0, m_answer=lambda m: seen.append((m, xyz(get_pos(lib, 0)[0]))) or 0)
    start(lib, 0)
    step(lib, 0, 0.2)
    assert lib.ToolChainCore_StopCNCEx(0, b"M8 M9") == 0
    assert poll_run(lib, 0)[1] == -31
    stood = xyz(get_pos(lib, 0)[0])
    assert [m for m, _ in seen] == [8, 9]
    assert all(p == stood for _, p in seen)
    assert driver.what()[-1] == ("end", None)


def test_start_add_code_goes_first_and_regime_33_skips_the_leading_m(api):
    lib = api
    text = "M7\nM1010\nG1 X10 F6000\nM8\nG1 X20\n"
    compile_on(lib, 0, text)
    driver = Driver(lib, 0)
    start(lib, 0, FWD, b"M9")
    assert poll_run(lib, 0)[1] == -32
    assert driver.what("M") == [("M", 9), ("M", 7), ("M", 1010), ("M", 8)]
    compile_on(lib, 0, text)
    driver = Driver(lib, 0)
    start(lib, 0, FWD_SKIP_M, b"M9")
    assert poll_run(lib, 0)[1] == -32
    assert driver.what("M") == [("M", 9), ("M", 8)]
    assert driver.what()[0] == ("init", 33)


def test_regime_33_skips_the_m_it_stands_before(api):
    """Stopped by a breakpoint before line 2 (a waiting M7), StartCNCEx 33 goes on
    without it; 30 from the same place sends it."""
    lib = api
    text = "G1 X10 F6000\nM7\nG1 X20\nM8\nG1 X30\n"
    for regime, expected in ((FWD_SKIP_M, [8]), (FWD, [7, 8])):
        compile_on(lib, 0, text)
        main = lib.ToolChainCore_FileToIdx(0, b"m.nc")
        assert lib.ToolChainCore_SetBreakpoint(0, 2, main) == 0
        start(lib, 0)
        assert poll_run(lib, 0)[1] == -31
        assert math.dist(xyz(get_pos(lib, 0)[0]), (10.0, 0.0, 0.0)) <= EPS
        driver = Driver(lib, 0)
        start(lib, 0, regime)
        assert poll_run(lib, 0)[1] == -32
        assert [d for w, d in driver.what("M")] == expected


def test_regime_31_sends_no_m_and_runs_at_the_feed_of_motion_4(api):
    """20 mm at motion[4]'s 1200 mm/min (20 mm/s), 500 mm/s^2: 1 s + 0.04 s."""
    lib = api
    p = abi.GCODE_PARAMETERS()
    lib.ToolChainCore_GetGCodeParameters(0, ctypes.byref(p))
    p.motion[4].feed = 1200.0
    assert lib.ToolChainCore_SetGCodeParameters(0, ctypes.byref(p)) == 0
    compile_on(lib, 0, "G1 X10 F6000\nG1 X20\n")
    start(lib, 0, FWD_NO_M)
    samples, status = poll_run(lib, 0)
    assert status == -32
    assert all(enh.m_actFeed <= 1200.0 * (1 + 1e-9) for _, enh in samples)
    assert get_pos(lib, 0)[1].m_cncRunTime == pytest.approx(1.04, rel=0.005)
    # neither the program's M functions nor addCode reach the driver
    compile_on(lib, 0, "G1 X10 F6000\nM8\nG1 X20\n")
    driver = Driver(lib, 0)
    start(lib, 0, FWD_NO_M, b"M9")
    assert poll_run(lib, 0)[1] == -32
    assert driver.what("M") == []
    assert driver.what()[0] == ("init", 31)


def test_a_continuous_m_is_signalled_without_stopping(api):
    """G1 X10 / G1 X20 M1005 at 100 mm/s: one move of 20 mm, 0.2 s + 0.2 s ramps."""
    lib = api
    compile_on(lib, 0, "G1 X10 F6000\nG1 X20 M1005\n")
    driver = Driver(lib, 0)
    start(lib, 0)
    assert poll_run(lib, 0)[1] == -32
    assert driver.what("M") == [("M", 1005)]
    assert get_pos(lib, 0)[1].m_cncRunTime == pytest.approx(0.4, rel=0.005)


def test_a_waiting_m_confirmed_by_the_driver_at_once(api):
    """M7 answered 0: the machine stops there (two moves of 10 mm from rest to rest at
    500 mm/s^2, 100 mm/s never reached: 2 x 2 sqrt(10 / 500) s)."""
    lib = api
    compile_on(lib, 0, "G1 X10 F6000\nM7\nG1 X20\n")
    driver = Driver(lib, 0)
    start(lib, 0)
    assert poll_run(lib, 0)[1] == -32
    assert driver.what("M") == [("M", 7)]
    assert get_pos(lib, 0)[1].m_cncRunTime == pytest.approx(4 * math.sqrt(0.02), rel=0.005)
    assert lib.ToolChainCore_ConfirmMFunc(0) == -1              # nothing waits


def test_a_waiting_m_confirmed_later_with_ConfirmMFunc(api):
    lib = api
    compile_on(lib, 0, "G1 X10 F6000\nM7\nG1 X20\n")
    driver = Driver(lib, 0, m_answer=lambda m: MFUNC_LATER)
    start(lib, 0)
    step(lib, 0, 0.5)                   # it reaches M7 after 2 sqrt(10 / 500) = 0.28 s
    assert driver.what("M") == [("M", 7)]
    held = []
    for _ in range(5):                  # and waits there, however long the time asked for
        step(lib, 0, 2.0)
        pos, enh = get_pos(lib, 0)
        held.append((xyz(pos), pos.m_func, pos.m_pars.M, enh.m_actFeed))
    assert lib.ToolChainCore_StatusCNC(0) == 30
    assert all(h == ((10.0, 0.0, 0.0), 10007, 7.0, 0.0) for h in held), held
    # MFunc is refused while the machine runs
    fun = abi.SIMPLE_GM_PARAMS()
    fun.m_func = 8
    assert lib.ToolChainCore_MFunc(0, ctypes.byref(fun), 0) == -1
    assert lib.ToolChainCore_ConfirmMFunc(0) == 0
    assert lib.ToolChainCore_ConfirmMFunc(0) == -1              # already confirmed
    assert poll_run(lib, 0)[1] == -32
    assert math.dist(xyz(get_pos(lib, 0)[0]), (20.0, 0.0, 0.0)) <= EPS


def test_MFunc_while_stopped_and_its_pending_confirmation(api):
    lib = api
    compile_on(lib, 0, "G1 X10 F6000\n")
    answers = [2, 0]
    driver = Driver(lib, 0, m_answer=lambda m: answers.pop(0))
    fun = abi.SIMPLE_GM_PARAMS()
    fun.m_func = 8
    assert lib.ToolChainCore_MFunc(0, ctypes.byref(fun), 0) == 0       # answered "later"
    assert lib.ToolChainCore_MFunc(0, ctypes.byref(fun), 0) == -1      # the previous one is pending
    assert lib.ToolChainCore_ConfirmMFunc(0) == 0
    assert lib.ToolChainCore_MFunc(0, ctypes.byref(fun), 0) == 0
    assert lib.ToolChainCore_ConfirmMFunc(0) == -1
    assert driver.what("M") == [("M", 8), ("M", 8)]
    assert lib.ToolChainCore_MFunc(0, None, 0) == -1


def test_start_m_functions_answered_later_hold_the_start_at_70(api):
    """StartCNCEx(30, "M7 M8") with DriverMFunc answering TC_MFUNC_LATER: status 70
    ("sending start M functions") while M7 waits, the machine does not move however
    much time passes; ConfirmMFunc sends M8, which waits too; its confirmation starts
    the run (30), which ends at -32. The machine's time starts with the motion."""
    lib = api
    compile_on(lib, 0, "G1 X10 F6000\n")
    driver = Driver(lib, 0, m_answer=lambda m: MFUNC_LATER)
    start(lib, 0, FWD, b"M7 M8")
    for m in (7, 8):
        assert wait(lib, 0, lambda s: s == 70 and driver.what("M")[-1:] == [("M", m)]) == 70
        step(lib, 0, 1.0)                               # nothing moves: nothing runs
        pos, enh = get_pos(lib, 0)
        assert (xyz(pos), pos.m_func, pos.m_pars.M) == ((0.0, 0.0, 0.0), 10000 + m, float(m))
        assert lib.ToolChainCore_StatusCNC(0) == 70 and enh.m_cncRunTime == 0.0
        assert lib.ToolChainCore_ConfirmMFunc(0) == 0
    assert wait(lib, 0, lambda s: s != 70) == 30
    samples, status = poll_run(lib, 0)
    assert status == -32
    assert [d for w, d in driver.what() if w != "G"] == [30, 7, 8, None]       # init, M7, M8, end
    assert get_pos(lib, 0)[1].m_cncRunTime == pytest.approx(2 * math.sqrt(10 / 500), abs=2e-4)


def test_a_stop_while_the_start_m_functions_wait_ends_the_start(api):
    """StopCNCEx while M7 of the start waits (70): the start ends -31 where the machine
    stood, M8 is never sent and nothing waits any more; the next start sends its own."""
    lib = api
    compile_on(lib, 0, "G1 X10 F6000\n")
    driver = Driver(lib, 0, m_answer=lambda m: MFUNC_LATER if m == 7 else 0)
    start(lib, 0, FWD, b"M7 M8")
    assert wait(lib, 0, lambda s: s == 70 and driver.what("M") == [("M", 7)]) == 70
    assert lib.ToolChainCore_StopCNCEx(0, None) == 0
    assert wait(lib, 0, lambda s: s != 70) == -31
    assert lib.ToolChainCore_ConfirmMFunc(0) == -1
    assert xyz(get_pos(lib, 0)[0]) == (0.0, 0.0, 0.0) and driver.what("M") == [("M", 7)]
    start(lib, 0, FWD, b"M8")
    assert poll_run(lib, 0)[1] == -32
    assert driver.what("M") == [("M", 7), ("M", 8)]


def test_stop_m_functions_answered_later_hold_the_stop_at_80(api):
    """StopCNCEx(M8 M9) at cruise, DriverMFunc answering TC_MFUNC_LATER: the machine
    brakes, then stands at 80 ("sending stop M functions") while M8 waits, M9 after
    its confirmation, -31 after M9's. A second StopCNCEx answers the one that waits:
    -31 at once, the rest not sent."""
    lib = api
    for second_stop in (False, True):
        compile_on(lib, 0, "G1 X1000 F6000\n")
        driver = Driver(lib, 0, m_answer=lambda m: MFUNC_LATER)
        start(lib, 0)
        step(lib, 0, 0.5)
        assert lib.ToolChainCore_StopCNCEx(0, b"M8 M9") == 0
        assert poll_run(lib, 0, running=(30,))[1] == 80
        assert wait(lib, 0, lambda s: driver.what("M") == [("M", 8)]) == 80
        stood = xyz(get_pos(lib, 0)[0])
        assert stood == pytest.approx((45.0, 0.0, 0.0), abs=1e-9)
        if second_stop:
            assert lib.ToolChainCore_StopCNCEx(0, None) == 0
            assert wait(lib, 0, lambda s: s != 80) == -31
            assert driver.what("M") == [("M", 8)] and lib.ToolChainCore_ConfirmMFunc(0) == -1
        else:
            assert lib.ToolChainCore_ConfirmMFunc(0) == 0
            assert wait(lib, 0, lambda s: driver.what("M") == [("M", 8), ("M", 9)]) == 80
            assert lib.ToolChainCore_ConfirmMFunc(0) == 0
            assert wait(lib, 0, lambda s: s != 80) == -31
        assert xyz(get_pos(lib, 0)[0]) == stood and driver.what()[-1] == ("end", None)


def test_a_simulation_does_not_wait_for_m_functions_answered_later(api):
    """The same session runs a simulation (10), which never waits: addCode's and the
    program's M functions answered TC_MFUNC_LATER go by, nothing is left waiting."""
    lib = api
    compile_on(lib, 0, "G1 X10 F6000\nM7\nG1 X20\n")
    driver = Driver(lib, 0, m_answer=lambda m: MFUNC_LATER)
    assert lib.ToolChainCore_StartCNCEx(0, 10, b"M8") == 0
    assert wait(lib, 0, lambda s: s != 10) == -10
    assert driver.what("M") == [("M", 8), ("M", 7)] and driver.what()[0] == ("init", 10)
    assert lib.ToolChainCore_ConfirmMFunc(0) == -1


def test_a_stop_answers_the_m_function_that_waits(api):
    """stale_m_pending.py: M7 answered TC_MFUNC_LATER, StopCNCEx: -31 at M7, nothing
    waits (ConfirmMFunc -1). The stop answered M7: the next start goes on after it
    without sending it again, and M8 is the next the driver gets."""
    lib = api
    compile_on(lib, 0, "G1 X10 F6000\nM7\nG1 X20\nM8\nG1 X30\n")
    driver = Driver(lib, 0, m_answer=lambda m: MFUNC_LATER)
    start(lib, 0)
    step(lib, 0, 1.0)
    assert driver.what("M") == [("M", 7)] and get_pos(lib, 0)[0].m_func == 10007
    assert lib.ToolChainCore_StopCNCEx(0, None) == 0
    assert poll_run(lib, 0)[1] == -31
    assert lib.ToolChainCore_ConfirmMFunc(0) == -1
    start(lib, 0)
    step(lib, 0, 1.0)
    assert driver.what("M") == [("M", 7), ("M", 8)]
    assert xyz(get_pos(lib, 0)[0]) == pytest.approx((20.0, 0.0, 0.0), abs=1e-9)
    assert lib.ToolChainCore_ConfirmMFunc(0) == 0
    assert poll_run(lib, 0)[1] == -32


def test_a_confirmation_racing_the_next_start_confirms_nothing_of_it(api):
    """A waiting M7, StopCNCEx; a host thread's ConfirmMFunc races the next activity's
    start (a manual move): it confirms nothing (-1; no data race under ThreadSanitizer)
    and the move runs as a move."""
    lib = api
    compile_on(lib, 0, "G1 X10 F6000\nM7\nG1 X20\n")
    driver = Driver(lib, 0, m_answer=lambda m: MFUNC_LATER)     # kept: its thunks must live
    for i in range(20):
        assert lib.ToolChainCore_ResetCNC(0, 0, 10, (ctypes.c_double * 10)()) == 0
        start(lib, 0)
        step(lib, 0, 1.0)
        assert lib.ToolChainCore_StopCNCEx(0, None) == 0
        assert poll_run(lib, 0)[1] == -31
        go = threading.Barrier(2)
        confirmed = []
        racer = threading.Thread(target=lambda: (go.wait(), confirmed.append(lib.ToolChainCore_ConfirmMFunc(0))))
        racer.start()
        go.wait()
        assert lib.ToolChainCore_GoToPosition(0, 2, (ctypes.c_double * 2)(i % 5, 1.0)) == 0
        racer.join()
        assert poll_run(lib, 0, running=(50,))[1] == -50
        assert confirmed == [-1]
        assert xyz(get_pos(lib, 0)[0]) == (i % 5, 1.0, 0.0)


def test_GetPos_counters_of_a_run_are_the_programs(api):
    """A run of the machine counts as a simulation does: cuts, rapids, their changes
    and M functions (counted from the program's text), also across a stop and a
    continue."""
    lib = api
    text = "G0 X5\nG1 X10 F6000\nG1 X15\nM7\nG0 X20\nG1 X25 M1005\nG0 X30\nG4 H0.1\nG1 X35\n"
    set_params(lib, 0, tolerance=AS_WRITTEN["tolerance"])      # X10, X15: two cuts as written
    expected = dict(m_nWorkCounter=4, m_nG00Counter=3, m_nG00ToWorkChanges=3, m_nWorkToG00Changes=2,
                    m_nMCounter=2)
    compile_on(lib, 0, text)
    assert lib.ToolChainCore_StartCNCEx(0, 10, None) == 0
    assert wait(lib, 0, lambda s: s != 10) == -10
    simulated = get_pos(lib, 0)[1]
    assert {k: getattr(simulated, k) for k in expected} == expected
    for stop_at in (None, 0.15):
        compile_on(lib, 0, text)
        start(lib, 0)
        if stop_at is not None:
            step(lib, 0, stop_at)
            assert lib.ToolChainCore_StopCNCEx(0, None) == 0
            assert poll_run(lib, 0)[1] == -31
            start(lib, 0)
        assert poll_run(lib, 0)[1] == -32
        enh = get_pos(lib, 0)[1]
        assert {k: getattr(enh, k) for k in expected} == expected


def test_GetPos_during_a_dwell_shows_G4(api):
    """G4 H0.5 between two moves: while the machine dwells GetPos shows m_func 4 and
    the G cell 4 (the cells of a G function), as a simulation of the dwell does."""
    lib = api
    compile_on(lib, 0, "G1 X10 F6000\nG4 H0.5\nG1 X20\n")
    start(lib, 0)
    step(lib, 0, 0.5)                   # the first move takes 0.28 s
    pos, enh = get_pos(lib, 0)
    assert (pos.m_func, pos.m_pars.G, pos.m_editorLine) == (4, 4.0, 2)
    assert (pos.m_calcS.x, enh.m_actFeed) == (10.0, 0.0)
    assert poll_run(lib, 0)[1] == -32


def test_M0_pauses_at_minus_33_and_a_start_goes_on(api):
    lib = api
    compile_on(lib, 0, "G1 X10 F6000\nM0\nG1 X20\n")
    driver = Driver(lib, 0)
    start(lib, 0)
    assert poll_run(lib, 0)[1] == -33
    assert math.dist(xyz(get_pos(lib, 0)[0]), (10.0, 0.0, 0.0)) <= EPS
    assert driver.what("M") == [("M", 0)]
    start(lib, 0)
    assert poll_run(lib, 0)[1] == -32
    assert math.dist(xyz(get_pos(lib, 0)[0]), (20.0, 0.0, 0.0)) <= EPS


def test_a_dwell_waits_its_time(api):
    lib = api
    compile_on(lib, 0, "G1 X10 F6000\nG4 H0.5\nG1 X20\n")
    expected = run_time_of(lib, 0)
    assert expected == pytest.approx(4 * math.sqrt(0.02) + 0.5, rel=1e-6)
    start(lib, 0)
    assert poll_run(lib, 0)[1] == -32
    assert get_pos(lib, 0)[1].m_cncRunTime == pytest.approx(expected, rel=0.005)


def test_SetBreakpoint_stops_before_its_line_and_the_next_start_passes(api):
    lib = api
    compile_on(lib, 0, LINES)
    main = lib.ToolChainCore_FileToIdx(0, b"m.nc")
    assert lib.ToolChainCore_SetBreakpoint(0, 3, main) == 0
    start(lib, 0)
    assert poll_run(lib, 0)[1] == -31
    pos, _ = get_pos(lib, 0)
    assert math.dist(xyz(pos), (100.0, 50.0, 0.0)) <= EPS
    start(lib, 0)
    assert poll_run(lib, 0)[1] == -32
    assert math.dist(xyz(get_pos(lib, 0)[0]), (0.0, 50.0, 0.0)) <= EPS
    # a breakpoint of another file never stops this one
    assert lib.ToolChainCore_SetBreakpoint(0, 3, main + 1) == 0
    assert lib.ToolChainCore_ResetCNC(0, 1, 0, None) == 0
    start(lib, 0)
    assert poll_run(lib, 0)[1] == -32


IsBreakpoint = ctypes.CFUNCTYPE(ctypes.c_int32, ctypes.c_ssize_t, ctypes.c_uint32, ctypes.c_int32)


def test_the_IsBreakpoint_callback_is_asked_per_line_and_stops_before_it(api):
    lib = api
    set_params(lib, 0, tolerance=AS_WRITTEN["tolerance"])      # the collinear lines as written
    compile_on(lib, 0, "G1 X10 F6000\nG1 X20\nG1 X30\nG1 X40\n")
    asked = []
    fn = IsBreakpoint(lambda user, line, file_idx: asked.append((line, file_idx)) or int(line in (2, 4)))
    assert lib.ToolChainCore_SetCallBack(0, abi.CB_IS_BREAKPOINT, 0, ctypes.cast(fn, ctypes.c_void_p)) == 0
    main = lib.ToolChainCore_FileToIdx(0, b"m.nc")
    ends, per_run = [], []
    for _ in range(3):
        start(lib, 0)
        ends.append((poll_run(lib, 0)[1], xyz(get_pos(lib, 0)[0])))
        per_run.append([line for line, idx in asked if idx == main])
        asked.clear()
    assert ends == [(-31, (10.0, 0.0, 0.0)), (-31, (30.0, 0.0, 0.0)), (-32, (40.0, 0.0, 0.0))]
    # asked once for every line ahead, never for the one a run starts at
    assert per_run == [[2, 3, 4], [3, 4], []]


def test_GetPos_m_relFeed_follows_the_override_ramp(api):
    """overrideInc 1e-5 per 100 us: 1.0 -> 0.5 takes 5 s of machine time, and GetPos
    shows the override of the moment, not the one set."""
    lib = api
    set_params(lib, 0, overrideInc=1e-5)
    compile_on(lib, 0, "G1 X2000 F6000\n")
    start(lib, 0)
    step(lib, 0, 0.5)
    assert lib.ToolChainCore_SetRelFeed(0, 0.5) == 0
    ramp = []
    for _ in range(60):
        step(lib, 0, 0.1)
        pos, enh = get_pos(lib, 0)
        ramp.append((enh.m_cncRunTime, enh.m_relFeed))
    # 0.01 less every 0.1 s (1000 steps of 1e-5) from 1.0, then 0.5 from 5 s on
    assert [round(r, 9) for t, r in ramp] == [round(max(1.0 - 0.01 * k, 0.5), 9) for k in range(1, 61)]
    assert lib.ToolChainCore_StopCNCEx(0, None) == 0


def test_the_override_ramp_shows_in_the_actual_feed(api):
    """overrideInc 1e-5 per 100 us (feed-cap override): the override falls by 0.1 per
    second of machine time, so m_actFeed goes from 6000 to 3000 mm/min at exactly
    600 mm/min per second (the ramps' 500 mm/s^2 follow it easily), then stays."""
    lib = api
    set_params(lib, 0, overrideInc=1e-5)
    compile_on(lib, 0, "G1 X2000 F6000\n")
    start(lib, 0)
    step(lib, 0, 0.5)
    assert get_pos(lib, 0)[1].m_actFeed == pytest.approx(6000.0)
    assert lib.ToolChainCore_SetRelFeed(0, 0.5) == 0
    feeds = []
    for _ in range(55):
        step(lib, 0, 0.1)
        feeds.append(get_pos(lib, 0)[1].m_actFeed)
    expected = [max(6000.0 - 60.0 * k, 3000.0) for k in range(1, 56)]
    assert feeds == pytest.approx(expected, abs=1e-6)
    assert lib.ToolChainCore_StopCNCEx(0, None) == 0
    assert poll_run(lib, 0)[1] == -31


def continuous_on_path(samples, records, fastest):
    """Every GetPos sample on the path, and no jump: between two samples the machine
    moved at most the fastest feed times the machine time between them."""
    for (p0, e0), (p1, e1) in zip(samples, samples[1:]):
        assert on_path(records, xyz(p1)) <= EPS, xyz(p1)
        dt = e1.m_cncRunTime - e0.m_cncRunTime
        assert math.dist(xyz(p0), xyz(p1)) <= fastest * dt + EPS, (xyz(p0), xyz(p1), dt)


@pytest.mark.parametrize("stop_after", [0.3, 3.6, None], ids=["first_part", "later_part", "from_the_end"])
def test_backward_retraces_to_the_start_through_the_api(api, stop_after):
    lib = api
    set_params(lib, 0)
    p = abi.GCODE_PARAMETERS()
    lib.ToolChainCore_GetGCodeParameters(0, ctypes.byref(p))
    p.motion[2].feed = 1500.0
    assert lib.ToolChainCore_SetGCodeParameters(0, ctypes.byref(p)) == 0
    compile_on(lib, 0, ARCS)
    records = records_of(lib, 0)
    start(lib, 0)
    if stop_after is None:
        samples, status = poll_run(lib, 0)
        assert status == -32
    else:
        step(lib, 0, stop_after)
        assert lib.ToolChainCore_StopCNCEx(0, None) == 0
        samples, status = poll_run(lib, 0)
        assert status == -31
    samples = [get_pos(lib, 0)]
    driver = Driver(lib, 0)
    start(lib, 0, BACK, b"M9")
    more, status = poll_run(lib, 0)
    samples += more + [get_pos(lib, 0)]
    assert status == -30
    continuous_on_path(samples, records, 3000.0 / 60.0)
    assert all(enh.m_actFeed <= 1500.0 * (1 + 1e-9) for _, enh in samples)
    assert math.dist(xyz(samples[-1][0]), (0.0, 0.0, 0.0)) <= EPS
    assert driver.what("M") == [] and driver.what()[0] == ("init", 32)
    # backward again: nothing left to retrace (-30 is not a status it starts from)
    assert lib.ToolChainCore_StartCNCEx(0, BACK, None) == -1
    # and forward from the start runs the whole program
    start(lib, 0)
    assert poll_run(lib, 0)[1] == -32
    assert math.dist(xyz(get_pos(lib, 0)[0]), tuple(records[-1].tool_end)) <= EPS


@pytest.mark.slow
def test_backward_ends_at_minus_31_where_the_remembered_path_ends(api):
    """105,000 parts of 1 mm along X run forward; backward retraces what the machine
    remembers and stops -31 there. docs/machine.md says 100,000 motion parts; the
    history drops its oldest tenth when full, so it holds 90,000 to 100,000."""
    lib = api
    n = 105_000
    p = abi.GCODE_PARAMETERS()
    lib.ToolChainCore_GetGCodeParameters(0, ctypes.byref(p))
    for k in range(6):
        p.motion[k].acc = p.motion[k].dec = 50000.0
    p.motion[2].feed = 60000.0
    p.tolerance[2] = 0.0                # the collinear parts stay parts (the vendor's default joins them)
    assert lib.ToolChainCore_SetGCodeParameters(0, ctypes.byref(p)) == 0
    compile_on(lib, 0, "F60000\n" + "".join(f"G1 X{i}\n" for i in range(1, n + 1)))
    start(lib, 0)
    assert poll_run(lib, 0, dt=1.0, limit=1000.0)[1] == -32
    assert get_pos(lib, 0)[0].m_calcS.x == pytest.approx(n)
    start(lib, 0, BACK)
    assert poll_run(lib, 0, dt=1.0, limit=1000.0)[1] == -31
    retraced = n - get_pos(lib, 0)[0].m_calcS.x
    assert 90_000 <= retraced <= 100_000
    assert retraced == pytest.approx(round(retraced), abs=1e-6)       # at a part's end
    # forward from there reaches the end again
    start(lib, 0)
    assert poll_run(lib, 0, dt=1.0, limit=1000.0)[1] == -32
    assert get_pos(lib, 0)[0].m_calcS.x == pytest.approx(n)


def test_three_cores_run_at_once_each_on_its_own_path(api):
    lib = api
    programs = {0: (LINES, 0.0), 1: (ARCS, 0.0), 2: (SQUARE_G42, 2.0)}
    records = {}
    for core, (text, radius) in programs.items():
        p = abi.GCODE_PARAMETERS()
        lib.ToolChainCore_GetGCodeParameters(core, ctypes.byref(p))
        for k in range(8):
            p.correction[k].size = radius
        assert lib.ToolChainCore_SetGCodeParameters(core, ctypes.byref(p)) == 0
        compile_on(lib, core, text)
        records[core] = records_of(lib, core)
    for core in programs:
        start(lib, core)
    samples = {core: [] for core in programs}
    while any(lib.ToolChainCore_StatusCNC(core) == 30 for core in programs):
        for core in programs:           # the three run side by side, each on its own clock
            step(lib, core, 0.01)
            samples[core].append(get_pos(lib, core))
    for core in programs:
        assert lib.ToolChainCore_StatusCNC(core) == -32
        samples[core].append(get_pos(lib, core))
        assert len(samples[core]) > 20
        fastest = max(r.feed for r in records[core] if r.kind == abi.TC_TOOLPATH_MOTION) / 60.0
        continuous_on_path(samples[core], records[core], fastest)
        end, enh = get_pos(lib, core)
        assert math.dist(xyz(end), tuple(records[core][-1].tool_end)) <= EPS
        # the simulation from where the run started
        assert lib.ToolChainCore_ResetCNC(core, 0, 10, (ctypes.c_double * 10)()) == 0
        assert enh.m_cncRunTime == pytest.approx(run_time_of(lib, core), rel=0.005)


def test_GoToPosition_moves_at_motion_5_then_stands_out_of_the_trajectory(api):
    """A line to (18, 24) at motion[5]'s 1200 mm/min, then -50."""
    lib = api
    p = abi.GCODE_PARAMETERS()
    lib.ToolChainCore_GetGCodeParameters(0, ctypes.byref(p))
    p.motion[5].feed = 1200.0
    assert lib.ToolChainCore_SetGCodeParameters(0, ctypes.byref(p)) == 0
    compile_on(lib, 0, LINES)
    target = (ctypes.c_double * 3)(18.0, 24.0, 0.0)
    assert lib.ToolChainCore_GoToPosition(0, 3, target) == 0
    samples, status = poll_run(lib, 0, running=(50,))
    assert status == -50
    for pos, enh in samples:
        x, y, z = xyz(pos)
        assert abs(x * 24.0 - y * 18.0) <= 1e-6 and enh.m_actFeed <= 1200.0 * (1 + 1e-9)
    pos, enh = get_pos(lib, 0)
    assert xyz(pos) == pytest.approx((18.0, 24.0, 0.0), abs=1e-9)
    # out of the trajectory: no forward run until ResetCNC marks the start again
    assert lib.ToolChainCore_StartCNCEx(0, FWD, None) == -1
    assert lib.ToolChainCore_ResetCNC(0, 1, 0, None) == 0
    assert lib.ToolChainCore_StatusCNC(0) == -30


def test_GoToPosition_with_no_coordinates_moves_nothing(api):
    """GoToPosition(core, 0, NULL) is allowed (the header: -1 only for nCoords > 0 with
    NULL): a manual move to where the machine stands, 50 then -50, nothing moved (no
    NULL reaches memcpy: the ASan + UBSan build stops at undefined behaviour)."""
    lib = api
    assert lib.ToolChainCore_ResetCNC(0, 0, 2, (ctypes.c_double * 2)(3.0, 4.0)) == 0
    assert lib.ToolChainCore_GoToPosition(0, 0, None) == 0
    assert poll_run(lib, 0, running=(50,))[1] == -50
    assert xyz(get_pos(lib, 0)[0]) == (3.0, 4.0, 0.0)


@pytest.mark.parametrize("case", ["distance", "arc_centre", "feed"])
def test_manual_moves_whose_path_is_not_finite_are_refused(api, case):
    """goto_nonfinite_position.py: finite arguments whose path overflows -- +1e308 from
    -1e308 (the distance), an arc round (5, 1e300) (its points), a line at feed 1e300
    (its speed squared) -- left NaN or infinite positions. Refused: -1, error 24 naming
    the call, nothing moves; the position stays finite and the next move runs."""
    lib = api
    start_x = -1e308 if case == "distance" else 0.0
    assert lib.ToolChainCore_ResetCNC(0, 0, 1, (ctypes.c_double * 1)(start_x)) == 0
    before = lib.ToolChainCore_StatusCNC(0)
    if case == "distance":
        rc = lib.ToolChainCore_GoToPosition(0, 1, (ctypes.c_double * 1)(1e308))
    else:
        dest = abi.SIMPLE_GM_PARAMS()
        dest.m_func, dest.m_planeTool = (2, 17) if case == "arc_centre" else (1, 17)
        dest.m_calcE.x = 10.0 if case == "arc_centre" else 1e300
        if case == "arc_centre":
            dest.m_cc.x, dest.m_cc.y = 5.0, 1e300
        else:
            dest.m_cc.a = 1e300
        rc = lib.ToolChainCore_GoToPositionEx(0, ctypes.byref(dest))
    assert rc == -1 and lib.ToolChainCore_StatusCNC(0) == before
    info = abi.CALLBACK_INFO()
    assert lib.ToolChainCore_GetLastCallError(0, ctypes.byref(info)) == 1
    assert info.stringId == 24 and info.m_fullError.startswith(b"GoToPosition: the move's path is not finite")
    assert xyz(get_pos(lib, 0)[0]) == (start_x, 0.0, 0.0)
    assert lib.ToolChainCore_ResetCNC(0, 0, 10, (ctypes.c_double * 10)()) == 0
    assert lib.ToolChainCore_GoToPosition(0, 3, (ctypes.c_double * 3)(1.0, 2.0, 3.0)) == 0
    assert poll_run(lib, 0, running=(50,))[1] == -50
    assert xyz(get_pos(lib, 0)[0]) == pytest.approx((1.0, 2.0, 3.0), abs=1e-12)


def test_GoToPosition_run_time_is_the_moves_own_after_DestroyCNC(api):
    """After a run and DestroyCNC, a manual line of 30 mm at 20 mm/s (500 mm/s^2):
    GetPos shows its own time, 1.5 s + 0.04 s, not the run's before it."""
    lib = api
    compile_on(lib, 0, "G1 X100 F6000\n")
    start(lib, 0)
    assert poll_run(lib, 0)[1] == -32
    assert get_pos(lib, 0)[1].m_cncRunTime > 1.0
    assert lib.ToolChainCore_DestroyCNC(0) == 0
    set_params(lib, 0, calcTime=1)
    p = abi.GCODE_PARAMETERS()
    lib.ToolChainCore_GetGCodeParameters(0, ctypes.byref(p))
    p.motion[5].feed = 1200.0
    assert lib.ToolChainCore_SetGCodeParameters(0, ctypes.byref(p)) == 0
    assert lib.ToolChainCore_ResetCNC(0, 0, 10, (ctypes.c_double * 10)()) == 0
    assert lib.ToolChainCore_GoToPosition(0, 2, (ctypes.c_double * 2)(18.0, 24.0)) == 0
    assert poll_run(lib, 0, running=(50,))[1] == -50
    assert get_pos(lib, 0)[1].m_cncRunTime == pytest.approx(1.54, rel=0.005)


def test_the_largest_time_scale_runs_a_program_of_many_parts(run_python):
    """200 parts of 1 mm at SetTimeScale 1e6 (documented range (0, 1e6]): 2 s of
    machine time end at once (the subprocess is given 5 s): the pacer waits for the
    feeder instead of spending its budget on an empty ring."""
    import runtime_host
    out = runtime_host.run_script(run_python, """
        load_ini(lib, 0)
        compile_wait(lib, 0, b"F6000\\n" + b"".join(b"G1 X%d\\n" % i for i in range(1, 201)))
        assert lib.ToolChainCore_SetTimeScale(0, 1e6) == 0
        assert lib.ToolChainCore_StartCNCEx(0, 30, None) == 0
        print(wait_status(lib, 0, lambda s: s != 30, timeout=60))
    """, seconds=5, what="a run at time scale 1e6")
    assert out.split() == ["-32"]


def test_the_largest_time_scale_runs_waiting_m_functions_at_once(run_python):
    """Five waiting M functions between moves of 1 mm at SetTimeScale 1e6, each
    confirmed at once by DriverMFunc: the run ends at once (5 s given; the pacer
    does not spend its budget while the machine waits for a confirmation)."""
    import runtime_host
    out = runtime_host.run_script(run_python, """
        load_ini(lib, 0)
        answer = abi.DriverMFunc(lambda user, part: 0)
        set_callback(lib, 0, abi.CB_DRIVER_M_FUNC, answer)
        compile_wait(lib, 0, b"F6000\\n" + b"".join(b"G1 X%d\\nM%d\\n" % (i, 7 + i) for i in range(1, 6)))
        assert lib.ToolChainCore_SetTimeScale(0, 1e6) == 0
        assert lib.ToolChainCore_StartCNCEx(0, 30, None) == 0
        print(wait_status(lib, 0, lambda s: s != 30, timeout=60))
    """, seconds=5, what="waiting M functions at time scale 1e6")
    assert out.split() == ["-32"]


def test_at_the_largest_time_scale_GetPos_moves_and_endings_return_at_once(run_python):
    """high_timescale_latency.py: at time scale 1e6 on 20,000 moves of ~200 mm the pacer
    ran steps for seconds between two looks at the clock: GetPos stood still for 2.8 s
    and DestroyCNC / ResetCNC blocked for 2-13 s. A tick's work now ends after a
    millisecond of wall time, so GetPos moves and an ending call is seen within a tick
    or two. (Wall-time bounds, wide for a loaded machine: the defect was seconds.)"""
    import runtime_host
    out = runtime_host.run_script(run_python, """
        import random
        rnd = random.Random(1)
        code = b"G0 X0 Y0\\nF3000\\n" + b"".join(b"G1 X%.3f Y%.3f\\n" % (rnd.uniform(-200, 200), rnd.uniform(-200, 200))
                                                for _ in range(20000))
        assert lib.ToolChainCore_SetTimeScale(0, 1e6) == 0
        pos, enh = abi.SIMPLE_GM_PARAMS(), abi.GM_PARAMS_ENHANCED()
        def seen():
            lib.ToolChainCore_GetPos(0, 0, ctypes.byref(pos), ctypes.byref(enh))
            return pos.m_gCodeIndex, enh.m_actPartsLen
        for end in ("destroy", "reset"):
            assert compile_wait(lib, 0, code) is None
            assert lib.ToolChainCore_ResetCNC(0, 0, 0, None) == 0
            assert lib.ToolChainCore_StartCNCEx(0, 30, None) == 0
            last, since, stale = seen(), time.monotonic(), 0.0
            t0 = time.monotonic()
            while time.monotonic() - t0 < 1.0 and lib.ToolChainCore_StatusCNC(0) == 30:
                now = seen()
                if now != last:
                    last, since = now, time.monotonic()
                stale = max(stale, time.monotonic() - since)
                time.sleep(0.001)
            assert lib.ToolChainCore_StatusCNC(0) == 30
            t1 = time.monotonic()
            if end == "destroy":
                assert lib.ToolChainCore_DestroyCNC(0) == 0
            else:
                assert lib.ToolChainCore_ResetCNC(0, 1, 0, None) == 0
            print(end, round(stale, 3), round(time.monotonic() - t1, 3))
    """, seconds=60, what="the largest time scale on a long program")
    for line in out.splitlines():
        end, stale, took = line.split()
        assert float(stale) < 0.25 and float(took) < 1.0, line


# ------------------------------------------------------------------ endings at random moments

RANDOM_ENDINGS = """
import random
rng = random.Random(SEED)
PROGRAMS = [
    b"G1 X40 F6000\\nM7\\nG1 Y40\\nG4 H0.2\\nG1 X0\\nM0\\nG1 Y0\\n",
    b"F3000\\n" + b"".join(b"G1 X%d Y%d\\n" % (i % 7, i % 5) for i in range(300)),
    b"G0 X10 Y10\\nG42 G1 X20 F3000\\nG3 X20 Y30 I0 J10\\nG1 X10\\nG40 G1 X0 Y0\\nM1005\\nM8\\n",
]
later = {0: False, 1: False, 2: False}
polled = {"bad": 0, "calls": 0}
running = threading.Event()
running.set()

def poll():
    pos, enh = abi.SIMPLE_GM_PARAMS(), abi.GM_PARAMS_ENHANCED()
    while running.is_set():
        for core in range(3):
            polled["calls"] += 1
            if lib.ToolChainCore_GetPos(core, 0, ctypes.byref(pos), ctypes.byref(enh)) != 0:
                polled["bad"] += 1
            status = lib.ToolChainCore_StatusCNC(core)
            if status not in (0, 1, -1, -30, -31, -32, -33, 30, 31, 32, 33, 70, 80):
                polled["bad"] += 1
                polled[status] = polled.get(status, 0) + 1
        time.sleep(0.0002)

def make_m(core):
    def answer(user, part):
        roll = rng.random()
        if roll < 0.05:
            lib.ToolChainCore_DestroyCNC(core)         # applied once the callback returns
        elif roll < 0.1:
            lib.ToolChainCore_ResetCNC(core, 1, 0, None)
        return 2 if later[core] else 0
    return abi.DriverMFunc(answer)

thunks = []
for core in range(3):
    load_ini(lib, core)
    thunks.append(make_m(core))
    set_callback(lib, core, abi.CB_DRIVER_M_FUNC, thunks[-1])
base = thread_count()
poller = threading.Thread(target=poll)
poller.start()
ends = {}
deadline = time.monotonic() + SECONDS
while time.monotonic() < deadline:
    core = rng.randrange(3)
    status = lib.ToolChainCore_StatusCNC(core)
    if status <= 0:
        if status in (0, -50) or rng.random() < 0.2:
            lib.ToolChainCore_ResetCNC(core, 0, 10, (ctypes.c_double * 10)())
            compile_wait(lib, core, rng.choice(PROGRAMS))
        lib.ToolChainCore_SetTimeScale(core, rng.choice([2.0, 20.0, 200.0]))
        later[core] = rng.random() < 0.5
        regimes = [30, 31, 33] + ([32] if lib.ToolChainCore_StatusCNC(core) in (-31, -32, -33) else [])
        if lib.ToolChainCore_StatusCNC(core) == -32:
            regimes = [32]
        regime = rng.choice(regimes)
        rc = lib.ToolChainCore_StartCNCEx(core, regime, rng.choice([None, b"M9"]))
        assert rc == 0, (core, regime, lib.ToolChainCore_StatusCNC(core))
    time.sleep(rng.uniform(0, 0.01))
    action = rng.choice(["reset", "destroy", "stop", "confirm", "none"])
    if action == "reset":
        assert lib.ToolChainCore_ResetCNC(core, 1, 0, None) == 0
        after = lib.ToolChainCore_StatusCNC(core)
        assert after in (-30, 0), after                  # 0: a callback destroyed it meanwhile
    elif action == "destroy":
        assert lib.ToolChainCore_DestroyCNC(core) == 0
        assert lib.ToolChainCore_StatusCNC(core) == 0
    elif action == "stop":
        if lib.ToolChainCore_StopCNCEx(core, rng.choice([None, b"M8"])) == 0:
            # a stop answers an M function that waits; the stop's own M8 (status 80)
            # waits for its confirmation when the driver answers "later"
            def confirmed(s):
                if s == 80:
                    lib.ToolChainCore_ConfirmMFunc(core)
                return s <= 0
            after = wait_status(lib, core, confirmed)
            assert after in (-30, -31, -32, -33, 0), after
    elif action == "confirm":
        lib.ToolChainCore_ConfirmMFunc(core)
    ends[action] = ends.get(action, 0) + 1
for core in range(3):
    assert lib.ToolChainCore_DestroyCNC(core) == 0
    assert lib.ToolChainCore_StatusCNC(core) == 0
running.clear()
poller.join()
assert_threads_back(base, "before the runs")
assert polled["bad"] == 0 and polled["calls"] > 0, polled
# every core still runs a program to its end
for core in range(3):
    set_callback(lib, core, abi.CB_DRIVER_M_FUNC, None)
    compile_wait(lib, core, b"G1 X5 F6000\\nM7\\nG1 X10\\n")
    lib.ToolChainCore_SetTimeScale(core, 50.0)
    assert lib.ToolChainCore_StartCNCEx(core, 30, None) == 0
for core in range(3):
    assert wait_status(lib, core, lambda s: s != 30) == -32
    lib.ToolChainCore_DestroyCNC(core)
assert_threads_back(base, "before the runs")
print(sorted(ends.items()))
"""


def random_endings(run_python, seconds):
    seed = int(os.environ.get("SF_TCH_STORM_SEED") or random.randrange(1 << 30))
    import runtime_host
    body = f"SEED = {seed}\nSECONDS = {seconds}\n" + RANDOM_ENDINGS
    out = runtime_host.run_script(run_python, body, seconds + 60, f"machine endings (seed {seed})")
    assert "('destroy'" in out and "('reset'" in out, out


def test_DestroyCNC_and_ResetCNC_at_random_moments(run_python):
    """Three cores run forward, backward, wait for M functions, dwell, pause at M0,
    while the host resets, destroys, stops and confirms at random moments (and the
    M callback destroys or resets its core): every call returns, the statuses are
    the documented ones (docs/api.md), GetPos never fails, no thread is left, and every core runs again."""
    random_endings(run_python, 3)


@pytest.mark.slow
def test_DestroyCNC_and_ResetCNC_at_random_moments_long(run_python):
    random_endings(run_python, 10 * SLOW_SCALE)


def brute_force_nearest(records, p, samples=20000):
    """The nearest point of the motion parts' tool paths to p: every part sampled
    (arcs at `samples` points, lines projected exactly); (distance, point)."""
    best = (math.inf, None)
    for k, r in enumerate(records):
        if r.kind != abi.TC_TOOLPATH_MOTION or r.length <= 0:
            continue
        if r.number in (0, 1):
            a, b = tool_start(records, k), tuple(r.tool_end)
            ab = [b[i] - a[i] for i in range(3)]
            f = max(0.0, min(1.0, sum((p[i] - a[i]) * ab[i] for i in range(3)) / sum(c * c for c in ab)))
            q = tuple(a[i] + f * ab[i] for i in range(3))
            best = min(best, (math.dist(p, q), q))
        else:
            for i in range(samples + 1):
                q = point_at(records, k, r.length * i / samples)
                best = min(best, (math.dist(p, q), q))
    return best


@pytest.mark.parametrize("away", [(60.0, 45.0, 0.0), (-7.0, 33.0, 2.0), (30.0, 100.0, -1.0)])
def test_connect_type_0_goes_to_the_brute_force_nearest_point(api, away):
    """A run from the origin places the program there; GoTo away from the path (-50),
    ConnectCNCEx_Plane type 0 with the machine's position: 40, 41, then -31 on the
    nearest point of the trajectory (all axes count); a forward run from there
    reaches the program's end."""
    lib = api
    set_params(lib, 0, maxConnectionDistance=1000.0)
    compile_on(lib, 0, ARCS)
    records = records_of(lib, 0)
    start(lib, 0)
    assert poll_run(lib, 0)[1] == -32
    assert lib.ToolChainCore_GoToPosition(0, 3, (ctypes.c_double * 3)(*away)) == 0
    assert poll_run(lib, 0, running=(50,))[1] == -50
    here = (ctypes.c_double * 10)(*away)
    assert lib.ToolChainCore_ConnectCNCEx_Plane(0, 0, 3, here, None, 0, 0x3FF, 0) == 0
    seen = set()
    while lib.ToolChainCore_StatusCNC(0) in (40, 41):
        seen.add(lib.ToolChainCore_StatusCNC(0))
        step(lib, 0, 0.01)
    assert lib.ToolChainCore_StatusCNC(0) == -31 and 41 in seen
    there = xyz(get_pos(lib, 0)[0])
    distance, nearest = brute_force_nearest(records, away)
    assert on_path(records, there) <= EPS
    assert math.dist(away, there) == pytest.approx(distance, abs=1e-6)
    assert math.dist(there, nearest) <= 5e-3          # the samples lie ~3 um apart on the arcs
    start(lib, 0)
    assert poll_run(lib, 0)[1] == -32
    assert math.dist(xyz(get_pos(lib, 0)[0]), tuple(records[-1].tool_end)) <= EPS
