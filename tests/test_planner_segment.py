"""The shared segment geometry (toolchain/geometry.pyx): a part's length and the
point at a path length on lines, arcs, full circles and helices against the circle's
parametric form; the point on an arc is the one the compensation's regions use."""
import math

import pytest

from test_planner import harness_module


@pytest.mark.parametrize("code, centre, radius, a0, turn, z0, dz", [
    ("G1 X10 Y0 F1000\nG3 X0 Y10 I-10 J0\n", (0, 0), 10.0, 0.0, math.pi / 2, 0.0, 0.0),
    ("G1 X10 Y0 F1000\nG2 X0 Y-10 I-10 J0\n", (0, 0), 10.0, 0.0, -math.pi / 2, 0.0, 0.0),
    ("G1 X5 Y2 F1000\nG3 X5 Y2 I-3 J0\n", (2, 2), 3.0, 0.0, 2 * math.pi, 0.0, 0.0),          # full circle
    ("G1 X4 Y0 Z1 F1000\nG2 X-4 Y0 Z-2 I-4 J0\n", (0, 0), 4.0, 0.0, -math.pi, 1.0, -3.0),   # helix
])
def test_point_at_a_path_length_on_arcs(code, centre, radius, a0, turn, z0, dz):
    """segment_point_at (arc_point_at, shared with the compensation's regions): the point
    at path length s of an arc or a helix against the circle's parametric form."""
    ph = harness_module()
    length = abs(turn) * math.hypot(radius, dz / abs(turn))
    fractions = [0.0, 0.1, 0.25, 0.5, 0.77, 1.0]
    got_length, points = ph.segment_points(code, 1, [f * length for f in fractions])
    assert got_length == pytest.approx(length, rel=1e-12)
    for f, p in zip(fractions, points):
        a = a0 + f * turn
        expected = (centre[0] + radius * math.cos(a), centre[1] + radius * math.sin(a), z0 + f * dz)
        assert p[:3] == pytest.approx(expected, abs=1e-9)


def test_point_at_a_path_length_on_a_line_and_beyond_the_ends():
    ph = harness_module()
    length, points = ph.segment_points("G1 X1 Y2 Z3 F1000\nG1 X4 Y6 Z3\n", 1, [-1.0, 0.0, 2.5, 5.0, 9.0])
    assert length == 5.0
    assert points == [[1, 2, 3], [1, 2, 3], [2.5, 4.0, 3.0], [4, 6, 3], [4, 6, 3]]
