# Junction speeds between two consecutive motion parts: the angle slow-down
# (startAngle, endAngle, minAngleFeed; G900 S9) and the exact stops, among them
# those of enhancedInterpolatorParameters bits 20 and 21.
from libc.math cimport acos, sqrt, fabs, M_PI

cdef extern from *:
    """
    /* a component of a unit tangent at or below this: the axis stands there */
    #define TC_AXIS_REST_EPS 1e-9
    """
    const double AXIS_REST_EPS "TC_AXIS_REST_EPS"


cdef double junction_cosine(const double *t_end, const double *t_start, uint32_t ignored) noexcept nogil:
    """Cosine of the angle between the end tangent of one part and the start tangent of
    the next (unit vectors), over the axes not in `ignored`; 1 when either moves only
    on ignored axes."""
    cdef double dot = 0.0, n0 = 0.0, n1 = 0.0, c
    cdef int k
    if ignored == 0:
        for k in range(AXES):
            dot += t_end[k] * t_start[k]
        return dot
    for k in range(AXES):
        if (ignored >> k) & 1:
            continue
        dot += t_end[k] * t_start[k]
        n0 += t_end[k] * t_end[k]
        n1 += t_start[k] * t_start[k]
    if n0 <= ANGLE_EPS * ANGLE_EPS or n1 <= ANGLE_EPS * ANGLE_EPS:
        return 1.0
    return dot / sqrt(n0 * n1)


cdef inline double junction_degrees(double cosine) noexcept nogil:
    """The angle in degrees (0..180) between two tangents whose cosine is given, clamped where
    rounding leaves it past +-1."""
    if cosine > 1.0:
        return 0.0
    if cosine < -1.0:
        return 180.0
    return acos(cosine) * (180.0 / M_PI)


cdef double angle_feed(double angle, double full, const PlanRegion *s) noexcept nogil:
    """Speed (mm/s) allowed at a junction of `angle` degrees when the parts allow
    `full`: full below startAngle, linear to minAngleFeed at endAngle, minAngleFeed above."""
    cdef double low = s.minAngleFeed / 60.0, v
    if angle <= s.startAngle:
        return full
    if angle >= s.endAngle or s.endAngle <= s.startAngle:
        v = low
    else:
        v = full + (low - full) * (angle - s.startAngle) / (s.endAngle - s.startAngle)
    if v > full:
        v = full
    return v if v > 0.0 else 0.0


cdef bint junction_stops(bint prev_rapid, bint next_rapid, const PlanRegion *s,
                         const GCODE_PARAMETERS *params) noexcept nogil:
    """The machine stands between the two motion parts (no waiting M between them)."""
    if prev_rapid and next_rapid and params.disableG0FeedOverride == 1:
        return True
    if s.stop_mode == STOP_MODE_EVERY_JUNCTION:
        return True
    if s.stop_mode == STOP_MODE_RAPID_CHANGE and prev_rapid != next_rapid:
        return True
    return False


cdef uint32_t axis_stop_axes(uint32_t enhanced, uint32_t ignore_angle) noexcept nogil:
    """The axes whose start from rest (bit 20) or reversal (bit 21) stops the
    machine at a junction: those without the tangency slow-down (bits 0-9, G900 S10);
    0 when neither bit is set."""
    if not (enhanced & (ENH_STOP_FROM_REST | ENH_STOP_ON_REVERSAL)):
        return 0
    return (ignore_angle | ((enhanced >> ENH_ANGLE_SHIFT) & AXIS_MASK)) & AXIS_MASK


cdef bint junction_axis_stops(const double *t_end, const double *t_start, uint32_t axes,
                              uint32_t enhanced) noexcept nogil:
    """enhancedInterpolatorParameters bits 20 and 21 at a junction (unit tangents: the
    end of the part before, the start of the next): bit 20, an axis of `axes` that
    stands at the end of the part before moves at the start of the next; bit 21, one
    that moves on in the opposite direction. Either: the machine stands there."""
    cdef double a, b
    cdef int k
    for k in range(AXES):
        if not ((axes >> k) & 1):
            continue
        b = t_start[k]
        if fabs(b) <= AXIS_REST_EPS:
            continue                    # it stands after the junction
        a = t_end[k]
        if fabs(a) <= AXIS_REST_EPS:
            if enhanced & ENH_STOP_FROM_REST:
                return True
        elif (a > 0.0) != (b > 0.0):
            if enhanced & ENH_STOP_ON_REVERSAL:
                return True
    return False


cdef inline bint part_stops_motion(const Part *p) noexcept nogil:
    """A non-motion part the machine waits at: waiting M functions (M0, M1 too), dwells."""
    if p.kind == PART_DWELL:
        return True
    return p.kind == PART_MFUNC and not (p.flags & FLAG_CONTINUOUS_M)
