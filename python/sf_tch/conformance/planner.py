"""The planner's run time model: GetGCodeRunTime after a simulation with calcTime = 1
against the closed form of the documented profile (docs/planner.md, docs/api.md)."""
import math

from .checks import Differs, check, expect, near

P, A, S = "planner.md", "api.md", "structures.md"


def trapezoid(length, v, acc, dec):
    """Time of a move from rest to rest with at most v (mm/s), ramps acc and dec (mm/s²)."""
    if length >= v * v / (2 * acc) + v * v / (2 * dec):
        return length / v + v / (2 * acc) + v / (2 * dec)
    peak = math.sqrt(2 * length * acc * dec / (acc + dec))
    return peak / acc + peak / dec


def run_time(host, code, name="timed.nc", **motion):
    """Simulates code with calcTime = 1 and motion[k] set from motion (k: (feed, acc,
    dec, ramp)); GetGCodeRunTime of the file."""
    def edit(p):
        p.calcTime = 1
        for k, (feed, acc, dec, ramp) in motion.items():
            m = p.motion[int(k[1:])]
            m.feed, m.acc, m.dec, m.rampType = feed, acc, dec, ramp
    host.set_params(0, edit=edit)
    host.reset_cnc(0, (0.0, 0.0, 0.0))
    host.compiled(code, name=name)
    host.reset_cnc(0)
    host.start(0, 10)
    expect(-10, host.wait(0, lambda s: s != 10), "status after the simulation")
    idx = host.lib.ToolChainCore_FileToIdx(0, host.texts.arg(name))
    return host.lib.ToolChainCore_GetGCodeRunTime(0, idx)


@check("planner", "trapezoid_line", P, "Ramps",
       "rampType 1: a line from rest to rest takes L/v + v/2a + v/2d (GetGCodeRunTime)")
def _(host):
    t = run_time(host, "G1 X100 F3000\n", m1=(3000, 500, 250, 1))
    near(trapezoid(100, 50, 500, 250), t, 1e-3, "run time of G1 X100 F3000, acc 500, dec 250")


@check("planner", "triangle_line", P, "Ramps",
       "rampType 1: a line too short to reach its feed peaks at sqrt(2 L a d / (a + d))")
def _(host):
    t = run_time(host, "G1 X2 F3000\n", m1=(3000, 500, 250, 1))
    near(trapezoid(2, 50, 500, 250), t, 1e-3, "run time of G1 X2 F3000")


@check("planner", "sine_ramp", P, "Ramps",
       "rampType 2 (sine): the time and distance of a trapezoid with 2a/π")
def _(host):
    t = run_time(host, "G1 X100 F3000\n", m1=(3000, 500, 250, 2))
    near(trapezoid(100, 50, 1000 / math.pi, 500 / math.pi), t, 1e-3, "run time with sine ramps")


@check("planner", "rapid_motion0", P, "Static limits of a part",
       "rapids run at motion[0] (feed, acc, dec)")
def _(host):
    t = run_time(host, "G0 X200\n", m0=(6000, 1000, 500, 1))
    near(trapezoid(200, 100, 1000, 500), t, 1e-3, "run time of G0 X200")


@check("planner", "collinear_full_speed", P, "Junctions",
       "two collinear lines are run through at full speed: the time of one line")
def _(host):
    t = run_time(host, "G1 X50 F3000\nG1 X100\n", m1=(3000, 500, 500, 1))
    near(trapezoid(100, 50, 500, 500), t, 1e-3, "run time of two collinear halves")


@check("planner", "stop_at_waiting_m", P, "Junctions",
       "the machine stands at a waiting M function: two moves from rest to rest")
def _(host):
    t = run_time(host, "G1 X50 F3000\nM51\nG1 X100\n", m1=(3000, 500, 500, 1))
    near(2 * trapezoid(50, 50, 500, 500), t, 1e-3, "run time with M51 between")


@check("planner", "dwell_time", P, "Junctions",
       "a dwell stands for its time: G4 H seconds adds to two moves from rest to rest")
def _(host):
    t = run_time(host, "G1 X50 F3000\nG4 H0.25\nG1 X100\n", m1=(3000, 500, 500, 1))
    near(2 * trapezoid(50, 50, 500, 500) + 0.25, t, 1e-3, "run time with a dwell of 0.25 s")


@check("planner", "angle_slowdown", P, "Junctions",
       "at an angle of endAngle or more the junction runs at minAngleFeed (here 0: from rest to rest)")
def _(host):
    def edit(p):
        p.startAngle, p.endAngle, p.minAngleFeed = 10.0, 80.0, 0.0
    host.set_params(0, edit=edit)
    t = run_time(host, "G1 X50 F3000\nG1 Y50\n", m1=(3000, 500, 500, 1))
    near(2 * trapezoid(50, 50, 500, 500), t, 2e-3, "run time round a 90° corner")


@check("planner", "force_mode_1", S, "GCODE_PARAMETERS — a core's G-code properties",
       "forceMode 1: every feed from motion[], the program's F ignored")
def _(host):
    host.set_params(0, forceMode=1)
    t = run_time(host, "G1 X100 F100\n", m1=(3000, 500, 500, 1))
    near(trapezoid(100, 50, 500, 500), t, 1e-3, "run time of G1 X100 F100 at motion[1].feed 3000")


@check("planner", "arc_length", P, "The plan",
       "an arc runs its length: a half circle of radius 10 at 50 mm/s")
def _(host):
    t = run_time(host, "G2 X20 Y0 I10 J0 F3000\n", m1=(3000, 500, 500, 1))
    near(trapezoid(math.pi * 10, 50, 500, 500), t, 1e-3, "run time of the half circle")


@check("planner", "run_time_in_getpos", S, "GM_PARAMS_ENHANCED — GetPos",
       "after a simulation with calcTime = 1 GetPos's m_cncRunTime is the estimated run time")
def _(host):
    t = run_time(host, "G1 X100 F3000\n", m1=(3000, 500, 250, 1))
    _, enh = host.pos(0)
    near(t, enh.m_cncRunTime, 1e-6, "m_cncRunTime")


@check("planner", "run_time_unknown_without_calc", A, "Compilation",
       "without calcTime = 1 a simulation computes no run time: GetGCodeRunTime stays negative")
def _(host):
    host.reset_cnc(0, (0.0, 0.0, 0.0))
    host.compiled("G1 X100 F3000\n", name="untimed.nc")
    host.reset_cnc(0)
    host.start(0, 10)
    host.wait(0, lambda s: s != 10)
    t = host.lib.ToolChainCore_GetGCodeRunTime(0, host.lib.ToolChainCore_FileToIdx(0, host.texts.arg("untimed.nc")))
    if not t < 0:
        raise Differs("a negative time", t, "GetGCodeRunTime")


@check("planner", "dwell_milliseconds", "dialect.md", "G functions",
       "G4 W is a dwell in milliseconds: G4 W250 stands 0.25 s")
def _(host):
    t = run_time(host, "G1 X50 F3000\nG4 W250\nG1 X100\n", m1=(3000, 500, 500, 1))
    near(2 * trapezoid(50, 50, 500, 500) + 0.25, t, 1e-3, "run time with G4 W250")
