"""The geometry module (toolchain/geometry.pyx) alone, through tests/harness: a Segment's
sweep, length, point and tangent at a path length, curvature and the axes' share of
the speed against the closed forms of a line and a helix (a plane arc: lead 0) in
every plane (17, 18, 19, -18); its box against dense sampling; its nearest point
against brute force; the plane's 2-D primitives against their definitions."""
import math

import numpy as np
import pytest

import harness

AXES = 10
PLANES = {17: (0, 1), 18: (0, 2), 19: (1, 2), -18: (2, 0)}


@pytest.fixture(scope="module")
def geo():
    return harness.load()


def cross(a, b):
    return a[0] * b[1] - a[1] * b[0]


class Helix:
    """The closed form of an arc round `centre` in `plane`, radius r, from polar angle
    a0 turning `turn` radians (+ counter-clockwise from the plane's first axis to its
    second), the other axes moving by `rise` (ten values, 0 on the plane's axes)."""

    def __init__(self, plane, centre, r, a0, turn, base, rise):
        self.plane, self.r, self.a0, self.turn = plane, r, a0, turn
        self.first, self.second = PLANES[plane]
        self.centre = np.array(centre, float)
        self.base = np.array(base, float)
        self.rise = np.array(rise, float)
        self.rise[[self.first, self.second]] = 0.0
        self.length = math.hypot(r * turn, np.linalg.norm(self.rise))

    def at(self, u):
        """Points at the fractions u (array) of the way."""
        u = np.atleast_1d(np.asarray(u, float))
        out = self.base[None, :] + u[:, None] * self.rise[None, :]
        theta = self.a0 + u * self.turn
        out[:, self.first] = self.centre[self.first] + self.r * np.cos(theta)
        out[:, self.second] = self.centre[self.second] + self.r * np.sin(theta)
        return out

    def tangents(self, u):
        """Unit tangents at the fractions u (array)."""
        u = np.atleast_1d(np.asarray(u, float))
        theta = self.a0 + u * self.turn
        d = np.repeat(self.rise[None, :], len(u), axis=0)
        d[:, self.first] = -self.r * self.turn * np.sin(theta)
        d[:, self.second] = self.r * self.turn * np.cos(theta)
        return d / self.length

    def segment(self, geo, full=False):
        start, end = self.at([0.0, 1.0])
        if full:
            end[[self.first, self.second]] = start[[self.first, self.second]]
        return geo.Seg(start, end, self.plane, self.centre[:3], self.r, self.turn > 0)


def random_helix(rng, plane, turn=None, helical=True):
    centre = np.zeros(AXES)
    centre[:3] = rng.uniform(-50, 50, 3)
    r = rng.uniform(0.5, 30)
    a0 = rng.uniform(-math.pi, math.pi)
    if turn is None:
        turn = rng.uniform(0.05, 2 * math.pi - 0.05) * rng.choice([-1, 1])
    base = rng.uniform(-20, 20, AXES)
    rise = rng.uniform(-15, 15, AXES) if helical else np.zeros(AXES)
    return Helix(plane, centre, r, a0, turn, base, rise)


# ---- sweep, length, point, tangent, curvature ---------------------------------------------

@pytest.mark.parametrize("plane", PLANES)
@pytest.mark.parametrize("helical", (False, True))
def test_arcs_and_helices_against_their_closed_form(geo, plane, helical):
    rng = np.random.default_rng(abs(plane) + 7 * helical)
    for _ in range(40):
        h = random_helix(rng, plane, helical=helical)
        g = h.segment(geo)
        assert g.arc and g.plane_axes == PLANES[plane]
        assert g.sweep == pytest.approx(h.turn, abs=1e-12)
        assert g.length == pytest.approx(h.length, rel=1e-12)
        assert g.lead == pytest.approx(np.linalg.norm(h.rise) / abs(h.turn), rel=1e-12, abs=1e-15)
        lead = np.linalg.norm(h.rise) / abs(h.turn)
        assert g.curvature() == pytest.approx(h.r / (h.r ** 2 + lead ** 2), rel=1e-12)
        for u in (0.0, 0.125, 0.5, 0.9, 1.0):
            assert g.point(u * h.length) == pytest.approx(h.at(u)[0], abs=1e-9)
            assert g.tangent(u * h.length) == pytest.approx(h.tangents(u)[0], abs=1e-9)


@pytest.mark.parametrize("plane", PLANES)
@pytest.mark.parametrize("turn", (2 * math.pi, -2 * math.pi))
def test_an_arc_whose_ends_meet_is_a_full_turn(geo, plane, turn):
    h = random_helix(np.random.default_rng(3), plane, turn=turn)
    g = h.segment(geo, full=True)
    assert g.sweep == pytest.approx(turn, abs=1e-12)
    assert g.length == pytest.approx(h.length, rel=1e-12)
    assert g.point(0.25 * h.length) == pytest.approx(h.at(0.25)[0], abs=1e-9)


def test_ends_that_meet_within_the_angle_tolerance(geo):
    """arc_sweep: an end ANGLE_EPS or less ahead of the start is a full turn, one
    farther ahead is the short arc it says."""
    eps = geo.tolerances()["ANGLE_EPS"]
    for ahead in (0.0, 0.5 * eps, 0.9 * eps):
        assert geo.arc_sweep_of(1.0, 0.0, math.cos(ahead), math.sin(ahead), True) == pytest.approx(2 * math.pi)
        assert geo.arc_sweep_of(1.0, 0.0, math.cos(-ahead), math.sin(-ahead), False) == pytest.approx(-2 * math.pi)
    for ahead in (4 * eps, 1e-9, 0.3):
        assert geo.arc_sweep_of(1.0, 0.0, math.cos(ahead), math.sin(ahead), True) == pytest.approx(ahead, rel=1e-6)
        assert geo.arc_sweep_of(1.0, 0.0, math.cos(ahead), -math.sin(ahead), False) == pytest.approx(-ahead, rel=1e-6)


def test_arc_sweep_against_the_angles_of_its_ends(geo):
    rng = np.random.default_rng(5)
    for _ in range(500):
        a, b = rng.uniform(-math.pi, math.pi, 2)
        rs, re = rng.uniform(0.1, 10, 2)
        ccw = bool(rng.integers(2))
        want = (b - a) % (2 * math.pi) if ccw else -((a - b) % (2 * math.pi))
        got = geo.arc_sweep_of(rs * math.cos(a), rs * math.sin(a), re * math.cos(b), re * math.sin(b), ccw)
        assert got == pytest.approx(want, abs=1e-12)


def test_lines_against_their_closed_form(geo):
    rng = np.random.default_rng(2)
    for n_axes in (3, AXES):
        for _ in range(50):
            a, b = rng.uniform(-100, 100, (2, n_axes))
            g = geo.Seg(a, b, n_axes=n_axes)
            length = np.linalg.norm(b - a)
            assert not g.arc and g.length == pytest.approx(length, rel=1e-14)
            assert g.curvature() == 0.0
            for u in (0.0, 0.3, 1.0):
                assert g.point(u * length) == pytest.approx(a + u * (b - a), abs=1e-12)
                assert g.tangent(u * length)[:n_axes] == pytest.approx((b - a) / length, abs=1e-14)
            assert g.point(-1.0) == list(a) and g.point(2 * length) == list(b)     # clamped to the ends
            assert g.reach()[:n_axes] == pytest.approx(np.abs(b - a) / length, abs=1e-14)


def test_a_part_without_length(geo):
    g = geo.Seg([1, 2, 3], [1, 2, 3], n_axes=3)
    assert g.length == 0.0 and g.point(5.0) == [1, 2, 3]
    assert g.tangent(0.0) == [0.0] * AXES and g.reach() == [0.0] * AXES


# ---- the axes' share of the speed, the feed's length ---------------------------------------

@pytest.mark.parametrize("plane", PLANES)
def test_axis_reach_against_sampled_tangents(geo, plane):
    """segment_axis_reach: the largest |tangent_k| over the part, against the closed-form
    tangent sampled densely."""
    rng = np.random.default_rng(11 + abs(plane))
    n = 20001
    u = np.linspace(0.0, 1.0, n)
    for _ in range(25):
        h = random_helix(rng, plane, helical=bool(rng.integers(2)))
        g = h.segment(geo)
        sampled = np.abs(h.tangents(u)).max(axis=0)
        step = abs(h.turn) / (n - 1)
        assert np.all(np.array(g.reach()) >= sampled - 1e-12)
        assert np.all(np.array(g.reach()) <= sampled + step)


def test_feed_length_leaves_out_the_ignored_axes(geo):
    rng = np.random.default_rng(4)
    h = random_helix(rng, 17, turn=2.0)
    g = h.segment(geo)
    assert g.feed_length(0) == g.length
    assert g.feed_length(1 << 2) == pytest.approx(math.hypot(h.r * 2.0, np.linalg.norm(np.delete(h.rise, 2))))
    assert g.feed_length(1 << 0) == g.length         # a plane axis ignored: the arc counts whole
    a, b = rng.uniform(-10, 10, (2, AXES))
    line = geo.Seg(a, b)
    assert line.feed_length(0b1000000101) == pytest.approx(np.linalg.norm(np.delete(b - a, [0, 2, 9])))


# ---- box ----------------------------------------------------------------------------------

@pytest.mark.parametrize("plane", PLANES)
def test_box_against_dense_sampling(geo, plane):
    """segment_box holds every point and is no larger than the sampled extremes plus
    what the sampling can miss between two samples."""
    rng = np.random.default_rng(21 + abs(plane))
    n = 20001
    u = np.linspace(0.0, 1.0, n)
    for k in range(40):
        turn = (2 * math.pi * rng.choice([-1, 1])) if k % 10 == 0 else None
        h = random_helix(rng, plane, turn=turn, helical=bool(rng.integers(2)))
        g = h.segment(geo, full=turn is not None)
        pts = h.at(u)
        lo, hi = (np.array(c) for c in g.box())
        miss = h.r * (1 - math.cos(abs(h.turn) / (n - 1))) + 1e-9
        assert np.all(lo <= pts.min(axis=0) + 1e-9) and np.all(hi >= pts.max(axis=0) - 1e-9)
        assert np.all(lo >= pts.min(axis=0) - miss) and np.all(hi <= pts.max(axis=0) + miss)


def test_box_of_arcs_that_end_on_the_axes(geo):
    """Quarter, half and full turns that start and end exactly on an axis: the box is
    the circle's part they cover."""
    half = geo.Seg([1, 0, 0], [-1, 0, 0], 17, (0, 0, 0), 1.0, True, n_axes=3)
    assert half.box() == ([-1, 0, 0], [1, 1, 0])
    quarter = geo.Seg([0, -1, 0], [1, 0, 0], 17, (0, 0, 0), 1.0, True, n_axes=3)
    assert quarter.box() == ([0, -1, 0], [1, 0, 0])
    cw = geo.Seg([0, -1, 0], [1, 0, 0], 17, (0, 0, 0), 1.0, False, n_axes=3)
    assert cw.box() == ([-1, -1, 0], [1, 1, 0])
    full = geo.Seg([0, 0, 2], [0, 0, 2], -18, (0, 0, 0), 2.0, True, n_axes=3)
    assert full.box() == ([-2, 0, -2], [2, 0, 2])


@pytest.mark.parametrize("ccw", (True, False))
def test_arc_axis_points_against_the_angles_they_pass(geo, ccw):
    rng = np.random.default_rng(31 + ccw)
    checked = 0
    while checked < 2000:
        a = rng.uniform(-math.pi, math.pi)
        turn = rng.uniform(0.001, 2 * math.pi - 0.001)
        b = a + (turn if ccw else -turn)
        lo, hi = (a, a + turn) if ccw else (b, a)
        axes = [q * math.pi / 2 + 2 * math.pi * k for q in range(4) for k in (-2, -1, 0, 1, 2)]
        if min(min(abs(x - lo), abs(x - hi)) for x in axes) < 1e-6:
            continue                    # an end on an axis: rounding decides
        want = sum(1 << q for q in range(4)
                   if any(lo <= q * math.pi / 2 + 2 * math.pi * k <= hi for k in (-2, -1, 0, 1, 2)))
        r = rng.uniform(0.1, 5)
        s, e = (r * math.cos(a), r * math.sin(a)), (r * math.cos(b), r * math.sin(b))
        assert geo.arc_axis_points_of(*s, *e, ccw) == want
        assert geo.arc_axis_points_of(*s, *e, ccw, turn) == want
        checked += 1


def test_arc_axis_points_where_the_ends_meet(geo):
    """Ends that meet: the sweep decides when it is known (a full turn, or an end a
    hair behind the start of a short arc), else they are a full turn."""
    s = (math.cos(0.3), math.sin(0.3))
    behind = (math.cos(0.3 - 1e-13), math.sin(0.3 - 1e-13))
    ahead = (math.cos(0.3 + 1e-13), math.sin(0.3 + 1e-13))
    assert geo.arc_axis_points_of(*s, *s, True) == 0xF
    assert geo.arc_axis_points_of(*s, *ahead, True, 2 * math.pi) == 0xF
    assert geo.arc_axis_points_of(*s, *ahead, True, 1e-13) == 0
    assert geo.arc_axis_points_of(*s, *behind, True, 1e-13) == 0
    assert geo.arc_axis_points_of(*s, *behind, True, 2 * math.pi - 1e-13) == 0xF
    assert geo.arc_axis_points_of(1.0, 0.0, 1.0, 0.0, True, 0.0) == 0b0001      # starts on +first


# ---- nearest point ------------------------------------------------------------------------

@pytest.mark.parametrize("plane", PLANES)
def test_nearest_point_against_brute_force(geo, plane):
    """segment_nearest in random axis masks: no sampled point of the closed form is
    nearer, and the answer is within a sample's spacing of the nearest sample."""
    rng = np.random.default_rng(41 + abs(plane))
    n = 20001
    u = np.linspace(0.0, 1.0, n)
    first, second = PLANES[plane]
    masks = [0x3FF, (1 << first) | (1 << second), 1 << first, (1 << second) | (1 << 3),
             (1 << 3) | (1 << 5), 0x3FF & ~(1 << second)]
    for _ in range(12):
        h = random_helix(rng, plane, helical=bool(rng.integers(2)))
        g = h.segment(geo)
        pts = h.at(u)
        spacing = h.length / (n - 1)
        for mask in masks:
            sel = [k for k in range(AXES) if mask >> k & 1]
            for _ in range(6):
                q = pts[rng.integers(n)] + rng.normal(0, h.r, AXES)
                s, d2, point = g.nearest(q, mask)
                assert 0.0 <= s <= g.length
                assert point == pytest.approx(h.at(s / h.length)[0], abs=1e-9)
                assert d2 == pytest.approx(((np.array(point) - q)[sel] ** 2).sum(), rel=1e-12, abs=1e-12)
                brute = np.sqrt(((pts - q)[:, sel] ** 2).sum(axis=1)).min()
                assert math.sqrt(d2) <= brute + 1e-9
                assert math.sqrt(d2) >= brute - spacing


def test_nearest_point_of_a_line(geo):
    rng = np.random.default_rng(6)
    for _ in range(200):
        a, b, q = rng.uniform(-10, 10, (3, AXES))
        mask = int(rng.integers(1, 1 << AXES))
        sel = [k for k in range(AXES) if mask >> k & 1]
        d = (b - a)[sel]
        t = np.clip(np.dot((q - a)[sel], d) / np.dot(d, d), 0.0, 1.0) if np.dot(d, d) > 0 else 0.0
        s, d2, _ = geo.Seg(a, b).nearest(q, mask)
        assert s == pytest.approx(t * np.linalg.norm(b - a), abs=1e-9)
        assert d2 == pytest.approx((((a + t * (b - a)) - q)[sel] ** 2).sum(), rel=1e-9, abs=1e-12)


# ---- the plane's primitives ---------------------------------------------------------------

def test_line_circle_and_circle_circle_against_their_definitions(geo):
    rng = np.random.default_rng(8)
    met = [0, 0]
    for _ in range(500):
        p, c = rng.uniform(-5, 5, (2, 2))
        ang = rng.uniform(0, 2 * math.pi)
        u = np.array([math.cos(ang), math.sin(ang)])
        r = rng.uniform(0.1, 5)
        pts = geo.line_circle_of(p, u, c, r)
        dist = abs(cross(u, c - p))          # of the centre from the line
        assert (pts is not None) == (dist <= r)
        if pts is not None:
            met[0] += 1
            for x in pts:
                assert np.linalg.norm(np.array(x) - c) == pytest.approx(r, abs=1e-9)
                assert abs(cross(u, np.array(x) - p)) < 1e-9
        c2 = rng.uniform(-5, 5, 2)
        r2 = rng.uniform(0.1, 5)
        pts = geo.circle_circle_of(c, r, c2, r2)
        d = np.linalg.norm(c2 - c)
        assert (pts is not None) == (abs(r - r2) <= d <= r + r2)
        if pts is not None:
            met[1] += 1
            for x in pts:
                assert np.linalg.norm(np.array(x) - c) == pytest.approx(r, abs=1e-9)
                assert np.linalg.norm(np.array(x) - c2) == pytest.approx(r2, abs=1e-9)
    assert min(met) > 100
    # a miss by less than the slack is a touch
    assert geo.line_circle_of((0, 1.001), (1, 0), (0, 0), 1.0) is None
    assert geo.line_circle_of((0, 1.001), (1, 0), (0, 0), 1.0, slack=0.002) == [(0, 1.001), (0, 1.001)]
    assert geo.circle_circle_of((0, 0), 1.0, (2.001, 0), 1.0, slack=0.002) is not None
    assert geo.circle_circle_of((0, 0), 1.0, (0, 0), 1.0) is None          # concentric


def test_turns_and_the_pseudo_sweep(geo):
    rng = np.random.default_rng(9)
    quarter = [(1, 0), (0, 1), (-1, 0), (0, -1)]
    for direction in (1, -1):
        for i, s in enumerate(quarter):
            for j, e in enumerate(quarter):
                steps = ((j - i) * direction) % 4 or 4           # a full turn when s = e
                assert geo.pseudo_sweep_of(*s, *e, direction) == pytest.approx(steps * math.pi / 2)
    for _ in range(300):
        a, b = rng.uniform(-math.pi, math.pi, 2)
        direction = int(rng.choice([-1, 1]))
        want = ((b - a) * direction) % (2 * math.pi)
        va, vb = (math.cos(a), math.sin(a)), (2 * math.cos(b), 2 * math.sin(b))
        assert geo.turn_from_of(*va, *vb, direction) == pytest.approx(want, abs=1e-12)
        # the stand-in is monotone in the true sweep
        c = b + 0.01 * direction
        vc = (math.cos(c), math.sin(c))
        if 0.02 < want < 2 * math.pi - 0.02:
            assert geo.pseudo_sweep_of(*va, *vc, direction) > geo.pseudo_sweep_of(*va, *vb, direction)
    for t in (0.0, 1e-10, -3e-9, 1e-3, 2.5, -3.0):
        v = (math.cos(0.7 + t), math.sin(0.7 + t))
        assert geo.vector_turn_near_of(math.cos(0.7), math.sin(0.7), *v) == pytest.approx(t, abs=1e-15)
