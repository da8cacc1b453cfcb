"""Latency of the polling calls while the three cores work.

    python benchmarks/getpos_latency.py [--lines 200000] [--seconds 10] [--period-us 200]

Three host threads each compile a generated cutting program of --lines lines
(CompileFromMemory, lines and arcs) on their own core and simulate it (regime 10, no
driver callbacks: the simulation runs at the library's speed), again and again. A
polling thread calls ToolChainCore_GetPos and ToolChainCore_StatusCNC on every core
each --period-us and times every call (time.perf_counter_ns around the ctypes call:
the figures include ctypes' own cost, measured alone as the "empty call" row on an
idle core before the load starts). Prints p50 / p99 / max per call.
Target (issue 9): GetPos p99 < 20 us.
"""
import argparse
import ctypes
import statistics
import sys
import tempfile
import threading
import time
from pathlib import Path

from sf_tch import abi, library


def cutting_program(lines: int) -> bytes:
    out = []
    for i in range(lines // 4):
        x, y = (i * 37) % 900, (i * 53) % 600
        out.append(f"G0 X{x}.5 Y{y}.25\nG1 X{x + 20}.5 F3000\n"
                   f"G2 X{x + 20}.5 Y{y + 10}.25 I0 J5\nG1 X{x}.5\n")
    return "".join(out).encode()


def percentile(sorted_ns, q):
    return sorted_ns[min(len(sorted_ns) - 1, int(q * len(sorted_ns)))] / 1000.0


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--lines", type=int, default=200_000)
    ap.add_argument("--seconds", type=float, default=10.0)
    ap.add_argument("--period-us", type=float, default=200.0)
    args = ap.parse_args()

    lib = library.load()
    ini = Path(tempfile.mkdtemp()) / "cores.ini"
    ini.write_text("[Modules]\nCompiler0=SF_DComp\n[CNC]\nDriver=SF_RTDrv\n")
    cores = range(abi.TOOL_CHAIN_MAX_CORES)
    for core in cores:
        assert lib.ToolChainCore_LoadFromIni(core, str(ini).encode(), None) == 0
    program = cutting_program(args.lines)
    pos, enh = abi.SIMPLE_GM_PARAMS(), abi.GM_PARAMS_ENHANCED()

    def timed(call, n):
        samples = []
        for _ in range(n):
            t0 = time.perf_counter_ns()
            call()
            samples.append(time.perf_counter_ns() - t0)
        return samples

    empty = timed(lambda: lib.ToolChainCore_StatusCNC(0), 20000)

    stop = threading.Event()
    done = {"compilations": 0, "simulations": 0}

    def work(core):
        while not stop.is_set():
            assert lib.ToolChainCore_CompileFromMemory(core, b"load.nc", program) == 0
            while lib.ToolChainCore_StatusCNC(core) == 1 and not stop.is_set():
                time.sleep(0.002)
            if lib.ToolChainCore_StatusCNC(core) != -1:
                continue
            done["compilations"] += 1
            lib.ToolChainCore_ResetCNC(core, 1, 0, None)
            if lib.ToolChainCore_StartCNCEx(core, abi.RUN_SIMULATION, None) == 0:
                while lib.ToolChainCore_StatusCNC(core) == 10 and not stop.is_set():
                    time.sleep(0.002)
                done["simulations"] += 1

    workers = [threading.Thread(target=work, args=(core,)) for core in cores]
    for t in workers:
        t.start()
    getpos, status = [], []
    period = args.period_us / 1e6
    deadline = time.monotonic() + args.seconds
    while time.monotonic() < deadline:
        for core in cores:
            t0 = time.perf_counter_ns()
            lib.ToolChainCore_GetPos(core, 0, ctypes.byref(pos), ctypes.byref(enh))
            t1 = time.perf_counter_ns()
            lib.ToolChainCore_StatusCNC(core)
            t2 = time.perf_counter_ns()
            getpos.append(t1 - t0)
            status.append(t2 - t1)
        time.sleep(period)
    stop.set()
    for t in workers:
        t.join()
    for core in cores:
        lib.ToolChainCore_DestroyCNC(core)

    print(f"{args.lines} lines ({len(program) / 1e6:.1f} MB) on {len(cores)} cores for {args.seconds:.0f} s: "
          f"{done['compilations']} compilations, {done['simulations']} simulations")
    print(f"{'call':<34}{'calls':>9}{'p50 us':>10}{'p99 us':>10}{'max us':>10}")
    for name, samples in (("empty call (StatusCNC, idle)", empty), ("GetPos under load", getpos),
                          ("StatusCNC under load", status)):
        ordered = sorted(samples)
        print(f"{name:<34}{len(ordered):>9}{statistics.median(ordered) / 1000:>10.2f}"
              f"{percentile(ordered, 0.99):>10.2f}{ordered[-1] / 1000:>10.1f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
