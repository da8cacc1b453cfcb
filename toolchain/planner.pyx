# Feed planning. For now: the run-time estimate of a simulation with calcTime,
# a symmetric-free trapezoid per part (each part starts and ends at rest), which is
# an upper bound of the real motion with look-ahead.
from libc.math cimport sqrt


cdef double trapezoid_time(double length, double feed_mm_min, double acc, double dec) noexcept nogil:
    """Seconds to travel `length` from rest to rest at most at `feed` (mm/min) with
    acceleration `acc` and deceleration `dec` (mm/s^2)."""
    cdef double v, peak
    if length <= 0.0:
        return 0.0
    v = feed_mm_min / 60.0
    if v <= 0.0:
        return -1.0
    if acc <= 0.0 or dec <= 0.0:
        return length / v
    if length >= v * v / (2.0 * acc) + v * v / (2.0 * dec):
        return length / v + v / (2.0 * acc) + v / (2.0 * dec)
    peak = sqrt(2.0 * length * acc * dec / (acc + dec))
    return peak / acc + peak / dec


cdef double part_feed(const Part *p, const GCODE_PARAMETERS *params) noexcept nogil:
    """The feed a part runs at, mm/min: rapids motion[0]; per-revolution feeds with
    the spindle speed; FP scales the programmed feed."""
    cdef double feed
    if p.func == 0:
        return params.motion[0].feed
    feed = p.feed
    if not (p.flags & FLAG_FEED_PER_MIN):
        feed = feed * p.spindle
    feed = feed * p.fp
    if feed <= 0.0:
        feed = params.motion[1].feed
    return feed


cdef double part_time(const Program *prog, size_t i, const GCODE_PARAMETERS *params) noexcept nogil:
    """Estimated seconds of part i (dwell: its time; M functions: 0)."""
    cdef const Part *p = &prog.parts[i]
    cdef const GCODE_FEED *ramp
    if p.kind == PART_DWELL:
        return p.value
    if p.kind != PART_MOTION:
        return 0.0
    if p.func == 0:
        ramp = &params.motion[0]
    else:
        ramp = &params.motion[1]
    return trapezoid_time(part_length(prog, i), part_feed(p, params), ramp.acc, ramp.dec)
