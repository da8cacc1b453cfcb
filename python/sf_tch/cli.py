"""The command line: ``sf-tch`` or ``python -m sf_tch``.

    sf-tch demo [FILE]            compile, compensate and simulate (default: the bundled sample)
    sf-tch compile FILE           summary, warnings, errors as file:line:col: error N: text
    sf-tch simulate FILE          compile and run the simulation (or --test: machine limits)
    sf-tch run FILE               run it on the offline machine: position, line, feed, progress
    sf-tch plot FILE -o OUT       draw it (PNG, SVG or PDF, from OUT's suffix)
    sf-tch info                   version, library, cores, structure sizes
    sf-tch --version

Options of the commands that compile: --radius MM, --strategy BITS, --ini FILE,
--core N, --relative, --iso (the ISO compatibility mode, docs/compiler.md), --strict (tool
radius compensation refuses a tool path that cuts into the contour: error 504 instead of
warning 601, docs/compensation.md), --look-ahead N, --json (one JSON document on stdout
instead of text). Warnings go to stderr as file:line: warning N: text, then their count.

Exit codes: 0 success; 1 the program has errors (compile or run); 2 bad usage (bad
arguments, a missing or unreadable file, no library); 130 interrupted (Ctrl-C);
141 stdout closed early (e.g. ``| head``).
"""
from __future__ import annotations

import argparse
import ctypes
import importlib.util
import json
import os
import sys
import threading
import time
import warnings
from typing import Sequence

from . import __version__, abi, library_path
from .core import sample_program
from .enums import ErrorNumber, Regime
from .errors import Cancelled, CncError, GougeWarning, SfTchError
from .library import load
from .program import Program, start_compile

EXIT_OK, EXIT_PROGRAM_ERRORS, EXIT_USAGE, EXIT_INTERRUPTED, EXIT_BROKEN_PIPE = 0, 1, 2, 130, 141


class UsageError(Exception):
    """A one-line error of the command's arguments or files (exit 2)."""


# ------------------------------------------------------------------ argument types

def _radius(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None
    if not value >= 0 or value == float("inf"):
        raise argparse.ArgumentTypeError(f"must be a radius >= 0 mm, not {text}")
    return value


def _core(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a core number: {text!r}") from None
    if not 0 <= value < abi.TOOL_CHAIN_MAX_CORES:
        raise argparse.ArgumentTypeError(f"core {value} does not exist (0..{abi.TOOL_CHAIN_MAX_CORES - 1})")
    return value


def _look_ahead(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number of parts: {text!r}") from None
    if value < -1:
        raise argparse.ArgumentTypeError(f"must be -1 (unlimited), 0 (the vendor's 8) or more parts, not {value}")
    return value


def _time_scale(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None
    if not 0.0 < value <= 1e6:
        raise argparse.ArgumentTypeError(f"{value:g} is outside (0, 1e6]")
    return value


def _strategy(text: str) -> int:
    try:
        value = int(text, 0)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not an integer (0x.. for hex): {text!r}") from None
    if not 0 <= value <= 0xFFFFFFFF:
        raise argparse.ArgumentTypeError(f"out of the 32-bit range: {text}")
    return value


# ------------------------------------------------------------------ progress

class ProgressBar:
    """A bar on stderr for work longer than half a second, only on a terminal."""

    def __init__(self, title: str, enabled: bool | None = None):
        self.title = title
        self.enabled = sys.stderr.isatty() if enabled is None else enabled
        self.started = time.monotonic()
        self.shown = False
        self.lock = threading.Lock()

    def __call__(self, percent: int) -> None:
        if not self.enabled or time.monotonic() - self.started < 0.5:
            return
        with self.lock:
            filled = percent * 30 // 100
            sys.stderr.write(f"\r{self.title} [{'#' * filled}{' ' * (30 - filled)}] {percent:3d} %")
            sys.stderr.flush()
            self.shown = True

    def close(self) -> None:
        """Clears the bar's line (the summary follows on a clean terminal)."""
        with self.lock:
            if self.shown:
                sys.stderr.write("\r\033[K")
                sys.stderr.flush()
                self.shown = False


# ------------------------------------------------------------------ compiling

def _compile(args, path: str) -> Program:
    """Compiles `path` with the command's options, a progress bar meanwhile (a
    missing file, a directory or an unreadable one raise OSError: exit 2); its
    warnings to stderr (text output), then how many there are."""
    bar = ProgressBar(f"compiling {os.path.basename(path)}")
    params = {"absMode": 0} if args.relative else None
    try:
        job = start_compile(path, radius=args.radius, strategy=args.strategy, ini=args.ini, params=params,
                            core=args.core, progress=bar, iso=args.iso, strict=args.strict,
                            look_ahead=args.look_ahead)
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", GougeWarning)     # printed below, as every warning
                program = job.result()
        except BaseException:
            job.core.close()
            raise
    finally:
        bar.close()
    if not args.json:
        for warning in program.warnings:
            print(str(warning), file=sys.stderr)
        if program.warnings:
            print(_warning_count(program), file=sys.stderr)
    return program


def _summary(program: Program) -> list[str]:
    info = program.toolpath.to_dict()
    size = program.size_info.m_size
    lines = [f"program:       {program.name}",
             f"parts:         {info['moves']} motion, {info['m_functions']} M functions",
             f"cut length:    {info['cut_length']:.3f} mm in {info['cut_parts']} parts",
             f"rapid length:  {info['rapid_length']:.3f} mm in {info['rapid_parts']} parts"]
    for title, k in (("programmed", 0), ("compensated", 1)):
        lo, hi = size[k].m_minimalPos, size[k].m_maximalPos
        lines.append(f"box {title + ':':<13} X {lo.x:.3f}..{hi.x:.3f}  Y {lo.y:.3f}..{hi.y:.3f}  "
                     f"Z {lo.z:.3f}..{hi.z:.3f}")
    return lines


def _warning_count(program: Program) -> str:
    """The summary line after the warnings: how many, and how many gouges (601)."""
    count = len(program.warnings)
    gouges = sum(w.number == ErrorNumber.COMPENSATION_GOUGE for w in program.warnings)
    text = f"sf-tch: {count} warning{'s' if count != 1 else ''}"
    if gouges:
        text += (f", {gouges} where the tool cuts into the contour (warning 601; --strict refuses "
                 f"such a program)")
    return text


def _report(program: Program, args, extra: Sequence[str] = ()) -> int:
    """Prints the program's result (text or JSON); the exit code."""
    if args.json:
        print(json.dumps(program.to_dict(), indent=2))
        return EXIT_OK if program.ok else EXIT_PROGRAM_ERRORS
    if not program.ok:
        for error in program.errors:
            print(str(error), file=sys.stderr)
        return EXIT_PROGRAM_ERRORS
    for line in _summary(program) + list(extra):
        print(line)
    return EXIT_OK


# ------------------------------------------------------------------ commands

def cmd_compile(args) -> int:
    """``sf-tch compile``: the summary, or the errors."""
    with _compile(args, args.program) as program:
        return _report(program, args)


def cmd_demo(args) -> int:
    """``sf-tch demo``: the summary with run time, PRINT texts and errors (the README's main job)."""
    with _compile(args, args.program or sample_program()) as program:
        if args.json or not program.ok:
            return _report(program, args)
        lines = [f"run time:      {program.run_time:.2f} s (estimate)"]
        lines += [f"PRINT:         {text}" for text in program.printed]
        lines.append("errors:        none")
        return _report(program, args, lines)


def _run_summary(core, status, error) -> dict:
    """What a run ended with: status, machine time, lengths, the error."""
    _, enh = core.position()
    return {"status": int(status), "status_name": getattr(status, "name", str(status)),
            "run_time": enh.m_cncRunTime, "cut_length": enh.m_actWorkPartsLen,
            "rapid_length": enh.m_actG00PartsLen, "error": error.to_dict() if error else None}


def _report_run(program: Program, args, run: dict, lines: Sequence[str], error) -> int:
    """Prints a program's run (text or JSON) and its error; the exit code."""
    if args.json:
        print(json.dumps({**program.to_dict(), "run": run}, indent=2))
    else:
        for line in _summary(program) + list(lines):
            print(line)
        if error:
            print(str(error), file=sys.stderr)
    return EXIT_PROGRAM_ERRORS if error else EXIT_OK


def cmd_simulate(args) -> int:
    """``sf-tch simulate``: compile, run regime 10 (or 20 with --test), report the run."""
    with _compile(args, args.program) as program:
        if not program.ok:
            return _report(program, args)
        try:
            status = program.core.run(Regime.TEST if args.test else Regime.SIMULATION)
            error = None
        except CncError as exc:
            status, error = program.core.status, exc
        _, enh = program.core.position()
        run = {"regime": "test" if args.test else "simulation", **_run_summary(program.core, status, error),
               "cut_parts": enh.m_nWorkCounter, "rapid_parts": enh.m_nG00Counter, "m_functions": enh.m_nMCounter}
        return _report_run(program, args, run, [f"run:           {run['regime']}, status {run['status']} "
                                                f"({run['status_name']})",
                                                f"run time:      {run['run_time']:.2f} s (estimate)"], error)


def cmd_run(args) -> int:
    """``sf-tch run``: the offline machine runs the program (StartCNCEx 30) at
    --time-scale times real time; a status line while it moves, Ctrl-C stops it on
    the path (a second Ctrl-C ends the run at once)."""
    with _compile(args, args.program) as program:
        if not program.ok:
            return _report(program, args)
        core = program.core
        total = max(program.toolpath.to_dict()["cut_length"] + program.toolpath.to_dict()["rapid_length"], 1e-9)
        core.set_time_scale(args.time_scale)
        core.reset()
        core.start(Regime.FORWARD)
        live = sys.stderr.isatty() and not args.json
        try:
            while core.status > 0:
                pos, enh = core.position()
                if live:
                    done = 100.0 * enh.m_actPartsLen / total
                    sys.stderr.write(f"\r{done:5.1f} %  line {pos.m_editorLine:<6} X {pos.m_calcS.x:9.3f} "
                                     f"Y {pos.m_calcS.y:9.3f} Z {pos.m_calcS.z:8.3f}  F {enh.m_actFeed:8.1f}  "
                                     f"t {enh.m_cncRunTime:7.2f} s ")
                    sys.stderr.flush()
                time.sleep(0.1)
        except KeyboardInterrupt:
            core.stop()
            core.wait()
        if live:
            sys.stderr.write("\n")
        pos, _ = core.position()
        error = core.last_error()
        run = {**_run_summary(core, core.status, error),
               "position": [pos.m_calcS.x, pos.m_calcS.y, pos.m_calcS.z]}
        return _report_run(program, args, run, [f"run:           status {run['status']} ({run['status_name']})",
                                                f"machine time:  {run['run_time']:.2f} s "
                                                f"(planned {program.run_time:.2f} s)"], error)


def cmd_plot(args) -> int:
    """``sf-tch plot``: draw the program into a PNG, SVG or PDF file."""
    from .plot import save_plot
    suffix = os.path.splitext(args.output)[1].lower()
    if suffix not in (".png", ".svg", ".pdf"):
        raise UsageError(f"{args.output}: the picture's name must end in .png, .svg or .pdf")
    if importlib.util.find_spec("matplotlib") is None:
        raise UsageError("plotting needs matplotlib: pip install 'sf-tch[plot]'")
    with _compile(args, args.program) as program:
        save_plot(program, args.output, step=args.step)
        if args.json:
            print(json.dumps({**program.to_dict(), "picture": args.output}, indent=2))
        else:
            for error in program.errors:
                print(str(error), file=sys.stderr)
            print(f"wrote {args.output}")
        return EXIT_OK if program.ok else EXIT_PROGRAM_ERRORS


def cmd_info(args) -> int:
    """``sf-tch info``: version, library path, cores, structure sizes (library / mirror)."""
    lib = load()
    sizes = (ctypes.c_uint32 * 9)()
    lib.ToolChainCore_GetStructuresSize(0, 9, sizes)
    structures = {name: {"library": sizes[k], "mirror": ctypes.sizeof(abi.STRUCTURES[name])}
                  for k, name in enumerate(abi.STRUCTURES_SIZE_ORDER, start=1)}
    info = {"version": lib.ToolChainCore_GetVersionString(0).decode(), "package": __version__,
            "library": library_path(), "cores": abi.TOOL_CHAIN_MAX_CORES, "structures": structures}
    if args.json:
        print(json.dumps(info, indent=2))
        return EXIT_OK
    print(info["version"])
    print(f"package: sf-tch {__version__}")
    print(f"library: {info['library']}")
    print(f"cores:   {info['cores']}")
    print("structures (library / ctypes mirror):")
    for name, both in structures.items():
        flag = "" if both["library"] == both["mirror"] else "   MISMATCH"
        print(f"  {name:<20} {both['library']:>5} / {both['mirror']:<5}{flag}")
    return EXIT_OK


# ------------------------------------------------------------------ parser

class _Parser(argparse.ArgumentParser):
    """argparse with a one-line error (no usage block) and exit code 2."""

    def error(self, message: str):
        self.exit(EXIT_USAGE, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def parser() -> argparse.ArgumentParser:
    """The argument parser of ``sf-tch``."""
    top = _Parser(prog="sf-tch", description="Compile, simulate and draw G-code with libSF_TCh.",
                                  epilog="Exit codes: 0 ok, 1 errors in the program, 2 bad usage, "
                                         "130 interrupted, 141 output closed.")
    top.add_argument("--version", action="version", version=f"sf-tch {__version__}")
    sub = top.add_subparsers(dest="command", required=True, metavar="COMMAND", parser_class=_Parser)

    def compiling(name: str, help: str, program_optional: bool = False) -> argparse.ArgumentParser:
        p = sub.add_parser(name, help=help, description=help)
        p.add_argument("program", nargs="?" if program_optional else None, metavar="FILE", help="G-code file")
        p.add_argument("--radius", type=_radius, default=1.0, help="tool radius for G41..G48, mm (default 1)")
        p.add_argument("--strategy", type=_strategy, default=None,
                       help="correctionStrategy bits, e.g. 0x80600 (default: the INI's or 0x600)")
        p.add_argument("--ini", default=None, help="vendor INI file (default: the bundled offline one)")
        p.add_argument("--core", type=_core, default=None, help="core 0..2 (default: the first free)")
        p.add_argument("--relative", action="store_true", help="absMode 0 (relative coordinates)")
        p.add_argument("--iso", action="store_true",
                       help="ISO compatibility mode: G20/G21, G4 P seconds, G18 as ISO, G43 H a tool length, ...")
        p.add_argument("--strict", action="store_true",
                       help="compensation refuses a tool path that cuts into the contour (error 504; "
                            "default: warning 601 and the path as its offsets give it)")
        p.add_argument("--look-ahead", type=_look_ahead, default=None, metavar="N",
                       help="parts the feed planner looks ahead: 0 the vendor's 8 (default), -1 unlimited")
        p.add_argument("--json", action="store_true", help="one JSON document on stdout")
        return p

    compiling("demo", "compile, compensate and simulate a program (default: the bundled sample)",
              program_optional=True).set_defaults(run=cmd_demo)
    compiling("compile", "compile a program: summary, warnings, errors").set_defaults(run=cmd_compile)
    simulate = compiling("simulate", "compile a program and run the simulation")
    simulate.add_argument("--test", action="store_true", help="the test regime: check the machine limits")
    simulate.set_defaults(run=cmd_simulate)
    run = compiling("run", "run a program on the offline machine, showing position, line, feed, progress")
    run.add_argument("--time-scale", type=_time_scale, default=1.0, metavar="N",
                     help="run N times faster than real time (default 1)")
    run.set_defaults(run=cmd_run)
    plot = compiling("plot", "draw a program: programmed and compensated path, rapids dashed")
    plot.add_argument("-o", "--output", required=True, help="picture file: .png, .svg or .pdf")
    plot.add_argument("--step", type=_radius, default=0.2, help="longest arc chord, mm (default 0.2)")
    plot.set_defaults(run=cmd_plot)
    info = sub.add_parser("info", help="version, library, cores and structure sizes")
    info.add_argument("--json", action="store_true", help="one JSON document on stdout")
    info.set_defaults(run=cmd_info)
    return top


def main(argv: list[str] | None = None) -> int:
    """Runs the command line; returns the exit code (see the module's docstring)."""
    args = parser().parse_args(argv)
    try:
        code = args.run(args)
        sys.stdout.flush()
        return code
    except (UsageError, SfTchError, OSError, ValueError) as exc:
        if isinstance(exc, BrokenPipeError):
            return _broken_pipe()
        if isinstance(exc, CncError) and not isinstance(exc, Cancelled):
            print(str(exc), file=sys.stderr)
            return EXIT_PROGRAM_ERRORS
        print(f"sf-tch: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except (KeyboardInterrupt, Cancelled):
        print("sf-tch: interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED


def _broken_pipe() -> int:
    """stdout was closed by the reader: no more output, no traceback at exit."""
    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, sys.stdout.fileno())
    return EXIT_BROKEN_PIPE


if __name__ == "__main__":
    sys.exit(main())
