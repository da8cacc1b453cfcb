"""The feed planner (toolchain/planner/): closed forms computed by hand, the junction
and arc feed tables, centripetal and axis limits, exact stops, the look-ahead window,
ruckig (test-only) as the time-optimal oracle, and the run time of a simulation.
The planner runs through tests/harness (compiler + planner, no ctypes)."""
import ctypes
import math
from pathlib import Path

import pytest

from sf_tch import abi
from sf_tch.core import Core

@pytest.fixture(scope="session")
def ph(harness):
    return harness


PLAN = 2e-7    # the plan keeps floats, 7 digits (program.pxd PartPlan)


def params(ph, **fields):
    """Default GCODE_PARAMETERS with `fields` set; motion=[(feed, acc, dec, ramp), ...]
    from index 0; axis=[(k, maxFeed, maxAcc, maxDec)]; arc=[(r, rel)]. The planner's
    tests plan the parts as written: tolerance[2] = 0, no collinear G1 parts joined
    (the joins: tests/test_join_lines.py; tolerance= gives all ten)."""
    p = abi.GCODE_PARAMETERS.from_buffer_copy(ph.default_params())
    p.tolerance[2] = 0.0
    for k, m in enumerate(fields.pop("motion", ())):
        if m is not None:
            p.motion[k].feed, p.motion[k].acc, p.motion[k].dec, p.motion[k].rampType = m
    for k, f, a, d in fields.pop("axis", ()):
        p.axisLimits[k].maxFeed, p.axisLimits[k].maxAcc, p.axisLimits[k].maxDec = f, a, d
    for k, (r, rel) in enumerate(fields.pop("arc", ())):
        p.arcFeedTable[k].m_r, p.arcFeedTable[k].m_relFeed = r, rel
    for name, value in fields.items():
        setattr(p, name, value)
    return bytes(p)


# the GCODE_PARAMETERS fields of a compile through the library that keep the parts as written
AS_WRITTEN = dict(tolerance=(0.005, 0.001, 0.0, 0.005, 0.0, 3.0, 0.01, 0.0, 0.0, 0.0))


def plan(ph, text, window=0, enhanced=0, **fields):
    parts, error, _ = ph.plan_text(text, params(ph, **fields), window, enhanced)
    assert error is None, error
    return parts


def total(parts):
    return sum(p["time"] for p in parts)


# ------------------------------------------------------------------ closed forms

@pytest.mark.parametrize("ramp", [1, 2])
@pytest.mark.parametrize("length", [100.0, 3.0])
def test_single_line_rest_to_rest(ph, ramp, length):
    v, a, d = 100.0, 500.0, 250.0            # F6000; acceleration and braking differ
    parts = plan(ph, f"G1 X{length} F6000\n", motion=[None, (6000.0, a, d, ramp)])
    (p,) = parts
    ka, kd = (a, d) if ramp == 1 else (2 * a / math.pi, 2 * d / math.pi)   # sine: same time as 2a/pi
    if length >= v * v / (2 * ka) + v * v / (2 * kd):
        expected = length / v + v / (2 * ka) + v / (2 * kd)
        peak = v
    else:
        peak = math.sqrt(2 * length * ka * kd / (ka + kd))
        expected = peak / ka + peak / kd
    assert p["time"] == pytest.approx(expected, rel=PLAN)
    assert p["v_peak"] == pytest.approx(peak, rel=PLAN)
    assert p["v_in"] == 0.0 and p["v_out"] == 0.0


def test_long_line_by_hand(ph):
    # 100 mm at 100 mm/s, 500 mm/s^2: trapezoid 1 + 0.1 + 0.1; sine ramps last pi/2 longer
    assert total(plan(ph, "G1 X100 F6000\n")) == pytest.approx(1.2, rel=PLAN)
    sine = plan(ph, "G1 X100 F6000\n", motion=[None, (1000.0, 500.0, 500.0, 2)])
    assert total(sine) == pytest.approx(1.0 + math.pi / 10.0, rel=PLAN)


def test_full_circle_rest_to_rest(ph):
    # r 10, 2*pi*10 mm at 50 mm/s with 500 mm/s^2 (the dwell stops the rapid)
    (p,) = plan(ph, "G0 X10\nG4 X0\nG3 X10 Y0 I-10 J0 F3000\n")[2:]
    L = 20 * math.pi
    assert p["length"] == pytest.approx(L, rel=1e-12)
    assert p["time"] == pytest.approx(L / 50.0 + 0.1, rel=PLAN)


def test_ramp_closed_forms(ph):
    # trapezoid 20 -> 80 mm/s at 300 mm/s^2: 0.2 s, 10 mm; sine at peak 300: pi/2 longer
    assert ph.ramp(20.0, 80.0, 300.0, 1) == pytest.approx((0.2, 10.0), rel=1e-14)
    assert ph.ramp(20.0, 80.0, 300.0, 2) == pytest.approx((0.1 * math.pi, 5.0 * math.pi), rel=1e-14)
    # sine: speed halfway is the mean, the distance there v0 t + dv/2 (t - T/pi)
    T = 0.1 * math.pi
    v, s = ph.ramp(20.0, 80.0, 300.0, 2, T / 2)
    assert v == pytest.approx(50.0, rel=1e-14)
    assert s == pytest.approx(20.0 * T / 2 + 30.0 * (T / 2 - T / math.pi), rel=1e-14)
    # numeric integral of the sampled speed equals the closed-form distance
    n = 20000
    xs = [ph.ramp(20.0, 80.0, 300.0, 2, T * (k + 0.5) / n)[0] for k in range(n)]
    assert sum(xs) * T / n == pytest.approx(5.0 * math.pi, rel=1e-8)


@pytest.mark.parametrize("ramp", [1, 2])
def test_the_machine_runs_each_planned_part_in_its_planned_time(ph, ramp):
    """The profile of each planned part as the offline machine samples it
    (profile.pyx profile_plan capped by the plan's peak and exit, profile_at) reaches
    the plan's peak, lasts the plan's time, and its sampled speed integrates
    (midpoint rule) to the part's length."""
    text = corner(50.0) + "G1 X300 Y150\nG1 X300.5 Y150\nG1 X301 Y150.3\n"
    parts = plan(ph, text, startAngle=20.0, endAngle=120.0, minAngleFeed=900.0,
                 motion=[None, (6000.0, 400.0, 700.0, ramp)])
    for p in parts:
        duration, peak, _ = ph.profile(p["length"], p["v_in"], p["v_peak"], p["v_out"], 400.0, 700.0, ramp, [])
        assert peak == pytest.approx(p["v_peak"], rel=PLAN)
        assert duration == pytest.approx(p["time"], rel=1e-7)
        n = 20000
        _, _, speeds = ph.profile(p["length"], p["v_in"], p["v_peak"], p["v_out"], 400.0, 700.0, ramp,
                                  [duration * (k + 0.5) / n for k in range(n)])
        assert sum(speeds) * duration / n == pytest.approx(p["length"], rel=1e-6)


# ------------------------------------------------------------------ static limits

def test_arc_feed_table_values(ph):
    """arcFeedTable as the vendor's manual describes it (0 = the table is off)."""
    table = [(10.0, 0.6), (2.0, 0.2), (50.0, 0.9)]   # any order
    assert ph.arc_factor(table, 1.0) == pytest.approx(0.2)       # below the smallest radius: its feed
    assert ph.arc_factor(table, 2.0) == pytest.approx(0.2)
    assert ph.arc_factor(table, 5.0) == pytest.approx(0.2 + 0.4 * 3 / 8)
    assert ph.arc_factor(table, 30.0) == pytest.approx(0.6 + 0.3 * 20 / 40)
    assert ph.arc_factor(table, 50.0) == pytest.approx(0.9)      # at and above the largest: its feed
    assert ph.arc_factor(table, 500.0) == pytest.approx(0.9)
    assert ph.arc_factor(table, 5.0, 0) == 0.0                   # G900 S13 A0
    assert ph.arc_factor([], 5.0) == 0.0                         # all zero: not used
    # "[0] = (0, 0.5): every arc at 50 %"
    for r in (1e-3, 1.0, 20.0, 1e6):
        assert ph.arc_factor([(0.0, 0.5)], r) == 0.5
    # "(10, 1.25), (0.9, 0.1): radius >= 10 at 125 %, smaller ones down to 10 % at
    # R0.9, every arc below R0.9 at 10 %"
    vendor = [(10.0, 1.25), (0.9, 0.1)]
    for r, expected in ((20.0, 1.25), (10.0, 1.25), (0.9, 0.1), (0.5, 0.1), (5.45, 0.1 + 1.15 * 0.5)):
        assert ph.arc_factor(vendor, r) == pytest.approx(expected, rel=1e-12)
    # a radius of 0 is the table's last entry: it counts when its feed is not 0
    assert ph.arc_factor([(4.0, 0.5), (0.0, 0.1), (8.0, 0.9)], 6.0) == 0.5
    assert ph.arc_factor([(4.0, 0.5), (0.0, 0.1), (8.0, 0.9)], 2.0) == pytest.approx(0.3)
    assert ph.arc_factor([(4.0, 0.5), (0.0, 0.0), (8.0, 0.9)], 2.0) == 0.5
    assert ph.arc_factor([(-1.0, 0.5), (4.0, 0.7)], 2.0) == 0.0  # a negative radius ends it empty


def test_arc_feed_table_in_the_plan(ph):
    table = [(2.0, 0.2), (10.0, 0.6)]
    text = "G0 X5\nG3 X5 Y0 I-5 J0 F600\n"
    (p,) = plan(ph, text, arc=table)[1:]
    assert p["v_peak"] == pytest.approx(10.0 * 0.35, rel=PLAN)
    (p,) = plan(ph, "G900 S13 A0\n" + text, arc=table)[1:]
    assert p["v_peak"] == pytest.approx(10.0, rel=PLAN)
    (p,) = plan(ph, "G900 S13 A0\nG900 S13 A1\n" + text, arc=table)[1:]
    assert p["v_peak"] == pytest.approx(3.5, rel=PLAN)


@pytest.mark.parametrize("table, rel", [([(0.0, 0.5)], 0.5), ([(10.0, 1.25), (0.9, 0.1)], 1.25),
                                        ([], 1.0)], ids=["all_arcs_50", "r10_and_up_125", "off"])
def test_the_vendors_arc_feed_table_examples_on_a_full_circle(ph, table, rel):
    """G3 X0 Y0 I20 J0 F3000 from the origin: a full circle of radius 20 at 50 mm/s
    times the table's relative feed, 500 mm/s^2 up and down: 2 pi 20 / v + v / 500
    (5.077 s at 50 %, 2.136 s at 125 %)."""
    (p,) = plan(ph, "G3 X0 Y0 I20 J0 F3000\n", arc=table)
    v = 50.0 * rel
    assert p["v_peak"] == pytest.approx(v, rel=PLAN)
    assert p["time"] == pytest.approx(2 * math.pi * 20.0 / v + v / 500.0, rel=PLAN)


def test_centripetal_limit_on_a_circle(ph):
    (p,) = plan(ph, "G0 X10\nG3 X10 Y0 I-10 J0 F6000\n", rezerva1=abi.GCODE_REZERVA1_APPLY_UNIMPLEMENTED, centripetalAcc=100.0)[1:]
    assert p["v_peak"] == pytest.approx(math.sqrt(100.0 * 10.0), rel=PLAN)
    # a helix: curvature r / (r^2 + h^2) with h the rise per radian
    (p,) = plan(ph, "G0 X10\nG3 X10 Y0 Z20 I-10 J0 F6000\n", rezerva1=abi.GCODE_REZERVA1_APPLY_UNIMPLEMENTED, centripetalAcc=100.0)[1:]
    h = 20.0 / (2 * math.pi)
    assert p["v_peak"] == pytest.approx(math.sqrt(100.0 * (100.0 + h * h) / 10.0), rel=PLAN)


def test_axis_limits_on_a_line_at_30_degrees(ph):
    c, s = math.cos(math.radians(30)), math.sin(math.radians(30))
    text = f"G1 X{100 * c:.12f} Y{100 * s:.12f} F6000\n"
    (p,) = plan(ph, text, axis=[(0, 3000.0, 200.0, 100.0)])
    v, a, d = 50.0 / c, 200.0 / c, 100.0 / c
    assert p["v_peak"] == pytest.approx(v, rel=PLAN)
    assert p["time"] == pytest.approx(100.0 / v + v / (2 * a) + v / (2 * d), rel=PLAN)
    # Y limited harder than X: Y decides
    (p,) = plan(ph, text, axis=[(0, 3000.0, 0.0, 0.0), (1, 1200.0, 0.0, 0.0)])
    assert p["v_peak"] == pytest.approx(20.0 / s, rel=PLAN)
    # M-5 X0 switches the X limits off; G900 S7 sets them from the program
    (p,) = plan(ph, "M-5 X0\n" + text, axis=[(0, 3000.0, 200.0, 100.0)])
    assert p["v_peak"] == pytest.approx(100.0, rel=PLAN)
    (p,) = plan(ph, "G900 S7 A0 F3000\n" + text)
    assert p["v_peak"] == pytest.approx(50.0 / c, rel=PLAN)


def test_axis_limits_over_the_whole_arc(ph):
    # circle: X takes the whole speed somewhere -> v <= maxFeed_X
    (p,) = plan(ph, "G0 X10\nG3 X10 Y0 I-10 J0 F6000\n", axis=[(0, 3000.0, 0.0, 0.0)])[1:]
    assert p["v_peak"] == pytest.approx(50.0, rel=PLAN)
    # CCW from 0 to 60 degrees: |t_x| = |sin| is at most sin 60 at the end
    e = (10 * math.cos(math.radians(60)), 10 * math.sin(math.radians(60)))
    text = f"G0 X10\nG3 X{e[0]:.12f} Y{e[1]:.12f} I-10 J0 F6000\n"
    (p,) = plan(ph, text, axis=[(0, 3000.0, 0.0, 0.0)])[1:]
    assert p["v_peak"] == pytest.approx(50.0 / math.sin(math.radians(60)), rel=PLAN)
    # Y: |cos| is 1 at the start
    (p,) = plan(ph, text, axis=[(1, 3000.0, 0.0, 0.0)])[1:]
    assert p["v_peak"] == pytest.approx(50.0, rel=PLAN)


def test_limits_on_arcs_in_other_planes(ph):
    # a full circle in XZ (G18) and in YZ (G19): Z takes the whole speed somewhere
    (p,) = plan(ph, "G18\nG0 X10\nG3 X10 Z0 I-10 K0 F6000\n", axis=[(2, 3000.0, 0.0, 0.0)])[1:]
    assert p["v_peak"] == pytest.approx(50.0, rel=PLAN)
    assert p["length"] == pytest.approx(20 * math.pi, rel=1e-12)
    (p,) = plan(ph, "G19\nG0 Y10\nG2 Y10 Z0 J-10 K0 F6000\n", axis=[(2, 3000.0, 0.0, 0.0)],
                rezerva1=abi.GCODE_REZERVA1_APPLY_UNIMPLEMENTED, centripetalAcc=160.0)[1:]
    assert p["v_peak"] == pytest.approx(40.0, rel=PLAN)     # sqrt(160 * 10) below the axis's 50


def test_axes_ignored_for_the_feed(ph):
    # G1 X30 A40 F600: the feed holds on X alone (A ignored), the path runs 5/3 faster
    text = "G1 X30 A40 F600\n"
    assert plan(ph, text)[0]["v_peak"] == pytest.approx(10.0, rel=PLAN)
    assert plan(ph, text, enhanced=1 << (10 + 8))[0]["v_peak"] == pytest.approx(10.0 * 50 / 30, rel=PLAN)
    assert plan(ph, "G900 S11 A1\n" + text)[0]["v_peak"] == pytest.approx(10.0 * 50 / 30, rel=PLAN)


def test_feeds_by_force_mode_rev_and_rapids(ph):
    assert plan(ph, "G95 S100\nG1 X100 F0.5\n")[0]["v_peak"] == pytest.approx(50.0 / 60.0, rel=PLAN)
    assert plan(ph, "G1 X100 F600 FP0.5\n")[0]["v_peak"] == pytest.approx(5.0, rel=1e-6)
    assert plan(ph, "G1 X100 F600\n", forceMode=1)[0]["v_peak"] == pytest.approx(1000.0 / 60, rel=PLAN)
    assert plan(ph, "G0 X1000\n")[0]["v_peak"] == pytest.approx(10000.0 / 60, rel=PLAN)
    assert plan(ph, "G900 S20 F3000\nG0 X1000\n")[0]["v_peak"] == pytest.approx(50.0, rel=PLAN)
    assert plan(ph, "M99 F1200\nG1 X100 F0\n")[0]["v_peak"] == pytest.approx(20.0, rel=PLAN)
    # a thread: pitch 2 mm at S300 = 600 mm/min, whatever F and FP say
    assert plan(ph, "S300 F5000 FP0.5\nG33 Z-100 K2\n")[0]["v_peak"] == pytest.approx(10.0, rel=PLAN)


def test_constant_cutting_speed_g96(ph):
    # facing from X40 to X10 at S200 m/min, F0.1 mm/rev: the spindle at r = 10 mm turns
    # 1000 * 200 / (2 pi 10) rev/min, the feed is 0.1 mm per turn of it
    n = 1000.0 * 200.0 / (2.0 * math.pi * 10.0)
    parts = plan(ph, "G0 X40\nG95 G96 S200\nG1 X10 F0.1\nG1 X0.5\nG97\nG1 X40\n")
    moves = [p for p in parts if p["kind"] == 1][1:]
    assert moves[0]["v_peak"] == pytest.approx(0.1 * n / 60.0, rel=PLAN)
    # through the axis: r is held at 1 mm
    assert moves[1]["v_peak"] == pytest.approx(0.1 * 1000.0 * 200.0 / (2.0 * math.pi) / 60.0, rel=PLAN)
    # G97: S is the spindle speed again (200 rev/min)
    assert moves[2]["v_peak"] == pytest.approx(0.1 * 200.0 / 60.0, rel=PLAN)
    # G96 with a feed per minute changes nothing
    assert plan(ph, "G0 X40\nG94 G96 S200\nG1 X10 F600\n")[-1]["v_peak"] == pytest.approx(10.0, rel=PLAN)


def test_settings_from_the_program_apply_from_their_part_on(ph):
    # acceleration of the forward class changed between the two lines: G4 stops between
    parts = plan(ph, "G1 X100 F6000\nG4 X0\nG900 S30 C100 D100\nG1 X200\n")
    assert parts[0]["time"] == pytest.approx(1.2, rel=PLAN)
    assert parts[2]["time"] == pytest.approx(1.0 + 0.5 + 0.5, rel=PLAN)
    # G900 S1 / S2: push and pop
    parts = plan(ph, "G900 S1\nG900 S30 C100 D100\nG1 X100 F6000\nG900 S2\nG4 X0\nG1 X200\n")
    assert [p["time"] for p in parts if p["kind"] == 1] == pytest.approx([2.0, 1.2], rel=PLAN)


def test_a_setting_repeated_in_a_loop_makes_one_region(ph):
    loop = "FOR P1 = 1 TO 500\nG900 S9 A30 B90 F600\nG1 X P1 F6000\nEND\n"
    summary, error, _ = ph.plan_text(loop, params(ph), 0, 0, False)
    assert error is None and summary["regions"] == 1 and summary["n_parts"] == 500
    toggling = "FOR P1 = 1 TO 50\nG900 S13 A0\nG1 X P1 F6000\nG900 S13 A1\nG1 Y P1\nEND\n"
    summary, error, _ = ph.plan_text(toggling, params(ph), 0, 0, False)
    assert error is None and summary["regions"] == 100


# ------------------------------------------------------------------ junctions

def corner(angle_deg):
    """Two 100 mm lines turning by angle_deg at (100, 0)."""
    t = math.radians(angle_deg)
    return f"G1 X100 F6000\nG1 X{100 + 100 * math.cos(t):.12f} Y{100 * math.sin(t):.12f}\n"


@pytest.mark.parametrize("angle", [0.0, 10.0, 30.0, 45.0, 60.0, 89.0, 90.0, 135.0, 180.0])
def test_junction_feed_table(ph, angle):
    parts = plan(ph, corner(angle), startAngle=30.0, endAngle=90.0, minAngleFeed=600.0)
    if angle <= 30.0:
        expected = 100.0
    elif angle >= 90.0:
        expected = 10.0
    else:
        expected = 100.0 + (10.0 - 100.0) * (angle - 30.0) / 60.0
    assert parts[0]["v_out"] == pytest.approx(expected, rel=PLAN)
    assert parts[1]["v_in"] == parts[0]["v_out"]


def test_angle_slow_down_off_by_default_and_from_the_program(ph):
    assert plan(ph, corner(90.0))[0]["v_out"] == pytest.approx(100.0)
    assert plan(ph, "G900 S9 A30 B90 F600\n" + corner(60.0))[0]["v_out"] == pytest.approx(55.0)
    # G900 S10: Y left out of the angle: the corner is a straight line for X (junction 0 deg)
    assert plan(ph, "G900 S9 A30 B90 F600\nG900 S10 Y1\n" + corner(60.0))[0]["v_out"] == pytest.approx(100.0)
    # enhancedInterpolatorParameters bit 1 (Y) the same
    parts = plan(ph, "G900 S9 A30 B90 F600\n" + corner(60.0), enhanced=0b10)
    assert parts[0]["v_out"] == pytest.approx(100.0)


def test_exact_stops(ph):
    lines = "G1 X100 F6000\n{}G1 X200\n"
    assert plan(ph, lines.format(""))[0]["v_out"] == pytest.approx(100.0)
    for stop in ("M50\n", "M0\n", "M1\n", "G4 X0.5\n"):
        parts = plan(ph, lines.format(stop))
        assert parts[0]["v_out"] == 0.0 and parts[1]["v_out"] == 0.0 and parts[2]["v_in"] == 0.0
    assert total(plan(ph, lines.format("G4 X0.5\n"))) == pytest.approx(2 * 1.2 + 0.5, rel=PLAN)
    # a continuous M function never stops the motion
    parts = plan(ph, "G1 X100 F6000\nG1 X200 M1005\n")
    assert [p["kind"] for p in parts] == [1, 2, 1]
    assert parts[0]["v_out"] == pytest.approx(100.0) and parts[1]["v_out"] == pytest.approx(100.0)
    assert total(parts) == pytest.approx(2.2, rel=PLAN)
    # the end of the program
    assert plan(ph, "G1 X100 F6000\n")[-1]["v_out"] == 0.0
    # consecutive rapids with disableG0FeedOverride; G900 S12 stop modes
    rapids = "G0 X100\nG0 X200\n"
    assert plan(ph, rapids)[0]["v_out"] > 0.0
    assert plan(ph, rapids, disableG0FeedOverride=1)[0]["v_out"] == 0.0
    assert plan(ph, "G900 S12 A1\n" + lines.format(""))[0]["v_out"] == 0.0
    assert plan(ph, "G900 S12 A2\n" + lines.format(""))[0]["v_out"] > 0.0
    assert plan(ph, "G900 S12 A2\nG0 X100\nG1 X200 F6000\n")[0]["v_out"] == 0.0


def rest_to_rest(length, v, a, d):
    """Seconds of a trapezoid from rest to rest over `length` at most at v."""
    if length >= v * v / (2 * a) + v * v / (2 * d):
        return length / v + v / (2 * a) + v / (2 * d)
    peak = math.sqrt(2 * length * a * d / (a + d))
    return peak / a + peak / d


# a tangential knife: C (axis 3, bit 3 of enhancedInterpolatorParameters bits 0-9)
# turns the blade in place between the XY cuts
KNIFE = "G1 X10 F6000\nG1 C90\nG1 Y10\nG1 C180\nG1 X0\n"
KNIFE_FOLLOWS = "G1 X10 C45 F6000\nG1 X20 C0\n"       # C turns back while X goes on
C_AXIS = 1 << 3
FROM_REST, REVERSAL = 1 << 20, 1 << 21


def test_an_axis_that_starts_from_rest_stops_the_others_first(ph):
    """MACHINE_PARAMETERS.enhancedInterpolatorParameters bit 20, in the structures'
    reference: when an axis chosen in bits 0-9 starts to move from rest, the other
    axes come to a stop before it does. The knife's C starts from rest twice (after
    the X cut, after the Y cut): the machine stands at both junctions, and the run is
    three trapezoids from rest to rest (10 mm; 90 + 10; 90 + 10); where C comes to
    rest and Y or X go on, nothing stops."""
    motion = [None, (6000.0, 500.0, 500.0, 1)]
    plain = plan(ph, KNIFE, motion=motion)
    assert total(plain) == pytest.approx(rest_to_rest(210.0, 100.0, 500.0, 500.0), rel=PLAN)
    parts = plan(ph, KNIFE, enhanced=C_AXIS | FROM_REST, motion=motion)
    assert [p["v_out"] for p in parts][:4] == [0.0, pytest.approx(100.0), 0.0, pytest.approx(100.0)]
    expected = rest_to_rest(10.0, 100.0, 500.0, 500.0) + 2 * rest_to_rest(100.0, 100.0, 500.0, 500.0)
    assert total(parts) == pytest.approx(expected, rel=PLAN)
    # bit 21 alone: C never reverses here; either bit without an axis in bits 0-9: nothing
    assert total(plan(ph, KNIFE, enhanced=C_AXIS | REVERSAL, motion=motion)) == total(plain)
    assert total(plan(ph, KNIFE, enhanced=FROM_REST | REVERSAL, motion=motion)) == total(plain)
    # the axis chosen by the program (G900 S10 C1) counts as one of bits 0-9
    assert total(plan(ph, "G900 S10 C1\n" + KNIFE, enhanced=FROM_REST, motion=motion)) == pytest.approx(
        expected, rel=PLAN)


def test_an_axis_that_reverses_stops_all_axes_first(ph):
    """enhancedInterpolatorParameters bit 21: when an axis chosen in bits 0-9 changes
    its direction of motion, every axis stops first. C follows the cut to 45 degrees
    and turns back while X goes on: with bit 21 the machine stands where C reverses
    (two trapezoids), with bit 20 alone (C does not start from rest) it does not."""
    motion = [None, (6000.0, 500.0, 500.0, 1)]
    one = math.hypot(10.0, 45.0)
    parts = plan(ph, KNIFE_FOLLOWS, enhanced=C_AXIS | REVERSAL, motion=motion)
    assert parts[0]["v_out"] == 0.0 and parts[1]["v_in"] == 0.0
    assert total(parts) == pytest.approx(2 * rest_to_rest(one, 100.0, 500.0, 500.0), rel=PLAN)
    for enhanced in (0, C_AXIS | FROM_REST, REVERSAL):
        assert total(plan(ph, KNIFE_FOLLOWS, enhanced=enhanced, motion=motion)) == pytest.approx(
            rest_to_rest(2 * one, 100.0, 500.0, 500.0), rel=PLAN)


# ------------------------------------------------------------------ mFuncInsertTable

def mfunc_table(ph, entries, text, window=0, **fields):
    p = abi.GCODE_PARAMETERS.from_buffer_copy(params(ph, **fields))
    p.MfuncInsertType = 1
    for k, (m, rel, dist) in enumerate(entries):
        p.mFuncInsertTable[k].mFunc, p.mFuncInsertTable[k].relFeed, p.mFuncInsertTable[k].distance = m, rel, dist
    parts, error, _ = ph.plan_text(text, bytes(p), window, 0)
    assert error is None, error
    return parts


def layout(parts):
    return [("M", p["func"]) if p["kind"] == 2 else ("G", p["func"], p["line"]) for p in parts]


def inserted_at(parts):
    """(M number, x, y) of every M function in the plan, in order, to 0.1 um (the
    plan keeps floats, and a speed counts as reached 1e-6 of it below)."""
    return [(p["func"], round(p["end"][0], 4), round(p["end"][1], 4)) for p in parts if p["kind"] == 2]


def test_mfunc_insert_table(ph):
    """A 90-degree corner slows to 10 mm/s (entry 0 at 50 % of F6000, its braking of
    500 mm/s^2 passes 50 mm/s (50^2 - 10^2) / 1000 = 2.4 mm before the corner), full
    speed again (entry 1 at 90 %: (90^2 - 10^2) / 1000 = 8 mm after it), the end
    (50 mm/s 2.5 mm before it). The part where one lies is split there: its first
    piece keeps the part's place, the rest follows the M function."""
    text = "G1 X10 F6000\nG1 X50\nG1 X100\nG1 X100 Y100\nG1 X100 Y200\n"
    slow = dict(startAngle=30.0, endAngle=90.0, minAngleFeed=600.0)
    table = [(1100, 0.5, 0.0), (1101, 0.9, 0.0), (1102, 1.0, 0.0)]
    parts = mfunc_table(ph, table, text, **slow)
    assert layout(parts) == [("G", 1, 1), ("G", 1, 2), ("G", 1, 3), ("M", 1100), ("G", 1, 3), ("G", 1, 4),
                             ("M", 1101), ("G", 1, 4), ("G", 1, 5), ("M", 1100), ("G", 1, 5)]
    assert inserted_at(parts) == [(1100, 97.6, 0.0), (1101, 100.0, 8.0), (1100, 100.0, 197.5)]
    pieces = [p for p in parts if p["line"] == 3]
    assert [p["flags"] & 2 for p in pieces] == [0, 2, 2]     # the programmed piece, the M, the rest
    assert [p["gcode_index"] for p in parts] == sorted(p["gcode_index"] for p in parts)
    # distance: 60 mm before 97.6 lies in line 2, 20 mm after Y8 in line 4
    parts = mfunc_table(ph, [(1100, 0.5, 60.0), (1101, 0.9, 20.0)], text, **slow)
    assert inserted_at(parts) == [(1100, 37.6, 0.0), (1101, 100.0, 28.0), (1100, 100.0, 137.5)]
    # entry 1 alone: its speed both ways
    parts = mfunc_table(ph, [(0, 0.0, 0.0), (1101, 0.9, 20.0)], text, **slow)
    assert inserted_at(parts) == [(1101, 100.0, 28.0)]
    # continuous: the motion is the plan's without them (the pieces plan as the part did)
    for window in (0, -1):
        plain = plan(ph, text, window=window, **slow)
        with_m = mfunc_table(ph, table, text, window=window, **slow)
        assert total(with_m) == pytest.approx(total(plain), rel=1e-7)
    # off unless MfuncInsertType = 1
    assert len(plan(ph, text, **slow)) == 5


def crossing(ph, v0, v1, acc, ramp, v):
    """Distance into the ramp v0 -> v1 where its speed is v (bisection on the harness's
    ramp closed form)."""
    T, _ = ph.ramp(v0, v1, acc, ramp)
    lo, hi = 0.0, T
    for _ in range(200):
        mid = (lo + hi) / 2
        if (ph.ramp(v0, v1, acc, ramp, mid)[0] - v) * (v1 - v0) < 0:
            lo = mid
        else:
            hi = mid
    return ph.ramp(v0, v1, acc, ramp, lo)[1]


# a line into an arc the arc feed table slows to 50 % (50 mm/s of F6000), a line out of it
INTO_ARC = "G1 X50 F6000\nG2 X70 Y0 I10 J0\nG1 X150\n"


@pytest.mark.parametrize("ramp", [1, 2])
def test_mfunc_before_a_slow_down_lies_distance_before_it(ph, ramp):
    """mFuncInsertTable[0], in the structures' reference: an M function that signals a
    coming slow-down (an arc) -- placed `distance` before the point where the speed
    falls below relFeed x the programmed feed. Braking from 100 to the arc's 50 mm/s
    with 500 mm/s^2 passes 60 mm/s 1.1 mm before the arc (X48.9, trapezoid; the sine
    ramp's point by bisection of its closed form); 5 mm before that: X43.9."""
    motion = [None, (6000.0, 500.0, 500.0, ramp)]
    parts = mfunc_table(ph, [(1100, 0.6, 5.0)], INTO_ARC, arc=[(0.0, 0.5)], motion=motion)
    before_arc = crossing(ph, 100.0, 50.0, 500.0, ramp, 60.0)
    ramp_length = crossing(ph, 100.0, 50.0, 500.0, ramp, 50.0)
    at = 50.0 - (ramp_length - before_arc) - 5.0
    if ramp == 1:
        assert at == pytest.approx(43.9, abs=1e-9)
    first = inserted_at(parts)[0]
    assert first[0] == 1100 and first[1] == pytest.approx(at, abs=1e-4) and first[2] == 0.0
    assert layout(parts)[:3] == [("G", 1, 1), ("M", 1100), ("G", 1, 1)]


def test_mfunc_after_a_slow_down_lies_distance_after_it(ph):
    """mFuncInsertTable[1]: an M function that signals full cutting speed ahead, placed
    `distance` after the point where the speed is back at relFeed x the feed. Out of
    the arc at 50 mm/s, 90 mm/s is (90^2 - 50^2) / 1000 = 5.6 mm on (X75.6); 10 mm
    after that: X85.6."""
    parts = mfunc_table(ph, [(1100, 0.6, 0.0), (1101, 0.9, 10.0)], INTO_ARC, arc=[(0.0, 0.5)],
                        motion=[None, (6000.0, 500.0, 500.0, 1)])
    assert inserted_at(parts)[:2] == [(1100, 48.9, 0.0), (1101, 85.6, 0.0)]
    assert layout(parts)[:7] == [("G", 1, 1), ("M", 1100), ("G", 1, 1), ("G", 2, 2), ("G", 1, 3), ("M", 1101),
                                 ("G", 1, 3)]


def test_mfunc_before_a_rapid_lies_distance_before_it(ph):
    """mFuncInsertTable[2]: an M function `distance` before a G00 rapid that follows a
    cut (relFeed plays no part): 30 mm before X100 is X70; 95 mm before it lies in the
    first line, at X5; at the program's start (150 mm) it comes first of all."""
    text = "G1 X10 F6000\nG1 X100\nG0 X200\nG0 X300\n"
    for distance, expected in ((0.0, 100.0), (30.0, 70.0), (95.0, 5.0)):
        parts = mfunc_table(ph, [(0, 0, 0), (0, 0, 0), (1102, 1.0, distance)], text)
        assert inserted_at(parts) == [(1102, expected, 0.0)]
    parts = mfunc_table(ph, [(0, 0, 0), (0, 0, 0), (1102, 1.0, 0.0)], text)
    assert layout(parts) == [("G", 1, 1), ("G", 1, 2), ("M", 1102), ("G", 0, 3), ("G", 0, 4)]
    parts = mfunc_table(ph, [(0, 0, 0), (0, 0, 0), (1102, 1.0, 150.0)], text)
    assert layout(parts)[:2] == [("M", 1102), ("G", 1, 1)]
    assert inserted_at(parts) == [(1102, 0.0, 0.0)]
    assert total(parts) == pytest.approx(total(plan(ph, text)), rel=1e-7)


# ------------------------------------------------------------------ look-ahead window

def dense_line(n, step):
    return "G1 X0 F6000\n" + "".join(f"G1 X{step * (k + 1):.6f}\n" for k in range(n))


def test_window_on_dense_collinear_segments(ph):
    text = dense_line(1000, 0.1)            # 100 mm in 0.1 mm pieces
    unlimited = total(plan(ph, text, window=-1))
    assert unlimited == pytest.approx(1.2, rel=PLAN)         # the single line's trapezoid
    times = [total(plan(ph, text, window=w)) for w in (1, 2, 8, 32, 200)]
    assert times == sorted(times, reverse=True)
    # window 8 (the vendor's): stops within 8 parts = 0.8 mm ahead: v <= sqrt(2 * 500 * 0.7..0.8)
    assert times[2] > 3.0
    assert times[4] == pytest.approx(1.2, rel=PLAN)          # 20 mm ahead: enough to brake from 100 mm/s
    # window 1: every part starts and ends at rest: 1000 triangles of 0.1 mm
    peak = math.sqrt(0.1 * 500.0)
    assert times[0] == pytest.approx(1000 * 2 * peak / 500.0, rel=PLAN)


@pytest.mark.parametrize("window", [0, 3, 20])
def test_continuous_m_functions_take_no_window_slot(ph, window):
    """The window counts motion parts (the vendor's sections: G0-G3, M3-M999):
    continuous M functions ride inside a section, so a line of them runs as fast as
    the same line without them."""
    plain = plan(ph, dense_line(200, 0.5), window=window)
    with_m = plan(ph, "G1 X0 F6000\n" + "".join(f"G1 X{0.5 * (k + 1):.6f} M1001\n" for k in range(200)),
                  window=window)
    assert len(with_m) == 2 * len(plain) - 1
    assert total(with_m) == pytest.approx(total(plain), rel=1e-12)
    assert [p["v_out"] for p in with_m if p["kind"] == 1] == [p["v_out"] for p in plain]


# ------------------------------------------------------------------ ruckig oracle

def ruckig_time(length, v0, v1, vmax, acc, dec, jerk):
    """Time-optimal 1-D move over `length` from v0 to v1 (ruckig, the test extra)."""
    ruckig = pytest.importorskip("ruckig")
    inp = ruckig.InputParameter(1)
    inp.current_position = [0.0]
    inp.current_velocity = [v0]
    inp.current_acceleration = [0.0]
    inp.target_position = [length]
    inp.target_velocity = [v1]
    inp.target_acceleration = [0.0]
    inp.max_velocity = [vmax]
    inp.max_acceleration = [acc]
    inp.min_acceleration = [-dec]
    inp.max_jerk = [jerk]
    traj = ruckig.Trajectory(1)
    result = ruckig.Ruckig(1).calculate(inp, traj)
    assert result == ruckig.Result.Working
    return traj.duration


def test_trapezoid_parts_are_time_optimal(ph):
    # each part of a chain with boundary speeds: ruckig with (almost) no jerk limit
    text = corner(40.0) + "G1 X150 Y80\nG1 X152 Y80\nG1 X152 Y200\n"
    parts = plan(ph, text, startAngle=20.0, endAngle=90.0, minAngleFeed=300.0,
                 motion=[None, (6000.0, 500.0, 300.0, 1)])
    for p in parts:
        opt = ruckig_time(p["length"], p["v_in"], p["v_out"], 100.0 + 1e-9, 500.0, 300.0, 1e9)
        assert p["time"] == pytest.approx(opt, rel=2e-4)
        assert p["time"] >= opt * (1 - 1e-5)     # ruckig's finite jerk makes it a little slower


def test_sine_ramps_against_the_jerk_limited_optimum(ph):
    # rest to rest: the sine ramp's peak jerk is a*pi/T = 2 a^2 / v; ruckig with that jerk
    # is the time-optimal lower bound; the sine profile is close to it
    for length in (100.0, 10.0):
        (p,) = plan(ph, f"G1 X{length} F6000\n", motion=[None, (6000.0, 500.0, 500.0, 2)])
        jerk = 2 * 500.0 ** 2 / p["v_peak"]
        opt = ruckig_time(length, 0.0, 0.0, 100.0, 500.0, 500.0, jerk)
        assert opt <= p["time"] <= opt * 1.15


# ------------------------------------------------------------------ the simulation's run time

def test_run_time_of_a_simulation_comes_from_the_plan(ph, fresh_core):
    text = corner(60.0) + "M50\nG0 X0 Y0\nG1 X10 Y10 F3000\nG4 X0.25\nG2 X20 Y0 I0 J-10\n"
    expected = total(plan(ph, text, startAngle=30.0, endAngle=90.0, minAngleFeed=600.0))
    with Core(2) as core:
        saved = core.params
        try:
            core.update_params(absMode=1, calcTime=1, startAngle=30.0, endAngle=90.0, minAngleFeed=600.0)
            core.reset([0.0] * 10)
            core.compile_text(text, "plan.nc")
            core.simulate()
            assert core.run_time(core.file_index("plan.nc")) == pytest.approx(expected, rel=1e-12)
        finally:
            core.lib.ToolChainCore_DestroyCNC(2)
            core.params = saved


# ------------------------------------------------------------------ hostile settings

@pytest.mark.parametrize("head", [
    "G900 S7 A0 F-5 C-1 D-1\n",                 # negative axis limits: no limit
    "G900 S9 A120 B30 F-600\n",                 # end below start, negative feed: a stop at sharp corners
    "G900 S30 F0 C0 D0 R7\n",                   # no acceleration, an unknown ramp type: trapezoid
    "G900 S30 C1e-300 D1e-300\n",               # accelerations that barely move
    "G900 S30 C1e300 D1e300\nG900 S7 A1 F1e300\n",
    "G95 S0\n",                                 # per-revolution feed with the spindle stopped
])
def test_hostile_settings_plan_finite_times(ph, head):
    parts = plan(ph, head + "G1 X10 F6000 FP0\nG2 X20 Y0 I5 J0\nG1 X20 Y0.000000000001\nG3 I0 J0.5\nG1 X0\n",
                 centripetalAcc=-1.0, arc=[(5.0, -1.0)])
    for p in parts:
        assert math.isfinite(p["time"]) and p["time"] >= 0.0
        assert math.isfinite(p["v_peak"]) and p["v_peak"] >= 0.0 and p["v_out"] >= 0.0


def test_nan_settings_from_the_host_plan_finite_times(ph):
    nan = float("nan")
    parts = plan(ph, corner(70.0) + "G3 I5 J0\n", motion=[None, (nan, nan, nan, 2)],
                 axis=[(0, nan, nan, nan)], arc=[(nan, 0.5), (2.0, nan)], centripetalAcc=nan,
                 startAngle=nan, endAngle=nan, minAngleFeed=nan)
    for p in parts:
        assert math.isfinite(p["time"]) and p["time"] >= 0.0 and math.isfinite(p["v_peak"])


def test_simulation_with_machine_bits_and_inserted_m_functions(ph, fresh_core):
    """Through the library: enhancedInterpolatorParameters from SetMachineParameters
    reach the planner, and the inserted M functions reach the driver's M callback."""
    text = "G1 X30 A40 F600\nG1 X60\nG0 X100\n"
    expected = total(plan(ph, text, enhanced=1 << 18))
    assert expected < total(plan(ph, text))
    with Core(2) as core:
        saved = core.params
        machine = abi.MACHINE_PARAMETERS()
        core.lib.ToolChainCore_GetMachineParameters(2, ctypes.byref(machine))
        saved_machine = abi.MACHINE_PARAMETERS.from_buffer_copy(machine)
        try:
            machine.enhancedInterpolatorParameters = 1 << 18
            assert core.lib.ToolChainCore_SetMachineParameters(2, ctypes.byref(machine)) == 0
            p = core.params
            p.absMode, p.calcTime, p.MfuncInsertType = 1, 1, 1
            p.mFuncInsertTable[2].mFunc, p.mFuncInsertTable[2].relFeed = 1102, 1.0
            core.params = p
            core.reset([0.0] * 10)
            core.compile_text(text, "bits.nc")
            run = core.simulate()
            assert [int(m["m_func"]) % 10000 for m in run.m_functions] == [1102]
            assert core.run_time(core.file_index("bits.nc")) == pytest.approx(expected, rel=1e-12)
        finally:
            core.lib.ToolChainCore_SetMachineParameters(2, ctypes.byref(saved_machine))
            core.lib.ToolChainCore_DestroyCNC(2)
            core.params = saved


def test_look_ahead_through_the_library(ph, tmp_path, fresh_core):
    """The window reaches the planner by ToolChainCore_SetLookAhead, the INI key
    lookAheadParts and sf_tch.compile(look_ahead=): each gives the harness's time for
    that window (the vendor's 8 by default). The dense line's parts as written
    (tolerance[2] = 0: collinear, they would be one part)."""
    import sf_tch
    text = dense_line(1000, 0.1)
    expected = {w: total(plan(ph, text, window=w)) for w in (0, 8, 32, -1)}
    assert expected[0] == expected[8] > expected[32] > expected[-1]

    def simulated(program):
        program.simulate()
        return program.run_time

    with sf_tch.compile(text, look_ahead=32, core=2, params=AS_WRITTEN) as program:
        assert simulated(program) == pytest.approx(expected[32], rel=1e-12)
    with sf_tch.compile(text, core=2, params=AS_WRITTEN) as program:       # the core keeps what was set
        assert simulated(program) == pytest.approx(expected[32], rel=1e-12)
    lib = fresh_core
    assert lib.ToolChainCore_SetLookAhead(2, -2) == -1
    assert lib.ToolChainCore_SetLookAhead(2, -1) == 0
    with sf_tch.compile(text, core=2, params=AS_WRITTEN) as program:
        assert simulated(program) == pytest.approx(expected[-1], rel=1e-12)
    ini = tmp_path / "window.ini"
    ini.write_text(Path(sf_tch.default_ini()).read_text()
                   + "\n[GCodeParameters]\nlookAheadParts = 0\n")
    with sf_tch.compile(text, ini=ini, core=2, params=AS_WRITTEN) as program:
        assert simulated(program) == pytest.approx(expected[0], rel=1e-12)
    ini.write_text("[GCodeParameters]\nlookAheadParts = -5\n")
    assert lib.ToolChainCore_LoadFromIni(2, str(ini).encode(), None) == abi.TOOL_CHAIN_XEXEC
    with pytest.raises(ValueError):
        sf_tch.compile(text, look_ahead=-3, core=2)
