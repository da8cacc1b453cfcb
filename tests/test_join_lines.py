"""The finished path's tolerances (toolchain/compensation/join_lines.pyx), as the
structures' reference gives them: tolerance[2], the angle of two parts below which
they are joined (0.03 degrees by default); tolerance[3], how far the joined G1 may
pass from the G1 parts it replaces (0.005 mm by default); tolerance[4], the smallest
arc radius, smaller arcs are removed. Through tests/harness (compile, G167 arcs, the
joins, the plan) and through the library (the driver callbacks)."""
import math

import pytest

from sf_tch import abi
from sf_tch.core import Core
from test_planner import plan as plan_as_written

VENDOR = (0.005, 0.001, 0.03, 0.005, 0.0, 3.0, 0.01, 0.0, 0.0, 0.0)


def tolerances(**at):
    values = list(VENDOR)
    for k, v in at.items():
        values[int(k[1:])] = v
    return tuple(values)


def plan(ph, text, **fields):
    """test_planner's plan with the vendor's tolerances unless given."""
    fields.setdefault("tolerance", VENDOR)
    return plan_as_written(ph, text, **fields)


@pytest.fixture(scope="module")
def ph(harness):
    return harness


def motions(parts):
    return [(p["func"], p["line"], tuple(round(c, 9) for c in p["end"][:2])) for p in parts if p["kind"] == 1]


def turned(angle_deg, length=10.0):
    """X0 -> X10 -> on by `length` mm turned by angle_deg (F6000)."""
    t = math.radians(angle_deg)
    return f"G1 X10 F6000\nG1 X{10 + length * math.cos(t):.12f} Y{length * math.sin(t):.12f}\n"


def test_collinear_g1_parts_are_one_by_default(ph):
    """Three collinear G1 parts are one G1 (the defaults are the vendor's): the last
    line's part, from where the first began; with tolerance[2] = 0 each stays."""
    text = "G1 X10 F6000\nG1 X20\nG1 X30\n"
    parts = plan(ph, text)
    assert motions(parts) == [(1, 3, (30.0, 0.0))]
    assert parts[0]["length"] == pytest.approx(30.0, abs=1e-12)
    assert parts[0]["time"] == pytest.approx(30.0 / 100.0 + 0.2, rel=2e-7)   # one trapezoid
    assert motions(plan(ph, text, tolerance=tolerances(t2=0.0))) == [(1, 1, (10.0, 0.0)), (1, 2, (20.0, 0.0)),
                                                                     (1, 3, (30.0, 0.0))]


@pytest.mark.parametrize("angle, joined", [(0.02, True), (0.029, True), (0.031, False), (0.5, False)])
def test_the_angle_below_tolerance_2_joins(ph, angle, joined):
    """Two 10 mm parts turning by `angle`: below 0.03 degrees they are one (the corner
    lies 10 sin(angle / 2), at most 0.0026 mm, off the joined line: within tolerance[3])."""
    assert len(motions(plan(ph, turned(angle)))) == (1 if joined else 2)


def test_the_deviation_tolerance_3_limits_a_join(ph):
    """0.02 degrees between two 100 mm parts: the corner lies 100 sin(0.01 deg) =
    0.0175 mm off the joined line, more than 0.005 mm: two parts; with tolerance[3]
    0.02 one."""
    assert 100 * math.sin(math.radians(0.01)) == pytest.approx(0.01745, abs=1e-5)
    text = "G1 X100 F6000\nG1 X{:.12f} Y{:.12f}\n".format(100 + 100 * math.cos(math.radians(0.02)),
                                                        100 * math.sin(math.radians(0.02)))
    assert len(motions(plan(ph, text))) == 2
    assert len(motions(plan(ph, text, tolerance=tolerances(t3=0.02)))) == 1


def test_a_long_run_checks_every_point_it_leaves_out(ph):
    """A polyline bending by 0.02 degrees at every 10 mm vertex: each pair is below
    the angle, but the run stops before its chord passes a left-out vertex by more
    than 0.005 mm; every joined part stays within it."""
    x, y, heading, text = 0.0, 0.0, 0.0, "F6000\n"
    points = [(0.0, 0.0)]
    for _ in range(40):
        heading += math.radians(0.02)
        x, y = x + 10 * math.cos(heading), y + 10 * math.sin(heading)
        points.append((x, y))
        text += f"G1 X{x:.12f} Y{y:.12f}\n"
    parts = motions(plan(ph, text))
    assert 1 < len(parts) < 40
    start = (0.0, 0.0)
    for _, line, end in parts:              # every vertex a part leaves out lies within 0.005 mm
        first = points.index(min(points, key=lambda p: math.dist(p, start)))
        for p in points[first + 1:line]:
            ax, ay, bx, by = *start, *end
            d = abs((bx - ax) * (ay - p[1]) - (ax - p[0]) * (by - ay)) / math.dist(start, end)
            assert d <= 0.005 + 1e-9
        start = end


def test_parts_that_differ_stay_apart(ph):
    """A feed change, a G900 planning region, an M function between, a rapid, an
    inserted part of the library: no join."""
    assert len(motions(plan(ph, "G1 X10 F6000\nG1 X20 F3000\n"))) == 2
    assert len(motions(plan(ph, "G1 X10 F6000\nG900 S9 A30 B90 F600\nG1 X20\n"))) == 2
    assert len(motions(plan(ph, "G1 X10 F6000\nM8\nG1 X20\n"))) == 2
    assert len(motions(plan(ph, "G0 X10\nG0 X20\n"))) == 2


def test_planning_regions_follow_the_joined_parts(ph):
    """A G900 after a joined run applies from the same programmed line on: the run
    before it is one part, the angle slow-down of the region applies at its corner."""
    text = "G1 X10 F6000\nG1 X20\nG900 S9 A30 B90 F600\nG1 X30\nG1 X30 Y10\n"
    parts = plan(ph, text)
    assert motions(parts) == [(1, 2, (20.0, 0.0)), (1, 4, (30.0, 0.0)), (1, 5, (30.0, 10.0))]
    corner = [p for p in parts if p["kind"] == 1][1]
    assert corner["v_out"] == pytest.approx(10.0, rel=1e-6)     # 90 degrees: minAngleFeed 600


def test_arcs_below_tolerance_4_become_lines(ph):
    """tolerance[4], the smallest arc radius: a programmed arc of R0.5 with tolerance[4]
    1 mm becomes a G1 to its end point; R2 stays an arc; 0 (the default) removes none."""
    text = "G1 X10 F6000\nG2 X11 Y0 I0.5 J0\nG1 X20 Y5\nG3 X24 Y5 I2 J0\n"
    assert [f for f, _, _ in motions(plan(ph, text))] == [1, 2, 1, 3]
    parts = motions(plan(ph, text, tolerance=tolerances(t4=1.0)))
    assert parts == [(1, 2, (11.0, 0.0)), (1, 3, (20.0, 5.0)), (3, 4, (24.0, 5.0))]   # X10 -> X11 joined too


def test_the_driver_reports_the_joined_part_by_its_line(fresh_core):
    """Through the library: DriverGFunc sees the run's last line once, with its own
    end; GetGCodeRunTime is one trapezoid over the 40 mm (no angle slow-down by default)."""
    with Core(2) as core:
        saved = core.params
        try:
            core.update_params(absMode=1, calcTime=1)
            core.reset([0.0] * 10)
            core.compile_text("G1 X10 F6000\nG1 X20\nG1 X30\nG1 X30 Y10\n", "join.nc")
            run = core.simulate()
            assert [int(p["m_editorLine"]) for p in run.parts] == [3, 4]
            assert float(run.parts[0]["m_e"]["x"]) == 30.0
            assert core.run_time(core.file_index("join.nc")) == pytest.approx(0.4 + 0.2, rel=1e-6)
        finally:
            core.lib.ToolChainCore_DestroyCNC(2)
            core.params = saved
