"""What tool radius compensation does with offsets that cross or cut into the contour
(docs/compensation.md, "Crossing equidistants: warning, removal, refusal"): by default
the vendor's warning (601: the line and how deep the tool cuts) and the program
compiles; with 0x80000 the crossing parts are removed and nothing is refused; only the
strict mode (GCODE_REZERVA1_COMP_STRICT) refuses, with error 504. The switch from C,
an INI file, Python and the command line; the vendor's example program and three
contours of generated CAM jobs that cross themselves (tests/comp_repro/). Shapely is
the oracle of the tool path's clearance and of the warning's depth."""
import ctypes
import math
import re
import subprocess
import sys
import time
import warnings

import numpy as np
import pytest

shapely = pytest.importorskip("shapely")
from shapely.geometry import LineString  # noqa: E402

import sf_tch  # noqa: E402
from comp_helpers import check_gouge_warnings, polygon_elements, programmed_polyline  # noqa: E402
from compiler_host import SEED_PROGRAM  # noqa: E402
from sf_tch import ErrorNumber, abi  # noqa: E402
from test_compensation_cases import L, chamfered_pocket, comp_run  # noqa: E402
from test_compensation_geometry import harness  # noqa: E402,F401
from test_compensation_regions import REPRO, clearance, offset_region, read_contour, sampled_path  # noqa: E402
from test_compensation_regions import toolpath_clearances  # noqa: E402

TOL = 1e-3
REFUSED = ["comp_refused_83", "comp_refused_150", "comp_refused_1409"]
# lines of the seed example whose tool path cuts into an earlier arc's circle
SEED_GOUGES = {5, 7, 8, 9, 10}


def compile_seed(strategy, strict=False):
    """The vendor's example program as the vendor runs it: relative, G42, radius 1.5."""
    with warnings.catch_warnings(record=True) as shown:
        warnings.simplefilter("always", sf_tch.GougeWarning)
        program = sf_tch.compile(SEED_PROGRAM, radius=1.5, strategy=strategy, params={"absMode": 0},
                                 name="seed.nc", strict=strict)
    return program, [w for w in shown if issubclass(w.category, sf_tch.GougeWarning)]


def gouges(program):
    return {w.line: float(w.arguments[1]) for w in program.warnings if w.number == ErrorNumber.COMPENSATION_GOUGE}


# ------------------------------------------------------------------ the vendor's example program

@pytest.mark.parametrize("strategy", [0x600, 0x601])
def test_seed_example_compiles_with_warnings_by_default(strategy):
    program, shown = compile_seed(strategy)
    with program:
        program.check()
        found = gouges(program)
        assert set(found) == SEED_GOUGES
        # the tool's centre crosses the circles of the other arcs: it cuts the radius deep
        assert all(depth == pytest.approx(1.5) for depth in found.values())
        for w in program.warnings:
            if w.number == ErrorNumber.COMPENSATION_GOUGE:
                assert w.arguments[0] == str(w.line) and w.file == "seed.nc"
                assert str(w).startswith(f"seed.nc:{w.line}:1: warning 601: Equidistant error on line {w.line}: "
                                         f"the tool cuts 1.5 mm into the contour")
        # Python shows each one at its G-code line
        assert sorted((w.filename, w.lineno, str(w.message)) for w in shown) == \
            sorted(("seed.nc", w.line, f"warning 601: {w.text}") for w in program.warnings
                   if w.number == ErrorNumber.COMPENSATION_GOUGE)
        # as the offsets give them: the seven arcs keep their centres, radius R - 1.5
        records = program.toolpath.records
        arcs = records[(records["kind"] == abi.TC_TOOLPATH_MOTION) & (records["number"] == 2)
                       & (records["compensation"] == 42) & (records["flags"] & abi.TC_TOOLPATH_INSERTED == 0)]
        assert len(arcs) == 7
        prog_r = np.hypot(*(arcs["end"][:, :2] - arcs["centre"][:, :2]).T)
        assert np.allclose(arcs["radius"], prog_r - 1.5, atol=0.006)      # (the seed's centres: tolerance[0])
        assert np.allclose(np.hypot(*(arcs["tool_end"][:, :2] - arcs["centre"][:, :2]).T), arcs["radius"])


@pytest.mark.parametrize("strategy", [0x80600, 0x90600, 0xA0600, 0xA0601])
def test_seed_example_with_0x80000_is_never_refused(strategy):
    """Its tool path crosses itself only where the programmed arcs cross each other
    (no loop to cut), and the chain is open (no regions to rebuild): compiled as by
    default, with the same warnings."""
    program, _ = compile_seed(strategy)
    default, _ = compile_seed(strategy & 0xFF | 0x600)
    with program, default:
        program.check()
        assert set(gouges(program)) == SEED_GOUGES
        a, b = program.toolpath.records, default.toolpath.records
        assert np.array_equal(a["tool_end"], b["tool_end"]) and np.array_equal(a["radius"], b["radius"])


@pytest.mark.parametrize("strategy", [0x600, 0x601, 0x80600, 0xA0600, 0xA0601, 0x90600])
def test_seed_example_is_refused_only_in_the_strict_mode(strategy):
    program, shown = compile_seed(strategy, strict=True)
    with program:
        assert [(e.number, e.line) for e in program.errors] == [(ErrorNumber.COMP_CROSSING, 5)]
        assert not shown and not gouges(program)


# ------------------------------------------------------------------ contours that cross themselves

@pytest.mark.parametrize("mode", [0, 1])
@pytest.mark.parametrize("name", REFUSED)
def test_refused_contours_compile_with_0x80000_and_keep_the_radius(harness, name, mode):
    """Each contour twists over itself at a spike (its polygon is not simple): the
    region the tool fits in is bordered by its lines out of program order. The rebuilt
    path goes round the largest region (shapely), every point at least the radius from
    the contour, the lines left out named by warning 600."""
    r = 0.15
    parts, pts, _ = read_contour(name)
    out, err, warn = comp_run(parts, r=r, strategy=0xA0600 | mode, start=(0, 0, 0))
    assert err is None, err
    assert "Equidistant error" not in warn
    path = sampled_path(out, pts[0])
    assert clearance(path, pts) > r - TOL
    shape, inside = offset_region(pts, r, 41)
    largest = max(getattr(shape, "geoms", [shape]), key=lambda c: c.area)
    ring_pts = np.asarray(shapely.segmentize(largest.exterior, 0.01).coords)
    assert float(np.max(shapely.distance(shapely.points(ring_pts), LineString(path)))) < 0.01
    assert float(np.max(shapely.distance(shapely.points(path), shape.boundary))) < 2 * TOL
    # warning 600 names exactly the lines whose tool side offset has no piece of that
    # border ("skipped"), and those whose piece comes out of program order (cut after
    # a later line)
    first = next(i for i, p in enumerate(parts) if p["comp"] != 40)
    lines = [p["line"] for p in parts[first + 1:] if p["comp"] != 40]
    no_piece = set()
    for i in range(len(pts) - 1):
        d = pts[i + 1] - pts[i]
        n = np.array([-d[1], d[0]]) / np.hypot(*d)
        offset = LineString([pts[i] + r * n, pts[i + 1] + r * n])
        if offset.intersection(largest.exterior.buffer(1e-6)).length < 1e-5:
            no_piece.add(lines[i])
    skipped = {int(m) for m in re.findall(r"line (\d+): part skipped", warn)}
    moved = {int(m) for m in re.findall(r"line (\d+): part's tool path cut after a later line", warn)}
    assert skipped == no_piece and skipped
    assert not moved & no_piece
    if mode == 0:
        idx = [k for k, p in enumerate(out) if p["comp"] != 40]
        assert np.allclose(out[idx[0]]["ce"][:2], out[idx[-1]]["ce"][:2], atol=1e-6)


@pytest.mark.parametrize("name", REFUSED)
def test_refused_contours_warn_by_default_and_fail_only_when_strict(harness, name):
    r = 0.15
    parts, pts, _ = read_contour(name)
    for mode in (0, 1):
        out, err, warn = comp_run(parts, r=r, strategy=0x20600 | mode, start=(0, 0, 0))
        assert err is None, err
        assert check_gouge_warnings(out, warn, pts, r, start_point=pts[0])
        _, err, _ = comp_run(parts, r=r, strategy=0x20600 | mode, start=(0, 0, 0), strict=True)
        assert err is not None and err["number"] == 504
        # 0x80000 removes the crossing: nothing to refuse, nothing to warn about
        _, err, warn = comp_run(parts, r=r, strategy=0xA0600 | mode, start=(0, 0, 0), strict=True)
        assert err is None and "Equidistant error" not in warn


def test_refused_contours_through_the_library():
    """The three contours as one CAM job, with 0xA0600 and 0xA0601: compiled, each
    tool path at least the radius from its contour (shapely on the toolpath records)."""
    texts, contours, offset = [], [], 0
    for name in REFUSED:
        text = (REPRO / f"{name}.nc").read_text().replace("M2\n", "")
        _, pts, _ = read_contour(name)
        moves = [k for k, line in enumerate(text.splitlines(), 1) if line.startswith("G1 X")]
        contours.append((offset + moves[1], offset + moves[-2], pts))
        texts.append(text)
        offset += len(text.splitlines())
    job = "".join(texts) + "M2\n"
    for strategy in (0xA0600, 0xA0601):
        with sf_tch.compile(job, radius=0.15, strategy=strategy, name="job.nc") as program:
            program.check()
            assert not gouges(program)
            named = {w.line for w in program.warnings if w.number == ErrorNumber.COMPENSATION_WARNING}
            assert named and all(any(first <= line <= last for first, last, _ in contours) for line in named)
            assert toolpath_clearances(program, contours).min() > 0.15 - TOL


# ------------------------------------------------------------------ the warning

def test_the_warning_gives_the_line_and_the_depth(harness):
    """A square pocket (corner (10, 10)) with a chamfer of 0.3 mm, tool of radius r
    inside: the side's and the top's offsets meet the chamfer's x + y = 19.7 - sqrt(2) r
    at (10 - r, 9.7 - (sqrt(2) - 1) r), 0.3 + (sqrt(2) - 1) r from the top, and the
    chamfer's part runs back between them: the lines of the side, the chamfer and the
    top cut (2 - sqrt(2)) r - 0.3 mm into the contour (closed form), none below r =
    0.3 / (2 - sqrt(2))."""
    m0, els = chamfered_pocket(0.3)
    parts = [dict(func=1, e=(0, -30), comp=40), L(*m0)] + [dict(el, comp=41, line=20 + i) for i, el in enumerate(els)]
    parts.append(L(0, -30, comp=40))
    for tool in (2.0, 1.0, 0.6, 0.5):
        depth = (2 - math.sqrt(2)) * tool - 0.3
        out, err, warn = comp_run(parts, r=tool, start=(0, -30, 0))
        assert err is None
        warned = check_gouge_warnings(out, warn, programmed_polyline(m0, els), tool)
        assert warned == ({line: pytest.approx(depth, abs=1e-6) for line in (21, 22, 23)} if depth > 0 else {})
    out, err, warn = comp_run(parts, r=2.0, start=(0, -30, 0))
    assert "line 22: Equidistant error on line 22: the tool cuts 0.871573 mm into the contour" in warn


def test_a_notch_narrower_than_the_tool_warns_once_per_line(harness):
    """The walls of a 3 mm notch under a tool of radius 2 inside: each wall's line
    warned once, with the deepest cut (1 mm: the other wall is 3 away)."""
    m0, els = polygon_elements([(-20, -10), (20, -10), (20, 10), (1.5, 10), (1.5, -2), (-1.5, -2), (-1.5, 10),
                                (-20, 10)])
    approach = (m0[0] + 0.3, m0[1] - 60.0)
    parts = [dict(func=1, e=approach, comp=40), dict(func=1, e=m0, comp=42)]
    parts += [dict(el, comp=42) for el in els] + [dict(func=1, e=approach, comp=40)]
    out, err, warn = comp_run(parts, r=2.0, start=(approach[0], approach[1], 0))
    assert err is None
    warned = check_gouge_warnings(out, warn, programmed_polyline(m0, els), 2.0, start_point=np.asarray(m0))
    assert max(warned.values()) == pytest.approx(1.0)
    assert len(re.findall(r"Equidistant error", warn)) == len(warned)


# ------------------------------------------------------------------ the strict switch

ABSOLUTE = {"absMode": 1}           # (a core keeps its parameters from one user to the next)
CHAMFER = "G0 X0 Y-20\nG41 G1 X0 Y-10 F1000\nX10\nY9.7\nX9.7 Y10\nX-10\nY-10\nX0\nG40 X0 Y-20\nM30\n"


def _wait(lib, core):
    deadline = time.monotonic() + 60
    while lib.ToolChainCore_StatusCNC(core) == 1:
        assert time.monotonic() < deadline
        time.sleep(0.002)


def _compile_c(lib, code, params=None):
    """CompileFromMemory on core 0: (GetLastError's number and line or None, the
    MathWarning callback's (number, line, arguments))."""
    seen = []

    def on_warning(user, info):
        i = info.contents
        seen.append((i.stringId, i.actLine, (i.m_errorArguments or b"").decode()))
        return 0

    if params is not None:
        assert lib.ToolChainCore_SetGCodeParameters(0, ctypes.byref(params)) == 0
    cb = abi.MathWarning(on_warning)
    assert lib.ToolChainCore_SetCallBack(0, abi.CB_MATH_WARNING, 0, ctypes.cast(cb, ctypes.c_void_p)) == 0
    try:
        assert lib.ToolChainCore_CompileFromMemory(0, b"chamfer.nc", code.encode()) == 0
        _wait(lib, 0)
    finally:
        lib.ToolChainCore_SetCallBack(0, abi.CB_MATH_WARNING, 0, None)
    info = abi.CALLBACK_INFO()
    err = (info.stringId, info.actLine) if lib.ToolChainCore_GetLastError(0, ctypes.byref(info)) == 1 else None
    return err, seen


def _load_ini(lib, tmp_path, strict):
    ini = tmp_path / "strict.ini"
    ini.write_text("[CNC]\nDriver=offline\n[GCodeParameters]\ncorrection0=2\ncorrectionStrategy=0x600\n"
                   + (f"strictCompensation={strict}\n" if strict is not None else ""))
    assert lib.ToolChainCore_LoadFromIni(0, str(ini).encode(), None) == 0


def test_strict_switch_from_c_and_from_the_ini(fresh_core, tmp_path):
    lib = fresh_core
    _load_ini(lib, tmp_path, None)
    p = abi.GCODE_PARAMETERS()
    assert lib.ToolChainCore_GetGCodeParameters(0, ctypes.byref(p)) == 0
    assert p.rezerva1 & abi.GCODE_REZERVA1_COMP_STRICT == 0             # off by default
    err, seen = _compile_c(lib, CHAMFER)
    assert err is None
    # the right side, the chamfer (line 5) and the top, 3.7 - 2 sqrt(2) mm deep
    assert [(n, line) for n, line, _ in seen] == [(601, 4), (601, 5), (601, 6)]
    assert seen[1][2] == "5\n0.871573"
    # the bit, set by the host
    p.rezerva1 |= abi.GCODE_REZERVA1_COMP_STRICT
    err, seen = _compile_c(lib, CHAMFER, p)
    assert err == (504, 5) and seen == []
    # the INI key sets and clears it
    for strict, expected in ((0, None), (1, (504, 5))):
        _load_ini(lib, tmp_path, strict)
        assert lib.ToolChainCore_GetGCodeParameters(0, ctypes.byref(p)) == 0
        assert bool(p.rezerva1 & abi.GCODE_REZERVA1_COMP_STRICT) == bool(strict)
        assert _compile_c(lib, CHAMFER)[0] == expected
    # 0x80000: the chamfer removed (warning 600), nothing refused, also when strict
    p.correctionStrategy = 0x80600
    err, seen = _compile_c(lib, CHAMFER, p)
    assert err is None and [(n, line) for n, line, _ in seen] == [(600, 5)]


def test_strict_ini_value_must_be_0_or_1(fresh_core, tmp_path):
    ini = tmp_path / "bad.ini"
    ini.write_text("[GCodeParameters]\nstrictCompensation = yes\n")
    assert fresh_core.ToolChainCore_LoadFromIni(0, str(ini).encode(), None) == abi.TOOL_CHAIN_XEXEC


def test_strict_switch_from_python():
    with warnings.catch_warnings(record=True) as shown:
        warnings.simplefilter("always")
        program = sf_tch.compile(CHAMFER, radius=2.0, name="chamfer.nc", params=ABSOLUTE)
    with program:
        assert program.ok and set(gouges(program)) == {4, 5, 6}
        assert [(w.filename, w.lineno, str(w.message)) for w in shown if w.category is sf_tch.GougeWarning] == \
            [("chamfer.nc", w.line, f"warning 601: {w.text}") for w in program.warnings]
    with warnings.catch_warnings():
        warnings.simplefilter("error", sf_tch.GougeWarning)       # a host that wants an exception
        with pytest.raises(sf_tch.GougeWarning, match="warning 601: Equidistant error on line 4"):
            sf_tch.compile(CHAMFER, radius=2.0, name="chamfer.nc", params=ABSOLUTE).close()
    with sf_tch.compile(CHAMFER, radius=2.0, name="chamfer.nc", params=ABSOLUTE, strict=True) as program:
        assert [(e.number, e.line) for e in program.errors] == [(ErrorNumber.COMP_CROSSING, 5)]
        assert program.compile_args()["strict"] is True
    # the mode is the call's: the core keeps no strictness for the next user
    with sf_tch.compile(CHAMFER, radius=2.0, name="chamfer.nc", params=ABSOLUTE, core=0, strict=True) as program:
        assert not program.ok
    with pytest.warns(sf_tch.GougeWarning):
        program = sf_tch.compile(CHAMFER, radius=2.0, name="chamfer.nc", params=ABSOLUTE, core=0)
    with program:
        assert program.ok


def _cli(*args):
    return subprocess.run([sys.executable, "-m", "sf_tch", *args], capture_output=True, text=True, timeout=120)


def test_strict_switch_from_the_command_line(tmp_path):
    path = tmp_path / "chamfer.nc"
    path.write_text(CHAMFER)
    proc = _cli("compile", str(path), "--radius", "2")
    assert proc.returncode == 0, proc.stderr
    lines = proc.stderr.splitlines()
    assert lines[:3] == [f"{path}:{n}:1: warning 601: Equidistant error on line {n}: the tool cuts 0.871573 mm into "
                         f"the contour" for n in (4, 5, 6)]
    assert lines[3] == ("sf-tch: 3 warnings, 3 where the tool cuts into the contour (warning 601; --strict "
                        "refuses such a program)")
    assert "GougeWarning" not in proc.stderr and "program:" in proc.stdout
    proc = _cli("compile", str(path), "--radius", "2", "--strict")
    assert proc.returncode == 1
    assert f"{path}:5:1: error 504: Equidistants cross" in proc.stderr
    proc = _cli("compile", str(path), "--radius", "2", "--strategy", "0x80600", "--strict")
    assert proc.returncode == 0 and "601" not in proc.stderr


# ------------------------------------------------------------------ parts farther apart than the depth

@pytest.mark.parametrize("depth", [0x100, 0x200, 0x600])
def test_an_open_hairpin_gouges_whatever_the_depth(harness, depth):
    """An open path out and back 1.5 mm apart, 20 parts each way, the tool (radius 1)
    between the legs: each leg's path comes 0.5 mm into the other leg, up to 40 parts
    apart in program order (at the bend, shorter than the tool, it crosses the
    contour). Found at every depth (10, 50, 2000): warning 601 on the lines shapely
    names, the strict mode refuses it; 0x80000 cannot remove it from an open chain (no
    loop within the depth, no regions) and compiles it the same way."""
    pts = [(float(k), 0.0) for k in range(21)] + [(20.0 - k, 1.5) for k in range(21)]
    parts = [dict(func=1, e=(0.0, -5.0), comp=40), dict(func=1, e=(0.0, 0.0), comp=41)]
    parts += [dict(func=1, e=p, comp=41) for p in pts[1:]] + [dict(func=1, e=(-5.0, 1.5), comp=40)]
    contour = np.array(pts)
    for strategy in (depth, depth | 0x80000):
        out, err, warn = comp_run(parts, r=1.0, strategy=0x20000 | strategy, start=(0.0, -5.0, 0))
        assert err is None, err
        warned = check_gouge_warnings(out, warn, contour, 1.0)
        # lines 6 and 40 (x 3 .. 4 on the two legs) lie 34 parts apart
        assert warned[6] == pytest.approx(0.5) and warned[40] == pytest.approx(0.5)
        _, err, _ = comp_run(parts, r=1.0, strategy=0x20000 | strategy, start=(0.0, -5.0, 0), strict=True)
        assert err is not None and err["number"] == 504
