"""Drawing a program with matplotlib (``pip install matplotlib``; from a checkout
also ``pip install '.[plot]'``): the programmed path, the tool centre's path after
radius compensation, rapids dashed, the start of every cut, warnings and errors
marked at their lines; seen from above (X/Y, the default), from the front (X/Z), from
the side (Y/Z) or in 3D (``view="xy" | "xz" | "yz" | "3d"``), with equal axes. Where
the cuts lie at more than one depth (a 3D program: passes at several Z, ramps, helices)
the cutting path is coloured by its Z with a colour bar (deeper is darker; from above
the deeper passes are drawn over the higher ones); a flat program's cut is blue. Each
sort of line is one matplotlib line (runs apart at NaN rows; a coloured cut one line
per colour), so a program of a million parts draws in seconds.

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

# the views: the axes drawn (0 x, 1 y, 2 z), horizontal first
VIEWS = {"xy": (0, 1), "xz": (0, 2), "yz": (1, 2), "3d": (0, 1, 2)}
_AXIS_NAMES = "XYZ"
DEPTH_COLOURS = 64          # colours of a cut coloured by Z (one matplotlib line each)
DEPTH_MAP = "viridis"       # low Z (deep) dark blue, high Z yellow
_FLAT = 1e-6                # mm: cuts whose Z spans less are one colour


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


def plot_program(program: Program, ax=None, step: float = 0.2, title: str | None = None, view: str = "xy"):
    """Draws `program` on `ax` (a new figure when None) and returns the Axes (its
    figure: ``ax.figure``). `view`: ``"xy"`` from above (default), ``"xz"`` from the
    front, ``"yz"`` from the side, ``"3d"`` in perspective (`ax`, when given, then a
    3D Axes: ``projection="3d"``). `step`: the longest arc chord in mm, or 1/2000 of
    the drawing's larger side when that is longer (finer chords than a pixel of a
    large picture only cost time and memory on large programs)."""
    if view not in VIEWS:
        raise ValueError(f"view must be one of {', '.join(VIEWS)}, not {view!r}")
    plt = _pyplot()
    if ax is None:
        fig = plt.figure(figsize=(8, 6), layout="constrained")
        ax = fig.add_subplot(projection="3d" if view == "3d" else None)
    elif (view == "3d") != (getattr(ax, "name", "") == "3d"):
        needs = "a 3D Axes (projection='3d')" if view == "3d" else "a 2D Axes"
        raise ValueError(f"view {view!r} needs {needs}")
    axes = VIEWS[view]
    drawing = _drawing(program)
    if drawing.toolpath is not None and len(drawing.toolpath):
        draw_toolpath(ax, drawing.toolpath, max(step, _side(drawing.toolpath) / 2000), view=view)
        _mark(ax, drawing.toolpath, list(program.errors) + list(program.warnings), drawing.ends_at_error, axes)
    labels = [f"{_AXIS_NAMES[k]} [mm]" for k in axes]
    ax.set_xlabel(labels[0])
    ax.set_ylabel(labels[1])
    if view == "3d":
        ax.set_zlabel(labels[2])
        ax.set_aspect("equal")
    else:
        ax.set_aspect("equal", adjustable="datalim")
        ax.grid(True, linewidth=0.4, alpha=0.5)
    heading = title or program.name.rsplit("/", 1)[-1]
    if view != "xy":
        heading += f" ({'3D' if view == '3d' else view.upper()} view)"
    if program.errors:
        heading += f" ({len(program.errors)} error{'s' if len(program.errors) > 1 else ''}: "\
                   f"{program.errors[0].text}; {drawing.note})"
    ax.set_title(heading, fontsize=10)
    handles, labels = ax.get_legend_handles_labels()
    if handles:
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0) if view != "3d" else (0.0, 1.0), fontsize=8,
                  borderaxespad=0)
    return ax


def draw_toolpath(ax, toolpath: Toolpath, step: float = 0.2, view: str = "xy") -> None:
    """The programmed path (grey), the compensated path when it differs (blue, or
    coloured by Z with a colour bar when the cuts lie at more than one depth), rapids
    (green, dashed) and the start of every cut after a rapid, in `view`'s axes."""
    axes = VIEWS[view]
    records = toolpath.records
    # drawn twice only where the paths differ (G41 with radius 0 is the programmed path)
    compensated = bool(np.any(np.abs(records["tool_end"] - records["end"]) > 1e-9))
    runs = toolpath.polyline(step)
    cuts = [run for run in runs if not run.rapid]
    tool_cuts = [run for run in toolpath.polyline(step, tool=True) if not run.rapid] if compensated else cuts
    label = "tool centre (compensated)" if compensated else "cut"
    depths = _depth_range(tool_cuts)
    by_depth = depths is not None and depths[1] - depths[0] > _FLAT
    _line(ax, [run for run in runs if run.rapid], axes, linestyle=(0, (4, 3)), color=RAPID, linewidth=0.9,
          label="rapid")
    if compensated:
        _line(ax, cuts, axes, color=PROGRAMMED, linewidth=1.0, label="programmed")
    if by_depth:
        _depth_lines(ax, tool_cuts, depths, axes, view, label, linewidth=1.4)
    else:
        _line(ax, tool_cuts, axes, color=TOOL, linewidth=1.4, label=label)
    if cuts:
        starts = np.array([run.points[0] for run in cuts])
        ax.plot(*(starts[:, k] for k in axes), "o", color=START, markersize=4, label="start of a cut")


def _side(toolpath: Toolpath) -> float:
    """The larger side (mm) of the X/Y box of the moves' ends."""
    records = toolpath.records
    ends = records["end"][records["kind"] == PartKind.MOTION][:, :2]
    return float(np.ptp(ends, axis=0).max()) if len(ends) else 0.0


def _joined(runs: list[Run]) -> np.ndarray:
    """The runs' points one after the other, a NaN row between two runs."""
    apart = np.full((1, 3), np.nan)
    return np.concatenate([piece for run in runs for piece in (run.points, apart)][:-1])


def _line(ax, runs: list[Run], axes: tuple = (0, 1), **style) -> None:
    """The runs as one matplotlib line in the view's axes, apart at NaN points."""
    if not runs:
        return
    points = _joined(runs)
    ax.plot(*(points[:, k] for k in axes), **style)


def _depth_range(runs: list[Run]) -> tuple[float, float] | None:
    """The Z range the colours span: that of the cuts' segments that move in X/Y (a
    plunge or a lift from above the part would spend the colours on air), of every
    point when none does; None without points."""
    if not runs:
        return None
    points = _joined(runs)
    step = np.diff(points, axis=0)
    level = np.hypot(step[:, 0], step[:, 1]) > _FLAT                # False across a gap (NaN)
    z = np.concatenate([points[:-1, 2][level], points[1:, 2][level]]) if level.any() else points[:, 2]
    return float(np.nanmin(z)), float(np.nanmax(z))


def _depth_lines(ax, runs: list[Run], depths: tuple[float, float], axes: tuple, view: str, label: str,
                 **style) -> None:
    """The runs coloured by Z in `depths` (beyond it: the colour of its end): each
    segment gets the colour of its middle's Z among DEPTH_COLOURS, the segments of a
    colour are one line (consecutive ones joined); a colour bar beside; the legend
    shows `label` once. From above the deepest colour is drawn last (on top)."""
    import matplotlib as mpl
    points = _joined(runs)
    middle = 0.5 * (points[:-1, 2] + points[1:, 2])          # NaN for the segments across a gap
    segments = np.flatnonzero(~np.isnan(middle))
    low, high = depths
    norm = mpl.colors.Normalize(low, high, clip=True)
    cmap = mpl.colormaps[DEPTH_MAP]
    colour = np.minimum((np.asarray(norm(middle[segments])) * DEPTH_COLOURS).astype(int), DEPTH_COLOURS - 1)
    order = range(DEPTH_COLOURS - 1, -1, -1) if view == "xy" else range(DEPTH_COLOURS)
    for c in order:
        chosen = segments[colour == c]
        if not len(chosen):
            continue
        # a segment's start point; after the last of consecutive segments its end and a gap
        last = np.r_[np.diff(chosen) != 1, True]
        at = np.arange(len(chosen)) + 2 * (np.cumsum(last) - last)
        index = np.full(len(chosen) + 2 * int(last.sum()), -1)
        index[at] = chosen
        index[at[last] + 1] = chosen[last] + 1
        drawn = np.where(index[:, None] >= 0, points[np.maximum(index, 0)], np.nan)[:-1]
        ax.plot(*(drawn[:, k] for k in axes), color=cmap((c + 0.5) / DEPTH_COLOURS),
                label=f"_depth {low + (c + 0.5) / DEPTH_COLOURS * (high - low):.4f}", **style)
    ax.plot(*([] for _ in axes), color=cmap(0.5), label=f"{label}, coloured by Z", **style)
    bar = ax.figure.colorbar(mpl.cm.ScalarMappable(norm=norm, cmap=cmap), ax=ax, shrink=0.8,
                             pad=0.02 if view != "3d" else 0.1, location="right" if view == "3d" else "bottom")
    bar.set_label("Z [mm] of the cut")


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


def _mark(ax, toolpath: Toolpath, marks: list[Diagnostic], ends_at_error: bool, axes: tuple = (0, 1)) -> None:
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
        coordinates = [hit["end"][:, k] for k in axes]
        ax.plot(*coordinates, "x", color=colour, markersize=9, markeredgewidth=2,
                label=f"{diagnostic.severity} {int(diagnostic.number)} (line {diagnostic.line})")
        if len(axes) == 2:
            x, y = coordinates
            ax.annotate(f"{int(diagnostic.number)}", (x[-1], y[-1]), textcoords="offset points", xytext=(6, 6),
                        color=colour, fontsize=8)


def save_plot(program: Program, path: str, step: float = 0.2, dpi: int = 150, view: str = "xy") -> None:
    """Draws `program` into an image file (PNG, SVG, PDF: from the suffix) in `view`
    (:func:`plot_program`)."""
    plt = _pyplot()
    fig = plt.figure(figsize=(10, 6) if view != "3d" else (10, 8), layout="constrained")
    try:
        ax = fig.add_subplot(projection="3d" if view == "3d" else None)
        plot_program(program, ax=ax, step=step, view=view)
        fig.savefig(path, dpi=dpi)
    finally:
        plt.close(fig)
