"""Tool radius compensation: hand-computed cases for each corner type, each
strategy bit and each error (compensation stage alone, see tests/harness)."""
import math

import pytest

from comp_helpers import check_gouge_warnings, polygon_elements, programmed_polyline, rounded_rectangle
from test_compensation_geometry import check_oracle, comp, harness  # noqa: F401

ERR_COMP_NOT_FOUND, ERR_COMP_ON_ARC, ERR_COMP_PLANE_CHANGE = 500, 501, 502
ERR_COMP_NEGATIVE_ARC, ERR_COMP_CROSSING, ERR_COMP_LOOKAHEAD = 503, 504, 505


def L(x, y, comp=41, **kw):
    return dict(func=1, e=(x, y), comp=comp, **kw)


def A(func, x, y, cx, cy, comp=41, **kw):
    return dict(func=func, e=(x, y), cc=(cx, cy), radius=math.hypot(x - cx, y - cy), comp=comp, **kw)


def close(p, q, tol=1e-9):
    return all(abs(a - b) < tol for a, b in zip(p, q))


SQUARE = [L(0, -10), L(10, -10), L(10, 10), L(-10, 10), L(-10, -10), L(0, -10)]


def square(g, strategy=0, r=2.0):
    parts = [dict(func=1, e=(0, -20), comp=40)]
    for i, p in enumerate(SQUARE):
        parts.append(dict(p, comp=g))
    parts.append(L(0, -20, comp=40))
    return comp_run(parts, r=r, strategy=strategy)


def comp_run(parts, r=2.0, strategy=0, start=(0, -20, 0), **kw):
    from test_compensation_geometry import _harness_module
    return comp(_harness_module(), parts, r=r, strategy=strategy, start=start, **kw)


# ------------------------------------------------------------------ corners

def test_inner_line_line_corners_go_to_the_intersection(harness):
    out, err, _ = square(41)                 # CCW square, tool inside
    assert err is None
    assert [p["inserted"] for p in out].count(True) == 0
    ce = [tuple(round(v, 9) for v in p["ce"][:2]) for p in out]
    assert ce == [(0, -20), (0, -8), (8, -8), (8, 8), (-8, 8), (-8, -8), (0, -8), (0, -20)]


def test_outer_line_line_corners_insert_arcs_about_the_corner(harness):
    out, err, _ = square(42)                 # tool outside
    assert err is None
    ins = [p for p in out if p["inserted"]]
    assert len(ins) == 4
    # after the first side: arc from (10,-12) to (12,-10) about (10,-10), CCW for G42
    k = next(i for i, p in enumerate(out) if p["inserted"])
    arc = out[k]
    assert close(out[k - 1]["ce"][:2], (10, -12))
    assert arc["func"] == 3 and close(arc["ce"][:2], (12, -10)) and close(arc["cc"][:2], (10, -10))
    assert arc["radius"] == pytest.approx(2.0)
    assert arc["gcode_index"] == out[k - 1]["gcode_index"] + 1 and arc["gcode_index"] % 2 == 1
    assert arc["line"] == out[k - 1]["line"] and arc["comp"] == 42
    assert close(out[1]["ce"][:2], (0, -12)) and close(out[-2]["ce"][:2], (0, -12))


def test_outer_corner_intersection_strategy_uses_the_extended_offsets(harness):
    out, err, _ = square(42, strategy=0x800000)
    assert err is None
    assert not any(p["inserted"] for p in out)
    assert close(out[2]["ce"][:2], (12, -12)) and close(out[3]["ce"][:2], (12, 12))


def _sharp(strategy, turn_deg=140.0, r=2.0):
    a = math.radians(-turn_deg)              # right turn: outer for G41
    end = (10 * math.cos(a), 10 * math.sin(a))
    parts = [dict(func=1, e=(-20, 5), comp=40), L(-10, 0), L(0, 0), L(*end), L(end[0], end[1] - 10, comp=40)]
    return comp_run(parts, r=r, strategy=strategy, start=(-20, 5, 0))


def test_outer_corner_limit_three_or_two_radii(harness):
    # the extended offsets meet 2/cos(70 deg) = 5.85 from the corner: < 3r, > 2r
    out, err, _ = _sharp(0x800000)
    assert err is None and not any(p["inserted"] for p in out)
    assert math.hypot(*out[2]["ce"][:2]) == pytest.approx(2 / math.cos(math.radians(70)))
    out, err, _ = _sharp(0x800000 | 0x400000)
    assert err is None and sum(p["inserted"] for p in out) == 1
    out, err, _ = _sharp(0)
    assert err is None and sum(p["inserted"] for p in out) == 1
    arc = next(p for p in out if p["inserted"])
    assert arc["func"] == 2 and close(arc["cc"][:2], (0, 0))


def test_tangent_line_arc_join_adds_nothing(harness):
    parts = [dict(func=1, e=(-20, 0), comp=40), L(-10, 0), L(0, 0), A(3, 5, 5, 0, 5), L(5, 15), L(20, 15, comp=40)]
    out, err, _ = comp_run(parts, r=1.0, start=(-20, -5, 0))
    assert err is None and not any(p["inserted"] for p in out)
    assert close(out[2]["ce"][:2], (0, 1))
    assert close(out[3]["ce"][:2], (4, 5)) and out[3]["radius"] == pytest.approx(4.0)
    assert close(out[3]["cc"][:2], (0, 5))


def test_inner_line_arc_corner(harness):
    parts = [dict(func=1, e=(-20, 0), comp=40), L(-10, 0), L(0, 0), A(3, -3, 9, -3, 4), L(-10, 9), L(-20, 20, comp=40)]
    out, err, _ = comp_run(parts, r=1.0, start=(-20, -5, 0))
    assert err is None and not any(p["inserted"] for p in out)
    assert close(out[2]["ce"][:2], (-3 + math.sqrt(7), 1))
    assert out[3]["radius"] == pytest.approx(4.0)


def test_arc_arc_outer_corner_inserts_an_arc(harness):
    # two CW arcs meeting at (0,0) with a right turn; G41 puts the tool outside
    ex, ey = -3 + math.sqrt(34) * math.cos(math.radians(-120)), 5 + math.sqrt(34) * math.sin(math.radians(-120))
    parts = [dict(func=1, e=(-10, -10), comp=40), L(-10, 0), A(2, 0, 0, -5, -3), A(2, ex, ey, -3, 5),
             L(ex, -10), L(ex, -20, comp=40)]
    out, err, _ = comp_run(parts, r=1.0, start=(-10, -20, 0))
    assert err is None
    k = next(i for i, p in enumerate(out) if p["inserted"])
    assert out[k]["func"] == 2 and close(out[k]["cc"][:2], (0, 0))
    # both ends on the perpendiculars at (0,0), one tool radius away
    for p in (out[k - 1], out[k]):
        assert math.hypot(*p["ce"][:2]) == pytest.approx(1.0)
    assert out[k - 1]["radius"] == pytest.approx(math.hypot(5, 3) + 1)


# ------------------------------------------------------------------ start and end

def test_strategy_1_compensates_from_the_end_of_the_next_move(harness):
    out, err, _ = square(41, strategy=1)
    assert err is None
    ce = [tuple(round(v, 9) for v in p["ce"][:2]) for p in out]
    # the G41 block and the last move before G40 end uncompensated
    assert ce == [(0, -20), (0, -10), (8, -8), (8, 8), (-8, 8), (-8, -8), (0, -10), (0, -20)]


def test_rapid_suspends_and_restores_compensation(harness):
    parts = [dict(func=1, e=(0, -10), comp=40), L(0, 0), L(10, 0), dict(func=0, e=(20, 10), comp=41),
             L(30, 10), L(40, 10, comp=40)]
    out, err, _ = comp_run(parts, r=1.0, start=(0, -10, 0))
    assert err is None
    assert close(out[2]["ce"][:2], (10, 1))          # leaves on the perpendicular
    assert close(out[3]["ce"][:2], (20, 11))         # the rapid ends on the next perpendicular
    assert close(out[4]["ce"][:2], (30, 11))
    out, err, _ = comp_run(parts, r=1.0, start=(0, -10, 0), strategy=0x40000000)
    assert err is None
    assert close(out[3]["ce"][:2], (20, 10))         # G0 never compensated
    assert close(out[4]["ce"][:2], (30, 11))


def test_switching_off_on_an_arc_is_an_error(harness):
    parts = [dict(func=1, e=(0, -10), comp=40), L(0, 0), L(10, 0), A(3, 20, 10, 20, 0, comp=40, line=9)]
    out, err, _ = comp_run(parts, start=(0, -10, 0))
    assert err["number"] == ERR_COMP_ON_ARC and err["line"] == 9


@pytest.mark.parametrize("strategy", [0, 1])
def test_switching_on_before_an_arc_inserts_a_line_to_its_perpendicular(harness, strategy):
    # G42 alone, then an arc (the interpolator manual's example program): G1 to the arc's perpendicular, the arc compensated
    parts = [dict(func=0, e=(0, -10), comp=40), dict(kind=2, func=51, comp=41, line=3),
             A(3, 10, 0, 10, -10, line=4), L(10, 10), L(0, 10, comp=40)]
    out, err, warn = comp_run(parts, r=1.0, start=(0, -10, 0), strategy=strategy)
    assert err is None and "arc" in warn
    assert out[2]["inserted"] and out[2]["func"] == 1 and out[2]["line"] == 4 and out[2]["comp"] == 41
    assert close(out[2]["ce"][:2], (1, -10)) and close(out[1]["ce"][:2], (0, -10))
    assert out[3]["radius"] == pytest.approx(9.0)


def test_strategy_1_leaves_an_arc_by_an_inserted_line(harness):
    parts = [dict(func=1, e=(0, -10), comp=40), L(0, 0), L(10, 0), A(3, 20, 10, 20, 0, line=5), L(30, 10, comp=40)]
    out, err, warn = comp_run(parts, r=1.0, start=(0, -10, 0), strategy=1)
    assert err is None
    k = next(i for i, p in enumerate(out) if p["inserted"] and p["func"] == 1)
    assert out[k]["line"] == 5 and close(out[k]["ce"][:2], (20, 10)) and close(out[k - 1]["ce"][:2], (20, 9))


def test_plane_change_while_compensated(harness):
    parts = [dict(func=1, e=(0, -10), comp=40), L(0, 0), L(10, 0), L(10, 10, plane=18, line=12), L(0, 10, comp=40)]
    out, err, _ = comp_run(parts, start=(0, -10, 0))
    assert err["number"] == ERR_COMP_PLANE_CHANGE and err["line"] == 12


def test_m_functions_and_plunges_take_the_compensated_position(harness):
    parts = [dict(func=1, e=(0, -10, 5), comp=40), L(0, 0), dict(kind=2, func=8, comp=41),
             dict(func=1, e=(0, 0, -2), comp=41), L(10, 0), dict(kind=2, func=9, comp=41), L(10, 10), L(20, 10, comp=40)]
    out, err, _ = comp_run(parts, r=1.0, start=(0, -10, 5))
    assert err is None
    assert close(out[1]["ce"], (0, 1, 5))            # entry on the perpendicular of X10
    assert close(out[2]["ce"], out[1]["ce"])         # M8 sits at the entry point
    assert close(out[3]["ce"], (0, 1, -2))           # plunge: xy compensated, z programmed
    assert close(out[4]["ce"][:2], (9, 1))           # inner corner of the look-ahead across M9
    assert close(out[5]["ce"][:2], (9, 1))


def test_look_ahead_is_limited_to_200_blocks_without_motion(harness):
    ms = [dict(kind=2, func=100, comp=41, line=100 + i) for i in range(201)]
    parts = [dict(func=1, e=(0, -10), comp=40), L(0, 0), L(10, 0)] + ms + [L(10, 10), L(20, 10, comp=40)]
    out, err, _ = comp_run(parts, r=1.0, start=(0, -10, 0))
    assert err["number"] == ERR_COMP_LOOKAHEAD and err["line"] == 300
    out, err, _ = comp_run(parts[:3] + ms[:200] + parts[-2:], r=1.0, start=(0, -10, 0))
    assert err is None


def test_compatibility_ignores_a_leading_g41_and_g40_g41_pairs(harness):
    parts = [L(0, 0), L(10, 0), L(10, 10), L(0, 10, comp=40)]
    out, err, _ = comp_run(parts, r=1.0, start=(0, -10, 0), strategy=0x80000000)
    assert err is None
    assert all(p["comp"] == 40 and close(p["ce"][:2], p["e"][:2]) for p in out)
    parts = [dict(func=1, e=(0, -10), comp=40), L(0, 0), L(10, 0), dict(kind=2, func=100, comp=40),
             L(10, 10), L(0, 10, comp=40)]
    out, err, _ = comp_run(parts, r=1.0, start=(0, -10, 0), strategy=0x80000000)
    assert err is None
    assert close(out[2]["ce"][:2], (9, 1))           # one run: the inner corner, no exit
    out, err, _ = comp_run(parts, r=1.0, start=(0, -10, 0))
    assert err is None
    assert close(out[2]["ce"][:2], (10, 1))          # without the bit: G40 then G41 again


# ------------------------------------------------------------------ robustness

def chamfered_pocket(ch):
    pts = [(-10, -10), (10, -10), (10, 10 - ch), (10 - ch, 10), (-10, 10)]
    return polygon_elements(pts)


def test_crossing_offsets_warning_removal_or_error(harness):
    m0, els = chamfered_pocket(0.3)          # chamfer shorter than the inner offset trims
    for i, el in enumerate(els):
        el["line"] = 10 + i
    with pytest.raises(AssertionError, match="504"):
        check_oracle(harness, m0, els, 2.0, 41, strict=True)
    with pytest.raises(AssertionError, match="Equidistant error on line 12"):
        check_oracle(harness, m0, els, 2.0, 41)         # compiled as the offsets give it
    out = check_oracle(harness, m0, els, 2.0, 41, strategy=0x80000)
    assert any(close(p["ce"][:2], (8, 8)) for p in out)


def test_crossing_warning_names_the_line_and_the_depth(harness):
    m0, els = chamfered_pocket(0.3)
    parts = [dict(func=1, e=(0, -30), comp=40), L(*m0)] + [dict(el, comp=41, line=20 + i) for i, el in enumerate(els)]
    parts.append(L(0, -30, comp=40))
    out, err, _ = comp_run(parts, start=(0, -30, 0), strict=True)
    assert err["number"] == ERR_COMP_CROSSING and err["line"] == 22     # the chamfer
    out, err, warn = comp_run(parts, start=(0, -30, 0))
    assert err is None
    # as the offsets give it: the corners meet where the chamfer's offset x + y =
    # 19.7 - 2 sqrt(2) crosses x = 8 and y = 8, and the chamfer's part runs back along
    # it; the tool stands 10 - (11.7 - 2 sqrt(2)) from the top and the right side
    # there: the right side, the chamfer and the top cut 3.7 - 2 sqrt(2) mm into them
    c = 11.7 - 2 * math.sqrt(2)
    assert [tuple(p["ce"][:2]) for p in out[3:6]] == [pytest.approx((8, c)), pytest.approx((c, 8)),
                                                      pytest.approx((-8, 8))]
    warned = check_gouge_warnings(out, warn, programmed_polyline(m0, els), 2.0)
    assert warned == {21: pytest.approx(3.7 - 2 * math.sqrt(2), abs=1e-6),
                      22: pytest.approx(3.7 - 2 * math.sqrt(2), abs=1e-6),
                      23: pytest.approx(3.7 - 2 * math.sqrt(2), abs=1e-6)}


def test_intersection_not_found_error_and_joins(harness):
    # an inner corner whose offset circle (radius 1.04) misses the offset line y = 2
    # (the arc is left tangentially: a corner arc there would cross the first part's offset)
    parts = [dict(func=1, e=(-20, 0), comp=40), L(-10, 0), L(0, 0, line=3), A(3, -3, 0.5 + math.hypot(3, 0.5), -3, 0.5),
             L(-20, 0.5 + math.hypot(3, 0.5)), L(-20, 20, comp=40)]
    out, err, _ = comp_run(parts, r=2.0, start=(-20, -5, 0))
    assert err["number"] == ERR_COMP_NOT_FOUND and err["line"] == 3
    # the join passes 1.54 from the corner at (0, 0): a gouge, warning 601 on its line
    # (strict: error 504) ...
    for strategy in (0x20000, 0x40000):
        out, err, warn = comp_run(parts, r=2.0, start=(-20, -5, 0), strategy=strategy, strict=True)
        assert err["number"] == 504 and err["line"] == 3
        out, err, warn = comp_run(parts, r=2.0, start=(-20, -5, 0), strategy=strategy)
        assert err is None and "line 3: Equidistant error on line 3" in warn


def test_negative_offset_arcs_error_or_removed(harness):
    m0, els = rounded_rectangle(-20, -15, 40, 30, 1.5)
    parts = [dict(func=1, e=(0, -40), comp=40), L(*m0)] + [dict(el, comp=41, line=30 + i) for i, el in enumerate(els)]
    parts.append(L(0, -40, comp=40))
    out, err, _ = comp_run(parts, r=2.0, start=(0, -40, 0))
    assert err["number"] == ERR_COMP_NEGATIVE_ARC and err["line"] == 31
    assert "1.5" in err["text"] and "2" in err["text"]
    out = check_oracle(harness, m0, els, 2.0, 41, strategy=0x200000)
    arcs = [p for p in out if p["func"] == 3]
    assert len(arcs) == 4 and all(p["radius"] == 0 for p in arcs)


def test_arcs_below_the_minimum_radius_are_removed(harness):
    # tolerance[4]: tool path arcs smaller than it are removed like arcs of no radius,
    # the neighbouring lines' offsets meet at their intersection
    m0, els = rounded_rectangle(-20, -15, 40, 30, 2.3)
    parts = [dict(func=1, e=(0, -40), comp=40), L(*m0)] + [dict(el, comp=41) for el in els]
    parts.append(L(0, -40, comp=40))
    out = check_oracle(harness, m0, els, 2.0, 41)       # radius 0.3 kept without it
    assert sorted(round(p["radius"], 9) for p in out if p["func"] == 3) == [0.3] * 4
    tol = (0.005, 0.001, 0.03, 0.005, 0.5)
    out, err, warn = comp_run(parts, r=2.0, start=(0, -40, 0), tolerances=tol)
    assert err is None and warn.count("tolerance[4]") == 4
    arcs = [p for p in out if p["func"] == 3]
    assert len(arcs) == 4 and all(p["radius"] == 0 for p in arcs)
    corners = {tuple(round(v, 9) for v in p["ce"][:2]) for p in out[2:-1]}
    assert corners == {(-18, -13), (18, -13), (18, 13), (-18, 13), (0, -13)}
    out, err, warn = comp_run(parts, r=2.0, start=(0, -40, 0), tolerances=(0, 0, 0, 0, 0.2))
    assert err is None and "tolerance[4]" not in warn


def test_arc_radius_equal_to_the_tool_radius_is_a_point(harness):
    m0, els = rounded_rectangle(-20, -15, 40, 30, 2.0)
    check_oracle(harness, m0, els, 2.0, 41)


def test_side_change_without_g40_joins_by_a_line(harness):
    parts = [dict(func=1, e=(0, -10), comp=40), L(0, 0), L(10, 0), L(20, 0, comp=42), L(30, 0, comp=42), L(40, 0, comp=40)]
    out, err, _ = comp_run(parts, r=1.0, start=(0, -10, 0))
    assert err is None
    k = next(i for i, p in enumerate(out) if p["inserted"])
    assert out[k]["func"] == 1 and close(out[k - 1]["ce"][:2], (10, 1)) and close(out[k]["ce"][:2], (10, -1))


def test_helix_and_xz_plane(harness):
    parts = [dict(func=1, e=(0, -10, 0), comp=40), L(0, 0), dict(func=3, e=(0, 10, -5), cc=(0, 5, 0), radius=5.0, comp=41),
             L(-10, 10), L(-10, 20, comp=40)]
    out, err, _ = comp_run(parts, r=1.0, start=(0, -10, 0))
    assert err is None
    helix = next(p for p in out if p["func"] == 3 and not p["inserted"])
    assert helix["radius"] == pytest.approx(4.0) and helix["ce"][2] == pytest.approx(-5.0)
    # the same square in XZ: y untouched
    parts = [dict(func=1, e=(0, 7, -20), comp=40, plane=18)]
    for p in SQUARE:
        parts.append(dict(func=1, e=(p["e"][0], 7, p["e"][1]), comp=41, plane=18))
    parts.append(dict(func=1, e=(0, 7, -20), comp=40, plane=18))
    out, err, _ = comp_run(parts, r=2.0, start=(0, 7, -20))
    assert err is None
    assert [tuple(round(v, 9) for v in p["ce"]) for p in out][1:4] == [(0, 7, -8), (8, 7, -8), (8, 7, 8)]
