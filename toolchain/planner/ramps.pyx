# Speed ramps between two speeds, closed forms (the plan, and later the machine's
# re-planning: stop, override, continue from rest). rampType 1: trapezoid, constant
# acceleration a. rampType 2: sine, the acceleration is a half sine wave that starts
# and ends at 0 and peaks at a: v(t) = v0 + (v1 - v0) (1 - cos(pi t / T)) / 2 with
# T = pi |v1 - v0| / (2 a). Its time and distance are those of a trapezoid with
# 2a/pi, so the passes plan both with one "equivalent" acceleration.
from libc.math cimport fabs, cos, sin, M_PI

cdef enum:
    RAMP_TRAPEZOID = 1
    RAMP_SINE = 2


cdef inline double ramp_equivalent_acc(double acc, int32_t ramp_type) noexcept nogil:
    """The constant acceleration with the same time and distance as the ramp."""
    if ramp_type == RAMP_SINE:
        return acc * (2.0 / M_PI)
    return acc


cdef inline double ramp_time(double v0, double v1, double acc, int32_t ramp_type) noexcept nogil:
    """Seconds from speed v0 to v1 (mm/s) with the ramp's peak acceleration acc."""
    return fabs(v1 - v0) / ramp_equivalent_acc(acc, ramp_type)


cdef inline double ramp_distance(double v0, double v1, double acc, int32_t ramp_type) noexcept nogil:
    """Path travelled from v0 to v1: (v0 + v1)/2 times the ramp's time for both shapes."""
    return 0.5 * (v0 + v1) * ramp_time(v0, v1, acc, ramp_type)


cdef inline double ramp_speed_at(double v0, double v1, double acc, int32_t ramp_type, double t) noexcept nogil:
    """Speed t seconds into the ramp (t in [0, ramp_time])."""
    cdef double T = ramp_time(v0, v1, acc, ramp_type)
    if T <= 0.0 or t >= T:
        return v1
    if t <= 0.0:
        return v0
    if ramp_type == RAMP_SINE:
        return v0 + (v1 - v0) * 0.5 * (1.0 - cos(M_PI * t / T))
    return v0 + (v1 - v0) * t / T


cdef inline double ramp_distance_at(double v0, double v1, double acc, int32_t ramp_type, double t) noexcept nogil:
    """Path travelled t seconds into the ramp."""
    cdef double T = ramp_time(v0, v1, acc, ramp_type)
    if T <= 0.0:
        return 0.0
    if t >= T:
        return 0.5 * (v0 + v1) * T
    if t <= 0.0:
        return 0.0
    if ramp_type == RAMP_SINE:
        return v0 * t + (v1 - v0) * 0.5 * (t - T / M_PI * sin(M_PI * t / T))
    return v0 * t + (v1 - v0) * 0.5 * t * t / T
