"""Program.plot(): the picture of the bundled sample (programmed and compensated
paths, dashed rapids, starts, errors) and its extent against the library's size
info; a PNG that is not empty; a failing program drawn up to its error; the hint
that installs matplotlib; cuts at several depths coloured by Z with a colour bar;
the views from above, the front, the side and in 3D."""
import builtins
import math
import re
import sys

import pytest

import sf_tch

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")
import matplotlib.image  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from sf_tch.plot import save_plot  # noqa: E402

ORIGIN = (0.0, 0.0, 0.0)        # the sample's first rapid starts at the machine's zero


def _lines(ax):
    return {line.get_label(): line for line in ax.get_lines() if not line.get_label().startswith("_")}


def test_plot_of_the_compensated_sample_has_the_librarys_extent():
    with sf_tch.compile(sf_tch.sample_program(), radius=1.0, start=ORIGIN) as program:
        size = program.size_info.m_size
        fig, ax = plt.subplots()
        try:
            assert program.plot(ax=ax, step=0.05) is ax
            limits = ax.dataLim
            labels = _lines(ax)
        finally:
            plt.close(fig)
    # the sample's helical holes go from Z0 to Z-1: the tool centre is coloured by Z
    assert set(labels) == {"rapid", "programmed", "start of a cut", "tool centre (compensated), coloured by Z"}
    assert labels["rapid"].get_linestyle() == "--"
    # everything drawn lies inside the programmed and compensated boxes, and reaches their edges
    lo = min(size[0].m_minimalPos.x, size[1].m_minimalPos.x), min(size[0].m_minimalPos.y, size[1].m_minimalPos.y)
    hi = max(size[0].m_maximalPos.x, size[1].m_maximalPos.x), max(size[0].m_maximalPos.y, size[1].m_maximalPos.y)
    sag = 0.05 ** 2 / 8
    assert (limits.x0, limits.y0) == pytest.approx(lo, abs=sag) and (limits.x1, limits.y1) == pytest.approx(hi, abs=sag)
    assert (lo, hi) == ((-1.0, -8.0), (121.0, 81.0))
    assert ax.get_aspect() == 1.0


def test_errors_are_marked_at_their_line():
    with sf_tch.compile(sf_tch.sample_program(), radius=6.0, start=ORIGIN) as program:
        assert not program.ok
        fig, ax = plt.subplots()
        try:
            program.plot(ax=ax)
            labels = _lines(ax)
            title = ax.get_title()
        finally:
            plt.close(fig)
    mark = labels["error 503 (line 34)"]
    assert list(zip(mark.get_xdata(), mark.get_ydata())) == [(80.0, 45.0)]    # N270 G3 X80 Y45
    assert "Arc radius 5 smaller than the tool radius 6" in title and "drawn without compensation" in title
    assert "cut, coloured by Z" in labels                                          # drawn uncompensated
    assert not any(label.startswith("tool centre") for label in labels)


def _drawn_points(ax, label):
    line = _lines(ax)[label]
    xy = np.column_stack([line.get_xdata(), line.get_ydata()])
    return xy[~np.isnan(xy).any(axis=1)]


@pytest.mark.parametrize("given_as", ["text", "file", "bytes"])
def test_a_failing_program_draws_the_moves_before_its_error(tmp_path, given_as):
    # line 4: the centre (13, 10) is 3 mm from the start and 7 mm from the end: error 400
    code = "G0 X0 Y0 Z0\nG1 X10 F600\nG1 Y10\nG2 X20 Y10 I3 J0\nG1 X30\nM30\n"
    # a file and bytes as an editor writes them: a byte-order mark, a Latin-1 comment
    raw = b"\xef\xbb\xbf" + code.replace("\n", " (\xb0)\n", 1).encode("latin-1")
    source = {"text": code, "file": tmp_path / "arc.nc", "bytes": raw}[given_as]
    if given_as == "file":
        source.write_bytes(raw)
    with sf_tch.compile(source, name=None if given_as == "file" else "arc.nc", start=ORIGIN) as program:
        (error,) = program.errors
        fig, ax = plt.subplots()
        try:
            program.plot(ax=ax)
            cut = _drawn_points(ax, "cut")
            mark = _lines(ax)[f"error {int(error.number)} (line 4)"]
            title = ax.get_title()
        finally:
            plt.close(fig)
    assert error.line == 4
    # the moves of lines 2 and 3, nothing of the arc or after it; the cross where they end
    assert cut.tolist() == [[0, 0], [10, 0], [10, 10]]
    assert list(zip(mark.get_xdata(), mark.get_ydata())) == [(10.0, 10.0)]
    assert "drawn without compensation up to line 3" in title


def test_an_error_inside_a_loop_draws_what_compiles_before_the_loop():
    # the division by zero is in the loop's second pass; the text before its line leaves
    # the FOR open, so the picture is of the text before the FOR
    code = ("G0 X0 Y0 Z0\nG1 X5 F600\nFOR P1 = 1 TO 3\n  G1 X(P1 * 10)\n  G1 Y(10 / (P1 - 2))\nEND\nM30\n")
    with sf_tch.compile(code, name="loop.nc", start=ORIGIN) as program:
        assert program.errors[0].line == 5
        fig, ax = plt.subplots()
        try:
            program.plot(ax=ax)
            cut = _drawn_points(ax, "cut")
            title = ax.get_title()
        finally:
            plt.close(fig)
    assert cut.tolist() == [[0, 0], [5, 0]] and "up to line 2" in title


def test_arcs_are_drawn_no_finer_than_the_picture_shows():
    # a drawing 1000 mm wide: a circle of r 50 asked for in 0.01 mm chords is drawn in
    # chords of 1/2000 of that (0.5 mm), then the line
    with sf_tch.compile("G0 X0 Y0 Z0\nG2 X0 Y0 I50 J0 F1000\nG1 X1000\nM30\n", start=ORIGIN) as program:
        fig, ax = plt.subplots()
        try:
            program.plot(ax=ax, step=0.01)
            cut = _drawn_points(ax, "cut")
        finally:
            plt.close(fig)
    circle = cut[:-1]
    assert len(circle) == 1 + math.ceil(2 * math.pi * 50 / 0.5)
    assert np.allclose(np.hypot(circle[:, 0] - 50, circle[:, 1]), 50) and cut[-1].tolist() == [1000, 0]


def test_plot_hint_names_the_install_command(monkeypatch):
    real_import = builtins.__import__

    def no_matplotlib(name, *args, **kwargs):
        if name.startswith("matplotlib"):
            raise ImportError(f"No module named {name!r}")
        return real_import(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", no_matplotlib)
    with sf_tch.compile("G1 X1 F100\n") as program:
        with pytest.raises(ImportError, match=re.escape(f"{sys.executable} -m pip install matplotlib")):
            program.plot()


def test_png_is_not_empty(tmp_path):
    out = tmp_path / "sample.png"
    with sf_tch.compile(sf_tch.sample_program(), radius=1.0, start=ORIGIN) as program:
        save_plot(program, str(out))
    pixels = matplotlib.image.imread(out)
    assert pixels.shape[0] > 500 and pixels.shape[1] > 500
    drawn = np.any(pixels[:, :, :3] < 0.9, axis=2).mean()
    assert 0.02 < drawn < 0.5


TERRACES = "".join(["G0 X0 Y0 Z5\n"] + [f"G1 Z{z} F300\nG1 X30 F1000\nG1 Y20\nG1 X0\nG1 Y0\n" for z in (-1, -2, -3)]
                   + ["G0 Z5\nM30\n"])


def _depth_lines(ax):
    """The lines of a cut coloured by Z: {Z of the colour: line}, in drawing order."""
    return {float(line.get_label().split()[1]): line for line in ax.get_lines()
            if line.get_label().startswith("_depth ")}


def test_cuts_at_several_depths_are_coloured_by_z_with_a_colour_bar():
    with sf_tch.compile(TERRACES, start=ORIGIN) as program:
        fig, ax = plt.subplots()
        try:
            program.plot(ax=ax)
            depth = _depth_lines(ax)
            labels = _lines(ax)
            bars = [other for other in fig.axes if other is not ax]
            colour_bar = bars[0].get_xlabel() if bars else None
        finally:
            plt.close(fig)
    assert set(labels) == {"rapid", "cut, coloured by Z", "start of a cut"}
    assert labels["rapid"].get_linestyle() == "--"
    assert colour_bar == "Z [mm] of the cut"
    # the colours span the passes' Z (-3..-1; the plunge from Z5 takes the top colour), one per pass
    by_pass = {}
    for z, line in depth.items():
        ys = line.get_ydata()
        if np.nanmax(ys) - np.nanmin(ys) == 20:                   # a whole pass round the rectangle
            by_pass[round(z)] = matplotlib.colors.to_hex(line.get_color())
    assert sorted(by_pass) == [-3, -2, -1] and len(set(by_pass.values())) == 3
    assert min(depth) == pytest.approx(-3, abs=0.05) and max(depth) == pytest.approx(-1, abs=0.05)
    # from above the deepest pass is drawn last, over the others
    assert list(depth) == sorted(depth, reverse=True)


def test_a_flat_program_is_one_colour_without_a_colour_bar():
    with sf_tch.compile("G0 X0 Y0 Z0\nG1 X10 F600\nG1 Y10\nM30\n", start=ORIGIN) as program:
        fig, ax = plt.subplots()
        try:
            program.plot(ax=ax)
            labels = _lines(ax)
            axes = len(fig.axes)
            depth = _depth_lines(ax)
        finally:
            plt.close(fig)
    assert "cut" in labels and not depth and axes == 1


@pytest.mark.parametrize("view, names", [("xy", "XY"), ("xz", "XZ"), ("yz", "YZ"), ("3d", "XYZ")])
def test_views_draw_their_axes(view, names):
    with sf_tch.compile(TERRACES, start=ORIGIN) as program:
        ax = program.plot(view=view)
        try:
            labels = [ax.get_xlabel(), ax.get_ylabel()] + ([ax.get_zlabel()] if view == "3d" else [])
            start = _lines(ax)["start of a cut"]
            drawn = (list(start.get_data_3d()[k] for k in range(3)) if view == "3d"
                     else [start.get_xdata(), start.get_ydata()])
            title = ax.get_title()
        finally:
            plt.close(ax.figure)
    assert labels == [f"{name} [mm]" for name in names]
    # the start of the first cut (X0 Y0 Z5) in the view's coordinates
    assert [float(values[0]) for values in drawn] == [{"X": 0.0, "Y": 0.0, "Z": 5.0}[name] for name in names]
    assert (view.upper() if view != "3d" else "3D") in title or view == "xy"


def test_a_view_needs_its_kind_of_axes():
    with sf_tch.compile(TERRACES, start=ORIGIN) as program:
        fig, ax = plt.subplots()
        try:
            with pytest.raises(ValueError, match="3D Axes"):
                program.plot(ax=ax, view="3d")
            with pytest.raises(ValueError, match="view must be one of xy, xz, yz, 3d"):
                program.plot(ax=ax, view="top")
        finally:
            plt.close(fig)
