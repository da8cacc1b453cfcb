# The speed profile of one part, the one the plan and the offline machine share:
# from the speed it is entered at up to its cap, a cruise, down to the highest exit
# the parts after it allow (the backward pass, passes.pyx plan_backward) -- the
# fastest its accelerations allow. profile_plan computes it in closed form (the
# compile for every part; the machine again where the host changed something: the
# start, the override, a stop), profile_at samples it (the machine's step), as a
# trajectory generator computes a trajectory once and samples it at any time.
from libc.math cimport sqrt


cdef inline void profile_plan(Profile *p, const PlanNode *nd, double v_in, const PlanNode *next,
                              Reciprocals *rc) noexcept nogil:
    """The fastest profile over nd.length from v_in, under nd.vmax (above it -- a
    lowered override, a stop -- it brakes to it first), ending at most at the speed
    the node after it may be entered at (next.entry2, squared: the backward pass's;
    NULL: rest), or at the lowest speed braking all the way allows when that is
    higher (entered faster than the plan foresaw). Ramps with the equivalent
    accelerations nd.acc, nd.dec; rc keeps their reciprocals between calls (runs of
    parts share them, and a part that cruises into its junction's limit takes no
    square root)."""
    cdef double a = nd.acc, d = nd.dec, L = nd.length, cap = nd.vmax
    cdef double in2 = v_in * v_in
    cdef double out2 = min(next.entry2 if next != NULL else 0.0, in2 + 2.0 * a * L)
    cdef double lowest2 = in2 - nd.brake2
    cdef double v_out, peak, peak2, cruise
    if out2 < lowest2 - SPEED2_REL_EPS * in2:   # (not where rounding alone puts it below)
        out2 = lowest2
    if next != NULL and out2 == next.jin2:
        v_out = next.jin
    else:
        v_out = sqrt(out2)
    if a != rc.acc:
        rc.acc = a
        rc.half_inv_acc = 0.5 / a
    if d != rc.dec:
        rc.dec = d
        rc.half_inv_dec = 0.5 / d
    if cap != rc.vmax:
        rc.vmax = cap
        rc.inv_vmax = 1.0 / cap
    p.v_in = v_in
    p.v_out = v_out
    p.length = L
    p.ramp = nd.ramp
    if v_in <= cap:
        peak2 = cap * cap
        cruise = L - (peak2 - in2) * rc.half_inv_acc - (peak2 - out2) * rc.half_inv_dec
        if cruise >= 0.0:
            peak = cap
            p.t2 = cruise * rc.inv_vmax
        else:                           # no room to cruise: the ramps meet below the cap
            peak = sqrt((2.0 * a * d * L + d * in2 + a * out2) / (a + d))
            if peak < v_in:
                peak = v_in
            if peak < v_out:
                peak = v_out
            p.t2 = 0.0
        p.t1 = (peak - v_in) * 2.0 * rc.half_inv_acc
    else:                               # above the cap: brake to it, cruise, brake to the exit
        cruise = L - (in2 - out2) * rc.half_inv_dec
        if cruise < 0.0:
            cruise = 0.0
        if out2 <= cap * cap:
            peak = cap
            p.t2 = cruise * rc.inv_vmax
        else:                           # it cannot even reach the cap: braking all the way
            peak = v_in
            p.t2 = cruise / v_in
        p.t1 = (v_in - peak) * 2.0 * rc.half_inv_dec
    p.v_peak = peak
    p.t3 = (peak - v_out) * 2.0 * rc.half_inv_dec


cdef inline void profile_at(const Profile *p, double t, double *d, double *v) noexcept nogil:
    """Distance along the part and speed t seconds into the profile (at and after its
    end: its length and exit speed)."""
    cdef double rest
    if t < p.t1:
        d[0] = ramp_distance_in(p.v_in, p.v_peak, p.t1, p.ramp, t)
        v[0] = ramp_speed_in(p.v_in, p.v_peak, p.t1, p.ramp, t)
        return
    t -= p.t1
    if t < p.t2:
        d[0] = 0.5 * (p.v_in + p.v_peak) * p.t1 + p.v_peak * t
        v[0] = p.v_peak
        return
    t -= p.t2
    if t >= p.t3:
        d[0] = p.length
        v[0] = p.v_out
        return
    # the last ramp measured back from the end: the profile ends at its length exactly
    rest = 0.5 * (p.v_peak + p.v_out) * p.t3 - ramp_distance_in(p.v_peak, p.v_out, p.t3, p.ramp, t)
    d[0] = p.length - rest
    v[0] = ramp_speed_in(p.v_peak, p.v_out, p.t3, p.ramp, t)
