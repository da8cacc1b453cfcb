# The corner between two consecutive offset elements a -> b: where the tool path
# leaves a and enters b, and what (if anything) is inserted between them.
#   0. parts removed in between (crossing, negative arcs): only the intersection joins;
#   1. tangent join (turn below tolerance[2]): the perpendicular points coincide;
#   2. inner corner: the intersection of the two offsets (they overlap there);
#   3. outer corner: an arc about the programmed corner (radius = tool radius), or with
#      CORR_CORNER_INTERSECTION the intersection of the extended offsets when it lies
#      closer than factor x radius to the corner.
from libc.math cimport fabs


cdef int corner_resolve(CompEl *a, CompEl *b, const CompCfg *cfg) noexcept nogil:
    """Sets a.pe, a.ins/a.ins_end and b.ps for the corner at a's programmed end."""
    cdef double ta[2]
    cdef double tb[2]
    cdef double ref[2]
    cdef double x[2]
    cdef double cr, dt
    cdef bint outer
    a.ins = INS_NONE
    el_tangent(a, True, ta)
    el_tangent(b, False, tb)
    cr = ta[0] * tb[1] - ta[1] * tb[0]
    dt = ta[0] * tb[0] + ta[1] * tb[1]
    if a.d != b.d:
        # side or radius changed without G40: join the two perpendicular points by a line
        a.pe[0] = a.oe[0]; a.pe[1] = a.oe[1]
        b.ps[0] = b.os[0]; b.ps[1] = b.os[1]
        if distance2d(a.oe[0] - b.os[0], a.oe[1] - b.os[1]) > cfg.slack:
            a.ins = INS_G1
            a.ins_end[0] = b.os[0]; a.ins_end[1] = b.os[1]
        return CORNER_OK
    if distance2d(a.e[0] - b.s[0], a.e[1] - b.s[1]) > LENGTH_EPS:
        # parts between them were removed: no common corner to go round, only the
        # intersection of the two offsets joins them
        ref[0] = 0.5 * (a.oe[0] + b.os[0])
        ref[1] = 0.5 * (a.oe[1] + b.os[1])
        if el_intersect(a, b, ref, cfg.slack, x):
            a.pe[0] = x[0]; a.pe[1] = x[1]
            b.ps[0] = x[0]; b.ps[1] = x[1]
            return CORNER_OK
        if b.kind == EL_LINE and dt > 0 and fabs(cr) < cfg.sin_tol \
                and fabs((a.oe[0] - b.os[0]) * tb[1] - (a.oe[1] - b.os[1]) * tb[0]) <= cfg.slack:
            # the removed parts leave a gap on one straight line: b starts where a ends
            a.pe[0] = a.oe[0]; a.pe[1] = a.oe[1]
            b.ps[0] = a.oe[0]; b.ps[1] = a.oe[1]
            return CORNER_OK
        return CORNER_NOT_FOUND
    if dt > 0 and fabs(cr) < cfg.sin_tol:
        a.pe[0] = a.oe[0]; a.pe[1] = a.oe[1]
        b.ps[0] = a.oe[0]; b.ps[1] = a.oe[1]
        return CORNER_OK
    # the tool is outside the turn when it turns away from the compensated side;
    # a reversal (180 deg) always goes round the corner
    outer = a.d * cr < 0 or (dt < 0 and fabs(cr) < cfg.sin_tol)
    ref[0] = 0.5 * (a.oe[0] + b.os[0])
    ref[1] = 0.5 * (a.oe[1] + b.os[1])
    if not outer:
        if not el_intersect(a, b, ref, cfg.slack, x):
            return CORNER_NOT_FOUND
        a.pe[0] = x[0]; a.pe[1] = x[1]
        b.ps[0] = x[0]; b.ps[1] = x[1]
        return CORNER_OK
    if (cfg.strategy & CORR_CORNER_INTERSECTION) and el_intersect(a, b, ref, cfg.slack, x) \
            and distance2d(x[0] - a.e[0], x[1] - a.e[1]) < (cfg.corner_distance if cfg.corner_distance > 0
                                                       else cfg.factor * fabs(a.d)):
        a.pe[0] = x[0]; a.pe[1] = x[1]
        b.ps[0] = x[0]; b.ps[1] = x[1]
        return CORNER_OK
    a.pe[0] = a.oe[0]; a.pe[1] = a.oe[1]
    b.ps[0] = b.os[0]; b.ps[1] = b.os[1]
    # round the corner: clockwise when the tool is on the left
    a.ins = INS_G2 if a.d > 0 else INS_G3
    a.ins_end[0] = b.os[0]; a.ins_end[1] = b.os[1]
    return CORNER_OK
