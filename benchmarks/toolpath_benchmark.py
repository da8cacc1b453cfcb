"""The toolpath of a large program into numpy: time and peak memory of the process.

    python benchmarks/toolpath_benchmark.py [--lines 1000000] [--runs 5] [--radius 0]

Writes the cutting program of compile_benchmark.py (--lines lines, relative
coordinates), then in a fresh Python process per run: ``sf_tch.compile(path)``
(timed, keeping its core), ``program.toolpath`` (ToolChainCore_GetToolpath into a numpy structured
array, timed), and the process's peak RSS (VmHWM) at the end; the memory before the
compile is printed beside it. The best and the median of the runs.
Targets: the toolpath in < 1 s after the compile, < 400 MB peak for the whole process.
"""
import argparse
import json
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from compile_benchmark import write_program  # noqa: E402

CHILD = r"""
import ctypes, json, sys, time
import sf_tch
from sf_tch import abi

def status_mb(key):
    for line in open("/proc/self/status"):
        if line.startswith(key + ":"):
            return int(line.split()[1]) / 1024

before = status_mb("VmRSS")
t0 = time.perf_counter()
with sf_tch.compile(sys.argv[1], radius=float(sys.argv[2]), params={"absMode": 0}, keep_core=True) as program:
    t1 = time.perf_counter()
    program.check()
    path = program.toolpath
    t2 = time.perf_counter()
    summary = path.to_dict()
    # the library's copy alone: again into the same, now resident, array
    out = path.records.ctypes.data_as(ctypes.POINTER(abi.TC_TOOLPATH_RECORD))
    t3 = time.perf_counter()
    program.core.lib.ToolChainCore_GetToolpath(program.core.index, out, len(path), 0, None)
    t4 = time.perf_counter()
print(json.dumps({"compile_s": t1 - t0, "toolpath_s": t2 - t1, "copy_only_s": t4 - t3, "parts": len(path),
                  "cut_length": summary["cut_length"], "array_mb": path.records.nbytes / 2**20,
                  "rss_before_mb": before, "peak_rss_mb": status_mb("VmHWM")}))
"""


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--lines", type=int, default=1_000_000)
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--radius", type=float, default=0.0, help="tool radius (the program has no G41: 0)")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="sf_tch_toolpath_") as tmp:
        program = Path(tmp) / "program.nc"
        write_program(program, args.lines)
        size = program.stat().st_size
        runs = []
        for _ in range(args.runs):
            out = subprocess.run([sys.executable, "-c", CHILD, str(program), str(args.radius)],
                                 capture_output=True, text=True, check=True).stdout
            runs.append(json.loads(out))
            print(json.dumps(runs[-1]))
    first = runs[0]
    print(f"program: {args.lines} lines, {size / 1e6:.1f} MB; "
          f"{first['parts']} parts, array {first['array_mb']:.0f} MB")
    for key, unit in (("compile_s", "s"), ("toolpath_s", "s"), ("copy_only_s", "s"), ("peak_rss_mb", "MB"),
                      ("rss_before_mb", "MB")):
        values = [r[key] for r in runs]
        print(f"{key:<14} best {min(values):8.3f} {unit}   median {statistics.median(values):8.3f} {unit}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
