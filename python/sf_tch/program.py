"""``sf_tch.compile()``: G-code in, a :class:`Program` out.

    program = sf_tch.compile("part.nc", radius=1.0)
    print(program.errors or "ok", program.run_time)
    path = program.toolpath              # numpy records (sf_tch.toolpath)

The library has three cores. A program takes one for its compile only: before
:func:`compile` returns, its results (toolpath, extents, run time, PRINT texts,
warnings and errors) are copied into Python and the core is given back, so any
number of programs can be alive at once (``[sf_tch.compile(f) for f in files]``).
:meth:`Program.simulate` takes a free core again for its run. ``keep_core=True``
keeps the core instead (for runs on the offline machine through ``program.core``;
then at most three such programs and Cores live at a time, each until it is
closed, its ``with`` block ends or nothing references it any more).
"""
from __future__ import annotations

import gzip
import io
import os
import re
import threading
import warnings
import zlib
from pathlib import Path
from typing import Callable, Iterator, Sequence, Union

import numpy as np

from . import abi
from .core import Core, RunResult, attach_column
from .enums import Callback, ErrorNumber, OutputTab, Regime
from .errors import Cancelled, CncError, Diagnostic, GougeWarning
from .toolpath import TOOLPATH_DTYPE, Toolpath, read_chunks, summarize

Source = Union[str, bytes, os.PathLike]   # (not `|`: CPython 3.9 evaluates it)


# a str that starts like a line of G-code: a G, M or N word, an axis or feed word, a
# parameter assignment, a comment
_LOOKS_LIKE_G_CODE = re.compile(r"\s*(?:[GMN]\s*-?\d|[XYZABCUVWIJKF]\s*[-+]?[\d.(]|P\d+\s*=|[(;%])", re.I)


GZIP_MAGIC = b"\x1f\x8b"
MAX_PROGRAM_BYTES = 1 << 30             # the library's limit of a program file (error 12)


def _gunzip(data: bytes | Path, what: str) -> bytes:
    """The G-code of a gzip-compressed program (LinuxCNC's samples ship as .ngc.gz),
    at most the library's 1 GiB of text."""
    with gzip.open(io.BytesIO(data) if isinstance(data, bytes) else data) as f:
        try:
            text = f.read(MAX_PROGRAM_BYTES + 1)
        except (OSError, EOFError, zlib.error) as e:
            raise OSError(f"{what}: not a readable gzip file ({e})") from None
    if len(text) > MAX_PROGRAM_BYTES:
        raise OSError(f"{what}: more than 1 GiB of G-code once decompressed")
    return text


def _read_source(source: Source, name: str | None) -> tuple[str | bytes | None, Path | None, str]:
    """(text, path, name): text for G-code given as text, path for a file. A str
    with a line break, or bytes, is G-code; any other str or a PathLike is a file
    (a str without a line break is never guessed to be G-code: the message says so).
    Bytes stay bytes: the library gets them as they are (a byte-order mark too). A
    gzip-compressed file or bytes (starting 1F 8B) are decompressed here: the library
    reads text only (its CompileFromFile refuses them with error 26)."""
    if isinstance(source, bytes):
        if source[:2] == GZIP_MAGIC:
            return _gunzip(source, name or "program"), None, name or "program.nc"
        return source, None, name or "program.nc"
    if isinstance(source, str) and ("\n" in source or "\r" in source):
        return source, None, name or "program.nc"
    path = Path(source)
    if not path.exists():
        if isinstance(source, str) and _LOOKS_LIKE_G_CODE.match(source):
            raise FileNotFoundError(f"{source!r}: no such file; G-code given as text needs a line break "
                                    f"(a one-line program: {source + chr(10)!r})")
        raise FileNotFoundError(f"{path}: no such file")
    if path.is_dir():
        raise IsADirectoryError(f"{path}: is a directory, not a G-code file")
    if not path.is_file():
        raise OSError(f"{path}: not a regular file (G-code is read from a regular file, or given as text)")
    if not os.access(path, os.R_OK):
        raise PermissionError(f"{path}: not readable")
    with open(path, "rb") as f:
        compressed = f.read(2) == GZIP_MAGIC
    if compressed:
        return _gunzip(path, str(path)), None, name or str(path)
    return None, path, name or str(path)


def _check_ini(ini: str | os.PathLike) -> None:
    path = Path(ini)
    if not path.exists():
        raise FileNotFoundError(f"{ini}: no such INI file")
    if path.is_dir():
        raise IsADirectoryError(f"{ini}: is a directory, not an INI file")
    if not path.is_file():
        raise OSError(f"{ini}: not a regular file (an INI file is read whole)")


class _Progress:
    """The last percent the library reported and an event set when it changes (the
    job's listener: it holds nothing that holds the core)."""

    def __init__(self):
        self.percent = 0
        self.changed = threading.Event()

    def update(self, percent: int) -> None:
        self.percent = percent
        self.changed.set()


class CompileJob:
    """A compilation running in the library's thread: iterate over it for the
    progress in percent (0..100, each value once), :meth:`cancel` it, or wait for
    its :meth:`result`. Made by :func:`start_compile`."""

    def __init__(self, core: Core, text: str | bytes | None, path: Path | None, name: str,
                 progress: Callable[[int], object] | None = None, cancel=None, arguments: dict | None = None,
                 keep_core: bool = False):
        self.core = core
        self._keep_core = keep_core
        self.name = name
        self._text = text
        self._path = path
        self._lines: list[str] | None = None      # the source's lines, read for the first diagnostic
        self._cancel_event = cancel
        self._progress = _Progress()
        self.warnings: list[Diagnostic] = []
        self.errors: list[Diagnostic] = []
        self._program: Program | None = None
        self._arguments = dict(arguments or {})      # those of start_compile, for compiling again
        self._removers = [
            core.listen(Callback.SET_STATUS_BAR_PROGRESS, self._progress.update),
            core.listen(Callback.MATH_WARNING, self.warnings.append),
            core.listen(Callback.DISP_AND_LOCATE_ERROR, self.errors.append),
        ]
        if progress is not None:
            self._removers.append(core.listen(Callback.SET_STATUS_BAR_PROGRESS, progress))
        if text is not None:
            core.start_compile_text(text, name)
        else:
            core.start_compile_file(path)

    def __repr__(self) -> str:
        return f"<CompileJob {self.name!r} {'done' if self.done() else f'{self._progress.percent} %'}>"

    def done(self) -> bool:
        """True once the library has finished (or given up)."""
        return self.core.lib.ToolChainCore_IsBusy(self.core.index) <= 0

    def cancel(self) -> None:
        """Interrupts the compilation; :meth:`result` then raises :class:`Cancelled`."""
        self.core.cancel()

    def __iter__(self) -> Iterator[int]:
        last = -1
        while True:
            finished = self.done()
            if self._progress.percent != last:
                last = self._progress.percent
                yield last
            if finished:
                return
            if self._cancel_event is not None and self._cancel_event.is_set():
                self.cancel()
            self._progress.changed.wait(0.05)
            self._progress.changed.clear()

    def result(self, timeout: float | None = None) -> Program:
        """Waits for the end and returns the :class:`Program` (errors in its
        ``errors``), its results copied and the core given back unless the job was
        started with ``keep_core=True``. Raises :class:`Cancelled` when it was
        cancelled; Ctrl-C cancels it and is raised."""
        if self._program is None:
            self.core.wait(timeout, cancel=self._cancel_event)
            for remove in self._removers:
                remove()
            last = self.core.last_error()
            if last is not None and last.number == ErrorNumber.CANCELLED:
                raise last
            if last is not None:    # the library's record of it, with the column it keeps
                same = [k for k, e in enumerate(self.errors) if e.number == last.number and e.line == last.line]
                if same:
                    self.errors[same[0]] = last.diagnostic
                else:
                    self.errors.append(last.diagnostic)
            errors = [attach_column(e, self._source_lines(e)) for e in self.errors]
            located = [attach_column(w, self._source_lines(w)) for w in self.warnings]
            program = Program(self.core, self.name, errors, located, self._arguments)
            if not self._keep_core:
                program._copy_results_and_release(self._cancel_event)
            self._program = program
            for warning in located:
                if warning.number == ErrorNumber.COMPENSATION_GOUGE:
                    # the part would be damaged: shown by Python itself, at the G-code line
                    # (strict=True refuses it)
                    warnings.warn_explicit(f"warning {int(warning.number)}: {warning.text}", GougeWarning,
                                           warning.file, warning.line, module="sf_tch")
        return self._program

    def _source_lines(self, diagnostic: Diagnostic) -> list[str] | None:
        """The lines of the source a diagnostic points into (only read when there is
        one), None for another file (a prefix, a called file)."""
        if diagnostic.file != self.name or diagnostic.line <= 0:
            return None
        if self._lines is None:
            text = self._text.decode("latin-1") if isinstance(self._text, bytes) else self._text
            if text is None:
                try:
                    text = self._path.read_text(encoding="latin-1") if self._path else None
                except OSError:
                    return None
            # the library counts columns after a UTF-8 byte-order mark
            for bom in ("\ufeff", "\xef\xbb\xbf"):
                if text is not None and text.startswith(bom):
                    text = text[len(bom):]
            self._lines = text.split("\n") if text is not None else None     # (lines as the library counts them)
        return self._lines


def start_compile(source: Source, radius: float | None = None, strategy: int | None = None,
                  ini: str | os.PathLike | None = None, params: dict | None = None, core: int | None = None,
                  name: str | None = None, progress: Callable[[int], object] | None = None,
                  cancel=None, start: Sequence[float] | None = None, look_ahead: int | None = None,
                  iso: bool | str = False, strict: bool = False, keep_core: bool = False) -> CompileJob:
    """Starts compiling and returns the running :class:`CompileJob`; the arguments
    are those of :func:`compile`. The job holds its core until its :meth:`~CompileJob.result`
    (and with ``keep_core`` its program after that)."""
    if radius is not None and not radius >= 0:
        raise ValueError(f"tool radius must be a number >= 0 mm, not {radius}")
    if iso not in (False, True, "strict"):
        raise ValueError(f"iso must be False, True or 'strict', not {iso!r}")
    if ini is not None:
        _check_ini(ini)
    text, path, name = _read_source(source, name)
    handle = Core(core, ini=str(ini) if ini is not None else None)
    try:
        fields = dict(params or {})
        fields.setdefault("calcTime", 1)
        if iso or strict or "rezerva1" not in fields:
            # the modes are this call's (a core keeps its parameters from one user to the next)
            base = fields.get("rezerva1", handle.params.rezerva1)
            for bit, on in ((abi.GCODE_REZERVA1_ISO_COMPAT, iso), (abi.GCODE_REZERVA1_ISO_STRICT, iso == "strict"),
                            (abi.GCODE_REZERVA1_COMP_STRICT, strict)):
                base = base | bit if on else base & ~bit
            fields["rezerva1"] = base
        if strategy is not None:
            fields["correctionStrategy"] = strategy
        handle.update_params(**fields)
        if radius is not None:
            handle.set_tool_radius(radius)
        if start is not None:
            handle.reset(start)
        if look_ahead is not None:
            handle.set_look_ahead(look_ahead)
        arguments = {"source": source, "radius": radius, "strategy": strategy, "ini": ini, "params": params,
                     "name": name, "start": start, "look_ahead": look_ahead, "iso": iso, "strict": strict}
        return CompileJob(handle, text, path, name, progress, cancel, arguments, keep_core)
    except BaseException:
        handle.close()
        raise


def compile(source: Source, radius: float | None = None, strategy: int | None = None,
            ini: str | os.PathLike | None = None, params: dict | None = None, core: int | None = None,
            name: str | None = None, progress: Callable[[int], object] | None = None,
            cancel=None, start: Sequence[float] | None = None, look_ahead: int | None = None,
            iso: bool | str = False, strict: bool = False, keep_core: bool = False) -> Program:
    """Compiles G-code and returns the :class:`Program`; errors of the G-code are in
    ``program.errors`` (``program.check()`` raises the first).

    - ``source``: a file (path or str without a line break) or G-code text (a str
      with a line break, or bytes: a one-line program is ``"G1 X10 F1000\\n"``);
      ``name`` names text in errors;
    - ``radius``: tool radius in mm for every G41..G48 slot (>= 0; G41/G42 choose
      the side); ``strategy``: correctionStrategy bits (CORR_* of tgm_cnc.h);
    - ``ini``: a vendor INI file instead of the bundled one; ``params``: any other
      GCODE_PARAMETERS fields by name, e.g. ``{"absMode": 0}``;
    - ``core``: the core (0..2) to compile on, default the first free one (NoFreeCoreError
      when none is); ``keep_core``: the program keeps that core after the compile
      (``program.core``, e.g. for a run on the offline machine) instead of giving it
      back with its results copied (the default); ``start``: the machine
      position (x y z ... in axis order, up to 10) the program starts from, default
      where the core's machine stands (set by ResetCNC, or 0);
    - ``iso``: the ISO compatibility mode (G20/G21, ``G4 P`` seconds, G18 as ISO, G43 H
      as a tool length, ... docs/compiler.md), off by default; ``iso="strict"``: the
      mode, and what LinuxCNC refuses (unknown M codes, K on an XY arc, a nested
      comment, ...) is error 414 instead of warning 621;
    - ``strict``: tool radius compensation refuses a tool path that cuts into the
      contour where it cannot remove that part (error 504); by default such a part
      is compiled as its offsets give it, with warning 601 (line, depth in mm), which
      Python also shows as a :class:`GougeWarning` (docs/compensation.md);
    - ``look_ahead``: parts the feed planner looks ahead (0 the vendor's 8, -1
      unlimited; default what the core has, see ToolChainCore_SetLookAhead);
    - ``progress``: called with the percent from the library's thread; ``cancel``:
      an object with ``is_set()`` (threading.Event) that interrupts when set.
    Raises FileNotFoundError / IsADirectoryError / OSError for a bad path (a
    missing one that looks like G-code says it needs a line break), ValueError for
    a negative radius, :class:`Cancelled` when cancelled."""
    job = start_compile(source, radius, strategy, ini, params, core, name, progress, cancel, start, look_ahead, iso,
                        strict, keep_core)
    try:
        return job.result()
    except BaseException:
        job.core.close()
        raise


class Program:
    """A compiled program: ``errors`` and ``warnings`` (:class:`Diagnostic` lists),
    ``toolpath`` (numpy records), ``summary()`` (counts and lengths), ``size_info``
    (GCODE_INFO), ``run_time`` (seconds) and ``printed`` (PRINT texts) of a
    simulation, ``simulate()`` and ``plot()``.

    By default (:func:`compile`) these results are copied into Python before the
    program is returned and its core is given back (``core`` is None): the program
    holds no library resource, and :meth:`simulate` takes a free core for its run.
    With ``keep_core=True`` the program holds its core (``core``) and reads the
    results from it on first use, until :meth:`close`, the end of its ``with`` block
    or the program's end when nothing references it any more."""

    def __init__(self, core: Core, name: str, errors: list[Diagnostic], warnings: list[Diagnostic],
                 arguments: dict | None = None):
        self.core: Core | None = core
        self._arguments = dict(arguments or {})
        self.name = name
        self.errors = errors
        self.warnings = warnings
        self._toolpath: Toolpath | None = None
        self._size_info = None
        self._run_time: float | None = None
        self._run_error: CncError | None = None
        self._printed: list[str] = []

    def __repr__(self) -> str:
        state = f"{len(self.errors)} error(s)" if self.errors else "ok"
        parts = f", {len(self._toolpath)} parts" if self._toolpath is not None else ""
        return f"<Program {self.name!r} {state}, {len(self.warnings)} warning(s){parts}>"

    def __enter__(self) -> Program:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def close(self) -> None:
        """Gives back the core a program compiled with ``keep_core=True`` holds (its
        program in the library is destroyed; what was read from it stays); nothing
        to do otherwise. Safe twice."""
        if self.core is not None:
            self.core.close()

    def _held(self) -> Core:
        """The kept core, to read a result from; RuntimeError once it was given back."""
        if self.core is None or self.core.closed:
            raise RuntimeError(f"the core of {self.name!r} was given back (close()) before this result was read "
                               f"from it")
        return self.core

    def _copy_results_and_release(self, cancel=None) -> None:
        """Copies every result out of the core (toolpath, extents, a simulation's run
        time and PRINT texts, or the simulation's error) and gives the core back."""
        core = self.core
        try:
            if self.ok:
                self._toolpath = core.toolpath()
                self._size_info = core.size_info()
                try:
                    self._simulate_once(cancel)
                except Cancelled:
                    raise
                except CncError as error:       # raised where the run time is asked for, as when kept
                    self._run_error = error
        finally:
            core.close()
            self.core = None

    def compile_args(self, **changes) -> dict:
        """The keyword arguments of :func:`compile` that made this program, with
        `changes` (e.g. ``radius=0.0``): to compile it again on another core."""
        return {**self._arguments, **changes}

    @property
    def ok(self) -> bool:
        """True when the program compiled without error."""
        return not self.errors

    def check(self) -> Program:
        """Raises the first error as :class:`CncError`; returns the program otherwise."""
        if self.errors:
            raise CncError.from_diagnostic(self.errors[0])
        return self

    @property
    def toolpath(self) -> Toolpath:
        """Every part, in order (:class:`~sf_tch.toolpath.Toolpath`, 168 bytes a part);
        empty after an error."""
        if self._toolpath is None:
            if not self.ok:
                return Toolpath(np.empty(0, TOOLPATH_DTYPE))
            self._toolpath = self._held().toolpath()
        return self._toolpath

    def summary(self) -> dict:
        """Counts and lengths (mm) of the parts, cuts and rapids
        (:meth:`Toolpath.to_dict`): from the toolpath; on a kept core before the
        toolpath is read, from the library a chunk at a time (a program of any size
        in a few MB); all zero after an error."""
        if self._toolpath is not None or not self.ok:
            return self.toolpath.to_dict()
        core = self._held()
        return summarize(read_chunks(core.lib, core.index))

    @property
    def size_info(self):
        """GCODE_INFO: m_size[0] programmed, [1] compensated, [2]/[3] as the machine
        runs them (G168 rotations); None after an error."""
        if not self.ok:
            return None
        if self._size_info is None:
            self._size_info = self._held().size_info()
        return self._size_info

    @property
    def run_time(self) -> float | None:
        """Estimated seconds (per-part trapezoids, calcTime) of a simulation run after
        the compile (on a kept core: on first use); None after an error. Raises the
        simulation's error when it failed."""
        self._simulated()
        return self._run_time

    @property
    def printed(self) -> list[str]:
        """The PRINT / M29 texts of that simulation, in order."""
        self._simulated()
        return list(self._printed)

    def _simulated(self) -> None:
        if self._run_error is not None:
            raise self._run_error
        if self._run_time is None and self.ok:
            self._held()
            self._simulate_once()

    def _simulate_once(self, cancel=None) -> None:
        def on_output(tab: int, text: str) -> None:
            if tab == OutputTab.PRINT:
                self._printed.append(text)

        remove = self.core.listen(Callback.ADD_OUTPUT_LOG, on_output)
        try:
            self.core.run(Regime.SIMULATION, cancel=cancel)
        finally:
            remove()
        self._run_time = self.core.run_time()

    def simulate(self, regime: Regime = Regime.SIMULATION) -> RunResult:
        """Runs the program (regime 10, or 20 the test regime: the machine limits) and
        returns every part as the driver callbacks receive it (SIMPLE_GM_PARAMS
        records). On the kept core while it is held, or else on a free core where
        the program is compiled again with :meth:`compile_args` (a file is read
        again) and that core given back after the run."""
        self.check()
        if self.core is not None and not self.core.closed:
            return self.core.simulate(regime)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", GougeWarning)       # shown by the first compile
            again = compile(**self.compile_args(core=None), keep_core=True)
        with again:
            again.check()
            return again.core.simulate(regime)

    def plot(self, ax=None, **options):
        """Draws the program with matplotlib (``pip install matplotlib``) on `ax`, or
        on a new figure; ``view="xy"`` (default), ``"xz"``, ``"yz"`` or ``"3d"``,
        ``step`` (mm), ``title``: see :func:`sf_tch.plot.plot_program`. Cuts at more
        than one depth are coloured by Z with a colour bar. Returns the Axes; in a
        script save its figure (``program.plot().figure.savefig("part.png")``) or
        call ``matplotlib.pyplot.show()``. ImportError without matplotlib, its
        message the command that installs it."""
        from .plot import plot_program
        return plot_program(self, ax=ax, **options)

    def to_dict(self) -> dict:
        """Name, errors, warnings, toolpath summary, extents and run time, as plain types."""
        result = {"program": self.name, "ok": self.ok, "errors": [e.to_dict() for e in self.errors],
                  "warnings": [w.to_dict() for w in self.warnings]}
        if self.ok:
            size = self.size_info.m_size
            result["toolpath"] = self.summary()
            result["extent"] = {title: {"min": [size[k].m_minimalPos.x, size[k].m_minimalPos.y, size[k].m_minimalPos.z],
                                        "max": [size[k].m_maximalPos.x, size[k].m_maximalPos.y, size[k].m_maximalPos.z]}
                                for title, k in (("programmed", 0), ("compensated", 1))}
            result["run_time"] = self.run_time
            result["printed"] = self.printed
        return result
