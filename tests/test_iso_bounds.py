"""The ISO mode's numbers and its bounded work (docs/dialect.md, "Numbers"; docs/compiler.md,
"ISO compatibility mode"): every value that reaches a part passes the address words'
bound of 1e30 (through parameters, polar words, dwells, work offsets, G92 and the home
positions), computed O-word labels are whole numbers, a canned-cycle line asking for more
parts than a program holds is refused before it makes one, an ending call is seen per part,
and the tables a part names (zero offsets, rotations, radii) have a named limit. Core 2."""
import ctypes

import pytest

import sf_tch
from compiler_host import Host, ok

ISO = 1
ERR_CANCELLED, ERR_BAD_VALUE, ERR_NGC_G, ERR_NGC_WORD, ERR_TABLE_LIMIT = 5, 106, 412, 413, 312


@pytest.fixture(scope="module")
def host(tmp_path_factory):
    h = Host(2, tmp_path_factory.mktemp("core2bounds"))
    h.defaults.rezerva1 = 0
    yield h
    h.lib.ToolChainCore_SetGCodeParameters(h.core, ctypes.byref(h.defaults))
    h.close()


def iso_error(host, code):
    r = host.compile(code, run=False, start=[0] * 10, rezerva1=ISO)
    assert r.error is not None, code
    return r.error


BEYOND = [
    ("polar-distance", "G1 @[10**300] ^45 F100\nM2\n", 1, "Bad value 1e+300 of address @"),
    ("polar-angle", "G1 @5 ^[-10**31] F100\nM2\n", 1, "Bad value -1e+31 of address ^"),
    ("home-g28", "#5161=[10**300]\nG28\nM2\n", 1, "Bad value 1e+300 of address #5161"),
    ("home-g30", "G0 X1\n#5189=[-2*10**30]\nG30\nM2\n", 2, "Bad value -2e+30 of address #5189"),
    ("dwell", "G4 P[10**300]\nM2\n", 1, "Bad value 1e+300 of address P"),
    ("work-offset", "#5221=[10**308]\nG54\nG1 X1 F100\nM2\n", 1, "Bad value 1e+308 of address #5221"),
    ("g59.3-offset", "#5389=[10**31]\nM2\n", 1, "Bad value 1e+31 of address #5389"),
    ("g92-offsets", "#5211=[10**308]\nG92.3\nG1 X1 F100\nM2\n", 1, "Bad value 1e+308 of address #5211"),
    ("indirect", "#1=5221\n#[#1]=[10**40]\nM2\n", 2, "Bad value 1e+40 of address #5221"),
    ("g10-word", "G10 L2 P1 X[10**31]\nM2\n", 1, "Bad value 1e+31 of address X"),
    ("cycle-dwell", "G17 G82 X0 Y0 Z-1 R1 P[10**35] F100\nM2\n", 1, "Bad value 1e+35 of address P"),
]


@pytest.mark.parametrize("code, line, text", [b[1:] for b in BEYOND], ids=[b[0] for b in BEYOND])
def test_values_beyond_the_bound_never_reach_a_part(host, code, line, text):
    number, got_line, _, got_text, _ = iso_error(host, code)
    assert (number, got_line, got_text) == (ERR_BAD_VALUE, line, text)


def test_parameters_off_the_positional_ranges_keep_large_values(host):
    """LinuxCNC's parameters hold any number; only those a G function turns into a
    position are bounded (#5220, the coordinate system's number, and #5230 are not)."""
    r = ok(host, "#1=[10**300]\n#5230=[10**300]\n#<big>=[10**300]\nG1 X[#1/10**300] F100\nM2\n",
           start=[0] * 10, rezerva1=ISO)
    assert [p.e[0] for p in r.g] == [1.0]


def test_the_error_is_located_in_the_python_layer():
    with sf_tch.compile("G1 X1 F100\n#5161=[10**300]\nG28\n", iso=True, start=[0] * 10, core=0) as program:
        (error,) = program.errors
    assert (error.number, error.line, error.column) == (ERR_BAD_VALUE, 2, 1)


@pytest.mark.parametrize("label, shown", [("-5", "-5"), ("-1", "-1"), ("10**300", "1e+300"), ("2.5", "2.5"),
                                          ("#1", "-7")])
def test_a_computed_label_that_is_no_number_says_so(host, label, shown):
    number, line, _, text, _ = iso_error(host, f"#1=-7\no[{label}] call\n")
    assert (number, line) == (ERR_NGC_WORD, 2)
    assert text == (f"'o[{label}] call' at column 1: the computed label {shown} is no subroutine number "
                    "(a whole number 0 .. 999999999999)")
    assert text.isprintable()


@pytest.mark.parametrize("code, why", [
    ("G17 G81 X0 Y0 Z-1 R1 L[10**9] F100\n", "1000000000 repeats of 0 pecks"),
    ("G17 G83 X0 Y0 Z-1 R1 Q[10**-300] F100\n", "1 repeats of 2e+300 pecks"),
    ("G17 G73 X0 Y0 Z-1 R1 Q[10**-7] L10 F100\n", "10 repeats of 2e+07 pecks"),
])
def test_a_cycle_asking_for_more_parts_than_a_program_holds_is_refused_at_once(host, code, why):
    number, line, _, text, _ = iso_error(host, code)
    assert number == ERR_NGC_G and line == 1
    assert text.endswith(f"{why} make more parts than a program holds (20000000)"), text


def test_a_cycle_within_the_limit_still_runs(host):
    r = ok(host, "G17 G81 X0 Y0 Z-1 R1 L3 F100\nM2\n", start=[0] * 10, rezerva1=ISO)
    assert len(r.g) == 1 + 3 * 3          # to R, then per hole: rapid to R, feed down, rapid out


def test_an_ending_call_is_seen_within_the_line_that_expands(harness):
    """The cancel flag set before a one-line program of 40,000 parts: the compiler stops at
    its first part; it used to look only between lines (every 1024 lines)."""
    params = bytearray(harness.default_params())
    params[_rezerva1_offset():_rezerva1_offset() + 4] = ISO.to_bytes(4, "little")
    code = "G17 G81 X0 Y0 Z-1 R1 L10000 F100\n"
    assert harness.compile(code, bytes(params)).n_parts > 30000
    with pytest.raises(ValueError) as caught:
        harness.compile(code, bytes(params), cancelled=True)
    assert caught.value.args[0][0] == ERR_CANCELLED


def _rezerva1_offset():
    from sf_tch import abi
    return abi.GCODE_PARAMETERS.rezerva1.offset


def test_names_and_skipped_branches_in_long_loops(host):
    """Named parameters are found among thousands (an index, not a scan), locals vanish at
    the return, and a loop over a branch not taken skips it every pass (the scan of the
    branch is remembered, its line numbers stay right)."""
    names = "".join(f"#<n{k}>={k}\n" for k in range(3000))
    skipped = "".join(f"G1 X{k}\n" for k in range(200))
    code = (names + "o10 sub\n#<local>=#1\n#<_g>=[#<_g>+#<local>]\no10 endsub\n#<_g>=0\n#<i>=0\n"
            "o20 while [#<i> LT 50]\no30 if [#<i> LT 0]\n" + skipped + "o30 else\n"
            "o10 call [#<n2999>]\no30 endif\n#<i>=[#<i>+1]\no20 endwhile\n"
            "G1 X[#<_g>/50] Y[#<n1234>] F100\nM2\n")
    r = ok(host, code, start=[0] * 10, rezerva1=ISO)
    assert [(p.e[0], p.e[1]) for p in r.g] == [(2999.0, 1234.0)]
    number, line, _, text, _ = iso_error(host, code.replace("G1 X[#<_g>/50]", "G1 X[#<local>]"))
    assert line == code.count("\n") - 1 and "local" in text


def test_a_program_with_more_zero_offsets_than_the_table_holds(host):
    code = "".join(f"G92 X{k}\n" for k in range(1, 70001)) + "M2\n"
    number, line, _, text, _ = iso_error(host, code)
    assert number == ERR_TABLE_LIMIT
    assert text == "More than 65535 different zero offsets (G54.., G92, tool lengths) in one program"
    assert line == 65535             # entry 0 is the program's start
