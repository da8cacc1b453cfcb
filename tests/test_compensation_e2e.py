"""Tool radius compensation end to end, as an HMI sees it through ctypes: parameters
(correction sizes, strategy), CompileFromMemory, GetLastError, the offline driver's
DriverGFunc callback with m_calcS / m_calcE / m_cc / m_func / m_bFeedIsMin."""
import ctypes
import math
import time

import numpy as np
import pytest

from compiler_host import SEED_PROGRAM
from sf_tch import abi
from sf_tch.library import load

CORE = 2
INI = "[Modules]\nCompiler0=x\n[CNC]\nDriver=offline\n"


class Hmi:
    def __init__(self, tmp_path):
        self.tmp = tmp_path
        self.lib = load()
        ini = tmp_path / "comp.ini"
        ini.write_text(INI)
        n = ctypes.c_uint32()
        assert self.lib.ToolChainCore_LoadFromIni(CORE, str(ini).encode(), ctypes.byref(n)) == 0
        self.saved = abi.GCODE_PARAMETERS()
        assert self.lib.ToolChainCore_GetGCodeParameters(CORE, ctypes.byref(self.saved)) == 0

    def close(self):
        # DestroyCNC joins the core's last worker thread (a host that exits without it leaves the thread unjoined)
        assert self.lib.ToolChainCore_DestroyCNC(CORE) == 0
        self.lib.ToolChainCore_SetGCodeParameters(CORE, ctypes.byref(self.saved))

    def wait(self, done, timeout=60):
        deadline = time.monotonic() + timeout
        while True:
            status = self.lib.ToolChainCore_StatusCNC(CORE)
            if done(status):
                return status
            assert time.monotonic() < deadline, f"status stuck at {status}"
            time.sleep(0.002)

    def compile(self, code, r=2.0, strategy=0, abs_mode=1, strict=False):
        p = abi.GCODE_PARAMETERS.from_buffer_copy(self.saved)
        p.absMode = abs_mode
        p.correctionStrategy = strategy
        if strict:
            p.rezerva1 |= abi.GCODE_REZERVA1_COMP_STRICT
        for i in range(8):
            p.correction[i].size = r
        assert self.lib.ToolChainCore_SetGCodeParameters(CORE, ctypes.byref(p)) == 0
        assert self.lib.ToolChainCore_CompileFromMemory(CORE, b"comp.nc", code.encode()) == 0
        self.wait(lambda s: s != 1)
        info = abi.CALLBACK_INFO()
        if self.lib.ToolChainCore_GetLastError(CORE, ctypes.byref(info)) == 1:
            return (info.stringId, info.actLine, (info.m_fullError or b"").decode())
        return None

    def run(self):
        parts = []

        def on_g(user, gm):
            g = gm.contents
            parts.append(dict(func=g.m_func, s=[getattr(g.m_calcS, a) for a in "xyz"],
                              e=[getattr(g.m_calcE, a) for a in "xyz"],
                              pe=[getattr(g.m_e, a) for a in "xyz"],
                              cc=[g.m_cc.x, g.m_cc.y, g.m_cc.z, g.m_cc.c], comp=g.m_bFeedIsMin >> 16,
                              line=g.m_editorLine, index=g.m_gCodeIndex))
            return 0

        cb = abi.DriverGFunc(on_g)
        assert self.lib.ToolChainCore_SetCallBack(CORE, abi.CB_DRIVER_G_FUNC, 0, ctypes.cast(cb, ctypes.c_void_p)) == 0
        try:
            assert self.lib.ToolChainCore_ResetCNC(CORE, 0, 0, None) == 0
            assert self.lib.ToolChainCore_StartCNCEx(CORE, 10, None) == 0
            self.wait(lambda s: s == -10)
        finally:
            self.lib.ToolChainCore_SetCallBack(CORE, abi.CB_DRIVER_G_FUNC, 0, None)
        return parts


@pytest.fixture
def hmi(tmp_path):
    h = Hmi(tmp_path)
    yield h
    h.close()


def _compiles(hmi):
    err = hmi.compile("G1 X1\n")
    if err is not None and err[0] == 10:
        pytest.skip("the G-code compiler is not there yet")


SQUARE = "G0 X0 Y-20\n{g} G1 X0 Y-10 F1000\nX10\nY10\nX-10\nY-10\nX0\nG40 X0 Y-20\nM30\n"


def test_inner_square_through_the_driver(hmi):
    _compiles(hmi)
    assert hmi.compile(SQUARE.format(g="G41")) is None
    parts = hmi.run()
    ends = [tuple(round(v, 6) for v in p["e"][:2]) for p in parts]
    assert ends == [(0, -20), (0, -8), (8, -8), (8, 8), (-8, 8), (-8, -8), (0, -8), (0, -20)]
    assert [p["comp"] for p in parts] == [40, 41, 41, 41, 41, 41, 41, 40]
    # every part starts where the previous one ended (compensated)
    for a, b in zip(parts, parts[1:]):
        assert np.allclose(a["e"], b["s"])


def test_outer_square_inserts_corner_arcs(hmi):
    _compiles(hmi)
    assert hmi.compile(SQUARE.format(g="G42")) is None
    parts = hmi.run()
    arcs = [p for p in parts if p["func"] == 3]
    assert len(arcs) == 4
    assert all(p["index"] % 2 == 1 and p["cc"][3] == pytest.approx(2.0) for p in arcs)
    assert np.allclose(arcs[0]["cc"][:2], (10, -10)) and np.allclose(arcs[0]["e"][:2], (12, -10))
    for p in parts:
        if p["func"] == 3:
            assert math.hypot(p["s"][0] - p["cc"][0], p["s"][1] - p["cc"][1]) == pytest.approx(2.0)


def test_g41_on_a_g42_negative_radius_swaps_sides(hmi):
    _compiles(hmi)
    assert hmi.compile(SQUARE.format(g="G41"), r=-2.0) is None
    assert sum(p["func"] == 3 for p in hmi.run()) == 4     # outside, like G42


def test_error_on_the_right_line(hmi):
    _compiles(hmi)
    code = "G0 X0 Y-20\nG41 G1 X0 Y-10 F1000\nX10\nY9.7\nX9.7 Y10\nX-10\nY-10\nX0\nG40 X0 Y-20\n"
    err = hmi.compile(code, strict=True)
    assert err is not None and err[0] == 504 and err[1] == 5
    assert hmi.compile(code) is None                # the vendor's default: warning 601, compiled
    assert hmi.compile(code, strategy=0x80000) is None
    ends = [tuple(round(v, 6) for v in p["e"][:2]) for p in hmi.run()]
    assert (8, 8) in ends
    err = hmi.compile("G0 X0 Y-20\nG41 G1 X0 Y-10 F1000\nG2 X10 Y0 I0 J10\nG40 G2 X0 Y10 I-10 J0\n")
    assert err is not None and err[0] == 501 and err[1] == 4




def test_seed_003_example_with_g42(hmi):
    _compiles(hmi)
    # read relative, the seed's arcs turn almost a full circle each and the next one
    # starts inside it: a tool of radius 0.5 on the right would cut line 6's arc
    # (the strict mode refuses it; by default warning 601, test_compensation_policy)
    err = hmi.compile(SEED_PROGRAM, r=0.5, abs_mode=0, strict=True)
    assert err is not None and err[0] == 504 and err[1] == 5
    r = 0.01
    err = hmi.compile(SEED_PROGRAM, r=r, abs_mode=0)
    assert err is None, err
    parts = hmi.run()
    assert [p["comp"] for p in parts if p["func"] == 2] == [42] * 7
    # the compensated arcs: same centres, radius - r for G2 with the tool on the right
    for p in parts:
        if p["func"] == 2:
            r_prog = math.hypot(p["pe"][0] - p["cc"][0], p["pe"][1] - p["cc"][1])
            # (the seed's centres are off by up to 0.005 mm: tolerance[0])
            assert abs(p["cc"][3] - r_prog + r) < 0.005
            assert math.hypot(p["e"][0] - p["cc"][0], p["e"][1] - p["cc"][1]) == pytest.approx(p["cc"][3])
    for a, b in zip(parts, parts[1:]):
        assert np.allclose(a["e"], b["s"])


DUMBBELL = """G0 X-12.5 Y-60
G41 G1 X-12.5 Y-10 F1000
X-5
Y-2
X5
Y-10
X20
Y10
X5
Y2
X-5
Y10
X-20
Y-10
X-12.5
G40 G1 X-12.5 Y-60
M30
"""


def test_loop_at_a_narrow_neck_through_the_driver(hmi):
    # the bar between the two squares is 4 high: a tool of radius 3 does not pass it
    _compiles(hmi)
    err = hmi.compile(DUMBBELL, r=3.0, strict=True)
    assert err is not None and err[0] == 504 and err[1] == 10
    assert hmi.compile(DUMBBELL, r=3.0) is None      # the loop kept, warning 601
    assert hmi.compile(DUMBBELL, r=3.0, strategy=0x80000) is None
    parts = hmi.run()
    # only the left square is machined; the parts of the loop are zero-length moves
    assert max(p["e"][0] for p in parts) < 0
    for a, b in zip(parts, parts[1:]):
        assert np.allclose(a["e"], b["s"])
    ends = [tuple(round(v, 6) for v in p["e"][:2]) for p in parts]
    assert (round(-5 - math.sqrt(5), 6), 0) in ends            # the corner arcs' crossing
    assert hmi.compile(DUMBBELL, r=1.9) is None                 # a tool that fits


def test_the_benchmark_cutting_program_compensates(hmi):
    # benchmarks/compile_benchmark.py compiles this program under G41: it must
    # compensate cleanly (its timing assumes no error), with three outer corners per
    # cut part: the notch's two ends and the corner before the bottom edge
    import importlib.util
    from pathlib import Path
    path = Path(__file__).resolve().parents[1] / "benchmarks" / "compile_benchmark.py"
    spec = importlib.util.spec_from_file_location("compile_benchmark", path)
    bench = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(bench)
    program = hmi.tmp / "cutting.nc"
    bench.write_program(program, 1100, head="G41")
    assert hmi.compile(program.read_text(), r=0.3, abs_mode=0) is None
    parts = hmi.run()
    inserted = [p for p in parts if p["index"] % 2 == 1]
    assert len(inserted) == 3 * 100
    assert all(p["func"] in (2, 3) and p["cc"][3] == pytest.approx(0.3) for p in inserted)
    for a, b in zip(parts, parts[1:]):
        assert np.allclose(a["e"], b["s"], atol=1e-9)


# A square wave run to the right, compensated on the left (G41, r = 2), written
# relative and repeated by a FOR loop: far more parts than lines, so the part array
# grows while the compensation reads it beside the compiler (toolchain/pipeline.pyx),
# and G172/G173 in the loop grow the strategy regions meanwhile. Each tooth (X10 Y10
# X10 Y-10 from (0, 0)) has two inner corners, where the offsets meet, and two outer
# ones, where an arc of radius 2 goes round the corner: hand-computed ends below.
TOOTH_ENDS = [(8, 2), (8, 10), (10, 12), (20, 12), (22, 10), (22, 2)]
WAVE = """G41 G1 X0 Y0 F1000
FOR P1 = 1 TO {n}
G1 X10
Y10
G172 C0
X10
G173
Y-10
END
G1 X10
G40 G1 X0 Y-10
M30
"""


def test_a_long_program_is_compensated_beside_the_compiler(hmi):
    _compiles(hmi)
    n = 3000                                # 12,000 programmed parts from 12 lines
    assert hmi.compile(WAVE.format(n=n), abs_mode=0) is None
    parts = hmi.run()
    first = 1                               # parts[0] is the G41 block, at the wave's start
    origin = np.array(parts[0]["pe"][:2])   # (a relative program starts where the machine is)
    ends = np.array([p["e"][:2] for p in parts]) - origin
    # the first X10 is the ramp to the perpendicular of the next part (8, 0)
    assert np.allclose(ends[first:first + 6], [(8, 0)] + TOOTH_ENDS[1:], atol=1e-9)
    for k in range(1, n):
        tooth = ends[first + 6 * k: first + 6 * k + 6]
        assert np.allclose(tooth, np.array(TOOTH_ENDS) + (20 * k, 0), atol=1e-9), k
    assert [p["func"] for p in parts[first:first + 6]] == [1, 1, 2, 1, 2, 1]
    for a, b in zip(parts, parts[1:]):
        assert np.allclose(a["e"], b["s"], atol=1e-9)


def test_an_error_of_the_compensation_beside_the_compiler_keeps_its_line(hmi):
    _compiles(hmi)
    # after 12,000 parts an arc of radius 1 on the tool's side (G41, CCW): error 503
    code = WAVE.format(n=3000).replace("G1 X10\nG40", "G1 X10\nG3 X2 Y0 I1 J0\nG1 X10\nG40")
    err = hmi.compile(code, abs_mode=0)
    assert err is not None and err[0] == 503 and err[1] == 11, err
    # a compile error later in the program is the one reported (the compiler's errors
    # come first, as when the compensation ran after it)
    err = hmi.compile(code.replace("M30", "G1 X1/0\nM30"), abs_mode=0)
    assert err is not None and err[0] == 200 and err[1] == 14, err
    assert hmi.compile(WAVE.format(n=10), abs_mode=0) is None      # the core is usable


def test_reset_interrupts_a_compensated_compilation(hmi):
    _compiles(hmi)
    p = abi.GCODE_PARAMETERS.from_buffer_copy(hmi.saved)
    p.absMode = 0
    p.correction[0].size = 2.0
    assert hmi.lib.ToolChainCore_SetGCodeParameters(CORE, ctypes.byref(p)) == 0
    code = WAVE.format(n=2_000_000).encode()
    for delay in (0.0, 0.02, 0.2):
        assert hmi.lib.ToolChainCore_CompileFromMemory(CORE, b"comp.nc", code) == 0
        time.sleep(delay)
        assert hmi.lib.ToolChainCore_ResetCNC(CORE, 0, 0, None) == 0
        assert hmi.lib.ToolChainCore_StatusCNC(CORE) != 1
    assert hmi.compile(WAVE.format(n=10), abs_mode=0) is None


def test_a_warning_callback_may_destroy_the_core_during_a_long_compile(hmi):
    # the warnings of the pass beside the compiler come from the compiling thread, in
    # order, after the pass: a host may call back into the library from them
    _compiles(hmi)
    seen = []

    def on_warn(user, info):
        seen.append(info.contents.actLine)
        hmi.lib.ToolChainCore_DestroyCNC(CORE)
        return 0

    cb = abi.MathWarning(on_warn)
    assert hmi.lib.ToolChainCore_SetCallBack(CORE, abi.CB_MATH_WARNING, 0, ctypes.cast(cb, ctypes.c_void_p)) == 0
    try:
        # the arc of radius 1 on the tool's side is dropped with 0x200000: a warning
        code = WAVE.format(n=3000).replace("G1 X10\nG40", "G1 X10\nG3 X2 Y0 I1 J0\nG1 X10\nG40")
        p = abi.GCODE_PARAMETERS.from_buffer_copy(hmi.saved)
        p.absMode = 0
        p.correctionStrategy = 0x200000
        p.correction[0].size = 2.0
        assert hmi.lib.ToolChainCore_SetGCodeParameters(CORE, ctypes.byref(p)) == 0
        assert hmi.lib.ToolChainCore_CompileFromMemory(CORE, b"comp.nc", code.encode()) == 0
        hmi.wait(lambda s: s != 1, timeout=30)
    finally:
        hmi.lib.ToolChainCore_SetCallBack(CORE, abi.CB_MATH_WARNING, 0, None)
    assert seen[:1] == [11]
    assert hmi.compile(WAVE.format(n=10), abs_mode=0) is None      # usable again
