"""The offline machine's cost while three cores run at real time.

    python benchmarks/machine_benchmark.py [--seconds 10] [--period-us 1000]
    python benchmarks/machine_benchmark.py --fast 20000

The second form: one core runs a generated program of --fast parts (lines and arcs
at 6000 mm/min) at time scale 1e6 and prints how many times faster than real time it
ran and its machine time against the plan's (GetGCodeRunTime).

Each of the three cores compiles a generated cutting program (lines and arcs at
3000 mm/min, longer than the measurement) and runs it on the offline machine
(StartCNCEx 30, time scale 1: the 100 us step paced on CLOCK_MONOTONIC). For
--seconds the process's CPU time (user + system, all of the library's threads) is
measured with the host's polling thread asleep between polls, and a polling thread
times ToolChainCore_GetPos on every core each --period-us (time.perf_counter_ns
around the ctypes call). Prints the CPU share of one core (the library's threads from /proc/self/task, and the whole process) and GetPos p50 / p99 / max.
Targets (issue 11): < 5 % of one core for the three machines; GetPos p99 < 20 us.
"""
import argparse
import ctypes
import os
import sys
import tempfile
import time
from pathlib import Path

from sf_tch import abi, library


def cutting_program(lines: int) -> bytes:
    out = ["G0 X0 Y0\n"]
    for i in range(lines // 4):
        x, y = (i * 37) % 900, (i * 53) % 600
        out.append(f"G1 X{x}.5 Y{y}.25 F3000\nG1 X{x + 20}.5\n"
                   f"G2 X{x + 20}.5 Y{y + 10}.25 I0 J5\nG1 X{x}.5\n")
    return "".join(out).encode()


def library_cpu_seconds() -> float:
    """CPU seconds of every thread but the host's main one (/proc/self/task)."""
    ticks = 0
    main_tid = os.getpid()
    for tid in os.listdir("/proc/self/task"):
        if int(tid) == main_tid:
            continue
        try:
            fields = Path(f"/proc/self/task/{tid}/stat").read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        ticks += int(fields[11]) + int(fields[12])      # utime, stime
    return ticks / os.sysconf("SC_CLK_TCK")


def fast_run(parts: int) -> int:
    lib = library.load()
    prog = "G0 X0 Y0\n" + "".join(f"G1 X{(i * 37) % 900}.5 Y{(i * 53) % 600}.25 F6000\n"
                                   f"G2 X{(i * 37) % 900 + 10}.5 Y{(i * 53) % 600}.25 I5 J0\n"
                                   for i in range(parts // 2))
    p = abi.GCODE_PARAMETERS()
    lib.ToolChainCore_GetGCodeParameters(0, ctypes.byref(p))
    p.calcTime = 1
    assert lib.ToolChainCore_SetGCodeParameters(0, ctypes.byref(p)) == 0
    assert lib.ToolChainCore_CompileFromMemory(0, b"fast.nc", prog.encode()) == 0
    while lib.ToolChainCore_StatusCNC(0) == 1:
        time.sleep(0.01)
    assert lib.ToolChainCore_StartCNCEx(0, 10, None) == 0
    while lib.ToolChainCore_StatusCNC(0) == 10:
        time.sleep(0.01)
    planned = lib.ToolChainCore_GetGCodeRunTime(0, lib.ToolChainCore_FileToIdx(0, b"fast.nc"))
    assert lib.ToolChainCore_ResetCNC(0, 1, 0, None) == 0
    assert lib.ToolChainCore_SetTimeScale(0, 1e6) == 0
    wall0, cpu0 = time.monotonic(), time.process_time()
    assert lib.ToolChainCore_StartCNCEx(0, 30, None) == 0
    while lib.ToolChainCore_StatusCNC(0) > 0:
        time.sleep(0.005)
    wall, cpu = time.monotonic() - wall0, time.process_time() - cpu0
    enh = abi.GM_PARAMS_ENHANCED()
    lib.ToolChainCore_GetPos(0, 0, None, ctypes.byref(enh))
    print(f"{parts} parts: status {lib.ToolChainCore_StatusCNC(0)}, machine time {enh.m_cncRunTime:.3f} s, "
          f"planned {planned:.3f} s; {wall:.2f} s wall ({enh.m_cncRunTime / wall:.0f} x real time), "
          f"{cpu:.2f} s CPU of the process")
    lib.ToolChainCore_DestroyCNC(0)
    return 0 if abs(enh.m_cncRunTime - planned) <= 0.005 * planned else 1


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--seconds", type=float, default=10.0)
    ap.add_argument("--period-us", type=float, default=1000.0)
    ap.add_argument("--fast", type=int, default=0, metavar="PARTS",
                    help="instead: run PARTS parts at time scale 1e6")
    args = ap.parse_args()
    if args.fast:
        return fast_run(args.fast)

    lib = library.load()
    ini = Path(tempfile.mkdtemp()) / "cores.ini"
    ini.write_text("[Modules]\nCompiler0=SF_DComp\n[CNC]\nDriver=SF_RTDrv\n")
    cores = range(abi.TOOL_CHAIN_MAX_CORES)
    program = cutting_program(4000)
    for core in cores:
        assert lib.ToolChainCore_LoadFromIni(core, str(ini).encode(), None) == 0
        assert lib.ToolChainCore_CompileFromMemory(core, b"bench.nc", program) == 0
    for core in cores:
        while lib.ToolChainCore_StatusCNC(core) == 1:
            time.sleep(0.01)
        assert lib.ToolChainCore_StatusCNC(core) == -1, "compilation failed"
        assert lib.ToolChainCore_ResetCNC(core, 1, 0, None) == 0
        assert lib.ToolChainCore_StartCNCEx(core, 30, None) == 0
    time.sleep(0.5)                                 # the runs settle
    pos, enh = abi.SIMPLE_GM_PARAMS(), abi.GM_PARAMS_ENHANCED()
    samples = []
    period = args.period_us * 1e-6
    cpu0, lib0, wall0 = os.times(), library_cpu_seconds(), time.monotonic()
    while time.monotonic() - wall0 < args.seconds:
        for core in cores:
            t0 = time.perf_counter_ns()
            lib.ToolChainCore_GetPos(core, 0, ctypes.byref(pos), ctypes.byref(enh))
            samples.append(time.perf_counter_ns() - t0)
        time.sleep(period)
    cpu1, lib1, wall1 = os.times(), library_cpu_seconds(), time.monotonic()
    statuses = [lib.ToolChainCore_StatusCNC(core) for core in cores]
    for core in cores:
        lib.ToolChainCore_DestroyCNC(core)
    cpu = (cpu1.user - cpu0.user + cpu1.system - cpu0.system) / (wall1 - wall0)
    samples.sort()
    q = lambda f: samples[min(len(samples) - 1, int(f * len(samples)))] / 1000.0
    print(f"three machines running (statuses {statuses}) for {wall1 - wall0:.1f} s")
    print(f"library threads' CPU: {100 * (lib1 - lib0) / (wall1 - wall0):.2f} % of one core; "
          f"the whole process {100 * cpu:.2f} % (the host's poller included)")
    print(f"GetPos: p50 {q(0.5):.2f} us, p99 {q(0.99):.2f} us, max {samples[-1] / 1000.0:.1f} us "
          f"({len(samples)} calls)")
    return 0 if all(s == 30 for s in statuses) else 1


if __name__ == "__main__":
    sys.exit(main())
