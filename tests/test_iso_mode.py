"""The ISO compatibility mode against LinuxCNC's documented results (docs/compiler.md,
"ISO compatibility mode"): parameters and expressions, O-word flow, home positions,
canned cycles, work offsets, the order of a line, and what the TG dialect keeps.
Expected endpoints are computed by hand from LinuxCNC's documentation (the G-code,
O-code and overview chapters); expression values by Python's math. Core 2."""
import ctypes
import math

import pytest

import sf_tch
from compiler_host import Host, close, ok

ISO = 1                                 # GCODE_REZERVA1_ISO_COMPAT


PACKAGE_CORE = 0                        # sf_tch.compile's core, for the toolpath's feeds and lengths


@pytest.fixture(scope="module")
def host(tmp_path_factory):
    """Core 2 through the test host; a core keeps its GCODE_PARAMETERS from one user to
    the next, so both cores leave with the mode off."""
    h = Host(2, tmp_path_factory.mktemp("core2iso"))
    h.defaults.rezerva1 = 0
    yield h
    h.lib.ToolChainCore_SetGCodeParameters(h.core, ctypes.byref(h.defaults))
    h.close()
    with sf_tch.Core(PACKAGE_CORE) as core:
        core.update_params(rezerva1=0)


# the parts as written: no collinear G1 parts joined (tolerance[2] = 0)
AS_WRITTEN = dict(tolerance=(0.005, 0.001, 0.0, 0.005, 0.0, 3.0, 0.01, 0.0, 0.0, 0.0))


def toolpath(code):
    with sf_tch.compile(code, iso=True, start=[0] * 10, core=PACKAGE_CORE, params=AS_WRITTEN) as program:
        assert program.ok, program.errors
        return program.toolpath.records


def iso(host, code, **kw):
    return ok(host, code, start=[0] * 10, rezerva1=ISO, **kw)


def iso_error(host, code):
    r = host.compile(code, run=False, start=[0] * 10, rezerva1=ISO)
    assert r.error is not None, code
    return r.error


def ends(parts):
    return [tuple(round(v, 9) for v in p.e[:3]) for p in parts]


def moves(r):
    """(G number, x y z end) of every motion part."""
    return [(p.func, tuple(round(v, 9) for v in p.e[:3])) for p in r.g if p.func != 4]


# ------------------------------------------------------------------ parameters

def test_parameters_are_set_after_the_line_is_read(host):
    # LinuxCNC: the values of a line are read first, its settings take effect after it;
    # of two settings of one parameter the last counts
    r = iso(host, "#1=2 #<_g>=3 #<a>=[#1+1] #3=15 #3=6\nG0 X#1 Y[#<_g>**2] Z#<a>\nG0 X#3\n")
    assert ends(r.g) == [(2, 9, 1), (6, 9, 1)]
    # ##n and #[expression] read a parameter whose number is a value
    r = iso(host, "#5=7 #7=4\nG0 X##5 Y#[2+3]\n")
    assert ends(r.g) == [(4, 7, 0)]


EXPRESSIONS = [
    ("2**3**2", (2 ** 3) ** 2),                     # equal precedence: left to right
    ("2+3*4-6/3", 2 + 3 * 4 - 6 / 3),
    ("-2**2", 4.0),                                 # a sign belongs to its number
    ("-[2]**2", 4.0),
    ("7 MOD 3", 1.0),
    ("-7 MOD 3", 2.0),                              # LinuxCNC's MOD is never negative
    ("2 EQ 2.0000001", 1.0),                        # EQ and NE within 1e-6
    ("2 EQ 2.00001", 0.0),
    ("2 NE 2.0000001", 0.0),
    ("3 GT 2 AND 1 LT 0", 0.0),                     # relations bind tighter than AND
    ("1 OR 0 XOR 1", 0.0),                          # AND OR XOR: left to right
    ("2 GE 2", 1.0), ("2 LE 1", 0.0),
    ("ABS[-2.5]", 2.5), ("ACOS[0.5]", 60.0), ("ASIN[0.5]", 30.0), ("COS[60]", math.cos(math.radians(60))),
    ("SIN[30]", math.sin(math.radians(30))), ("TAN[45]", math.tan(math.radians(45))),
    ("ATAN[1]/[-1]", 135.0), ("EXP[1]", math.e), ("LN[10]", math.log(10)), ("SQRT[2]", math.sqrt(2)),
    ("FIX[-2.8]", -3.0), ("FUP[-2.8]", -2.0), ("FIX[2.8]", 2.0), ("FUP[2.8]", 3.0), ("ROUND[2.5]", 3.0),
    ("ROUND[-2.5]", -3.0), ("EXISTS[#<_value>]", 1.0), ("EXISTS[#<nothing>]", 0.0),
    ("[1 + acos[0] - [3 ** [4.0/2]]]", 1 + 90 - 9),
    ("2.0 / 3 * 1.5 - 5.5 / 11.0", 0.5),
]


@pytest.mark.parametrize("expression, value", EXPRESSIONS)
def test_expressions_operators_and_functions(host, expression, value):
    r = iso(host, f"G0 X[{expression}]\n")
    assert math.isclose(r.g[0].e[0], value, rel_tol=1e-12, abs_tol=1e-12), (expression, r.g[0].e[0])


def test_predefined_parameters_read_the_state(host):
    # (read with the line, before its G91 runs)
    r = iso(host, "G21 G0 X3 Y4\nG91 G0 X#<_x> Y#<_absolute> Z[#<_incremental> + #5420]\n")
    assert ends(r.g) == [(3, 4, 0), (6, 5, 3)]
    r = iso(host, "G20 G0 X1\nG0 Y#<_x> Z#<_imperial>\n")          # in the program's units
    assert ends(r.g) == [(25.4, 0, 0), (25.4, 25.4, 25.4)]


def test_parameter_scoping_in_subroutines(host):
    # O-codes: #1..#30 are the call's (the caller's come back); named parameters belong
    # to the level that set them; #<_name> is global; #<_value> is what return gave
    code = """#1 = 7 #2 = 8 #<loc> = 1 #<_glob> = 2
o<s> sub
  G0 X#1 Y#2
  o1 if [EXISTS[#<loc>]]
    G0 Z99
  o1 endif
  #<loc> = 50
  #<_glob> = [#<_glob> + 1]
  #1 = 100
o<s> return [42]
o<s> endsub
o<s> call [5]
G0 X#1 Y#<loc> Z#<_glob>
G0 Z[#<_value> + #<_value_returned>]
"""
    r = iso(host, code)
    assert ends(r.g) == [(5, 8, 0), (7, 1, 3), (7, 1, 43)]
    assert [p.line for p in r.g] == [3, 13, 14]


def test_subroutine_nesting_limit_names_the_line(host):
    code = "o<r> sub\no1 if [#1 GT 0]\no<r> call [#1 - 1]\no1 endif\nG0 X#1\no<r> endsub\no<r> call [{}]\n"
    r = iso(host, code.format(8))               # 9 nested calls: LinuxCNC's limit of 10 levels
    assert [p.e[0] for p in r.g] == list(range(9))
    number, line, _, text, _ = iso_error(host, code.format(9))
    assert (number, line) == (304, 3) and text == "Subroutine calls nested deeper than 9"


def test_a_subroutine_is_called_after_its_definition(host):
    # its body does not run where it is defined; a call before it is an error
    r = iso(host, "G0 X1\no100 sub\nG0 X#1\no100 endsub\nG0 Y2\no100 call [3]\n")
    assert ends(r.g) == [(1, 0, 0), (1, 2, 0), (3, 2, 0)]
    number, line, _, text, _ = iso_error(host, "o100 call [3]\no100 sub\no100 endsub\n")
    assert (number, line) == (311, 1) and "'o100' at column 1" in text


@pytest.mark.parametrize("value, branch", [(1, 1), (2, 2), (5, 3)])
def test_if_elseif_else(host, value, branch):
    code = (f"#1 = {value}\no1 if [#1 EQ 1]\nG0 X1\no1 elseif [#1 LT 3]\nG0 X2\no1 else\nG0 X3\no1 endif\n"
            "G0 Y1\n")
    r = iso(host, code)
    assert ends(r.g) == [(branch, 0, 0), (branch, 1, 0)]


def test_loops(host):
    code = """#1 = 0
o1 while [#1 LT 3]
  G0 X#1
  #1 = [#1 + 1]
o1 endwhile
o2 do
  G0 Y#1
  #1 = [#1 - 1]
  o3 if [#1 EQ 1]
    o2 continue
  o3 endif
o2 while [#1 GT 0]
o4 repeat [5]
  G0 Z#1
  #1 = [#1 + 1]
  o5 if [#1 GT 1]
    o4 break
  o5 endif
o4 endrepeat
o6 repeat [0]
  G0 Z9
o6 endrepeat
"""
    r = iso(host, code)
    assert [p.e[0] for p in r.g[:3]] == [0, 1, 2]                 # while: 0 1 2
    assert [p.e[1] for p in r.g[3:6]] == [3, 2, 1]                # do/while with continue
    assert [p.e[2] for p in r.g[6:]] == [0, 1]                    # repeat left by break; repeat [0]


def test_computed_call_label(host):
    r = iso(host, "o102 sub\nG0 X#1\no102 endsub\n#101 = 100\no[#101 + 2] call [4]\n")
    assert ends(r.g) == [(4, 0, 0)]


# ------------------------------------------------------------------ the order of a line

def test_dwell_then_motion_on_one_line(host):
    # LinuxCNC's skeleton.ngc: G4 runs before the motion of its line
    r = iso(host, "G20\nG04 P.001 G0 X1.0 Y1.0\n")
    assert [p.func for p in r.g] == [4, 0] and r.g[0].pars["H"] == pytest.approx(0.001) and "H" not in r.g[1].pars
    assert close(r.g[1].e[:2], (25.4, 25.4))


def test_g90_with_axis_words_keeps_the_modal_motion(host):
    # SuperCam: G90 X0 Y0 Z0 M30 after a G0 is a rapid (TG: G90 with axis words is G1)
    r = iso(host, "G0 X10 Y5\nG90 X0 Y0 Z0 M30\n")
    assert [p.func for p in r.g] == [0, 0] and [p.func for p in r.m] == [30]


def test_m_functions_run_before_the_motion_the_stops_after(host):
    r = iso(host, "G0 X10 M3 S1000\nG0 X20 M5 M30\n")
    assert [(p.kind, p.func) for p in r.parts] == [("M", 3), ("G", 0), ("M", 5), ("G", 0), ("M", 30)]


# ------------------------------------------------------------------ home positions

def test_g28_g91_z0_as_fusion_posts_write_it(host):
    # G91 of the line applies first: the intermediate point is the current Z (no move),
    # then Z goes to the stored position (#5163, 0); X and Y stay; G91 stays in force
    r = iso(host, "G0 X10 Y20 Z30\nG28 G91 Z0.\nX1\n")
    assert ends(r.g) == [(10, 20, 30), (10, 20, 0), (11, 20, 0)]


def test_g28_with_axes_goes_through_them_and_g28_1_stores(host):
    r = iso(host, "G0 X10 Y20 Z30\nG28 X5\nG0 X7 Y8 Z9\nG28.1\nG0 X1 Y1 Z1\nG28\nG30 Y3\n")
    # G28 X5: to X5, then X home (0) alone; G28 (no axes): every axis to #5161.. (7 8 9);
    # G30 Y3: to Y3, then Y to #5182 (never stored: 0)
    assert ends(r.g) == [(10, 20, 30), (5, 20, 30), (0, 20, 30), (7, 8, 9), (1, 1, 1), (7, 8, 9),
                         (7, 3, 9), (7, 0, 9)]
    assert all(p.func == 0 for p in r.g)


def test_home_parameters_can_be_written(host):
    r = iso(host, "#5161 = 2 #5163 = 4\nG0 X10 Y10 Z10\nG28 X0 Z0\n")
    assert ends(r.g)[-1] == (2, 10, 4)


# ------------------------------------------------------------------ canned cycles

def test_g81_documented_examples(host):
    # G-code chapter, G81 example 1: from (1, 2, 3), G90 G98 ... X4 Y5 Z1.5 R2.8
    r = iso(host, "G0 X1 Y2 Z3 F10\nG90 G98 G81 X4 Y5 Z1.5 R2.8\n")
    assert moves(r)[1:] == [(0, (4, 5, 3)), (0, (4, 5, 2.8)), (1, (4, 5, 1.5)), (0, (4, 5, 3))]
    # example 2: G91 G98 ... X4 Y5 Z-0.6 R1.8 L3: R from the current Z, Z from R, three holes
    r = iso(host, "G0 X1 Y2 Z3 F10\nG91 G98 G81 X4 Y5 Z-0.6 R1.8 L3\n")
    assert moves(r)[1:] == [(0, (1, 2, 4.8)),
                            (0, (5, 7, 4.8)), (1, (5, 7, 4.2)), (0, (5, 7, 4.8)),
                            (0, (9, 12, 4.8)), (1, (9, 12, 4.2)), (0, (9, 12, 4.8)),
                            (0, (13, 17, 4.8)), (1, (13, 17, 4.2)), (0, (13, 17, 4.8))]


def test_cycles_are_modal_with_sticky_r_and_z_and_g99_retracts_to_r(host):
    r = iso(host, "G0 X0 Y0 Z10 F100\nG99 G81 X1 Z-2 R1\nX2\nG98 X3 Z-3\nG80\nG0 X0\n")
    assert moves(r)[1:] == [(0, (1, 0, 10)), (0, (1, 0, 1)), (1, (1, 0, -2)), (0, (1, 0, 1)),      # G99: to R
                            (0, (2, 0, 1)), (1, (2, 0, -2)), (0, (2, 0, 1)),
                            # G98: back to the level before the series (10)
                            (0, (3, 0, 1)), (1, (3, 0, -3)), (0, (3, 0, 10)),
                            (0, (0, 0, 10))]
    number, line, _, text, _ = iso_error(host, "G0 Z5 F10\nG81 X1 Z-1 R1\nG80\nX2\n")
    assert (number, line) == (411, 4)


def test_g83_peck_and_g73_chip_break(host):
    # G83: feed down by Q, rapid out to R, rapid back to 0.010 inch (0.254 mm) above the
    # last depth; G73: the same without going out to R
    r = iso(host, "G0 X0 Y0 Z5 F100\nG83 Z-2.5 R1 Q1.5\n")
    assert moves(r)[1:] == [(0, (0, 0, 5)), (0, (0, 0, 1)), (1, (0, 0, -0.5)), (0, (0, 0, 1)),
                            (0, (0, 0, -0.246)), (1, (0, 0, -2)), (0, (0, 0, 1)), (0, (0, 0, -1.746)),
                            (1, (0, 0, -2.5)), (0, (0, 0, 5))]
    r = iso(host, "G0 X0 Y0 Z5 F100\nG73 Z-2.5 R1 Q1.5\n")
    assert moves(r)[1:] == [(0, (0, 0, 5)), (0, (0, 0, 1)), (1, (0, 0, -0.5)), (0, (0, 0, -0.246)),
                            (1, (0, 0, -2)), (0, (0, 0, -1.746)), (1, (0, 0, -2.5)), (0, (0, 0, 5))]
    # in an inch program Q is a length too
    r = iso(host, "G20 G0 X0 Y0 Z1 F10\nG99 G73 Z-0.1 R0.1 Q0.1\n")
    assert [p.e[2] for p in r.g if p.func == 1] == pytest.approx([0.0, -2.54])


def test_dwell_and_feed_out_cycles(host):
    code = "G0 X0 Y0 Z5 F100\nM3 S500\n{} Z-1 R1 P0.5\n"
    kinds = lambda r: [(p.kind, p.func, round(p.e[2], 9)) for p in r.parts[2:]]
    # G82: dwell at the bottom, rapid out
    assert kinds(iso(host, code.format("G82"))) == [("G", 0, 5), ("G", 0, 1), ("G", 1, -1), ("G", 4, -1),
                                                     ("G", 0, 5)]
    # G85: feed to the bottom, feed out to R, rapid to the clear level
    assert kinds(iso(host, code.format("G85"))) == [("G", 0, 5), ("G", 0, 1), ("G", 1, -1), ("G", 1, 1),
                                                     ("G", 0, 5)]
    # G86: dwell, spindle stop, rapid out, spindle on again as it turned
    assert kinds(iso(host, code.format("G86"))) == [("G", 0, 5), ("G", 0, 1), ("G", 1, -1), ("G", 4, -1),
                                                     ("M", 5, -1), ("G", 0, 5), ("M", 3, 5)]
    # G89: dwell, feed out
    assert kinds(iso(host, code.format("G89"))) == [("G", 0, 5), ("G", 0, 1), ("G", 1, -1), ("G", 4, -1),
                                                     ("G", 1, 5)]
    # G84 (right hand tapping): feed in, spindle reversed, dwell, feed out, spindle clockwise
    assert kinds(iso(host, code.format("G84"))) == [("G", 0, 5), ("G", 0, 1), ("G", 1, -1), ("M", 5, -1),
                                                     ("M", 4, -1), ("G", 4, -1), ("G", 1, 5), ("M", 5, 5),
                                                     ("M", 3, 5)]
    assert iso_error(host, "G0 Z5 F10\n" + "G84 Z-1 R1\n")[0] == 412     # the spindle does not turn


def test_absolute_repeats_drill_the_same_hole(host):
    r = iso(host, "G0 X0 Y0 Z5 F100\nG98 G81 X2 Z-1 R1 L2\n")
    assert [e for f, e in moves(r)[1:] if f == 1] == [(2, 0, -1), (2, 0, -1)]


def test_polar_positions_of_a_bolt_circle(host):
    # LinuxCNC's hole-circle.ngc: G91 G81 ... ^60 L6 turns each hole by 60 degrees
    r = iso(host, "G21 G17 G90\nG0 X1.5 Y0 Z0 F10\nG91 G81 R.1 Z-.5 ^60 L6\n")
    holes = [p.e[:2] for p in r.g if p.func == 1]
    assert len(holes) == 6
    for k, (x, y) in enumerate(holes):
        assert close((x, y), (1.5 * math.cos(math.radians(60 * (k + 1))), 1.5 * math.sin(math.radians(60 * (k + 1)))),
                     1e-12)
    # absolute: @ distance, ^ angle from the program zero; a missing one is the current point's
    r = iso(host, "G0 @2 ^90\nG0 ^180\n")
    assert close(r.g[0].e[:2], (0, 2), 1e-12) and close(r.g[1].e[:2], (-2, 0), 1e-12)


# ------------------------------------------------------------------ work offsets

def test_g10_and_coordinate_systems(host):
    # G10 L2 P2 sets G55's offset; G55 selects it; G10 L20 P0 makes the current point X0
    # in the active system; G53 moves in machine coordinates for its line only
    code = ("G10 L2 P2 X10 Y20\nG0 X1 Y1\nG55 G0 X1 Y1\nG10 L20 P0 X0\nG0 X2\nG53 G0 X0\nG0 Y0\n"
            "G59.3 G0 X0 Y0\n")
    r = iso(host, code)
    assert ends(r.g) == [(1, 1, 0), (11, 21, 0), (13, 21, 0), (0, 21, 0), (0, 20, 0), (0, 0, 0)]
    # the offsets are parameters: #5241.. (G55); #5220 the active system
    r = iso(host, "#5241 = 3\nG55 G0 X1 Y[#5220]\nG0 Y[#5220]\n")      # (#5220 read before the G55 runs)
    assert ends(r.g) == [(4, 1, 0), (4, 2, 0)]


def test_g92_offsets(host):
    r = iso(host, "G0 X5\nG92 X0\nG0 X1 Y#5211\nG92.1\nG0 X1\n")
    assert ends(r.g) == [(5, 0, 0), (6, 5, 0), (1, 5, 0)]


def test_g90_1_absolute_arc_centres(host):
    a = iso(host, "G0 X10 Y0 F100\nG90.1 G3 X0 Y10 I0 J0\n")
    b = iso(host, "G0 X10 Y0 F100\nG91.1 G3 X0 Y10 I-10 J0\n")
    assert close(a.g[1].e, b.g[1].e) and a.g[1].func == b.g[1].func == 3
    assert iso_error(host, "G0 X10 Y0 F100\nG90.1 G3 X0 Y10 I0\n")[0] == 402   # LinuxCNC wants I and J


# ------------------------------------------------------------------ feeds

def test_inverse_time_feed(host):
    # G93: F is 1 / minutes: a move of 10 mm at F6 takes 10 s (60 mm/min)
    feeds = [float(r["feed"]) for r in toolpath("G21 G0 X0 Y0\nG93 G1 X10 F6\nG1 X40 F2\nG94 G1 X41 F100\n")
             if r["number"] == 1]
    assert feeds == pytest.approx([60.0, 60.0, 100.0])
    assert iso_error(host, "G93 G1 X10 F6\nG1 X20\n")[0] == 412      # every G1 wants its F
    assert iso_error(host, "G93 G1 X10 F6\nG94 G1 X20\n")[0] == 410  # a new F after G93


def test_probe_moves_go_to_the_point_and_set_its_parameters(host):
    r = iso(host, "G0 X1 Y2 Z3\nG38.2 Z-1 F10\nG0 X#5063\n")
    assert [p.func for p in r.g] == [0, 1, 0] and ends(r.g)[1:] == [(1, 2, -1), (-1, 2, -1)]


def test_an_arc_end_off_its_circle_runs_at_the_mean_radius(host):
    # LinuxCNC accepts the end within 0.5 mm when within 0.1 % of the radius and runs a
    # spiral between the radii: the part's radius is their mean
    arc = [r for r in toolpath("G0 X10 Y0 F100\nG3 X-10.004 Y0 I-10 J0\n") if r["number"] == 3][0]
    assert float(arc["radius"]) == pytest.approx(10.002) and float(arc["length"]) == pytest.approx(math.pi * 10.002)
    assert iso_error(host, "G0 X10 Y0 F100\nG3 X0 Y10.03 I-10 J0\n")[0] == 407          # 0.3 %
    assert iso_error(host, "G0 X1000 Y0 F100\nG3 X0 Y1000.6 I-1000 J0\n")[0] == 407      # over 0.5 mm


def test_a_zero_radius_compensates_nothing(host):
    # LinuxCNC's G41 with a tool of radius 0: the programmed path (TG's engine is not run)
    r = iso(host, "G0 X0 Y-5 F100\nG41 G1 X0 Y0\nG1 X10\nG1 Y10\nG40 G1 X0 Y15\n")
    assert [p.comp for p in r.g] == [40] * 5


# ------------------------------------------------------------------ both dialects

def test_a_byte_order_mark_is_no_word(host):
    for mode in (0, ISO):
        r = ok(host, "\ufeffG0 X1 Y2\nG0 X3\n".encode("utf-8"), start=[0] * 10, rezerva1=mode)
        assert ends(r.g) == [(1, 2, 0), (3, 2, 0)]


def test_tg_keeps_its_meaning_and_warns(host):
    from test_cam_programs import compile_logged, warnings_of
    r, log = compile_logged(host, "X1 Y1\nG0 X2\nG90 X3\nG4 W10 G0 Y5\nG1 X4\n")
    w = warnings_of(log)
    assert [p.func for p in r.g] == [1, 0, 1, 4, 1]             # TG: bare axes and G90 move as G1
    assert len(w) == 4, w
    assert w[0].startswith("Warning: G-code, line 1: Axis words at column 1 before any G0..G3 move as G1")
    assert w[1].startswith("Warning: G-code, line 1: G1 at column 1 at feed 0")
    assert w[2].startswith("Warning: G-code, line 3: G90 at column 1 with axis words moves as G1; ISO moves "
                           "with the modal G0")
    assert w[3].startswith("Warning: G-code, line 4: G4 at column 1 with G0: the line dwells and does not move")
