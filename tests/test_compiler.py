"""The G-code compiler seen from an HMI: positions, arcs, feeds, M functions,
parameters, expressions and program flow (core 1)."""
import ctypes
import math
import random

import pytest

from compiler_host import SEED_PROGRAM, Host, close, ok
from sf_tch import library

@pytest.fixture(scope="module")
def host(tmp_path_factory):
    h = Host(1, tmp_path_factory.mktemp("core1"))
    yield h
    h.close()


# ------------------------------------------------------------ the interpolator manual's example program

def test_seed_relative_compiles(host):
    r = host.compile(SEED_PROGRAM, absMode=0, run=False)
    assert r.error is None, r.error


def test_seed_relative_geometry_without_compensation(host):
    code = "\n".join("" if l in ("G42", "G40") else l for l in SEED_PROGRAM.splitlines())
    r = ok(host, code, absMode=0, start=[0] * 10)
    g = r.g
    assert [p.func for p in g] == [0, 2, 2, 2, 2, 2, 2, 2, 0]
    x, y = 60.6051, 40.7723
    assert close(g[0].e[:2], (x, y))
    # first arc: centre relative to its start, radius sqrt(I^2 + J^2)
    assert close(g[1].cc[:2], (x + 3.0336, y - 1.2601))
    assert g[1].cc[3] == pytest.approx(math.hypot(3.0336, 1.2601))
    assert close(g[1].e[:2], (x, y - 2.5202))
    ends = [p.e[:2] for p in g]
    assert close(ends[7], (x + 0.922 + 1.079 + 2.2624 + 1.9856 + 3.015 + 6.2889,
                           y - 2.5202 - 1.5646 - 1.0269 - 1.3678 - 0.8109 - 0.7892), 1e-9)
    assert [p.func for p in r.m] == [51, 50, 51, 2]
    assert [p.line for p in r.parts] == [1, 3, 4, 5, 6, 7, 8, 9, 10, 11, 13, 15, 17]


def test_seed_absolute_fails_on_line_4_with_the_centre_error(host):
    r = host.compile(SEED_PROGRAM, absMode=1)
    number, line, file_idx, text, args = r.error
    assert number == 400 and line == 4
    # the vendor's three lines: start, end, then the chord against 2 R; exactly six arguments
    assert text.startswith("Wrongly entered centre of circular interpolation XY\n"
                           "Start X = 60.6051 Y = 40.7723 | End X = 0 Y = -2.5202\nDelta (")
    parts = args.split("\n")
    assert len(parts) == 6 and parts[:4] == ["60.6051", "40.7723", "0", "-2.5202"]
    assert float(parts[4]) == pytest.approx(math.hypot(60.6051, 40.7723 + 2.5202), abs=1e-6)
    assert float(parts[5]) == pytest.approx(2 * math.hypot(3.0336, 1.2601), abs=1e-6)


# The structures description's example of CALLBACK_INFO, as the vendor printed it
VENDOR_400_FORMAT = ("Wrongly entered centre of circular interpolation XY\nStart X = %g Y = %g | "
                     "End X = %g Y = %g\nDelta (%.7f) > 2*R (%.7f)")


def test_error_400_is_the_vendors_format_with_exactly_its_six_arguments(host, lib):
    """The documented example byte for byte: the format, and the start and end
    20.123 30.653 / 43.987 -1.26 as the vendor's arguments give them; the text is the
    format filled with the arguments (Python's %-formatting follows printf); the
    column of the centre words is beside the text, not among the arguments."""
    from sf_tch import ErrorNumber
    assert ErrorNumber.ARC_CENTRE.format == VENDOR_400_FORMAT
    r = host.compile("G0 X20.123 Y30.653\nG2 X43.987 Y-1.26 I5 J0\n", absMode=1)
    number, line, _, text, args = r.error
    values = args.split("\n")
    assert (number, line) == (400, 2) and values[:4] == ["20.123", "30.653", "43.987", "-1.26"]
    chord = math.hypot(43.987 - 20.123, -1.26 - 30.653)
    assert values[4:] == [f"{chord:.7f}", "10.0000000"]
    assert text == VENDOR_400_FORMAT % (20.123, 30.653, 43.987, -1.26, chord, 10.0)
    column = ctypes.c_int32()
    assert lib.ToolChainCore_GetLastErrorColumn(1, 0, ctypes.byref(column)) == 1 and column.value == 19
    assert lib.ToolChainCore_GetLastErrorColumn(1, 2, ctypes.byref(column)) == -1
    assert lib.ToolChainCore_GetLastErrorColumn(1, 0, None) == -1
    assert lib.ToolChainCore_GetLastErrorColumn(7, 0, ctypes.byref(column)) == -2


@pytest.mark.parametrize("plane, arc, number, first_line", [
    ("G18", "G0 X10 Z0\nG2 X0 Z10.03 I-10 K0\n", 418, "XZ\nStart X = 10 Z = 0 | End X = 0 Z = 10.03"),
    ("G19", "G0 Y0 Z0\nG2 Y30 Z0 J1 K0\n", 416, "YZ\nStart Y = 0 Z = 0 | End Y = 30 Z = 0"),
    ("G-18", "G0 Z10 X0\nG2 Z0 X10.03 K-10 I0\n", 420, "ZX\nStart Z = 10 X = 0 | End Z = 0 X = 10.03"),
])
def test_the_other_planes_have_the_400_form_of_their_own(host, plane, arc, number, first_line):
    """An XY text would tell a panel the wrong axes: each plane has its number, its
    axes in the text and six arguments."""
    from sf_tch import ErrorNumber
    r = host.compile(f"{plane}\n{arc}", absMode=1)
    got, line, _, text, args = r.error
    assert (got, line) == (number, 3)
    assert text.startswith("Wrongly entered centre of circular interpolation " + first_line + "\n")
    assert len(args.split("\n")) == 6
    assert text == ErrorNumber(number).format % tuple(float(a) for a in args.split("\n"))


# ------------------------------------------------------------ words, positions

def test_empty_program_has_no_parts(host):
    assert ok(host, "").parts == []
    assert ok(host, "\n\n  \n% header\n( only a comment )\n").parts == []


def test_words_case_spaces_comments(host):
    code = ("%\nn10 g1x10y20 f500 ; comment\nN20 G1 X 30 (inline) Y 40 // tail\n"
            "REM remark\nG29 a comment line X99\nG1 X50 rem Y99\n")
    r = ok(host, code, start=[0] * 10)
    assert [p.e[:2] for p in r.g] == [(10, 20), (30, 40), (50, 40)]
    assert [p.line for p in r.g] == [2, 3, 6]
    assert r.g[0].pars["F"] == 500


def test_absolute_relative_and_start(host):
    start = [1, 2, 3, 4, 5, 6, 7, 8, 9, 10]
    r = ok(host, "G91 G1 X1 Y1 Z1 C1 B1 U1 V1 W1 A1 O1\nG90 X0\nX5 Y5\n", start=start)
    assert close(r.g[0].e, [v + 1 for v in start])
    assert close(r.g[0].s, start)
    assert close(r.g[1].e[:3], (0, 3, 4))
    assert r.g[1].func == 1
    r = ok(host, "G1 X1\nX1\n", absMode=0, start=[5] * 10)
    assert [p.e[0] for p in r.g] == [6, 7]


def test_modal_motion_and_rapid_feed(host):
    p = host.params(absMode=1)
    p.motion[0].feed = 12000
    p.motion[1].feed = 777
    r = ok(host, "G0 X10\nY10\nG1 X0\nY0 F100\nG0 X1\n", params=p, start=[0] * 10)
    assert [q.func for q in r.g] == [0, 0, 1, 1, 0]
    assert [q.feed for q in r.g] == [12000, 12000, 777, 100, 12000]
    assert all(q.per_min == 1 for q in r.g)


def test_force_mode_fp_ff_and_m99(host):
    p = host.params()
    p.motion[0].feed = 5000
    p.motion[1].feed = 300
    code = "G1 X1 F100 FP0.5\nG0 X2 FF2000\nM99 F250\nG1 X3 F0\nG95 G1 X4 F0.2\n"
    r = ok(host, code, params=p, start=[0] * 10)
    assert [q.feed for q in r.g] == [100, 2000, 250, pytest.approx(0.2)]
    assert r.g[0].fp == pytest.approx(0.5)
    assert [q.per_min for q in r.g] == [1, 1, 1, 0]
    p.forceMode = 1
    r = ok(host, code, params=p, start=[0] * 10)
    assert [q.feed for q in r.g] == [300, 5000, 300, 300]
    assert r.g[0].fp == 1.0
    p.forceMode = 2
    r = ok(host, code, params=p, start=[0] * 10)
    assert [q.feed for q in r.g] == [300, 5000, 300, 300]
    assert r.g[0].fp == pytest.approx(0.5)


def test_spindle_tool_and_dwell(host):
    r = ok(host, "T3 M6\nM3 S1200\nG4 X1.5\nG4 W250\nG1 X1\n", start=[0] * 10)
    assert [(p.kind, p.func) for p in r.parts] == [("M", 6), ("M", 3), ("G", 4), ("G", 4), ("G", 1)]
    assert r.parts[0].tool == 3 and r.parts[-1].tool == 3
    assert r.parts[-1].pars["S"] == 1200
    # the dwell's X is no axis move
    assert r.parts[-1].s[0] == 0


# ------------------------------------------------------------ arcs

def test_arc_ijk_r_and_q70(host):
    r = ok(host, "G1 X10 Y0\nG3 X0 Y10 I-10 J0\nG2 X10 Y0 R10\nG3 X0 Y10 R10\nG2 X10 Y0 I0 J0 Q70\n",
           start=[0] * 10)
    g = r.g[1:]
    assert close(g[0].cc[:2], (0, 0)) and g[0].func == 3
    assert g[0].cc[3] == pytest.approx(10)
    # G2 from (0,10) to (10,0) with R10 (<= 180 deg): the centre is at the origin
    assert close(g[1].cc[:2], (0, 0), 1e-9)
    # G3 (10,0) -> (0,10) R10: CCW short arc -> centre at origin as well
    assert close(g[2].cc[:2], (0, 0), 1e-9)
    assert close(g[3].cc[:2], (0, 0)) and g[3].func == 2


def test_arc_r_picks_the_side_by_direction(host):
    r = ok(host, "G2 X20 Y0 R10\nG0 X0 Y0\nG3 X20 Y0 R10\nG0 X0 Y0\nG2 X10 Y0 R-7.0710678118654755\n",
           start=[0] * 10)
    assert close(r.g[0].cc[:2], (10, 0), 1e-9)
    assert close(r.g[2].cc[:2], (10, 0), 1e-9)
    # half circle with a radius larger than half the chord
    c = r.g[4].cc
    assert math.hypot(c[0], c[1]) == pytest.approx(7.0710678118654755)
    assert c[1] == pytest.approx(5.0)      # G2 with negative R: the long way, centre above


def test_arc_planes_and_helix(host):
    r = ok(host, "G18 G2 X10 Z10 I10 K0\nG19 G3 Y10 Z0 J0 K-10\nG-18 G2 X-10 Z0 I-10 K0\nG17 G3 X0 Y10 Z5 I5 J0\n",
           start=[0] * 10)
    g = r.g
    assert [p.plane for p in g] == [18, 19, -18, 17]
    assert close(g[0].cc[:3], (10, 0, 0))
    assert close(g[1].cc[:3], (10, 0, 0))
    assert close(g[2].cc[:3], (0, 10, 0))
    assert close(g[3].e[:3], (0, 10, 5)) and close(g[3].cc[:2], (-5, 10))


def test_full_circle_and_swap(host):
    r = ok(host, "G2 I5 J0\n", start=[0] * 10)
    assert r.g[0].func == 2 and close(r.g[0].e[:2], (0, 0)) and close(r.g[0].cc[:2], (5, 0))
    r = ok(host, "G2 X10 Y0 I5 J0\nG3 X0 Y0 I-5 J0\n", start=[0] * 10, swapG2G3=1)
    assert [p.func for p in r.g] == [3, 2]


def test_arc_tolerance(host):
    p = host.params()
    p.tolerance[0] = 0.01
    assert host.compile("G2 X10 Y0.005 I5 J0\n", params=p, start=[0] * 10).error is None
    err = host.compile("G2 X9 Y0 I5 J0\n", params=p, start=[0] * 10).error
    assert err[0] == 407 and err[3].endswith("\nRadius at start (5.0000000) <> radius at end (4.0000000)")


# ------------------------------------------------------------ offsets and transforms

def test_zero_offsets_and_g92(host):
    code = ("G54 X100 Y50\nG1 X1 Y1\nG59 Z7\nG1 Z1\nG55 X10\nG1 X0 Y0 Z0\nG53\nG1 X0\n"
            "G92 X0 Y0\nG1 X1 Y1\n")
    r = ok(host, code, start=[0] * 10)
    g = r.g
    assert close(g[0].e[:3], (101, 51, 0)) and close(g[0].zero[:2], (100, 50))
    assert close(g[1].e[:3], (101, 51, 8))
    assert close(g[2].e[:3], (10, 0, 0))
    assert close(g[3].e[:3], (0, 0, 0))
    assert close(g[4].e[:2], (1, 1))
    r = ok(host, "G1 X5 Y5\nG92 X0 Y0\nG1 X1 Y1\n", start=[0] * 10)
    assert close(r.g[1].e[:2], (6, 6)) and close(r.g[1].zero[:2], (5, 5))


def test_mirroring_and_rotation(host):
    r = ok(host, "G1 X10 Y5\nM81\nG1 X10 Y5\nG2 X20 Y5 I5 J0\nM80\nG1 X1 Y1\n", start=[0] * 10)
    g = r.g
    assert close(g[1].e[:2], (-10, 5))
    assert g[2].func == 3 and close(g[2].cc[:2], (-15, 5)) and close(g[2].e[:2], (-20, 5))
    assert close(g[3].e[:2], (1, 1))
    r = ok(host, "G168 X0 Y0 R90\nG1 X10 Y0\nG169\nG1 X10 Y0\n", start=[0] * 10)
    assert close(r.g[0].e[:2], (0, 10), 1e-9)
    assert close(r.g[1].e[:2], (10, 0), 1e-9)


def test_relative_mirror_renumbered_builtins(host):
    p = host.params()
    p.M81_mirrorX = 181
    p.M02_programEnd1 = 0
    r = ok(host, "M81\nM181\nG1 X5\nM2\nG1 Y5\n", params=p, start=[0] * 10)
    # M81 became an ordinary waiting M, M181 mirrors X, M2 no longer ends the program
    assert [(q.kind, q.func) for q in r.parts] == [("M", 81), ("G", 1), ("M", 2), ("G", 1)]
    assert close(r.parts[1].e[:2], (-5, 0))


# ------------------------------------------------------------ M functions, indexes

def test_m_function_order_and_program_end(host):
    r = ok(host, "G1 X14.2 Y45.89 M2003 M8\nM0\nM1\nM30\nG1 X0\n", start=[0] * 10)
    assert [(p.kind, p.func) for p in r.parts] == [("M", 2003), ("G", 1), ("M", 8), ("M", 0), ("M", 1), ("M", 30)]
    assert r.parts[0].s[:2] == (0, 0)        # signalled at the start of the move
    assert [p.gindex for p in r.parts] == [0, 2, 4, 6, 8, 10]
    assert r.parts[2].pars["M"] == 8


def test_gcode_index_restart_and_plc_write(host):
    plc = library.plc_memory()
    ctypes.memset(ctypes.addressof(plc) + 100, 0, 4)
    r = ok(host, "G1 X1\nM-6 A100\nM-6 S51\nG1 X2\nM10\n", start=[0] * 10)
    assert [p.gindex for p in r.parts] == [0, 52, 54]
    assert int.from_bytes(bytes(plc[100:104]), "little", signed=True) == 2


def test_print_and_m29(host):
    r = ok(host, 'PRINT "Hello world"\nM29 second text  \nG1 X1\n', start=[0] * 10)
    assert r.printed == ["Hello world", "second text"]
    assert [p.func for p in r.parts] == [1]


# ------------------------------------------------------------ parameters, expressions

def test_parameters_and_expressions(host):
    user = [0.0] * 100
    user[21] = 2.0
    user[22] = 3.0
    code = ("P37 = 10 + 25 * SIN(30)\nG1 X P37 Y P21+P22\nG1 X (P21*2)^3 Y -2^2\n"
            "G1 X 7 % 4 + ABS(-1) + SQRT(16) Y ATAN2(1, 1) + HYPOT(3, 4)\n"
            "G1 X FLOOR(2.7) + CEIL(2.2) + LOG10(100) + LOG(1) Y PI() + COS(60) + TAN(45)\n"
            "P1 = ASIN(1) + ACOS(1) + ATAN(1) + FABS(-2)\nG1 X P1\nG1 X 10 - 2 * 3 Y (10 - 2) * 3\n")
    r = ok(host, code, user=user, start=[0] * 10)
    g = r.g
    assert close(g[0].e[:2], (22.5, 5))
    assert close(g[1].e[:2], (64, -4))
    assert close(g[2].e[:2], (3 + 1 + 4, 45 + 5))
    assert close(g[3].e[:2], (2 + 3 + 2 + 0, math.pi + 0.5 + 1))
    assert close(g[4].e[:1], (90 + 0 + 45 + 2,))
    assert close(g[5].e[:2], (4, 24))


def test_plc_memory_access(host):
    plc = library.plc_memory()
    ctypes.c_int32.from_address(ctypes.addressof(plc) + 8).value = 1234
    ctypes.c_double.from_address(ctypes.addressof(plc) + 16).value = 2.5
    code = ("G1 X ReadPLCLong(8) Y ReadPLCDouble(16)\nP1 = WritePLCLong(8, 77)\nP2 = WritePLCDouble(16, -1.25)\n"
            "G1 X P1 Y P2\n")
    r = ok(host, code, start=[0] * 10)
    assert close(r.g[0].e[:2], (1234, 2.5)) and close(r.g[1].e[:2], (1234, 2.5))
    assert ctypes.c_int32.from_address(ctypes.addressof(plc) + 8).value == 77
    assert ctypes.c_double.from_address(ctypes.addressof(plc) + 16).value == -1.25


def test_numbers_match_strtod(host):
    rnd = random.Random(7)
    values = []
    for _ in range(300):
        digits = rnd.randint(1, 19)
        frac = rnd.randint(0, min(digits, 12))
        s = "".join(rnd.choice("0123456789") for _ in range(digits))
        text = s[:digits - frac] + ("." + s[digits - frac:] if frac else "")
        if text.startswith("."):
            text = "0" + text
        values.append(text)
    values += ["0.1", "123456789012345678901234567890.5", "0.30000000000000004", "1.", ".5",
               "9007199254740993", "0.0000000000000000000000001"]
    code = "".join(f"G1 X{v}\n" for v in values)
    r = ok(host, code, start=[0] * 10)
    assert [p.e[0] for p in r.g] == [float(v) for v in values]


def _decimal(rnd, int_digits, frac_digits, dot):
    """A decimal text of the given digit counts: '' int digits make '.5', a dot without
    decimals '5.'."""
    whole = "".join(rnd.choice("0123456789") for _ in range(int_digits))
    frac = "".join(rnd.choice("0123456789") for _ in range(frac_digits))
    return whole + ("." + frac if dot else "")


def test_number_forms_match_float(host):
    """Every form of a plain number reads as Python's float() reads it (correctly rounded):
    the exact path (up to 19 digits, mantissa up to 2^53, up to 22 decimals) and strtod's
    (beyond any of these) alike, wherever the word stands on its line."""
    rnd = random.Random(11)
    values = ["9007199254740992", "9007199254740993", "900719925474099.3", "1234567890123456789",
              "12345678901234567890", "0.5", "0.5000000000000000000000", "0.50000000000000000000000",
              "0.0000000000000000000001", "0.00000000000000000000001", "5.", ".5", "0.", "000.000",
              "00000000000000000000000001.5", "1" * 25, "3." + "3" * 30]
    for _ in range(400):
        int_digits = rnd.choice((0, 1, 2, 3, 4, 5, 8, 12, 15, 16, 17, 19, 20, 25))
        frac_digits = rnd.choice((0, 1, 2, 3, 4, 6, 10, 15, 19, 22, 23, 30))
        dot = frac_digits > 0 or int_digits == 0 or rnd.random() < 0.2
        if int_digits + frac_digits == 0:
            frac_digits = 1
        values.append(_decimal(rnd, int_digits, frac_digits, dot))
    # the word's surroundings: end of line, blanks, CR, a comment, the next word, lower case,
    # a minus sign, blanks between the letter and the number
    forms = ["G1 X{}\n", "G1 X{} Y1\n", "G1 X{}\r\n", "G1 X{}(c)Y1\n", "G1 X{} ; c\n", "g1 x{}\n",
             "G1 X {}\n", "G1 X\t{} // c\n", "G1 X-{}\n", "G1 X -{} Y2\n"]
    lines, expected = [], []
    for k, v in enumerate(values):
        form = forms[k % len(forms)]
        lines.append(form.format(v))
        expected.append(-float(v) if "-{}" in form else float(v))
    r = ok(host, "G90\n" + "".join(lines), start=[0] * 10)
    assert [p.e[0] for p in r.g] == expected


@pytest.mark.parametrize("text", ["1.5", "0.25", "12345.678", "7", "0.0001"])
def test_number_then_expression_agree(host, text):
    """A number followed by an operator leaves the number's path for the expression
    parser's: both read it the same."""
    r = ok(host, f"G90\nG1 X{text}\nG1 X{text}+0\nG1 X ( {text} )\nG1 X{text} * 1\nG1 X-{text}\n"
                 f"G1 X-{text}-0\nG1 X0-{text}\n", start=[0] * 10)
    v = float(text)
    assert [p.e[0] for p in r.g] == [v, v, v, v, -v, -v, -v]


# ------------------------------------------------------------ program flow

def test_loops_and_conditions(host):
    code = """P1 = 0
FOR P2 = 1 TO 5
  IF P2 == 2 CONTINUE
  IF P2 > 4 BREAK
  G1 X P2
END
WHILE P1 < 3
  P1 = P1 + 1
  IF P1 <> 2 THEN
    G1 Y P1
  ELSE
    G1 Z P1
  END
END
FOR P3 = 10 TO 0 STEP -5
  G1 A P3
ENDFOR
FOR P4 = 1 TO 0
  G1 X999
END
"""
    r = ok(host, code, start=[0] * 10)
    moves = [(p.e[0], p.e[1], p.e[2], p.e[8]) for p in r.g]
    assert moves == [(1, 0, 0, 0), (3, 0, 0, 0), (4, 0, 0, 0), (4, 1, 0, 0), (4, 1, 2, 0), (4, 3, 2, 0),
                     (4, 3, 2, 10), (4, 3, 2, 5), (4, 3, 2, 0)]


def test_subroutines_labels_and_jumps(host):
    code = """CALL SQUARE
G25 L1000
G26 L1000 H3
GOTO SKIP
G1 X999
SKIP:
G27 LFINISH
G1 X888
G29 FINISH end of the program
M30
SQUARE:
G91 G1 X1
RETURN
N1000 G91 G1 Y1
IF P1 > 100 RETURN
M17
"""
    r = ok(host, code, start=[0] * 10)
    assert [p.e[:2] for p in r.g] == [(1, 0), (1, 1), (1, 2), (1, 3), (1, 4)]
    assert [p.line for p in r.g] == [12, 14, 14, 14, 14]
    assert r.m[-1].func == 30


def test_prefix_postfix_file_indexes(host):
    r = ok(host, "G1 X1\n", prefix="G1 Y5\n", postfix="M5\n", start=[0] * 10)
    lib = host.lib
    names = [lib.ToolChainCore_IdxToFile(1, p.file_idx).decode() for p in r.parts]
    assert names == ["__prefix__", "prog.nc", "__postfix__"]
    assert [p.line for p in r.parts] == [1, 1, 1]


def test_realistic_cutting_program(host):
    lines = ["% cutting plate 3", "G90 G17 G94", "T1 M6", "M3 S12000", "P10 = 4"]
    lines += ["FOR P1 = 0 TO P10 - 1", "  G0 X P1 * 30 Y0", "  M1001", "  G1 Y20 F1500",
              "  G2 X P1 * 30 + 20 Y20 R10", "  G1 Y0", "  G3 X P1 * 30 Y0 I-10 J0", "  M1002", "END"]
    lines += ["M5", "G0 X0 Y0", "M30"]
    r = ok(host, "\n".join(lines) + "\n", start=[0] * 10)
    assert len(r.g) == 4 * 5 + 1
    arcs = [p for p in r.g if p.func in (2, 3)]
    assert len(arcs) == 8 and all(p.cc[3] == pytest.approx(10) for p in arcs)
    gi = [p.gindex for p in r.parts]
    assert gi == list(range(0, 2 * len(gi), 2))
