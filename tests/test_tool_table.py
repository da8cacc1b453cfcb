"""The tool correction table (docs/tool-table.md): the vendor's example TAB0.KOR read
exactly, every malformed field refused with its line and the table kept, any bytes read
safely, numbers independent of the locale, G92 D's write (the example of entry 12),
the INI key."""
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
], ids=["crlf-bom-tab", "case-signs-exponents", "nul-in-comment", "blank-and-empty", "long-comment", "long-line"])
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
    ("axis-name-U", "$KOR\n01: U=5\n", ERR_LINE, 2, "'U=5' is no value of an entry"),
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


def test_numbers_do_not_follow_a_decimal_comma_locale(run_python, tmp_path, tmp_path_factory):
    from test_inputs import _comma_locale
    name, env = _comma_locale(tmp_path_factory)
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
