"""The gouge check's measure (compensation/clearance.pyx) against shapely: the distance
of two pieces (lines and arcs, touching, crossing, nested) and its cheap proof of
distance, and the check of long chains while they grow (small search depth)."""
import math
import random

import numpy as np
import pytest

shapely = pytest.importorskip("shapely")
from shapely.geometry import LineString  # noqa: E402

from comp_helpers import (check_gouge_warnings, contour_parts, polygon_elements, programmed_polyline,  # noqa: E402
                          star_cases)
from test_compensation_geometry import comp, harness, signed_area  # noqa: E402,F401
from test_compensation_regions import ERR_COMP_CROSSING, JOIN_G1, REMOVE, TOL, clearance, sampled_path  # noqa: E402

# the oracle's arcs are chords of at most this sagitta
SAGITTA = 1e-6


def sampled(spec):
    """A piece as a dense polyline (arcs: chords of sagitta <= SAGITTA)."""
    if spec[0] == "line":
        return LineString([spec[1], spec[2]])
    _, s, e, c, direction = spec
    r = math.hypot(s[0] - c[0], s[1] - c[1])
    a0 = math.atan2(s[1] - c[1], s[0] - c[0])
    sweep = (direction * (math.atan2(e[1] - c[1], e[0] - c[0]) - a0)) % (2 * math.pi)
    if sweep < 1e-12:
        sweep = 2 * math.pi
    n = max(8, int(math.ceil(sweep / (2 * math.acos(1 - SAGITTA / r)))))
    a = a0 + direction * np.linspace(0, sweep, n + 1)
    pts = np.column_stack([c[0] + r * np.cos(a), c[1] + r * np.sin(a)])
    pts[0], pts[-1] = s, e
    return LineString(pts)


def random_piece(rng, near=None):
    """A line or an arc in a 4 mm square (near: starting at that point)."""
    s = near if near is not None else (rng.uniform(-2, 2), rng.uniform(-2, 2))
    if rng.random() < 0.4:
        return ("line", s, (rng.uniform(-2, 2), rng.uniform(-2, 2)))
    r = rng.uniform(0.1, 2.0)
    a = rng.uniform(0, 2 * math.pi)
    c = (s[0] - r * math.cos(a), s[1] - r * math.sin(a))
    b = a + rng.uniform(0.05, 2 * math.pi - 0.05)
    return ("arc", s, (c[0] + r * math.cos(b), c[1] + r * math.sin(b)), c, rng.choice((1, -1)))


def offset_pair(rng):
    """A line's offset by r and an arc that starts where the line ends (tangent or at
    a corner): the pieces of the tool path and the contour the check meets most."""
    r = rng.uniform(0.1, 1.0)
    L = rng.uniform(0.2, 3.0)
    side = rng.choice((1, -1))
    line = ("line", (-L, side * r), (0.0, side * r))
    R = rng.uniform(0.05, 3.0)
    turn = rng.uniform(-math.pi / 2, math.pi / 2)     # the arc's start direction
    direction = rng.choice((1, -1))
    tx, ty = math.cos(turn), math.sin(turn)
    c = (-direction * ty * R, direction * tx * R)       # centre to the left (CCW) or right (CW)
    a0 = math.atan2(-c[1], -c[0])
    b = a0 + direction * rng.uniform(0.05, 2 * math.pi - 0.05)
    arc = ("arc", (0.0, 0.0), (c[0] + R * math.cos(b), c[1] + R * math.sin(b)), c, direction)
    return (line, arc) if rng.random() < 0.5 else (arc, line), r


def _check_pair(harness, t, g, stop):
    true = sampled(t).distance(sampled(g))
    far, gap = harness.piece_gap(t, g, stop)
    tol = 1e-6 + 2 * SAGITTA
    if far:
        assert true >= stop - tol, (t, g, stop, true)
    if gap < stop:
        assert gap >= true - tol, (t, g, stop, true, gap)
    else:
        assert true >= stop - tol, (t, g, stop, true, gap)
    return gap < stop


def test_piece_gap_matches_shapely(harness):
    rng = random.Random(41)
    below = 0
    for _ in range(1500):
        t = random_piece(rng)
        g = random_piece(rng, near=t[2] if rng.random() < 0.3 else None)
        true = sampled(t).distance(sampled(g))
        # stops on both sides of the true distance, some very close to it
        for stop in (true * 0.5 + 1e-3, true + 1e-4, true * 1.5 + 1e-3, true - 1e-4):
            if stop > 0:
                below += _check_pair(harness, t, g, stop)
    assert below > 500


def test_piece_gap_of_offsets_next_to_arcs(harness):
    rng = random.Random(42)
    for _ in range(1000):
        (t, g), r = offset_pair(rng)
        for stop in (r - 1e-3, r - 1e-6, 0.5 * r):
            _check_pair(harness, t, g, stop)


def long_star(rng, r):
    """A star polygon of 60-120 vertices, jittered radii, some short edges (longer
    than 4 x 10 + 2 elements: its chain is checked while it grows at depth 10)."""
    n = rng.randint(60, 120)
    r_min = 3 * r
    r_max = r_min + rng.uniform(4, 20)
    pts = []
    for i in range(n):
        a = 2 * math.pi * (i + rng.uniform(-0.3, 0.3)) / n
        rho = rng.uniform(r_min, r_max)
        pts.append((rho * math.cos(a), rho * math.sin(a)))
        if rng.random() < 0.3:
            L = rng.uniform(0.05, 0.5)
            t = rng.uniform(0, 2 * math.pi)
            q = (pts[-1][0] + L * math.cos(t), pts[-1][1] + L * math.sin(t))
            if math.hypot(*q) >= r_min and 0 < (math.atan2(q[1], q[0]) - a) % (2 * math.pi) < math.pi / n:
                pts.append(q)
    return pts if signed_area(np.array(pts)) > 0 and shapely.Polygon(pts).is_valid else None


def _compensate_star(harness, pts, r, g, strategy, strict=False):
    m0, els = polygon_elements(pts)
    approach = (m0[0] + 0.3, m0[1] - 80.0)
    parts = contour_parts(els, g, m0, approach)
    out, err, warn = comp(harness, parts, r=r, strategy=strategy, start=(approach[0], approach[1], 0), strict=strict)
    return out, err, warn, m0, programmed_polyline(m0, els)


@pytest.mark.parametrize("seed", range(2))
def test_long_chains_checked_while_they_grow(harness, seed):
    """Search depth 10 (0x100): chains of 60+ elements are checked in steps beside the
    compiler, and their parts farther apart than the depth at the end. With 0x80000
    each contour compiles and keeps the radius; without it each one compiles, warning
    601 on exactly the lines that cut into the contour (shapely, whatever the depth),
    and the strict mode refuses exactly those (504)."""
    warned = 0
    cases = star_cases(25, 140 + seed, long_star, 1.0)
    for pts, r, g, mode in cases:
        out, err, _, m0, contour = _compensate_star(harness, pts, r, g, REMOVE | JOIN_G1 | 0x100 | mode)
        assert err is None, (err, pts, r, g, mode)
        assert clearance(sampled_path(out, np.asarray(m0), step=0.02), contour) > r - TOL, (pts, r, g, mode)
        out, err, warn, m0, contour = _compensate_star(harness, pts, r, g, JOIN_G1 | 0x100 | mode)
        assert err is None, (err, pts, r, g, mode)
        gouges = check_gouge_warnings(out, warn, contour, r, start_point=np.asarray(m0))
        warned += bool(gouges)
        _, err, _, _, _ = _compensate_star(harness, pts, r, g, JOIN_G1 | 0x100 | mode, strict=True)
        assert (err is not None) == bool(gouges), (err, gouges)
        assert err is None or err["number"] == ERR_COMP_CROSSING
    assert warned > len(cases) // 2      # the features smaller than the tool were measured


@pytest.mark.parametrize("index", [38, 68, 362])
def test_rebuild_sees_the_whole_contour(harness, index):
    """Search depth 10, inside offsets of long stars rebuilt from their regions, where
    pieces of elements 11 to 14 parts apart cross: the rebuild splits and measures its
    pieces against the whole contour (only within the depth, #68's path came 0.06 mm
    too close, #38 and #362 were error 504)."""
    pts, r, g, mode = star_cases(index + 1, 140, long_star, 1.0)[index]
    out, err, warn, m0, contour = _compensate_star(harness, pts, r, g, REMOVE | JOIN_G1 | 0x100 | mode)
    assert err is None, err
    assert "part skipped" in warn                       # rebuilt
    path = sampled_path(out, np.asarray(m0), step=0.02)
    assert clearance(path, contour) > r - TOL
