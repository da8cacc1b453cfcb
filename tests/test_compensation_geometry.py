"""Tool radius compensation checked on the compensation stage alone (parts given
directly, see tests/harness): exact offset curves from shapely as the oracle
for random closed contours, and hand-computed cases for every corner type and
strategy bit."""
import math
import os
import random

import numpy as np
import pytest

shapely = pytest.importorskip("shapely")
from shapely.geometry import LineString, Point, Polygon  # noqa: E402

from comp_helpers import (contour_parts, polygon_elements, programmed_polyline,  # noqa: E402
                          random_convex, random_star, reverse_contour, rounded_rectangle,
                          tool_path, arc_centre)

TOL = 1e-3


def _harness_module():
    import harness
    return harness.load()


@pytest.fixture(scope="session")
def harness():
    return _harness_module()


def comp(harness, parts, r=2.0, strategy=0, start=(0, 0, 0), tolerances=(), corrections=None, strict=False):
    corr = corrections if corrections is not None else (r,) * 8
    return harness.compensate(parts, start, strategy, corr, tolerances, strict)


def signed_area(poly_pts):
    x, y = poly_pts[:, 0], poly_pts[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def exact_offset(poly, m0, els, r, inside):
    """The region bounded by the offset curve. GEOS simplifies the input of a buffer by
    1 % of the distance, too coarse here: the band within r of the contour is built as
    the union of the round-capped buffers of single segments (exact up to the caps'
    polygonisation), the contour's arcs cut into chords of negligible sagitta."""
    pts = programmed_polyline(m0, els, sagitta=5e-5)
    segments = shapely.linestrings(np.stack([pts[:-1], pts[1:]], axis=1))
    band = shapely.union_all(shapely.buffer(segments, r, quad_segs=64))
    return poly.difference(band) if inside else poly.union(band)


def check_oracle(harness, m0, els, r, g, strategy=0, strict=False):
    """Compensates the closed contour with G41/G42 (g) and compares the tool path with
    the exact offset ring (no warning 601: it keeps the radius). Returns the output
    parts."""
    approach = (m0[0] + 0.3, m0[1] - 60.0)
    parts = contour_parts(els, g, m0, approach)
    out, err, warn = comp(harness, parts, r=r, strategy=strategy, start=(approach[0], approach[1], 0),
                          strict=strict)
    assert err is None, f"error {err['number']}: {err['text']} (line {err['line']})"
    assert "Equidistant error" not in warn, warn
    prog = programmed_polyline(m0, els)
    ccw = signed_area(prog) > 0
    inside = ccw == (g == 41)
    poly = Polygon(prog)
    assert poly.is_valid
    shape = exact_offset(poly, m0, els, r, inside)
    assert shape.geom_type == "Polygon", "oracle: offset splits"
    ring = shape.exterior
    path = tool_path(out, 2, len(out) - 2)
    # every point of the tool path on the offset ring ...
    d_path = shapely.distance(shapely.points(path), ring)
    assert float(np.max(d_path)) < TOL, f"path off the offset by {np.max(d_path)}"
    # ... and every point of the ring reached by the tool path
    ring_pts = np.asarray(shapely.segmentize(ring, 0.05).coords)
    d_ring = shapely.distance(shapely.points(ring_pts), LineString(path))
    assert float(np.max(d_ring)) < TOL, f"offset not covered by {np.max(d_ring)}"
    # the compensated end points lie exactly at the tool radius from the contour
    boundary = LineString(prog)
    for p in out[2:-1]:
        assert abs(boundary.distance(Point(p["ce"][:2])) - r) < 1e-4
    return out


# ------------------------------------------------------------------ oracle: random contours

def _cases(n, seed):
    rng = random.Random(seed)
    for _ in range(n):
        yield rng


@pytest.mark.parametrize("g", [41, 42])
@pytest.mark.parametrize("reverse", [False, True])
def test_convex_polygons_match_exact_offsets(harness, g, reverse):
    for rng in _cases(15, 1 + g + 7 * reverse):
        pts = random_convex(rng, rng.randint(3, 9))
        m0, els = polygon_elements(pts)
        if reverse:
            m0, els = reverse_contour(m0, els)
        check_oracle(harness, m0, els, rng.uniform(0.5, 4.0), g)


@pytest.mark.parametrize("g", [41, 42])
def test_concave_polygons_match_exact_offsets(harness, g):
    for rng in _cases(15, 100 + g):
        pts = random_star(rng, 2 * rng.randint(3, 6))
        m0, els = polygon_elements(pts)
        check_oracle(harness, m0, els, rng.uniform(0.3, 1.5), g)


@pytest.mark.parametrize("g", [41, 42])
@pytest.mark.parametrize("reverse", [False, True])
def test_rounded_rectangles_match_exact_offsets(harness, g, reverse):
    for rng in _cases(8, 200 + g + reverse):
        rad = rng.uniform(3, 8)
        m0, els = rounded_rectangle(rng.uniform(-20, 0), rng.uniform(-20, 0),
                                    rng.uniform(25, 50), rng.uniform(25, 50), rad)
        if reverse:
            m0, els = reverse_contour(m0, els)
        check_oracle(harness, m0, els, rng.uniform(0.5, rad * 0.9), g)


@pytest.mark.parametrize("g", [41, 42])
def test_contours_with_arcs_match_exact_offsets(harness, g):
    for rng in _cases(8, 300 + g):
        n = rng.randint(4, 8)
        pts = random_convex(rng, n, radius=40.0)
        arcs = {}
        for i in range(1, n):
            if rng.random() < 0.6:
                c = math.dist(pts[i], pts[(i + 1) % n])
                arcs[i] = rng.choice([1, -1]) * rng.uniform(0.05, 0.25) * c
        m0, els = polygon_elements(pts, arcs)
        check_oracle(harness, m0, els, rng.uniform(0.5, 2.5), g)


@pytest.mark.slow
@pytest.mark.parametrize("g", [41, 42])
def test_many_random_contours(harness, g):
    # bounded for CI: 25 contours per side at SF_TCH_SLOW_SCALE=1 (6 for 150)
    count = 25 * int(os.environ.get("SF_TCH_SLOW_SCALE", "1"))
    for rng in _cases(count, 1000 + g):
        kind = rng.randrange(3)
        if kind == 0:
            m0, els = polygon_elements(random_convex(rng, rng.randint(3, 12)))
            r = rng.uniform(0.3, 4)
        elif kind == 1:
            m0, els = polygon_elements(random_star(rng, 2 * rng.randint(3, 8)))
            r = rng.uniform(0.2, 1.2)
        else:
            n = rng.randint(4, 10)
            pts = random_convex(rng, n, radius=40.0)
            arcs = {i: rng.choice([1, -1]) * rng.uniform(0.05, 0.25) * math.dist(pts[i], pts[(i + 1) % n])
                    for i in range(1, n) if rng.random() < 0.6}
            m0, els = polygon_elements(pts, arcs)
            r = rng.uniform(0.3, 2.5)
        if rng.random() < 0.5:
            m0, els = reverse_contour(m0, els)
        check_oracle(harness, m0, els, r, g)
