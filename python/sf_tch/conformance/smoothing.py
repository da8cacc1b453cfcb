"""The smoothing of the machine's output: spline and IIR filter (docs/smoothing.md).
The vendor sets it through TG Motion; a library reaches it through this project's extension
exports, so each check is not applicable where they are missing."""
import ctypes
from ctypes import c_double, c_uint64

from .checks import Differs, check, expect, near

SM = "smoothing.md"


def _smoothing(host, command, values):
    set_ = host.need("ToolChainCore_SetSmoothing")
    return set_(0, command, (c_double * 4)(*values))


def _get_smoothing(host, command):
    out = (c_double * 4)()
    expect(0, host.need("ToolChainCore_GetSmoothing")(0, command, out), f"GetSmoothing({command})")
    return tuple(out)


@check("smoothing", "smoothing_round_trip", SM, "Configuration: the vendor's Command register",
       "the vendor's examples SetSmoothing(-2, {200, 1000000}) and (-1, {3000000, 3000000, 20000, 0b101}) "
       "read back as given")
def _(host):
    try:
        expect(0, _smoothing(host, -2, (200, 1e6, 0, 0)), "SetSmoothing(-2)")
        expect(0, _smoothing(host, -1, (3e6, 3e6, 20000, 0b101)), "SetSmoothing(-1)")
        expect((200, 1e6, 0, 0), _get_smoothing(host, -2), "GetSmoothing(-2)")
        expect((3e6, 3e6, 20000, 5), _get_smoothing(host, -1), "GetSmoothing(-1)")
    finally:
        _smoothing(host, -2, (0, 0, 0, 0))
        _smoothing(host, -1, (0, 0, 0, 0))


@check("smoothing", "smoothing_bad_value", SM, "Configuration: the vendor's Command register",
       "a spline buffer outside 50 … 500 is refused and changes nothing")
def _(host):
    try:
        expect(0, _smoothing(host, -2, (100, 1e6, 0, 0)), "SetSmoothing(-2, 100)")
        expect(-1, _smoothing(host, -2, (10, 1e6, 0, 0)), "SetSmoothing(-2, 10)")
        expect((100, 1e6, 0, 0), _get_smoothing(host, -2), "GetSmoothing(-2)")
    finally:
        _smoothing(host, -2, (0, 0, 0, 0))


def _smooth(host, xs):
    fn = host.need("ToolChainCore_SmoothSamples")
    n = len(xs)
    samples = (c_double * (10 * n))()
    for i, x in enumerate(xs):
        samples[10 * i] = x
    out, settled = (c_double * (10 * n))(), c_uint64()
    expect(0, fn(0, samples, n, out, ctypes.byref(settled)), "SmoothSamples")
    return [out[10 * i] for i in range(n)], settled.value


@check("smoothing", "spline_delay", SM, "The spline",
       "the spline delays the motion by exactly its buffer of N samples where nothing exceeds the jerk limit")
def _(host):
    try:
        expect(0, _smoothing(host, -2, (50, 1e12, 0, 0)), "SetSmoothing(-2)")
        xs = [0.0] * 10 + [0.001 * i * i for i in range(100)] + [9.801] * 60
        out, _ = _smooth(host, xs)
        for i in range(len(xs)):
            want = xs[i - 50] if i >= 50 else xs[0]
            if abs(out[i] - want) > 1e-9:
                raise Differs(want, out[i], f"output sample {i}")
    finally:
        _smoothing(host, -2, (0, 0, 0, 0))


@check("smoothing", "iir_low_pass", SM, "The IIR filter",
       "the IIR filter is a low-pass of unit gain: after a step the output lags, then settles on the step")
def _(host):
    try:
        expect(0, _smoothing(host, -1, (3e6, 3e6, 20000, 1)), "SetSmoothing(-1) (Bessel, 20 ms, X)")
        xs = [0.0] + [1.0] * 2000           # 200 ms after a step of 1 mm
        out, settled = _smooth(host, xs)
        if not 0 <= out[1] < 0.5:
            raise Differs("a lagging first sample", out[1], "output after the step")
        near(1.0, out[-1], 1e-6, "the output 200 ms after the step")
        if not settled < len(xs):
            raise Differs("settled within 200 ms", settled, "settledFrom")
    finally:
        _smoothing(host, -1, (0, 0, 0, 0))
