"""The offline machine's output stage (docs/machine.md, "The output stage"): every
100 us step's position passes the spline, the IIR filter and the axis corrections on
its way to the drives. Sampled after every step on the machine's stepped clock
(ToolChainCore_TestClock, test-only), GetPos shows the interpolator's position in
m_s, the filtered one in m_calcS and the corrected one in m_calcE. Checked against
independent oracles: the bed function of an ACHS table and the bilinear
interpolation of its floats; the IIR filter as a superposition of the closed-form
step responses of H(s) over the commanded samples; the spline's delay of exactly
its buffer, on the positions and on the M functions, and its jerk on a corner."""
import ctypes
import math
import struct

import numpy as np
import pytest

from sf_tch import abi, default_ini
from test_smoothing import step_response     # the closed form of H(s), the filter's oracle

CORE = 0
KEY = abi.TC_TEST_CLOCK_KEY
T = 1e-4                                     # the machine's step, s
SETTLED_MM = 1e-6                            # the settled predicate's tolerance (docs/smoothing.md)
INI = default_ini().encode()
AXES = "XYZCBUVWAO"


@pytest.fixture
def machine(fresh_core):
    """Core 0 fresh, its INI loaded, known motion classes (F as programmed, 500 mm/s^2
    trapezoid ramps), on the stepped clock; afterwards back at the origin, on the
    wall clock, with no smoothing and no tables."""
    lib = fresh_core
    assert lib.ToolChainCore_LoadFromIni(CORE, INI, None) == 0
    p = abi.GCODE_PARAMETERS()
    assert lib.ToolChainCore_GetGCodeParameters(CORE, ctypes.byref(p)) == 0
    for k in range(0, 6):
        p.motion[k].acc = p.motion[k].dec = 500.0
        p.motion[k].rampType = 1
    p.motion[0].feed = 10000.0
    p.motion[6].dec, p.motion[6].rampType = 1000.0, 1
    assert lib.ToolChainCore_SetGCodeParameters(CORE, ctypes.byref(p)) == 0
    assert lib.ToolChainCore_TestClock(CORE, KEY, 0.0) == 0
    yield lib
    assert lib.ToolChainCore_ResetCNC(CORE, 0, 10, (ctypes.c_double * 10)()) == 0
    assert lib.ToolChainCore_DestroyCNC(CORE) == 0
    assert lib.ToolChainCore_TestClock(CORE, KEY, -1.0) == 0


def compile_program(lib, text, origin=True):
    if origin:
        assert lib.ToolChainCore_ResetCNC(CORE, 0, 10, (ctypes.c_double * 10)()) == 0
    assert lib.ToolChainCore_CompileFromMemory(CORE, b"out.nc", text.encode()) == 0
    while lib.ToolChainCore_StatusCNC(CORE) == 1:
        assert lib.ToolChainCore_TestClock(CORE, KEY, 0.0) == 0       # returns at once: nothing moves
    assert lib.ToolChainCore_StatusCNC(CORE) == -1
    info = abi.CALLBACK_INFO()
    assert lib.ToolChainCore_GetLastError(CORE, ctypes.byref(info)) == 0, info.m_fullError


def iir(lib, p, q, f, axes):
    params = (ctypes.c_double * 4)(p * 1e6, q * 1e6, f * 1e6, axes)
    assert lib.ToolChainCore_SetSmoothing(CORE, abi.TC_SMOOTHING_IIR, params) == 0


def spline(lib, points, jerk):
    params = (ctypes.c_double * 4)(points, jerk, 0, 0)
    assert lib.ToolChainCore_SetSmoothing(CORE, abi.TC_SMOOTHING_SPLINE, params) == 0


def axes(p10):
    return [getattr(p10, a.lower()) for a in AXES]


class Run:
    """A run sampled after every TestClock call of one step: commanded (m_s), output
    (m_calcS), drives (m_calcE) as (samples, 10) arrays, m_func and the status after
    each call, and the sample of every DriverMFunc call (the callbacks a step causes
    return inside its TestClock call). Each call runs step k (from 1) as sample
    k - 1, except while the machine stands at an M function answered
    TC_MFUNC_LATER: there the calls run steps only until the output settled.
    `m_answer(m)` is DriverMFunc's answer; an M answered TC_MFUNC_LATER is confirmed
    (ConfirmMFunc) `confirm_after` calls after its own, and `confirmed` lists the
    first sample after each confirmation. StopCNCEx(`stop_code`) before call
    `stop_at`. The run starts from the origin unless `origin` is False, and is
    sampled while its status is one of `running`."""

    def __init__(self, lib, regime=30, limit_s=30.0, stop_at=None, stop_code=None, origin=True,
                 m_answer=lambda m: 0, confirm_after=None, running=(30, 31, 32, 33)):
        self.m_calls = []                    # (M number, the sample it was called in)
        self.m_seen = []                     # (status, output) the driver saw at each M
        self.confirmed = []
        self.step = 0
        self.lib, self.m_answer = lib, m_answer
        thunk = abi.DriverMFunc(self._m)
        assert lib.ToolChainCore_SetCallBack(CORE, abi.CB_DRIVER_M_FUNC, 0, ctypes.cast(thunk, ctypes.c_void_p)) == 0
        rows, self.funcs, self.status = [], [], []
        pos = abi.SIMPLE_GM_PARAMS()
        if origin:
            assert lib.ToolChainCore_ResetCNC(CORE, 0, 10, (ctypes.c_double * 10)()) == 0
        assert lib.ToolChainCore_StartCNCEx(CORE, regime, None) == 0
        waiting = None                       # the sample of the M answered later
        while lib.ToolChainCore_StatusCNC(CORE) in running:
            assert self.step * T < limit_s, "the run does not end"
            if self.step == stop_at:
                assert lib.ToolChainCore_StopCNCEx(CORE, stop_code) == 0
            if waiting is not None and self.step - waiting == confirm_after:
                self._stands(lib)
                assert lib.ToolChainCore_ConfirmMFunc(CORE) == 0
                self.confirmed.append(self.step)
                waiting = None
            self.step += 1
            calls = len(self.m_calls)
            assert lib.ToolChainCore_TestClock(CORE, KEY, T) == 0
            if len(self.m_calls) > calls and m_answer(self.m_calls[-1][0]) == abi.TC_MFUNC_LATER:
                waiting = self.step
            assert lib.ToolChainCore_GetPos(CORE, 0, ctypes.byref(pos), None) == 0
            rows.append([axes(pos.m_s), axes(pos.m_calcS), axes(pos.m_calcE)])
            self.funcs.append(pos.m_func)
            self.status.append(lib.ToolChainCore_StatusCNC(CORE))
        self.thunk = thunk                   # alive while a stop's M functions may come (80)
        if lib.ToolChainCore_StatusCNC(CORE) < 0:
            assert lib.ToolChainCore_SetCallBack(CORE, abi.CB_DRIVER_M_FUNC, 0, None) == 0
        data = np.array(rows)
        self.commanded, self.output, self.drives = data[:, 0], data[:, 1], data[:, 2]

    @staticmethod
    def _stands(lib):
        """Standing at the M answered later, settled: seconds more change nothing."""
        before, after = abi.SIMPLE_GM_PARAMS(), abi.SIMPLE_GM_PARAMS()
        assert lib.ToolChainCore_GetPos(CORE, 0, ctypes.byref(before), None) == 0
        for _ in range(3):
            assert lib.ToolChainCore_TestClock(CORE, KEY, 1.0) == 0
            assert lib.ToolChainCore_StatusCNC(CORE) == 30
        assert lib.ToolChainCore_GetPos(CORE, 0, ctypes.byref(after), None) == 0
        assert bytes(before) == bytes(after)

    def _m(self, user, part):
        pos = abi.SIMPLE_GM_PARAMS()
        assert self.lib.ToolChainCore_GetPos(CORE, 0, ctypes.byref(pos), None) == 0
        self.m_calls.append((part.contents.m_func, self.step))
        self.m_seen.append((self.lib.ToolChainCore_StatusCNC(CORE), axes(pos.m_s), axes(pos.m_calcS)))
        return self.m_answer(part.contents.m_func)


# ------------------------------------------------------------------ axis corrections

def achs(letters, number, definition, values):
    """An ACHS3D??.KOR file: the letters (corrected axis first) in a 128-byte header
    whose last byte is the number; (min, max, points) per basis axis; the floats."""
    header = (letters.encode() + b"\0").ljust(127, b"\0") + bytes([number])
    block = b"".join(struct.pack("<ffI", lo, hi, n) for lo, hi, n in definition)
    return header + block + np.asarray(values, dtype="<f4").tobytes()


def load_tables(lib, paths):
    names = (ctypes.c_char_p * len(paths))(*[str(p).encode() for p in paths])
    assert lib.ToolChainCore_LoadAxisCorrections(CORE, len(paths), names) == 0


BED = [(-10.0, 30.0, 9), (-10.0, 20.0, 7)]       # X every 5 mm, Y every 5 mm


def bed_table(lib, tmp_path):
    """Z over X and Y: the bed z = 0.01 x + 0.02 y as the file's floats; returns the
    floats (x slowest) for the bilinear oracle."""
    xs, ys = (np.linspace(lo, hi, n) for lo, hi, n in BED)
    floats = np.array([[float(np.float32(0.01 * x + 0.02 * y)) for y in ys] for x in xs])
    path = tmp_path / "ACHS3D01.KOR"
    path.write_bytes(achs("ZXY", 1, BED, floats.ravel()))
    load_tables(lib, [path])
    return xs, ys, floats


def bilinear(xs, ys, floats, x, y):
    """The multilinear interpolation of the grid written out (brute force: the cell
    found by search), the edge value outside."""
    x, y = min(max(x, xs[0]), xs[-1]), min(max(y, ys[0]), ys[-1])
    i = min(int(np.searchsorted(xs, x, side="right")) - 1, len(xs) - 2)
    j = min(int(np.searchsorted(ys, y, side="right")) - 1, len(ys) - 2)
    u, v = (x - xs[i]) / (xs[i + 1] - xs[i]), (y - ys[j]) / (ys[j + 1] - ys[j])
    return ((1 - u) * (1 - v) * floats[i, j] + u * (1 - v) * floats[i + 1, j]
            + (1 - u) * v * floats[i, j + 1] + u * v * floats[i + 1, j + 1])


ZIGZAG = "G1 X5 Y3 Z1 F3000\nG1 X25 Y17\nG2 X15 Y7 I-5 J-5\nG1 X0 Y0 Z2\n"


def test_the_drives_get_the_axis_corrections_at_every_step(machine, tmp_path):
    """An ACHS table Z over X and Y of the bed z = 0.01 x + 0.02 y: at every step the
    drives' Z (m_calcE) is the position's Z plus the bed there -- the closed form
    within the floats' rounding, the bilinear interpolation of the file's floats
    exactly; X, Y and the other axes unchanged; GetPos's m_s and m_calcS are the
    uncorrected position (no filter: both the interpolator's)."""
    lib = machine
    xs, ys, floats = bed_table(lib, tmp_path)
    compile_program(lib, ZIGZAG)
    r = Run(lib)
    assert r.status[-1] == -32 and r.step > 1000
    assert np.array_equal(r.output, r.commanded)
    x, y = r.output[:, 0], r.output[:, 1]
    correction = r.drives[:, 2] - r.output[:, 2]
    assert np.abs(correction - (0.01 * x + 0.02 * y)).max() < 2e-6
    oracle = np.array([bilinear(xs, ys, floats, a, b) for a, b in zip(x, y)])
    assert np.abs(correction - oracle).max() < 1e-12
    assert np.ptp(correction) > 0.4                     # the run crossed the bed
    others = [k for k in range(10) if k != 2]
    assert np.array_equal(r.drives[:, others], r.output[:, others])
    # CorrectPosition says the same of the last position
    out = (ctypes.c_double * 10)()
    assert lib.ToolChainCore_CorrectPosition(CORE, (ctypes.c_double * 10)(*r.output[-1]), out) == 0
    assert list(out) == list(r.drives[-1])


def test_the_corrections_read_the_filtered_basis_axes(machine, tmp_path):
    """The order interpolator -> IIR -> corrections: with X filtered, the drives' Z
    is corrected at the filtered X (m_calcS), which differs from the commanded X."""
    lib = machine
    xs, ys, floats = bed_table(lib, tmp_path)
    iir(lib, 2.0, 1.0, 0.05, 0b1)
    compile_program(lib, ZIGZAG)
    r = Run(lib)
    assert r.status[-1] == -32
    assert np.abs(r.output[:, 0] - r.commanded[:, 0]).max() > 0.01
    oracle = np.array([bilinear(xs, ys, floats, a, b) for a, b in r.output[:, :2]])
    assert np.abs(r.drives[:, 2] - r.output[:, 2] - oracle).max() < 1e-12


# ------------------------------------------------------------------ the IIR filter

def filtered(u, start, p, q, f):
    """The continuous filter's output and speed after each step, its input held at
    each commanded sample for a step: the superposition of the closed-form step
    responses of the input's changes (the output of step n is the filter one step
    after sample n took effect)."""
    n = len(u)
    du = np.diff(np.concatenate([[start], u]))
    g, dg = step_response(p, q, f, T * np.arange(1, n + 1))
    return start + np.convolve(du, g)[:n], np.convolve(du, dg)[:n]


FILTERS = [("Butterworth", math.sqrt(2), 2.0), ("Bessel", 3.0, 3.0), ("critically damped", 2.0, 1.0)]


@pytest.mark.parametrize("name, p, q", FILTERS, ids=[f[0] for f in FILTERS])
def test_the_output_is_the_IIR_filter_of_the_commanded_path_and_the_run_ends_settled(machine, name, p, q):
    """IIR filter on X and Y (f = 20 ms): at every step the output is the closed form
    of H(s) over the commanded samples (within 1e-9 mm), Z is not filtered; the run
    goes on after the interpolator ended until the output has settled (within 1e-6 mm
    of the end and slower than 1e-6 mm x wn), and ends at the first such step."""
    lib = machine
    f = 0.02
    iir(lib, p, q, f, 0b011)
    compile_program(lib, "G1 X4 Y1 Z1 F6000\nG1 X6 Y-2\nG0 X0 Y0 Z0\n")
    r = Run(lib)
    assert r.status[-1] == -32
    wn = math.sqrt(q) * 2 * math.pi / f
    for axis in (0, 1):
        y, v = filtered(r.commanded[:, axis], 0.0, p, q, f)
        assert np.abs(r.output[:, axis] - y).max() < 1e-9
        assert np.abs(r.output[:, axis] - r.commanded[:, axis]).max() > 0.05    # it did filter
    assert np.array_equal(r.output[:, 2:], r.commanded[:, 2:])
    # the interpolator ended at its last change; the machine ran on until settled
    moving = np.nonzero(np.any(np.diff(r.commanded, axis=0) != 0, axis=1))[0]
    ended = moving[-1] + 1                               # the sample where the commanded stands still
    assert r.step > ended + 10
    settled = np.ones(r.step, dtype=bool)
    for axis in (0, 1):
        y, v = filtered(r.commanded[:, axis], 0.0, p, q, f)
        settled &= (np.abs(y - r.commanded[:, axis]) <= SETTLED_MM) & (np.abs(v) <= SETTLED_MM * wn)
    assert settled[-1] and not settled[ended:-1].any()
    assert np.abs(r.output[-1] - r.commanded[-1]).max() <= SETTLED_MM
    assert r.commanded[-1][:3] == pytest.approx([0, 0, 0], abs=1e-12)


# ------------------------------------------------------------------ the spline

M_PROGRAM = "G1 X10 Y5 F6000\nM1001\nG1 X20\nM3\nG1 Y0\nM1002\n"


@pytest.mark.parametrize("points", [50, 200])
def test_the_spline_delays_the_output_and_the_M_functions_by_its_buffer(machine, points):
    """A spline of N steps whose jerk limit nothing reaches (1e12 mm/s^3): the output is
    the commanded position N steps earlier, bit for bit, on every axis. The M
    functions come N steps later than without the spline, where the output reaches
    them: M1001 (continuous) on the way, M3 (waiting: the interpolator stands at it
    until the output arrived and the driver answered, so what follows is N steps later
    again), M1002 at the end; the run ends once the output stands at the end."""
    lib = machine
    compile_program(lib, M_PROGRAM)
    plain = Run(lib)
    spline(lib, points, 1e12)
    r = Run(lib)
    n = points
    assert plain.status[-1] == r.status[-1] == -32
    assert np.array_equal(r.output[n:], r.commanded[:-n])
    assert np.array_equal(r.output[:n], np.zeros((n, 10)))
    assert [m for m, _ in r.m_calls] == [m for m, _ in plain.m_calls] == [1001, 3, 1002]
    (_, m1001), (_, m3), (_, m1002) = plain.m_calls
    assert [k for _, k in r.m_calls] == [m1001 + n, m3 + n, m1002 + 2 * n]
    # the commanded path is the plain run's until M3, then N steps later
    assert np.array_equal(r.commanded[:m3], plain.commanded[:m3])
    assert np.array_equal(r.commanded[m3 + n - 1:plain.step + n], plain.commanded[m3 - 1:])
    # at each M function the output is where the plain run's interpolator was
    assert np.array_equal(r.output[m1001 + n - 1], plain.commanded[m1001 - 1])
    assert np.array_equal(r.output[m3 + n - 1], plain.commanded[m3 - 1])
    assert r.output[-1][:2] == pytest.approx([20, 0], abs=0)
    # the spline settled: its buffer and the three samples it gave out last stand at the end
    last_change = np.nonzero(np.any(np.diff(r.commanded, axis=0) != 0, axis=1))[0][-1] + 2    # its step
    assert r.step == last_change + n + 3


def polyline_distance(points, corners):
    """Each point's distance from the polyline through `corners` (brute force)."""
    best = np.full(len(points), np.inf)
    for a, b in zip(corners[:-1], corners[1:]):
        ab = b - a
        t = np.clip((points - a) @ ab / (ab @ ab), 0, 1)
        best = np.minimum(best, np.linalg.norm(points - (a + t[:, None] * ab), axis=1))
    return best


def test_the_spline_keeps_the_jerk_under_its_limit_on_a_corner(machine):
    """A corner of 17 degrees at 30 mm/s passed at speed, and the trapezoid ramps'
    jumps of acceleration: the commanded jerk is far above 1e6 mm/s^3; through a
    spline of 200 steps (the buffer docs/smoothing.md gives for velocity changes up to
    64 mm/s per axis) the output's third differences stay under the limit on both
    axes, and the output stays within 3/32 |dv| D of the programmed path (dv the
    commanded velocity's jump at the corner, D the buffer's span)."""
    lib = machine
    jerk_limit, n = 1e6, 200
    spline(lib, n, jerk_limit)
    compile_program(lib, "G1 X10 F1800\nG1 X20 Y3\n")
    r = Run(lib)
    assert r.status[-1] == -32
    jerk = lambda a: np.abs(np.diff(a[:, :2], 3, axis=0)).max(axis=0) / T ** 3
    assert jerk(r.commanded).min() > 10 * jerk_limit
    assert jerk(r.output).max() <= jerk_limit
    velocity = np.diff(r.commanded[:, :2], axis=0) / T
    corner = np.linalg.norm(np.diff(velocity, axis=0), axis=1).argmax()
    dv = np.linalg.norm(velocity[corner + 3] - velocity[corner - 3])    # the jump, over the steps around it
    assert dv > 5.0
    corners = np.array([[0.0, 0.0], [10.0, 0.0], [20.0, 3.0]])
    bound = 3 / 32 * dv * (n - 1) * T
    assert polyline_distance(r.output[:, :2], corners).max() <= bound
    assert r.output[-1][:2] == pytest.approx([20, 3], abs=0)


# ------------------------------------------------------------------ stop and reset

def test_a_stop_brakes_the_commanded_path_and_the_output_settles(machine):
    """StopCNCEx while the spline and the IIR filter are on: the interpolator brakes
    (m_s stands after v^2 / 2d), the output follows it there, and the run ends at -31
    only once the output stands within 1e-6 mm of the commanded position; the next
    start continues to the program's end."""
    lib = machine
    spline(lib, 100, 1e6)
    iir(lib, 3.0, 3.0, 0.02, 0b11)
    compile_program(lib, "G1 X40 Y10 F6000\n")
    r = Run(lib, stop_at=2000)
    assert r.status[-1] == -31
    stood = np.nonzero(np.any(np.diff(r.commanded, axis=0) != 0, axis=1))[0][-1] + 1
    assert r.step > stood + 100                          # the output caught up after the commanded stood
    assert np.abs(r.output[-1] - r.commanded[-1]).max() <= SETTLED_MM
    assert 1.0 < r.commanded[-1][0] < 39.0
    pos = abi.SIMPLE_GM_PARAMS()
    assert lib.ToolChainCore_StartCNCEx(CORE, 30, None) == 0
    while lib.ToolChainCore_StatusCNC(CORE) > 0:
        assert lib.ToolChainCore_TestClock(CORE, KEY, 0.01) == 0
    assert lib.ToolChainCore_StatusCNC(CORE) == -32
    assert lib.ToolChainCore_GetPos(CORE, 0, ctypes.byref(pos), None) == 0
    assert (pos.m_calcS.x, pos.m_calcS.y) == pytest.approx((40, 10), abs=SETTLED_MM)


def test_ResetCNC_clears_the_filters_to_the_position(machine, tmp_path):
    """ResetCNC while the filtered output trails the commanded one: the run ends at
    once; GetPos shows the reset's coordinates in every position (the drives'
    corrected); the next run's filters start standing there (its first output is
    the commanded one, not a jump from where the filter was)."""
    lib = machine
    bed_table(lib, tmp_path)
    iir(lib, 2.0, 1.0, 0.3, 0b1)
    compile_program(lib, "G1 X20 F6000\n")
    assert lib.ToolChainCore_StartCNCEx(CORE, 30, None) == 0
    assert lib.ToolChainCore_TestClock(CORE, KEY, 0.2) == 0
    pos = abi.SIMPLE_GM_PARAMS()
    assert lib.ToolChainCore_GetPos(CORE, 0, ctypes.byref(pos), None) == 0
    assert pos.m_s.x - pos.m_calcS.x > 1.0                # the output trails
    where = (ctypes.c_double * 10)(5.0, 2.0)
    assert lib.ToolChainCore_ResetCNC(CORE, 0, 10, where) == 0
    assert lib.ToolChainCore_GetPos(CORE, 0, ctypes.byref(pos), None) == 0
    for p10 in (pos.m_s, pos.m_e, pos.m_calcS):
        assert axes(p10)[:3] == [5.0, 2.0, 0.0]
    assert pos.m_calcE.z == pytest.approx(0.01 * 5 + 0.02 * 2, abs=2e-6)
    # a program from there: the filter stands at (5, 2) when it starts
    compile_program(lib, "G91 G1 X1 F600\n", origin=False)
    assert lib.ToolChainCore_StartCNCEx(CORE, 30, None) == 0
    assert lib.ToolChainCore_TestClock(CORE, KEY, T) == 0
    assert lib.ToolChainCore_GetPos(CORE, 0, ctypes.byref(pos), None) == 0
    assert pos.m_s.x - pos.m_calcS.x < 1e-3 and pos.m_calcS.x >= 5.0
    assert pos.m_calcS.y == 2.0


# ------------------------------------------------------------------ the run's halts through the filters

WAIT_PROGRAM = "G1 X10 Y5 F6000\nM7\nG1 X20 Y-5\n"
FEED = 100.0                                 # mm/s, F6000


def delayed(u, n, start):
    """The spline's oracle under an unreachable jerk limit: each sample n steps late,
    the start before."""
    return np.concatenate([np.repeat(start[None, :], n, axis=0), u[:len(u) - n]]) if n else u


def settled_iir(u, y, v, wn):
    """The settled predicate of the filtered axes at each sample."""
    return np.all((np.abs(y - u) <= SETTLED_MM) & (np.abs(v) <= SETTLED_MM * wn), axis=1)


def assert_no_jump(output, bound):
    """Consecutive samples of the output move at most `bound` mm (on X and Y)."""
    moved = np.linalg.norm(np.diff(output[:, :2], axis=0), axis=1)
    assert moved.max() <= bound, moved.max()


@pytest.mark.parametrize("points", [50, 200])
def test_a_waiting_m_answered_later_reaches_the_driver_with_the_spline_s_output(machine, points):
    """M7 answered TC_MFUNC_LATER through a spline of N steps (jerk limit unreached):
    the driver hears of it N steps after the plain run's driver does, with the output
    standing where the interpolator stands; the machine then stands (status 30, no
    position moves, however much time is granted) until ConfirmMFunc; the rest of the
    path is the plain run's, the output N steps behind it, bit for bit; no sample
    moves more than the feed allows; the run ends settled at the end."""
    lib = machine
    n = points
    compile_program(lib, WAIT_PROGRAM)
    plain = Run(lib)
    (_, m7), = plain.m_calls
    spline(lib, n, 1e12)
    hold = n + 50
    r = Run(lib, m_answer=lambda m: abi.TC_MFUNC_LATER, confirm_after=hold)
    assert plain.status[-1] == r.status[-1] == -32
    assert [m for m, _ in r.m_calls] == [7]
    called = r.m_calls[0][1]
    assert called == m7 + n
    assert r.m_seen[0][0] == 30
    assert np.array_equal(r.output[called - 1], plain.commanded[m7 - 1])
    assert not np.array_equal(r.output[called - 2], plain.commanded[m7 - 1])   # it arrived then
    # before the confirmation: the plain run's path until M7, the output N steps late
    confirmed, = r.confirmed
    assert np.array_equal(r.commanded[:m7], plain.commanded[:m7])
    assert np.all(r.commanded[m7 - 1:confirmed] == plain.commanded[m7 - 1])
    assert np.array_equal(r.output[:confirmed], delayed(r.commanded[:confirmed], n, np.zeros(10)))
    assert all(s == 30 for s in r.status[:-1])
    # standing: more time changed nothing (Run._stands); after the confirmation: the plain run's rest, the output N steps late from the standing position
    rest = r.commanded[confirmed:]
    assert np.array_equal(rest[:plain.step - m7], plain.commanded[m7:])
    assert np.array_equal(r.output[confirmed:], delayed(rest, n, plain.commanded[m7 - 1]))
    assert r.output[-1][:2] == pytest.approx([20, -5], abs=0)
    assert_no_jump(r.output, FEED * T * (1 + 1e-9))


def test_a_waiting_m_answered_later_holds_the_IIR_filtered_machine_until_confirmed(machine):
    """M7 answered TC_MFUNC_LATER, a critically damped IIR filter on X and Y: the
    driver hears of M7 when the interpolator reaches it (the filter delays no event);
    the steps go on exactly until the output settled there, then the machine stands
    until ConfirmMFunc. Over the steps that ran, the output is the closed form of H(s)
    (within 1e-9 mm); it never moves more than the feed in a step (a filter whose
    impulse response is positive never overshoots the input's speed)."""
    lib = machine
    p, q, f = 2.0, 1.0, 0.02
    wn = math.sqrt(q) * 2 * math.pi / f
    compile_program(lib, WAIT_PROGRAM)
    plain = Run(lib)
    (_, m7), = plain.m_calls
    iir(lib, p, q, f, 0b11)
    r = Run(lib, m_answer=lambda m: abi.TC_MFUNC_LATER, confirm_after=1500)
    assert r.status[-1] == -32 and all(s == 30 for s in r.status[:-1])
    assert r.m_calls == [(7, m7)]
    confirmed, = r.confirmed
    assert np.array_equal(r.commanded[:confirmed][:m7], plain.commanded[:m7])
    assert np.all(r.commanded[m7 - 1:confirmed] == plain.commanded[m7 - 1])
    # the steps before the confirmation as if each call ran one: the first settled one is the last that ran
    y = np.empty((confirmed, 2))
    v = np.empty((confirmed, 2))
    for axis in (0, 1):
        y[:, axis], v[:, axis] = filtered(r.commanded[:confirmed, axis], 0.0, p, q, f)
    settled = settled_iir(r.commanded[:confirmed, :2], y, v, wn)
    last = m7 - 1 + int(np.argmax(settled[m7 - 1:]))
    assert settled[last] and m7 + 10 < last < confirmed - 100
    assert np.abs(r.output[:last + 1, :2] - y[:last + 1]).max() < 1e-9
    assert np.all(r.output[last:confirmed] == r.output[last])          # standing: no step ran
    # the steps that ran: those until `last`, then the rest after the confirmation
    ran = np.concatenate([r.commanded[:last + 1], r.commanded[confirmed:]])
    assert np.array_equal(r.commanded[confirmed:][:plain.step - m7], plain.commanded[m7:])
    for axis in (0, 1):
        y_all, _ = filtered(ran[:, axis], 0.0, p, q, f)
        assert np.abs(r.output[confirmed:, axis] - y_all[last + 1:]).max() < 1e-9
    assert np.abs(r.output[-1] - r.commanded[-1]).max() <= SETTLED_MM
    assert r.commanded[-1][:2] == pytest.approx([20, -5], abs=1e-12)
    assert_no_jump(r.output, FEED * T * (1 + 1e-9))


SPLINE_N, IIR_PQF = 100, (3.0, 3.0, 0.02)      # the filters of the halts below: a spline, a Bessel filter


def filters_on(lib):
    spline(lib, SPLINE_N, 1e12)
    iir(lib, *IIR_PQF, 0b11)


def through_filters(commanded, start):
    """The oracle of filters_on: the commanded samples SPLINE_N steps late (the spline
    under an unreachable jerk limit), through the closed form of H(s) on X and Y;
    the output and its speed."""
    u = delayed(commanded, SPLINE_N, start)
    y, v = u.copy(), np.zeros_like(u)
    for axis in (0, 1):
        y[:, axis], v[:, axis] = filtered(u[:, axis], start[axis], *IIR_PQF)
    return y, v


def filters_bound():
    """How far the filters may move the output in a step at the feed: the spline
    delays, H(s) moves at most its speed times the integral of |h| (the closed form's
    derivative, brute force over 20 f)."""
    p, q, f = IIR_PQF
    t = np.arange(0, 20 * f, T / 10)
    _, h = step_response(p, q, f, t)
    return FEED * T * np.abs(h).sum() * T / 10 * (1 + 1e-6)


def assert_halts_once_settled(r, start, halt):
    """The output is the filters' oracle at every step (within 1e-9 mm); the run halts
    with `halt` at the first step after the interpolator stood where the output
    settled (the spline's buffer and its last three samples at the interpolator's
    position, the filtered axes within 1e-6 mm of it and slower than 1e-6 mm x wn)."""
    y, v = through_filters(r.commanded, start)
    assert np.abs(r.output - y).max() < 1e-9
    assert r.status[-1] == halt and all(s > 0 for s in r.status[:-1])
    p, q, f = IIR_PQF
    settled = settled_iir(r.commanded[:, :2], y[:, :2], v[:, :2], math.sqrt(q) * 2 * math.pi / f)
    stood = np.nonzero(np.any(np.diff(r.commanded, axis=0) != 0, axis=1))[0][-1] + 1
    settled[:stood + SPLINE_N + 3] = False       # the spline's buffer not yet at the position
    assert settled[-1] and not settled[:-1].any()
    assert np.abs(r.output[-1] - r.commanded[-1]).max() <= SETTLED_MM


def test_M0_pauses_once_the_filtered_output_settled_and_a_start_goes_on(machine):
    """M0 through the spline and the IIR filter: -33 only once the output settled at
    M0's position; StartCNCEx goes on from there to the end, the output never jumping."""
    lib = machine
    filters_on(lib)
    compile_program(lib, "G1 X10 Y5 F6000\nM0\nG1 X20 Y-5\n")
    r = Run(lib)
    assert_halts_once_settled(r, np.zeros(10), -33)
    assert r.commanded[-1][:2] == pytest.approx([10, 5], abs=1e-12)
    assert [m for m, _ in r.m_calls] == [0]
    rest = Run(lib, origin=False)
    assert_halts_once_settled(rest, r.commanded[-1], -32)
    assert rest.commanded[-1][:2] == pytest.approx([20, -5], abs=1e-12)
    assert_no_jump(np.concatenate([r.output, rest.output]), filters_bound())


def test_a_breakpoint_halts_once_the_filtered_output_settled(machine):
    """SetBreakpoint at line 3 through the spline and the IIR filter: -31 once the
    output settled at line 2's end, GetPos at line 3; the next start goes on."""
    lib = machine
    filters_on(lib)
    compile_program(lib, "G1 X10 Y0 F6000\nG1 X10 Y5\nG1 X0 Y5\n")
    assert lib.ToolChainCore_SetBreakpoint(CORE, 3, lib.ToolChainCore_FileToIdx(CORE, b"out.nc")) == 0
    r = Run(lib)
    assert_halts_once_settled(r, np.zeros(10), -31)
    assert r.commanded[-1][:2] == pytest.approx([10, 5], abs=1e-12)
    pos = abi.SIMPLE_GM_PARAMS()
    assert lib.ToolChainCore_GetPos(CORE, 0, ctypes.byref(pos), None) == 0
    assert pos.m_editorLine == 3
    rest = Run(lib, origin=False)
    assert_halts_once_settled(rest, r.commanded[-1], -32)
    assert rest.commanded[-1][:2] == pytest.approx([0, 5], abs=1e-12)


def test_backward_through_the_filters_retraces_the_path_and_settles_at_the_start(machine):
    """Backward (32, motion[2] at 25 mm/s) after a run to the end, the spline and the
    IIR filter on: the commanded path retraces the program's polyline, the output is
    the filters' oracle of it (so within the filters' lag of the path), never jumps,
    and the run ends -30 once it settled at the start."""
    lib = machine
    p = abi.GCODE_PARAMETERS()
    assert lib.ToolChainCore_GetGCodeParameters(CORE, ctypes.byref(p)) == 0
    p.motion[2].feed = 1500.0
    assert lib.ToolChainCore_SetGCodeParameters(CORE, ctypes.byref(p)) == 0
    filters_on(lib)
    compile_program(lib, "G1 X10 Y0 F6000\nG1 X10 Y5\nG1 X0 Y5\n")
    forward = Run(lib)
    assert forward.status[-1] == -32
    back = Run(lib, regime=32, origin=False)
    assert_halts_once_settled(back, forward.commanded[-1], -30)
    corners = np.array([[0.0, 0.0], [10.0, 0.0], [10.0, 5.0], [0.0, 5.0]])
    assert polyline_distance(back.commanded[:, :2], corners).max() <= 1e-9
    assert back.commanded[-1][:2] == pytest.approx([0, 0], abs=1e-9)
    assert np.ptp(back.commanded[:, 0]) == pytest.approx(10, abs=1e-9)     # the whole path
    assert_no_jump(back.output, filters_bound())


def test_a_stop_s_m_functions_reach_the_driver_once_the_filtered_output_settled(machine):
    """StopCNCEx("M8 M9") while filtered, DriverMFunc answering TC_MFUNC_LATER: the
    machine brakes, the output settles, and only then the status is 80 and M8 comes
    (the output standing there); M9 after its confirmation, -31 after M9's."""
    from test_machine import wait
    lib = machine
    filters_on(lib)
    compile_program(lib, "G1 X40 Y10 F6000\n")
    r = Run(lib, stop_at=2000, stop_code=b"M8 M9", m_answer=lambda m: abi.TC_MFUNC_LATER, running=(30,))
    assert r.status[-1] == 80
    r.status[-1] = -31                           # the halt the oracle checks: the motion's
    assert_halts_once_settled(r, np.zeros(10), -31)
    assert wait(lib, CORE, lambda s: len(r.m_calls) == 1) == 80
    (m8, called), = r.m_calls
    assert m8 == 8 and called == r.step          # after the last step
    status, commanded, output = r.m_seen[0]
    assert status == 80 and commanded == list(r.commanded[-1]) and output == list(r.output[-1])
    assert lib.ToolChainCore_ConfirmMFunc(CORE) == 0
    assert wait(lib, CORE, lambda s: len(r.m_calls) == 2) == 80
    assert r.m_calls[1] == (9, r.step) and r.m_seen[1][2] == output
    assert lib.ToolChainCore_ConfirmMFunc(CORE) == 0
    assert wait(lib, CORE, lambda s: s != 80) == -31
    assert lib.ToolChainCore_SetCallBack(CORE, abi.CB_DRIVER_M_FUNC, 0, None) == 0
