"""Command line: ``sf-tch info`` and ``sf-tch demo [PROGRAM]``."""
import argparse
import ctypes
import sys

from . import abi, library_path
from .core import CncError, Core, sample_program
from .library import load


def info(args) -> int:
    lib = load()
    sizes = (ctypes.c_uint32 * 9)()
    lib.ToolChainCore_GetStructuresSize(0, 9, sizes)
    with Core(0) as core:
        cores = core.cores
    print(lib.ToolChainCore_GetVersionString(0).decode())
    print(f"library: {library_path()}")
    print(f"cores:   {cores}")
    print("structures (library / ctypes mirror):")
    for k, name in enumerate(abi.STRUCTURES_SIZE_ORDER, start=1):
        mirror = ctypes.sizeof(abi.STRUCTURES[name])
        flag = "" if mirror == sizes[k] else "   MISMATCH"
        print(f"  {name:<20} {sizes[k]:>5} / {mirror:<5}{flag}")
    return 0


def demo(args) -> int:
    path = args.program or sample_program()
    with Core(args.core) as core:
        core.update_params(calcTime=1, absMode=0 if args.relative else 1)
        p = core.params
        for k in range(8):
            p.correction[k].size = args.radius
        core.params = p
        try:
            core.compile_file(path)
            run = core.simulate()
        except CncError as error:
            print(f"error: {error}", file=sys.stderr)
            return 1
        parts = run.parts
        funcs = parts["m_func"]
        lengths = parts["m_pars"]["N"].astype(float)
        size = core.size_info().m_size
        print(f"program:       {path}")
        print(f"parts:         {len(parts)} motion, {len(run.m_functions)} M functions")
        print(f"cut length:    {lengths[funcs != 0].sum():.3f} mm in {(funcs != 0).sum()} parts")
        print(f"rapid length:  {lengths[funcs == 0].sum():.3f} mm in {(funcs == 0).sum()} parts")
        for title, k in (("programmed", 0), ("compensated", 1)):
            lo, hi = size[k].m_minimalPos, size[k].m_maximalPos
            print(f"box {title + ':':<13} X {lo.x:.3f}..{hi.x:.3f}  Y {lo.y:.3f}..{hi.y:.3f}  Z {lo.z:.3f}..{hi.z:.3f}")
        print(f"run time:      {core.run_time():.2f} s (estimate)")
        for text in run.printed:
            print(f"PRINT:         {text}")
        print("errors:        none")
    return 0


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="sf-tch", description=__doc__)
    sub = parser.add_subparsers(dest="command", required=True)
    sub.add_parser("info", help="version, cores and structure sizes").set_defaults(run=info)
    d = sub.add_parser("demo", help="compile and simulate a program (default: the bundled sample)")
    d.add_argument("program", nargs="?", help="G-code file")
    d.add_argument("--core", type=int, default=0)
    d.add_argument("--relative", action="store_true", help="absMode 0 (relative coordinates)")
    d.add_argument("--radius", type=float, default=1.0, help="tool radius for G41..G48 (default 1 mm)")
    d.set_defaults(run=demo)
    args = parser.parse_args(argv)
    return args.run(args)


if __name__ == "__main__":
    sys.exit(main())
