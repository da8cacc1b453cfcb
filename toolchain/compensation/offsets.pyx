# Offset curves (equidistants) of lines and arcs in the compensation plane.
# Everything here is plain 2-D geometry on (first, second) plane coordinates (its
# primitives: geometry.pxd); the offset distance d is signed: d > 0 = left of the
# direction of travel (G41).
from libc.math cimport fabs


cdef inline double el_offset_ends(const CompEl *el, double d, double *s, double *e) noexcept nogil:
    """The ends of el's offset by d, on the perpendiculars at its programmed ends (its
    direction u, or centre and radius, set); an arc's radius shrinks by d on the left
    of a counter-clockwise arc (its centre's side) and each end is projected on the
    offset circle (a programmed end a little off the circle, within the arc-centre
    tolerance, still gives a point on the path). The offset radius of an arc (0 for a
    line)."""
    cdef double ro, L, f
    if el.kind == EL_LINE:
        # left normal (-uy, ux)
        s[0] = el.s[0] - d * el.u[1]; s[1] = el.s[1] + d * el.u[0]
        e[0] = el.e[0] - d * el.u[1]; e[1] = el.e[1] + d * el.u[0]
        return 0.0
    ro = el.R - d * el.dir
    f = ro / el.R if el.R > 0 else 0.0
    s[0] = el.c[0] + (el.s[0] - el.c[0]) * f; s[1] = el.c[1] + (el.s[1] - el.c[1]) * f
    L = distance2d(el.e[0] - el.c[0], el.e[1] - el.c[1])
    f = ro / L if L > 0 else 0.0
    e[0] = el.c[0] + (el.e[0] - el.c[0]) * f; e[1] = el.c[1] + (el.e[1] - el.c[1]) * f
    return ro


cdef bint el_init(CompEl *el, size_t part, int kind, int direction, double d,
                  const double *s, const double *e, const double *c, double sweep) noexcept nogil:
    """Fills the programmed geometry and the perpendicular offset points. False for a
    line of zero length in the plane."""
    cdef double L
    el.part = part
    el.kind = kind
    el.dir = direction
    el.d = d
    el.s[0] = s[0]; el.s[1] = s[1]
    el.e[0] = e[0]; el.e[1] = e[1]
    el.ins = INS_NONE
    el.first = False
    el.fixed_start = False
    if kind == EL_LINE:
        L = distance2d(e[0] - s[0], e[1] - s[1])
        if L <= ROUNDING_EPS:
            return False
        el.u[0] = (e[0] - s[0]) / L
        el.u[1] = (e[1] - s[1]) / L
        el.c[0] = 0.0; el.c[1] = 0.0
        el.R = 0.0; el.sweep = 0.0
    else:
        el.c[0] = c[0]; el.c[1] = c[1]
        el.R = distance2d(s[0] - c[0], s[1] - c[1])
        el.sweep = fabs(sweep)
        el.u[0] = 0.0; el.u[1] = 0.0
    el.ro = el_offset_ends(el, d, el.os, el.oe)
    el.ps[0] = el.os[0]; el.ps[1] = el.os[1]
    el.pe[0] = el.oe[0]; el.pe[1] = el.oe[1]
    return True


cdef void el_tangent(const CompEl *el, bint at_end, double *t) noexcept nogil:
    """Unit direction of travel at the start or the end of the programmed element."""
    cdef double px, py
    if el.kind == EL_LINE:
        t[0] = el.u[0]; t[1] = el.u[1]
        return
    if at_end:
        px = el.e[0] - el.c[0]; py = el.e[1] - el.c[1]
    else:
        px = el.s[0] - el.c[0]; py = el.s[1] - el.c[1]
    t[0] = -py * el.dir / el.R
    t[1] = px * el.dir / el.R


cdef inline void _pick(const double *pts, const double *ref, double *out) noexcept nogil:
    """Of two crossings (pts[0..1], pts[2..3]), the one nearer ref into out."""
    cdef int k = 0 if distance2d(pts[0] - ref[0], pts[1] - ref[1]) <= distance2d(pts[2] - ref[0], pts[3] - ref[1]) else 2
    out[0] = pts[k]; out[1] = pts[k + 1]


cdef bint el_intersect(const CompEl *a, const CompEl *b, const double *ref, double slack,
                       double *out) noexcept nogil:
    """Intersection of the offset curves of a and b taken whole (lines infinite, arcs
    as full circles), the root nearest `ref`; a miss by less than `slack` counts as
    tangent; False when they do not meet."""
    cdef double den, t
    cdef double pts[4]
    if a.kind == EL_LINE and b.kind == EL_LINE:
        den = cross2d(a.u[0], a.u[1], b.u[0], b.u[1])
        if fabs(den) < ANGLE_EPS:
            return False
        t = cross2d(b.os[0] - a.oe[0], b.os[1] - a.oe[1], b.u[0], b.u[1]) / den
        out[0] = a.oe[0] + t * a.u[0]
        out[1] = a.oe[1] + t * a.u[1]
        return True
    if a.kind == EL_LINE:
        if not line_circle(a.oe, a.u, b.c, b.ro, slack, pts):
            return False
    elif b.kind == EL_LINE:
        if not line_circle(b.os, b.u, a.c, a.ro, slack, pts):
            return False
    elif not circle_circle(a.c, a.ro, b.c, b.ro, slack, pts):
        return False
    _pick(pts, ref, out)
    return True


cdef double el_path_sweep(const CompEl *el) noexcept nogil:
    """Arcs: sweep (radians, >= 0 normally) of the tool path from ps to pe in the arc's
    direction, measured against the programmed sweep so that trimming past the other
    end gives a negative value."""
    cdef double a_s = el.dir * vector_turn_near(el.s[0] - el.c[0], el.s[1] - el.c[1],
                                                el.ps[0] - el.c[0], el.ps[1] - el.c[1])
    cdef double a_e = el.dir * vector_turn_near(el.e[0] - el.c[0], el.e[1] - el.c[1],
                                                el.pe[0] - el.c[0], el.pe[1] - el.c[1])
    return el.sweep - a_s + a_e


cdef double el_path_length(const CompEl *el) noexcept nogil:
    """Signed length of the tool path on the element: negative when the corners have
    trimmed it past itself (the offsets cross)."""
    if el.kind == EL_LINE:
        return (el.pe[0] - el.ps[0]) * el.u[0] + (el.pe[1] - el.ps[1]) * el.u[1]
    return el_path_sweep(el) * el.ro
