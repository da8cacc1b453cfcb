"""The connection search of ConnectCNCEx_Plane (toolchain/machine/connect_search.pyx),
through tests/harness (the library's pipeline and the searches, no ctypes).

The oracle of the nearest point is the generated program's own geometry (lines,
arcs in G17/G18/G19, helices, a C axis), sampled densely in numpy and refined by
golden-section search around every sampled local minimum; lines in closed form.
The lookups are checked against the parts' own fields."""
import math

import numpy as np
import pytest

from sf_tch import ErrorNumber, abi

FOUND, NOT_FOUND, OFF_PART, BAD_ARGUMENT = 0, -1, -2, -3
PLANES = {17: (0, 1, 2), 18: (0, 2, 1), 19: (1, 2, 0)}
LETTERS = "XYZCBUVWAO"
@pytest.fixture(scope="session")
def ch():
    import harness
    return harness.load()


# ---- generated programs with known geometry ----------------------------------------

class Geometry:
    """One motion part: a line (start, end) or an arc/helix (plane axes a b, centre,
    radius, start angle, signed sweep, the other axes linear), all ten axes."""

    def __init__(self, start, end, arc=None):
        self.start = np.array(start, float)
        self.end = np.array(end, float)
        self.arc = arc                  # (a, b, centre_a, centre_b, radius, alpha0, sweep)

    def shifted(self, delta):
        arc = None
        if self.arc:
            a, b, ca, cb, r, alpha0, sweep = self.arc
            arc = (a, b, ca + delta[a], cb + delta[b], r, alpha0, sweep)
        return Geometry(self.start + delta, self.end + delta, arc)

    def points(self, u):
        """Points at the fractions u (array) of the part, shape (len(u), 10)."""
        u = np.asarray(u, float)[:, None]
        pts = self.start + (self.end - self.start) * u
        if self.arc:
            a, b, ca, cb, r, alpha0, sweep = self.arc
            ang = alpha0 + sweep * u[:, 0]
            pts[:, a] = ca + r * np.cos(ang)
            pts[:, b] = cb + r * np.sin(ang)
            pts[u[:, 0] == 0.0] = self.start     # the ends exactly, as programmed
            pts[u[:, 0] == 1.0] = self.end
        return pts


def _d2(pts, q, mask):
    sel = [k for k in range(10) if (mask or 0x3FF) >> k & 1]     # 0: every axis
    return ((pts[..., sel] - np.asarray(q)[sel]) ** 2).sum(axis=-1)


class Oracle:
    """Brute force over every part of `geos` ({part index: Geometry}): each part
    sampled at SAMPLES points, every sampled local minimum within SLACK of the part's
    sampled minimum refined by golden-section search (vectorised over them)."""
    SAMPLES = 2001
    SLACK = 0.2     # mm: > half the longest sampling step (an arc of r 15 turned 2 pi: 0.05 mm)

    def __init__(self, geos):
        self.ids = list(geos)
        self.geos = [geos[i] for i in self.ids]
        self.u = np.linspace(0.0, 1.0, self.SAMPLES)
        self.samples = np.stack([g.points(self.u) for g in self.geos])      # parts x samples x 10
        self.start = np.stack([g.start for g in self.geos])
        self.end = np.stack([g.end for g in self.geos])
        self.arc = np.array([g.arc is not None for g in self.geos])
        self.arcs = np.array([g.arc if g.arc else (0, 1, 0, 0, 0, 0, 0) for g in self.geos], float)

    def _points(self, which, u):
        """Points of parts `which` at fractions u (arrays of one length)."""
        pts = self.start[which] + (self.end[which] - self.start[which]) * u[:, None]
        a, b, ca, cb, r, alpha0, sweep = self.arcs[which].T
        arc = self.arc[which]
        rows = np.nonzero(arc)[0]
        ang = alpha0 + sweep * u
        pts[rows, a[rows].astype(int)] = (ca + r * np.cos(ang))[rows]
        pts[rows, b[rows].astype(int)] = (cb + r * np.sin(ang))[rows]
        return pts

    def part_distances(self, q, mask):
        """(true distance, u) of every part."""
        f = _d2(self.samples, q, mask)                                      # parts x samples
        left = np.concatenate([np.full((len(f), 1), np.inf), f[:, :-1]], axis=1)
        right = np.concatenate([f[:, 1:], np.full((len(f), 1), np.inf)], axis=1)
        local = (f < left) & (f <= right)          # a flat stretch: its first sample
        fd = np.sqrt(f)
        local &= fd <= fd.min(axis=1, keepdims=True) + self.SLACK
        which, at = np.nonzero(local)
        step = self.u[1]
        lo = np.clip(self.u[at] - step, 0.0, 1.0)
        hi = np.clip(self.u[at] + step, 0.0, 1.0)
        g = (math.sqrt(5) - 1) / 2
        for _ in range(50):
            m1, m2 = hi - g * (hi - lo), lo + g * (hi - lo)
            v1 = _d2(self._points(which, m1), q, mask)
            v2 = _d2(self._points(which, m2), q, mask)
            hi = np.where(v1 < v2, m2, hi)
            lo = np.where(v1 < v2, lo, m1)
        um = 0.5 * (lo + hi)
        dm = np.sqrt(_d2(self._points(which, um), q, mask))
        best = [(fd[w].min(), self.u[fd[w].argmin()]) for w in range(len(self.geos))]
        for w, d, x in zip(which, dm, um):
            if d < best[w][0]:
                best[w] = (d, x)
        return best

    def nearest(self, q, mask, max_distance=0.0, parts=None):
        """The least distance over the parts (indexes in `parts`) by the vendor's rule:
        beyond max_distance a part counts by its two ends."""
        best = math.inf
        for w, (d, _) in enumerate(self.part_distances(q, mask)):
            if parts is not None and self.ids[w] not in parts:
                continue
            if max_distance > 0 and d > max_distance:
                d = math.sqrt(min(_d2(self.samples[w, 0], q, mask), _d2(self.samples[w, -1], q, mask)))
            best = min(best, d)
        return best


def _fmt(v):
    return f"{v:.6f}"


def random_program(rng, n, helix=True, c_axis=True, relative=False):
    """G-code and the geometry of its motion parts in order: lines, arcs in every
    plane, helices, C moves. Returns (text, [Geometry]) from the start 0."""
    pos = np.zeros(10)
    lines = ["G90" if not relative else "G91", "F1000"]
    geos = []

    def emit(cmd, end, extra=""):
        words = []
        for k, letter in enumerate(LETTERS[:4]):
            if end[k] != pos[k] or k < 3:
                v = end[k] - pos[k] if relative else end[k]
                words.append(f"{letter}{_fmt(v)}")
        lines.append(f"{cmd} {' '.join(words)}{extra}")

    first = np.zeros(10)
    first[:3] = np.round(rng.uniform(-30, 30, 3), 6)
    emit("G0", first)
    geos.append(Geometry(pos.copy(), first.copy()))
    pos = first
    plane = 17
    for _ in range(n):
        kind = rng.random()
        end = pos.copy()
        if kind < 0.45:
            end[:3] = np.round(pos[:3] + rng.uniform(-15, 15, 3) * (rng.random() < 0.7), 6)
            if c_axis and rng.random() < 0.2:
                end[3] = np.round(pos[3] + rng.uniform(-20, 20), 6)
            emit("G1", end)
            geos.append(Geometry(pos.copy(), end.copy()))
        else:
            new_plane = int(rng.choice([17, 18, 19]))
            if new_plane != plane:
                lines.append(f"G{new_plane}")
                plane = new_plane
            a, b, nrm = PLANES[plane]
            r = float(rng.uniform(2, 15))
            alpha0 = float(rng.uniform(-math.pi, math.pi))
            ca, cb = round(pos[a] - r * math.cos(alpha0), 6), round(pos[b] - r * math.sin(alpha0), 6)
            r = math.hypot(pos[a] - ca, pos[b] - cb)
            alpha0 = math.atan2(pos[b] - cb, pos[a] - ca)
            turn = float(rng.uniform(0.3, 2 * math.pi - 0.3))
            ccw = rng.random() < 0.5
            end[a] = round(ca + r * math.cos(alpha0 + (turn if ccw else -turn)), 6)
            end[b] = round(cb + r * math.sin(alpha0 + (turn if ccw else -turn)), 6)
            if helix and rng.random() < 0.4:
                end[nrm] = round(pos[nrm] + rng.uniform(-10, 10), 6)
            # the sweep as the end point rounded gives it
            turn_back = math.atan2(end[b] - cb, end[a] - ca) - alpha0
            sweep = turn_back % (2 * math.pi) if ccw else -((-turn_back) % (2 * math.pi))
            centre = {a: ca - pos[a], b: cb - pos[b]}
            ijk = " ".join(f"{'IJK'[k]}{_fmt(centre[k])}" for k in sorted(centre))
            emit("G3" if ccw else "G2", end, " " + ijk)
            geos.append(Geometry(pos.copy(), end.copy(), (a, b, ca, cb, r, alpha0, sweep)))
        pos = end
    return "\n".join(lines) + "\n", geos


def motion_geometry(compiled, geos):
    """{part index: Geometry}: the generated geometry beside the compiled motion parts."""
    motion = [i for i, p in enumerate(compiled.parts()) if p["kind"] == 1]
    assert len(motion) == len(geos)
    return dict(zip(motion, geos))


def queries(rng, geos, count):
    """Random points round the program, points on it, and arc centres."""
    allpts = np.concatenate([g.points(np.linspace(0, 1, 9)) for g in geos.values()])
    lo, hi = allpts.min(axis=0) - 5, allpts.max(axis=0) + 5
    out = [rng.uniform(lo, hi) for _ in range(count)]
    keys = list(geos)
    for _ in range(count // 3):
        g = geos[keys[rng.integers(len(keys))]]
        out.append(g.points([rng.random()])[0] + rng.normal(0, 0.3, 10) * (rng.random() < 0.5))
    for g in list(geos.values())[:count // 3]:
        if g.arc:
            q = g.start.copy()
            a, b, ca, cb = g.arc[:4]
            q[a], q[b] = ca, cb
            out.append(q)
    return out


def check_hit(hit, geos, q, mask, expected, tol=2e-5):
    assert hit["distance"] == pytest.approx(expected, abs=tol)
    geo = geos[hit["part"]]
    u = hit["s"] / hit["length"] if hit["length"] > 0 else 0.0
    on_part = geo.points([u])[0]
    assert np.abs(np.asarray(hit["point"]) - on_part).max() < tol
    assert math.sqrt(_d2(np.asarray([hit["point"]]), q, mask)[0]) == pytest.approx(hit["distance"], abs=1e-9)


MASKS = (0x3, 0x5, 0x6, 0x7, 0x1, 0x9, 0x0, 0xB)


@pytest.mark.parametrize("seed", range(4))
def test_nearest_matches_a_brute_force_oracle_in_every_axis_mask(ch, seed):
    rng = np.random.default_rng(seed)
    text, geo_list = random_program(rng, 40)
    c = ch.compile(text)
    geos = motion_geometry(c, geo_list)
    oracle = Oracle(geos)
    pts = queries(rng, geos, 12)
    for mask in MASKS:
        rc, err, _ = c.build_index(mask)
        assert rc == FOUND and err is None
        for q in pts:
            rc, hit, err = c.nearest(q)
            assert rc == FOUND, err
            check_hit(hit, geos, q, mask, oracle.nearest(q, mask))


def test_nearest_on_a_single_plane_arc_is_exact(ch):
    """Quarter arcs r 10 round the origin in each plane: the distance from a point in
    the plane is | |q - c| - r | where its angle falls inside, else the nearer end."""
    for plane, (a, b, _) in PLANES.items():
        start, end = ["X0", "Y0", "Z0"], ["X0", "Y0", "Z0"]
        start[a] = f"{LETTERS[a]}10"
        end[b] = f"{LETTERS[b]}10"
        centre = {a: -10.0, b: 0.0}
        ijk = " ".join(f"{'IJK'[k]}{centre[k]}" for k in sorted(centre))
        c = ch.compile(f"G{plane}\nG0 {' '.join(start)}\nG3 {' '.join(end)} {ijk} F100\n")
        assert c.build_index((1 << a) | (1 << b))[0] == FOUND
        for angle, rho in ((0.3, 4.0), (1.2, 17.0), (-0.5, 12.0), (2.5, 3.0)):
            q = [0.0] * 10
            q[a], q[b] = rho * math.cos(angle), rho * math.sin(angle)
            rc, hit, _ = c.nearest(q, 0.0, 1)           # the arc alone, not the rapid to it
            if 0 <= angle <= math.pi / 2:
                expected = abs(rho - 10)
            else:
                ends = ((10.0, 0.0), (0.0, 10.0))
                expected = min(math.hypot(q[a] - x, q[b] - y) for x, y in ends)
            assert hit["distance"] == pytest.approx(expected, abs=1e-12)
            if 0 <= angle <= math.pi / 2:
                assert hit["s"] == pytest.approx(10 * angle, abs=1e-9)


def test_a_helix_seen_from_one_plane_axis_and_its_own_axis(ch):
    """Mask X Z on a G17 helix (x = r cos, z linear): the projected curve is no arc;
    the result agrees with the oracle, and a point on the curve is found at 0."""
    c = ch.compile("G0 X10 Y0 Z0\nG3 X10 Y0 Z-6.283185 I-10 J0 F100\n")
    geos = {1: Geometry([10, 0, 0] + [0] * 7, [10, 0, -6.283185] + [0] * 7,
                        (0, 1, 0.0, 0.0, 10.0, 0.0, 2 * math.pi))}
    oracle = Oracle(geos)
    assert c.build_index(0x5)[0] == FOUND
    rng = np.random.default_rng(5)
    for _ in range(30):
        q = [rng.uniform(-12, 12), 0.0, rng.uniform(-8, 2)] + [0.0] * 7
        rc, hit, _ = c.nearest(q, 0.0, 1)               # the helix alone
        check_hit(hit, geos, q, 0x5, oracle.nearest(q, 0x5))
    on_curve = geos[1].points([0.37])[0]
    assert c.nearest(on_curve, 0.0, 1)[1]["distance"] == pytest.approx(0.0, abs=1e-9)


def test_max_connection_distance_counts_far_parts_by_their_ends(ch):
    """The vendor's maxConnectionDistance: a part farther than it counts by its ends."""
    c = ch.compile("G1 X0 Y0 F100\nG1 X100 Y0\nG1 X100 Y100\n")    # part 0 has no length
    assert c.build_index(0x3)[0] == FOUND
    q = [40.0, 8.0] + [0.0] * 8
    assert c.nearest(q, 10.0)[1]["point"][:2] == pytest.approx([40.0, 0.0])  # within: the foot
    rc, hit, _ = c.nearest(q, 5.0)                  # beyond: the nearer vertex (0, 0), part 0's
    assert (hit["part"], hit["s"]) == (0, 0.0) and hit["distance"] == pytest.approx(math.hypot(40, 8))
    q = [70.0, 8.0] + [0.0] * 8                     # the vertex (100, 0): end of part 1
    rc, hit, _ = c.nearest(q, 5.0)
    assert hit["part"] == 1 and hit["s"] == pytest.approx(100.0) and hit["point"][:2] == [100.0, 0.0]
    for unlimited in (0.0, -1.0, math.inf, math.nan):
        assert c.nearest(q, unlimited)[1]["distance"] == pytest.approx(8.0)


@pytest.mark.parametrize("seed", range(2))
def test_max_connection_distance_against_the_oracle(ch, seed):
    rng = np.random.default_rng(10 + seed)
    text, geo_list = random_program(rng, 30)
    c = ch.compile(text)
    geos = motion_geometry(c, geo_list)
    oracle = Oracle(geos)
    for mask in (0x3, 0x7):
        assert c.build_index(mask)[0] == FOUND
        for q in queries(rng, geos, 9):
            for limit in (0.5, 3.0):
                rc, hit, _ = c.nearest(q, limit)
                check_hit(hit, geos, q, mask, oracle.nearest(q, mask, limit))


@pytest.mark.parametrize("seed", range(3))
def test_the_index_answers_as_every_part_does(ch, seed):
    """connect_nearest (the index) and connect_nearest_each (every part in order)
    evaluate a part alike: on large random programs of lines, arcs and helices their
    answers are the same to the last bit, for every mask, limit and range."""
    rng = np.random.default_rng(20 + seed)
    text, geo_list = random_program(rng, 1500)
    c = ch.compile(text)
    geos = motion_geometry(c, geo_list)
    n = c.n_parts
    for mask in MASKS:
        assert c.build_index(mask)[0] == FOUND
        for q in queries(rng, geos, 6):
            for limit, first, end in ((0.0, 0, n), (2.0, 0, n), (0.0, n // 3, n // 2)):
                by_index = c.nearest(q, limit, first, end)
                assert by_index == c.nearest_each(q, mask, limit, first, end)
                assert by_index[0] == FOUND


def test_a_hook_sees_every_candidate_and_may_change_it(ch):
    """The harness's hook: part 1 (G1 Z0) to distance 0 and x = -1; every other part
    1 mm farther, used on even parts only."""
    c = ch.compile(LOOKUP)
    q = [40.0, 0.0] + [0.0] * 8
    rc, plain, _ = c.nearest_each(q, 0x3)
    assert plain["part"] != 1 and plain["distance"] == pytest.approx(0.0)
    rc, hooked, _ = c.nearest_each(q, 0x3, hook=True)
    assert (hooked["part"], hooked["distance"], hooked["point"][0]) == (1, 0.0, -1.0)
    rc, hooked, _ = c.nearest_each(q, 0x3, 0.0, 2, c.n_parts, hook=True)   # without part 1
    by_part = {}
    for i, p in enumerate(c.parts()):
        if p["kind"] == 1 and i >= 2:
            d = c.nearest_each(q, 0x3, 0.0, i, i + 1)[1]["distance"]
            by_part[i] = d + 1.0 if i % 2 == 0 else d       # odd: the change is not used
    assert hooked["distance"] == pytest.approx(min(by_part.values()))
    assert hooked["part"] == min(by_part, key=lambda i: (by_part[i], i))
    assert c.nearest_each(q, 0x400)[0] == BAD_ARGUMENT
    assert c.nearest_each(q, 0x3, 0.0, 2, 3)[0] == NOT_FOUND          # an M function only


def test_a_part_range_restricts_the_search(ch):
    rng = np.random.default_rng(3)
    text, geo_list = random_program(rng, 60)
    c = ch.compile(text)
    geos = motion_geometry(c, geo_list)
    oracle = Oracle(geos)
    assert c.build_index(0x7)[0] == FOUND
    n = c.n_parts
    for q in queries(rng, geos, 6):
        for first, end in ((0, 10), (20, 25), (n - 5, n), (30, n + 100)):
            inside = [i for i in geos if first <= i < min(end, n)]
            rc, hit, err = c.nearest(q, 0.0, first, end)
            assert rc == FOUND, err
            assert first <= hit["part"] < end
            check_hit(hit, geos, q, 0x7, oracle.nearest(q, 0x7, parts=inside))


def test_a_run_placed_elsewhere_moves_the_trajectory(ch):
    """A relative program (G91) run from another start: every part moves with the
    start (placed_part_to_gm), in every axis; the oracle's geometry is moved alike."""
    rng = np.random.default_rng(7)
    text, geo_list = random_program(rng, 30, relative=True)
    c = ch.compile(text)
    start = np.array([12.5, -40.0, 7.0, 30.0, 0, 0, 0, 0, 0, 0])
    c.place(start)
    geos = {i: g.shifted(start) for i, g in motion_geometry(c, geo_list).items()}
    oracle = Oracle(geos)
    for mask in (0x3, 0xF, 0x0):
        assert c.build_index(mask)[0] == FOUND
        for q in queries(rng, geos, 8):
            rc, hit, _ = c.nearest(q)
            check_hit(hit, geos, q, mask, oracle.nearest(q, mask))


@pytest.mark.parametrize("relative", (False, True))
def test_the_parts_own_geometry_equals_the_records_one(ch, relative):
    """segment_of_placed_part takes the geometry from the part and moves it by the
    placement; placed_part_to_gm + segment_of_gm (the API's record) give the same
    numbers, unmoved and moved -- absolute programs (only the head follows the
    start, the part that names an axis first is reshaped) and relative ones."""
    rng = np.random.default_rng(1)
    text, _ = random_program(rng, 50, relative=relative)
    c = ch.compile(("G0 Z5\nG91 G1 X1 F100\nG90\n" if not relative else "") + text)
    motion = [i for i, p in enumerate(c.parts()) if p["kind"] == 1]
    for i in motion:
        assert c.segment(i) == c.segment(i, via_record=True)
    c.place([3.0, -4.0, 2.5, 10.0, 0, 0, 0, 0, 0, 0])
    for i in motion:
        assert c.segment(i) == c.segment(i, via_record=True)


def test_a_large_program_against_a_vectorised_oracle(ch):
    """20,000 lines of a random walk with jumps, the whole index at work: every
    answer equals the exact nearest point over all parts (numpy, closed form)."""
    rng = np.random.default_rng(11)
    n = 20000
    steps = rng.normal(0, 1.0, (n, 2))
    jumps = rng.random(n) < 0.01
    steps[jumps] = rng.uniform(-300, 300, (jumps.sum(), 2))
    pts = np.round(np.cumsum(steps, axis=0), 6)
    text = "G0 X0 Y0\nF1000\n" + "".join(f"G1 X{x:.6f} Y{y:.6f}\n" for x, y in pts)
    c = ch.compile(text)
    assert c.build_index(0x3)[0] == FOUND
    a = np.vstack([[0.0, 0.0], pts[:-1]])
    b = pts
    d = b - a
    dd = (d * d).sum(axis=1)
    lo, hi = pts.min(axis=0) - 20, pts.max(axis=0) + 20
    for q in rng.uniform(lo, hi, (40, 2)):
        u = np.clip(((q - a) * d).sum(axis=1) / np.where(dd > 0, dd, 1), 0, 1)
        expected = np.sqrt((((a + u[:, None] * d) - q) ** 2).sum(axis=1)).min()
        rc, hit, _ = c.nearest(list(q) + [0.0] * 8)
        assert hit["distance"] == pytest.approx(expected, abs=1e-9)


# ---- lookups ---------------------------------------------------------------------------

LOOKUP = """G0 X0 Y0 Z5
G1 Z0 F500
M3
G1 X10 Y0
G1 X10 Y10 M8
G2 X20 Y10 I5 J0
M5
G4 F0.5
G1 X30 Y0
M3
G1 X40
M3
M9
G1 X50 Y5
"""


def test_a_line_connects_to_its_first_part_or_the_end_of_its_run(ch):
    c = ch.compile(LOOKUP)
    parts = c.parts()
    for line in range(1, 15):
        first = next(i for i, p in enumerate(parts) if p["line"] == line)
        last = first
        while last + 1 < len(parts) and parts[last + 1]["line"] == line:
            last += 1
        rc, hit, _ = c.line([line])
        assert rc == FOUND and hit["part"] == first and hit["s"] == 0.0
        rc, hit_end, _ = c.line([line, c.main_file_idx], at_end=True)
        assert rc == FOUND and hit_end["part"] == last
        seg = c.segment(last)
        assert hit_end["point"] == seg["end"] and hit_end["s"] == seg["length"] * (parts[last]["kind"] == 1)
    assert c.line([5], at_end=True)[1]["part"] == c.line([5])[1]["part"] + 1   # G1 then M8
    rc, hit, err = c.line([99])
    assert (rc, hit) == (NOT_FOUND, None)
    assert err == (ErrorNumber.CONNECT_NO_LINE, 0, 99, "ConnectCNCEx_Plane: no part at line 99 of file 0")
    assert c.line([3, 7])[0] == NOT_FOUND                  # another file
    for bad in ([2.5], [math.nan], [0], [3, 0.5], []):
        rc, _, err = c.line(bad)
        assert rc == BAD_ARGUMENT and err[0] == ErrorNumber.CONNECT_BAD_ARGUMENT, bad


def test_a_g_code_index_gives_its_part(ch):
    c = ch.compile(LOOKUP)
    for i, p in enumerate(c.parts()):
        rc, hit, _ = c.gindex([p["gcode_index"]])
        assert rc == FOUND and hit["part"] == i
        seg = c.segment(i)
        assert hit["point"] == seg["start"]
        assert c.gindex([p["gcode_index"]], at_end=True)[1]["point"] == seg["end"]
    rc, _, err = c.gindex([1])                                   # odd: no inserted part here
    assert rc == NOT_FOUND and err[0] == ErrorNumber.CONNECT_NO_GINDEX and "index 1" in err[3]
    assert c.gindex([1e12])[0] == BAD_ARGUMENT


def test_the_nearest_point_of_one_part(ch):
    c = ch.compile(LOOKUP)
    parts = c.parts()
    arc = next(i for i, p in enumerate(parts) if p["func"] == 2)
    g = parts[arc]["gcode_index"]
    rc, hit, _ = c.gindex_nearest([g], [15, 20, 0] + [0] * 7, 0x3)   # above the arc's top
    assert rc == FOUND and hit["part"] == arc
    assert hit["point"][:2] == pytest.approx([15.0, 15.0]) and hit["distance"] == pytest.approx(5.0)
    assert hit["s"] == pytest.approx(hit["length"] / 2)
    rc, hit, _ = c.gindex_nearest([g], [15, 20, 0] + [0] * 7, 0x3, 2.0)   # beyond the limit: an end
    assert hit["s"] in (0.0, hit["length"]) and hit["distance"] == pytest.approx(math.hypot(5, 10))
    assert c.gindex_nearest([g], [math.nan] * 10, 0x3)[0] == BAD_ARGUMENT
    assert c.gindex_nearest([g], [0] * 10, 0x400)[0] == BAD_ARGUMENT


def test_exact_point_on_its_part(ch):
    c = ch.compile(LOOKUP)
    parts = c.parts()
    arc = next(i for i, p in enumerate(parts) if p["func"] == 2)
    g = parts[arc]["gcode_index"]
    top = [15.0, 15.0, 0.0] + [0.0] * 7
    rc, hit, err = c.exact(top + [g])
    assert rc == FOUND and err is None and hit["part"] == arc
    assert hit["s"] == pytest.approx(hit["length"] / 2) and hit["distance"] < 1e-9
    rc, hit, err = c.exact([15.0, 15.01, 0.0] + [0.0] * 7 + [g], 0, 1e-3)
    assert rc == OFF_PART and hit["distance"] == pytest.approx(0.01)
    assert err[:3] == (ErrorNumber.CONNECT_OFF_PART, 0, 6)
    assert err[3] == f"ConnectCNCEx_Plane: the point lies 0.01 mm from the part with G-code index {g} (tolerance 0.001 mm)"
    assert c.exact([15.0, 15.01, 0.0] + [0.0] * 7 + [g], 0, 0.02)[0] == FOUND
    assert c.exact([15.0, 15.01, 3.0] + [0.0] * 7 + [g], 0x3, 0.02)[0] == FOUND   # Z not asked
    assert c.exact(top)[0] == BAD_ARGUMENT                        # 10 coordinates only
    assert c.exact(top + [g], 0, -1.0)[0] == BAD_ARGUMENT
    assert c.exact(top + [g + 1000])[0] == NOT_FOUND


def mfunc_parts(c, m):
    return [i for i, p in enumerate(c.parts()) if p["kind"] == 2 and p["func"] == m and not p["flags"] & 2]


def test_the_nth_occurrence_of_an_m_function(ch):
    c = ch.compile(LOOKUP)
    m3 = mfunc_parts(c, 3)
    assert len(m3) == 3
    # absolute: n > 0 from the start, n <= 0 back from the end
    for n in (1, 2, 3):
        assert c.mfunc([n, 3])[1]["part"] == m3[n - 1]
    for n in (0, -1, -2):
        assert c.mfunc([n, 3])[1]["part"] == m3[-1 + n]
    rc, _, err = c.mfunc([4, 3])
    assert rc == NOT_FOUND and err[0] == ErrorNumber.CONNECT_NO_MFUNC
    assert err[3] == "ConnectCNCEx_Plane: occurrence n = 4 of M3 not found (3 in that direction)"
    # relative to the current part: n > 0 after it, n <= 0 at or before it
    for current in range(-1, c.n_parts):
        after = [i for i in m3 if i > current]
        before = [i for i in m3 if i <= current][::-1]
        for n in (1, 2):
            rc, hit, _ = c.mfunc([n, 3], relative=True, current=current)
            assert (hit["part"] if rc == FOUND else None) == (after[n - 1] if len(after) >= n else None)
        for n in (0, -1):
            rc, hit, _ = c.mfunc([n, 3], relative=True, current=current)
            assert (hit["part"] if rc == FOUND else None) == (before[-n] if len(before) > -n else None)
    # where the M function stands: the end of the motion before it
    hit = c.mfunc([1, 8])[1]
    assert hit["point"][:3] == [10.0, 10.0, 0.0] and hit["s"] == 0.0 and hit["length"] == 0.0
    # the vendor's sign rules: at the start only n > 0, at the end only n <= 0
    assert c.mfunc([0, 3], status=-30)[0] == BAD_ARGUMENT
    assert c.mfunc([1, 3], status=-30)[0] == FOUND
    rc, _, err = c.mfunc([1, 3], status=-32)
    assert rc == BAD_ARGUMENT
    assert err[3] == "ConnectCNCEx_Plane: coords[0] = 1: at the end of the trajectory only n <= 0"
    assert c.mfunc([0, 3], status=-32)[0] == FOUND
    assert c.mfunc([1])[0] == BAD_ARGUMENT and c.mfunc([1, 3.5])[0] == BAD_ARGUMENT


def test_inserted_m_functions_do_not_count(ch):
    """mFuncInsertTable M functions (inserted by the planner) are not occurrences."""
    p = abi.GCODE_PARAMETERS.from_buffer_copy(ch.default_params())
    p.mFuncInsertTable[2].mFunc = 1050          # before every rapid
    p.MfuncInsertType = 1
    c = ch.compile("G1 X10 F100\nG0 X20\nM1050\nG0 X30\n", bytes(p))
    parts = c.parts()
    inserted = [i for i, q in enumerate(parts) if q["func"] == 1050 and q["kind"] == 2 and q["flags"] & 2]
    programmed = mfunc_parts(c, 1050)
    assert inserted and len(programmed) == 1
    assert c.mfunc([1, 1050])[1]["part"] == programmed[0]
    assert c.mfunc([2, 1050])[0] == NOT_FOUND


def test_errors_of_the_index_and_of_a_program_without_motion(ch):
    c = ch.compile("M3\nM5\n")
    assert c.build_index(0x3)[0] == FOUND
    rc, hit, err = c.nearest([0] * 10)
    assert rc == NOT_FOUND and err[0] == ErrorNumber.CONNECT_NO_MOTION
    assert err[3] == "ConnectCNCEx_Plane: no motion to connect to in parts 0 to 2 (the program has 2)"
    c = ch.compile(LOOKUP)
    rc, err, _ = c.build_index(0x400)
    assert rc == BAD_ARGUMENT and err[3] == "ConnectCNCEx_Plane: axesForCalc = 1024: bits above 0x3FF"
    assert c.build_index(0x3)[0] == FOUND
    assert c.nearest([0] * 10, 0.0, 5, 5)[0] == NOT_FOUND
    assert c.nearest([0] * 10, 0.0, 2, 3)[0] == NOT_FOUND           # an M function only
    assert ch.bad_argument("nType", 7, "no such connect type") == (
        BAD_ARGUMENT, (ErrorNumber.CONNECT_BAD_ARGUMENT, -1, 0, "ConnectCNCEx_Plane: nType = 7: no such connect type"))
    rc, _, err = c.nearest([0, math.inf] + [0] * 8)
    assert rc == BAD_ARGUMENT and err[3] == "ConnectCNCEx_Plane: coords[1] = inf: not a finite number"
    assert c.nearest([0, 0, math.nan] + [0] * 7)[0] == FOUND       # Z is not asked


def test_axes_that_never_move_stay_out_of_the_boxes(ch):
    """C, never moved, adds the same distance to every part; with X it gives X's
    answer and its own offset."""
    c = ch.compile("G0 X0 Y0\nG1 X10 Y5 F100\nG1 X20 Y0\n")
    assert c.build_index(0x9)[0] == FOUND
    assert c.index_dims() == [0]
    rc, hit, _ = c.nearest([12, 0, 0, 3] + [0] * 6)
    assert hit["distance"] == pytest.approx(3.0) and hit["point"][0] == pytest.approx(12.0)
    assert c.build_index(0x8)[0] == FOUND and c.index_dims() == []
    rc, hit, _ = c.nearest([50, 50, 0, 4] + [0] * 6)    # every point as far: the first part's start
    assert (hit["part"], hit["s"], hit["distance"]) == (0, 0.0, 4.0)


def test_the_search_follows_the_compensated_path(ch):
    """G41 with a 1 mm tool round a 10 mm square run counter-clockwise, entered from
    its centre: the tool centre runs 1 mm inside; a point 2.5 mm above the bottom
    edge is 1.5 mm from the tool's path (2.5 mm from the programmed one)."""
    p = abi.GCODE_PARAMETERS.from_buffer_copy(ch.default_params())
    for slot in range(8):
        p.correction[slot].size = 1.0
    c = ch.compile("G0 X5 Y5\nG41\nG1 X5 Y0 F100\nG1 X10 Y0\nG1 X10 Y10\nG1 X0 Y10\nG1 X0 Y0\n"
                   "G1 X5 Y0\nG40\nG1 X5 Y5\n", bytes(p))
    assert c.build_index(0x3)[0] == FOUND
    rc, hit, _ = c.nearest([7.0, 2.5] + [0.0] * 8)
    assert hit["distance"] == pytest.approx(1.5, abs=1e-9)
    assert hit["point"][:2] == pytest.approx([7.0, 1.0], abs=1e-9)
    assert c.parts()[hit["part"]]["line"] == 4
    rc, hit, _ = c.line([5], at_end=True)                  # the end of the right edge: a corner inside
    assert hit["point"][:2] == pytest.approx([9.0, 9.0], abs=1e-9)
