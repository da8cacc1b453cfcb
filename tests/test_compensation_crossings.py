"""Crossings of the tool path between parts that are not neighbours (narrow necks,
notches narrower than the tool): loops removed with strategy 0x80000, kept with warning
601 without it (the strict mode: error 504); removed within the search depth (0x700),
seen whatever it is. Shapely is the oracle (see test_compensation_geometry)."""
import math

import numpy as np
import pytest

shapely = pytest.importorskip("shapely")
from shapely.geometry import LineString, Point, Polygon  # noqa: E402

from comp_helpers import (check_gouge_warnings, contour_parts, polygon_elements, programmed_polyline,  # noqa: E402
                          reverse_contour, tool_path)
from test_compensation_geometry import check_oracle, comp, exact_offset, harness, signed_area  # noqa: E402,F401

TOL = 1e-3
REMOVE = 0x80000
ERR_COMP_CROSSING = 504

# CCW dumbbell: two 15 x 20 squares joined by a bar 10 long and 4 high
DUMBBELL = [(-20, -10), (-5, -10), (-5, -2), (5, -2), (5, -10), (20, -10), (20, 10), (5, 10),
            (5, 2), (-5, 2), (-5, 10), (-20, 10)]
# CCW block with a notch 3 wide and 12 deep from the top
NOTCH = [(-20, -10), (20, -10), (20, 10), (1.5, 10), (1.5, -2), (-1.5, -2), (-1.5, 10), (-20, 10)]
# U-shaped pocket: two arms 8 wide joined at the bottom by a channel 3 high
# (starting on the right arm's outer wall: a start in the channel is itself too narrow)
U_POCKET = [(12, -10), (12, 15), (4, 15), (4, -7), (-4, -7), (-4, 15), (-12, 15), (-12, -10)]


def run(harness, m0, els, r, g, strategy, strict=False):
    approach = (m0[0] + 0.3, m0[1] - 60.0)
    parts = contour_parts(els, g, m0, approach)
    return comp(harness, parts, r=r, strategy=strategy, start=(approach[0], approach[1], 0), strict=strict)


def check_kept(harness, m0, els, r, g, strategy=0):
    """Without 0x80000 the crossing stays: the contour compiles, with warning 601 on
    exactly the lines whose tool path cuts into it (shapely); the strict mode refuses
    it (504) on one of them. Returns {line: depth}."""
    out, err, warn = run(harness, m0, els, r, g, strategy)
    assert err is None, err
    warned = check_gouge_warnings(out, warn, programmed_polyline(m0, els), r, start_point=np.asarray(m0))
    assert warned
    _, err, _ = run(harness, m0, els, r, g, strategy, strict=True)
    assert err is not None and err["number"] == ERR_COMP_CROSSING and err["line"] in warned, (err, warned)
    return warned


def check_split(harness, m0, els, r, g, strategy=REMOVE):
    """A neck narrower than 2r splits the offset: the tool path keeps r from the contour,
    lies on the offset and goes round the whole component the contour starts in."""
    out, err, warn = run(harness, m0, els, r, g, strategy)
    assert err is None, err
    assert "loop removed" in warn
    prog = programmed_polyline(m0, els)
    inside = (signed_area(prog) > 0) == (g == 41)
    poly = Polygon(prog)
    shape = exact_offset(poly, m0, els, r, inside)
    path = tool_path(out, 2, len(out) - 2)
    contour = LineString(prog)
    d_contour = shapely.distance(shapely.points(path), contour)
    assert float(np.min(d_contour)) > r - TOL, f"gouges by {r - np.min(d_contour)}"
    d_off = shapely.distance(shapely.points(path), shape.boundary)
    assert float(np.max(d_off)) < TOL, f"path off the offset by {np.max(d_off)}"
    start = Point(out[1]["ce"][:2])
    comps = list(getattr(shape, "geoms", [shape]))
    home = min(comps, key=lambda c: c.exterior.distance(start))
    ring_pts = np.asarray(shapely.segmentize(home.exterior, 0.05).coords)
    d_ring = shapely.distance(shapely.points(ring_pts), LineString(path))
    assert float(np.max(d_ring)) < TOL, f"offset not covered by {np.max(d_ring)}"
    return out, shape


@pytest.mark.parametrize("reverse", [False, True])
@pytest.mark.parametrize("r", [2.5, 3.0, 4.0])
def test_dumbbell_neck_inside_splits(harness, reverse, r):
    m0, els = polygon_elements(DUMBBELL)
    g = 41
    if reverse:
        m0, els = reverse_contour(m0, els)
        g = 42
    out, shape = check_split(harness, m0, els, r, g)
    assert shape.geom_type == "MultiPolygon"
    # nothing of the path on the right side
    assert max(p["ce"][0] for p in out[1:-1]) < 0


def test_dumbbell_neck_warning_or_error_names_the_later_part(harness):
    m0, els = polygon_elements(DUMBBELL)
    out, err, _ = run(harness, m0, els, 3.0, 41, 0, strict=True)
    # lines: 1 approach, 2 G41 block, 3.. the contour; the first loop closes at the
    # corner arc of the part ending at (5, 2)
    assert err["number"] == ERR_COMP_CROSSING and err["line"] == 3 + DUMBBELL.index((5, 2)) - 1
    # without the strict mode the loop stays: the tool cuts 2 mm into the bar's walls
    # (4 high, the tool 3 from the other one)
    warned = check_kept(harness, m0, els, 3.0, 41)
    assert 3 + DUMBBELL.index((5, 2)) - 1 in warned and max(warned.values()) == pytest.approx(2.0)
    # a neck wide enough: no crossing, no warning
    out, err, warn = run(harness, m0, els, 1.9, 41, 0)
    assert err is None and "loop" not in warn and "Equidistant" not in warn


def test_u_pocket_narrow_channel(harness):
    m0, els = polygon_elements(U_POCKET)
    check_split(harness, m0, els, 1.8, 41)
    check_kept(harness, m0, els, 1.8, 41)


@pytest.mark.parametrize("g,reverse", [(42, False), (41, True)])
def test_notch_narrower_than_the_tool_is_bridged(harness, g, reverse):
    m0, els = polygon_elements(NOTCH)
    if reverse:
        m0, els = reverse_contour(m0, els)
    for r in (1.6, 2.0, 3.0):
        check_oracle(harness, m0, els, r, g, strategy=REMOVE)
        with pytest.raises(AssertionError, match="504"):
            check_oracle(harness, m0, els, r, g, strict=True)
        check_kept(harness, m0, els, r, g)
    check_oracle(harness, m0, els, 1.4, g)          # the tool fits: nothing to remove


def test_notch_with_a_round_bottom(harness):
    # the bottom arc (radius 1.5) is smaller than the tool: dropped (0x200000), then the
    # walls' offsets cross at the notch's mouth
    pts = [(-20, -10), (20, -10), (20, 10), (1.5, 10), (1.5, -2)]
    m0 = (0.0, -10.0)
    els = [dict(func=1, e=p) for p in pts[1:]]
    els.append(dict(func=2, e=(-1.5, -2), cc=(0, -2), radius=1.5))
    els += [dict(func=1, e=(-1.5, 10)), dict(func=1, e=(-20, 10)), dict(func=1, e=(-20, -10)),
            dict(func=1, e=m0)]
    check_oracle(harness, m0, els, 2.0, 42, strategy=REMOVE | 0x200000)


def test_arc_contour_neck(harness):
    # two discs (radius 10) joined by a neck 3 high; r = 2 inside
    h = 1.5
    x = math.sqrt(100 - h * h)
    m0 = (-12.0, -x * 0 - 10.0)
    els = [dict(func=3, e=(-12 + x, -h), cc=(-12, 0), radius=10.0),
           dict(func=1, e=(12 - x, -h)),
           dict(func=3, e=(12 - x, h), cc=(12, 0), radius=10.0),
           dict(func=1, e=(-12 + x, h)),
           dict(func=3, e=m0, cc=(-12, 0), radius=10.0)]
    check_split(harness, m0, els, 2.0, 41)
    check_kept(harness, m0, els, 2.0, 41)


def _long_dumbbell(left=False):
    """DUMBBELL with the right square's bottom, right and top edges cut into parts
    longer than the tool radius (left: the left square's top and left edges too)."""
    pts = []
    for i, p in enumerate(DUMBBELL):
        q = DUMBBELL[(i + 1) % len(DUMBBELL)]
        k = 4 if i in (4, 6) or (left and i in (10, 11)) else (5 if i == 5 else 1)
        pts += [(p[0] + (q[0] - p[0]) * j / k, p[1] + (q[1] - p[1]) * j / k) for j in range(k)]
    return polygon_elements(pts)


def test_search_depth_limits_only_the_search(harness):
    # the bar's bottom and top: 16 parts apart in program order, 7 round the start
    m0, els = _long_dumbbell()
    # 0x100: 10 parts back, the loop is not searched; the gouge check counts the parts
    # round the start of the closed contour: warning 601 (strict: 504), rebuilt with
    # 0x80000
    out, err, warn = run(harness, m0, els, 3.0, 41, 0x100)
    assert err is None and "loop" not in warn
    check_kept(harness, m0, els, 3.0, 41, 0x100)
    check_rebuilt(harness, m0, els, 3.0, 41, 0x100 | REMOVE)
    # 0x200: 50 parts: the loop is found
    check_kept(harness, m0, els, 3.0, 41, 0x200)
    for depth in (0x200, 0x700, 0):
        check_split(harness, m0, els, 3.0, 41, strategy=REMOVE | depth)
    # the left square cut too: 13 parts round the start, more than 10 either way: the
    # loop is not searched, but the gouge is seen all the same (the parts farther apart
    # than the depth are measured when the chain ends): warning 601, rebuilt with
    # 0x80000 round one of the squares
    m0, els = _long_dumbbell(left=True)
    out, err, warn = run(harness, m0, els, 3.0, 41, 0x100)
    assert err is None and "loop" not in warn
    assert max(p["ce"][0] for p in out) > 10        # the tool passes the neck ...
    check_kept(harness, m0, els, 3.0, 41, 0x100)    # ... and cuts 2 mm into it
    check_rebuilt(harness, m0, els, 3.0, 41, 0x100 | REMOVE)
    check_split(harness, m0, els, 3.0, 41, strategy=REMOVE | 0x200)


def check_rebuilt(harness, m0, els, r, g, strategy):
    """The chain rebuilt from its regions: the tool path keeps r from the contour,
    lies on shapely's offset and goes round a component of the largest area."""
    out, err, warn = run(harness, m0, els, r, g, strategy)
    assert err is None, (err, warn)
    assert "part skipped" in warn
    prog = programmed_polyline(m0, els)
    inside = (signed_area(prog) > 0) == (g == 41)
    shape = exact_offset(Polygon(prog), m0, els, r, inside)
    path = tool_path(out, 2, len(out) - 2)
    path = np.asarray(shapely.segmentize(LineString(path), 0.02).coords)
    d_contour = shapely.distance(shapely.points(path), LineString(prog))
    assert float(np.min(d_contour)) > r - TOL, f"gouges by {r - np.min(d_contour)}"
    d_off = shapely.distance(shapely.points(path), shape.boundary)
    assert float(np.max(d_off)) < TOL, f"path off the offset by {np.max(d_off)}"
    comps = list(getattr(shape, "geoms", [shape]))
    top = max(c.area for c in comps)
    covered = []
    for c in comps:
        ring_pts = np.asarray(shapely.segmentize(c.exterior, 0.05).coords)
        covered.append((float(np.max(shapely.distance(shapely.points(ring_pts), LineString(path)))), c.area))
    assert any(d < TOL and area > top - 1e-6 for d, area in covered), covered
    return out, shape


def test_start_inside_the_loop_is_rebuilt(harness):
    # the contour starts on a wall of a notch narrower than the tool: the loop cut at
    # the notch's mouth would keep the notch; with 0x80000 the chain is rebuilt from
    # the region outside (the notch bridged), without it the gouge is warning 601
    # (strict: error 504)
    pts = [(1.5, 4), (1.5, -2), (-1.5, -2), (-1.5, 10), (-20, 10), (-20, -10), (20, -10), (20, 10), (1.5, 10)]
    m0 = (1.5, 7.0)
    els = [dict(func=1, e=p) for p in pts] + [dict(func=1, e=m0)]
    for strategy in (REMOVE, REMOVE | 0x10000):
        check_rebuilt(harness, m0, els, 2.0, 42, strategy)
    check_kept(harness, m0, els, 2.0, 42)


def test_a_contour_crossing_itself_is_no_loop(harness):
    # an open path whose fourth part crosses the first one: the programmed contour
    # crosses itself there, so does the tool path
    parts = [dict(func=1, e=(0, -10), comp=40), dict(func=1, e=(0, 0), comp=41),
             dict(func=1, e=(20, 0), comp=41), dict(func=1, e=(20, 5), comp=41),
             dict(func=1, e=(10, 5), comp=41), dict(func=1, e=(10, -10), comp=41),
             dict(func=1, e=(10, -20), comp=40)]
    for strategy in (0, REMOVE):
        out, err, warn = comp(harness, parts, r=1.0, strategy=strategy, start=(0, -10, 0))
        assert err is None and "loop" not in warn
        ce = [tuple(round(v, 9) for v in p["ce"][:2]) for p in out]
        assert ce == [(0, -10), (0, 1), (19, 1), (19, 4), (11, 4), (11, -10), (10, -20)]


@pytest.mark.parametrize("reverse", [False, True])
@pytest.mark.parametrize("r", [2.5, 3.0, 4.0])
def test_dumbbell_entered_in_the_neck_is_rebuilt(harness, reverse, r):
    # the chain starts in the bar: the loop cuts would keep the bar's offsets, which
    # lie closer than r to the other side of the bar; 0x80000 rebuilds the chain round
    # one of the squares (both as large), without it warning 601 (strict: 504)
    pts = DUMBBELL[2:] + DUMBBELL[:2]       # the first edge is the bar's bottom
    m0, els = polygon_elements(pts)
    g = 41
    if reverse:
        m0, els = reverse_contour(m0, els)
        g = 42
    _, shape = check_rebuilt(harness, m0, els, r, g, REMOVE)
    assert shape.geom_type == "MultiPolygon"
    check_kept(harness, m0, els, r, g)


def test_dumbbell_entered_in_a_wide_neck_is_clean(harness):
    pts = DUMBBELL[2:] + DUMBBELL[:2]
    m0, els = polygon_elements(pts)
    out, err, warn = run(harness, m0, els, 1.9, 41, REMOVE)
    assert err is None and "loop" not in warn
    path = tool_path(out, 2, len(out) - 2)
    d = shapely.distance(shapely.points(path), LineString(programmed_polyline(m0, els)))
    assert float(np.min(d)) > 1.9 - TOL


@pytest.mark.parametrize("depth", [0x600, 0x700])
def test_comb_with_gaps_narrower_than_the_tool(harness, depth):
    # CCW comb: 40 teeth 3 wide and 10 high with gaps 1 wide; outside (G42) with r = 1
    # every gap is a loop, bridged at its mouth; the checks after the cuts pass
    pts = [(-10, -10), (160, -10), (160, 10)]
    x = 160.0
    for _ in range(40):
        pts += [(x - 3, 10), (x - 3, 0), (x - 4, 0), (x - 4, 10)]
        x -= 4
    pts += [(-10, 10)]
    m0, els = polygon_elements(pts)
    out = check_oracle(harness, m0, els, 1.0, 42, strategy=REMOVE | depth)
    assert sum(1 for p in out if p["inserted"]) > 40
