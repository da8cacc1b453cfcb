"""Tool radius compensation: corners and the start and end strategies on a square
whose tool path is known in closed form, compared within 1e-6 mm on the compensated
ends (m_calcE) DriverGFunc receives (docs/compensation.md, docs/structures.md)."""
import math

from .checks import Differs, check, expect, near, near_point
from .dialect import SEED_PROGRAM

C, S = "compensation.md", "structures.md"
TOL = 1e-6


def square(g):
    """A square of side 20 about the origin, entered and left at (0, -10) from (0, -20),
    counter-clockwise: G41 puts the tool inside, G42 outside."""
    return (f"G{g} G1 X0 Y-10 F1000\nG1 X10 Y-10\nG1 X10 Y10\nG1 X-10 Y10\nG1 X-10 Y-10\nG1 X0 Y-10\n"
            "G40 G1 X0 Y-20\n")


def _run(host, code, radius=2.0, slot=0, strategy=None, coords=(0.0, -20.0, 0.0), **params):
    def edit(p):
        p.correction[slot].size = radius
        if strategy is not None:
            p.correctionStrategy = (p.correctionStrategy & ~0xFF & ~0x800000 & ~0x400000) | strategy
    host.set_params(0, edit=edit, **params)
    return [p for p in host.simulate(code, coords=coords).of("G")]


def _ends(parts):
    return [tuple(round(v, 6) for v in p["ce"][:2]) for p in parts]


@check("compensation", "inner_corners", C, "Geometry",
       "inner corners: the tool centre goes to the intersection of the consecutive offsets")
def _(host):
    got = _ends(_run(host, square(41)))
    expect([(0, -8), (8, -8), (8, 8), (-8, 8), (-8, -8), (0, -8), (0, -20)], got, "compensated ends (G41, r 2)")


@check("compensation", "outer_corners_arcs", C, "Geometry",
       "outer corners: an arc about the programmed corner with the tool radius is inserted")
def _(host):
    parts = _run(host, square(42), slot=1)
    arcs = [p for p in parts if p["func"] in (2, 3)]
    expect(4, len(arcs), "inserted arcs")
    corners = [(10, -10), (10, 10), (-10, 10), (-10, -10)]
    for arc, corner in zip(arcs, corners):
        near_point(corner, arc["cc"][:2], TOL, "arc centre")
        near(2.0, arc["radius"], TOL, "arc radius")
        expect(3, arc["func"], "direction (G42 round a counter-clockwise square)")
    k = parts.index(arcs[0])
    near_point((10, -12), parts[k - 1]["ce"][:2], TOL, "end before the first corner")
    near_point((12, -10), arcs[0]["ce"][:2], TOL, "end of the first corner's arc")


@check("compensation", "outer_corners_intersection", S, "correctionStrategy",
       "0x800000: outer corners take the intersection of the extended offsets when within three radii")
def _(host):
    parts = _run(host, square(42), slot=1, strategy=0x800000)
    expect([], [p["func"] for p in parts if p["func"] in (2, 3)], "inserted arcs")
    near_point((12, -12), parts[1]["ce"][:2], TOL, "first corner")
    near_point((12, 12), parts[2]["ce"][:2], TOL, "second corner")


@check("compensation", "outer_corner_limit", S, "correctionStrategy",
       "0x800000 | 0x400000: the limit is two radii; an intersection farther away gets an arc")
def _(host):
    a = math.radians(-140.0)
    end = (10 * math.cos(a), 10 * math.sin(a))
    code = (f"G41 G1 X-10 Y0 F1000\nG1 X0 Y0\nG1 X{end[0]:.9f} Y{end[1]:.9f}\n"
            f"G40 G1 X{end[0]:.9f} Y{end[1] - 10:.9f}\n")
    three = _run(host, code, strategy=0x800000)
    expect(0, sum(p["func"] in (2, 3) for p in three), "arcs with 0x800000 (meeting 5.85 mm away, < 3 r)")
    near(2 / math.cos(math.radians(70)), math.hypot(*three[1]["ce"][:2]), TOL, "corner's distance")
    two = _run(host, code, strategy=0x800000 | 0x400000)
    expect(1, sum(p["func"] in (2, 3) for p in two), "arcs with 0x400000 (> 2 r)")


@check("compensation", "start_end_strategy_0", C, "Start and end (correctionStrategy low byte)",
       "low byte 0: the G41 move ends on the perpendicular of the next move, the move before G40 on its own")
def _(host):
    got = _ends(_run(host, square(41), strategy=0))
    expect((0, -8), got[0], "end of the G41 move")
    expect((0, -8), got[-2], "end of the move before G40")
    expect((0, -20), got[-1], "end of the G40 move")


@check("compensation", "start_end_strategy_1", C, "Start and end (correctionStrategy low byte)",
       "low byte 1: the G41 move and the move before G40 end uncompensated")
def _(host):
    got = _ends(_run(host, square(41), strategy=1))
    expect([(0, -10), (8, -8), (8, 8), (-8, 8), (-8, -8), (0, -10), (0, -20)], got, "compensated ends")


@check("compensation", "negative_radius", C, "Geometry", "a negative radius swaps the sides")
def _(host):
    parts = _run(host, square(41), radius=-2.0)
    expect(4, sum(p["func"] in (2, 3) for p in parts), "outer corner arcs of G41 with radius -2")
    near_point((10, -12), parts[1]["ce"][:2], TOL, "end of the first side")


@check("compensation", "programmed_kept", S, "SIMPLE_GM_PARAMS — one part",
       "m_e keeps the programmed end, m_calcE the compensated one")
def _(host):
    parts = _run(host, square(41))
    near_point((10, -10), parts[1]["e"][:2], TOL, "m_e")
    near_point((8, -8), parts[1]["ce"][:2], TOL, "m_calcE")


@check("compensation", "side_in_force", S, "SIMPLE_GM_PARAMS — one part",
       "m_bFeedIsMin's high 16 bits: the compensation in force, 41 or 42, 40 once off")
def _(host):
    parts = _run(host, square(42), slot=1)
    expect(42, parts[1]["comp"], "a G42 part")
    expect(40, parts[-1]["comp"], "the G40 part")


@check("compensation", "tangent_join", C, "Geometry", "tangent joins add nothing")
def _(host):
    code = "G41 G1 X-10 Y0 F1000\nG1 X0 Y0\nG3 X5 Y5 I0 J5\nG1 X5 Y15\nG40 G1 X20 Y15\n"
    parts = _run(host, code, radius=1.0)
    expect([1, 1, 3, 1, 1], [p["func"] for p in parts], "parts")
    near_point((0, 1), parts[1]["ce"][:2], TOL, "the line's compensated end")
    near_point((4, 5), parts[2]["ce"][:2], TOL, "the arc's compensated end")
    near(4.0, parts[2]["radius"], TOL, "the arc's tool-centre radius")


@check("compensation", "inner_line_arc", C, "Geometry", "an inner line-arc corner: the offsets' intersection")
def _(host):
    code = "G41 G1 X-10 Y0 F1000\nG1 X0 Y0\nG3 X-3 Y9 I-3 J4\nG1 X-10 Y9\nG40 G1 X-20 Y20\n"
    parts = _run(host, code, radius=1.0)
    expect(0, sum(1 for p in parts if p["func"] in (2, 3)) - 1, "inserted arcs")
    near_point((-3 + math.sqrt(7), 1), parts[1]["ce"][:2], TOL, "corner")
    near(4.0, parts[2]["radius"], TOL, "the arc's tool-centre radius")


@check("compensation", "seed_g42_arc_start", C, "Start and end (correctionStrategy low byte)",
       "switching on right before an arc inserts a line to the arc's perpendicular point "
       "(the interpolator manual's example)")
def _(host):
    r = 0.5
    parts = _run(host, SEED_PROGRAM, radius=r, slot=1, absMode=0, coords=(0.0, 0.0, 0.0))
    arcs = [p for p in parts if p["func"] == 2]
    if not arcs:
        raise Differs("G2 parts", [p["func"] for p in parts], "parts")
    first = arcs[0]
    s, c = (60.6051, 40.7723), (60.6051 + 3.0336, 40.7723 - 1.2601)
    R = math.hypot(3.0336, 1.2601)
    perp = (s[0] + (c[0] - s[0]) * r / R, s[1] + (c[1] - s[1]) * r / R)   # G42 on a CW arc: towards the centre
    near_point(perp, first["cs"][:2], 1e-5, "the first arc's compensated start")
    near(R - r, first["radius"], 1e-5, "its tool-centre radius")
    before = parts[parts.index(first) - 1]
    near_point(perp, before["ce"][:2], 1e-5, "the part before ends there")


@check("compensation", "plane_change_error", C, "Start and end (correctionStrategy low byte)",
       "changing the plane inside a compensated run is an error (on its line or the next move's)")
def _(host):
    host.set_params(0, edit=lambda p: setattr(p.correction[0], "size", 1.0))
    host.reset_cnc(0, (0.0, -20.0, 0.0))
    err = host.compile("G41 G1 X0 Y-10 F1000\nG1 X10 Y-10\nG18\nG1 X10 Y10\nG40 G1 X0 Y20\n")
    if err is None:
        raise Differs("an error", None, "GetLastError")
    if err[1] not in (3, 4):
        raise Differs("line 3 or 4", err[1], "actLine")


@check("compensation", "g40_on_arc_error", C, "Start and end (correctionStrategy low byte)",
       "G40 taking effect on an arc is an error on that line")
def _(host):
    host.set_params(0, edit=lambda p: setattr(p.correction[0], "size", 1.0))
    host.reset_cnc(0, (0.0, -20.0, 0.0))
    err = host.compile("G41 G1 X0 Y-10 F1000\nG1 X10 Y-10\nG40 G3 X20 Y0 I0 J10\n")
    if err is None:
        raise Differs("an error", None, "GetLastError")
    expect(3, err[1], "actLine")
