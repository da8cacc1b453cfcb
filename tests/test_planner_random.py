"""Randomised invariants of the feed planner over random contours of lines and arcs
(tangent, slightly and sharply cornered joins, waiting and continuous M functions,
dwells). The geometry, the limits and the speed profile are rebuilt here from the
G-code's numbers, independently of the library; the profile is integrated numerically."""
import math
import os
import random

import numpy as np
import pytest

from sf_tch import abi
from test_planner import params, ph  # noqa: F401  (ph: the fixture)

SCALE = int(os.environ.get("SF_TCH_SLOW_SCALE", "1"))
GL_X, GL_W = np.polynomial.legendre.leggauss(24)


def random_program(rng):
    """G-code and, per part in order, ('M'|'D'|'L'|'A', geometry)."""
    x, y, h = 0.0, 0.0, rng.uniform(0, 2 * math.pi)
    lines = ["G1 X0 Y0 F{:.3f}".format(rng.uniform(600, 12000))]
    parts = [("L", ((0.0, 0.0), (0.0, 0.0)))]          # the first move goes nowhere
    for _ in range(rng.randint(5, 40)):
        kind = rng.random()
        join = rng.random()
        if join < 0.4:
            turn = 0.0
        elif join < 0.7:
            turn = math.radians(rng.uniform(1, 20)) * rng.choice((-1, 1))
        else:
            turn = math.radians(rng.uniform(30, 170)) * rng.choice((-1, 1))
        h += turn
        extra = ""
        if rng.random() < 0.1:
            extra = " M1001"
            parts.append(("M", None))
        if kind < 0.55:
            length = rng.choice((rng.uniform(0.05, 1.0), rng.uniform(1.0, 30.0)))
            e = (x + length * math.cos(h), y + length * math.sin(h))
            lines.append(f"G1 X{e[0]:.9f} Y{e[1]:.9f}{extra}")
            parts.append(("L", ((x, y), e)))
            x, y = e
        else:
            r = rng.uniform(0.5, 40.0)
            sweep = math.radians(rng.uniform(10, 300)) * rng.choice((-1, 1))
            side = 1.0 if sweep > 0 else -1.0            # centre on the left for CCW
            c = (x - side * r * math.sin(h), y + side * r * math.cos(h))
            a0 = math.atan2(y - c[1], x - c[0])
            e = (c[0] + r * math.cos(a0 + sweep), c[1] + r * math.sin(a0 + sweep))
            g = 3 if sweep > 0 else 2
            lines.append(f"G{g} X{e[0]:.9f} Y{e[1]:.9f} I{c[0] - x:.9f} J{c[1] - y:.9f}{extra}")
            parts.append(("A", (c, r, a0, sweep)))
            x, y = e
            h += sweep
        if rng.random() < 0.08:
            lines.append(rng.choice(("M50", "G4 X0.1")))
            parts.append(("D" if lines[-1].startswith("G4") else "W", None))
    return "\n".join(lines) + "\n", parts


def tangent(kind, geo, u):
    if kind == "L":
        (x0, y0), (x1, y1) = geo
        n = math.hypot(x1 - x0, y1 - y0)
        return ((x1 - x0) / n, (y1 - y0) / n) if n > 0 else None
    c, r, a0, sweep = geo
    a = a0 + u * sweep
    s = 1.0 if sweep > 0 else -1.0
    return (-s * math.sin(a), s * math.cos(a))


def length_of(kind, geo):
    if kind == "L":
        (x0, y0), (x1, y1) = geo
        return math.hypot(x1 - x0, y1 - y0)
    return abs(geo[3]) * geo[1]


def static_limit(kind, geo, feed, setting):
    """mm/s: feed, centripetal, X/Y maxFeed over sampled tangents (>= the exact limit)."""
    v = feed / 60.0
    samples = [tangent(kind, geo, u) for u in np.linspace(0.0, 1.0, 2001)]
    if kind == "A" and setting["centripetal"] > 0:
        v = min(v, math.sqrt(setting["centripetal"] * geo[1]))
    for k, fmax in enumerate(setting["axis_feed"]):
        if fmax > 0:
            reach = max(abs(t[k]) for t in samples)
            if reach > 1e-12:
                v = min(v, fmax / 60.0 / reach)
    return v


def angle_rule(angle, full, setting):
    if angle <= setting["start"]:
        return full
    low = setting["min_feed"] / 60.0
    if angle >= setting["end"]:
        return min(full, low)
    return min(full, full + (low - full) * (angle - setting["start"]) / (setting["end"] - setting["start"]))


def ramp_speed(v0, v1, a, ramp, t):
    """Speed t s into a ramp of peak acceleration a (own closed forms of the two shapes)."""
    T = ramp_duration(v0, v1, a, ramp)
    if T <= 0.0:
        return v1
    t = min(max(t, 0.0), T)
    if ramp == 1:
        return v0 + (v1 - v0) * t / T
    return v0 + (v1 - v0) * 0.5 * (1 - math.cos(math.pi * t / T))


def ramp_duration(v0, v1, a, ramp):
    return abs(v1 - v0) / a * (1.0 if ramp == 1 else math.pi / 2)


def integrate(fn, t0, t1):
    if t1 <= t0:
        return 0.0
    mid, half = 0.5 * (t0 + t1), 0.5 * (t1 - t0)
    return half * float(sum(w * fn(mid + half * x) for x, w in zip(GL_X, GL_W)))


def check_program(ph, rng):
    text, geo = random_program(rng)
    feed = float(text.split("F", 1)[1].split()[0])
    ramp = rng.choice((1, 2))
    acc, dec = rng.uniform(50, 2000), rng.uniform(50, 2000)
    setting = dict(start=rng.choice((360.0, rng.uniform(5, 60))), end=rng.uniform(60, 175),
                   min_feed=rng.uniform(10, 3000), centripetal=rng.choice((0.0, rng.uniform(10, 5000))),
                   axis_feed=[rng.choice((0.0, rng.uniform(1000, 12000))) for _ in range(2)])
    window = rng.choice((0, 0, 3, 20, -1))
    p = params(ph, motion=[None, (1000.0, acc, dec, ramp)], startAngle=setting["start"],
               endAngle=setting["end"], minAngleFeed=setting["min_feed"],
               rezerva1=abi.GCODE_REZERVA1_APPLY_UNIMPLEMENTED, centripetalAcc=setting["centripetal"],
               axis=[(k, f, 0.0, 0.0) for k, f in enumerate(setting["axis_feed"])])
    parts, error, _ = ph.plan_text(text, p, window, 0)
    assert error is None, (error, text)
    assert [{1: "LA", 2: "MW", 3: "D"}[q["kind"]].find(k) >= 0 for q, (k, _) in zip(parts, geo)] == [True] * len(geo)
    assert len(parts) == len(geo)
    prev_out, prev_motion = 0.0, None      # speed and (limit, end tangent) of the last motion part
    for q, (kind, g) in zip(parts, geo):
        assert q["v_in"] == prev_out
        if kind in "WD":
            assert q["v_in"] == 0.0 and q["v_out"] == 0.0           # the machine stands
            assert q["time"] == pytest.approx(0.1 if kind == "D" else 0.0, rel=1e-7)     # a float
            prev_motion = None
            prev_out = q["v_out"]
            continue
        if kind == "M" or length_of(kind, g) <= 1e-9:
            assert q["v_out"] == q["v_in"] and q["time"] == 0.0        # the speed passes through
            prev_out = q["v_out"]
            continue
        L = length_of(kind, g)
        assert q["length"] == pytest.approx(L, rel=1e-7)
        L = q["length"]
        limit = static_limit(kind, g, feed, setting)
        v_in, v_pk, v_out = q["v_in"], q["v_peak"], q["v_out"]
        # the G-code rounds to 1e-9 mm; the plan keeps floats
        assert max(v_in, v_out) <= v_pk * (1 + 1e-6) and v_pk <= limit * (1 + 1e-6)
        if prev_motion is None:
            assert v_in == 0.0
        else:
            t0, t1 = prev_motion[1], tangent(kind, g, 0.0)
            angle = math.degrees(math.acos(max(-1.0, min(1.0, t0[0] * t1[0] + t0[1] * t1[1]))))
            assert v_in <= angle_rule(angle, min(prev_motion[0], limit), setting) * (1 + 1e-6) + 1e-6
        # the profile: ramp up, cruise, ramp down with this test's accelerations
        t_up, t_down = ramp_duration(v_in, v_pk, acc, ramp), ramp_duration(v_pk, v_out, dec, ramp)
        t_cruise = q["time"] - t_up - t_down
        assert t_cruise >= -1e-6                                   # s; the plan keeps floats
        t_cruise = max(t_cruise, 0.0)
        t_end = t_up + t_cruise + t_down

        def speed(t):
            if t < t_up:
                return ramp_speed(v_in, v_pk, acc, ramp, t)
            if t < t_up + t_cruise:
                return v_pk
            return ramp_speed(v_pk, v_out, dec, ramp, t - t_up - t_cruise)
        travelled = (integrate(speed, 0.0, t_up) + v_pk * t_cruise
                     + integrate(speed, t_up + t_cruise, t_end))
        assert travelled == pytest.approx(L, rel=1e-6, abs=1e-4)   # mm: from the floats it keeps
        # acceleration at sampled points never above the limits
        for t0_, t1_, a in ((0.0, t_up, acc), (t_up + t_cruise, t_end, dec)):
            if t1_ - t0_ > 1e-9:
                ts = np.linspace(t0_, t1_, 64)
                vs = [speed(t) for t in ts]
                slopes = np.abs(np.diff(vs)) / np.diff(ts)
                # a short ramp's differences are near the speeds' last bits: their rounding allowed
                rounding = 4 * np.finfo(float).eps * max(map(abs, vs)) / np.diff(ts).min()
                assert slopes.max() <= a * (1 + 1e-6) + rounding
        prev_motion = (limit, tangent(kind, g, 1.0))
        prev_out = v_out
    assert prev_out == 0.0                                      # the end of the program
    return text, p, sum(q["time"] for q in parts)


def test_random_contours(ph):
    rng = random.Random(20261123)
    for _ in range(40):
        check_program(ph, rng)


@pytest.mark.slow
def test_random_contours_slow(ph):
    rng = random.Random(7)
    for _ in range(150 * SCALE):
        check_program(ph, rng)


def test_deeper_window_never_slower(ph):
    rng = random.Random(99)
    for _ in range(30):
        text, _ = random_program(rng)
        times = []
        for w in (1, 2, 8, 50, -1):
            parts, error, _ = ph.plan_text(text, None, w, 0)
            assert error is None
            times.append(sum(q["time"] for q in parts))
        assert all(a >= b * (1 - 1e-12) for a, b in zip(times, times[1:])), times


def optimum_bounds(segments, caps, n_cells=200):
    """Brute force: the time-optimal speed over a fine grid of each motion part, with
    the part's speed limit, the junction caps, constant acceleration and deceleration
    and a stop at the end. v^2 is exact at the grid nodes (a minimum of linear
    constraints in s); within a cell the time lies between the chord's and that of the
    highest speed the cell allows: returns (lower, upper) bounds of the optimal time."""
    ds, vmax, acc, dec, cap = [], [], [], [], [0.0]
    for (L, vm, a, d), c in zip(segments, caps):
        cap[-1] = min(cap[-1], c * c) if len(cap) > 1 else 0.0
        for k in range(n_cells):
            ds.append(L / n_cells)
            vmax.append(vm)
            acc.append(a)
            dec.append(d)
            cap.append(vm * vm)
        cap[-1] = vm * vm
    cap[-1] = 0.0
    # the boundary between cells of two parts: both parts' limits and the junction's
    w = cap[:]
    for k in range(1, len(w) - 1):
        w[k] = min(w[k], vmax[k - 1] ** 2, vmax[k] ** 2)
    for k in range(len(ds)):
        w[k + 1] = min(w[k + 1], w[k] + 2 * acc[k] * ds[k])
    for k in range(len(ds) - 1, -1, -1):
        w[k] = min(w[k], w[k + 1] + 2 * dec[k] * ds[k])
    lower = upper = 0.0
    for k in range(len(ds)):
        v0, v1 = math.sqrt(w[k]), math.sqrt(w[k + 1])
        upper += 2 * ds[k] / (v0 + v1)
        # the speed in the cell is at most what it reaches accelerating from the node
        # before, what it can still brake from to the node after, and the limit
        lower += max((math.sqrt(w[k] + 2 * acc[k] * ds[k]) - v0) / acc[k],
                     (math.sqrt(w[k + 1] + 2 * dec[k] * ds[k]) - v1) / dec[k], ds[k] / vmax[k])
    return lower, upper


def test_unlimited_window_is_the_brute_force_optimum(ph):
    """Random contours without stops inside (trapezoid ramps, feed, centripetal and angle
    limits): the unlimited plan lies within the brute-force bounds of the optimum, the
    vendor's window never below them."""
    rng = random.Random(4242)
    gaps = []
    for _ in range(12):
        text, geo = random_program(rng)
        text = text.replace(" M1001", "").replace("M50\n", "").replace("G4 X0.1\n", "")
        geo = [(k, g) for k, g in geo if k in "LA"]
        feed = float(text.split("F", 1)[1].split()[0])
        acc, dec = rng.uniform(50, 2000), rng.uniform(50, 2000)
        setting = dict(start=rng.uniform(5, 60), end=rng.uniform(60, 175), min_feed=rng.uniform(10, 3000),
                       centripetal=rng.uniform(10, 5000), axis_feed=[0.0, 0.0])
        p = params(ph, motion=[None, (1000.0, acc, dec, 1)], startAngle=setting["start"],
                   endAngle=setting["end"], minAngleFeed=setting["min_feed"],
                   rezerva1=abi.GCODE_REZERVA1_APPLY_UNIMPLEMENTED, centripetalAcc=setting["centripetal"])
        segments, caps, prev = [], [], None
        for kind, g in geo:
            L = length_of(kind, g)
            if L <= 1e-9:
                continue
            vm = static_limit(kind, g, feed, setting)
            if prev is None:
                caps.append(0.0)
            else:
                t0, t1 = prev[1], tangent(kind, g, 0.0)
                angle = math.degrees(math.acos(max(-1.0, min(1.0, t0[0] * t1[0] + t0[1] * t1[1]))))
                caps.append(angle_rule(angle, min(prev[0], vm), setting))
            segments.append((L, vm, acc, dec))
            prev = (vm, tangent(kind, g, 1.0))
        lower, upper = optimum_bounds(segments, caps)
        unlimited = sum(q["time"] for q in ph.plan_text(text, p, -1, 0)[0])
        vendor = sum(q["time"] for q in ph.plan_text(text, p, 0, 0)[0])
        assert lower * (1 - 1e-6) <= unlimited <= upper * (1 + 1e-6)
        assert vendor >= lower * (1 - 1e-6)
        gaps.append(upper / lower - 1)
    assert max(gaps) < 1e-3
