"""The G-code dialect: the interpolator manual's example program and the statements
of docs/dialect.md, checked on the parts a simulation hands to the driver."""
import math

from .checks import Differs, check, expect, near, near_point

D = "dialect.md"

# The example program of the interpolator manual (section "Example of part of the
# G-code", docs/vendor-sources.md): relative coordinates, G42 switched on before arcs.
SEED_PROGRAM = """G00 X60.6051 Y40.7723
G42
M51
G02 X0 Y-2.5202 I3.0336 J-1.2601
G02 X0.922 Y-1.5646 I6.0604 J2.5173
G02 X1.079 Y-1.0269 I4.2143 J3.3479
G02 X2.2624 Y-1.3678 I9.8772 J13.7817
G02 X1.9856 Y-0.8109 I6.1778 J12.2908
G02 X3.015 Y-0.7892 I8.8515 J27.6632
G02 X6.2889 Y0 I3.1444 J33.011
M50
G40
G00 X-28.9085 Y30.4365
G42
M51
G40
M2
"""
SEED_DX = (60.6051, 0, 0.922, 1.079, 2.2624, 1.9856, 3.015, 6.2889)
SEED_DY = (40.7723, -2.5202, -1.5646, -1.0269, -1.3678, -0.8109, -0.7892, 0)


def _plain_seed():
    return "\n".join("" if l in ("G42", "G40") else l for l in SEED_PROGRAM.splitlines()) + "\n"


@check("dialect", "seed_relative_compiles", "vendor-sources.md", "the interpolator manual",
       "the manual's example program compiles with absMode 0 (relative coordinates)")
def _(host):
    host.set_params(0, absMode=0)
    host.compiled(SEED_PROGRAM)


@check("dialect", "seed_parts", D, "G functions",
       "the example's parts: G0, seven G2 arcs, G0; M51 M50 M51 M2; each on its own line")
def _(host):
    rec = host.simulate(_plain_seed(), absMode=0)
    expect([0, 2, 2, 2, 2, 2, 2, 2, 0], [p["func"] for p in rec.of("G")], "G parts")
    expect([51, 50, 51, 2], [p["func"] for p in rec.of("M")], "M parts")
    expect([1, 4, 5, 6, 7, 8, 9, 10, 13], [p["line"] for p in rec.of("G")], "lines of the G parts")


@check("dialect", "seed_relative_ends", D, "Lines and words",
       "relative axis words (G91 / absMode 0) add up: each arc ends at the sum of the words before")
def _(host):
    rec = host.simulate(_plain_seed(), absMode=0)
    x = y = 0.0
    for i, p in enumerate(rec.of("G")[:8]):
        x, y = x + SEED_DX[i], y + SEED_DY[i]
        near_point((x, y), p["e"][:2], 1e-6, f"end of part {i}")


@check("dialect", "seed_arc_centre", D, "G functions",
       "G2 / G3 with I J: the centre relative to the start, the radius sqrt(I² + J²) (m_cc, cells I J)")
def _(host):
    rec = host.simulate(_plain_seed(), absMode=0)
    arc = rec.of("G")[1]
    near_point((60.6051 + 3.0336, 40.7723 - 1.2601), arc["cc"][:2], 1e-6, "m_cc")
    near(math.hypot(3.0336, 1.2601), arc["radius"], 1e-6, "m_cc.c (radius)")


@check("dialect", "absolute_relative", D, "Lines and words",
       "axis words are modal, absolute under G90 and relative under G91")
def _(host):
    rec = host.simulate("G90 G1 X10 Y5 F1000\nG91 X2 Y2\nX1\nG90 X0\n")
    expect([(10, 5), (12, 7), (13, 7), (0, 7)], [tuple(round(v, 9) for v in p["e"][:2]) for p in rec.of("G")],
           "ends")


@check("dialect", "words_comments", D, "Lines and words",
       "words with or without blanks, any case; ( ) // ; REM and % lines are comments")
def _(host):
    code = ("%\nn10 g1x10y20 f500 ; comment\nN20 G1 X 30 (inline) Y 40 // tail\nREM remark\nG1 X50\n")
    rec = host.simulate(code)
    expect([(10, 20), (30, 40), (50, 40)], [tuple(round(v, 9) for v in p["e"][:2]) for p in rec.of("G")], "ends")
    expect([2, 3, 5], [p["line"] for p in rec.of("G")], "lines")
    expect(500.0, rec.of("G")[0]["F"], "F")


@check("dialect", "arc_radius_word", D, "G functions",
       "G2 / G3 with R > 0: the arc up to 180°, its centre from the radius")
def _(host):
    rec = host.simulate("G1 X0 Y0 F1000\nG2 X10 Y0 R5\nG3 X20 Y0 R5\n")
    g = rec.of("G")
    near_point((5, 0), g[1]["cc"][:2], 1e-6, "centre of the G2")
    near_point((15, 0), g[2]["cc"][:2], 1e-6, "centre of the G3")
    expect([1, 2, 3], [p["func"] for p in g], "G numbers")


@check("dialect", "helix", D, "G functions", "G2 / G3 with an axis off the plane: a helix, that axis linear")
def _(host):
    rec = host.simulate("G1 X10 Y0 Z0 F1000\nG3 X10 Y0 Z-3 I-10 J0\n")
    arc = rec.of("G")[1]
    near_point((10, 0, -3), arc["e"], 1e-6, "the helix's end")
    near_point((0, 0), arc["cc"][:2], 1e-6, "its centre")


@check("dialect", "dwell", D, "G functions", "G4 is a dwell: a G part of number 4")
def _(host):
    rec = host.simulate("G1 X1 F1000\nG4 H0.1\nG1 X2\n")
    expect([1, 4, 1], [p["func"] for p in rec.of("G")], "G parts")


@check("dialect", "parameters_expressions", D, "Parameters and expressions",
       "P parameters and expressions with functions in degrees: P37 = 10 + 25 * SIN(30) gives 22.5")
def _(host):
    rec = host.simulate("P37 = 10 + 25 * SIN(30)\nP2 = (P37 - 2.5) / 4\nG1 X P37 Y P2 F1000\n")
    near_point((22.5, 5.0), rec.of("G")[0]["e"][:2], 1e-9, "X P37 Y P2")


@check("dialect", "for_loop", D, "Program flow", "FOR Pn = a TO b … END runs its body once per value")
def _(host):
    rec = host.simulate("G1 X0 F1000\nFOR P1 = 1 TO 3\nG1 X P1\nEND\n")
    expect([0.0, 1.0, 2.0, 3.0], [round(p["e"][0], 9) for p in rec.of("G")], "X of each part")


@check("dialect", "call_return", D, "Program flow",
       "CALL label runs the subroutine at the label up to RETURN / M17, then goes on after the CALL")
def _(host):
    code = "G1 X1 F1000\nCALL sub\nG1 X3\nM30\nsub:\nG1 X2\nRETURN\n"
    rec = host.simulate(code)
    expect([1.0, 2.0, 3.0], [round(p["e"][0], 9) for p in rec.of("G")], "X of each part")
    expect([1, 6, 3], [p["line"] for p in rec.of("G")], "lines")


@check("dialect", "if_else", D, "Program flow", "IF cond THEN … ELSE … END takes one branch")
def _(host):
    rec = host.simulate("P1 = 2\nIF P1 > 1 THEN\nG1 X5 F1000\nELSE\nG1 X7 F1000\nEND\n")
    expect([5.0], [round(p["e"][0], 9) for p in rec.of("G")], "X of the parts")


@check("dialect", "program_end", D, "M functions", "M30 ends the program: nothing after it runs")
def _(host):
    rec = host.simulate("G1 X1 F1000\nM30\nG1 X2\n")
    expect([1.0], [round(p["e"][0], 9) for p in rec.of("G")], "X of the G parts")


@check("dialect", "waiting_m", D, "M functions",
       "an M function below 1000 reaches DriverMFunc with its number, between the moves around it")
def _(host):
    rec = host.simulate("G1 X1 F1000\nM51\nG1 X2\n")
    seq = [(k, v["func"]) for k, v in rec.events if k in ("G", "M")]
    expect([("G", 1), ("M", 51), ("G", 1)], seq, "order of G and M parts")


@check("dialect", "zero_offset", D, "G functions",
       "G54 sets a zero offset: positions are the programmed value plus the offset (m_zero)")
def _(host):
    rec = host.simulate("G54 X100 Y50\nG1 X1 Y2 F1000\n")
    near_point((101, 52), rec.of("G")[-1]["e"][:2], 1e-9, "machine position")


@check("dialect", "g92", D, "G functions", "G92 gives the current point new coordinates; nothing moves")
def _(host):
    rec = host.simulate("G1 X10 Y0 F1000\nG92 X0 Y0\nG1 X5\n")
    g = rec.of("G")
    expect(2, len(g), "G parts")
    near(15.0, g[-1]["e"][0], 1e-9, "machine X after G92 X0 and G1 X5")


@check("dialect", "print_output", D, "Program flow", "PRINT writes a text to the output log (tab 2)")
def _(host):
    rec = host.simulate('G1 X1 F1000\nPRINT "hello"\n')
    logs = [text for tab, text in rec.of("log") if tab == 2]
    if not any("hello" in t for t in logs):
        raise Differs("'hello' on tab 2", rec.of("log"), "AddOutputLog")


@check("dialect", "planes", D, "G functions", "G17 / G18 / G19 choose the arc plane (m_planeTool's low 16 bits)")
def _(host):
    rec = host.simulate("G18\nG1 X10 Z0 F1000\nG2 X0 Z0 I-5 K0\nG17\nG2 X10 Y0 I5 J0\n")
    arcs = [p for p in rec.of("G") if p["func"] == 2]
    expect([18, 17], [p["plane"] for p in arcs], "planes")


def _ends(rec, n=2):
    return [tuple(round(v, 6) for v in p["e"][:n]) for p in rec.of("G")]


@check("dialect", "continuous_m", D, "M functions",
       "a continuous M function (M1001 and above) written after a move is signalled at the start of that move")
def _(host):
    rec = host.simulate("G1 X14.2 Y45.89 F1000 M2003\nG1 X20\n")
    seq = [(k, v["func"], v["line"]) for k, v in rec.events if k in ("G", "M")]
    expect([("M", 2003, 1), ("G", 1, 1), ("G", 1, 2)], seq, "order of the parts")


@check("dialect", "expression_words", D, "Lines and words",
       "a word's value may be an expression: X P21+P22, Z (P1*2)")
def _(host):
    rec = host.simulate("P21 = 2\nP22 = 3\nP1 = 4\nG1 X P21+P22 Z (P1*2) F1000\n")
    near_point((5, 0, 8), rec.of("G")[0]["e"], 1e-9, "the end")


@check("dialect", "functions", D, "Parameters and expressions",
       "ATAN2(y, x) and HYPOT(a, b) among the functions, angles in degrees")
def _(host):
    rec = host.simulate("G1 X ATAN2(1, 1) Y HYPOT(3, 4) F1000\n")
    near_point((45, 5), rec.of("G")[0]["e"][:2], 1e-9, "the end")


@check("dialect", "g26_repeat", D, "G functions", "G26 L label H n calls the subroutine n times")
def _(host):
    rec = host.simulate("G1 X0 F1000\nG26 Lsub H3\nM30\nsub:\nG91 G1 X1\nG90\nM17\n")
    expect([(0, 0), (1, 0), (2, 0), (3, 0)], _ends(rec), "ends")


@check("dialect", "jumps", D, "Program flow", "GOTO label and G27 L label jump over the lines between")
def _(host):
    for jump in ("GOTO skip", "G27 Lskip"):
        rec = host.simulate(f"G1 X1 F1000\n{jump}\nG1 X2\nskip:\nG1 X3\n")
        expect([(1, 0), (3, 0)], _ends(rec), f"ends with {jump}")


@check("dialect", "while_loop", D, "Program flow", "WHILE cond … END repeats while the condition holds")
def _(host):
    rec = host.simulate("P1 = 0\nWHILE P1 < 3\nP1 = P1 + 1\nG1 X P1 F1000\nEND\n")
    expect([(1, 0), (2, 0), (3, 0)], _ends(rec), "ends")


@check("dialect", "if_break", D, "Program flow", "IF cond BREAK leaves the loop")
def _(host):
    rec = host.simulate("FOR P1 = 1 TO 5\nIF P1 > 2 BREAK\nG1 X P1 F1000\nEND\n")
    expect([(1, 0), (2, 0)], _ends(rec), "ends")


@check("dialect", "g29_label", D, "Program flow", "the first word of a G29 comment may be a label")
def _(host):
    rec = host.simulate("G1 X0 F1000\nCALL sub\nM30\nG29 sub a comment\nG1 X9\nRETURN\n")
    expect([(0, 0), (9, 0)], _ends(rec), "ends")


@check("dialect", "mirroring", D, "M functions", "M81 mirrors X, M80 switches mirroring off")
def _(host):
    rec = host.simulate("M81\nG1 X5 Y2 F1000\nM80\nG1 X6 Y2\n")
    expect([(-5, 2), (6, 2)], _ends(rec), "ends")


@check("dialect", "zero_offsets_g59_g53", D, "G functions",
       "G54 sets axes not written to 0, G59 keeps them; G53 switches the offset off")
def _(host):
    rec = host.simulate("G54 X10 Y10\nG59 X5\nG1 X1 Y1 F1000\nG54 X7\nG1 X1 Y1\nG53\nG1 X1 Y1\n")
    expect([(6, 11), (8, 1), (1, 1)], _ends(rec), "ends")


@check("dialect", "arc_negative_radius", D, "G functions",
       "G2 / G3 with R < 0: the longer arc (its centre mirrored about the chord)")
def _(host):
    rec = host.simulate("G1 X0 Y0 F1000\nG2 X8 Y0 R5\nG1 X0 Y0\nG2 X8 Y0 R-5\n")
    arcs = [p for p in rec.of("G") if p["func"] == 2]
    near_point((4, -3), arcs[0]["cc"][:2], 1e-6, "centre with R5")
    near_point((4, 3), arcs[1]["cc"][:2], 1e-6, "centre with R-5")


@check("dialect", "absolute_centre_q70", D, "G functions", "G2 / G3 with Q70: I J K are the centre in absolute coordinates")
def _(host):
    rec = host.simulate("G1 X2 Y0 F1000\nG2 X8 Y0 I5 J0 Q70\n")
    near_point((5, 0), rec.of("G")[1]["cc"][:2], 1e-6, "centre")


@check("dialect", "g91_moves", D, "G functions", "G90 / G91 with axis words also move, as G1")
def _(host):
    rec = host.simulate("G1 X0 Y0 F1000\nG91 X2 Y1\nG90 X5\n")
    expect([1, 1, 1], [p["func"] for p in rec.of("G")], "G numbers")
    expect([(0, 0), (2, 1), (5, 1)], _ends(rec), "ends")


@check("dialect", "rotation_g168", D, "G functions", "G168 X Y Z R rotates the program about a point; G169 ends it")
def _(host):
    rec = host.simulate("G1 X0 Y0 F1000\nG168 X0 Y0 Z0 R90\nG1 X10 Y0\nG169\nG1 X10 Y0\n")
    g = rec.of("G")
    near_point((0, 10), g[1]["ce"][:2], 1e-6, "the rotated line's end")
    near_point((10, 0), g[2]["ce"][:2], 1e-6, "the end after G169")
