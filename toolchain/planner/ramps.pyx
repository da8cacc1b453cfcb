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


ctypedef struct Profile:      # one part: ramp up, cruise, ramp down
    double v_in, v_peak, v_out
    double t_up, t_cruise, t_down
    double s_up, s_cruise, s_down


cdef void profile_of(double length, double v_in, double v_peak, double v_out,
                     double acc, int32_t ramp_acc, double dec, int32_t ramp_dec,
                     Profile *pr) noexcept nogil:
    """The profile of a part from its plan (entry, peak, exit): times and distances of
    its three phases; the cruise takes what the ramps leave of the length."""
    pr.v_in = v_in; pr.v_peak = v_peak; pr.v_out = v_out
    pr.t_up = ramp_time(v_in, v_peak, acc, ramp_acc)
    pr.t_down = ramp_time(v_peak, v_out, dec, ramp_dec)
    pr.s_up = 0.5 * (v_in + v_peak) * pr.t_up
    pr.s_down = 0.5 * (v_peak + v_out) * pr.t_down
    pr.s_cruise = length - pr.s_up - pr.s_down
    if pr.s_cruise < 0.0:
        pr.s_cruise = 0.0
    pr.t_cruise = pr.s_cruise / v_peak if v_peak > 0.0 else 0.0


cdef double profile_speed_at(const Profile *pr, double acc, int32_t ramp_acc, double dec,
                             int32_t ramp_dec, double t) noexcept nogil:
    """Speed t seconds into the part."""
    if t < pr.t_up:
        return ramp_speed_at(pr.v_in, pr.v_peak, acc, ramp_acc, t)
    t -= pr.t_up
    if t < pr.t_cruise:
        return pr.v_peak
    return ramp_speed_at(pr.v_peak, pr.v_out, dec, ramp_dec, t - pr.t_cruise)
