"""The tool correction table (docs/tool-table.md): the vendor's example TAB0.KOR read
exactly, every malformed field refused with its line and the table kept, any bytes read
safely, numbers independent of the locale, G92 D's write (the example of entry 12),
the INI key; in programs: D (radii against shapely's offsets), & (exact lengths), G92 D
(the example of entry 12 again), bad entries, a table change between compile and run,
the ISO mode's G41 D / G43 H / G49."""
import ctypes
import random
from ctypes import byref

import pytest

from sf_tch import abi

ERR_NOT_FINITE, ERR_OUT_OF_RANGE, ERR_INI_VALUE = 14, 15, 16
ERR_NO_KEYWORD, ERR_LINE, ERR_ENTRY = 720, 721, 722

# The example of the tool compensation manual (section 7.1), typed as printed: the
# trailing blanks, the blank line and the second $KOR block included.
VENDOR_EXAMPLE = (
    "Korekce frezky - komentar pred klicovym slovem\n"
    "$KOR      \n"
    "01: R=10.0 X=20.0 Y=30.0 Z=40.0  \n"
    "02: R=0.8 X=0.0 2=0.0   \n"
    "03: R=0.8 X=0.0 Y=120.0 Z=0.0 4=0.0 \n"
    "25:  X=85.0 Y=45.5 Z=0.0  \n"
    "95: R=0.0 1=12.55 2=0.0 3=0.0 4=0.0 \n"
    " \n"
    "$KOR      \n"
    "01: R=0.0 X=0.0 Y=0.0 Z=0.0 4=0.0 \n"
)


def table(lib, core=0):
    """The core's table: {entry: (radius, l1, l2, l3, l4)} for entries 1..99."""
    out = {}
    values = (ctypes.c_double * abi.TC_TOOL_VALUES)()
    for entry in range(1, abi.TC_TOOL_ENTRIES + 1):
        assert lib.ToolChainCore_GetToolCorrection(core, entry, values) == 0
        out[entry] = tuple(values)
    return out


def nonzero(t):
    return {entry: values for entry, values in t.items() if any(values)}


def load(lib, path, core=0):
    return lib.ToolChainCore_LoadToolTable(core, str(path).encode())


def call_error(lib, core=0):
    info = abi.CALLBACK_INFO()
    assert lib.ToolChainCore_GetLastCallError(core, byref(info)) == 1
    return info.stringId, info.actLine, info.m_fullError.decode()


def write(tmp_path, content, name="TAB0.KOR"):
    path = tmp_path / name
    path.write_bytes(content if isinstance(content, bytes) else content.encode())
    return path


# ------------------------------------------------------------------ the vendor's example

def test_the_vendor_example_is_read_exactly(fresh_core, tmp_path):
    """Entry 1 as milling machines write it (then given again, all zero, by the second
    $KOR block, which replaces it), 2 as lathes (axis 2 by its number), 3 with the
    fourth axis, 25 without a radius, 95 with axis numbers; every other entry 0."""
    assert load(fresh_core, write(tmp_path, VENDOR_EXAMPLE)) == 0
    assert nonzero(table(fresh_core)) == {
        2: (0.8, 0.0, 0.0, 0.0, 0.0),
        3: (0.8, 0.0, 120.0, 0.0, 0.0),
        25: (0.0, 85.0, 45.5, 0.0, 0.0),
        95: (0.0, 12.55, 0.0, 0.0, 0.0),
    }


def test_the_first_block_alone_gives_entry_1(fresh_core, tmp_path):
    first_block = VENDOR_EXAMPLE.split(" \n$KOR")[0]
    assert load(fresh_core, write(tmp_path, first_block)) == 0
    t = table(fresh_core)
    assert t[1] == (10.0, 20.0, 30.0, 40.0, 0.0)
    assert t[2] == (0.8, 0.0, 0.0, 0.0, 0.0)
    assert t[95] == (0.0, 12.55, 0.0, 0.0, 0.0)
    assert len(nonzero(t)) == 5


def test_a_load_replaces_the_whole_table(fresh_core, tmp_path):
    assert load(fresh_core, write(tmp_path, "$KOR\n07: R=1 X=2\n")) == 0
    assert load(fresh_core, write(tmp_path, "$KOR\n08: R=3\n", "other.kor")) == 0
    assert nonzero(table(fresh_core)) == {8: (3.0, 0, 0, 0, 0)}


@pytest.mark.parametrize("text, entries", [
    (b"\xef\xbb\xbf$KOR\r\n01: R=1.5\r\n02:\tX=2\r\n", {1: (1.5, 0, 0, 0, 0), 2: (0, 2.0, 0, 0, 0)}),
    (b"$kor\n  07: r=+1.5e-3 x=-.5 y=5. z=1E2 4=-0\n", {7: (1.5e-3, -0.5, 5.0, 100.0, 0)}),
    (b"comment \x00\xff with $KOR in it and\n$KOR inside a line\n$KOR\n09:R=9", {9: (9.0, 0, 0, 0, 0)}),
    (b"$KOR\n\n   \n10:\n11: 1=1 2=2 3=3 4=4\n", {11: (0, 1.0, 2.0, 3.0, 4.0)}),
    (b"; comment\n" * 20000 + b"$KOR\n99: R=-2.5\n", {99: (-2.5, 0, 0, 0, 0)}),
    (b"x" * 3_000_000 + b"\n$KOR\n12: Z=1000000 Y=-1000000\n", {12: (0, 0, -1e6, 1e6, 0)}),
    # the manual: axes are named X, Y, Z and U when they are the first to fourth axis
    (b"$KOR\n03: R=0.8 X=1 Y=120.0 Z=2 U=4.5\n04: u=-1\n", {3: (0.8, 1.0, 120.0, 2.0, 4.5), 4: (0, 0, 0, 0, -1.0)}),
], ids=["crlf-bom-tab", "case-signs-exponents", "nul-in-comment", "blank-and-empty", "long-comment", "long-line",
        "fourth-axis-U"])
def test_files_the_reader_takes(fresh_core, tmp_path, text, entries):
    assert load(fresh_core, write(tmp_path, text)) == 0
    assert nonzero(table(fresh_core)) == entries


# ------------------------------------------------------------------ bad files

BAD = [
    ("no-keyword", "01: R=1\n", ERR_NO_KEYWORD, 0, "has no line $KOR"),
    ("keyword-with-more", "$KOR 1\n01: R=1\n", ERR_NO_KEYWORD, 0, "$KOR"),
    ("one-digit", "$KOR\n1: R=1\n", ERR_LINE, 2, "'1: R=1' is no entry"),
    ("three-digits", "$KOR\n001: R=1\n", ERR_LINE, 2, "'001: R=1' is no entry"),
    ("no-colon", "$KOR\n01 R=1\n", ERR_LINE, 2, "is no entry"),
    ("not-an-entry", "$KOR\n01: R=1\nhello\n", ERR_LINE, 3, "'hello' is no entry"),
    ("entry-00", "$KOR\n00: R=1\n", ERR_LINE, 2, "entry 00 does not exist"),
    ("entry-twice", "$KOR\n05: R=1\n\n05: R=2\n", ERR_LINE, 4, "entry 05 is given twice in this $KOR block (first on line 2)"),
    ("axis-name-C", "$KOR\n01: C=5\n", ERR_LINE, 2, "'C=5' is no value of an entry"),
    ("axis-name-A", "$KOR\n01: A=5\n", ERR_LINE, 2, "'A=5' is no value of an entry"),
    ("axis-5", "$KOR\n01: 5=5\n", ERR_LINE, 2, "'5=5' is no value"),
    ("blank-before-equals", "$KOR\n01: R =1\n", ERR_LINE, 2, "'R' is no value"),
    ("radius-twice", "$KOR\n01: R=1 R=2\n", ERR_LINE, 2, "entry 01: its radius is given twice"),
    ("axis-twice", "$KOR\n01: Y=1 2=2\n", ERR_LINE, 2, "its length of axis 2 is given twice"),
    ("empty-value", "$KOR\n01: R=\n", ERR_LINE, 2, "'R=': the radius is not a number"),
    ("letters", "$KOR\n01: X=abc\n", ERR_LINE, 2, "'X=abc': the length of axis 1 is not a number"),
    ("decimal-comma", "$KOR\n01: Z=1,5\n", ERR_LINE, 2, "'Z=1,5': the length of axis 3 is not a number"),
    ("two-points", "$KOR\n01: 4=1.2.3\n", ERR_LINE, 2, "'4=1.2.3': the length of axis 4 is not a number"),
    ("nan", "$KOR\n01: R=nan\n", ERR_LINE, 2, "not a number"),
    ("inf", "$KOR\n01: R=inf\n", ERR_LINE, 2, "not a number"),
    ("hexadecimal", "$KOR\n01: R=0x10\n", ERR_LINE, 2, "not a number"),
    ("overflow", "$KOR\n01: R=1e999\n", ERR_LINE, 2, "not a number"),
    ("too-large", "$KOR\n01: R=1000000.5\n", ERR_LINE, 2, "'R=1000000.5': the radius is outside <-1e6, 1e6> mm"),
    ("long-number", "$KOR\n01: R=" + "1" * 100 + "\n", ERR_LINE, 2, "the radius is not a number"),
    ("nul-byte", b"$KOR\n01: R=1\x00 X=2\n", ERR_LINE, 2, "byte 0x00 at column 8 is no text"),
    ("control-byte", b"$KOR\n01: R=1\n02: X=\x1b2\n", ERR_LINE, 3, "byte 0x1b at column 7 is no text"),
    ("bare-cr-lines", b"$KOR\r01: R=1\r02: R=2\r", ERR_NO_KEYWORD, 0, "$KOR"),
    ("empty-file", b"", ERR_NO_KEYWORD, 0, "$KOR"),
]


@pytest.mark.parametrize("content, number, line, reason", [b[1:] for b in BAD], ids=[b[0] for b in BAD])
def test_a_bad_file_is_refused_with_its_line_and_the_table_stays(fresh_core, tmp_path, content, number, line, reason):
    good = write(tmp_path, "$KOR\n42: R=4.2 X=1\n", "good.kor")
    assert load(fresh_core, good) == 0
    before = table(fresh_core)
    bad = write(tmp_path, content, "bad.kor")
    assert load(fresh_core, bad) == abi.TOOL_CHAIN_ERROR
    got_number, got_line, text = call_error(fresh_core)
    assert (got_number, got_line) == (number, line), text
    assert str(bad) in text and reason in text, text
    assert table(fresh_core) == before


def test_a_file_that_cannot_be_read(fresh_core, tmp_path):
    assert fresh_core.ToolChainCore_LoadToolTable(0, None) == -1
    assert call_error(fresh_core)[0] == 1
    assert fresh_core.ToolChainCore_LoadToolTable(0, b"") == -1
    assert load(fresh_core, tmp_path / "missing.kor") == -1
    assert call_error(fresh_core)[0] == 1 and "missing.kor" in call_error(fresh_core)[2]
    assert load(fresh_core, tmp_path) == -1
    assert call_error(fresh_core)[0] == 13
    assert fresh_core.ToolChainCore_LoadToolTable(3, b"x") == abi.TOOL_CHAIN_BAD_INTR_INDEX


def test_random_bytes_never_crash_and_a_refusal_keeps_the_table(fresh_core, tmp_path):
    """Mutations of the vendor's example (bytes replaced, inserted, lines cut): each is
    read, or refused with 720/721 and the table as it was."""
    rng = random.Random(26)
    base = VENDOR_EXAMPLE.encode()
    assert load(fresh_core, write(tmp_path, base)) == 0
    kept = table(fresh_core)
    accepted = 0
    for case in range(300):
        data = bytearray(base)
        for _ in range(rng.randint(1, 6)):
            at = rng.randrange(len(data) + 1)
            what = rng.random()
            if what < 0.4 and at < len(data):
                data[at] = rng.randrange(256)
            elif what < 0.8:
                data[at:at] = bytes(rng.randrange(256) for _ in range(rng.randint(1, 4)))
            else:
                del data[at:at + rng.randint(1, 20)]
        path = write(tmp_path, bytes(data), f"m{case}.kor")
        rc = load(fresh_core, path)
        if rc == 0:
            accepted += 1
            kept = table(fresh_core)
        else:
            assert rc == -1 and call_error(fresh_core)[0] in (ERR_NO_KEYWORD, ERR_LINE)
            assert table(fresh_core) == kept
    assert 0 < accepted < 300


def test_numbers_do_not_follow_a_decimal_comma_locale(run_python, tmp_path, comma_locale):
    name, env = comma_locale
    path = write(tmp_path, "$KOR\n07: R=0.5 X=1.25e-1\n08: R=0,5\n")
    out = run_python(f"""
        import ctypes, locale
        locale.setlocale(locale.LC_ALL, {name!r})
        assert locale.localeconv()['decimal_point'] == ','
        from sf_tch import abi, library
        lib = library.load(LIB_PATH)
        print(lib.ToolChainCore_LoadToolTable(0, {str(path).encode()!r}))
        info = abi.CALLBACK_INFO()
        lib.ToolChainCore_GetLastCallError(0, ctypes.byref(info))
        print(info.actLine)
        open({str(path)!r}, "w").write("$KOR\\n07: R=0.5 X=1.25e-1\\n")
        print(lib.ToolChainCore_LoadToolTable(0, {str(path).encode()!r}))
        values = (ctypes.c_double * 5)()
        lib.ToolChainCore_GetToolCorrection(0, 7, values)
        print(repr(values[0]), repr(values[1]))
    """, env=env).stdout.split()
    assert out == ["-1", "3", "0", "0.5", "0.125"]


# ------------------------------------------------------------------ G92 D

def set_correction(lib, entry, programmed, values, core=0):
    arr = (ctypes.c_double * 5)(*values)
    return lib.ToolChainCore_SetToolCorrection(core, entry, programmed, arr)


def test_g92_d_writes_only_the_values_programmed(fresh_core, tmp_path):
    """The manual's example N10 G92 D12 R0=10.0 R2=25.5 R3=-5.0: the radius, the lengths
    of axes 2 and 3; the lengths of axes 1 and 4 stay. The file is not written."""
    path = write(tmp_path, "$KOR\n12: R=1 X=2 Y=3 Z=4 4=5\n13: R=7\n")
    content = path.read_bytes()
    assert load(fresh_core, path) == 0
    assert set_correction(fresh_core, 12, 0b01101, (10.0, 99.0, 25.5, -5.0, 99.0)) == 0
    t = table(fresh_core)
    assert t[12] == (10.0, 2.0, 25.5, -5.0, 5.0)
    assert t[13] == (7.0, 0, 0, 0, 0)
    assert path.read_bytes() == content
    assert set_correction(fresh_core, 12, 0, (0,) * 5) == 0               # nothing programmed
    assert fresh_core.ToolChainCore_SetToolCorrection(0, 12, 0, None) == 0
    assert table(fresh_core)[12] == (10.0, 2.0, 25.5, -5.0, 5.0)


@pytest.mark.parametrize("entry, programmed, values, number, text", [
    (0, 1, (1, 0, 0, 0, 0), ERR_ENTRY, "Tool correction D0 does not exist (D1..D99)"),
    (100, 1, (1, 0, 0, 0, 0), ERR_ENTRY, "D100"),
    (12, 0b00101, (1, 0, float("nan"), 0, 0), ERR_NOT_FINITE, "D12 R2 = nan is not a finite number"),
    (12, 0b10000, (0, 0, 0, 0, -2e6), ERR_OUT_OF_RANGE, "D12 R4 = -2e+06 is outside <-1e+06, 1e+06>"),
])
def test_g92_d_refuses_and_writes_nothing(fresh_core, entry, programmed, values, number, text):
    assert set_correction(fresh_core, 12, 0b11111, (1, 2, 3, 4, 5)) == 0
    assert set_correction(fresh_core, entry, programmed, values) == -1
    got = call_error(fresh_core)
    assert got[0] == number and text in got[2], got
    assert table(fresh_core)[12] == (1, 2, 3, 4, 5)


def test_argument_checks(fresh_core):
    values = (ctypes.c_double * 5)()
    lib = fresh_core
    assert lib.ToolChainCore_GetToolCorrection(0, 0, values) == -1
    assert lib.ToolChainCore_GetToolCorrection(0, 100, values) == -1
    assert lib.ToolChainCore_GetToolCorrection(0, 1, None) == -1
    assert lib.ToolChainCore_SetToolCorrection(0, 1, 0b100000, values) == -1     # no R5
    assert lib.ToolChainCore_SetToolCorrection(0, 1, 1, None) == -1
    for bad in (3, 0xFFFFFFFF):
        assert lib.ToolChainCore_GetToolCorrection(bad, 1, values) == abi.TOOL_CHAIN_BAD_INTR_INDEX
        assert lib.ToolChainCore_SetToolCorrection(bad, 1, 1, values) == abi.TOOL_CHAIN_BAD_INTR_INDEX


def test_the_cores_have_tables_of_their_own(fresh_core):
    assert set_correction(fresh_core, 5, 1, (1.5, 0, 0, 0, 0), core=1) == 0
    assert table(fresh_core, 0)[5] == (0, 0, 0, 0, 0)
    assert table(fresh_core, 1)[5] == (1.5, 0, 0, 0, 0)
    assert table(fresh_core, 2)[5] == (0, 0, 0, 0, 0)


# ------------------------------------------------------------------ INI

def test_the_ini_names_the_table_beside_it(fresh_core, tmp_path):
    (tmp_path / "tables").mkdir()
    write(tmp_path / "tables", "$KOR\n03: R=3.5\n", "TAB2.KOR")
    ini = tmp_path / "machine.ini"
    ini.write_text("[CNC]\nDriver=offline\n[Corrections]\nToolTable = tables/TAB2.KOR\n")
    assert fresh_core.ToolChainCore_LoadFromIni(1, str(ini).encode(), None) == 0
    assert nonzero(table(fresh_core, 1)) == {3: (3.5, 0, 0, 0, 0)}
    absolute = write(tmp_path, "$KOR\n04: R=4\n", "abs.kor")
    ini.write_text(f"[Corrections]\nToolTable={absolute}\n")
    assert fresh_core.ToolChainCore_LoadFromIni(1, str(ini).encode(), None) == 0
    assert nonzero(table(fresh_core, 1)) == {4: (4.0, 0, 0, 0, 0)}
    ini.write_text("[CNC]\nDriver=offline\n")          # no key: the table stays
    assert fresh_core.ToolChainCore_LoadFromIni(1, str(ini).encode(), None) == 0
    assert nonzero(table(fresh_core, 1)) == {4: (4.0, 0, 0, 0, 0)}


def test_an_ini_whose_table_is_bad_applies_nothing(fresh_core, tmp_path):
    write(tmp_path, "$KOR\n03: R=3.5\n04: R=oops\n", "TAB0.KOR")
    ini = tmp_path / "machine.ini"
    ini.write_text("[GCodeParameters]\ncorrection0 = 0.75\n[Corrections]\nToolTable=TAB0.KOR\n")
    assert fresh_core.ToolChainCore_LoadFromIni(0, str(ini).encode(), None) == abi.TOOL_CHAIN_XEXEC
    number, line, text = call_error(fresh_core)
    assert (number, line) == (ERR_LINE, 3) and "TAB0.KOR" in text and "'R=oops'" in text
    params = abi.GCODE_PARAMETERS()
    assert fresh_core.ToolChainCore_GetGCodeParameters(0, byref(params)) == 0
    assert params.correction[0].size == 0.0
    assert nonzero(table(fresh_core)) == {}
    for value, why in (("", "[Corrections] ToolTable names no file"), ("missing.kor", "missing.kor")):
        ini.write_text(f"[Corrections]\nToolTable={value}\n")
        assert fresh_core.ToolChainCore_LoadFromIni(0, str(ini).encode(), None) == abi.TOOL_CHAIN_XEXEC
        assert why in call_error(fresh_core)[2]


# ------------------------------------------------------------------ in programs: D, &, G92 D
#
# The compilation works on a copy of the core's table taken when it starts; D selects the
# radius of G41 / G42, & the lengths of axes 1..4 (x y z c), G92 D writes the copy and, once
# the program compiled, the core's table. Expected values are closed forms (the inner offset
# of a rectangle, programmed position + length) and shapely's offsets.

from shapely.geometry import LineString, Point, Polygon  # noqa: E402

from compiler_host import Host  # noqa: E402

ERR_MISSING_VALUE, ERR_TOOL_WORD = 102, 723
RECT = Polygon([(0, 0), (100, 0), (100, 60), (0, 60)])


def rectangle(select, comp="G41"):
    """The rectangle RECT counter-clockwise from the middle of its bottom edge, led in from
    its centre: G41 keeps the tool inside, G42 outside."""
    return (f"G0 X50 Y30\n{select} {comp} G1 X50 Y0 F1000\nG1 X100 Y0\nG1 X100 Y60\nG1 X0 Y60\n"
            "G1 X0 Y0\nG1 X50 Y0\nG40 G1 X50 Y30\nM30\n")


@pytest.fixture
def host(fresh_core, tmp_path):
    """Core 0 through the ctypes test host; fresh_core gives the table back all zero."""
    h = Host(0, tmp_path)
    yield h


def compile_ok(host, code, **kw):
    r = host.compile(code, **kw)
    assert r.error is None, r.error
    return r


def tool_run(parts):
    """(x, y) of the tool centre's path through the compensated parts, from the start of
    the first one."""
    g = [p for p in parts if p.kind == "G"]
    first = next(i for i, p in enumerate(g) if p.comp != 40)
    last = max(i for i, p in enumerate(g) if p.comp != 40)
    return [g[first - 1].ce[:2]] + [p.ce[:2] for p in g[first:last + 1]]


@pytest.mark.parametrize("entry, radius", [(1, 0.0), (2, 0.8), (3, 0.8), (25, 0.0), (95, 0.0)])
def test_d_selects_the_radius_of_the_vendor_examples_entries(host, tmp_path, entry, radius):
    """The manual's example table (entry 01 is zeroed by its second $KOR block): D n G41
    inside the rectangle follows the inner offset at entry n's radius (not the 5 mm of
    correction[0]) — shapely's mitred buffer, corner by corner."""
    assert load(host.lib, write(tmp_path, VENDOR_EXAMPLE)) == 0
    params = host.params()
    params.correction[0].size = 5.0             # the default without D: not what D n gives
    run = tool_run(compile_ok(host, rectangle(f"D{entry}"), params=params).parts)
    inner = RECT.buffer(-radius, join_style=2) if radius > 0 else RECT
    corners = {(round(x, 9), round(y, 9)) for x, y in inner.exterior.coords}
    assert run[1] == pytest.approx((50.0, radius), abs=1e-9)           # on the perpendicular of the first edge
    for x, y in run[2:6]:
        assert (round(x, 9), round(y, 9)) in corners
    path = LineString(run[1:])
    assert path.hausdorff_distance(inner.exterior) < 1e-9


def test_a_negative_radius_swaps_the_side(host, tmp_path):
    """Entry 8 (R=-3) under G41 runs exactly as entry 9 (R=3) under G42: outside the
    rectangle, every corner of the path 3 mm from it."""
    assert load(host.lib, write(tmp_path, "$KOR\n08: R=-3\n09: R=3\n")) == 0
    left = compile_ok(host, rectangle("D8", "G41")).parts
    right = compile_ok(host, rectangle("D9", "G42")).parts
    assert [(p.func, p.comp, p.ce) for p in left] == [(p.func, p.comp, p.ce) for p in right]
    run = tool_run(left)
    assert {p.comp for p in left if p.comp != 40} == {42}
    for point in run[1:-1]:
        assert RECT.exterior.distance(Point(point)) == pytest.approx(3.0, abs=1e-9)
        assert not RECT.contains(Point(point))


def test_without_d_the_correction_parameters_stay_the_default_and_d0_is_no_radius(host, tmp_path):
    assert load(host.lib, write(tmp_path, "$KOR\n05: R=7\n")) == 0
    params = host.params()
    params.correction[0].size = 2.0
    assert tool_run(compile_ok(host, rectangle(""), params=params).parts)[2] == pytest.approx((98, 2), abs=1e-9)
    assert tool_run(compile_ok(host, rectangle("D5"), params=params).parts)[2] == pytest.approx((93, 7), abs=1e-9)
    assert tool_run(compile_ok(host, rectangle("D0"), params=params).parts)[2] == pytest.approx((100, 0), abs=1e-9)
    # D is modal: a D on an earlier line holds; G43 .. G48 keep their correction[] slots
    params.correction[2].size = 4.0
    code = "D5\n" + rectangle("").replace("G41", "G43")
    assert tool_run(compile_ok(host, code, params=params).parts)[2] == pytest.approx((96, 4), abs=1e-9)
    code = "D5\n" + rectangle("")
    assert tool_run(compile_ok(host, code, params=params).parts)[2] == pytest.approx((93, 7), abs=1e-9)


def test_a_d_the_line_s_function_takes_selects_nothing(host, tmp_path):
    """M6's D is the tool's diameter, G172's D drops small arcs, G92's D names the entry it
    writes: none of them is a selection (and none is checked as an entry)."""
    assert load(host.lib, write(tmp_path, "$KOR\n05: R=7\n")) == 0
    params = host.params()
    params.correction[0].size = 2.0
    for line in ("M6 T1 D150", "G172 D1", "G92 D5"):
        run = tool_run(compile_ok(host, line + "\n" + rectangle(""), params=params).parts)
        assert run[2] == pytest.approx((98, 2), abs=1e-9), line


LENGTHS = "$KOR\n01: R=10.0 X=20.0 Y=30.0 Z=40.0\n40: X=1.5 Y=-2.25 Z=3.125 4=7.5\n95: R=0.0 1=12.55 2=0.0 3=0.0 4=0.0\n"


def test_ampersand_adds_the_lengths_of_axes_1_to_4(host, tmp_path):
    """& n adds entry n's lengths to x y z c of every programmed position from the next
    move on (the line's own move included); the machine does not move when & changes,
    relative moves go on from where it stands, &0 cancels; b stays as programmed."""
    assert load(host.lib, write(tmp_path, LENGTHS)) == 0
    code = ("G0 X0 Y0 Z0 C0 B0\n&40\nG1 X10 Y20 Z30 C40 B50 F1000\nG91 G1 X1\nG90\n"
            "&95\nG1 X10\nG1 Y20 Z30 C40\n&1 G1 X0 Y0\n&0\nG1 Z5\n")
    g = [p.e[:5] for p in compile_ok(host, code).g]
    assert g == [pytest.approx(e, abs=1e-12) for e in [
        (0, 0, 0, 0, 0),
        (11.5, 17.75, 33.125, 47.5, 50),       # + (1.5, -2.25, 3.125, 7.5)
        (12.5, 17.75, 33.125, 47.5, 50),       # G91: one more in x
        (22.55, 17.75, 33.125, 47.5, 50),      # &95: x + 12.55; y z c not named stay
        (22.55, 20, 30, 40, 50),               # &95's y z c lengths are 0
        (20, 30, 30, 40, 50),                  # &1: x y + (20, 30) on the same line's move, z stays
        (20, 30, 5, 40, 50),                   # &0: programmed positions again
    ]]


def test_ampersand_moves_the_extent_and_the_zero_offset_parts_carry(host, tmp_path):
    """The parts (machine coordinates) and the program's extent carry the corrected
    positions; a part's m_zero includes the lengths, so m_e - m_zero is the position as
    written."""
    assert load(host.lib, write(tmp_path, LENGTHS)) == 0
    r = compile_ok(host, "G54 X100\n&1\nG0 X0 Y0 Z0\nG1 X10 Y5 Z-2 F1000\n")
    last = r.g[-1]
    assert last.e[:3] == pytest.approx((130, 35, 38), abs=1e-12)
    assert last.zero[:4] == pytest.approx((120, 30, 40, 0), abs=1e-12)
    assert [e - z for e, z in zip(last.e[:3], last.zero[:3])] == pytest.approx([10, 5, -2], abs=1e-12)
    info = abi.GCODE_INFO()
    assert host.lib.ToolChainCore_GetGCodeSizeInfo(0, byref(info)) == 0
    size = info.m_size[0]
    assert (size.m_maximalPos.x, size.m_maximalPos.y, size.m_maximalPos.z) == pytest.approx((130, 35, 40))
    assert (size.m_minimalPos.x, size.m_minimalPos.y, size.m_minimalPos.z) == pytest.approx((0, 0, 0))


def test_g92_d_in_a_program_writes_its_values_from_the_next_line_and_into_the_core(host, tmp_path):
    """The manual's example N10 G92 D12 R0=10.0 R2=25.5 R3=-5.0 in a program: the active
    &12 takes the new lengths from the next line; once compiled, the core's entry 12 has
    the programmed values and keeps R1 and R4; the file is never written."""
    path = write(tmp_path, "$KOR\n12: R=1 X=2 Y=3 Z=4 4=5\n")
    content = path.read_bytes()
    assert load(host.lib, path) == 0
    code = ("G0 X0 Y0 Z0 C0\n&12\nG1 X1 Y1 Z1 C1 F1000\nN10 G92 D12 R0=10.0 R2=25.5 R3=-5.0\n"
            "G1 X1 Y1 Z1 C1\n")
    r = host.compile(code, run=False)
    assert r.error is None, r.error
    assert table(host.lib)[12] == (10.0, 2.0, 25.5, -5.0, 5.0)
    assert path.read_bytes() == content
    g = [p.e[:4] for p in host.run().g]
    assert g[1:] == [pytest.approx((3, 4, 5, 6)), pytest.approx((3, 26.5, -4, 6))]


def test_g92_d_changes_the_radius_of_the_next_contour(host, tmp_path):
    assert load(host.lib, write(tmp_path, "$KOR\n12: R=1\n")) == 0
    code = rectangle("D12").replace("M30\n", "") + "G92 D12 R0=5\n" + rectangle("")
    g = compile_ok(host, code).g
    second = next(i for i, p in enumerate(g) if p.line == 10)       # the second contour's G0
    first_run = {(round(p.ce[0], 9), round(p.ce[1], 9)) for p in g[:second] if p.comp != 40}
    second_run = {(round(p.ce[0], 9), round(p.ce[1], 9)) for p in g[second:] if p.comp != 40}
    assert {(99, 1), (99, 59), (1, 59), (1, 1)} <= first_run        # the first contour: 1 mm
    assert {(95, 5), (95, 55), (5, 55), (5, 5)} <= second_run       # the second: 5 mm


def test_a_program_that_fails_writes_nothing_into_the_core(host, tmp_path):
    assert load(host.lib, write(tmp_path, "$KOR\n12: R=1\n")) == 0
    r = host.compile("G92 D12 R0=3\nG1 X1/0\n")
    assert r.error is not None and r.error[0] == 200
    assert table(host.lib)[12] == (1, 0, 0, 0, 0)


def test_a_table_change_between_compile_and_run(host, tmp_path):
    """A compiled program keeps the table it was compiled with: the run follows the
    radius of the compilation, the core's table keeps the host's change (the run writes
    nothing), the next compilation takes it."""
    assert load(host.lib, write(tmp_path, "$KOR\n05: R=5\n")) == 0
    code = rectangle("D5").replace("M30\n", "") + "G92 D12 R0=10\n"
    assert host.compile(code, run=False).error is None
    assert table(host.lib)[12][0] == 10.0
    assert set_correction(host.lib, 5, 1, (2.0, 0, 0, 0, 0)) == 0
    assert set_correction(host.lib, 12, 1, (3.0, 0, 0, 0, 0)) == 0
    assert tool_run(host.run().parts)[2] == pytest.approx((95, 5), abs=1e-9)
    assert table(host.lib)[5][0] == 2.0 and table(host.lib)[12][0] == 3.0
    assert tool_run(compile_ok(host, code).parts)[2] == pytest.approx((98, 2), abs=1e-9)


@pytest.mark.parametrize("code, number, column, text", [
    ("D100 G41 G1 X1 F100", ERR_TOOL_WORD, 1, "'D100' at column 1: the table has the entries 1..99 (0: none)"),
    ("G1 X1 F100 D-1", ERR_TOOL_WORD, 12, "'D-1'"),
    ("G1 X1 F100 D1.5", ERR_TOOL_WORD, 12, "'D1.5'"),
    ("&100", ERR_TOOL_WORD, 1, "'&100'"),
    ("G1 X1 F100 & -1", ERR_TOOL_WORD, 12, "'&'"),
    ("&", ERR_MISSING_VALUE, 1, "Address & at column 1 without a value"),
    ("G92 D0 R0=1", ERR_TOOL_WORD, 5, "'D0' at column 5: G92 D writes the entries 1..99"),
    ("G92 D100 R0=1", ERR_TOOL_WORD, 5, "'D100'"),
    ("G92 D1 R5=1", ERR_TOOL_WORD, 8, "'R5' at column 8: G92 D writes R0 (the radius) .. R4"),
    ("G92 D1 R12=1", ERR_TOOL_WORD, 8, "'R12'"),
    ("G1 X1 F100 R0=1", ERR_TOOL_WORD, 12, "'R0=1' at column 12: R0= .. R4= write the tool table on a line with G92 D"),
    ("G92 R0=1", ERR_TOOL_WORD, 5, "G92 D n names the entry"),
    ("G92 D1 R0=", ERR_MISSING_VALUE, 8, "Address R0 at column 8 without a value"),
    ("G92 D1 R0=2000000", ERR_OUT_OF_RANGE, None, "D1 R0 = 2e+06 is outside"),
])
def test_bad_entries_and_values_are_errors_with_their_column(host, code, number, column, text):
    r = host.compile("G0 X0\n" + code + "\n")
    assert r.error is not None
    got_number, line, _, message, _ = r.error
    assert (got_number, line) == (number, 2), r.error
    assert text in message
    if column is not None:
        assert f"at column {column}" in message


def test_iso_mode_g41_d_and_g43_h_use_the_table(host, tmp_path):
    """ISO mode: G41 D n takes entry n's radius (D0: LinuxCNC's tool 0, nothing to
    compensate); G43 H n is & n (LinuxCNC applies every offset of tool n's row: here the
    lengths of x y z c), G43 without H takes the tool T, G49 cancels."""
    assert load(host.lib, write(tmp_path, "$KOR\n02: R=2.5\n07: Z=12.5\n08: X=1 Z=-3\n")) == 0
    rezerva1 = host.defaults.rezerva1 | abi.GCODE_REZERVA1_ISO_COMPAT
    run = tool_run(compile_ok(host, rectangle("D2"), rezerva1=rezerva1).parts)
    assert run[2] == pytest.approx((97.5, 2.5), abs=1e-9)
    assert {p.comp for p in compile_ok(host, rectangle("D0"), rezerva1=rezerva1).g} == {40}
    code = "G0 X0 Y0 Z0\nG43 H7\nG1 X1 Y2 Z3 F100\nT8 M6\nG43\nG1 Z3\nG49\nG1 Z3\n"
    g = [p.e[:3] for p in compile_ok(host, code, rezerva1=rezerva1).g]
    assert g == [pytest.approx(e) for e in [(0, 0, 0), (1, 2, 15.5), (1, 2, 0), (1, 2, 3)]]
    r = host.compile("G43 H100\n", rezerva1=rezerva1)
    assert r.error[0] == ERR_TOOL_WORD and "'H100' at column 5" in r.error[3]


def test_a_table_file_beyond_64_mib_is_refused_before_it_is_read(fresh_core, tmp_path):
    assert load(fresh_core, write(tmp_path, VENDOR_EXAMPLE)) == 0
    before = table(fresh_core)
    big = tmp_path / "BIG.KOR"
    with open(big, "wb") as f:                  # sparse: no 64 MiB written
        f.truncate((64 << 20) + 1)
    assert load(fresh_core, big) == -1
    assert call_error(fresh_core) == (25, 0, f"Table file '{big}' is larger than 64 MiB")
    assert table(fresh_core) == before
