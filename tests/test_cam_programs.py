"""Real CAM programs (issue 15): the dwell length, error texts that name the word and its
column, warnings where a program looks written for ISO G-code, the opt-in ISO
compatibility mode (GCODE_PARAMETERS.rezerva1 bit 0), and the generated corpus
(tests/cam_corpus.py). Core 0."""
import ctypes
import math

import pytest

import cam_corpus
from compiler_host import SEED_PROGRAM, Host, close, ok
from sf_tch import abi

ISO = 1                                 # GCODE_REZERVA1_ISO_COMPAT


@pytest.fixture(scope="module")
def host(tmp_path_factory):
    h = Host(0, tmp_path_factory.mktemp("core0cam"))
    yield h
    h.close()


def compile_logged(host, code, iso=0, **kw):
    """Compiles with the output log collected: (result, [(tab, text)])."""
    log = []

    def on_log(user, tab, text, info):
        log.append((tab & 0xFF, (text or b"").decode()))
        return 0

    cb = abi.AddOutputLog(on_log)
    lib = host.lib
    assert lib.ToolChainCore_SetCallBack(host.core, abi.CB_ADD_OUTPUT_LOG, 0, ctypes.cast(cb, ctypes.c_void_p)) == 0
    try:
        r = host.compile(code, run=False, rezerva1=iso, start=[0] * 10, **kw)
    finally:
        lib.ToolChainCore_SetCallBack(host.core, abi.CB_ADD_OUTPUT_LOG, 0, None)
    if r.error is None:
        host.run(r)
    return r, log


def warnings_of(log):
    return [text for tab, text in log if tab == 0 and text.startswith("Warning: G-code")]


# ----------------------------------------------------------------- the dwell length

def test_dwell_part_has_length_zero(host):
    r = ok(host, "G1 X10 Y0 F1000\nG4 W500\nG1 X20\nM2\n", start=[0] * 10)
    assert [p.func for p in r.g] == [1, 4, 1]
    assert [p.pars["N"] for p in r.g] == [10.0, 0.0, 10.0]
    # what `sf-tch demo` adds up: the cut length of the G parts is the 20 mm moved
    assert sum(p.pars["N"] for p in r.g if p.func != 0) == 20.0
    assert r.g[1].pars["W"] == 500.0


# ----------------------------------------------------------------- error texts

@pytest.mark.parametrize("code, number, line, parts", [
    # a P word that is no assignment: the whole word, its column, what G4 takes
    ("P12 = 3\nG4 P12\n", 110, 2, ["Word 'P12' at column 4", "P00..P99", "G4 takes W (milliseconds), H, X or T"]),
    ("M52 P1 (enable)\n", 110, 1, ["Word 'P1' at column 5", "M functions take no P word"]),
    # the CR of a CRLF file is no part of the word
    ("G1 X1\r\nG4 P0.1\r\n", 110, 2, ["Word 'P0.1' at column 4"]),
    ("G64 P0.1\r\n", 408, 1, ["G64 at column 1 is not TG G-code", "GCODE_PARAMETERS"]),
    ("O100 sub\nG1 X1\nO100 endsub\n", 111, 1, ["'sub' at column 6 is not TG G-code", "labels (name:) with CALL"]),
    ("o<drill> call [1]\n", 111, 1, ["'o<drill>' at column 1"]),
    # the unknown G82 is reported, not its P word
    ("G0 X0 Y0\nG82 X1 Y2 Z-3 R1 P0.25\n", 408, 2, ["G82 at column 1 is not TG G-code", "drilling"]),
    ("G1 X5\n  G0 G20 X1\n", 408, 2, ["G20 at column 6", "millimetres"]),
    ("G90 G94 G17 G28\n", 408, 1, ["G28 at column 13"]),
    ("G17 G92.1\n", 408, 1, ["G92.1 at column 5"]),
    ("#1 = 5\n", 111, 1, ["'#1' at column 1", "P00..P99"]),
    ("G1 X[1 + 2]\n", 111, 1, ["'[1' at column 5", "( ) brackets"]),
    ("G1 X P100 + 1\n", 201, 1, ["Parameter P100 at column 6"]),
    ("P123 = 4\n", 201, 1, ["Parameter P123 at column 1"]),
    ("IF 1 > 0 MAYBE\r\n", 308, 1, ["Bad condition 'MAYBE' at column 10"]),
    ("FOR P1 = 1 UNTIL 3\r\nEND\n", 308, 1, ["Bad condition 'UNTIL 3' at column 12"]),
    ("GOTO @\r\n", 300, 1, ["Undefined label '@'"]),
    ("G1 X1 QQ5\r\n", 100, 1, ["Unknown word 'QQ5' at column 7"]),
    ("G1 X1 Y1.2.3\n", 101, 1, ["'1.2.3' at column 8"]),
    ("G1 X1 Y\r\n", 102, 1, ["Address Y at column 7 without a value"]),
    ("G1 X1\nG7 X2\n", 404, 2, ["Unknown G function G7 at column 1"]),
    ("G1 X1 M2.5\n", 405, 1, ["Bad M function M2.5 at column 7"]),
    ("G900\n", 102, 1, ["Address S at column 1"]),
    ("G1 X1 P = 4\n", 110, 1, ["Word 'P' at column 7", "Pnn = value"]),
    ("IF 1 > 0 THEN (note\r\nEND\n", 104, 1, ["Comment '(' at column 15"]),
    ("G1 X1 (a) (b\r\n", 104, 1, ["Comment '(' at column 11"]),
    ("G1 X ABS(2\r\n", 103, 1, ["'(' at column 9"]),
    ("G1 X SQRTT(4)\n", 203, 1, ["'SQRTT' at column 6"]),
    ("G1 X 2 +* 3\r\n", 202, 1, ["'* 3' at column 9"]),
    ("FOR P1 = 1 TO 2\nG1 X1\nEND junk\r\n", 100, 3, ["'junk' at column 5"]),
])
def test_error_names_the_word_and_its_column(host, code, number, line, parts):
    r = host.compile(code, run=False, start=[0] * 10)
    assert r.error is not None
    got_number, got_line, _, text, args = r.error
    assert (got_number, got_line) == (number, line), r.error
    for part in parts:
        assert part in text, (part, text)
    assert "?" not in text.replace("program number?", "")      # no unprintable byte shown
    if number != 300:                   # a missing label is named; it has no column
        assert "column" in text


@pytest.mark.parametrize("code, number, parts", [
    # what LinuxCNC refuses, refused in ISO mode too; what the mode does not read, named
    ("G1 X1\n", 410, ["G1 at column 1 with feed 0"]),
    ("G0 X0\nG80\nX1\n", 411, ["Axis word 'X1' at column 1 without a motion mode"]),
    ("X1 Y2\n", 411, ["'X1' at column 1"]),
    ("G1 F100 X#<nothing>\n", 208, ["Named parameter '#<nothing>' at column 10 is not defined"]),
    ("G1 F#<_hal[plasmac.cut-feed-rate]> X1\n", 209,
     ["'#<_hal[plasmac.cut-feed-rate]>' at column 5 cannot be read", "HAL"]),
    ("#6000 = 1\n", 210, ["Parameter #6000 at column 1 does not exist"]),
    ("#<_x> = 1\n", 211, ["'#<_x>' at column 1 is read-only"]),
    ("O100 sub\nG0 X1\n", 310, ["O-word 'o100' at column 1: sub without endsub"]),
    ("G0 X0\n  o<drill> call [1]\n", 311, ["Subroutine 'o<drill>' at column 3 is not defined: no 'sub' line"]),
    ("o1 endwhile\n", 310, ["'o1' at column 1: endwhile without its while"]),
    ("G0 X0\nG7\n", 112, ["'G7' at column 1 is not supported", "lathe diameter"]),
    ("G0 X1\nM98 P100 L2\n", 112, ["'M98' at column 1 is not supported", "Fanuc-style subprograms"]),
    ("G0 Z5 F10\nG87 X1 Z-1 R2\n", 112, ["'G87' at column 1", "undefined"]),
    ("G0 Z5 F10\nG1 G82 X1 Z-1 R2\n", 412, ["G82 at column 4: P (the dwell in seconds) is missing"]),
    ("G0 Z5 F10\nG83 X1 Z-1 R2 Q-1\n", 412, ["G83 at column 1: Q (the peck depth) must be above 0"]),
    ("G0 Z0 F10\nG81 X1 Z1 R-1\n", 412, ["R level is below the hole bottom"]),
    ("G10 L1 P1 R2\n", 112, ["'L1' at column 5", "tool tables"]),
    ("G1 X1 P5 F10\n", 110, ["'P5' at column 7"]),
])
def test_iso_mode_errors_name_the_construct_and_column(host, code, number, parts):
    r = host.compile(code, run=False, rezerva1=ISO, start=[0] * 10)
    assert r.error is not None and r.error[0] == number, (code, r.error)
    for part in parts:
        assert part in r.error[3], (part, r.error)
    assert "column" in r.error[3] and "\n" not in r.error[3]


def test_iso_mode_home_return_refuses_cutter_compensation(host):
    p = host.params(rezerva1=ISO)
    p.correction[0].size = 1.0          # (a radius of 0 compensates nothing: G41 is then a no-op)
    r = host.compile("G0 Z0\nG41\nG28 Z1\n", params=p, run=False, start=[0] * 10)
    assert r.error is not None and r.error[:2] == (412, 3) and "G28 at column 1: cutter compensation is on" in r.error[3]
    p.correction[0].size = 0.0
    assert host.compile("G0 Z0\nG41\nG28 Z1\n", params=p, run=False, start=[0] * 10).error is None


# ----------------------------------------------------------------- warnings (TG meaning kept)

def test_g43_with_h_warns_and_keeps_radius_compensation(host):
    r, log = compile_logged(host, "G0 X0 Y0\nG43 H1 Z5\nG1 X10 F500\nG40\nG1 X20\n")
    assert r.error is None
    w = warnings_of(log)
    assert len(w) == 1 and w[0].startswith("Warning: G-code, line 2: G43 with H at column 1"), w
    assert [p.comp for p in r.g] == [40, 41, 41, 40], "TG's G43: compensation left, correction[2]"


def test_o_word_at_the_start_warns_and_moves_the_o_axis(host):
    r, log = compile_logged(host, "O1000\nG1 X1 F500\n")
    w = warnings_of(log)
    # (and the O axis moves before any F: at motion[1].feed, warning 614)
    assert len(w) == 2 and "line 1: O1000 at column 1 at the start of the program" in w[0], w
    assert "line 1: G1 at column 1 at feed 0" in w[1], w
    assert r.g[0].e[9] == 1000.0 and r.g[1].e[9] == 1000.0
    # later in the program an O word is an axis move like any other: no warning
    r, log = compile_logged(host, "G1 X1 F500\nO5\n")
    assert warnings_of(log) == [] and r.g[1].e[9] == 5.0


def test_zero_offset_on_a_motion_line_warns_and_does_not_move(host):
    r, log = compile_logged(host, "G0 G90 G54 X10 Y10\nG0 X1 Y1\n")
    w = warnings_of(log)
    assert len(w) == 1 and "G54 at column 8 with axis words sets the zero offset" in w[0], w
    assert len(r.g) == 1 and close(r.g[0].e[:2], (11, 11)), "TG: offset (10, 10), then X1 Y1 in it"


def test_g18_arc_after_an_iso_header_warns_once_and_keeps_xz(host):
    code = "G21\nG90\nG0 X10 Z0\nG18 G3 X0 Z10 I-10 K0 F500\nG3 X-10 Z0 I0 K-10\n"
    r, log = compile_logged(host, code)
    w = warnings_of(log)
    assert len(w) == 1 and "line 4: G18 arc at column 15" in w[0], w
    assert [p.plane for p in r.g] == [17, 18, 18]
    # without an ISO header, G18 arcs are TG's own: no warning
    r, log = compile_logged(host, "G0 X10 Z0\nG18 G3 X0 Z10 I-10 K0 F500\n")
    assert warnings_of(log) == []


SEED_WITH_FEED = SEED_PROGRAM.replace("G02 X0 Y-2.5202", "G02 F1000 X0 Y-2.5202")


def test_tg_programs_give_no_warnings(host):
    r, log = compile_logged(host, SEED_WITH_FEED.replace("G42\n", "G41\n"), absMode=0)
    assert r.error is None and warnings_of(log) == []
    # the vendor's sample itself gives no F: its arcs run at motion[1].feed, once said
    r, log = compile_logged(host, SEED_PROGRAM, absMode=0)
    w = warnings_of(log)
    assert len(w) == 1 and w[0].startswith("Warning: G-code, line 4: G2 at column 1 at feed 0"), w


def test_warnings_are_capped(host):
    r, log = compile_logged(host, "G0 X0 Y0\n" + "G43 H1 X1\nG40 X0\n" * 60)
    w = warnings_of(log)
    assert len(w) == 51 and w[-1] == "Warning: G-code: further warnings suppressed"


def test_compile_warnings_reach_math_warning(host):
    seen = []

    def on_warning(user, info):
        i = info.contents
        seen.append((i.stringId, i.actLine, (i.m_fullError or b"").decode()))
        return 0

    cb = abi.MathWarning(on_warning)
    assert host.lib.ToolChainCore_SetCallBack(host.core, abi.CB_MATH_WARNING, 0, ctypes.cast(cb, ctypes.c_void_p)) == 0
    try:
        ok(host, "G1 X1 F500\nG43 H1 X2\nG40 X3\n", start=[0] * 10, run=False)
    finally:
        host.lib.ToolChainCore_SetCallBack(host.core, abi.CB_MATH_WARNING, 0, None)
    assert seen and seen[0][:2] == (610, 2), seen


# ----------------------------------------------------------------- ISO compatibility mode

def geometry(r):
    return [(p.kind, p.func, p.plane, tuple(round(v, 9) for v in p.e[:3]), tuple(round(v, 9) for v in p.cc[:3]),
             p.comp) for p in r.parts]


def test_iso_mode_is_off_by_default(host):
    assert host.defaults.rezerva1 == 0
    assert host.compile("G4 P1\n", run=False).error[0] == 110


def test_iso_mode_changes_nothing_in_a_tg_program(host):
    # (without its G42: a radius of 0 compensates nothing in the ISO mode, see docs/compiler.md)
    tg = SEED_WITH_FEED.replace("G42\n", "G40\n")
    a = ok(host, tg, start=[0] * 10, absMode=0)
    b = ok(host, tg, start=[0] * 10, absMode=0, rezerva1=ISO)
    assert geometry(a) == geometry(b) and len(a.parts) == 13


def test_iso_dwell_p_is_seconds(host):
    # the oracle: the same dwell written in TG's seconds address H
    times = []
    # (the last: the same exact stop at X10 without the wait, for the feed planner)
    for code, iso in (("G1 X10 F600\nG4 P2.5\nG1 X20\n", ISO), ("G1 X10 F600\nG4 H2.5\nG1 X20\n", 0),
                      ("G1 X10 F600\nG4 H0\nG1 X20\n", 0)):
        ok(host, code, start=[0] * 10, rezerva1=iso, calcTime=1)
        file_idx = host.lib.ToolChainCore_FileToIdx(host.core, b"prog.nc")
        times.append(host.lib.ToolChainCore_GetGCodeRunTime(host.core, file_idx))
    assert times[0] == times[1]
    assert math.isclose(times[0] - times[2], 2.5, abs_tol=1e-6)
    # the driver gets the dwell as TG writes it: H seconds
    r = ok(host, "G4 P2.5\n", start=[0] * 10, rezerva1=ISO)
    assert r.g[0].func == 4 and r.g[0].pars["H"] == 2.5 and "P" not in r.g[0].pars


def test_iso_inches_equal_the_program_in_millimetres(host):
    inch = ("G20 G90 G17\nG0 X1 Y0.5\nG1 X2 F10\nG3 X3 Y1.5 I0 J1\nG2 X2.5 Y2 R0.5\nG91 G1 X-1 Y-0.25\n"
            "G21 G90 G1 X5 Y5\n")
    mm = ("G90 G17\nG0 X25.4 Y12.7\nG1 X50.8 F254\nG3 X76.2 Y38.1 I0 J25.4\nG2 X63.5 Y50.8 R12.7\n"
          "G91 G1 X-25.4 Y-6.35\nG90 G1 X5 Y5\n")
    a = ok(host, inch, start=[0] * 10, rezerva1=ISO)
    b = ok(host, mm, start=[0] * 10)
    assert len(a.g) == len(b.g) == 6
    for p, q in zip(a.g, b.g):
        assert p.func == q.func and close(p.e[:3], q.e[:3], 1e-12) and close(p.cc, q.cc, 1e-12)
        assert math.isclose(p.feed, q.feed, rel_tol=1e-6)


def test_iso_g18_is_tg_g_minus_18(host):
    iso = "G0 X10 Z0\nG18 G2 X0 Z10 I-10 K0 F500\nG3 X-10 Z0 I0 K-10\n"
    a = ok(host, iso, start=[0] * 10, rezerva1=ISO)
    b = ok(host, iso.replace("G18", "G-18"), start=[0] * 10)
    assert geometry(a) == geometry(b) and [p.plane for p in a.g] == [17, -18, -18]
    # and differs from TG's own G18 (the arcs turn the other way: other centres)
    c = ok(host, iso, start=[0] * 10)
    assert geometry(a) != geometry(c)


def test_iso_ignored_functions_warn(host):
    code = ("G17 G40 G49 G80 G90\nG64 P0.05 Q0.01\nG61\nG0 X0 Y0\nG43 H1 Z5\nM52 P1 (enable)\n"
            "G1 X10 F500\nG80\n")
    r, log = compile_logged(host, code, iso=ISO)
    assert r.error is None
    w = warnings_of(log)
    # (G80 is no longer among them: it ends a canned cycle; nor G43 H / G49: tool lengths
    # from the core's tool table, all zero here)
    expected = [(2, "'G64' at column 1"), (3, "'G61' at column 1"), (6, "'P1' at column 5")]
    assert len(w) == len(expected), w
    for text, (line, part) in zip(w, expected):
        assert text.startswith(f"Warning: G-code, line {line}: {part} ignored (ISO compatibility mode)"), text
    assert [p.comp for p in r.g] == [40, 40, 40], "G43 H is a tool length, not radius compensation"
    assert r.g[1].e[2] == 5.0               # entry 1's lengths are 0
    assert [p.func for p in r.m] == [52]


def test_iso_program_number_and_percent_lines_are_ignored(host):
    r, log = compile_logged(host, "%\nO1001 (PART)\nG0 X1 Y2\nM30\n%\n", iso=ISO)
    assert r.error is None and warnings_of(log) == []
    assert len(r.g) == 1 and r.g[0].e[9] == 0.0 and close(r.g[0].e[:2], (1, 2))


def test_iso_work_offsets_keep_the_move(host):
    r = ok(host, "G0 G90 G54 X10 Y10\nG53 G0 Z0\n", start=[0] * 10, rezerva1=ISO)
    assert [p.e[:3] for p in r.g] == [(10.0, 10.0, 0.0), (10.0, 10.0, 0.0)]
    assert r.g[0].zero[:3] == (0.0, 0.0, 0.0)


def test_iso_g92_1_clears_the_shift(host):
    r = ok(host, "G0 X5\nG92 X0\nG0 X1\nG92.1\nG0 X1\n", start=[0] * 10, rezerva1=ISO)
    assert [p.e[0] for p in r.g] == [5.0, 6.0, 1.0]


# ----------------------------------------------------------------- the corpus

def test_corpus_counts(fresh_core):
    """The figures of docs/compiler.md ("ISO compatibility mode"): how many of the generated
    CAM-style programs compile with and without the mode, and why the others do not."""
    from sf_tch.core import Core
    with Core(0) as core:
        tg, tg_errors = cam_corpus.count(core, iso=False)
        iso, iso_errors = cam_corpus.count(core, iso=True)
    assert sum(v[0] for v in tg.values()) == 12
    assert sum(v[0] for v in iso.values()) == 48 and iso_errors == []
    assert sum(v[1] for v in tg.values()) == 48
    # every TG-dialect failure names its construct and column
    assert all("column" in e.text for _, e in tg_errors)


@pytest.mark.parametrize("iso", [0, ISO])
def test_corpus_geometry(host, iso):
    """Every program of the corpus that compiles cuts its contours' corner arcs at their
    true length (closed form: a quarter circle per corner, from the generator's radii in
    mm): inches converted, I J relative, no arc turned into a loop, lead-in arcs of
    Fusion in their own plane."""
    compiled = 0
    for style, name, text, radii in cam_corpus.corpus():
        r = host.compile(text, name=name, start=[0] * 10, rezerva1=iso)
        if r.error is not None:
            continue
        compiled += 1
        arcs = [p for p in r.g if p.func in (2, 3) and p.plane == 17]
        assert len(arcs) == 4 * len(radii), name
        # coordinates are written with 3 or 4 decimals: 0.005 mm per arc
        assert math.isclose(sum(p.pars["N"] for p in arcs), sum(2 * math.pi * rad for rad in radii),
                            abs_tol=0.005 * len(arcs)), name
        if iso:
            assert all(p.comp == 40 for p in r.g), name      # G43 H is no radius compensation
    assert compiled == (48 if iso else 12)


MUTATION_SCRIPT = """
import ctypes, json, sys, time
from sf_tch import abi, library
lib = library.load(LIB_PATH)
programs = json.load(open(PROGRAMS_PATH))
p = abi.GCODE_PARAMETERS()
assert lib.ToolChainCore_GetGCodeParameters(0, ctypes.byref(p)) == 0
for iso, text in programs:
    p.rezerva1 = iso
    assert lib.ToolChainCore_SetGCodeParameters(0, ctypes.byref(p)) == 0
    assert lib.ToolChainCore_CompileFromMemory(0, b"mutated.nc", text.encode("latin-1")) == 0
    deadline = time.monotonic() + 60
    while lib.ToolChainCore_StatusCNC(0) == 1:
        assert time.monotonic() < deadline, "compilation hangs"
        time.sleep(0.001)
    info = abi.CALLBACK_INFO()
    failed = lib.ToolChainCore_GetLastError(0, ctypes.byref(info))
    print(json.dumps([lib.ToolChainCore_StatusCNC(0), failed, info.stringId if failed else 0,
                      info.actLine if failed else 0, (info.m_fullError or b"").decode("latin-1") if failed else ""]))
"""

WORD_ERRORS = {100, 101, 102, 103, 104, 108, 110, 111, 201, 202, 203, 404, 405, 408}


@pytest.mark.slow
def test_random_mutations_of_corpus_programs(run_python, tmp_path):
    """Corpus programs with bytes dropped, inserted or replaced (other dialects' characters
    among them), in both modes, in a fresh interpreter: no crash or hang, every error
    on a line of the program, word errors with a column."""
    import json
    import os
    import random
    scale = int(os.environ.get("SF_TCH_SLOW_SCALE", "1"))
    rng = random.Random(15)
    alphabet = "GXYZIJKFPMOHN0123456789.-+*/()[]#<>=:;% \r\n"
    texts = [text for _, _, text, _ in cam_corpus.corpus()]
    programs = []
    for k in range(60 * scale):
        code = list(rng.choice(texts))
        for _ in range(rng.randrange(1, 10)):
            i = rng.randrange(len(code))
            choice = rng.randrange(3)
            if choice == 0:
                del code[i]
            elif choice == 1:
                code.insert(i, rng.choice(alphabet))
            else:
                code[i] = rng.choice(alphabet)
        programs.append((k % 2, "".join(code)))
    path = tmp_path / "programs.json"
    path.write_text(json.dumps(programs))
    out = run_python(f"PROGRAMS_PATH = {str(path)!r}\n" + MUTATION_SCRIPT, timeout=600).stdout
    results = [json.loads(line) for line in out.splitlines()]
    assert len(results) == len(programs)
    for (iso, text), (status, failed, number, line, message) in zip(programs, results):
        assert status == -1
        if failed:
            assert 1 <= line <= text.count("\n") + 1, (number, line, message)
            if number in WORD_ERRORS:
                assert "column" in message, message
