"""Automatic arcs between non-tangent G1 lines (G167 / insertArcMode) and the
compensation's warnings on MathWarning (2001), through ctypes as an HMI sees them."""
import ctypes
import math

import numpy as np
import pytest

from sf_tch import abi

from test_compensation_e2e import Hmi, CORE


@pytest.fixture
def hmi(tmp_path):
    h = Hmi(tmp_path)
    yield h
    h.close()


def compile_with(hmi, code, r=2.0, **fields):
    """Like Hmi.compile, with extra GCODE_PARAMETERS fields (insertArc*)."""
    saved = hmi.saved
    p = abi.GCODE_PARAMETERS.from_buffer_copy(saved)
    for k, v in fields.items():
        setattr(p, k, v)
    hmi.saved = p
    try:
        return hmi.compile(code, r=r)
    finally:
        hmi.saved = saved


def arc_geometry(t_deg, d):
    """Radius and tangent length of the arc whose midpoint is d from a corner of
    deflection t."""
    t = math.radians(t_deg)
    r = d * math.cos(t / 2) / (1 - math.cos(t / 2))
    return r, r * math.tan(t / 2)


def rounded(parts):
    return [(p["func"], tuple(round(v, 6) for v in p["e"][:2])) for p in parts]


def test_right_angle_corner_by_hand(hmi):
    # 90 deg: r = d cos45 / (1 - cos45) = d (1 + sqrt 2), tangent points r from the corner
    assert hmi.compile("G0 X0 Y0 Z0 F1000\nG167 E0.1\nG1 X10\nY10\n") is None
    parts = hmi.run()
    r = 0.1 * (1 + math.sqrt(2))
    assert [p["func"] for p in parts] == [0, 1, 3, 1]
    line1, arc, line2 = parts[1], parts[2], parts[3]
    assert np.allclose(line1["e"][:2], (10 - r, 0)) and np.allclose(line1["pe"][:2], (10 - r, 0))
    assert np.allclose(arc["s"][:2], (10 - r, 0))
    assert np.allclose(arc["e"][:2], (10, r)) and np.allclose(arc["pe"][:2], (10, r))
    assert np.allclose(arc["cc"][:2], (10 - r, r)) and arc["cc"][3] == pytest.approx(r)
    assert np.allclose(line2["s"][:2], (10, r)) and np.allclose(line2["e"][:2], (10, 10))
    # the arc's midpoint is the tolerance away from the corner
    mid = np.array(arc["cc"][:2]) + r * np.array([1, -1]) / math.sqrt(2)
    assert math.hypot(mid[0] - 10, mid[1]) == pytest.approx(0.1)
    # inserted: odd index, the second line's line number
    assert arc["index"] % 2 == 1 and arc["index"] == line1["index"] + 1
    assert arc["line"] == line2["line"] == 4


def test_clockwise_corner_and_45_degrees(hmi):
    assert hmi.compile("G0 X0 Y0 Z0 F1000\nG167 E0.05 U60\nG1 X10\nX20 Y-10\n") is None
    parts = hmi.run()
    r, tl = arc_geometry(45, 0.05)
    assert [p["func"] for p in parts] == [0, 1, 2, 1]
    arc = parts[2]
    assert np.allclose(parts[1]["e"][:2], (10 - tl, 0))
    assert np.allclose(arc["e"][:2], (10 + tl / math.sqrt(2), -tl / math.sqrt(2)))
    assert np.allclose(arc["cc"][:2], (10 - tl, -r)) and arc["cc"][3] == pytest.approx(r)
    for q in (arc["s"], arc["e"]):
        assert math.hypot(q[0] - arc["cc"][0], q[1] - arc["cc"][1]) == pytest.approx(r)


def test_angle_limits(hmi):
    # U45: the 90 deg corner is too sharp, the 30 deg one gets an arc
    code = "G0 X0 Y0 Z0 F1000\nG167 E0.05 U45\nG1 X10\nY10\nX20 Y{y}\n"
    y = 10 + 10 * math.tan(math.radians(60))   # a 30 deg turn after the 90 deg one
    assert hmi.compile(code.format(y=y)) is None
    assert [p["func"] for p in hmi.run()] == [0, 1, 1, 2, 1]
    # the minimum angle comes from the host: 30 deg is not above it
    assert compile_with(hmi, code.format(y=y), rezerva1=abi.GCODE_REZERVA1_APPLY_UNIMPLEMENTED, insertArcMinAngle=30.5) is None
    assert [p["func"] for p in hmi.run()] == [0, 1, 1, 1]
    # exactly the maximum angle still gets its arc
    assert hmi.compile("G0 X0 Y0 Z0 F1000\nG167 E0.05 U90\nG1 X10\nY10\n") is None
    assert [p["func"] for p in hmi.run()] == [0, 1, 3, 1]
    # tangent lines: no arc (collinear, they are one G1: tolerance[2], tests/test_join_lines.py)
    assert hmi.compile("G0 X0 Y0 Z0 F1000\nG167 E0.05\nG1 X10\nX20\n") is None
    assert [p["func"] for p in hmi.run()] == [0, 1]


def test_short_lines_shrink_the_arc_down_to_the_minimum(hmi):
    # E0.1 needs 0.2414 of each line; the first line is 0.4 long: tangent length 0.2
    assert hmi.compile("G0 X0 Y0 Z0 F1000\nG167 E0.1 A0.05\nG1 X0.4\nY10\n") is None
    parts = hmi.run()
    assert [p["func"] for p in parts] == [0, 1, 3, 1]
    assert np.allclose(parts[1]["e"][:2], (0.2, 0)) and np.allclose(parts[2]["e"][:2], (0.4, 0.2))
    assert parts[2]["cc"][3] == pytest.approx(0.2)
    d = 0.2 * math.sqrt(2) - 0.2
    assert d > 0.05
    # A0.09: even the minimum does not fit in half of the short line: nothing inserted
    assert hmi.compile("G0 X0 Y0 Z0 F1000\nG167 E0.1 A0.09\nG1 X0.4\nY10\n") is None
    assert [p["func"] for p in hmi.run()] == [0, 1, 1]


def test_g167_on_and_off_in_the_program(hmi):
    code = "G0 X0 Y0 Z0 F1000\nG1 X10\nY10\nG167 E0.1\nX0\nY0\nG167\nX10\nY-10\n"
    assert hmi.compile(code) is None
    parts = hmi.run()
    funcs = [p["func"] for p in parts]
    # corners at (10,10) (line 5) and (0,10) (line 6) only: G167 before line 5, off before line 8
    assert funcs == [0, 1, 1, 3, 1, 3, 1, 1, 1]
    assert [p["line"] for p in parts if p["func"] == 3] == [5, 6]


def test_host_mode_and_a_bare_g167(hmi):
    code = "G0 X0 Y0 Z0 F1000\nG1 X10\nY10\nX0\n"
    assert compile_with(hmi, code, insertArcMode=1, insertArcToleranceRMax=0.1,
                        insertArcToleranceRMin=0.01) is None
    parts = hmi.run()
    assert [p["func"] for p in parts] == [0, 1, 3, 1, 3, 1]
    assert parts[2]["cc"][3] == pytest.approx(0.1 * (1 + math.sqrt(2)))
    # the program switches the host's insertion off
    assert compile_with(hmi, "G167\n" + code, insertArcMode=1) is None
    assert [p["func"] for p in hmi.run()] == [0, 1, 1, 1]
    # off by default: nothing
    assert hmi.compile(code) is None
    assert [p["func"] for p in hmi.run()] == [0, 1, 1, 1]


def test_insertion_plane(hmi):
    # lines in XZ: nothing with Q17, an arc with Q18
    code = "G0 X0 Y0 Z0 F1000\nG167 E0.1 Q{q}\nG1 X10\nZ10\n"
    assert hmi.compile(code.format(q=17)) is None
    assert [p["func"] for p in hmi.run()] == [0, 1, 1]
    assert hmi.compile(code.format(q=18)) is None
    parts = hmi.run()
    assert [p["func"] for p in parts][:2] == [0, 1] and parts[2]["func"] in (2, 3)
    r = 0.1 * (1 + math.sqrt(2))
    assert np.allclose(parts[2]["e"], (10, 0, r)) and np.allclose(parts[2]["cc"][:3], (10 - r, 0, r))
    assert hmi.compile("G167 E0.1 Q5\nG1 X1\n")[0] == 403


def test_arcs_on_the_compensated_path(hmi):
    # inner square, tool radius 2: the compensated corners are 90 deg too
    code = ("G0 X0 Y-20\nG167 E0.1\nG41 G1 X0 Y-10 F1000\nX10\nY10\nX-10\nY-10\nX0\nG40 X0 Y-20\nM30\n")
    assert hmi.compile(code) is None
    parts = hmi.run()
    r = 0.1 * (1 + math.sqrt(2))
    arcs = [p for p in parts if p["func"] in (2, 3)]
    # the four corners of the square; the entry and exit meet the square at right angles too
    corners = [(8, -8), (8, 8), (-8, 8), (-8, -8)]
    for c in corners:
        assert any(np.allclose(a["cc"][:2], (c[0] - math.copysign(r, c[0]), c[1] - math.copysign(r, c[1])))
                   for a in arcs), c
    for a, b in zip(parts, parts[1:]):
        assert np.allclose(a["e"], b["s"])
    for a in arcs:
        assert a["cc"][3] == pytest.approx(r) and a["index"] % 2 == 1 and a["comp"] in (40, 41)
        assert math.hypot(a["s"][0] - a["cc"][0], a["s"][1] - a["cc"][1]) == pytest.approx(r)
        assert math.hypot(a["e"][0] - a["cc"][0], a["e"][1] - a["cc"][1]) == pytest.approx(r)


def test_math_warning_callback(hmi):
    seen = []

    def on_warn(user, info):
        i = info.contents
        seen.append((user, i.stringId, i.actLine, i.fileIdx, i.nLines, (i.m_fullError or b"").decode()))
        return 0

    cb = abi.MathWarning(on_warn)
    assert hmi.lib.ToolChainCore_SetCallBack(CORE, abi.CB_MATH_WARNING, 77,
                                             ctypes.cast(cb, ctypes.c_void_p)) == 0
    try:
        # compensation switched on before an arc: a line to its perpendicular, with a warning
        code = "G0 X0 Y0\nG41\nG3 X20 Y0 I10 J0 F1000\nG1 Y-10\nG40 X0\nM30\n"
        assert hmi.compile(code) is None
    finally:
        hmi.lib.ToolChainCore_SetCallBack(CORE, abi.CB_MATH_WARNING, 0, None)
    assert seen, "no MathWarning"
    user, number, line, file_idx, n_lines, text = seen[0]
    assert user == 77 and number == 600 and line == 3 and n_lines == 6
    assert file_idx == hmi.lib.ToolChainCore_FileToIdx(CORE, b"comp.nc")
    assert text.startswith("Tool radius compensation: ") and "arc" in text
