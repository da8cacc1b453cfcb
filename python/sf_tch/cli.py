"""The command line: ``sf-tch`` or ``python -m sf_tch``.

    sf-tch demo [FILE]            compile, compensate and simulate (default: the bundled sample)
    sf-tch compile FILE           summary, warnings, errors as file:line:col: error N: text
                                  (FILE "-": the G-code on standard input, for every command)
    sf-tch simulate FILE          compile and run the simulation (or --test: machine limits)
    sf-tch run FILE               run it on the offline machine: position, line, feed, progress
    sf-tch plot FILE -o OUT       draw it (PNG, SVG or PDF, from OUT's suffix; --view xy|xz|yz|3d)
    sf-tch info                   version, library, cores, structure sizes
    sf-tch --version

Options of the commands that compile: --radius MM, --strategy BITS, --ini FILE,
--core N, --relative, --iso (the ISO compatibility mode, docs/compiler.md), --strict (tool
radius compensation refuses a tool path that cuts into the contour: error 504 instead of
warning 601, docs/compensation.md), --look-ahead N, --json (one JSON document on stdout
instead of text, also when the command fails: then with ``"ok": false``, ``"error"`` and
``"exit_code"``). Warnings go to stderr as file:line: warning N: text, then their count.

Exit codes: 0 success; 1 the program has errors (compile or run); 2 bad usage (bad
arguments, a missing, unreadable or not regular file, no library); 130 interrupted
(Ctrl-C; ``run`` stops the machine first); 141 stdout closed early (e.g. ``| head``).

Only what a command needs is imported: ``sf-tch --version`` and ``--help`` do not load
numpy (the numpy side is imported by the commands that compile).
"""
from __future__ import annotations

import argparse
import ctypes
import json
import os
import sys
import threading
import time
import warnings
from pathlib import Path
from typing import TYPE_CHECKING, Sequence

import sf_tch

from . import abi, library_path
from .enums import ErrorNumber, Regime, Status
from .errors import Cancelled, CncError, GougeWarning, SfTchError
from .library import load

if TYPE_CHECKING:
    from .program import Program

EXIT_OK, EXIT_PROGRAM_ERRORS, EXIT_USAGE, EXIT_INTERRUPTED, EXIT_BROKEN_PIPE = 0, 1, 2, 130, 141
LARGE_PLOT = 100_000        # parts from which `plot` says on stderr that it is drawing


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


class RunProgress:
    """The offline machine's progress while it runs: on a terminal one live line on
    stderr, redrawn at every call; otherwise a line on stderr each time the run
    passes another tenth of the path, and at least every `every` seconds."""

    def __init__(self, total_length: float, live: bool | None = None, every: float = 10.0):
        self.total = max(total_length, 1e-9)
        self.live = sys.stderr.isatty() if live is None else live
        self.every = every
        self.last_tenth = -1
        self.last_time = -float("inf")

    def line(self, pos, enh, line: int | None = None) -> str:
        """Percent of the path, line (`line` when given, else the GetPos's), position,
        feed and machine time of a GetPos."""
        done = min(100.0, 100.0 * enh.m_actPartsLen / self.total)
        line = pos.m_editorLine if line is None else line
        return (f"run {done:5.1f} %  line {line:<6} X {pos.m_calcS.x:9.3f} Y {pos.m_calcS.y:9.3f} "
                f"Z {pos.m_calcS.z:8.3f}  F {enh.m_actFeed:8.1f}  t {enh.m_cncRunTime:7.2f} s")

    def show(self, pos, enh) -> None:
        """The state while the machine moves."""
        if self.live:
            sys.stderr.write("\r" + self.line(pos, enh) + " ")
            sys.stderr.flush()
            return
        tenth = int(10 * min(1.0, enh.m_actPartsLen / self.total))
        now = time.monotonic()
        if tenth > self.last_tenth or now - self.last_time >= self.every:
            self.last_tenth, self.last_time = tenth, now
            print(self.line(pos, enh), file=sys.stderr, flush=True)

    def finish(self, pos, enh, line: int | None = None) -> None:
        """The state the run ended in, as the last line (100 % at the program's end;
        `line`: the line it ended on, where GetPos no longer names one)."""
        if self.live:
            sys.stderr.write("\r" + self.line(pos, enh, line) + " \n")
        else:
            print(self.line(pos, enh, line), file=sys.stderr)
        sys.stderr.flush()


# ------------------------------------------------------------------ compiling

STDIN = "-"


def _compile(args, path: str) -> Program:
    """Compiles the file `path` ("-": the G-code on standard input) with the
    command's options, a progress bar meanwhile (a missing file, a directory, a
    device or an unreadable file raise OSError: exit 2); its warnings to stderr
    (text output), then how many there are. The program keeps its core: the
    summary reads the toolpath from it a chunk at a time, and simulate and run run
    the program there."""
    from .program import start_compile
    if path == STDIN:
        source, name, title = sys.stdin.buffer.read(), "<stdin>", "standard input"
    else:
        source, name, title = Path(path), None, os.path.basename(path)
    bar = ProgressBar(f"compiling {title}")
    params = {"absMode": 0} if args.relative else None
    try:
        job = start_compile(source, radius=args.radius, strategy=args.strategy, ini=args.ini, params=params,
                            core=args.core, name=name, progress=bar, iso=args.iso, strict=args.strict,
                            look_ahead=args.look_ahead, keep_core=True)
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


def _parts(count: int) -> str:
    return f"{count} part{'' if count == 1 else 's'}"


def _summary(program: Program) -> list[str]:
    """The summary's lines: counts and lengths (read from the library a chunk at a
    time) and the compile's extents; before a run, which moves the machine."""
    info = program.summary()
    size = program.size_info.m_size
    lines = [f"program:       {program.name}",
             f"parts:         {info['moves']} motion, {info['m_functions']} M functions",
             f"cut length:    {info['cut_length']:.3f} mm in {_parts(info['cut_parts'])}",
             f"rapid length:  {info['rapid_length']:.3f} mm in {_parts(info['rapid_parts'])}"]
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


def _print_json(document: dict, code: int) -> int:
    """The command's one JSON document on stdout, with its exit code."""
    print(json.dumps({**document, "exit_code": code}, indent=2))
    return code


def _report(program: Program, args, extra: Sequence[str] = ()) -> int:
    """Prints the program's result (text or JSON); the exit code."""
    code = EXIT_OK if program.ok else EXIT_PROGRAM_ERRORS
    if args.json:
        return _print_json(program.to_dict(), code)
    if not program.ok:
        for error in program.errors:
            print(str(error), file=sys.stderr)
        return code
    for line in _summary(program) + list(extra):
        print(line)
    return code


# ------------------------------------------------------------------ commands

def cmd_compile(args) -> int:
    """``sf-tch compile``: the summary, or the errors."""
    with _compile(args, args.program) as program:
        return _report(program, args)


def cmd_demo(args) -> int:
    """``sf-tch demo``: the summary with run time, PRINT texts and errors (the README's main job)."""
    from .core import sample_program
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


def _report_run(args, document: dict, summary: Sequence[str], run: dict, lines: Sequence[str], error,
                code: int) -> int:
    """Prints a program's run (text or JSON), `document` and `summary` taken from
    the program before the run; its error; returns `code`."""
    if args.json:
        return _print_json({**document, "run": run}, code)
    for line in list(summary) + list(lines):
        print(line)
    if error:
        print(str(error), file=sys.stderr)
    return code


def cmd_simulate(args) -> int:
    """``sf-tch simulate``: compile, run regime 10 (or 20 with --test), report the run."""
    with _compile(args, args.program) as program:
        if not program.ok:
            return _report(program, args)
        document, summary = (program.to_dict(), []) if args.json else ({}, _summary(program))
        try:
            status = program.core.run(Regime.TEST if args.test else Regime.SIMULATION)
            error = None
        except CncError as exc:
            status, error = program.core.status, exc
        _, enh = program.core.position()
        run = {"regime": "test" if args.test else "simulation", **_run_summary(program.core, status, error),
               "cut_parts": enh.m_nWorkCounter, "rapid_parts": enh.m_nG00Counter, "m_functions": enh.m_nMCounter}
        lines = [f"run:           {run['regime']}, status {run['status']} ({run['status_name']})",
                 f"run time:      {run['run_time']:.2f} s (estimate)"]
        return _report_run(args, document, summary, run, lines, error,
                           EXIT_PROGRAM_ERRORS if error else EXIT_OK)


def cmd_run(args) -> int:
    """``sf-tch run``: the offline machine runs the program (StartCNCEx 30) at
    --time-scale times real time, its progress on stderr (a live line on a terminal,
    else a line every tenth of the path). Ctrl-C stops it on the path and exits 130
    once it stands (a second Ctrl-C ends the run at once)."""
    with _compile(args, args.program) as program:
        if not program.ok:
            return _report(program, args)
        core = program.core
        # what the compile gives, before the machine moves: extents, lengths, the planned time
        document = program.to_dict() if args.json else {}
        summary = [] if args.json else _summary(program)
        lengths = program.summary()
        planned = program.run_time
        progress = RunProgress(lengths["cut_length"] + lengths["rapid_length"])
        core.set_time_scale(args.time_scale)
        core.reset()
        core.start(Regime.FORWARD)
        interrupted = False
        try:
            while core.status > 0:
                progress.show(*core.position())
                time.sleep(0.1)
        except KeyboardInterrupt:
            interrupted = True
            core.stop()
            core.wait()
        pos, enh = core.position()
        # at the program's end GetPos names no line (0): the line of its last part
        ended_on = _last_line(core) if pos.m_editorLine == 0 and core.status == Status.AT_END else None
        progress.finish(pos, enh, ended_on)
        error = core.last_error()
        run = {**_run_summary(core, core.status, error), "position": [pos.m_calcS.x, pos.m_calcS.y, pos.m_calcS.z],
               "interrupted": interrupted}
        lines = [f"run:           status {run['status']} ({run['status_name']})"
                 + (", interrupted" if interrupted else ""),
                 f"machine time:  {run['run_time']:.2f} s (planned {planned:.2f} s)"]
        code = EXIT_INTERRUPTED if interrupted else EXIT_PROGRAM_ERRORS if error else EXIT_OK
        if interrupted and not args.json:
            print("sf-tch: interrupted: the machine stopped on the path", file=sys.stderr)
        return _report_run(args, document, summary, run, lines, error, code)


def _last_line(core) -> int:
    """The line of the compiled program's last part (0 without parts)."""
    from .toolpath import TOOLPATH_DTYPE, _read, _total
    total = _total(core.lib, core.index)
    if total == 0:
        return 0
    import numpy as np
    last = np.empty(1, TOOLPATH_DTYPE)
    _read(core.lib, core.index, last, total - 1, total)
    return int(last["line"][0])


def cmd_plot(args) -> int:
    """``sf-tch plot``: draw the program into a PNG, SVG or PDF file."""
    suffix = os.path.splitext(args.output)[1].lower()
    if suffix not in (".png", ".svg", ".pdf"):
        raise UsageError(f"{args.output}: the picture's name must end in .png, .svg or .pdf")
    from .plot import install_hint, save_plot
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        raise UsageError(install_hint()) from None
    with _compile(args, args.program) as program:
        parts = program.summary()["parts"]
        if parts >= LARGE_PLOT and not args.json:
            print(f"drawing {parts:,} parts into {args.output} ...", file=sys.stderr, flush=True)
        save_plot(program, args.output, step=args.step, view=args.view)
        code = EXIT_OK if program.ok else EXIT_PROGRAM_ERRORS
        if args.json:
            return _print_json({**program.to_dict(), "picture": args.output}, code)
        for error in program.errors:
            print(str(error), file=sys.stderr)
        print(f"wrote {args.output}")
        return code


def cmd_info(args) -> int:
    """``sf-tch info``: version, library path, cores, structure sizes (library / mirror)."""
    lib = load()
    sizes = (ctypes.c_uint32 * 9)()
    lib.ToolChainCore_GetStructuresSize(0, 9, sizes)
    structures = {name: {"library": sizes[k], "mirror": ctypes.sizeof(abi.STRUCTURES[name])}
                  for k, name in enumerate(abi.STRUCTURES_SIZE_ORDER, start=1)}
    info = {"version": abi.library_text(lib.ToolChainCore_GetVersionString(0)), "package": sf_tch.__version__,
            "library": library_path(), "cores": abi.TOOL_CHAIN_MAX_CORES, "structures": structures}
    if args.json:
        print(json.dumps(info, indent=2))
        return EXIT_OK
    print(info["version"])
    print(f"package: sf-tch {sf_tch.__version__}")
    print(f"library: {info['library']}")
    print(f"cores:   {info['cores']}")
    print("structures (library / ctypes mirror):")
    for name, both in structures.items():
        flag = "" if both["library"] == both["mirror"] else "   MISMATCH"
        print(f"  {name:<20} {both['library']:>5} / {both['mirror']:<5}{flag}")
    return EXIT_OK


# ------------------------------------------------------------------ parser

class _Version(argparse.Action):
    """--version: the package's version, read only when asked for."""

    def __call__(self, parser, namespace, values, option_string=None):
        print(f"sf-tch {sf_tch.__version__}")
        parser.exit()


class _Parser(argparse.ArgumentParser):
    """argparse raising :class:`UsageError` (main() prints it on one line, or as
    the JSON document, and exits 2) instead of printing the usage block."""

    def error(self, message: str):
        raise UsageError(f"{message} (see {self.prog} --help)")


def parser() -> argparse.ArgumentParser:
    """The argument parser of ``sf-tch``."""
    top = _Parser(prog="sf-tch", description="Compile, simulate and draw G-code with libSF_TCh.",
                                  epilog="Exit codes: 0 ok, 1 errors in the program, 2 bad usage, "
                                         "130 interrupted, 141 output closed.")
    top.add_argument("--version", action=_Version, nargs=0, help="show the package's version and exit")
    sub = top.add_subparsers(dest="command", required=True, metavar="COMMAND", parser_class=_Parser)

    def compiling(name: str, help: str, program_optional: bool = False) -> argparse.ArgumentParser:
        p = sub.add_parser(name, help=help, description=help)
        p.add_argument("program", nargs="?" if program_optional else None, metavar="FILE",
                       help="G-code file, - for standard input")
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
    plot = compiling("plot", "draw a program: programmed and compensated path, rapids dashed, cuts at "
                             "several depths coloured by Z")
    plot.add_argument("-o", "--output", required=True, help="picture file: .png, .svg or .pdf")
    plot.add_argument("--step", type=_radius, default=0.2, help="longest arc chord, mm (default 0.2)")
    plot.add_argument("--view", choices=("xy", "xz", "yz", "3d"), default="xy",
                      help="xy from above (default), xz from the front, yz from the side, 3d in perspective; "
                           "cuts at more than one depth are coloured by Z")
    plot.set_defaults(run=cmd_plot)
    info = sub.add_parser("info", help="version, library, cores and structure sizes",
                          description="Print the library's version string, the package's version, where the "
                                      "library was loaded from, its number of cores, and the size of each "
                                      "ABI structure as the library reports it beside its ctypes mirror "
                                      "(a mismatch is flagged).")
    info.add_argument("--json", action="store_true", help="one JSON document on stdout")
    info.set_defaults(run=cmd_info)
    return top


def main(argv: list[str] | None = None) -> int:
    """Runs the command line; returns the exit code (see the module's docstring)."""
    argv = sys.argv[1:] if argv is None else list(argv)
    as_json = "--json" in argv          # known before the arguments parse: a usage error is a document too
    try:
        args = parser().parse_args(argv)
        code = args.run(args)
        sys.stdout.flush()
        return code
    except (UsageError, SfTchError, OSError, ValueError) as exc:
        if isinstance(exc, BrokenPipeError):
            return _broken_pipe()
        if isinstance(exc, CncError) and not isinstance(exc, Cancelled):
            return _fail(as_json, str(exc), EXIT_PROGRAM_ERRORS, errors=[exc.to_dict()])
        return _fail(as_json, str(exc), EXIT_USAGE)
    except (KeyboardInterrupt, Cancelled):
        return _fail(as_json, "interrupted", EXIT_INTERRUPTED)


def _fail(as_json: bool, message: str, code: int, **fields) -> int:
    """A command that failed before its result: one line on stderr (``sf-tch:``
    first), or with --json the JSON document on stdout; returns the exit code."""
    if as_json:
        return _print_json({"ok": False, "error": message, **fields}, code)
    if code == EXIT_PROGRAM_ERRORS:
        print(message, file=sys.stderr)         # file:line:col: error N: text, as the compiler's errors
    elif code == EXIT_INTERRUPTED:
        print("sf-tch: interrupted", file=sys.stderr)
    else:
        print(f"sf-tch: error: {message}", file=sys.stderr)
    return code


def _broken_pipe() -> int:
    """stdout was closed by the reader: no more output, no traceback at exit."""
    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, sys.stdout.fileno())
    return EXIT_BROKEN_PIPE


if __name__ == "__main__":
    sys.exit(main())
