"""Shared helpers of the compensation tests: contour generators, tool path sampling
and the shapely oracle (exact offset curves)."""
import math
import random
import re

import numpy as np


def arc_centre(p, q, h):
    """Centre, radius and func (2/3) of the minor arc from p to q whose middle lies h
    to the right of the chord (h > 0: CCW arc, h < 0: CW arc)."""
    cx, cy = (p[0] + q[0]) / 2, (p[1] + q[1]) / 2
    dx, dy = q[0] - p[0], q[1] - p[1]
    c = math.hypot(dx, dy)
    nx, ny = -dy / c, dx / c                    # left normal
    R = (c * c / 4 + h * h) / (2 * abs(h))
    off = R - abs(h)
    if h > 0:
        return (cx + nx * off, cy + ny * off), R, 3
    return (cx - nx * off, cy - ny * off), R, 2


def contour_parts(elements, comp, start, approach, slot=None):
    """Parts of a program: G1 from `approach` .. no: the current position is `approach`;
    the G41/G42 block goes to `start`, then the contour `elements` (dicts), then G40 back."""
    parts = [dict(func=1, e=approach, comp=40)]
    parts.append(dict(func=1, e=start, comp=comp))
    for el in elements:
        d = dict(el)
        d["comp"] = comp
        if slot is not None:
            d["slot"] = slot
        parts.append(d)
    parts.append(dict(func=1, e=approach, comp=40))
    return parts


def polygon_elements(points, arcs=None):
    """Closed contour through points starting at the middle of the first edge; arcs maps
    an edge index (not 0) to a sagitta."""
    arcs = arcs or {}
    n = len(points)
    m0 = ((points[0][0] + points[1][0]) / 2, (points[0][1] + points[1][1]) / 2)
    els = [dict(func=1, e=points[1])]
    for i in range(1, n):
        p, q = points[i], points[(i + 1) % n]
        if i in arcs:
            c, R, func = arc_centre(p, q, arcs[i])
            els.append(dict(func=func, e=q, cc=c, radius=R))
        else:
            els.append(dict(func=1, e=q))
    els.append(dict(func=1, e=m0))
    return m0, els


def rounded_rectangle(x0, y0, w, h, rad):
    pts = []
    m0 = (x0 + w / 2, y0)
    els = [dict(func=1, e=(x0 + w - rad, y0)),
           dict(func=3, e=(x0 + w, y0 + rad), cc=(x0 + w - rad, y0 + rad), radius=rad),
           dict(func=1, e=(x0 + w, y0 + h - rad)),
           dict(func=3, e=(x0 + w - rad, y0 + h), cc=(x0 + w - rad, y0 + h - rad), radius=rad),
           dict(func=1, e=(x0 + rad, y0 + h)),
           dict(func=3, e=(x0, y0 + h - rad), cc=(x0 + rad, y0 + h - rad), radius=rad),
           dict(func=1, e=(x0, y0 + rad)),
           dict(func=3, e=(x0 + rad, y0), cc=(x0 + rad, y0 + rad), radius=rad),
           dict(func=1, e=m0)]
    return m0, els


def reverse_contour(m0, els):
    """The same closed contour travelled the other way."""
    pts = [m0] + [tuple(e["e"][:2]) for e in els]
    out = []
    for i in range(len(els) - 1, -1, -1):
        el = els[i]
        target = pts[i]
        d = dict(el)
        d["e"] = target
        if el["func"] in (2, 3):
            d["func"] = 5 - el["func"]
        out.append(d)
    return m0, out


def sample_arc(s, e, c, ccw, r=None, step=0.02):
    a0 = math.atan2(s[1] - c[1], s[0] - c[0])
    a1 = math.atan2(e[1] - c[1], e[0] - c[0])
    if r is None:
        r = math.hypot(s[0] - c[0], s[1] - c[1])
    d = a1 - a0
    if ccw:
        while d <= 1e-12:
            d += 2 * math.pi
    else:
        while d >= -1e-12:
            d -= 2 * math.pi
    n = max(2, int(abs(d) * r / step) + 2)
    t = np.linspace(0, 1, n)
    return np.column_stack([c[0] + r * np.cos(a0 + d * t), c[1] + r * np.sin(a0 + d * t)])


def programmed_polyline(m0, els, step=0.005, sagitta=None):
    """The contour as a polyline: arcs cut by `step`, or into chords whose sagitta is
    at most `sagitta`."""
    pts = [np.array([m0])]
    cur = m0
    for el in els:
        e = tuple(el["e"][:2])
        if el["func"] in (2, 3):
            if sagitta is not None:
                R = math.dist(cur, el["cc"][:2])
                step = R * 2 * math.sqrt(2 * sagitta / R)
            pts.append(sample_arc(cur, e, el["cc"], el["func"] == 3, step=step)[1:])
        else:
            pts.append(np.array([e]))
        cur = e
    return np.vstack(pts)


def tool_path(out, first, last, step=0.02):
    """Sampled tool path of the output parts first..last (inclusive, output indexes)."""
    pts = [np.array([out[first - 1]["ce"][:2]])]
    cur = tuple(out[first - 1]["ce"][:2])
    for p in out[first:last + 1]:
        e = tuple(p["ce"][:2])
        if p["func"] in (2, 3) and p["radius"] > 0:
            pts.append(sample_arc(cur, e, p["cc"][:2], p["func"] == 3, r=p["radius"], step=step)[1:])
        else:
            pts.append(np.array([cur, e]))
        cur = e
    return np.vstack(pts)


def random_convex(rng, n, radius=30.0):
    angles = sorted(rng.uniform(0, 2 * math.pi) for _ in range(n))
    # keep the angles apart so that no edge is tiny
    angles = [i * 2 * math.pi / n + rng.uniform(-0.25, 0.25) * 2 * math.pi / n for i in range(n)]
    return [(radius * math.cos(a), radius * math.sin(a)) for a in angles]


def star_cases(count, seed, star, r_max):
    """(points, r, g, mode) of `count` polygons star(rng, r) (None: drawn again): tool
    radius r from 0.1 to r_max, G41 or G42, entry strategy 0 or 1."""
    rng = random.Random(seed)
    cases = []
    while len(cases) < count:
        r = rng.uniform(0.1, r_max)
        pts = star(rng, r)
        if pts is not None:
            cases.append((pts, r, rng.choice((41, 42)), rng.choice((0, 1))))
    return cases


def random_star(rng, n, r_in=18.0, r_out=35.0):
    pts = []
    for i in range(n):
        a = i * 2 * math.pi / n
        r = r_out if i % 2 == 0 else rng.uniform(r_in, r_out - 5)
        pts.append((r * math.cos(a), r * math.sin(a)))
    return pts


# warning 601 in the harness's warning text (the output log's lines)
GOUGE_WARNING = re.compile(r"line (\d+): Equidistant error on line (\d+): the tool cuts (\S+) mm into the contour")


def gouge_warnings(warn):
    """{line: depth in mm} of the warnings 601 (one per line)."""
    found = {}
    for m in GOUGE_WARNING.finditer(warn):
        line = int(m.group(1))
        assert int(m.group(2)) == line and line not in found, warn
        found[line] = float(m.group(3))
    return found


def line_depths(out, contour, r, start_point=None, step=0.002):
    """Shapely's oracle of warning 601: {line: how far the tool path of that line's
    moves comes into the contour polyline, r less their least distance from it} for
    the compensated moves after the G41/G42 block (output parts with comp 41/42),
    without the ramps of entry strategy 1 (moves from or to start_point)."""
    import shapely
    from shapely.geometry import LineString
    idx = [k for k, p in enumerate(out) if p["comp"] != 40]
    poly = LineString(contour)
    depths = {}
    for k in range(idx[0] + 1, idx[-1] + 1):
        seg = tool_path(out, k, k, step=step)
        if start_point is not None and (np.hypot(*(seg[0] - start_point)) < 1e-6
                                        or np.hypot(*(seg[-1] - start_point)) < 1e-6):
            continue
        if np.ptp(seg, axis=0).max() == 0:
            continue                                # a removed part: no motion
        depth = r - shapely.distance(LineString(seg), poly)
        line = out[k]["line"]
        depths[line] = max(depths.get(line, -math.inf), depth)
    return depths


def check_gouge_warnings(out, warn, contour, r, start_point=None, allowance=1e-3):
    """The warnings 601 against shapely: every line whose tool path comes more than the
    allowance (tolerance[1]) into the contour has one (unless the compilation's 50
    warnings ran out), with that depth (1e-4 mm: the oracle samples arcs), and no
    other line has one. Returns {line: depth}."""
    warned = gouge_warnings(warn)
    depths = line_depths(out, contour, r, start_point)
    for line, depth in warned.items():
        assert line in depths and abs(depth - depths[line]) < 1e-4, (line, depth, depths.get(line))
    missed = {line: d for line, d in depths.items() if d > allowance + 1e-4 and line not in warned}
    assert not missed or "further warnings suppressed" in warn, f"cuts into the contour without warning 601: {missed}"
    return warned
