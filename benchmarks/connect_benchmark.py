"""The connection search of ConnectCNCEx_Plane on a large program: the index's build
time, the nearest-point query time, the lookups, the index's memory.

    python benchmarks/connect_benchmark.py [--lines 1000000] [--queries 2000] [--runs 5]

Loads the test harness (tests/harness: the library's stages with Python entry
points, among them to toolchain/machine/connect_search.pyx; here built with -O3 like
the library), compiles the compile benchmark's cutting program (benchmarks/
compile_benchmark.py, --lines lines, written relative) and
1. builds the index --runs times for the axes X Y (0x3) and X Y Z (0x7), run from
   the compile's start, and for X Y run from another start (every part moved by the
   placement): best and median wall time;
2. asks --queries nearest points (X Y and X Y Z): half uniform over the program's
   box, half within 1 mm of a random part's end; prints the CPU time of the thread
   per query (p50, p99, max) and the largest wall time (the CPU's and the time the
   thread waited for a core); in X Y also restricted to the first half of the parts
   (what a machine has executed);
3. times the lookups that scan the program (line, G-code index, M occurrence) and
   the nearest point without the index (every part evaluated).
Builds and lookups in wall time (CLOCK_MONOTONIC) on a machine shared with others:
the best of the runs is the cost, the median shows the noise.
"""
import argparse
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))
sys.path.insert(0, str(ROOT / "benchmarks"))

import harness  # noqa: E402
from compile_benchmark import write_program  # noqa: E402
from sf_tch import abi  # noqa: E402


def ms(seconds: float) -> str:
    return f"{seconds * 1e3:.1f} ms"


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--lines", type=int, default=1_000_000)
    ap.add_argument("--queries", type=int, default=2000)
    ap.add_argument("--runs", type=int, default=5)
    args = ap.parse_args()
    ch = harness.load("-O3")
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "cut.nc"
        write_program(path, args.lines)
        text = path.read_text()
    params = abi.GCODE_PARAMETERS.from_buffer_copy(ch.default_params())
    params.absMode = 0                      # the program is written relative
    program = ch.compile(text, bytes(params))
    n_parts = program.n_parts
    print(f"{args.lines} lines, {n_parts} parts, compiled (whole pipeline) in {ms(program.compile_seconds)}")

    # the program's box and points near its parts, from a sample of the parts' ends
    rng = np.random.default_rng(1)
    sample = rng.choice(n_parts, size=min(n_parts, 20000), replace=False)
    ends = np.array([program.segment(int(i))["end"][:3] for i in sample])
    lo, hi = ends.min(axis=0), ends.max(axis=0)
    half = args.queries // 2
    points = np.zeros((args.queries, 10))
    points[:half, :3] = rng.uniform(lo, hi, (half, 3))
    picks = ends[rng.integers(len(ends), size=args.queries - half)]
    points[half:, :3] = picks + rng.uniform(-1, 1, picks.shape)
    print(f"box of the program: {np.round(lo, 1).tolist()} .. {np.round(hi, 1).tolist()} mm")

    for label, axes, start, end in (("X Y", 0x3, None, n_parts), ("X Y Z", 0x7, None, n_parts),
                                    ("X Y, run from another start", 0x3, [100.0, -50.0, 5.0], n_parts),
                                    ("X Y, the first half of the parts only", 0x3, None, n_parts // 2)):
        program.place(start if start is not None else [0.0] * 10)
        builds = []
        for _ in range(args.runs):
            rc, err, seconds = program.build_index(axes)
            assert rc == 0, err
            builds.append(seconds)
        query_points = points.copy()
        if start is not None:
            query_points[:, :3] += start
        wall, cpu = (np.array(t) * 1e3 for t in program.nearest_seconds(query_points, 0.0, 0, end))
        print(f"{label}: index build best {ms(min(builds))} (median {ms(statistics.median(builds))}), "
              f"{program.index_bytes() / 2**20:.1f} MB; nearest ({len(cpu)} queries) CPU p50 "
              f"{np.percentile(cpu, 50):.3f} ms, p99 {np.percentile(cpu, 99):.3f} ms, max {cpu.max():.3f} ms; "
              f"wall max {wall.max():.3f} ms")
    program.place([0.0] * 10)

    parts = program.parts()
    last = parts[-1]
    lookups = (
        ("line (the last line: a scan of every part)", lambda: program.line([last["line"]], True)),
        ("G-code index (binary search)", lambda: program.gindex([last["gcode_index"]])),
        ("G-code index that does not exist (binary search, then a scan)", lambda: program.gindex([1])),
        ("M51, n = 0 (the last: a scan back from the end)", lambda: program.mfunc([0, 51])),
        ("M51, n = 1000000 (not found: a scan of every part)", lambda: program.mfunc([1000000, 51])),
        ("nearest without the index (connect_nearest_each, every part, X Y)",
         lambda: program.nearest_each(points[0], 0x3)),
    )
    for label, call in lookups:
        best = float("inf")
        for _ in range(args.runs):
            t0 = time.perf_counter()
            call()
            best = min(best, time.perf_counter() - t0)
        print(f"lookup {label}: best {ms(best)}")


if __name__ == "__main__":
    main()
