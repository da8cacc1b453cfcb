"""Compiler throughput, memory and host responsiveness on a large cutting program,
with and without tool radius compensation.

    python benchmarks/compile_benchmark.py [--lines 1000000] [--runs 7] [--pause 3] [--keep FILE] [--cam-only]

1. Writes a cutting program of --lines lines to a temporary file: parts cut one after
   the other (a contour of lines, tangent and cornered arcs, a notch; N numbers,
   waiting and continuous M functions, comments), a rapid between parts, Z moves.
2. In a fresh Python process: CompileFromFile on core 0 until StatusCNC reads -1,
   while the host thread polls StatusCNC + GetPos every millisecond; reports the
   wall time, the worst poll latency and the peak RSS (VmHWM) of that process.
3. The floor: a tiny C program (compiled now with cc -O2) that reads the same file
   and converts every number with strtod. Prints compile time / floor.
4. The same program under G41 (r = 0.3, a first line "G41"): compile time / floor and
   the extra time over the uncompensated compile.
5. Two compensation stress contours of --lines lines (an outer corner every second
   part; tangent joins only), each compiled with G40 and with G41 in the same run.
6. A CAM job of --lines lines (benchmarks/cam_job.py: ~50,000 short contours on 1M
   lines, each G0 / M51 / G41 / lead-in / contour / G40 / lead-out / M50), with
   radius 0 (G41/G40 in the text, nothing to offset) and with radius 0.15 and strategy
   0xA0600 (loops removed, G1 joins, search depth 2000), against its own floor.
   --cam-only runs this step alone.
7. --rows alone: the README's four rows -- the CAM job and the cutting program with a
   first line "G41", each with radius 0 and with radius 0.15 and strategy 0xA0600 --
   the median against the floor's median of the same file (the compiles of a program
   take turns between its rows), the peak RSS above the process's memory before the
   compile in bytes a line, and the compile's minor page faults (the kernel's count
   for the process: faults taken on the hot path and pages faulted in ahead with
   MADV_POPULATE_WRITE alike) a million lines. --against LIB compiles each row with
   another libSF_TCh.so in turn (an older commit's: the child sets the prototypes of
   the functions that library has).
Every compile runs --runs times and the floor as often: the best counts (this shared VM
backs fresh memory at very different speeds, so single runs vary up to 3x); the
median is printed too. Each compile process starts --pause seconds after the last one
ended: cold, as a host's compile is (on a VM whose balloon reports freed memory to the
host, memory freed less than about 2 s before comes back cheaply, and back-to-back runs
measure that instead; benchmarks/fresh_memory.py).
Targets: compile <= 1.5 x floor, peak RSS < 300 MB; with compensation the compile may
exceed its target by at most 20 %: <= 1.8 x floor. The CAM job: radius 0 <= 1.3 x
floor, radius 0.15 <= 1.6 x floor (medians), peak RSS <= 150 MB. On a VM whose balloon reports free
pages to the host the figures swing from round to round (benchmarks/fresh_memory.py).
"""
from __future__ import annotations

import argparse
import json
import statistics
import os
import random
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

FLOOR_C = r"""
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
int main(int argc, char **argv) {
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    FILE *f = fopen(argv[1], "rb");
    if (!f) return 1;
    fseek(f, 0, SEEK_END); long n = ftell(f); fseek(f, 0, SEEK_SET);
    char *buf = malloc(n + 1);
    if (fread(buf, 1, n, f) != (size_t)n) return 2;
    buf[n] = 0; fclose(f);
    double sum = 0; long count = 0;
    char *p = buf, *end;
    while (*p) {
        if ((*p >= '0' && *p <= '9') || *p == '.' || *p == '-') {
            double v = strtod(p, &end);
            if (end == p) { p++; continue; }
            sum += v; count++; p = end;
        } else p++;
    }
    clock_gettime(CLOCK_MONOTONIC, &t1);
    printf("%.6f %ld %g\n", (t1.tv_sec - t0.tv_sec) + (t1.tv_nsec - t0.tv_nsec) * 1e-9, count, sum);
    free(buf);
    return 0;
}
"""

CHILD = r"""
import ctypes, json, resource, sys, time, threading
from sf_tch import abi, library_path

def status_mb(key):
    # this process's own memory (ru_maxrss would still hold the parent's from before exec)
    for line in open("/proc/self/status"):
        if line.startswith(key + ":"):
            return int(line.split()[1]) / 1024

# the prototypes of the functions the library has (SF_TCH_LIBRARY may name an older one)
lib = ctypes.CDLL(library_path())
for name, restype, argtypes in abi.FUNCTIONS:
    if hasattr(lib, name):
        getattr(lib, name).restype = restype
        getattr(lib, name).argtypes = argtypes
path = sys.argv[1].encode()
p = abi.GCODE_PARAMETERS()
lib.ToolChainCore_GetGCodeParameters(0, ctypes.byref(p))
p.absMode = 0
p.correction[0].size = float(sys.argv[2]) if len(sys.argv) > 2 else 0.0
if len(sys.argv) > 3:
    p.correctionStrategy = int(sys.argv[3], 0)
lib.ToolChainCore_SetGCodeParameters(0, ctypes.byref(p))
pos, enh = abi.SIMPLE_GM_PARAMS(), abi.GM_PARAMS_ENHANCED()
rss0 = status_mb("VmRSS")
faults0 = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
t0 = time.perf_counter()
assert lib.ToolChainCore_CompileFromFile(0, path) == 0
worst = 0.0
polls = 0
while True:
    a = time.perf_counter()
    st = lib.ToolChainCore_StatusCNC(0)
    lib.ToolChainCore_GetPos(0, 0, ctypes.byref(pos), ctypes.byref(enh))
    b = time.perf_counter()
    worst = max(worst, b - a)
    polls += 1
    if st == -1:
        break
    time.sleep(0.001)
t1 = time.perf_counter()
faults = resource.getrusage(resource.RUSAGE_SELF).ru_minflt - faults0
info = abi.CALLBACK_INFO()
err = lib.ToolChainCore_GetLastError(0, ctypes.byref(info))
rss = status_mb("VmHWM")
print(json.dumps({"seconds": t1 - t0, "worst_poll_ms": worst * 1e3, "polls": polls,
                  "peak_rss_mb": rss, "rss_before_mb": rss0, "minor_faults": faults,
                  "error": (info.m_fullError or b"").decode() if err == 1 else None}))
lib.ToolChainCore_DestroyCNC(0)
"""


def write_program(path: Path, lines: int, seed: int = 1, head: str = "") -> None:
    """Parts cut one after the other, written relative (absMode 0). Each part is a
    closed contour run clockwise (a kerf on the left, G41, lies outside): up the left
    side, a tangent quarter arc, the top with a half-round notch (two outer corners),
    a slanted side (an outer corner) and the bottom (an outer corner); then a rapid to
    the next part and Z moves."""
    rnd = random.Random(seed)
    out = [head] if head else []
    n = 0
    while n < lines:
        h = round(rnd.uniform(2, 20), 3)
        r = round(rnd.uniform(1, 5), 3)
        a = round(rnd.uniform(3, 30), 3)
        # the notch (a half circle of radius q below the top) stays inside the part
        q = round(min(rnd.uniform(1, 4), 0.45 * (h + r)), 3)
        b = round(rnd.uniform(1, 10), 3)
        block = [
            f"N{n * 10} G1 X0 Y{h} F{rnd.randint(500, 3000)}",
            f"G2 X{r} Y{r} I{r} J0",
            f"G1 X{a} Y0 M1001",
            "; contour step",
            f"G3 X{2 * q:.3f} Y0 I{q} J0",
            f"G1 X{b} Y{-(h + r):.3f}",
            f"G1 X{-(r + a + 2 * q + b):.3f} Y0",
            f"G0 X{round(rnd.uniform(-5, 5), 3)} Y{round(rnd.uniform(-5, 5), 3)} (rapid to the next part)",
            "M51",
            f"G1 Z-{r}",
            f"G1 Z{r}",
        ]
        for line in block:
            if n >= lines:
                break
            out.append(line)
            n += 1
    path.write_text("\n".join(out) + "\n")


CORNER_BLOCK = ["G1 X2 Y0 F2000", "G3 X2 Y0 I1 J0", "G1 X1 Y1", "G1 X1 Y-1", "G2 X2 Y0 I1 J0",
                "G1 X1.5 Y0.5", "G1 X1.5 Y-0.5", "G1 X2 Y0"]
# a staircase of lines and quarter arcs joined tangentially: no corner needs an arc
TANGENT_BLOCK = ["G1 X2 Y0 F2000", "G3 X1 Y1 I0 J1", "G1 X0 Y2", "G2 X1 Y1 I1 J0"]


def write_contour(path: Path, lines: int, compensated: bool, block: list) -> None:
    """A long compensatable contour (relative coordinates) repeating `block`, under
    G41 (or G40 for the reference)."""
    out = ["G41" if compensated else "G40", "G1 X1 Y0 F2000"]
    while len(out) < lines - 2:
        out.extend(block)
    out = out[:lines - 2] + ["G40", "G1 X1 Y0"]
    path.write_text("\n".join(out) + "\n")


def median(results: list) -> float:
    return statistics.median(r["seconds"] for r in results)


PAUSE = 3.0     # s before each compile process (--pause)


def compile_runs(prog: Path, runs: int, radius: float = 0.0, strategy: int | None = None,
                 library: str | None = None) -> list:
    """Each compile in a fresh process, PAUSE seconds after the last one (cold);
    `library`: another libSF_TCh.so (SF_TCH_LIBRARY)."""
    results = []
    extra = [] if strategy is None else [hex(strategy)]
    env = None if library is None else dict(os.environ, SF_TCH_LIBRARY=library)
    for _ in range(runs):
        time.sleep(PAUSE)
        res = subprocess.run([sys.executable, "-c", CHILD, str(prog), str(radius)] + extra, check=True,
                             capture_output=True, text=True, env=env)
        results.append(json.loads(res.stdout.strip().splitlines()[-1]))
    return results


def floor_times(path: Path, workdir: Path, runs: int) -> list:
    """The floor's seconds in `runs` processes (the C program is compiled once)."""
    cc = shutil.which("cc") or shutil.which("gcc")
    src = workdir / "floor.c"
    exe = workdir / "floor"
    if not exe.exists():
        src.write_text(FLOOR_C)
        subprocess.run([cc, "-O2", str(src), "-o", str(exe)], check=True)
    return [float(subprocess.run([str(exe), str(path)], check=True, capture_output=True, text=True).stdout.split()[0])
            for _ in range(runs)]


def cam_rows(tmp: Path, lines: int, runs: int) -> None:
    """Step 6: the CAM job of many short contours, radius 0 and 0.15 (0xA0600)."""
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    from cam_job import write_cam_job
    job = tmp / "cam_job.nc"
    contours = write_cam_job(job, lines)
    floor = floor_times(job, tmp, runs)
    f_best, f_med = min(floor), statistics.median(floor)
    print(f"CAM job: {lines} lines, {contours} contours, {job.stat().st_size / 1e6:.1f} MB; "
          f"floor {f_best * 1e3:.1f} ms best, {f_med * 1e3:.1f} ms median")
    for title, radius, strategy, target in (("radius 0", 0.0, None, 1.3), ("radius 0.15, 0xA0600", 0.15, 0xA0600, 1.6)):
        results = compile_runs(job, runs, radius, strategy)
        assert all(r["error"] is None for r in results), results
        times = sorted(r["seconds"] for r in results)
        rss = [r["peak_rss_mb"] for r in results]
        print(f"CAM job {title}: {min(times) * 1e3:.1f} ms best, {median(results) * 1e3:.1f} ms median "
              f"({', '.join(f'{t * 1e3:.0f}' for t in times)}); / floor: {min(times) / f_best:.2f} best, "
              f"{median(results) / f_med:.2f} median (target <= {target}); peak RSS {min(rss):.1f}-{max(rss):.1f} MB "
              f"(target <= 150)")


ROWS = (("radius 0", 0.0, None), ("radius 0.15, 0xA0600", 0.15, 0xA0600))


def four_rows(tmp: Path, lines: int, runs: int, against: str | None = None) -> None:
    """--rows: the README's four rows, the CAM job and the long cutting path ("G41"
    first), each with radius 0 and with radius 0.15 and strategy 0xA0600: the median
    of `runs` cold processes against the floor's median of the same file in the same
    run, the peak RSS above the process's memory before the compile in bytes a line,
    and the compile's minor page faults a million lines. A program's compiles take
    turns between its rows (and with --against between the libraries), so the VM's
    hour weighs on all alike."""
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    from cam_job import write_cam_job
    cam = tmp / "cam_job.nc"
    write_cam_job(cam, lines)
    cutting = tmp / "cutting41.nc"
    write_program(cutting, lines, head="G41")
    libraries = [("", None)] + ([(f" [{against}]", against)] if against else [])
    print(f"{time.strftime('%Y-%m-%d %H:%M')}, load average {os.getloadavg()[0]:.2f} "
          f"{os.getloadavg()[1]:.2f} {os.getloadavg()[2]:.2f}; {runs} cold processes {PAUSE:g} s apart per row")
    for title, prog in (("CAM job", cam), ("long path", cutting)):
        n_lines = prog.read_bytes().count(b"\n")
        floor = floor_times(prog, tmp, runs)
        f_med = statistics.median(floor)
        print(f"{title}: {n_lines} lines, {prog.stat().st_size / 1e6:.1f} MB; floor median {f_med * 1e3:.1f} ms "
              f"(best {min(floor) * 1e3:.1f})")
        results = {}
        for _ in range(runs):
            for tag, library in libraries:
                for row, radius, strategy in ROWS:
                    r = compile_runs(prog, 1, radius, strategy, library)[0]
                    assert r["error"] is None, r
                    results.setdefault((tag, row), []).append(r)
        for tag, _ in libraries:
            for row, _, _ in ROWS:
                rs = results[(tag, row)]
                med = median(rs)
                above = statistics.median((r["peak_rss_mb"] - r["rss_before_mb"]) * 2 ** 20 / n_lines for r in rs)
                faults = statistics.median(r.get("minor_faults", 0) for r in rs) * 1e6 / n_lines
                print(f"  {title}, {row}{tag}: median {med * 1e3:.1f} ms / floor {med / f_med:.2f} "
                      f"(best {min(r['seconds'] for r in rs) / min(floor):.2f}; "
                      f"{', '.join(f'{t * 1e3:.0f}' for t in sorted(r['seconds'] for r in rs))} ms); "
                      f"peak RSS {statistics.median(r['peak_rss_mb'] for r in rs):.1f} MB, {above:.0f} bytes a line "
                      f"above the process's {rs[0]['rss_before_mb']:.1f} MB; {faults:,.0f} minor faults a million lines")


def main():
    global PAUSE
    ap = argparse.ArgumentParser()
    ap.add_argument("--lines", type=int, default=1_000_000)
    ap.add_argument("--runs", type=int, default=7)
    ap.add_argument("--keep", help="also copy the generated program here")
    ap.add_argument("--cam-only", action="store_true", help="only the CAM job of many contours (step 6)")
    ap.add_argument("--rows", action="store_true",
                    help="only the README's four rows: the CAM job and the long path, radius 0 and 0.15 + 0xA0600")
    ap.add_argument("--against", help="with --rows: another libSF_TCh.so compiled in turn with this one")
    ap.add_argument("--pause", type=float, default=PAUSE, help="seconds before each compile process (cold)")
    args = ap.parse_args()
    PAUSE = args.pause
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        if args.cam_only:
            cam_rows(tmp, args.lines, args.runs)
            return
        if args.rows:
            four_rows(tmp, args.lines, args.runs, args.against)
            return
        prog = tmp / "cutting.nc"
        write_program(prog, args.lines)
        if args.keep:
            shutil.copy(prog, args.keep)
        size_mb = prog.stat().st_size / 1e6
        floor = min(floor_times(prog, tmp, args.runs))
        runs = compile_runs(prog, args.runs)
        best = min(runs, key=lambda r: r["seconds"])
        print(f"program: {args.lines} lines, {size_mb:.1f} MB")
        sys.path.insert(0, str(Path(__file__).resolve().parent))
        from fresh_memory import balloon_reports_free_pages
        if balloon_reports_free_pages():
            # freed memory goes back to the host: runs that get it cold are slower (docs/benchmarks.md)
            print("note: this VM's balloon reports free pages to the host; check the rounds with "
                  "benchmarks/fresh_memory.py")
        print(f"floor (read + strtod every number, C -O2): {floor * 1e3:.1f} ms")
        for r in runs:
            print(f"compile to status -1: {r['seconds'] * 1e3:.1f} ms, peak RSS {r['peak_rss_mb']:.1f} MB "
                  f"(before {r['rss_before_mb']:.1f} MB), worst StatusCNC+GetPos poll {r['worst_poll_ms']:.3f} ms "
                  f"over {r['polls']} polls, error: {r['error']}")
        print(f"ratio compile/floor (best run): {best['seconds'] / floor:.2f} (target <= 1.5); "
              f"median run {median(runs) / floor:.2f}")
        print(f"peak RSS (best run): {best['peak_rss_mb']:.1f} MB (target < 300)")
        # the same program with tool radius compensation (G41, r = 0.3)
        prog41 = tmp / "cutting41.nc"
        write_program(prog41, args.lines, head="G41")
        runs41 = compile_runs(prog41, args.runs, 0.3)
        assert all(r["error"] is None for r in runs41), runs41
        best41 = min(runs41, key=lambda r: r["seconds"])
        times41 = ", ".join(f"{r['seconds'] * 1e3:.1f}" for r in runs41)
        print(f"with G41 r=0.3: compile {times41} ms, "
              f"peak RSS {best41['peak_rss_mb']:.1f} MB; ratio compile/floor (best run) "
              f"{best41['seconds'] / floor:.2f} (target <= 1.5 x 1.2 = 1.8), median run {median(runs41) / floor:.2f}, "
              f"{100 * (best41['seconds'] / best['seconds'] - 1):.0f} % over the uncompensated compile")
        # stress: long contours, G40 against G41 (r = 0.3)
        for title, block in (("corner contour (an outer corner every 2nd part)", CORNER_BLOCK),
                             ("tangent contour (no inserted parts)", TANGENT_BLOCK)):
            times = {}
            for compensated in (False, True):
                contour = tmp / f"contour{int(compensated)}.nc"
                write_contour(contour, args.lines, compensated, block)
                results = compile_runs(contour, args.runs, 0.3)
                assert all(r["error"] is None for r in results), results
                times[compensated] = min(r["seconds"] for r in results)
            print(f"{title}, {args.lines} lines: G40 {times[False] * 1e3:.1f} ms, G41 r=0.3 "
                  f"{times[True] * 1e3:.1f} ms, compensation cost {100 * (times[True] / times[False] - 1):.0f} %")
        cam_rows(tmp, args.lines, args.runs)

if __name__ == "__main__":
    main()
