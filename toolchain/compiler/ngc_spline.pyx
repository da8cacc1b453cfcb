# ISO mode: LinuxCNC's splines in the XY plane, made of arcs (G2 / G3) and, where the
# curve is straight, lines (G1) that stay within SPLINE_TOLERANCE (1 um) of the curve, so
# that they compensate, plan and run like any other part (docs/compiler.md, "Splines"):
#   G5   X Y I J P Q   a cubic Bezier: start, start + (I, J), end + (P, Q), end; on a G5
#                      following another, I J may be left out: the curve goes on in the
#                      direction the previous one ended in (I J = -P -Q of the previous)
#   G5.1 X Y I J       a quadratic Bezier: start, start + (I, J), end
#   G5.2 X Y P L ... G5.3   a NURBS: the current point and the X Y of the lines that
#                      follow (P their weights, default 1; L the order, default 3), on
#                      LinuxCNC's clamped knot vector 0 .. 0 1 2 .. n-k+2 .. n-k+2; G5.3
#                      ends it and makes its chords
# The parts: each piece of the parameter range (a knot span of the NURBS, the whole
# range of a Bezier, split in SPLINE_MIN_PIECES) is the arc through the curve's points at
# its ends and its middle, halved until the curve at each eighth of the piece is within
# the tolerance of that arc (of the chord, where the three are in line).
# An arc follows the curve's bending, so its length is the curve's to far better than the
# tolerance (a chord's length falls short by about the tolerance times the curvature).
from libc.math cimport sqrt, floor, fabs
from libc.string cimport memcpy

cdef extern from *:
    """
    /* mm: the chords' largest distance from the curve (1 um) */
    #define SPLINE_TOLERANCE 0.001
    """
    double SPLINE_TOLERANCE


cdef void spl_bezier(const double *c, int n, double t, double *out) noexcept nogil:
    """The point at t of the Bezier curve of n + 1 control points c (x y pairs), by de
    Casteljau's construction (n <= 3)."""
    cdef double x[4]
    cdef double y[4]
    cdef int i, r
    for i in range(n + 1):
        x[i] = c[2 * i]
        y[i] = c[2 * i + 1]
    for r in range(1, n + 1):
        for i in range(n - r + 1):
            x[i] = (1.0 - t) * x[i] + t * x[i + 1]
            y[i] = (1.0 - t) * y[i] + t * y[i + 1]
    out[0] = x[0]
    out[1] = y[0]


cdef inline double spl_knot(int i, int n, int k) noexcept nogil:
    """LinuxCNC's knot i of a NURBS of n + 1 control points and order k."""
    if i < k:
        return 0.0
    if i <= n:
        return <double>(i - k + 1)
    return <double>(n - k + 2)


cdef void spl_nurbs(const double *c, int n, int k, double u, double *out) noexcept nogil:
    """The point at u of the NURBS of n + 1 control points c (x y w triples) and order k
    (k <= SPLINE_MAX_ORDER) on LinuxCNC's knot vector, by de Boor's algorithm on the
    weighted points."""
    cdef double d[SPLINE_MAX_ORDER][3]
    cdef int p = k - 1, s, j, r, i
    cdef double a, left, right
    s = p + <int>floor(u)                   # the span [t_s, t_s+1) holding u (knots are whole numbers)
    if s > n:
        s = n                               # u at the end: the last span
    for j in range(p + 1):
        i = j + s - p
        d[j][0] = c[3 * i] * c[3 * i + 2]
        d[j][1] = c[3 * i + 1] * c[3 * i + 2]
        d[j][2] = c[3 * i + 2]
    for r in range(1, p + 1):
        j = p
        while j >= r:
            left = spl_knot(j + s - p, n, k)
            right = spl_knot(j + 1 + s - r, n, k)
            a = (u - left) / (right - left) if right > left else 0.0
            d[j][0] = (1.0 - a) * d[j - 1][0] + a * d[j][0]
            d[j][1] = (1.0 - a) * d[j - 1][1] + a * d[j][1]
            d[j][2] = (1.0 - a) * d[j - 1][2] + a * d[j][2]
            j -= 1
    out[0] = d[p][0] / d[p][2]
    out[1] = d[p][1] / d[p][2]


cdef void spl_point(const double *c, int n, int k, double u, double *out) noexcept nogil:
    """The curve's point at u: a Bezier (k == 0, degree n) or a NURBS of order k."""
    if k == 0:
        spl_bezier(c, n, u, out)
    else:
        spl_nurbs(c, n, k, u, out)


cdef double spl_off_chord(const double *a, const double *b, const double *q) noexcept nogil:
    """The distance of q from the segment a b."""
    cdef double dx = b[0] - a[0], dy = b[1] - a[1]
    cdef double len2 = dx * dx + dy * dy
    cdef double t = 0.0, ex, ey
    if len2 > 0.0:
        t = ((q[0] - a[0]) * dx + (q[1] - a[1]) * dy) / len2
        t = 0.0 if t < 0.0 else (1.0 if t > 1.0 else t)
    ex = a[0] + t * dx - q[0]
    ey = a[1] + t * dy - q[1]
    return sqrt(ex * ex + ey * ey)


cdef int spl_chord(CState *st, double x, double y, int col) noexcept nogil:
    """A G1 part to (x, y) in the plane, the other axes where they are."""
    cdef double newp[AXES]
    memcpy(newp, st.ppos, sizeof(newp))
    newp[0] = x
    newp[1] = y
    return ngc_feed_to(st, newp, col)


cdef int spl_arc(CState *st, double x, double y, double cx, double cy, bint ccw, int col) noexcept nogil:
    """A G2 / G3 part to (x, y) about (cx, cy) in the XY plane."""
    cdef LineWords words
    cdef double newp[AXES]
    cdef int func = 3 if ccw else 2
    memcpy(newp, st.ppos, sizeof(newp))
    newp[0] = x
    newp[1] = y
    words.mask = (1u << 23) | (1u << 24) | (1u << 25) | (1u << 8) | (1u << 9)
    words.v[23] = x; words.v[24] = y; words.v[25] = newp[2]
    if st.ngc.ijk_absolute:                 # G90.1: the centre as it is
        words.v[8] = cx; words.v[9] = cy
    else:
        words.v[8] = cx - st.ppos[0]; words.v[9] = cy - st.ppos[1]
    if st.params.swapG2G3:
        func = 5 - func                     # (em_arc swaps it back: the curve's own direction)
    return em_move(st, &words, func, newp, col)


cdef bint spl_circle(const double *a, const double *m, const double *b, double *c, double *r,
                     bint *ccw) noexcept nogil:
    """The circle through a, m, b (its centre c, radius r, whether a m b turn counter-
    clockwise); False when they are (nearly) on a line."""
    cdef double ax = m[0] - a[0], ay = m[1] - a[1], bx = b[0] - a[0], by = b[1] - a[1]
    cdef double d = 2.0 * (ax * by - ay * bx)
    cdef double a2 = ax * ax + ay * ay, b2 = bx * bx + by * by
    cdef double ux, uy
    if fabs(d) <= ANGLE_EPS * (a2 + b2):
        return False
    ux = (by * a2 - ay * b2) / d
    uy = (ax * b2 - bx * a2) / d
    c[0] = a[0] + ux
    c[1] = a[1] + uy
    r[0] = sqrt(ux * ux + uy * uy)
    ccw[0] = d > 0.0
    return r[0] < 1e6


cdef int spl_piece(CState *st, const double *c, int n, int k, double u0, double u1, const double *p0,
                   const double *p1, int depth, int col) noexcept nogil:
    """The curve from u0 (at p0) to u1 (at p1) as one arc through the point at the
    piece's middle, or a chord where the curve is straight, when the curve at each
    eighth of the piece is within the tolerance of it; else halved."""
    cdef double q[SPLINE_CHECKS][2]
    cdef double centre[2]
    cdef double r = 0.0, off = 0.0, um = 0.5 * (u0 + u1)
    cdef bint ccw = False, arc
    cdef int i, half = SPLINE_CHECKS // 2
    for i in range(SPLINE_CHECKS):
        spl_point(c, n, k, u0 + (u1 - u0) * (i + 1) / (SPLINE_CHECKS + 1), q[i])
    arc = spl_circle(p0, q[half], p1, centre, &r, &ccw)
    for i in range(SPLINE_CHECKS):
        if arc:
            off = max(off, fabs(sqrt((q[i][0] - centre[0]) ** 2 + (q[i][1] - centre[1]) ** 2) - r))
        else:
            off = max(off, spl_off_chord(p0, p1, q[i]))
    if off <= SPLINE_TOLERANCE or depth >= SPLINE_MAX_DEPTH:
        if arc:
            return spl_arc(st, p1[0], p1[1], centre[0], centre[1], ccw, col)
        return spl_chord(st, p1[0], p1[1], col)
    if spl_piece(st, c, n, k, u0, um, p0, q[half], depth + 1, col) != 0:
        return R_ERR
    return spl_piece(st, c, n, k, um, u1, q[half], p1, depth + 1, col)


cdef int spl_curve(CState *st, const double *c, int n, int k, double umax, int spans, int col) noexcept nogil:
    """The chords of a whole curve over [0, umax], its spans each split in
    SPLINE_MIN_PIECES first; the last chord ends exactly on the last control point."""
    cdef double p0[2]
    cdef double p1[2]
    cdef double u0, u1
    cdef int i, pieces = spans * SPLINE_MIN_PIECES
    p0[0] = st.ppos[0]
    p0[1] = st.ppos[1]
    for i in range(pieces):
        u0 = umax * i / pieces
        u1 = umax * (i + 1) / pieces
        if i == pieces - 1:
            p1[0] = c[(2 if k == 0 else 3) * n]
            p1[1] = c[(2 if k == 0 else 3) * n + 1]
        else:
            spl_point(c, n, k, u1, p1)
        if spl_piece(st, c, n, k, u0, u1, p0, p1, 0, col) != 0:
            return R_ERR
        p0[0] = p1[0]
        p0[1] = p1[1]
    return 0


cdef int spl_check(CState *st, const LineWords *lw, double g, int col) noexcept nogil:
    """What every spline line needs: the XY plane, no other axis, a feed, no G93."""
    if st.plane != 17:
        return err_ngc_g(st.err, st.unit.file_idx, st.line, g, col, "splines are drawn in the XY plane (G17) only")
    if lw.mask & AXIS_LETTERS & ~((1u << 23) | (1u << 24)):
        return err_ngc_g(st.err, st.unit.file_idx, st.line, g, col, "a spline moves X and Y only")
    if st.ngc.inverse_time:
        return err_ngc_g(st.err, st.unit.file_idx, st.line, g, col, "splines are not read in inverse time (G93)")
    return 0


cdef int spl_feed(CState *st, double g, int col) noexcept nogil:
    """Error 410 for a spline at feed 0, naming its G word."""
    if st.feed != 0.0:
        return 0
    return err_no_feed(st.err, st.unit.file_idx, st.line, g, col)


cdef void spl_end(CState *st, const LineWords *lw, double *x, double *y) noexcept nogil:
    """The end of the line's X Y (absolute or incremental), the current point where absent."""
    x[0] = st.ppos[0]
    y[0] = st.ppos[1]
    if has(lw, b'X'):
        x[0] = lw.v[23] if st.absolute else x[0] + lw.v[23]
        if st.absolute:
            em_fix_axis(st, 0)
    if has(lw, b'Y'):
        y[0] = lw.v[24] if st.absolute else y[0] + lw.v[24]
        if st.absolute:
            em_fix_axis(st, 1)


cdef int ngc_bezier(CState *st, const LineWords *lw, const Block *b, int motion, int col) noexcept nogil:
    """G5 (cubic) / G5.1 (quadratic): control points from the words, then the chords."""
    cdef NgcState *n = st.ngc
    cdef double g = 5.0 if motion == 5 else 5.1
    cdef double c[8]
    cdef double ex, ey, pv, qv
    cdef bint has_i = has(lw, b'I'), has_j = has(lw, b'J')
    cdef bint goes_on = n.spline_pq_set and n.spline_part == st.prog.n_parts
    if b.motion < 0 and not (lw.mask & AXIS_LETTERS) and not has_i and not has_j:
        return 0                            # a line of the modal spline without a position
    if spl_check(st, lw, g, col) != 0 or spl_feed(st, g, col) != 0:
        return R_ERR
    spl_end(st, lw, &ex, &ey)
    c[0] = st.ppos[0]
    c[1] = st.ppos[1]
    if motion == 51:
        if not has_i and not has_j:
            return err_ngc_g(st.err, st.unit.file_idx, st.line, g, col, "I and J (the control point from the start) are missing")
        c[2] = c[0] + (val(lw, b'I') if has_i else 0.0)
        c[3] = c[1] + (val(lw, b'J') if has_j else 0.0)
        c[4] = ex
        c[5] = ey
        n.spline_pq_set = False
        return spl_curve(st, c, 2, 0, 1.0, 1, col)
    if not lw.has_pword or not has(lw, b'Q'):
        return err_ngc_g(st.err, st.unit.file_idx, st.line, g, col, "P and Q (the second control point from the end) are both needed")
    if has_i != has_j or (not has_i and not goes_on):
        return err_ngc_g(st.err, st.unit.file_idx, st.line, g, col, "I and J are both needed (only a G5 right after another may leave "
                         "both out)")
    pv = lw.pword * st.unit_scale           # (iso_units scales I J X Y, not P Q)
    qv = val(lw, b'Q') * st.unit_scale
    if has_i:
        c[2] = c[0] + val(lw, b'I')
        c[3] = c[1] + val(lw, b'J')
    else:
        c[2] = c[0] - n.spline_pq[0]
        c[3] = c[1] - n.spline_pq[1]
    c[4] = ex + pv
    c[5] = ey + qv
    c[6] = ex
    c[7] = ey
    if spl_curve(st, c, 3, 0, 1.0, 1, col) != 0:
        return R_ERR
    n.spline_pq[0] = pv
    n.spline_pq[1] = qv
    n.spline_pq_set = True
    n.spline_part = st.prog.n_parts
    return 0


cdef int _nurbs_add(CState *st, double x, double y, double w) noexcept nogil:
    """One more control point (x, y, weight) of the open G5.2 block; error 4 when memory is
    exhausted."""
    cdef NgcState *n = st.ngc
    if not grow(<void **>&n.nurbs, &n.cap_nurbs, 3 * (n.n_nurbs + 1), sizeof(double)):
        return err_out_of_memory(st.err, st.unit.file_idx, st.line)
    n.nurbs[3 * n.n_nurbs] = x
    n.nurbs[3 * n.n_nurbs + 1] = y
    n.nurbs[3 * n.n_nurbs + 2] = w
    n.n_nurbs += 1
    return 0


cdef int ngc_nurbs(CState *st, const LineWords *lw, const Block *b, int motion, int col) noexcept nogil:
    """G5.2: opens a NURBS at the current point (P without X Y: its weight; L: the
    order); a line of it adds its X Y with the weight P; G5.3 makes the chords."""
    cdef NgcState *n = st.ngc
    cdef double x, y, w, order
    cdef int k, cnt
    if motion == 53:
        if not n.nurbs_open:
            return err_ngc_g(st.err, st.unit.file_idx, st.line, 5.3, col, "no NURBS block (G5.2) is open")
        n.nurbs_open = False
        k = n.nurbs_order
        cnt = <int>n.n_nurbs
        if cnt < k:
            return err_ngc_g(st.err, st.unit.file_idx, st.line, 5.3, col, "a NURBS needs at least as many control points as its order (L)")
        if spl_feed(st, 5.3, col) != 0:
            return R_ERR
        n.spline_pq_set = False
        return spl_curve(st, n.nurbs, cnt - 1, k, <double>(cnt - k + 1), cnt - k + 1, col)
    if b.motion < 0 and not (lw.mask & AXIS_LETTERS):
        return 0                            # a line of the block without a point
    if spl_check(st, lw, 5.2, col) != 0:
        return R_ERR
    w = lw.pword if lw.has_pword else 1.0
    if not (w > 0.0):
        return err_ngc_g(st.err, st.unit.file_idx, st.line, 5.2, col, "a control point's weight (P) must be above 0")
    if b.motion == 52 and not n.nurbs_open:
        order = val(lw, b'L') if has(lw, b'L') else 3.0
        if not (order >= 2.0 and order <= SPLINE_MAX_ORDER and order == floor(order)):
            return err_ngc_g(st.err, st.unit.file_idx, st.line, 5.2, col, "the order L must be a whole number from 2 to 16")
        n.nurbs_open = True
        n.nurbs_order = <int>order
        n.n_nurbs = 0
        if _nurbs_add(st, st.ppos[0], st.ppos[1], 1.0 if (lw.mask & AXIS_LETTERS) else w) != 0:
            return R_ERR
        if not (lw.mask & AXIS_LETTERS):
            return 0                        # G5.2 P alone: the first point's weight
    elif b.motion == 52:
        return err_ngc_g(st.err, st.unit.file_idx, st.line, 5.2, col, "a NURBS block is open already (G5.3 ends it)")
    x = n.nurbs[3 * (n.n_nurbs - 1)]
    y = n.nurbs[3 * (n.n_nurbs - 1) + 1]
    if has(lw, b'X'):
        x = lw.v[23] if st.absolute else x + lw.v[23]
    if has(lw, b'Y'):
        y = lw.v[24] if st.absolute else y + lw.v[24]
    return _nurbs_add(st, x, y, w)


cdef int ngc_spline(CState *st, const LineWords *lw, const Block *b, int motion, int col) noexcept nogil:
    """The spline motions of the ISO mode: 5 (G5), 51 (G5.1), 52 (G5.2), 53 (G5.3)."""
    if motion == 52 or motion == 53:
        return ngc_nurbs(st, lw, b, motion, col)
    return ngc_bezier(st, lw, b, motion, col)
