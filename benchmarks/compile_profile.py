"""Where a compile's work goes, counted in instructions (load-independent, unlike wall
time on a shared machine): the README's four rows -- the CAM job and the long cutting
path, radius 0 and radius 0.15 with strategy 0xA0600 -- each compiled once in a fresh
process under callgrind (`--separate-threads=yes`), against the floor (the C program
of compile_benchmark.py that reads the file and converts every number with strtod)
under callgrind too.

    python benchmarks/compile_profile.py [--lines 100000] [--rows cam_r0,long_r015]

Prints, per row and thread of the library, the instructions of the thread in all and
the inclusive instructions of the stage functions that ran on it (millions). Needs
valgrind and callgrind_annotate on PATH. One row takes about a minute at 100,000
lines (valgrind runs the interpreter's start-up as well; it is not counted: only
threads that ran a library stage are printed, and the compiler's thread is counted
from the compile's entry on)."""
import argparse
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import compile_benchmark  # noqa: E402
from cam_job import write_cam_job  # noqa: E402

# the stages, by their C function (Cython's `__pyx_f_9libSF_TCh_` prefix left off),
# in the order they run
STAGES = ("compile_body", "compile_program", "lx_number", "cp_words", "compensate_feed", "_cl_run",
          "compensate_end", "program_merge", "_extent_beside_body", "insert_arcs", "join_lines",
          "_ahead_body", "plan_ahead_end", "plan_beside_extent", "_plan_body", "plan_range", "program_extent",
          "program_number_parts", "_follow_body")
PREFIX = "__pyx_f_9libSF_TCh_"
# the functions a thread of the compile starts in
BODIES = ("compile_body", "_follow_body", "_extent_beside_body", "_ahead_body", "_plan_body")
ROWS = {"cam_r0": ("cam", 0.0, None), "cam_r015": ("cam", 0.15, 0xA0600),
        "long_r0": ("long", 0.0, None), "long_r015": ("long", 0.15, 0xA0600)}


def inclusive(out_file: Path) -> dict:
    """Inclusive instructions of every function of one callgrind thread file."""
    text = subprocess.run(["callgrind_annotate", "--inclusive=yes", "--threshold=100", str(out_file)],
                          check=True, capture_output=True, text=True).stdout
    found = {}
    for line in text.splitlines():
        m = re.match(r"\s*([\d,]+)\s+\(\s*[\d.]+%\)\s+(?:< )?(\S+)", line)
        if m:
            name = m.group(2).split(":")[-1]
            found.setdefault(name, int(m.group(1).replace(",", "")))
    return found


def profile(command: list, workdir: Path, tag: str) -> list:
    """[(thread, {function: inclusive instructions})] of a command under callgrind."""
    base = workdir / f"cg.{tag}"
    subprocess.run(["valgrind", "--tool=callgrind", "--separate-threads=yes", f"--callgrind-out-file={base}"]
                   + command, check=True, capture_output=True)
    files = sorted(workdir.glob(f"cg.{tag}-*")) or [base]
    return [(f.name.rsplit("-", 1)[-1], inclusive(f)) for f in files]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--lines", type=int, default=100_000)
    ap.add_argument("--rows", default=",".join(ROWS), help="of " + ", ".join(ROWS))
    args = ap.parse_args()
    if not shutil.which("valgrind") or not shutil.which("callgrind_annotate"):
        sys.exit("valgrind and callgrind_annotate are needed")
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        programs = {"cam": tmp / "cam_job.nc", "long": tmp / "cutting41.nc"}
        write_cam_job(programs["cam"], args.lines)
        compile_benchmark.write_program(programs["long"], args.lines, head="G41")
        compile_benchmark.floor_times(programs["cam"], tmp, 1)     # builds the floor
        for name in ("cam", "long"):
            threads = profile([str(tmp / "floor"), str(programs[name])], tmp, f"floor-{name}")
            total = max(f.get("main", 0) for _, f in threads)
            print(f"floor, {name}: {total / 1e6:.1f} M instructions (main)")
        for row in args.rows.split(","):
            program, radius, strategy = ROWS[row]
            command = [sys.executable, "-c", compile_benchmark.CHILD, str(programs[program]), str(radius)]
            command += [] if strategy is None else [hex(strategy)]
            print(f"{row} ({programs[program].name}, radius {radius}"
                  f"{'' if strategy is None else f', strategy {strategy:#x}'}), M instructions:")
            for thread, found in profile(command, tmp, row):
                stages = [(s, found[PREFIX + s]) for s in STAGES if PREFIX + s in found]
                if not stages:
                    continue            # the interpreter's own threads
                # a thread file may hold several threads one after the other (valgrind
                # reuses a finished thread's number): their bodies' sum is its total
                body = sum(v for s, v in stages if s in BODIES)
                print(f"  thread {thread}: {body / 1e6:.1f} in all; "
                      + "; ".join(f"{s} {v / 1e6:.1f}" for s, v in stages))


if __name__ == "__main__":
    main()
