"""Hostile and malformed G-code never crashes or hangs the host: each case runs in a
fresh interpreter (a crash would show as a dead subprocess), compiles, and must end
with status -1 and either success or a numbered error with a line."""
import os
import random

import pytest

SCRIPT = """
import ctypes, sys, time
from sf_tch import abi, library
lib = library.load(LIB_PATH)
code = open(CODE_PATH, "rb").read()
assert lib.ToolChainCore_CompileFromMemory(0, b"hostile.nc", code) == 0
deadline = time.monotonic() + 120
while lib.ToolChainCore_StatusCNC(0) == 1:
    assert time.monotonic() < deadline, "compilation hangs"
    time.sleep(0.005)
info = abi.CALLBACK_INFO()
failed = lib.ToolChainCore_GetLastError(0, ctypes.byref(info))
print(lib.ToolChainCore_StatusCNC(0), failed, info.stringId if failed else 0,
      info.actLine if failed else 0)
if failed:
    print((info.m_fullError or b"").decode(errors="replace"))
"""


def compile_in_subprocess(run_python, tmp_path, code: bytes):
    path = tmp_path / "hostile.nc"
    path.write_bytes(code)
    proc = run_python(f"CODE_PATH = {str(path)!r}\n" + SCRIPT, timeout=180)
    status, failed, number, line = (int(v) for v in proc.stdout.split("\n")[0].split())
    assert status == -1
    return failed, number, line, proc.stdout


CASES = {
    "binary garbage": bytes(random.Random(1).randrange(256) for _ in range(20000)),
    "nul bytes": b"G1 X1\x00\x00 Y2\nG1 X\x00\n",
    "only comments": b"(a)\n; b\n// c\nREM d\nG29 e\n%\n",
    "empty": b"",
    "unterminated comment": b"G1 X1 (never closed\nG1 X2\n",
    "very long line": b"G1 X" + b"9" * 200000 + b"\n",
    "many words": b"G1 " + b"X1 " * 100000 + b"\n",
    "deep brackets": b"P1 = " + b"(" * 5000 + b"1" + b")" * 5000 + b"\n",
    "division by zero": b"P1 = 0\nP2 = 5 / P1\n",
    "endless goto": b"L1:\nGOTO L1\n",
    "endless while": b"WHILE 1 > 0\nP1 = P1 + 1\nEND\n",
    "recursive call": b"CALL S1\nM30\nS1:\nCALL S1\nRETURN\n",
    "end without loop": b"G1 X1\nEND\n",
    "missing end": b"FOR P1 = 1 TO 3\nG1 X1\n",
    "undefined label": b"GOTO NOWHERE\n",
    "huge number": b"G1 X1e400 Y-1e400\n",
    "nan text": b"G1 Xnan Yinf\n",
    "bad parameter": b"P100 = 1\nP-1 = 2\n",
    "bad plc address": b"P1 = ReadPLCLong(-5)\nP2 = ReadPLCDouble(99999999)\n",
    "arc with zero radius": b"G2 X0 Y0 I0 J0\n",
    "crlf and tabs": b"G1\tX1\r\nG1\tY1\r\n",
}


@pytest.mark.parametrize("name", sorted(CASES))
def test_hostile_program_ends_cleanly(run_python, tmp_path, name):
    failed, number, line, out = compile_in_subprocess(run_python, tmp_path, CASES[name])
    if failed:
        assert number > 0
        assert "\n" in out


@pytest.mark.parametrize("name", ["endless goto", "endless while", "recursive call", "end without loop",
                                  "missing end", "undefined label", "division by zero"])
def test_flow_errors_are_reported_with_a_line(run_python, tmp_path, name):
    failed, number, line, _ = compile_in_subprocess(run_python, tmp_path, CASES[name])
    assert failed == 1 and number > 0 and line >= 1


@pytest.mark.slow
def test_random_mutations_of_a_real_program(run_python, tmp_path):
    """Randomly mutated cutting programs: bytes dropped, duplicated, replaced."""
    scale = int(os.environ.get("SF_TCH_SLOW_SCALE", "1"))
    rng = random.Random(7)
    base = (b"G90 G17\nG0 X0 Y0\nM51\nG1 X10 Y0 F1000\nG2 X20 Y10 I0 J10\nFOR P1 = 1 TO 3\n"
            b"G1 X(P1*5) Y(P1*2)\nEND\nIF P1 > 2 THEN\nG0 X0\nELSE\nG0 Y0\nEND\nM50\nM30\n")
    alphabet = b"GXYZIJKFPMN0123456789.-+*/()=:;% \n"
    for _ in range(8 * scale):
        code = bytearray(base)
        for _ in range(rng.randrange(1, 12)):
            k = rng.randrange(len(code))
            choice = rng.randrange(3)
            if choice == 0:
                del code[k]
            elif choice == 1:
                code.insert(k, rng.choice(alphabet))
            else:
                code[k] = rng.choice(alphabet)
        compile_in_subprocess(run_python, tmp_path, bytes(code))
