"""The feed planner: look-ahead window depth against the planned run time on dense
short segments, and the planner's cost on a large program.

    python benchmarks/planner_benchmark.py [--lines 1000000] [--runs 5]

Loads the test harness (tests/harness: the library's stages with Python entries, one
of them to compile and plan; here built with -O3 like the library) and
1. plans dense short segments at F6000 (100 mm/s), acc = dec = 500 mm/s^2, trapezoid
   ramps, the angle slow-down off, with windows of 1, 2, 4, 8 (the vendor's), 16, 32,
   64, 256 parts and unlimited: (a) a circle of r 50 mm in 0.05 mm chords (6284 parts,
   0.057 deg between chords), (b) a 100 mm straight line in 0.1 mm pieces (1000 parts);
   prints the planned run time of each;
2. compiles the compile benchmark's cutting program (benchmarks/compile_benchmark.py,
   --lines lines) --runs times in this process and prints the best compile time
   (compiler + G167 arcs), the best planning time (CPU time of the thread), their
   ratio, and the plan's memory per part: the default window, the same with the
   angle slow-down on (tangents at every junction), an unlimited window;
3. plans it as the library does, in two ranges with one in a thread of its own beside
   the extent (pipeline.pyx plan_in_two), and prints the wall time of the extent alone
   and with the plan beside it: what planning adds to the compile.
"""
import argparse
import math
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))
sys.path.insert(0, str(ROOT / "benchmarks"))

import harness  # noqa: E402
from compile_benchmark import write_program  # noqa: E402
from sf_tch import abi  # noqa: E402

WINDOWS = (1, 2, 4, 8, 16, 32, 64, 256, -1)


def circle(radius: float, chord: float) -> str:
    n = int(round(2 * math.pi * radius / chord))
    pts = [(radius * math.cos(2 * math.pi * k / n), radius * math.sin(2 * math.pi * k / n))
           for k in range(n + 1)]
    return (f"G92 X{pts[0][0]:.6f} Y{pts[0][1]:.6f}\nF6000\n"
            + "".join(f"G1 X{x:.6f} Y{y:.6f}\n" for x, y in pts[1:]))


def line(length: float, step: float) -> str:
    n = int(round(length / step))
    return "F6000\n" + "".join(f"G1 X{step * (k + 1):.6f}\n" for k in range(n))


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--lines", type=int, default=1_000_000)
    ap.add_argument("--runs", type=int, default=5)
    args = ap.parse_args()
    ph = harness.load("-O3")
    for name, text in (("circle r50 in 0.05 mm chords", circle(50.0, 0.05)),
                       ("line 100 mm in 0.1 mm pieces", line(100.0, 0.1))):
        print(f"{name}:")
        for w in WINDOWS:
            summary, error, _ = ph.plan_text(text, None, w, 0, False)
            assert error is None, error
            label = "unlimited" if w < 0 else str(w)
            print(f"  window {label:>9}: {summary['run_time']:8.3f} s  ({summary['n_parts']} parts)")
    with tempfile.TemporaryDirectory() as tmp:
        prog = Path(tmp) / "cut.nc"
        write_program(prog, args.lines)
        text = prog.read_text()
    relative = abi.GCODE_PARAMETERS.from_buffer_copy(ph.default_params())
    relative.absMode = 0                    # the program is written relative
    slowing = abi.GCODE_PARAMETERS.from_buffer_copy(relative)
    slowing.startAngle, slowing.endAngle, slowing.minAngleFeed = 30.0, 120.0, 600.0
    for w, settings, what in ((0, relative, ""), (0, slowing, ", angle slow-down on"), (-1, relative, "")):
        compile_s, plan_s = [], []
        for _ in range(args.runs):
            summary, error, timing = ph.plan_text(text, bytes(settings), w, 0, False)
            assert error is None, error
            compile_s.append(timing["compile"])
            plan_s.append(timing["plan"])
        label = "unlimited" if w < 0 else "8 (vendor)"
        print(f"{args.lines} lines, {summary['n_parts']} parts, window {label}{what}: compile best "
              f"{min(compile_s) * 1e3:.0f} ms, planning best {min(plan_s) * 1e3:.0f} ms "
              f"(+{100 * min(plan_s) / min(compile_s):.1f} %), median {sorted(plan_s)[len(plan_s) // 2] * 1e3:.0f} ms; "
              f"plan {summary['plan_bytes'] / summary['n_parts']:.0f} bytes/part; "
              f"run time {summary['run_time']:.1f} s")
    # as the library plans it: in two ranges, one in a thread beside the extent (pipeline.pyx)
    compile_s, extent_s, beside_s = [], [], []
    for _ in range(args.runs):
        summary, error, timing = ph.plan_text(text, bytes(relative), 0, 0, False, summary["n_parts"] // 8 * 3)
        assert error is None, error
        compile_s.append(timing["compile"])
        extent_s.append(timing["extent"])
        beside_s.append(timing["beside"])
    added = [b - e for b, e in zip(beside_s, extent_s)]
    print(f"{args.lines} lines, window 8 (vendor), planned beside the extent (split at part {timing['split']}): "
          f"the extent alone best {min(extent_s) * 1e3:.0f} ms, with the plan beside it best "
          f"{min(beside_s) * 1e3:.0f} ms (median {sorted(beside_s)[len(beside_s) // 2] * 1e3:.0f} ms): "
          f"planning adds {sorted(added)[len(added) // 2] * 1e3:.0f} ms (median; "
          f"+{100 * sorted(added)[len(added) // 2] / min(compile_s):.1f} % of the best compile)")


if __name__ == "__main__":
    main()
