"""Drawing a program with matplotlib (``pip install matplotlib``; from a checkout
also ``pip install '.[plot]'``): the programmed path, the tool centre's path after
radius compensation, rapids dashed, the start of every cut, warnings and errors
marked at their lines; X/Y with equal axes. Each sort of line is one matplotlib line
(runs apart at NaN rows), so a program of a million parts draws in seconds.

A program that failed to compile has no parts in the library (GetToolpath gives none
after an error), so it is drawn from a compilation again, without compensation:

- the whole program, when only the compensation failed: every error at its line;
- else the program's text before the first error's line (before the line of an
  error that compiling that text meets in turn, e.g. a loop left open): the moves
  before the error, and the error marked where they end, where the machine stands
  when the failing line begins. An error in another file (a called file, a prefix)
  leaves nothing to draw; the title says which of these the picture is.
"""
from __future__ import annotations

import sys
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from .enums import PartKind
from .errors import Diagnostic

if TYPE_CHECKING:
    from .program import Program
    from .toolpath import Run, Toolpath

PROGRAMMED = "#7f7f7f"
TOOL = "#1f77b4"
RAPID = "#2ca02c"
START = "#ff7f0e"
ERROR = "#d62728"
WARNING = "#bcbd22"

_RETRIES = 8        # compilations of shorter texts, each before the line of the error the last one met


def install_hint() -> str:
    """The command that installs matplotlib for this interpreter (a venv's own pip)."""
    return f"plotting needs matplotlib: {sys.executable} -m pip install matplotlib"


def _pyplot():
    try:
        import matplotlib.pyplot as plt     # without a display matplotlib falls back to Agg
    except ImportError as exc:
        raise ImportError(install_hint()) from exc
    return plt


@dataclass(frozen=True)
class _Drawing:
    """What is drawn of a program: its toolpath (None: nothing), how a failed one was
    compiled again (for the title), and whether it ends where the first error's line
    begins (the error is marked there)."""

    toolpath: Toolpath | None
    note: str = ""
    ends_at_error: bool = False


def plot_program(program: Program, ax=None, step: float = 0.2, title: str | None = None):
    """Draws `program` on `ax` (a new figure when None) and returns the Axes (its
    figure: ``ax.figure``). `step`: the longest arc chord in mm, or 1/2000 of the
    drawing's larger side when that is longer (finer chords than a pixel of a large
    picture only cost time and memory on large programs)."""
    plt = _pyplot()
    if ax is None:
        _, ax = plt.subplots(figsize=(8, 6), layout="constrained")
    drawing = _drawing(program)
    if drawing.toolpath is not None and len(drawing.toolpath):
        draw_toolpath(ax, drawing.toolpath, max(step, _side(drawing.toolpath) / 2000))
        _mark(ax, drawing.toolpath, list(program.errors) + list(program.warnings), drawing.ends_at_error)
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("X [mm]")
    ax.set_ylabel("Y [mm]")
    ax.grid(True, linewidth=0.4, alpha=0.5)
    heading = title or program.name.rsplit("/", 1)[-1]
    if program.errors:
        heading += f" ({len(program.errors)} error{'s' if len(program.errors) > 1 else ''}: "\
                   f"{program.errors[0].text}; {drawing.note})"
    ax.set_title(heading, fontsize=10)
    handles, labels = ax.get_legend_handles_labels()
    if handles:
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, borderaxespad=0)
    return ax


def draw_toolpath(ax, toolpath: Toolpath, step: float = 0.2) -> None:
    """The programmed path (grey), the compensated path when it differs (blue),
    rapids (green, dashed) and the start of every cut after a rapid."""
    records = toolpath.records
    # drawn twice only where the paths differ (G41 with radius 0 is the programmed path)
    compensated = bool(np.any(np.abs(records["tool_end"] - records["end"]) > 1e-9))
    runs = toolpath.polyline(step)
    cuts = [run for run in runs if not run.rapid]
    _line(ax, [run for run in runs if run.rapid], linestyle=(0, (4, 3)), color=RAPID, linewidth=0.9,
          label="rapid")
    _line(ax, cuts, color=PROGRAMMED if compensated else TOOL, linewidth=1.0 if compensated else 1.4,
          label="programmed" if compensated else "cut")
    if cuts:
        starts = np.array([run.points[0] for run in cuts])
        ax.plot(starts[:, 0], starts[:, 1], "o", color=START, markersize=4, label="start of a cut")
    if compensated:
        _line(ax, [run for run in toolpath.polyline(step, tool=True) if not run.rapid], color=TOOL,
              linewidth=1.4, label="tool centre (compensated)")


def _side(toolpath: Toolpath) -> float:
    """The larger side (mm) of the X/Y box of the moves' ends."""
    records = toolpath.records
    ends = records["end"][records["kind"] == PartKind.MOTION][:, :2]
    return float(np.ptp(ends, axis=0).max()) if len(ends) else 0.0


def _line(ax, runs: list[Run], **style) -> None:
    """The runs as one matplotlib line, apart at NaN points."""
    if not runs:
        return
    apart = np.full(1, np.nan)
    x, y = (np.concatenate([piece for run in runs for piece in (run.points[:, axis], apart)][:-1]) for axis in (0, 1))
    ax.plot(x, y, **style)


def _drawing(program: Program) -> _Drawing:
    if program.ok:
        return _Drawing(program.toolpath)
    whole = _compile_again(program, program.compile_args(radius=0.0))
    if whole is not None:
        return _Drawing(whole, "drawn without compensation")
    error = program.errors[0]
    lines = _source_lines(program, error)
    if lines is None:
        return _Drawing(None, f"nothing drawn: the error is in {error.file}")
    line = error.line
    for _ in range(_RETRIES):
        if line <= 1:
            break
        kept = (b"" if lines and isinstance(lines[0], bytes) else "").join(lines[:line - 1])
        before = _compile_again(program, program.compile_args(source=kept, name=program.name, radius=0.0),
                                keep_errors=True)
        if isinstance(before, list):            # the shorter text fails too: before that error's line
            if not before or before[0].line >= line or before[0].file != program.name:
                break
            line = before[0].line
            continue
        if before is not None:
            return _Drawing(before, f"drawn without compensation up to line {line - 1}", ends_at_error=True)
        break
    return _Drawing(None, "nothing drawn before the error")


def _compile_again(program: Program, arguments: dict, keep_errors: bool = False):
    """The toolpath of a compilation with `arguments`; when it fails: its errors
    (keep_errors) or None. None too when it cannot run (no free core, the file gone
    meanwhile): the picture then shows the errors only."""
    from .program import compile as compile_program
    try:
        with compile_program(**arguments) as again:
            if again.ok:
                return again.toolpath
            return list(again.errors) if keep_errors else None
    except Exception:
        return None


def _source_lines(program: Program, error: Diagnostic) -> list[str] | list[bytes] | None:
    """The lines (with their line breaks) of the program's own text, when the error
    is in it, as it was given (a file's and bytes as bytes: the first lines compile as
    they did in the whole); None for an error in another file."""
    source = program.compile_args()["source"]
    if error.file != program.name:
        return None
    try:
        if isinstance(source, bytes):
            text = source
        elif isinstance(source, str) and ("\n" in source or "\r" in source):
            text = source
        else:
            text = Path(source).read_bytes()
    except OSError:
        return None
    return text.splitlines(keepends=True)


def _mark(ax, toolpath: Toolpath, marks: list[Diagnostic], ends_at_error: bool) -> None:
    """A cross at the end of the parts of each diagnostic's line (errors red,
    warnings yellow), annotated with the number; with `ends_at_error` the first
    error's cross is where the drawn moves end."""
    records = toolpath.records
    for k, diagnostic in enumerate(marks):
        if k == 0 and ends_at_error:
            motion = records[records["kind"] == PartKind.MOTION]
            hit = motion[-1:]
        else:
            files = [index for index, name in toolpath.files.items() if name == diagnostic.file]
            hit = records[(records["line"] == diagnostic.line) & np.isin(records["file_index"], files)]
        if len(hit) == 0:
            continue
        colour = ERROR if diagnostic.severity == "error" else WARNING
        x, y = hit["end"][:, 0], hit["end"][:, 1]
        ax.plot(x, y, "x", color=colour, markersize=9, markeredgewidth=2,
                label=f"{diagnostic.severity} {int(diagnostic.number)} (line {diagnostic.line})")
        ax.annotate(f"{int(diagnostic.number)}", (x[-1], y[-1]), textcoords="offset points", xytext=(6, 6),
                    color=colour, fontsize=8)


def save_plot(program: Program, path: str, step: float = 0.2, dpi: int = 150) -> None:
    """Draws `program` into an image file (PNG, SVG, PDF: from the suffix)."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(10, 6), layout="constrained")
    try:
        plot_program(program, ax=ax, step=step)
        fig.savefig(path, dpi=dpi)
    finally:
        plt.close(fig)
