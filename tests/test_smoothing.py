"""Smoothing of the machine's output (docs/smoothing.md) through
ToolChainCore_SmoothSamples, which runs a core's configuration over positions sampled
every 100 us: the IIR filter's step response against the closed form of H(s) for the
vendor's three filter types, its axis mask, the settled predicate against the closed
form; the spline's delay of exactly its buffer, its jerk under the limit and its
distance from the programmed path on corners (the bounds docs/smoothing.md states);
the configuration in the vendor's units, its errors, the INI keys."""
import ctypes
import math
from ctypes import byref

import numpy as np
import pytest

from sf_tch import abi

T = 100e-6                       # the machine's step
SETTLED_MM = 1e-6
ERR_INI_VALUE, ERR_SMOOTHING = 16, 740
P = ctypes.POINTER(ctypes.c_double)


def set_smoothing(lib, command, params, core=0):
    return lib.ToolChainCore_SetSmoothing(core, command, (ctypes.c_double * 4)(*params))


def get_smoothing(lib, command, core=0):
    params = (ctypes.c_double * 4)()
    assert lib.ToolChainCore_GetSmoothing(core, command, params) == 0
    return list(params)


def iir(lib, p, q, f, axes, core=0):
    """The IIR filter in the vendor's units: p, q and f (seconds) times 1e6."""
    assert set_smoothing(lib, abi.TC_SMOOTHING_IIR, (p * 1e6, q * 1e6, f * 1e6, axes), core) == 0


def spline(lib, points, jerk, core=0):
    assert set_smoothing(lib, abi.TC_SMOOTHING_SPLINE, (points, jerk, 0, 0), core) == 0


def smooth(lib, samples, core=0):
    """(smoothed samples, settledFrom) of an (n, 10) array."""
    x = np.ascontiguousarray(samples, dtype=float)
    out = np.empty_like(x)
    settled = ctypes.c_uint64(12345)
    assert lib.ToolChainCore_SmoothSamples(core, x.ctypes.data_as(P), len(x), out.ctypes.data_as(P), byref(settled)) == 0
    return out, settled.value


def call_error(lib, core=0):
    info = abi.CALLBACK_INFO()
    assert lib.ToolChainCore_GetLastCallError(core, byref(info)) == 1
    return info.stringId, info.actLine, info.m_fullError.decode()


# ------------------------------------------------------------------ IIR

def step_response(p, q, f, t):
    """The unit step response of H(s) = q / ((s/w)^2 + p (s/w) + q), w = 2 pi / f, and
    its derivative: the textbook forms in the natural frequency wn = sqrt(q) w and the
    damping ratio z = p / (2 sqrt(q))."""
    wn = math.sqrt(q) * 2 * math.pi / f
    z = p / (2 * math.sqrt(q))
    if abs(z - 1) < 1e-12:
        return 1 - (1 + wn * t) * np.exp(-wn * t), wn * wn * t * np.exp(-wn * t)
    if z < 1:
        wd = wn * math.sqrt(1 - z * z)
        decay = np.exp(-z * wn * t)
        y = 1 - decay * (np.cos(wd * t) + z / math.sqrt(1 - z * z) * np.sin(wd * t))
        return y, decay * wn / math.sqrt(1 - z * z) * np.sin(wd * t)
    r1, r2 = -wn * (z - math.sqrt(z * z - 1)), -wn * (z + math.sqrt(z * z - 1))
    y = 1 - (r2 * np.exp(r1 * t) - r1 * np.exp(r2 * t)) / (r2 - r1)
    return y, -r1 * r2 * (np.exp(r1 * t) - np.exp(r2 * t)) / (r2 - r1)


FILTERS = [  # the vendor's table, and an overdamped one
    ("Butterworth", math.sqrt(2), 2.0),
    ("Bessel", 3.0, 3.0),
    ("critically damped", 2.0, 1.0),
    ("overdamped", 3.0, 1.0),
]


@pytest.mark.parametrize("name, p, q", [f for f in FILTERS], ids=[f[0] for f in FILTERS])
@pytest.mark.parametrize("f", [0.002, 0.02, 0.3])
def test_iir_step_response_is_the_closed_form(fresh_core, name, p, q, f):
    """A step of 1 mm on axis 0 after one standing sample: sample k is the continuous
    filter's output k periods after the step, on the axes of the mask only; the run
    has settled from the first sample where the closed form is within 1e-6 mm and
    slower than 1e-6 mm x wn for good."""
    iir(fresh_core, p, q, f, 0b1000000101)
    n = int(12 * f / T) + 200
    x = np.zeros((n, 10))
    x[1:, 0] = x[1:, 2] = x[1:, 9] = 1.0
    x[1:, 1] = -3.0                                     # not filtered
    y, settled_from = smooth(fresh_core, x)
    t = np.arange(n) * T
    expected, speed = step_response(p, q, f, t)
    expected[0] = speed[0] = 0.0
    for axis in (0, 2, 9):
        assert np.abs(y[:, axis] - expected).max() < 1e-12
    assert np.array_equal(y[:, 1], x[:, 1])
    assert np.array_equal(y[:, 3:9], x[:, 3:9])
    wn = math.sqrt(q) * 2 * math.pi / f
    unsettled = np.nonzero((np.abs(expected - 1) > SETTLED_MM) | (np.abs(speed) > SETTLED_MM * wn))[0]
    assert settled_from == unsettled[-1] + 1 < n
    assert abs(y[settled_from, 0] - 1) <= SETTLED_MM


def slowest_time_constant(p, q, f):
    """1 / the slower pole's decay rate of H(s) in seconds, from numpy's roots of its
    denominator (s/w)^2 + p (s/w) + q in the variable s/w (w = 2 pi / f); inf when the
    coefficients overflow."""
    w = 2 * math.pi / f
    with np.errstate(all="ignore"):
        roots = np.roots([1.0, p, q]) * w
    rate = -roots.real.max()
    return 1 / rate if np.isfinite(rate) and rate > 0 else math.inf


@pytest.mark.parametrize("p, q, f", [(1, 1, 1), (1e12, 1, 1), (1, 1e12, 1), (1e12, 1e12, 1), (1, 1, 1e12),
                                     (3e6, 1e6, 1), (3e6, 1e6, 1e12), (1, 1e12, 1e12), (1e12, 1e-3, 1),
                                     (1e-300, 1e-300, 1e-300), (3e6, 3e6, 20000), (2e6, 1e6, 1e5)])
def test_iir_at_the_extremes_of_its_registers(fresh_core, p, q, f):
    """Register values from 1e-300 to 1e12 (p, q from 1e-306 to 1e6, f from 1e-306 s to 11
    days): a setting whose slowest time constant (numpy's roots of H(s)'s denominator) is
    above 1 s is refused, since a stopped machine would take as long to rest; the others
    give a finite output between the step's ends (it may overshoot with little damping)."""
    tau = slowest_time_constant(p * 1e-6, q * 1e-6, f * 1e-6)
    rc = set_smoothing(fresh_core, -1, (p, q, f, 1))
    if not tau <= 1.0:
        assert rc == -1
        number, _, text = call_error(fresh_core)
        assert number == ERR_SMOOTHING and "slowest time constant" in text and "above 1 s" in text, text
        return
    assert rc == 0, call_error(fresh_core)
    x = np.zeros((2000, 10))
    x[1:, 0] = 1.0
    y = smooth(fresh_core, x)[0][:, 0]
    assert np.all(np.isfinite(y)) and np.abs(y).max() <= 2.0


@pytest.mark.parametrize("seed", range(6))
def test_every_accepted_iir_setting_settles_from_the_largest_step(fresh_core, seed):
    """Random settings near the bound (time constants 0.1 .. 1 s, any damping): a step of
    2e6 mm (the whole range) settles within 35 time constants (ln(2e12) = 28.3)."""
    rng = np.random.default_rng(seed)
    while True:
        p, q, f = 10 ** rng.uniform(-1, 1.5), 10 ** rng.uniform(-1, 1), 10 ** rng.uniform(-1, 1.5)
        tau = slowest_time_constant(p, q, f)
        if 0.1 <= tau <= 1.0:
            break
    iir(fresh_core, p, q, f, 1)
    n = int(35 * tau / T) + 10
    x = np.full((n, 10), -1e6)
    x[1:, 0] = 1e6
    y, settled_from = smooth(fresh_core, x)
    assert settled_from < n and abs(y[-1, 0] - 1e6) <= SETTLED_MM


def test_iir_overshoots_as_the_vendor_table_says(fresh_core):
    """Butterworth (as the vendor sets it) overshoots, Bessel a little, the critically
    damped filter never; each within about f of its target (the slowest, critically
    damped, at 98 % after 0.93 f)."""
    f = 0.01
    peaks, at98 = {}, {}
    for name, p, q in FILTERS[:3]:
        iir(fresh_core, p, q, f, 1)
        x = np.zeros((1000, 10))
        x[1:, 0] = 1.0
        y = smooth(fresh_core, x)[0][:, 0]
        peaks[name] = y.max() - 1
        at98[name] = np.argmax(y >= 0.98) * T / f
    assert peaks["Butterworth"] > 0.1 and 0 < peaks["Bessel"] < 0.01 and peaks["critically damped"] < 0
    assert at98["critically damped"] == pytest.approx(0.93, abs=0.01)
    assert at98["Butterworth"] < at98["Bessel"] < at98["critically damped"]


# ------------------------------------------------------------------ spline

def corner(v_in, v_out, n, corner_time, start=(0.0, 0.0, 5.0)):
    """Samples of straight moves at constant velocities (x y z) meeting at corner_time,
    and the corner point."""
    t = np.arange(n) * T
    before = np.minimum(t, corner_time)[:, None]
    after = np.maximum(t - corner_time, 0)[:, None]
    x = np.zeros((n, 10))
    x[:, :3] = np.asarray(start) + before * np.asarray(v_in) + after * np.asarray(v_out)
    return x, np.asarray(start) + corner_time * np.asarray(v_in)


def distance_to_path(points, corner_point, v_in, v_out):
    """Distance of each point to the programmed path: the ray ending at the corner and
    the ray leaving it."""
    best = np.full(len(points), np.inf)
    for direction, sign in ((np.asarray(v_in, float), -1), (np.asarray(v_out, float), 1)):
        u = direction / np.linalg.norm(direction)
        rel = points - corner_point
        s = np.maximum(sign * rel @ u, 0)
        best = np.minimum(best, np.linalg.norm(rel - sign * s[:, None] * u, axis=1))
    return best


@pytest.mark.parametrize("points, v_in, v_out", [
    (200, (50.0, 0.0, 0.0), (0.0, 50.0, 0.0)),          # 90 degrees at 3 m/min
    (500, (100.0, 20.0, 0.0), (-60.0, 80.0, 10.0)),     # 120 degrees, the speed changes, z joins
    (50, (0.5, 0.0, 0.1), (0.3, 0.4, 0.1)),             # a short buffer, slow
])
def test_spline_keeps_the_jerk_under_the_limit_on_a_corner(fresh_core, points, v_in, v_out):
    """A start from rest, then a corner: each axis's jerk (the output's third
    differences) stays under 1,000,000 mm/s^3 and under the bound of docs/smoothing.md,
    6 |dv| / D^2 (1 + 5 / (points - 1)), D = (points - 1) periods, dv the axis's change
    of velocity; the output stays within 3/32 |dv| D of where the input was a buffer
    earlier (dv now the change of the velocity vector), and so of the programmed path; outside the two blends the output is the input
    delayed by the buffer, bit for bit."""
    jerk = 1e6
    spline(fresh_core, points, jerk)
    start = points + 100                                 # standing until this sample
    bend = start + 2 * points                            # the corner between this sample and the next
    n = bend + 3 * points + 100
    x, corner_point = corner(v_in, v_out, n, (bend + 0.37) * T)
    x[:start] = x[start]
    y, _ = smooth(fresh_core, x)
    D = (points - 1) * T
    dv = np.subtract(v_out, v_in)
    axis_jerk = np.abs(np.diff(y[:, :3], 3, axis=0)) / T ** 3
    assert axis_jerk.max() <= jerk
    bound = 6 * np.maximum(np.abs(dv), np.abs(v_in)) / D ** 2 * (1 + 5 / (points - 1))
    assert np.all(axis_jerk.max(axis=0) <= bound * 1.001), (axis_jerk.max(axis=0), bound)
    delayed = np.vstack([np.repeat(x[:1], points, 0), x[:-points]])
    index = np.arange(n)
    blends = [(index >= i + points // 2 - 1) & (index <= i + 3 * points // 2 + 2) for i in (start, bend)]
    outside = ~(blends[0] | blends[1])
    assert np.array_equal(y[outside], delayed[outside])
    assert not np.array_equal(y[blends[1]], delayed[blends[1]])
    assert np.array_equal(y[:, 3:], x[:, 3:])
    largest_dv = max(np.linalg.norm(dv), np.linalg.norm(v_in))     # the corner's, the start's
    assert np.linalg.norm(y[:, :3] - delayed[:, :3], axis=1).max() <= 3 / 32 * largest_dv * D * 1.001
    deviation = distance_to_path(y[:, :3], corner_point, v_in, v_out)
    assert deviation.max() <= 3 / 32 * np.linalg.norm(dv) * D * 1.001


def test_a_buffer_too_short_for_the_limit_does_what_it_can(fresh_core):
    """50 steps (5 ms) cannot turn 50 mm/s on x into 50 mm/s on y under 1,000,000 mm/s^3:
    the jerk stays at the bound 6 |dv| / D^2 (1 + 5 / 49), two orders of magnitude below
    the unsmoothed corner's."""
    spline(fresh_core, 50, 1e6)
    x, _ = corner((50.0, 0.0, 0.0), (0.0, 50.0, 0.0), 2000, (1000 + 0.5) * T)
    x[:500] = x[500]
    y, _ = smooth(fresh_core, x)
    bound = 6 * 50 / (49 * T) ** 2 * (1 + 5 / 49)
    smoothed = np.abs(np.diff(y[:, :2], 3, axis=0)).max() / T ** 3
    raw = np.abs(np.diff(x[:, :2], 3, axis=0)).max() / T ** 3
    assert 1e6 < smoothed <= bound * 1.001 and raw > 100 * smoothed


@pytest.mark.parametrize("points", [50, 200, 500])
def test_spline_delays_by_its_buffer(fresh_core, points):
    """Where no axis's jerk exceeds the limit, the output is the input `points` samples
    later, bit for bit: a start from rest with continuous acceleration, a circle of
    r = 20 mm at up to 80 mm/s on x and y (jerk about v^3/r^2 = 1280 mm/s^3), z along."""
    spline(fresh_core, points, 1e6)
    n = 6000
    t = np.arange(n) * T
    w = 2.0
    phase = w * t - np.sin(w * t)          # from rest, the acceleration rising from 0
    x = np.zeros((n, 10))
    x[:, 0] = 3 + 20 * np.cos(phase)
    x[:, 1] = -1 + 20 * np.sin(phase)
    x[:, 2] = 0.5 * phase
    y, settled_from = smooth(fresh_core, x)
    assert np.array_equal(y[:points], np.repeat(x[:1], points, 0))
    assert np.array_equal(y[points:], x[:-points])
    assert settled_from == n


def test_spline_and_iir_together_settle_on_the_last_input(fresh_core):
    """A move that stops: the run's end is the first sample from which the output stays
    on the last input; the spline holds it back by its buffer at least."""
    spline(fresh_core, 100, 1e6)
    iir(fresh_core, 2.0, 1.0, 0.005, 0b11)
    x, _ = corner((80.0, 0.0, 0.0), (0.0, -80.0, 0.0), 3000, 0.1)
    stop = 2000
    x[stop:] = x[stop - 1]
    y, settled_from = smooth(fresh_core, x)
    assert stop + 100 < settled_from < len(x)
    assert np.abs(y[settled_from:, :3] - x[-1, :3]).max() <= SETTLED_MM
    assert np.abs(y[settled_from - 1, :2] - x[-1, :2]).max() > 0
    spline(fresh_core, 0, 0)
    iir(fresh_core, 0, 0, 0, 0)
    y, settled_from = smooth(fresh_core, x)             # off: the input itself, settled once it stands
    assert np.array_equal(y, x) and settled_from == 0


# ------------------------------------------------------------------ configuration

def test_the_configuration_round_trips_in_the_vendor_units(fresh_core):
    assert get_smoothing(fresh_core, abi.TC_SMOOTHING_SPLINE) == [0, 0, 0, 0]
    assert get_smoothing(fresh_core, abi.TC_SMOOTHING_IIR) == [0, 0, 0, 0]
    assert set_smoothing(fresh_core, -2, (200, 1000000, 7, 7)) == 0
    assert set_smoothing(fresh_core, -1, (1414214, 2000000, 20000, 0xFFFFF005)) == 0
    assert get_smoothing(fresh_core, -2) == [200, 1000000, 0, 0]
    assert get_smoothing(fresh_core, -1) == [1414214, 2000000, 20000, 0xFFFFF005]
    assert get_smoothing(fresh_core, -2, core=1) == [0, 0, 0, 0]
    lib = fresh_core
    params = (ctypes.c_double * 4)()
    for call in (lib.ToolChainCore_SetSmoothing, lib.ToolChainCore_GetSmoothing):
        assert call(0, 0, params) == -1 and call(0, -3, params) == -1 and call(0, -1, None) == -1
        assert call(3, -1, params) == abi.TOOL_CHAIN_BAD_INTR_INDEX


@pytest.mark.parametrize("command, params, index, why", [
    (-2, (49, 1e6, 0, 0), 0, "the spline's buffer: 0 (off) or 50..500 steps"),
    (-2, (501, 1e6, 0, 0), 0, "50..500"),
    (-2, (100.5, 1e6, 0, 0), 0, "50..500"),
    (-2, (-1, 1e6, 0, 0), 0, "not a number in <0, 1e12>"),
    (-2, (200, float("nan"), 0, 0), 1, "not a number"),
    (-2, (200, 2e12, 0, 0), 1, "not a number in <0, 1e12>"),
    (-2, (200, 0, 0, 0), 1, "a spline that is on needs a jerk limit above 0 mm/s^3"),
    (-1, (-1, 1, 1, 1), 0, "not a number"),
    (-1, (1, float("inf"), 1, 1), 1, "not a number"),
    (-1, (1, 1, 1, 1.5), 3, "a bit mask, a whole number"),
    (-1, (1, 1, 1, 2.0 ** 32), 3, "a whole number below 2^32"),
    (-1, (0, 1e6, 1e4, 1), 0, "an IIR filter on some axis needs p, q and f above 0"),
    (-1, (1e6, 1e6, 0, 4), 2, "needs p, q and f"),
])
def test_values_that_do_not_fit_change_nothing(fresh_core, command, params, index, why):
    before = get_smoothing(fresh_core, command)
    assert set_smoothing(fresh_core, command, params) == -1
    number, _, text = call_error(fresh_core)
    assert number == ERR_SMOOTHING and f"Smoothing, Command {command}, Command_Parameter[{index}] = " in text
    assert why in text, text
    assert get_smoothing(fresh_core, command) == before


def test_an_iir_mask_of_axes_above_the_tenth_filters_nothing(fresh_core):
    """The vendor uses the first ten bits only."""
    assert set_smoothing(fresh_core, -1, (0, 0, 0, 0xFC00)) == 0
    x = np.zeros((100, 10))
    x[1:] = 1.0
    assert np.array_equal(smooth(fresh_core, x)[0], x)


def test_smooth_samples_arguments(fresh_core):
    lib = fresh_core
    settled = ctypes.c_uint64(7)
    assert lib.ToolChainCore_SmoothSamples(0, None, 0, None, byref(settled)) == 0 and settled.value == 0
    x = np.zeros((5, 10))
    assert lib.ToolChainCore_SmoothSamples(0, None, 5, x.ctypes.data_as(P), None) == -1
    assert lib.ToolChainCore_SmoothSamples(0, x.ctypes.data_as(P), 5, None, None) == -1
    x[3, 7] = float("nan")
    assert lib.ToolChainCore_SmoothSamples(0, x.ctypes.data_as(P), 5, x.ctypes.data_as(P), None) == -1
    for beyond in (1.7e308, -1.01e30):      # beyond the address words' bound: refused, out untouched
        x[3, 7] = beyond
        out = np.full((5, 10), 7.0)
        assert lib.ToolChainCore_SmoothSamples(0, x.ctypes.data_as(P), 5, out.ctypes.data_as(P), None) == -1
        assert np.all(out == 7.0)
    x[3, 7] = 1e30
    assert lib.ToolChainCore_SmoothSamples(0, x.ctypes.data_as(P), 5, x.ctypes.data_as(P), None) == 0
    assert lib.ToolChainCore_SmoothSamples(3, None, 0, None, None) == abi.TOOL_CHAIN_BAD_INTR_INDEX
    iir(lib, 2.0, 1.0, 0.01, 1)                          # in place
    x = np.zeros((300, 10))
    x[1:, 0] = 1.0
    expected = smooth(lib, x)[0]
    assert lib.ToolChainCore_SmoothSamples(0, x.ctypes.data_as(P), 300, x.ctypes.data_as(P), None) == 0
    assert np.array_equal(x, expected)


# ------------------------------------------------------------------ INI

def test_the_ini_keys(fresh_core, tmp_path):
    ini = tmp_path / "m.ini"
    ini.write_text("[Smoothing]\nSplinePoints = 200\nSplineJerk=1000000\nIirP=3000000\nIirQ=3000000\n"
                   "IirF=20000\nIirAxes=0x5\n")
    assert fresh_core.ToolChainCore_LoadFromIni(1, str(ini).encode(), None) == 0
    assert get_smoothing(fresh_core, -2, core=1) == [200, 1e6, 0, 0]
    assert get_smoothing(fresh_core, -1, core=1) == [3e6, 3e6, 20000, 5]
    ini.write_text("[Smoothing]\nSplinePoints=0\n")      # one key: the others stay
    assert fresh_core.ToolChainCore_LoadFromIni(1, str(ini).encode(), None) == 0
    assert get_smoothing(fresh_core, -2, core=1) == [0, 1e6, 0, 0]


@pytest.mark.parametrize("text, line, why", [
    ("[Smoothing]\nSplinePoints=20\n", 2, "[Smoothing] SplinePoints: Smoothing, Command -2, Command_Parameter[0] = 20"),
    ("[Smoothing]\nIirF=abc\n", 2, "[Smoothing] IirF = 'abc' is not a number"),
    ("[Smoothing]\nIirAxes=1\n", 0, "[Smoothing]: Smoothing, Command -1, Command_Parameter[0] = 0: an IIR filter on"),
    ("[Smoothing]\nSplineJerk=0\nSplinePoints=60\n", 0, "a spline that is on needs a jerk limit"),
])
def test_ini_values_that_do_not_fit_apply_nothing(fresh_core, tmp_path, text, line, why):
    ini = tmp_path / "m.ini"
    ini.write_text(text + "[GCodeParameters]\ncorrection0=0.5\n")
    assert fresh_core.ToolChainCore_LoadFromIni(0, str(ini).encode(), None) == abi.TOOL_CHAIN_XEXEC
    number, got_line, message = call_error(fresh_core)
    assert number == ERR_INI_VALUE and got_line == line and why in message, message
    params = abi.GCODE_PARAMETERS()
    fresh_core.ToolChainCore_GetGCodeParameters(0, byref(params))
    assert params.correction[0].size == 0.0
    assert get_smoothing(fresh_core, -2) == [0, 0, 0, 0] and get_smoothing(fresh_core, -1) == [0, 0, 0, 0]
