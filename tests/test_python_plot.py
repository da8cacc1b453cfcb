"""Program.plot(): the picture of the bundled sample (programmed and compensated
paths, dashed rapids, starts, errors) and its extent against the library's size
info; a PNG that is not empty."""
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
    assert set(labels) == {"rapid", "programmed", "start of a cut", "tool centre (compensated)"}
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
    mark = labels["error 503 (line 28)"]
    assert list(zip(mark.get_xdata(), mark.get_ydata())) == [(80.0, 45.0)]    # N230 G3 X80 Y45
    assert "Arc radius 5 smaller than the tool radius 6" in title
    assert "cut" in labels and "tool centre (compensated)" not in labels        # drawn uncompensated


def test_png_is_not_empty(tmp_path):
    out = tmp_path / "sample.png"
    with sf_tch.compile(sf_tch.sample_program(), radius=1.0, start=ORIGIN) as program:
        save_plot(program, str(out))
    pixels = matplotlib.image.imread(out)
    assert pixels.shape[0] > 500 and pixels.shape[1] > 500
    drawn = np.any(pixels[:, :, :3] < 0.9, axis=2).mean()
    assert 0.02 < drawn < 0.5
