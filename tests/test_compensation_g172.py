"""G172 R C D / G173: the compensation strategy changed from the program."""
import pytest

from test_compensation_e2e import hmi  # noqa: F401  (the fixture)

SQUARE = ("G0 X0 Y-10\nG42 G1 X0 Y0 F1000\nG1 X20 Y0\nG1 X20 Y20\nG1 X0 Y20\nG1 X0 Y0\n"
          "G40 G1 X0 Y-10\n")


def corner_arcs(parts):
    return [p for p in parts if p["func"] in (2, 3)]


def test_without_g172_outer_corners_get_arcs(hmi):
    # outside a counter-clockwise square (G42 = right = outside): three outer corners
    assert hmi.compile("G0 X0 Y0 Z0\n" + SQUARE, r=1.0) is None
    assert len(corner_arcs(hmi.run())) == 3


def test_g172_r_takes_the_intersection_within_r_of_the_corner(hmi):
    # the extended offsets meet sqrt(2) * r = 1.414 from the corner
    assert hmi.compile("G0 X0 Y0 Z0\nG172 R2\n" + SQUARE, r=1.0) is None
    parts = hmi.run()
    assert corner_arcs(parts) == []
    ends = [tuple(round(v, 9) for v in p["e"][:2]) for p in parts]
    assert (21.0, -1.0) in ends and (21.0, 21.0) in ends and (-1.0, 21.0) in ends
    # closer limit than the intersection: arcs again
    assert hmi.compile("G0 X0 Y0 Z0\nG172 R1\n" + SQUARE, r=1.0) is None
    assert len(corner_arcs(hmi.run())) == 3


def test_g173_restores_the_hosts_strategy(hmi):
    code = "G0 X0 Y0 Z0\nG172 R2\n" + SQUARE + "G173\nG0 X0 Y0\n" + SQUARE
    assert hmi.compile(code, r=1.0) is None
    assert len(corner_arcs(hmi.run())) == 3            # only the second square has arcs


def test_g172_d_drops_arcs_whose_offset_radius_is_negative(hmi):
    # a bump of radius 0.5 inside a tool of radius 1: error 503 unless arcs may be dropped
    bump = ("G0 X0 Y-5\nG41 G1 X0 Y0 F1000\nG1 X10 Y0\nG3 X11 Y0 I0.5 J0\nG1 X20 Y0\n"
            "G40 G1 X20 Y-5\n")
    err = hmi.compile("G0 X0 Y0 Z0\n" + bump, r=1.0)
    assert err is not None and err[0] == 503 and err[1] == 5
    assert hmi.compile("G0 X0 Y0 Z0\nG172 D1\n" + bump, r=1.0) is None
    # the dropped bump leaves one straight tool path 1 mm above the contour
    cut = [p for p in hmi.run() if p["line"] in (5, 6, 7)]
    assert [round(p["e"][1], 9) for p in cut] == [1.0] * len(cut)
    assert round(cut[-1]["e"][0], 9) == 20.0
    assert hmi.compile("G0 X0 Y0 Z0\nG172 D1\n" + bump.replace("G41", "G173\nG41"), r=1.0)[0] == 503
