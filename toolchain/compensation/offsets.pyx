# Offset curves (equidistants) of lines and arcs in the compensation plane.
# Everything here is plain 2-D geometry on (first, second) plane coordinates; the
# offset distance d is signed: d > 0 = left of the direction of travel (G41).
from libc.math cimport sqrt, fabs, atan2, M_PI

cdef inline double _cross(double ax, double ay, double bx, double by) noexcept nogil:
    return ax * by - ay * bx


cdef inline double _wrap_pi(double a) noexcept nogil:
    while a > M_PI:
        a -= 2.0 * M_PI
    while a <= -M_PI:
        a += 2.0 * M_PI
    return a


cdef bint el_init(CompEl *el, size_t part, int kind, int direction, double d,
                  const double *s, const double *e, const double *c, double sweep) noexcept nogil:
    """Fills the programmed geometry and the perpendicular offset points. False for a
    line of zero length in the plane."""
    cdef double L, f
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
        if L <= 1e-12:
            return False
        el.u[0] = (e[0] - s[0]) / L
        el.u[1] = (e[1] - s[1]) / L
        el.c[0] = 0.0; el.c[1] = 0.0
        el.R = 0.0; el.ro = 0.0; el.sweep = 0.0
        # left normal (-uy, ux)
        el.os[0] = s[0] - d * el.u[1]; el.os[1] = s[1] + d * el.u[0]
        el.oe[0] = e[0] - d * el.u[1]; el.oe[1] = e[1] + d * el.u[0]
    else:
        el.c[0] = c[0]; el.c[1] = c[1]
        el.R = distance2d(s[0] - c[0], s[1] - c[1])
        el.sweep = fabs(sweep)
        el.u[0] = 0.0; el.u[1] = 0.0
        # the left side of a CCW arc is its centre: the radius shrinks by d
        el.ro = el.R - d * direction
        # each end projected on the offset circle (a programmed end a little off the
        # circle, within the arc-centre tolerance, still gives a point on the path)
        f = el.ro / el.R if el.R > 0 else 0.0
        el.os[0] = c[0] + (s[0] - c[0]) * f; el.os[1] = c[1] + (s[1] - c[1]) * f
        L = distance2d(e[0] - c[0], e[1] - c[1])
        f = el.ro / L if L > 0 else 0.0
        el.oe[0] = c[0] + (e[0] - c[0]) * f; el.oe[1] = c[1] + (e[1] - c[1]) * f
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


cdef inline void _pick(double ax, double ay, double bx, double by, const double *ref,
                       double *out) noexcept nogil:
    # the root nearer the reference point
    if distance2d(ax - ref[0], ay - ref[1]) <= distance2d(bx - ref[0], by - ref[1]):
        out[0] = ax; out[1] = ay
    else:
        out[0] = bx; out[1] = by


cdef bint _line_circle(const double *p, const double *u, const double *c, double r,
                       double slack, const double *ref, double *out) noexcept nogil:
    # p + t u on the circle |x - c| = r; a miss by less than `slack` counts as tangent
    cdef double wx = p[0] - c[0], wy = p[1] - c[1]
    cdef double b = wx * u[0] + wy * u[1]
    cdef double disc = b * b - (wx * wx + wy * wy - r * r)
    cdef double q, t1, t2
    if disc < 0:
        if disc < -2.0 * slack * r:
            return False
        disc = 0.0
    q = sqrt(disc)
    t1 = -b + q
    t2 = -b - q
    _pick(p[0] + t1 * u[0], p[1] + t1 * u[1], p[0] + t2 * u[0], p[1] + t2 * u[1], ref, out)
    return True


cdef bint _circle_circle(const double *c1, double r1, const double *c2, double r2,
                         double slack, const double *ref, double *out) noexcept nogil:
    cdef double dx = c2[0] - c1[0], dy = c2[1] - c1[1]
    cdef double dist = distance2d(dx, dy)
    cdef double a, h2, h, mx, my
    if dist < 1e-12:
        return False
    a = (r1 * r1 - r2 * r2 + dist * dist) / (2.0 * dist)
    h2 = r1 * r1 - a * a
    if h2 < 0:
        if h2 < -2.0 * slack * (r1 if r1 > r2 else r2):
            return False
        h2 = 0.0
    h = sqrt(h2)
    mx = c1[0] + a * dx / dist
    my = c1[1] + a * dy / dist
    _pick(mx - h * dy / dist, my + h * dx / dist, mx + h * dy / dist, my - h * dx / dist, ref, out)
    return True


cdef bint el_intersect(const CompEl *a, const CompEl *b, const double *ref, double slack,
                       double *out) noexcept nogil:
    """Intersection of the offset curves of a and b taken whole (lines infinite, arcs
    as full circles), the root nearest `ref`; False when they do not meet."""
    cdef double den, t
    if a.kind == EL_LINE and b.kind == EL_LINE:
        den = _cross(a.u[0], a.u[1], b.u[0], b.u[1])
        if fabs(den) < 1e-12:
            return False
        t = _cross(b.os[0] - a.oe[0], b.os[1] - a.oe[1], b.u[0], b.u[1]) / den
        out[0] = a.oe[0] + t * a.u[0]
        out[1] = a.oe[1] + t * a.u[1]
        return True
    if a.kind == EL_LINE:
        return _line_circle(a.oe, a.u, b.c, b.ro, slack, ref, out)
    if b.kind == EL_LINE:
        return _line_circle(b.os, b.u, a.c, a.ro, slack, ref, out)
    return _circle_circle(a.c, a.ro, b.c, b.ro, slack, ref, out)


cdef inline double vector_turn(double ax, double ay, double bx, double by) noexcept nogil:
    # signed angle from vector a to vector b, in (-pi, pi]
    return atan2(ax * by - ay * bx, ax * bx + ay * by)


cdef inline double _turn_small(double ax, double ay, double bx, double by) noexcept nogil:
    # vector_turn for the usual case of b on (or next to) the ray of a: an end not trimmed
    # lies on its perpendicular, the angle is rounding noise and atan(t) = t - t^3/3
    # is t to far below 1e-24 for |t| <= 1e-8
    cdef double y = ax * by - ay * bx
    cdef double x = ax * bx + ay * by
    if x > 0 and fabs(y) <= 1e-8 * x:
        return y / x
    return atan2(y, x)


cdef double el_path_sweep(const CompEl *el) noexcept nogil:
    """Arcs: sweep (radians, >= 0 normally) of the tool path from ps to pe in the arc's
    direction, measured against the programmed sweep so that trimming past the other
    end gives a negative value."""
    cdef double a_s = el.dir * _turn_small(el.s[0] - el.c[0], el.s[1] - el.c[1],
                                           el.ps[0] - el.c[0], el.ps[1] - el.c[1])
    cdef double a_e = el.dir * _turn_small(el.e[0] - el.c[0], el.e[1] - el.c[1],
                                           el.pe[0] - el.c[0], el.pe[1] - el.c[1])
    return el.sweep - a_s + a_e


cdef double el_path_length(const CompEl *el) noexcept nogil:
    """Signed length of the tool path on the element: negative when the corners have
    trimmed it past itself (the offsets cross)."""
    if el.kind == EL_LINE:
        return (el.pe[0] - el.ps[0]) * el.u[0] + (el.pe[1] - el.ps[1]) * el.u[1]
    return el_path_sweep(el) * el.ro
