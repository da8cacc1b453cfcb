"""Every compile error path ends in a numbered error with its line, never a hang or
a crash; cancellation and the block limit (core 2)."""
import ctypes
import time

import pytest

from compiler_host import Host, _wait


@pytest.fixture(scope="module")
def host(tmp_path_factory):
    h = Host(2, tmp_path_factory.mktemp("core2"))
    yield h
    h.close()


def err(host, code, **kw):
    r = host.compile(code, run=False, **kw)
    assert r.error is not None, "expected an error"
    return r.error


@pytest.mark.parametrize("code, number, line, text", [
    ("G1 X1\nGOTO NOWHERE\n", 300, 2, "Undefined label 'NOWHERE'"),
    ("G25 L77\n", 300, 1, "Undefined label 'N77'"),
    ("A:\nA:\nGOTO A\n", 301, 2, "Label 'A' defined twice (first on line 1)"),
    ("G1 X1\nEND\n", 302, 2, "END without FOR, WHILE or IF"),
    ("ELSE\n", 302, 1, None),
    ("FOR P1 = 1 TO 3\nG1 X1\n", 303, 2, "FOR without END"),
    ("WHILE 1 < 0\nG1 X1\n", 303, 1, "WHILE without END"),
    ("IF 1 > 2 THEN\nG1 X1\n", 303, 1, "IF without END"),
    ("G1 X1 QQ5\n", 100, 1, "Unknown word 'QQ5' at column 7"),
    ("G1 X1 #\n", 111, 1, None),
    ("G1 X1.2.3\n", 101, 1, None),
    ("G1 X1..5\n", 101, 1, "Bad number '1..5' at column 5"),
    ("G1 X.\n", 101, 1, "Bad number '.' at column 5"),
    ("G1 X 1.5.\n", 101, 1, "Bad number '1.5.' at column 6"),
    ("G1 X-.5.5\n", 101, 1, "Bad number '.5.5' at column 6"),
    ("G1 Y2 X12.5.7 Z1\n", 101, 1, "Bad number '12.5.7' at column 8"),
    ("G1 X1" + "0" * 401 + "\n", 101, 1, "Bad number '" + "1" + "0" * 39 + "' at column 5"),
    ("G1 X" + "9" * 320 + "\n", 108, 1, "Number '" + "9" * 40 + "' at column 5 is too large"),
    ("G1 X(" + "9" * 320 + ")\n", 108, 1, "Number '" + "9" * 40 + "' at column 6 is too large"),
    ("G1 X\n", 102, 1, "Address X at column 4 without a value"),
    ("G1 X (1 + 2\n", 103, 1, "Unbalanced brackets: '(' at column 6 not closed"),
    ("G1 X1 (open comment\n", 104, 1, "Comment '(' at column 7 not closed on this line"),
    ("G1 X 1/0\n", 200, 1, "Division by zero"),
    ("P1 = 5 % 0\n", 200, 1, None),
    ("G1 X P100\n", 201, 1, None),
    ("G1 X 2 +* 3\r\n", 202, 1, "Syntax error in expression '* 3' at column 9"),
    ("G1 X FOO(1)\n", 203, 1, "Unknown function 'FOO' at column 6"),
    ("G1 X SQRT(-1)\n", 204, 1, None),
    ("G1 X ASIN(2)\n", 204, 1, None),
    ("G1 X ReadPLCLong(0)\n", 205, 1, None),
    ("G1 X ReadPLCDouble(524284)\n", 205, 1, None),
    ("P1 = WritePLCLong(-4, 1)\n", 205, 1, None),
    ("M-6 A600000\n", 205, 1, None),
    ("RETURN\n", 305, 1, None),
    ("M17\n", 305, 1, None),
    ("BREAK\n", 307, 1, "BREAK outside a loop"),
    ("IF 1 CONTINUE\n", 307, 1, "CONTINUE outside a loop"),
    ("IF 1 > 0 MAYBE\n", 308, 1, None),
    ("G2 X10 Y0 R4\n", 401, 1, None),
    ("G2 X10 Y0\n", 402, 1, None),
    ("G2 X10 Y0 I3 J0\n", 400, 1, None),
    ("G2 X6 Y0 I5 J0\n", 407, 1, None),
    ("G7\n", 404, 1, "Unknown G function G7 at column 1"),
    ("G1.5 X1\n", 404, 1, None),
    ("M1000\n", 405, 1, None),
    ("M-7\n", 405, 1, None),
    ("M2.5\n", 405, 1, None),
    ("G168 X0 Y0 R5 Q5\n", 403, 1, None),
    ("G900 S2\n", 206, 1, "G900 parameter stack empty"),
    ("G900 S99\n", 106, 1, None),
    ("G900 S7 A12 F100\n", 106, 1, None),
    ("G1 " + "G1 " * 20 + "X1\n", 107, 1, None),
    ("M99999999999999999999\n", 405, 1, None),
    ("G(10^300)\n", 404, 1, None),
    ("G25 L(10^300)\n", 300, 1, None),
    ("G26 L(-10^300) H(10^300)\n", 106, 1, None),      # H beyond 1e30 is refused first
    ("G900 S(10^300)\n", 106, 1, None),
])
def test_error(host, code, number, line, text):
    e = err(host, code, start=[0] * 10)
    assert e[0] == number, e
    assert e[1] == line, e
    if text is not None:
        assert e[3] == text, e


@pytest.mark.parametrize("line, letter", [("T(10^300) M6", "T"), ("M-6 S(10^300)", "S"),
                                          ("G168 Q(10^300) R1", "Q"), ("G1 X(-10^30 * 1.01)", "X"),
                                          ("G1 F(2 * 10^30) X1", "F")])
def test_huge_values_are_refused(host, line, letter):
    """Beyond 1e30 a word (other than G, M, L) is a bad value: a part never carries
    an infinite float."""
    r = host.compile("G1 X1 F100\n" + line + "\n", run=False)
    assert r.error[0] == 106 and r.error[1] == 2
    assert r.error[3].startswith("Bad value") and r.error[3].endswith(f"of address {letter}")


def test_error_file_index_and_prefix(host):
    e = err(host, "G1 X1\n", prefix="G1 X1\nG1 Q(\n")
    idx = host.lib.ToolChainCore_FileToIdx(2, b"__prefix__")
    assert e[2] == idx and e[1] == 2


def test_call_stack_overflow(host):
    e = err(host, "SUB:\nG91 G1 X1\nCALL SUB\n")
    assert e[0] == 304 and "64" in e[3] and e[1] == 3


def test_block_limit_on_endless_loops(host):
    t = time.monotonic()
    e = err(host, "LOOP:\nP1 = P1 + 1\nGOTO LOOP\n")
    assert e[0] == 306 and e[1] in (1, 2, 3)
    e = err(host, "WHILE 1\nEND\n")
    assert e[0] == 306
    assert time.monotonic() - t < 30


def test_line_too_long_and_garbage(host):
    e = err(host, "G1 X1\n" + "G1 X1 " * 20000 + "\n")
    assert e[0] == 105 and e[1] == 2
    e = err(host, b"G1 X1\n\x01\x02\xff\xfe garbage\n")
    assert e[0] == 100 and e[1] == 2
    e = err(host, bytes(range(1, 256)) * 10)
    assert e[0] in (100, 101, 102, 103, 104)


def test_random_garbage_never_crashes(host):
    import random
    rnd = random.Random(3)
    alphabet = b"GXYZIJKRMPFST0123456789.-+*/^()%;:= \n\tABCDEFHLNOQUVW,<>!_"
    for _ in range(200):
        data = bytes(rnd.choice(alphabet) for _ in range(rnd.randint(1, 200))).replace(b"\0", b" ")
        r = host.compile(data, run=False, start=[0] * 10)
        assert r.error is None or r.error[0] > 0


def test_cancel_by_reset(host):
    lib = host.lib
    p = host.params()
    assert lib.ToolChainCore_SetGCodeParameters(2, ctypes.byref(p)) == 0
    code = b"FOR P1 = 1 TO 200000000\nP2 = P2 + SIN(P1)\nEND\n"
    assert lib.ToolChainCore_CompileFromMemory(2, b"slow.nc", code) == 0
    time.sleep(0.05)
    t = time.monotonic()
    assert lib.ToolChainCore_ResetCNC(2, 0, 0, None) in (0, -1)
    status = _wait(lib, 2, (-1, 0, -30), timeout=10)
    assert time.monotonic() - t < 2
    assert status != 1
