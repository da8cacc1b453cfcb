"""Digests of what a compile produces, to keep speed work honest: the records of
ToolChainCore_GetToolpath, the extents (GetGCodeSizeInfo), the run time of a
simulation (the plan's times summed), the warnings and the error, and on the smaller
programs every part the driver callbacks receive (SIMPLE_GM_PARAMS: G-code indexes,
addresses, ...). tests/test_output_identity.py compares them with the digests
recorded in tests/output_digests.json; a change that must not change any output
(a faster compile, less memory) keeps every one of them.

    python tests/output_digest.py [--record] [--corpus DIR] [--only NAME...]

prints the digests of this checkout's installed library (SF_TCH_LIBRARY picks
another), and with --record writes them to tests/output_digests.json.

The cases: the two programs of benchmarks/compile_benchmark.py's rows -- the CAM job
(benchmarks/cam_job.py) and the long cutting path (write_program, "G41" first) of
1,000,000 lines, each with radius 0 and with radius 0.15 and strategy 0xA0600 -- the
long path without G41 (G40, radius 0), the same programs at 30,000 lines with their
driver parts, and, with a corpus of real programs (SF_TCH_CORPUS names its directory),
each of its files in the ISO mode.
"""
import argparse
import gzip
import hashlib
import importlib.util
import json
import math
import os
import random
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
REFERENCE = Path(__file__).resolve().parent / "output_digests.json"
BIG = 1_000_000
SMALL = 30_000
ROWS = (("r0", 0.0, None), ("r0.15_0xA0600", 0.15, 0xA0600))


def _bench(name: str):
    spec = importlib.util.spec_from_file_location(name, ROOT / "benchmarks" / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def write_programs(directory: Path, lines: int) -> dict:
    """{name: path} of the benchmark's programs of `lines` lines."""
    cam = directory / f"cam_job_{lines}.nc"
    _bench("cam_job").write_cam_job(cam, lines)
    long41 = directory / f"long_path41_{lines}.nc"
    long40 = directory / f"long_path40_{lines}.nc"
    bench = _bench("compile_benchmark")
    bench.write_program(long41, lines, head="G41")
    bench.write_program(long40, lines)
    return {"cam_job": cam, "long_path": long41, "long_path_g40": long40}


def write_followers(path: Path, lines: int, seed: int = 7) -> None:
    """A random walk of compensated stretches (G41 / G42 ... G40) whose parts the
    compensation leaves where they sit -- Z moves, M functions, dwells -- between lines
    that often run on in the same direction (joined, tolerance[2]) and tangent arcs."""
    rnd = random.Random(seed)
    out = ["G90 G17 F2000", "G0 X0 Y0 Z0"]
    x = y = z = 0.0
    dx, dy = 1.0, 0.0
    side = 40
    switched = False                        # G41 / G42 / G40 goes on with a line
    while len(out) < lines:
        r = rnd.random()
        if r < 0.04 and not switched:
            side = rnd.choice((40, 41, 42)) if side == 40 else 40
            out.append(f"G{side}")
            switched = True
        elif r < 0.12:
            z += rnd.choice((-1.0, 1.0, -0.5))
            out.append(f"G1 Z{z:.3f}")
            if rnd.random() < 0.5:          # a second one on: a run of followers to join
                z += -0.5 if z > -20 else 0.5
                out.append(f"G1 Z{z:.3f}")
        elif r < 0.16:
            out.append(rnd.choice(("M51", "M50", "M1001", "G4 H0.1")))
        elif r < 0.22 and not switched:
            # a quarter arc turning left (G3) or right (G2), tangent to the last line
            turn = rnd.choice((2, 3))
            rad = rnd.uniform(2, 6)
            nx, ny = (-dy, dx) if turn == 3 else (dy, -dx)
            cx, cy = x + nx * rad, y + ny * rad
            ex, ey = cx + dx * rad, cy + dy * rad
            out.append(f"G{turn} X{ex:.4f} Y{ey:.4f} I{cx - x:.4f} J{cy - y:.4f}")
            x, y = ex, ey
            dx, dy = nx, ny
        else:
            if rnd.random() < 0.3:
                a = rnd.uniform(-2.5, 2.5)
                dx, dy = math.cos(a) * dx - math.sin(a) * dy, math.sin(a) * dx + math.cos(a) * dy
                n = math.hypot(dx, dy)
                dx, dy = dx / n, dy / n
            step = rnd.uniform(1, 10)
            x, y = x + dx * step, y + dy * step
            out.append(f"G1 X{x:.4f} Y{y:.4f}")
            switched = False
    out.append("G40")
    out.append("G1 X0 Y0")
    Path(path).write_text("\n".join(out) + "\n")


def cases(directory: Path | None, corpus: Path | None, only=None) -> list:
    """(name, spec) of every case; spec: what the child compiles and how. The
    benchmark's programs are written into `directory` (None: none of them)."""
    out = []
    for lines, parts in ((BIG, False), (SMALL, True)) if directory is not None else ():
        programs = write_programs(directory, lines)
        for program in ("cam_job", "long_path"):
            for row, radius, strategy in ROWS:
                out.append((f"{program}_{lines}_{row}", dict(path=str(programs[program]), radius=radius,
                                                             strategy=strategy, abs_mode=0, parts=parts)))
        out.append((f"long_path_g40_{lines}_r0", dict(path=str(programs["long_path_g40"]), radius=0.0,
                                                      strategy=None, abs_mode=0, parts=parts)))
        if parts:
            # the plan's window unlimited and deeper than the vendor's 8 (ranges planned apart)
            out.append((f"cam_job_{lines}_r0_window_unlimited", dict(path=str(programs["cam_job"]), radius=0.0,
                                                                     strategy=None, abs_mode=0, parts=True,
                                                                     look_ahead=-1)))
            out.append((f"long_path_{lines}_r0.15_0xA0600_window_64",
                        dict(path=str(programs["long_path"]), radius=0.15, strategy=0xA0600, abs_mode=0,
                             parts=True, look_ahead=64)))
    if directory is not None:
        followers = directory / "followers.nc"
        write_followers(followers, SMALL)
        for radius, strategy in ((0.0, None), (0.5, None), (0.5, 0xA0600)):
            out.append((f"followers_{SMALL}_r{radius}" + (f"_{strategy:#x}" if strategy else ""),
                        dict(path=str(followers), radius=radius, strategy=strategy, abs_mode=None, parts=True)))
    if corpus is not None:
        for path in sorted(corpus.iterdir()):
            if path.name in ("SOURCES.tsv", "rs274.json") or not path.is_file():
                continue
            out.append((f"corpus/{path.name}", dict(path=str(path), radius=None, strategy=None, abs_mode=None,
                                                    parts=True, iso=True)))
    if only:
        out = [(n, s) for n, s in out if any(o in n for o in only)]
    return out


CHILD = r"""
import gzip, hashlib, json, sys
from pathlib import Path
import sf_tch

import numpy as np

def sha(data):
    return hashlib.sha256(data).hexdigest()

def files_ranked(records, field):
    # file indexes as their rank: a library that compiled other files first numbers
    # the same files higher (the tool path is the same)
    out = records.copy()
    if len(out):
        out[field] = np.unique(out[field], return_inverse=True)[1].reshape(-1)
    return out

results = {}
for name, spec in json.loads(sys.stdin.read()):
    path = Path(spec["path"])
    source = gzip.open(path).read() if path.name.endswith(".gz") else path
    params = {"calcTime": 1}
    if spec.get("abs_mode") is not None:
        params["absMode"] = spec["abs_mode"]
    kw = dict(params=params, name=path.name, keep_core=True)
    if spec.get("iso"):
        kw.update(iso=True, start=[0] * 10)
    # every case names its radius and strategy: a core keeps those of its last compile
    kw["radius"] = spec.get("radius") or 0.0
    kw["strategy"] = spec.get("strategy") or 0
    kw["look_ahead"] = spec.get("look_ahead") or 0
    out = {}
    with sf_tch.compile(source, **kw) as program:
        diag = lambda d: [int(d.number), d.line, d.text.replace(str(path.parent), "DIR"), list(d.arguments), d.column]
        out["errors"] = [diag(e) for e in program.errors]
        warnings = sorted(json.dumps(diag(w)) for w in program.warnings)   # two threads warn: any order
        out["warnings"] = len(warnings)
        out["warnings_sha"] = sha("\n".join(warnings).encode())
        if program.ok:
            records = program.toolpath.records
            out["parts"] = len(records)
            out["toolpath_sha"] = sha(files_ranked(records, "file_index").tobytes())
            out["extent_sha"] = sha(bytes(program.size_info))
            out["run_time"] = float(program.run_time).hex()
            if spec.get("parts"):
                run = program.simulate()
                out["driver_parts_sha"] = sha(files_ranked(run.parts, "m_fileIdx").tobytes())
                out["driver_m_sha"] = sha(files_ranked(run.m_functions, "m_fileIdx").tobytes())
                out["printed_sha"] = sha("\n".join(run.printed).encode())
    results[name] = out
print(json.dumps(results))
"""


def digests(case_list: list, env: dict | None = None) -> dict:
    """{name: digest dict}: a child process for each program of a million lines (a
    fresh library, as a host's compile), one for all the others."""
    results = {}
    big = [[c] for c in case_list if f"_{BIG}_" in c[0]]
    small = [c for c in case_list if f"_{BIG}_" not in c[0]]
    for group in big + ([small] if small else []):
        proc = subprocess.run([sys.executable, "-c", CHILD], input=json.dumps(group), capture_output=True,
                              text=True, env=env, timeout=600)
        if proc.returncode != 0:
            raise RuntimeError(f"{group[0][0]}...: the child failed ({proc.returncode}):\n{proc.stderr[-3000:]}")
        results.update(json.loads(proc.stdout.strip().splitlines()[-1]))
    return results


def corpus_dir() -> Path | None:
    """SF_TCH_CORPUS when it names a directory, else None."""
    named = os.environ.get("SF_TCH_CORPUS")
    return Path(named) if named and Path(named).is_dir() else None


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--record", action="store_true", help=f"write the digests to {REFERENCE.name}")
    ap.add_argument("--corpus", help="a corpus directory (default $SF_TCH_CORPUS)")
    ap.add_argument("--only", nargs="*", help="only the cases whose names contain one of these")
    args = ap.parse_args()
    corpus = Path(args.corpus) if args.corpus else corpus_dir()
    with tempfile.TemporaryDirectory() as tmp:
        found = digests(cases(Path(tmp), corpus, args.only))
    if args.record:
        old = json.loads(REFERENCE.read_text()) if REFERENCE.exists() else {}
        old.update(found)
        REFERENCE.write_text(json.dumps(dict(sorted(old.items())), indent=1) + "\n")
    print(json.dumps(found, indent=1))


if __name__ == "__main__":
    main()
