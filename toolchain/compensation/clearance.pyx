# Clearance of the tool path (the general gouge check): when a chain ends, every piece
# of its final tool path (each compensated part's move and each inserted corner part)
# must keep the tool radius, less tolerance[1], from the programmed contour of the
# chain within the search window (parts at most `depth` apart, counted round a closed
# contour). A piece that comes closer gouges: error 504 on its line, or with 0x80000
# the chain is rebuilt from its regions (regions.pyx).
#
# The path is read back from the parts and the queued insertions, so the check sees
# exactly what the merge will write. The contour is held CL_BLOCK parts (plus the
# window either side) at a time in part order, with boxes of CL_G1 and CL_G1 * CL_G1
# elements grown by the tool radius: a piece is compared with the few elements near
# it, O(n) on ordinary contours.
from libc.stdlib cimport realloc, free
from libc.math cimport fabs, M_PI

cdef enum:
    CL_BLOCK = 4096         # parts of the chain whose contour window is held at a time
    CL_G1 = 16              # contour elements per small box; a large box holds CL_G1 small ones

ctypedef struct Clearance:
    XPiece *el              # the programmed elements of the window, in part order
    size_t n, cap
    double *g1              # boxes of groups of CL_G1 elements, grown by `grow`
    double *g2              # boxes of groups of CL_G1 * CL_G1 elements
    size_t cap_g
    double grow
    double off
    size_t lo, hi           # parts the window holds
    bint whole              # ... the whole chain
    size_t span             # parts of the chain
    bint closed             # distances in parts wrap round the closed chain (regions.pyx)


cdef inline double _cl_sweep(int direction, const double *s, const double *e, const double *c) noexcept nogil:
    """A stand-in for the sweep of an arc from s to e round c, in (0, 2pi]: monotone in
    the true one and equal to it at every quarter turn (what the boxes and _cl_within
    compare it with), without trigonometry; a full circle when s = e."""
    cdef double d = _x_pseudo(e[0] - c[0], direction * (e[1] - c[1])) - _x_pseudo(s[0] - c[0], direction * (s[1] - c[1]))
    if d <= 0:
        d += 4.0
    return d * (0.5 * M_PI)


cdef inline bint _cl_within(const XPiece *q, double x, double y) noexcept nogil:
    """Whether a point on q's line / circle lies on the piece (cross products, no
    angles: this is the check's inner loop)."""
    cdef double ax, ay, px, py, bx, by, L2, t
    if q.kind == EL_LINE:
        ax = q.e[0] - q.s[0]; ay = q.e[1] - q.s[1]
        L2 = ax * ax + ay * ay
        t = (x - q.s[0]) * ax + (y - q.s[1]) * ay
        return t >= 0 and t <= L2
    if q.sweep >= 2.0 * M_PI - 1e-12:
        return True
    ax = q.s[0] - q.c[0]; ay = q.s[1] - q.c[1]
    bx = q.e[0] - q.c[0]; by = q.e[1] - q.c[1]
    px = x - q.c[0]; py = y - q.c[1]
    if q.sweep <= M_PI:
        return q.dir * (ax * py - ay * px) >= 0 and q.dir * (px * by - py * bx) >= 0
    # more than a half turn: not strictly inside the rest of the circle
    return not (q.dir * (bx * py - by * px) > 0 and q.dir * (px * ay - py * ax) > 0)


cdef double _x_dist(const XPiece *g, double x, double y) noexcept nogil:
    """Distance of a point from piece g (a line segment or an arc with its sweep)."""
    cdef double dx, dy, L2, t, rho
    if g.kind == EL_LINE:
        dx = g.e[0] - g.s[0]; dy = g.e[1] - g.s[1]
        L2 = dx * dx + dy * dy
        t = ((x - g.s[0]) * dx + (y - g.s[1]) * dy) / L2 if L2 > 0 else 0.0
        t = 0.0 if t < 0 else (1.0 if t > 1 else t)
        return distance2d(x - g.s[0] - t * dx, y - g.s[1] - t * dy)
    rho = distance2d(x - g.c[0], y - g.c[1])
    if rho > 0 and _cl_within(g, x, y):
        return fabs(rho - g.r)
    dx = distance2d(x - g.s[0], y - g.s[1])
    dy = distance2d(x - g.e[0], y - g.e[1])
    return dx if dx < dy else dy


cdef int _x_toward(const XPiece *t, double x, double y, double *pts) noexcept nogil:
    """Points of piece t nearest to the point (x, y) and, for arcs, farthest from it on
    its circle (0 to 2 candidates, in pts)."""
    cdef double dx, dy, L2, u, rho
    cdef int n = 0, k
    if t.kind == EL_LINE:
        dx = t.e[0] - t.s[0]; dy = t.e[1] - t.s[1]
        L2 = dx * dx + dy * dy
        u = ((x - t.s[0]) * dx + (y - t.s[1]) * dy) / L2 if L2 > 0 else 0.0
        u = 0.0 if u < 0 else (1.0 if u > 1 else u)
        pts[0] = t.s[0] + u * dx; pts[1] = t.s[1] + u * dy
        return 1
    rho = distance2d(x - t.c[0], y - t.c[1])
    if rho <= 0:
        return 0
    for k in range(2):
        u = 1.0 - 2.0 * k
        pts[2 * n] = t.c[0] + u * t.r * (x - t.c[0]) / rho
        pts[2 * n + 1] = t.c[1] + u * t.r * (y - t.c[1]) / rho
        if _cl_within(t, pts[2 * n], pts[2 * n + 1]):
            n += 1
    return n


cdef double _x_gap(const XPiece *t, const XPiece *g, double slack) noexcept nogil:
    """Smallest distance between pieces t and g: 0 when they cross, else the least over
    the points where it can occur (ends, feet of the other's ends and centre, the
    points of an arc facing a line or the other circle)."""
    cdef double pts[4]
    cdef double cand[24]
    cdef double best, d, pos, nx, ny, L
    cdef int m, k, n = 0
    m = _x_meet(t, g, slack, pts)
    for k in range(m):
        if _cl_within(t, pts[2 * k], pts[2 * k + 1]) and _cl_within(g, pts[2 * k], pts[2 * k + 1]):
            return 0.0
    cand[0] = t.s[0]; cand[1] = t.s[1]; cand[2] = t.e[0]; cand[3] = t.e[1]
    n = 2
    n += _x_toward(t, g.s[0], g.s[1], &cand[2 * n])
    n += _x_toward(t, g.e[0], g.e[1], &cand[2 * n])
    if g.kind == EL_ARC:
        n += _x_toward(t, g.c[0], g.c[1], &cand[2 * n])
    elif t.kind == EL_ARC:
        # the points of t's circle along g's normal through its centre
        L = distance2d(g.e[0] - g.s[0], g.e[1] - g.s[1])
        if L > 0:
            nx = -(g.e[1] - g.s[1]) / L; ny = (g.e[0] - g.s[0]) / L
            n += _x_toward(t, t.c[0] + nx, t.c[1] + ny, &cand[2 * n])
    best = 1e300
    for k in range(n):
        d = _x_dist(g, cand[2 * k], cand[2 * k + 1])
        if d < best:
            best = d
    return best


cdef inline void _cl_box_empty(double *b) noexcept nogil:
    b[0] = 1e300; b[1] = 1e300; b[2] = -1e300; b[3] = -1e300


cdef bint cl_element(const CompState *S, size_t k, XPiece *g) noexcept nogil:
    """The programmed element of part k in the plane (a line or an arc, removed parts
    included: the tool keeps away from them too) with its exact box; False when part
    k draws nothing in the plane (a rapid, an M function, a move off the plane)."""
    cdef const Part *p = &S.prog.parts[k]
    cdef const double *st
    if p.kind != PART_MOTION or p.func == 0:
        return False
    st = part_start_xyz(S.prog, k)
    memset(g, 0, sizeof(XPiece))
    g.part = k
    g.s[0] = st[S.first]; g.s[1] = st[S.second]
    g.e[0] = p.e[S.first]; g.e[1] = p.e[S.second]
    if p.func == 2 or p.func == 3:
        g.c[0] = p.cc[S.first]; g.c[1] = p.cc[S.second]
        g.r = distance2d(g.s[0] - g.c[0], g.s[1] - g.c[1])
        if g.r <= 1e-9:
            return False
        g.kind = EL_ARC
        g.dir = 1 if p.func == 3 else -1
        g.sweep = _cl_sweep(g.dir, g.s, g.e, g.c)
    else:
        if (g.e[0] - g.s[0]) * (g.e[0] - g.s[0]) + (g.e[1] - g.s[1]) * (g.e[1] - g.s[1]) <= 1e-18:
            return False
        g.kind = EL_LINE
    _x_geometry(g)
    return True


cdef bint _cl_load(CompState *S, Clearance *C, size_t lo, size_t hi) noexcept nogil:
    """The contour of parts lo..hi of the chain, with its group boxes grown by the
    largest tool radius among them (C.grow); C.off: how far an arc's end lies off its
    circle at most."""
    cdef XPiece g
    cdef XPiece *el
    cdef double *b
    cdef double d
    cdef size_t k, cap, ng
    C.n = 0
    C.lo = lo
    C.hi = hi
    C.grow = 0.0
    C.off = 0.0
    for k in range(lo, hi + 1):
        d = fabs(_comp_distance(S, &S.prog.parts[k]))
        if d > C.grow:
            C.grow = d
        if not cl_element(S, k, &g):
            continue
        if g.kind == EL_ARC:
            d = fabs(distance2d(g.e[0] - g.c[0], g.e[1] - g.c[1]) - g.r)
            if d > C.off:
                C.off = d
        if C.n == C.cap:
            cap = C.cap * 2 if C.cap else 256
            el = <XPiece *>realloc(C.el, cap * sizeof(XPiece))
            if el == NULL:
                return False
            C.el = el
            C.cap = cap
        C.el[C.n] = g
        C.n += 1
    ng = C.n / CL_G1 + 1
    if ng > C.cap_g:
        b = <double *>realloc(C.g1, 4 * ng * sizeof(double))
        if b == NULL:
            return False
        C.g1 = b
        b = <double *>realloc(C.g2, 4 * (ng / CL_G1 + 1) * sizeof(double))
        if b == NULL:
            return False
        C.g2 = b
        C.cap_g = ng
    for k in range(ng):
        _cl_box_empty(&C.g1[4 * k])
    for k in range(ng / CL_G1 + 1):
        _cl_box_empty(&C.g2[4 * k])
    for k in range(C.n):
        _box_union(&C.g1[4 * (k / CL_G1)], C.el[k].box)
    for k in range(ng):
        _box_union(&C.g2[4 * (k / CL_G1)], &C.g1[4 * k])
    for k in range(ng):
        b = &C.g1[4 * k]
        b[0] -= C.grow; b[1] -= C.grow; b[2] += C.grow; b[3] += C.grow
    for k in range(ng / CL_G1 + 1):
        b = &C.g2[4 * k]
        b[0] -= C.grow; b[1] -= C.grow; b[2] += C.grow; b[3] += C.grow
    return True


cdef inline bint _cl_in_window(const Clearance *C, size_t a, size_t b, size_t depth) noexcept nogil:
    cdef size_t d = a - b if a > b else b - a
    if C.whole and C.closed and C.span - d < d:
        d = C.span - d
    return d <= depth


cdef inline double _cl_seg_dmin(const XPiece *q, double x, double y) noexcept nogil:
    """Distance of a point from line piece q."""
    cdef double dx = q.e[0] - q.s[0], dy = q.e[1] - q.s[1]
    cdef double L2 = dx * dx + dy * dy
    cdef double t = ((x - q.s[0]) * dx + (y - q.s[1]) * dy) / L2 if L2 > 0 else 0.0
    t = 0.0 if t < 0 else (1.0 if t > 1 else t)
    return distance2d(x - q.s[0] - t * dx, y - q.s[1] - t * dy)


cdef inline bint _cl_off_line(const XPiece *q, const XPiece *g, double stop) noexcept nogil:
    """Line piece q lies wholly on one side of g's line, at least `stop` from it."""
    cdef double dx = g.e[0] - g.s[0], dy = g.e[1] - g.s[1]
    cdef double L = distance2d(dx, dy)
    cdef double a, b
    if L <= 0:
        return False
    a = ((q.s[0] - g.s[0]) * dy - (q.s[1] - g.s[1]) * dx) / L
    b = ((q.e[0] - g.s[0]) * dy - (q.e[1] - g.s[1]) * dx) / L
    return (a >= stop and b >= stop) or (a <= -stop and b <= -stop)


cdef inline bint _cl_off_ring(const XPiece *q, const double *c, double R, double stop) noexcept nogil:
    """Line piece q stays outside the ring of radii R -+ stop round c."""
    cdef double dmax = distance2d(q.s[0] - c[0], q.s[1] - c[1])
    cdef double d2 = distance2d(q.e[0] - c[0], q.e[1] - c[1])
    if d2 > dmax:
        dmax = d2
    return dmax <= R - stop or _cl_seg_dmin(q, c[0], c[1]) >= R + stop


cdef bint _cl_far(const XPiece *t, const XPiece *g, double stop) noexcept nogil:
    """A cheap proof that pieces t and g are at least `stop` apart (False: measure)."""
    cdef double D, sd, L
    if t.kind == EL_LINE and g.kind == EL_LINE:
        return _cl_off_line(t, g, stop) or _cl_off_line(g, t, stop)
    if t.kind == EL_LINE:
        return _cl_off_ring(t, g.c, g.r, stop)
    if g.kind == EL_LINE:
        L = distance2d(g.e[0] - g.s[0], g.e[1] - g.s[1])
        if L > 0:
            sd = fabs(((t.c[0] - g.s[0]) * (g.e[1] - g.s[1]) - (t.c[1] - g.s[1]) * (g.e[0] - g.s[0])) / L)
            if sd - t.r >= stop:
                return True
        return _cl_off_ring(g, t.c, t.r, stop)
    D = distance2d(t.c[0] - g.c[0], t.c[1] - g.c[1])
    return D >= t.r + g.r + stop or D + t.r <= g.r - stop or D + g.r <= t.r - stop


cdef bint _cl_cross(const XPiece *a, const XPiece *b) noexcept nogil:
    """Whether two programmed elements cross (not only meet at their ends)."""
    cdef double pts[4]
    cdef double pos
    cdef int m, k
    m = _x_meet(a, b, 0.0, pts)
    for k in range(m):
        if _x_on(a, pts[2 * k], pts[2 * k + 1], 0.0, &pos) and _x_on(b, pts[2 * k], pts[2 * k + 1], 0.0, &pos) \
                and not ((_x_near(a.s, pts[2 * k], pts[2 * k + 1], 1e-9) or _x_near(a.e, pts[2 * k], pts[2 * k + 1], 1e-9))
                         and (_x_near(b.s, pts[2 * k], pts[2 * k + 1], 1e-9) or _x_near(b.e, pts[2 * k], pts[2 * k + 1], 1e-9))):
            return True
    return False


cdef double cl_gap(const Clearance *C, XPiece *t, const XPiece *own, size_t skip_a, size_t skip_b,
                   double r, size_t depth, double slack, double stop) noexcept nogil:
    """The smallest distance from piece t to the contour elements of the window within
    `depth` parts of t's part, looked at only where it is below r (else r); the first
    one found below `stop` ends the search. own: t's programmed element when the
    elements it crosses do not count (an open path crossing itself: the tool crosses
    there too), else NULL. skip_a, skip_b: parts whose elements t keeps the radius from
    by construction (not measured; (size_t)-1 none)."""
    cdef double box[4]
    cdef double best = r, d
    cdef size_t i, j, k, n1, n2
    cdef const XPiece *g
    box[0] = t.box[0] - r; box[1] = t.box[1] - r; box[2] = t.box[2] + r; box[3] = t.box[3] + r
    n1 = (C.n + CL_G1 - 1) / CL_G1
    n2 = (n1 + CL_G1 - 1) / CL_G1
    for i in range(n2):
        if not _box_hit(&C.g2[4 * i], box, 0.0):
            continue
        for j in range(i * CL_G1, min((i + 1) * CL_G1, n1)):
            if not _box_hit(&C.g1[4 * j], box, 0.0):
                continue
            for k in range(j * CL_G1, min((j + 1) * CL_G1, C.n)):
                g = &C.el[k]
                if not _box_hit(g.box, box, 0.0) or not _cl_in_window(C, g.part, t.part, depth) \
                        or g.part == skip_a or g.part == skip_b:
                    continue
                if own != NULL and _box_hit(g.box, own.box, 0.0) and _cl_cross(own, g):
                    continue
                if _cl_far(t, g, stop):
                    continue
                d = _x_gap(t, g, slack)
                if d < best:
                    best = d
                    if best < stop:
                        return best
    return best


cdef size_t _cl_next_el(const Clearance *C, size_t part) noexcept nogil:
    """The part of the first contour element of the window after part `part`."""
    cdef size_t lo = 0, hi = C.n, mid
    while lo < hi:
        mid = (lo + hi) / 2
        if C.el[mid].part <= part:
            lo = mid + 1
        else:
            hi = mid
    return C.el[lo].part if lo < C.n else <size_t>-1


cdef size_t _cl_prev_el(const Clearance *C, size_t part) noexcept nogil:
    """The part of the last contour element of the window before part `part`."""
    cdef size_t lo = 0, hi = C.n, mid
    while lo < hi:
        mid = (lo + hi) / 2
        if C.el[mid].part < part:
            lo = mid + 1
        else:
            hi = mid
    return C.el[lo - 1].part if lo > 0 else <size_t>-1


cdef inline void _cl_line(XPiece *t, const double *a, const double *b, size_t part) noexcept nogil:
    t.kind = EL_LINE
    t.s[0] = a[0]; t.s[1] = a[1]
    t.e[0] = b[0]; t.e[1] = b[1]
    t.part = part
    _x_geometry(t)


cdef inline bint _cl_arc(XPiece *t, const double *a, const double *b, const double *c, double r,
                         int direction, size_t part, bint full) noexcept nogil:
    """An arc piece from a to b round c in `direction` (a = b: a full circle when
    `full`, else nothing); False for no piece."""
    if r <= 1e-12 or (not full and distance2d(b[0] - a[0], b[1] - a[1]) <= 1e-12):
        return False
    t.kind = EL_ARC
    t.dir = direction
    t.s[0] = a[0]; t.s[1] = a[1]
    t.e[0] = b[0]; t.e[1] = b[1]
    t.c[0] = c[0]; t.c[1] = c[1]
    t.r = r
    t.sweep = _cl_sweep(direction, a, b, c)
    t.part = part
    _x_geometry(t)
    return True


cdef bint _cl_side_change(const CompState *S, size_t k, size_t last) noexcept nogil:
    """Whether the next element after part k is compensated on the other side or with
    another radius (the G1 between them crosses the contour on purpose)."""
    cdef size_t m
    for m in range(k + 1, last + 1):
        if S.role[m] == ROLE_SET:
            return _comp_distance(S, &S.prog.parts[m]) != _comp_distance(S, &S.prog.parts[k])
    return False


cdef bint cl_check_chain(CompState *S, size_t first, size_t last, size_t ins0, bint skip_first,
                         bint skip_last) noexcept nogil:
    """Checks the final tool path of the chain of parts first..last (its insertions
    from ins0 on). skip_first / skip_last: the first / last move is a ramp from / to
    the programmed contour (strategy 1). False with S.xs.err_* filled: 504 on the line
    of the first piece that gouges (or out of memory).
    The allowance is tolerance[1], plus tolerance[4] (a removed small arc lets the
    neighbours meet closer to it) and how far an arc's end lies off its circle (the
    arc-centre tolerance of the compiler)."""
    cdef Clearance *C = &S.cl
    cdef XState *X = &S.xs
    cdef Part *p
    cdef XPiece t
    cdef double cur[2]
    cdef double end[2]
    cdef double c[2]
    cdef double r, allow = S.cfg.slack + S.cfg.min_arc
    cdef size_t k, j, rec, blo, bhi, depth = S.cfg.depth
    cdef size_t last_el = last
    cdef bint first_piece = True, have, skip, is_open
    cdef XPiece own
    cdef const double *st
    cdef size_t na, nb
    st = part_start_xyz(S.prog, first)
    p = &S.prog.parts[last]
    is_open = distance2d(st[S.first] - p.e[S.first], st[S.second] - p.e[S.second]) > 1e-6
    C.span = last - first + 1
    C.closed = False
    C.whole = False
    # where the tool stands before the chain: the last part before it with a position
    j = first
    while j > 0 and S.role[j - 1] == ROLE_FOLLOW:
        j -= 1
    if j > 0:
        j -= 1
        cur[0] = S.prog.parts[j].ce[S.first]; cur[1] = S.prog.parts[j].ce[S.second]
    else:
        cur[0] = S.prog.start[S.first]; cur[1] = S.prog.start[S.second]
    # the insertions from part j on: the chain's own (from ins0) and any just before
    rec = ins0
    while rec > 0 and S.ins[rec - 1].after >= j:
        rec -= 1
    while rec < S.n_ins and S.ins[rec].after < first:
        cur[0] = S.ins[rec].end[0]; cur[1] = S.ins[rec].end[1]
        rec += 1
    while last_el > first and (S.role[last_el] != ROLE_SET or not cl_element(S, last_el, &t)):
        last_el -= 1
    blo = first
    bhi = first - 1
    memset(&t, 0, sizeof(t))
    for k in range(first, last + 1):
        if k > bhi:
            # the next block of parts and the contour of its window
            blo = k
            bhi = k + CL_BLOCK - 1 if last - k >= CL_BLOCK else last
            C.whole = blo - first <= depth and last - bhi <= depth
            if not _cl_load(S, C, blo - depth if blo - first > depth else first,
                            bhi + depth if last - bhi > depth else last):
                X.err_number = ERR_OUT_OF_MEMORY
                X.err_part = k
                return False
            allow = S.cfg.slack + S.cfg.min_arc + C.off
        p = &S.prog.parts[k]
        if S.role[k] == ROLE_SET and p.kind == PART_MOTION and p.func != 0:
            end[0] = p.ce[S.first]; end[1] = p.ce[S.second]
            r = fabs(_comp_distance(S, p))
            if (p.func == 2 or p.func == 3) and p.radius > 0:
                c[0] = p.cc[S.first]; c[1] = p.cc[S.second]
                have = _cl_arc(&t, cur, end, c, p.radius, 1 if p.func == 3 else -1, k, True)
            else:
                have = distance2d(end[0] - cur[0], end[1] - cur[1]) > 1e-12
                if have:
                    _cl_line(&t, cur, end, k)
            skip = (first_piece and skip_first) or (k == last_el and skip_last)
            first_piece = False
            # a line on the offset of a line keeps the radius from it and, past a corner
            # of the chain (an intersection or an arc), from a line next to it
            nb = <size_t>-1
            if have and not skip and t.kind == EL_LINE and p.func == 1:
                nb = _cl_prev_el(C, k)
                if nb != <size_t>-1 and S.prog.parts[nb].func != 1:
                    nb = <size_t>-1
            if have and not skip and cl_gap(C, &t, &own if is_open and cl_element(S, k, &own) else NULL,
                                            k, nb, r, depth, S.cfg.slack, r - allow) < r - allow:
                X.err_number = ERR_COMP_CROSSING
                X.err_part = k
                X.err_arg = r
                return False
            cur[0] = end[0]; cur[1] = end[1]
        while rec < S.n_ins and S.ins[rec].after == k:
            end[0] = S.ins[rec].end[0]; end[1] = S.ins[rec].end[1]
            r = fabs(_comp_distance(S, p))
            have = False
            if not S.ins[rec].no_centre:
                if S.ins[rec].func == INS_G1:
                    have = distance2d(end[0] - cur[0], end[1] - cur[1]) > 1e-12 and not _cl_side_change(S, k, last)
                    if have:
                        _cl_line(&t, cur, end, k)
                else:
                    have = _cl_arc(&t, cur, end, S.ins[rec].cc, r, 1 if S.ins[rec].func == INS_G3 else -1, k, False)
            # an arc round the corner at part k's end keeps the radius from the elements
            # that meet there
            nb = <size_t>-1
            na = <size_t>-1
            if have and S.ins[rec].func != INS_G1 and S.ins[rec].cc[0] == p.e[S.first] \
                    and S.ins[rec].cc[1] == p.e[S.second]:
                na = k
                nb = _cl_next_el(C, k)
            if have and cl_gap(C, &t, NULL, na, nb, r, depth, S.cfg.slack, r - allow) < r - allow:
                X.err_number = ERR_COMP_CROSSING
                X.err_part = k
                X.err_arg = r
                return False
            cur[0] = end[0]; cur[1] = end[1]
            rec += 1
    return True


cdef void cl_free(Clearance *C) noexcept nogil:
    free(C.el)
    free(C.g1)
    free(C.g2)
    C.el = NULL
    C.g1 = NULL
    C.g2 = NULL
