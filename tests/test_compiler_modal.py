"""Modal state of the compiler: compensation records, G900 parameter changes,
G167/G172 storage, lathe words, progress reporting and CompileFromFile (core 1)."""
import ctypes
import time

import pytest

from compiler_host import Host, _wait, close, last_error, ok
from sf_tch import abi


@pytest.fixture(scope="module")
def host(tmp_path_factory):
    h = Host(1, tmp_path_factory.mktemp("core1m"))
    yield h
    h.close()


def test_compensation_marks_the_parts(host):
    r = ok(host, "G1 X0 Y-5 F100\nG41\nG1 X0 Y0\nG1 X10\nG1 Y10\nG40\nG1 X0 Y15\n")
    assert [q.comp for q in r.g] == [40, 41, 41, 41, 40]
    r = ok(host, "G1 X0 Y-5 F100\nG44\nG1 X0 Y0\nM10\nG1 X10\nG40\nG1 X10 Y-5\n")
    assert [q.comp for q in r.g] == [40, 42, 42, 40]
    # no G41..G48: nothing is compensated
    assert [q.comp for q in ok(host, "G40\nG1 X10 F100\n").g] == [40]


def test_g900_changes_feeds_and_pops(host):
    p = host.params()
    p.motion[0].feed = 9000
    p.motion[1].feed = 400
    code = ("G900 S1\nG900 S20 F1234 C100 D200\nG900 S30 F55\nG0 X1\nG1 X2 F0\n"
            "G900 S2\nG0 X3\nG1 X4 F0\nG900 S7 A0 F100 C1 D2\nG900 S9 A10 B20 F5\nG900 S60 D9\n")
    r = ok(host, code, params=p, start=[0] * 10)
    assert [q.feed for q in r.g] == [1234, 55, 9000, 400]


def test_stored_functions_do_not_move(host):
    code = ("G167 E0.1 A0.01 U45\nG167\nG172 R1 C2 D3\nG173\nG24\nG21\nG96 S200\nG97\nM-5 X0 Y1\n"
            "G1 X1 Y1\nG98 X0 Y0\nG1 X1\n")
    r = ok(host, code, start=[0] * 10)
    assert [p.e[:2] for p in r.g] == [(1, 1), (2, 1)]


def test_g168_keeps_a_modal_arc_from_moving(host):
    r = ok(host, "G2 X10 Y0 I5 J0\nG168 X0 Y0 I0 J0 K1 R90\nG1 X10 Y0\n", start=[0] * 10)
    assert [p.func for p in r.g] == [2, 1]
    assert close(r.g[1].e[:2], (0, 10), 1e-9)


def test_progress_and_compile_from_file(host, tmp_path):
    lib = host.lib
    seen = []

    @abi.AddOutputLog
    def on_log(user, tab, text, info):
        return 0

    path = tmp_path / "big.nc"
    path.write_text("".join(f"G1 X{i % 100} Y{i % 7}.5\n" for i in range(300000)))
    p = host.params()
    assert lib.ToolChainCore_SetGCodeParameters(1, ctypes.byref(p)) == 0
    assert lib.ToolChainCore_CompileFromFile(1, str(path).encode()) == 0
    while True:
        status = lib.ToolChainCore_StatusCNC(1)
        if status != 1:
            break
        time.sleep(0.001)
    assert status == -1
    assert last_error(lib, 1) is None
    info = abi.GCODE_INFO()
    assert lib.ToolChainCore_GetGCodeSizeInfo(1, ctypes.byref(info)) == 0
    assert info.m_size[0].m_maximalPos.x == 99


def test_lines_count_and_crlf(host):
    r = ok(host, "G1 X1\r\nG1 X2\r\n\r\nG1 X3", start=[0] * 10)
    assert [p.line for p in r.g] == [1, 2, 4]
    assert [p.e[0] for p in r.g] == [1, 2, 3]


def test_relative_program_moves_with_reset(host):
    lib = host.lib
    coords = (ctypes.c_double * 10)(*([100.0] * 10))
    # G91 throughout: ResetCNC to a new start moves the whole program
    assert host.compile("G91 G1 X1 Y1\nG2 X2 Y0 I1 J0\n", start=[0] * 10, run=False).error is None
    assert lib.ToolChainCore_ResetCNC(1, 0, 10, coords) == 0
    r = host.run(keep_position=False)
    assert close(r.g[0].e[:2], (101, 101)) and close(r.g[1].cc[:2], (102, 101))
    # absolute positions stay where they are
    assert host.compile("G1 X1 Y1\n", start=[0] * 10, run=False).error is None
    assert lib.ToolChainCore_ResetCNC(1, 0, 10, coords) == 0
    r = host.run(keep_position=False)
    assert close(r.g[0].e[:2], (1, 1)) and close(r.g[0].s[:2], (100, 100))


def test_m_minus_5_changes_only_written_axes(host):
    # state only: no parts, no error
    assert ok(host, "M-5 X0\nM-5 Y0\nM-5 X1\n", start=[0] * 10).parts == []


def test_a_line_runs_in_one_order_whatever_the_order_written(host):
    """A line is read into modal groups and executed in the order of docs/compiler.md
    ("How a line is executed"): the words of a line in any order give the same parts.
    The oracle: the same settings written one per line before the parts' line."""
    import itertools
    words = ["G91", "G18", "G42", "G95", "T5", "G1 X4 Z-2", "M1001", "M52"]
    spread = ok(host, "G1 X1 Y1 F100\nG95\nT5\nG18\nG42\nG91\nM1001 G1 X4 Z-2 M52\n", start=[0] * 10)

    def parts(r):
        return [(q.kind, q.func, q.e, q.plane, q.comp, q.per_min, q.tool) for q in r.parts[1:]]
    assert [q[:2] for q in parts(spread)] == [("M", 1001), ("G", 1), ("M", 52)]
    for order in itertools.islice(itertools.permutations(words), 0, None, 997):
        r = ok(host, "G1 X1 Y1 F100\n" + " ".join(order) + "\n", start=[0] * 10)
        assert parts(r) == parts(spread), order


def test_modal_groups_on_a_line_of_their_own_or_on_the_move(host):
    """A line without a G function of groups 1, 2, 4 .. 10 (most: a move) skips those groups
    (block.pyx's cp_block): the groups written on lines of their own, or on the moves' lines,
    give the same parts."""
    pairs = [("G91", "G1 X1 Y1 F100"), ("G95", "X2 Y3 F0.5"), ("G19", "G0 X4"), ("G94 G17", "X5 Z1"),
             ("G90", "G1 Y2 F200"), ("G96 S100", "X7"), ("G97 G41", "G1 X8 Y1"), ("G40 G169", "G0 Y9")]
    apart = "\n".join(f"{g}\n{move}" for g, move in pairs) + "\n"
    together = "\n".join(f"{g} {move}" for g, move in pairs) + "\n"

    def seen(r):
        return [(q.kind, q.func, q.e, q.plane, q.per_min, q.comp, q.fp, q.feed, q.tool, q.zero) for q in r.parts]

    a, b = ok(host, apart, start=[0] * 10), ok(host, together, start=[0] * 10)
    assert len(a.parts) == len(pairs)
    assert seen(a) == seen(b)
    assert [q.plane for q in a.parts] == [17, 17, 19, 17, 17, 17, 17, 17]
    assert [q.per_min for q in a.parts] == [1, 0, 1, 1, 1, 1, 1, 1]
