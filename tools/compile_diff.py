"""Compares what two builds of the library make of the same random G-code: every
program's result (`Program.to_dict()`: ok, errors and warnings with their numbers,
lines, columns and texts) and, where it compiled, the digests of its toolpath records
and its extents (GetGCodeSizeInfo).
Speed work on the compiler must change none of it; tests/test_output_identity.py
holds fixed programs, this draws new ones (lines of G words and addresses, numbers
in every form the lexer reads and some it refuses, comments, a few statements),
mostly valid, with radius compensation on a third of them, a quarter in the ISO mode.

    python tools/compile_diff.py --against OTHER_LIB [--seed 1] [--programs 3000]

This checkout's installed library (SF_TCH_LIBRARY picks another) against OTHER_LIB;
exits 1 and shows the first programs whose results differ.
"""
from __future__ import annotations

import argparse
import json
import os
import random
import subprocess
import sys
import tempfile

# the child: compiles each program with one library, one line of JSON per program list
CHILD = r"""
import hashlib, json, sys
from sf_tch.program import compile
results = []
for text, radius, iso in json.load(open(sys.argv[1])):
    kw = {"params": {"absMode": 1}, "start": [0.0] * 10, "iso": iso}
    if radius:
        kw["radius"] = radius
    with compile(text, **kw) as program:
        made = program.toolpath.records.tobytes() + bytes(program.size_info) if program.ok else b""
        results.append([json.dumps(program.to_dict(), sort_keys=True, default=str),
                        hashlib.sha1(made).hexdigest()])
print(json.dumps(results))
"""

# numbers the lexer must refuse or read the long way, and words and statements around them
ODD_NUMBERS = ["1.2.3", "12345678901234567890.5", "123456789012345678", "9007199254740993",
               "0.1234567890123456789012345", "1e5", "--1", "1+2", "2*3", "(1)", "1/2", "10-", "-", "",
               " 7", "  -8.25", "1 + 2", "3//4", "999999999999999999999999", "007", "-007.700", "[1]", "#1",
               "1..2", "5.", "+1", "1^2", "7%3", "-.5", ".5", "-0"]
ANY_LETTER = ["X", "Y", "Z", "F", "S", "T", "I", "J", "R", "x", "y", "G", "M", "N", "P", "L", "E", "A", "FP",
              "FF", "O"]
G_WORDS = ["G0", "G1", "G01", "G2", "G3", "G4", "G17", "G90", "G91", "G41", "G42", "G40", "G1.5", "g1", "G 1",
           "G80", "G0", "G1", "G1", "G2", "G3",
           # modal groups beside the moves (planes, feed modes, offsets, rotation, arcs, strategy)
           "G18", "G19", "G94", "G95", "G96", "G97", "G92", "G54", "G55", "G168", "G169", "G167", "G172", "G173",
           "G21", "G24", "G43", "G25", "G29", "G900"]
EXTRAS = ["(comment)", "; tail", "(unclosed", "%", "  ", "\t", "IF 1", "END", "label:", "GOTO label", "M30",
          "M2", "N10", "REM x", 'PRINT "a"', "&1"]


def random_line(rng: random.Random) -> str:
    """One line: maybe a G word, up to four addresses (7 % of them odd), rarely a
    comment or a statement, joined by spaces, tabs or nothing."""
    words = [rng.choice(G_WORDS)] if rng.random() < 0.7 else []
    for _ in range(rng.randint(0, 4)):
        if rng.random() < 0.93:
            value = rng.choice(["%d", "%.1f", "%.3f", "%.4f", "%.6f", "%.0f."]) % rng.uniform(0, 500)
            words.append(rng.choice("XYXYZFIJ") + rng.choice(["", "-"]) + value)
        else:
            words.append(rng.choice(ANY_LETTER) + rng.choice(ODD_NUMBERS))
    if rng.random() < 0.05:
        words.append(rng.choice(EXTRAS))
    return rng.choice([" ", "", "  ", "\t"]).join(words)


def random_programs(seed: int, count: int) -> list:
    """[text, radius, ISO mode] of `count` programs of 1..8 random lines after a first
    move; one in four in the ISO mode."""
    rng = random.Random(seed)
    return [["\n".join(["G1 X0 Y0 F1000"] + [random_line(rng) for _ in range(rng.randint(1, 8))]) + "\n",
             rng.choice([0.0, 0.0, 0.2]), rng.random() < 0.25] for _ in range(count)]


def results_of(library: str | None, path: str) -> list:
    """Each program's [result, digest of records and extents] compiled by `library`
    (None: this one)."""
    env = dict(os.environ)
    if library is not None:
        env["SF_TCH_LIBRARY"] = library
    proc = subprocess.run([sys.executable, "-c", CHILD, path], capture_output=True, text=True, env=env,
                          timeout=3600)
    if proc.returncode != 0:
        sys.exit(f"compile_diff: the child failed ({library or 'this library'}):\n{proc.stderr[-3000:]}")
    return json.loads(proc.stdout.strip().splitlines()[-1])


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--against", required=True, help="the other libSF_TCh.so")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--programs", type=int, default=3000)
    args = ap.parse_args()
    programs = random_programs(args.seed, args.programs)
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "programs.json")
        with open(path, "w") as f:
            json.dump(programs, f)
        ours, theirs = results_of(None, path), results_of(args.against, path)
    differ = [k for k in range(len(programs)) if ours[k] != theirs[k]]
    failed = sum(1 for result, _ in ours if not json.loads(result)["ok"])
    print(f"compile_diff: {len(programs)} programs (seed {args.seed}), {failed} end in an error, "
          f"{len(differ)} differ")
    for k in differ[:5]:
        print(f"--- program {k} (radius {programs[k][1]}{', ISO mode' if programs[k][2] else ''}):\n{programs[k][0]}"
              f"this library:  {ours[k]}\nthe other one: {theirs[k]}")
    return 1 if differ else 0


if __name__ == "__main__":
    sys.exit(main())
