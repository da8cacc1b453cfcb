"""A CAM-like cutting job of many short compensated contours (the kind a nesting CAM
writes for a plasma or laser table).

    python benchmarks/cam_job.py FILE [--lines 1000000] [--seed 1]

Each contour is entered and left the same way:

    G0 X.. Y..          (5 mm before the start, diagonally)
    M51                 (tool on)
    G41
    G1 X.. Y.. F..      (lead-in to the contour's start)
    ...                 (the contour, counter-clockwise, back to its start)
    G40
    G1 X.. Y..          (lead-out to where the lead-in began)
    M50                 (tool off)

The contours are rounded rectangles (four lines and four quarter arcs, started where
the last arc meets the first line) or polygons of 4 to 27 vertices at random radii
(vertices at least 6 degrees apart round the centre, edges at least 1 mm), started at
the vertex on the centre's +X side; most polygons are not convex, and most start at a
convex vertex: with G41 on a counter-clockwise contour the tool runs inside, so the
start is an inner corner of the tool path. The contours stand on a grid of 100 mm,
50 a row. Absolute coordinates (G90), four decimals.
"""
import argparse
import math
import random
from pathlib import Path

PITCH = 100.0
PER_ROW = 50


def _polygon(rnd: random.Random) -> list:
    """Vertices (relative to the centre), counter-clockwise, the first on +X."""
    while True:
        size = rnd.uniform(15, 45)
        angles = [0.0]
        while True:
            a = angles[-1] + math.radians(rnd.uniform(6, 40))
            if a > 2 * math.pi - math.radians(6):
                break
            angles.append(a)
        if len(angles) < 4 or len(angles) > 27:
            continue
        pts = []
        for a in angles:
            r = size * rnd.uniform(0.6, 1.0)
            pts.append((r * math.cos(a), r * math.sin(a)))
        if all(math.dist(pts[k], pts[k - 1]) >= 1.0 for k in range(len(pts))):
            return pts


def _contour(rnd: random.Random, cx: float, cy: float) -> list:
    """The lines of one contour centred at (cx, cy)."""
    feed = rnd.choice((1500, 2000, 3000))
    out = []
    if rnd.random() < 0.46:
        w, h = rnd.uniform(10, 40), rnd.uniform(10, 40)
        q = rnd.uniform(1, min(w, h) / 3)
        # start where the bottom line begins (after the lower left arc)
        x0, x1, y0, y1 = cx - w, cx + w, cy - h, cy + h
        start = (x0 + q, y0)
        moves = [f"G1 X{x1 - q:.4f} Y{y0:.4f}",
                 f"G3 X{x1:.4f} Y{y0 + q:.4f} I0.0000 J{q:.4f}",
                 f"G1 X{x1:.4f} Y{y1 - q:.4f}",
                 f"G3 X{x1 - q:.4f} Y{y1:.4f} I{-q:.4f} J0.0000",
                 f"G1 X{x0 + q:.4f} Y{y1:.4f}",
                 f"G3 X{x0:.4f} Y{y1 - q:.4f} I0.0000 J{-q:.4f}",
                 f"G1 X{x0:.4f} Y{y0 + q:.4f}",
                 f"G3 X{x0 + q:.4f} Y{y0:.4f} I{q:.4f} J0.0000"]
    else:
        pts = [(cx + x, cy + y) for x, y in _polygon(rnd)]
        start = pts[0]
        moves = [f"G1 X{x:.4f} Y{y:.4f}" for x, y in pts[1:] + pts[:1]]
    sx, sy = start
    out.append(f"G0 X{sx - 5:.4f} Y{sy - 5:.4f}")
    out.append("M51")
    out.append("G41")
    out.append(f"G1 X{sx:.4f} Y{sy:.4f} F{feed}")
    out.extend(moves)
    out.append("G40")
    out.append(f"G1 X{sx - 5:.4f} Y{sy - 5:.4f}")
    out.append("M50")
    return out


def write_cam_job(path: Path, lines: int, seed: int = 1) -> int:
    """Writes about `lines` lines (whole contours, at least one); returns the number
    of contours."""
    rnd = random.Random(seed)
    out = ["G90", "G17"]
    n = 0
    while len(out) < lines - 1 or n == 0:
        out.extend(_contour(rnd, (n % PER_ROW) * PITCH, (n // PER_ROW) * PITCH))
        n += 1
    out.append("M2")
    Path(path).write_text("\n".join(out) + "\n")
    return n


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("file")
    ap.add_argument("--lines", type=int, default=1_000_000)
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args()
    n = write_cam_job(Path(args.file), args.lines, args.seed)
    print(f"{args.file}: {n} contours")


if __name__ == "__main__":
    main()
