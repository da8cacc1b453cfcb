"""Drawing a program with matplotlib (the optional extra ``sf-tch[plot]``): the
programmed path, the tool centre's path after radius compensation, rapids dashed,
the start of every cut, warnings and errors marked at their lines; X/Y with equal
axes. A program that failed to compile is drawn as compiled without compensation
(when that succeeds), with its errors marked."""
from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from .errors import Diagnostic

if TYPE_CHECKING:
    from .program import Program
    from .toolpath import Toolpath

PROGRAMMED = "#7f7f7f"
TOOL = "#1f77b4"
RAPID = "#2ca02c"
START = "#ff7f0e"
ERROR = "#d62728"
WARNING = "#bcbd22"


def _pyplot():
    try:
        import matplotlib.pyplot as plt     # without a display matplotlib falls back to Agg
    except ImportError as exc:
        raise ImportError("plotting needs matplotlib: pip install 'sf-tch[plot]'") from exc
    return plt


def plot_program(program: Program, ax=None, step: float = 0.2, title: str | None = None):
    """Draws `program` on `ax` (a new figure when None) and returns the Axes.
    `step`: the longest arc chord in mm."""
    plt = _pyplot()
    if ax is None:
        _, ax = plt.subplots(figsize=(8, 6), layout="constrained")
    toolpath = program.toolpath if program.ok else _uncompensated(program)
    marks = list(program.errors) + list(program.warnings)
    if toolpath is not None:
        draw_toolpath(ax, toolpath, step)
        _mark(ax, toolpath, marks)
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("X [mm]")
    ax.set_ylabel("Y [mm]")
    ax.grid(True, linewidth=0.4, alpha=0.5)
    heading = title or program.name.rsplit("/", 1)[-1]
    if program.errors:
        heading += f" ({len(program.errors)} error{'s' if len(program.errors) > 1 else ''}: "\
                   f"{program.errors[0].text})"
    ax.set_title(heading, fontsize=10)
    handles, labels = ax.get_legend_handles_labels()
    if handles:
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, borderaxespad=0)
    return ax


def draw_toolpath(ax, toolpath: Toolpath, step: float = 0.2) -> None:
    """The programmed path (grey), the compensated path when it differs (blue), rapids (green, dashed) and the start of every cut after a rapid."""
    records = toolpath.records
    # drawn twice only where the paths differ (G41 with radius 0 is the programmed path)
    compensated = bool(np.any(np.abs(records["tool_end"] - records["end"]) > 1e-9))
    labelled = set()

    def label(text: str) -> str | None:
        if text in labelled:
            return None
        labelled.add(text)
        return text

    for run in toolpath.polyline(step):
        x, y = run.points[:, 0], run.points[:, 1]
        if run.rapid:
            ax.plot(x, y, linestyle=(0, (4, 3)), color=RAPID, linewidth=0.9, label=label("rapid"))
        else:
            ax.plot(x, y, color=PROGRAMMED if compensated else TOOL, linewidth=1.0 if compensated else 1.4,
                    label=label("programmed" if compensated else "cut"))
            ax.plot(x[:1], y[:1], "o", color=START, markersize=4, label=label("start of a cut"))
    if compensated:
        for run in toolpath.polyline(step, tool=True):
            if not run.rapid:
                ax.plot(run.points[:, 0], run.points[:, 1], color=TOOL, linewidth=1.4,
                        label=label("tool centre (compensated)"))


def _uncompensated(program: Program) -> Toolpath | None:
    """The toolpath of the failed program compiled again without compensation (the
    first error may be the compensation's); None when that fails too."""
    from .program import compile as compile_program
    try:
        with compile_program(**program.compile_args(radius=0.0)) as again:
            return again.toolpath if again.ok else None
    except Exception:       # no free core, the file gone meanwhile: the picture shows the errors only
        return None


def _mark(ax, toolpath: Toolpath, marks: list[Diagnostic]) -> None:
    """A cross at the end of the parts of each diagnostic's line (errors red,
    warnings yellow), annotated with the number."""
    records = toolpath.records
    for diagnostic in marks:
        files = [k for k, name in toolpath.files.items() if name == diagnostic.file]
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

