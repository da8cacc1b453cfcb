"""ToolChainCore_GetToolpath and sf_tch.Toolpath: every field against the parts the
driver callbacks deliver (the vendor's path), chunked reads, argument checks, and
the arc sampling against closed forms, its memory on a large program."""
import ctypes
import math
import tracemalloc

import numpy as np
import pytest

import sf_tch
from compiler_host import SEED_PROGRAM
from sf_tch import PartKind, abi
from sf_tch.toolpath import TOOLPATH_DTYPE

# The plate of the bundled sample: G42/G41 contours, helical holes, M functions, PRINT.
RADIUS = 1.0


@pytest.fixture
def sample():
    # from the origin: the axes the sample has not named yet follow the machine position; on
    # its core, for the tests that read the library's toolpath through the ABI
    with sf_tch.compile(sf_tch.sample_program(), radius=RADIUS, start=[0.0] * 10, keep_core=True) as program:
        yield program


def _check_against_callbacks(program):
    path = program.toolpath
    run = program.simulate()
    rec = path.records
    tool_start = path.tool_start()
    g_rows = np.flatnonzero(np.isin(rec["kind"], [PartKind.MOTION, PartKind.DWELL]))
    m_rows = np.flatnonzero(rec["kind"] == PartKind.M_FUNCTION)
    assert len(g_rows) == len(run.parts) and len(m_rows) == len(run.m_functions)
    for rows, parts in ((g_rows, run.parts), (m_rows, run.m_functions)):
        r = rec[rows]
        xyz = lambda field: np.stack([parts[field][axis] for axis in "xyz"], axis=1)  # noqa: E731
        assert np.array_equal(r["start"], xyz("m_s"))
        assert np.array_equal(r["end"], xyz("m_e"))
        assert np.array_equal(r["tool_end"], xyz("m_calcE"))
        assert np.array_equal(tool_start[rows], xyz("m_calcS"))
        assert np.array_equal(r["number"], parts["m_func"])
        assert np.array_equal(r["line"], parts["m_editorLine"])
        assert np.array_equal(r["file_index"], parts["m_fileIdx"])
        assert np.array_equal(r["plane"], (parts["m_planeTool"] & 0xFFFF).astype(np.int16))
        assert np.array_equal(r["tool"], parts["m_planeTool"] >> 16)
        assert np.array_equal(r["compensation"], parts["m_bFeedIsMin"] >> 16)
        assert np.array_equal(r["flags"] & sf_tch.ToolpathFlag.FEED_PER_MINUTE, parts["m_bFeedIsMin"] & 1)
        assert np.array_equal(r["feed_factor"], parts["m_fp"])
        assert np.array_equal(r["spindle"], parts["m_pars"]["S"])
    motion = rec[g_rows]
    parts = run.parts
    moving = motion["kind"] == PartKind.MOTION
    # SIMPLE_GM_PARAMS carries length and feed as float32
    assert np.allclose(motion["length"][moving], parts["m_pars"]["N"][moving], rtol=1e-6, atol=1e-4)
    assert np.allclose(motion["feed"][moving], parts["m_pars"]["F"][moving], rtol=1e-6)
    arcs = np.isin(motion["number"], [2, 3])
    assert arcs.any()
    assert np.array_equal(motion["centre"][arcs], np.stack([parts["m_cc"][a][arcs] for a in "xyz"], axis=1))
    assert np.array_equal(motion["radius"][arcs], parts["m_cc"]["c"][arcs])
    assert not motion["radius"][~arcs].any() and not motion["centre"][~arcs].any()
    return path


def test_fields_match_the_driver_callbacks_on_the_compensated_sample(sample):
    path = _check_against_callbacks(sample)
    assert (path.records["compensation"] != 40).any()
    # each of the four holes is one helical turn from Z0 down to Z-1
    helix = path.records[(path.records["flags"] & sf_tch.ToolpathFlag.HELIX) != 0]
    assert len(helix) == 4 and (helix["start"][:, 2] == 0).all() and (helix["end"][:, 2] == -1).all()
    assert helix["length"] == pytest.approx(math.hypot(2 * math.pi * 4, 1))
    assert (path.records["kind"] == PartKind.PRINT).sum() == 1
    assert set(path.files.values()) == {sf_tch.sample_program()}


def test_the_sample_rapids_above_the_plate_and_its_holes_are_helical(sample):
    """What every user copies: no rapid below the plate's top (Z0), the cuts at Z-1,
    and the four holes of the header's comment each a helix (its z changes)."""
    rec = sample.toolpath.records
    moves = rec[rec["kind"] == PartKind.MOTION]
    rapids = moves[moves["number"] == 0]
    assert len(rapids) > 8 and (rapids["start"][:, 2] >= 0).all() and (rapids["end"][:, 2] >= 0).all()
    assert rapids["end"][-1].tolist() == [0, 0, 5]                      # the final G0 X0 Y0 at the safe height
    arcs = moves[np.isin(moves["number"], [2, 3])]
    holes = arcs[arcs["centre"][:, 1] == 20]                           # the outline and slot arcs lie elsewhere
    assert len(holes) == 4 and (holes["start"][:, 2] != holes["end"][:, 2]).all()
    assert sorted(holes["centre"][:, 0].tolist()) == [30, 50, 70, 90]
    cuts = moves[moves["number"] != 0]
    plunges = (cuts["start"][:, 0] == cuts["end"][:, 0]) & (cuts["start"][:, 1] == cuts["end"][:, 1])
    assert (cuts["end"][~plunges & ~np.isin(cuts["number"], [2, 3]), 2] == -1).all()   # contours through the plate


def test_fields_match_the_driver_callbacks_on_the_seed_program():
    # (r 0.5 gouges: the seed's arcs turn almost a full circle; warning 601, test_compensation_policy)
    with sf_tch.compile(SEED_PROGRAM + "\n", radius=0.01, params={"absMode": 0}, name="seed.nc") as program:
        program.check()
        _check_against_callbacks(program)


def test_lengths_and_arcs_against_closed_forms():
    code = "G0 X0 Y0 Z0\nG1 X10 F600\nG2 X30 Y0 I10 J0\nG3 X30 Y0 I-5 J0\nG18 G2 X40 Z0 I5 K0\nG17 G1 Y10 Z3\nM30\n"
    with sf_tch.compile(code) as program:
        rec = program.toolpath.records
    moves = rec[rec["kind"] == PartKind.MOTION]
    half, full, xz_half = math.pi * 10, 2 * math.pi * 5, math.pi * 5
    # (the first rapid starts wherever the machine stands)
    assert moves["length"][1:] == pytest.approx(np.array([10, half, full, xz_half, math.hypot(10, 3)]))
    assert list(moves["number"]) == [0, 1, 2, 3, 2, 1]
    assert moves["radius"][2:5] == pytest.approx(np.array([10, 5, 5]))
    assert moves["centre"][2:5] == pytest.approx(np.array([[20, 0, 0], [25, 0, 0], [35, 0, 0]]))
    assert moves["plane"][4] == 18


def test_points_lie_on_the_arcs_and_chords_respect_the_step():
    code = "G0 X0 Y0 Z0\nG2 X20 Y0 I10 J0 F600\nG3 X20 Y0 I-5 J0\nG1 X30\nM30\n"
    step = 0.25
    with sf_tch.compile(code) as program:
        path = program.toolpath
    pts = path.points(step)[1:]                       # from the end of the rapid to (0, 0)
    assert pts[0] == pytest.approx(np.zeros(3)) and pts[-1] == pytest.approx(np.array([30, 0, 0]))
    chords = np.linalg.norm(np.diff(pts, axis=0), axis=1)
    assert chords[:-1].max() <= step + 1e-9 and chords[-1] == pytest.approx(10)     # the arcs; the line
    # the clockwise half circle about (10, 0) passes through (10, 10); the circle about (15, 0) through (15, -5)
    first = pts[: int(math.ceil(math.pi * 10 / step)) + 1]
    assert np.allclose(np.hypot(first[:, 0] - 10, first[:, 1]), 10)
    # a sample lies within the sag of a chord (step^2 / 8r) of the arc's extreme
    assert first[:, 1].max() == pytest.approx(10, abs=step ** 2 / 80) and first[:, 1].min() >= -1e-9
    circle = pts[len(first):-1]
    assert np.allclose(np.hypot(circle[:, 0] - 15, circle[:, 1]), 5)
    assert circle[:, 1].min() == pytest.approx(-5, abs=step ** 2 / 40)
    assert circle[0, 1] > 0                                          # G3 from (20, 0) goes up first
    # the polyline of the path is as long as the arcs and the line (within the chords' sag)
    total = chords.sum()
    assert total == pytest.approx(math.pi * 10 + 2 * math.pi * 5 + 10, rel=1e-3)
    runs = path.polyline(step)
    assert [run.rapid for run in runs] == [True, False]
    assert np.array_equal(runs[1].points, pts)


def test_tool_path_points_of_a_compensated_square():
    code = "G0 X0 Y-10 Z0\nG42 G1 X0 Y0 F600\nG1 X10\nY10\nX0\nY0\nG40 G1 X0 Y-10\nM30\n"
    with sf_tch.compile(code, radius=1.0) as program:
        path = program.toolpath
    cut = [run for run in path.polyline(0.1, tool=True) if not run.rapid][0].points
    # G42 (tool right of the path) on a counter-clockwise square: outside, 1 mm away, corners rounded
    x, y = cut[:, 0], cut[:, 1]
    assert x.min() == pytest.approx(-1) and x.max() == pytest.approx(11)
    assert y.max() == pytest.approx(11)
    assert np.allclose(np.hypot(np.clip(x, 0, 10) - x, np.clip(y, 0, 10) - y)[y > -0.5], 1.0)
    inserted = path.records[(path.records["flags"] & sf_tch.ToolpathFlag.INSERTED) != 0]
    assert len(inserted) == 3 and set(inserted["number"]) == {3}             # the corner arcs at (10,0) (10,10) (0,10)
    assert inserted["radius"] == pytest.approx(1.0)


def test_chunked_reads_equal_one_read(sample):
    lib, core = sample.core.lib, sample.core.index
    whole = sample.toolpath.records
    total = ctypes.c_uint64()
    chunks = []
    first = 0
    while first < len(whole):
        out = np.empty(7, TOOLPATH_DTYPE)
        assert lib.ToolChainCore_GetToolpath(core, out.ctypes.data_as(ctypes.POINTER(abi.TC_TOOLPATH_RECORD)), 7,
                                             first, ctypes.byref(total)) == 0
        chunks.append(out[: min(7, total.value - first)])
        first += 7
    assert total.value == len(whole)
    assert np.concatenate(chunks).tobytes() == whole.tobytes()


def test_argument_checks(sample):
    lib, core = sample.core.lib, sample.core.index
    total = ctypes.c_uint64()
    one = np.empty(1, TOOLPATH_DTYPE)
    ptr = one.ctypes.data_as(ctypes.POINTER(abi.TC_TOOLPATH_RECORD))
    assert lib.ToolChainCore_GetToolpath(3, ptr, 1, 0, ctypes.byref(total)) == -2
    assert lib.ToolChainCore_GetToolpath(core, None, 1, 0, ctypes.byref(total)) == -1
    assert lib.ToolChainCore_GetToolpath(core, None, 0, 0, None) == 0
    assert lib.ToolChainCore_GetToolpath(core, None, 0, 0, ctypes.byref(total)) == 0 and total.value > 0
    assert lib.ToolChainCore_GetToolpath(core, ptr, 1, total.value, None) == 0       # nothing left: fine
    assert lib.ToolChainCore_GetToolpath(core, ptr, 1, total.value + 1, None) == -1
    # reading reports nothing: the last error stays none
    assert sample.core.last_error() is None


def test_no_toolpath_without_a_program():
    with sf_tch.Core() as core:
        total = ctypes.c_uint64(12345)
        assert core.lib.ToolChainCore_GetToolpath(core.index, None, 0, 0, ctypes.byref(total)) == -1
        assert total.value == 12345
        with pytest.raises(RuntimeError, match="no compiled program"):
            core.toolpath()
    program = sf_tch.compile("G1 X1/0\n", name="bad.nc", keep_core=True)
    with program:
        assert not program.ok and len(program.toolpath) == 0
        assert program.core.lib.ToolChainCore_GetToolpath(program.core.index, None, 0, 0, None) == -1


def test_record_layout_is_the_headers():
    assert TOOLPATH_DTYPE.itemsize == ctypes.sizeof(abi.TC_TOOLPATH_RECORD) == 168
    assert TOOLPATH_DTYPE["start"].shape == (3,) and TOOLPATH_DTYPE.fields["kind"][1] == 128


def _half_circles(count: int) -> str:
    """A zigzag of `count` lines 1 mm long, each followed by a half circle of r 5 mm."""
    blocks = "".join(f"G1 X{k * 11 + 1}\nG2 X{k * 11 + 11} Y0 I5 J0\n" for k in range(count))
    return "G0 X0 Y0 Z0\nG1 F3000\n" + blocks + "M30\n"


@pytest.mark.parametrize("tool", [False, True])
def test_points_of_a_large_program_need_little_beside_the_result(tool):
    """Sampled a bounded number of moves at a time: beside the array it returns,
    points() needs a few bytes per move (the old sampling held about six times the
    result's size at once)."""
    with sf_tch.compile(_half_circles(20_000), radius=0.0) as program:
        path = program.toolpath                        # 40,000 moves; the input, read before measuring
    tracemalloc.start()
    try:
        pts = path.points(step=0.5, tool=tool)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert len(pts) == 1 + 1 + 20_000 * (1 + math.ceil(math.pi * 5 / 0.5))    # start, the rapid, lines, arcs
    assert pts.nbytes > 15e6
    assert peak < 1.5 * pts.nbytes, (peak / pts.nbytes)
    # the same points as the arcs' closed form: the last half circle's samples on its circle
    last = pts[-1 - math.ceil(math.pi * 5 / 0.5):]
    assert np.allclose(np.hypot(last[:, 0] - (19_999 * 11 + 6), last[:, 1]), 5)
