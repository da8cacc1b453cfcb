"""CAM jobs of many short contours, each entered with G41/G42 and a lead-in at one of
its vertices and left with G40 and a lead-out there (as nesting CAM systems write
them for cutting tables), with strategy 0: the G41/G42 move ends on the first
part's perpendicular, the last part on its own perpendicular.

At a vertex where the tool path turns inwards (an inner corner) those two points
lie a turn of theta apart round the vertex, each r cos(theta) from the other line:
the tool cuts r (1 - cos theta) into the first and the last line (the vendor's rule
cuts that nick; warning 601 names it). With 0x80000 the two ends cross and are
trimmed to the offsets' intersection like any other crossing neighbours: the path
closes at the corner. Oracles: shapely's exact offsets and distances, and the
closed form of the nick."""
import math
import random
import warnings

import numpy as np
import pytest

shapely = pytest.importorskip("shapely")
from shapely.geometry import LineString, Polygon  # noqa: E402

from comp_helpers import (check_gouge_warnings, contour_parts, point_distances,  # noqa: E402
                          programmed_polyline, tool_path)
from test_compensation_geometry import comp, exact_offset, signed_area  # noqa: E402

R = 0.15
TOL = 1e-3
REMOVE = 0x80000
JOIN_G1 = 0x20000
DEPTH = 0x600
ERR_COMP_CROSSING = 504
ERR_COMP_GOUGE = 601


def corner_polygon(rng):
    """A polygon round the origin, counter-clockwise, 5 to 20 vertices at least 6
    degrees apart at random radii (most are not convex), the first on +X; edges of at
    least 1 mm."""
    while True:
        size = rng.uniform(15, 40)
        angles = [0.0]
        while True:
            a = angles[-1] + math.radians(rng.uniform(6, 45))
            if a > 2 * math.pi - math.radians(6):
                break
            angles.append(a)
        if not 5 <= len(angles) <= 20:
            continue
        pts = [(size * rng.uniform(0.6, 1.0) * math.cos(a), size * rng.uniform(0.6, 1.0) * math.sin(a))
               for a in angles]
        if all(math.dist(pts[k], pts[k - 1]) >= 1.0 for k in range(len(pts))):
            return pts


def start_turn(pts):
    """The contour's turn at its start vertex (radians, > 0 to the left)."""
    a, b, c = pts[-1], pts[0], pts[1]
    d1 = (b[0] - a[0], b[1] - a[1])
    d2 = (c[0] - b[0], c[1] - b[1])
    return math.atan2(d1[0] * d2[1] - d1[1] * d2[0], d1[0] * d2[0] + d1[1] * d2[1])


def polygon_contour(pts):
    """(m0, elements) of the closed polygon started at its first vertex."""
    return pts[0], [dict(func=1, e=p) for p in pts[1:] + pts[:1]]


def cases(count, seed):
    """(points, g) of random corner-started polygons, G41 (tool inside) or G42."""
    rng = random.Random(seed)
    return [(corner_polygon(rng), rng.choice((41, 42))) for _ in range(count)]


def inner_start(pts, g):
    """The turn at the start when the tool path turns inwards there, else 0."""
    turn = start_turn(pts)
    return abs(turn) if (turn > 0) == (g == 41) else 0.0


def lead_in_parts(pts, g):
    m0, els = polygon_contour(pts)
    approach = (m0[0] - 5.0, m0[1] - 5.0)
    return m0, els, contour_parts(els, g, m0, approach), approach


@pytest.mark.parametrize("seed", [1, 2])
def test_corner_starts_with_0x80000_close_on_the_exact_offset(harness, seed):
    """0x80000: every contour's tool path runs on the ring of shapely's exact offset
    and round all of it (the ramp ends where the path closes), with no warning 601;
    the strict mode refuses none of them."""
    checked = closed = 0
    for pts, g in cases(30, seed):
        m0, els, parts, approach = lead_in_parts(pts, g)
        prog = programmed_polyline(m0, els)
        inside = (signed_area(prog) > 0) == (g == 41)
        shape = exact_offset(Polygon(prog), m0, els, R, inside)
        if shape.geom_type != "Polygon":
            continue                            # the offset splits: test_compensation_regions
        for strict in (False, True):
            out, err, warn = comp(harness, parts, r=R, strategy=REMOVE | JOIN_G1 | DEPTH,
                                  start=(approach[0], approach[1], 0), strict=strict)
            assert err is None, (pts, g, err)
            assert "Equidistant error" not in warn, warn
        path = tool_path(out, 2, len(out) - 2, step=0.01)
        ring = shape.exterior
        assert float(np.max(point_distances(path, ring))) < TOL
        theta = inner_start(pts, g)
        if theta > 0:
            # closed at the offsets' intersection, r / cos(theta / 2) from the vertex,
            # and round the whole ring
            assert np.allclose(out[1]["ce"][:2], out[-2]["ce"][:2], atol=1e-9), "the path does not close"
            assert math.dist(out[1]["ce"][:2], m0) == pytest.approx(R / math.cos(theta / 2), abs=1e-9)
            ring_pts = np.asarray(shapely.segmentize(ring, 0.01).coords)
            assert float(np.max(point_distances(ring_pts, LineString(path)))) < 0.01
            closed += 1
        else:
            # the tool outside the turn: in on the first part's perpendicular, out on the last one's
            d = R if g == 41 else -R
            assert np.allclose(out[1]["ce"][:2], np.add(m0, _left(pts[0], pts[1], d)), atol=1e-9)
            assert np.allclose(out[-2]["ce"][:2], np.add(m0, _left(pts[-1], pts[0], d)), atol=1e-9)
        checked += 1
    assert checked >= 20 and closed >= 5


@pytest.mark.parametrize("seed", [3, 4])
def test_corner_starts_by_default_warn_the_nick(harness, seed):
    """Without 0x80000 the path stays as strategy 0 gives it: warning 601 on exactly the
    lines whose path cuts into the contour (shapely), among them the first and last
    line of a contour started at an inner corner, at least r (1 - cos theta) deep;
    strict: error 504 exactly when there is a warning."""
    nicks = 0
    for pts, g in cases(30, seed):
        m0, els, parts, approach = lead_in_parts(pts, g)
        out, err, warn = comp(harness, parts, r=R, strategy=JOIN_G1 | DEPTH, start=(approach[0], approach[1], 0))
        assert err is None, err
        assert np.allclose(out[1]["ce"][:2], np.add(m0, _left(pts[0], pts[1], R if g == 41 else -R)), atol=1e-9)
        warned = check_gouge_warnings(out, warn, programmed_polyline(m0, els), R)
        theta = inner_start(pts, g)
        nick = R * (1 - math.cos(theta))
        if theta < math.pi / 2 and nick > 2e-3:
            first, last = 3, 2 + len(els)
            # (the warning text gives six digits)
            assert min(warned[first], warned[last]) >= nick * (1 - 1e-5), (warned, nick)
            nicks += 1
        _, err, _ = comp(harness, parts, r=R, strategy=JOIN_G1 | DEPTH, start=(approach[0], approach[1], 0),
                         strict=True)
        assert (err is not None) == bool(warned)
        assert err is None or (err["number"] == ERR_COMP_CROSSING and err["line"] in warned)
    assert nicks >= 5


def _left(a, b, d):
    """d times the left normal of the direction a -> b."""
    L = math.dist(a, b)
    return (-(b[1] - a[1]) / L * d, (b[0] - a[0]) / L * d)


def cam_job(count, seed):
    """The text of a CAM job (absolute coordinates, a contour every 100 mm): polygons
    started at a vertex and rounded rectangles started where an arc meets a line,
    each G0 / M51 / G41 / lead-in / contour / G40 / lead-out / M50. Returns the text
    and per contour (first contour line, last contour line, contour points, points of
    a polygon or None, feed)."""
    rng = random.Random(seed)
    lines = ["G90", "G17"]
    contours = []
    for k in range(count):
        cx = 100.0 * (k % 10)
        cy = 100.0 * (k // 10)
        feed = rng.choice((1500, 2000, 3000))
        if k % 3 == 2:
            w, h, q = rng.uniform(10, 30), rng.uniform(10, 30), rng.uniform(1, 5)
            x0, x1, y0, y1 = cx - w, cx + w, cy - h, cy + h
            m0 = (x0 + q, y0)
            moves = [(1, (x1 - q, y0), None), (3, (x1, y0 + q), (x1 - q, y0 + q)), (1, (x1, y1 - q), None),
                     (3, (x1 - q, y1), (x1 - q, y1 - q)), (1, (x0 + q, y1), None),
                     (3, (x0, y1 - q), (x0 + q, y1 - q)), (1, (x0, y0 + q), None), (3, m0, (x0 + q, y0 + q))]
            poly = None
        else:
            poly = [(round(cx + x, 4), round(cy + y, 4)) for x, y in corner_polygon(rng)]
            m0 = poly[0]
            moves = [(1, p, None) for p in poly[1:] + poly[:1]]
        lines += [f"G0 X{m0[0] - 5:.4f} Y{m0[1] - 5:.4f}", "M51", "G41", f"G1 X{m0[0]:.4f} Y{m0[1]:.4f} F{feed}"]
        first = len(lines) + 1
        cur = m0
        for func, e, c in moves:
            if c is None:
                lines.append(f"G1 X{e[0]:.4f} Y{e[1]:.4f}")
            else:
                lines.append(f"G{func} X{e[0]:.4f} Y{e[1]:.4f} I{c[0] - cur[0]:.4f} J{c[1] - cur[1]:.4f}")
            cur = e
        els = [dict(func=f, e=e, cc=c) for f, e, c in moves]
        contours.append((first, len(lines), programmed_polyline(m0, els), poly, feed))
        lines += ["G40", f"G1 X{m0[0] - 5:.4f} Y{m0[1] - 5:.4f}", "M50"]
    lines.append("M2")
    return "\n".join(lines) + "\n", contours


def test_cam_job_through_the_library():
    """A whole job compiled by the library. Radius 0 (G41/G40 in the text): the tool
    path is the programmed path, part for part (its lines, numbers, ends and feeds as
    the text gives them), no part inserted. Radius 0.15 with
    0xA0600: no warning; each contour's tool path keeps the radius from its contour,
    closes where the lead-in ends and runs on its exact offset (shapely). With 0x20600:
    warning 601 on the first and last line of the contours started at an inner corner
    deeper than the allowance, only on contour lines."""
    import sf_tch
    text, contours = cam_job(24, 5)
    # every G0-G3 and M line is a part; the text gives its number and end
    written = [(n, line.split()) for n, line in enumerate(text.splitlines(), 1)
               if line.split()[0] in ("G0", "G1", "G2", "G3") or line[0] == "M"]
    with sf_tch.compile(text, radius=0.0) as program:
        program.check()
        assert not program.warnings
        rec = program.toolpath.records
    assert [int(x) for x in rec["line"]] == [n for n, _ in written]
    assert [int(x) for x in rec["number"]] == [int(words[0][1:]) for _, words in written]
    assert not np.any(rec["flags"] & 2)
    # (an arc's tool end lies on its circle: the rounded text leaves its end up to 1e-4 mm off)
    arc = np.isin(rec["number"], (2, 3)) & (rec["kind"] == 1)
    assert np.array_equal(rec["tool_end"][~arc], rec["end"][~arc])
    assert np.allclose(rec["tool_end"][arc], rec["end"][arc], atol=2e-4)
    for k, (_, words) in enumerate(written):
        xy = {w[0]: float(w[1:]) for w in words[1:] if w[0] in "XY"}
        if xy:
            assert (rec["end"][k][0], rec["end"][k][1]) == (xy["X"], xy["Y"])
    for first, last, pts, _, feed in contours:
        own = rec[(rec["line"] >= first - 1) & (rec["line"] <= last)]
        assert np.all(own["feed"] == feed) and np.all(own["compensation"] == 41)
    with sf_tch.compile(text, radius=R, strategy=0xA0600) as program:
        program.check()
        assert not program.warnings
        rec = program.toolpath.records
    motion = rec[rec["kind"] == 1]
    for first, last, pts, poly, _ in contours:
        assert contour_clearance(motion, first, last, pts) > R - TOL, first
        lead_in = motion[motion["line"] == first - 1][-1]
        lead_out = motion[motion["line"] == last + 2][0]
        before_out = motion[np.flatnonzero(motion["line"] == last + 2)[0] - 1]
        if poly is None or inner_start(poly, 41) > 0:
            assert np.allclose(lead_in["tool_end"], before_out["tool_end"], atol=1e-9), "the path does not close"
        assert np.array_equal(lead_out["tool_end"], lead_out["end"])
        own = motion[(motion["line"] >= first) & (motion["line"] <= last)]
        ring = exact_offset_ring(poly) if poly is not None else None
        if ring is not None:
            assert float(np.max(point_distances(own["tool_end"][:, :2], ring))) < TOL
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", sf_tch.GougeWarning)
        with sf_tch.compile(text, radius=R, strategy=0x20600) as program:
            program.check()
            warned = {w.line for w in program.warnings if w.number == ERR_COMP_GOUGE}
            assert len(program.warnings) < 49
    expected = set()
    for first, last, pts, poly, _ in contours:
        if poly is not None and R * (1 - math.cos(inner_start(poly, 41))) > 2e-3:
            expected |= {first, last}
    assert expected <= warned
    assert all(any(first <= line <= last for first, last, _, _, _ in contours) for line in warned)


def contour_clearance(motion, first, last, pts):
    """The least distance (shapely) of the tool path of the contour lines first..last
    from the contour (its arcs cut into chords 0.02 mm long: within 3e-4 mm)."""
    from sf_tch.toolpath import Toolpath
    own = np.flatnonzero((motion["line"] >= first) & (motion["line"] <= last))
    # each move of the tool path as a move of its own: from the previous tool end to its tool end
    moves = motion[own].copy()
    moves["start"], moves["end"] = motion["tool_end"][own - 1], moves["tool_end"]
    path = Toolpath(moves).points(step=0.02)[:, :2]
    return float(shapely.distance(LineString(path), LineString(pts)))


def exact_offset_ring(poly):
    """The ring of the inside offset of a polygon (shapely, exact up to the
    polygonisation of its round caps), None when it splits."""
    m0, els = polygon_contour(poly)
    shape = exact_offset(Polygon(poly), m0, els, R, True)
    return shape.exterior if shape.geom_type == "Polygon" else None
