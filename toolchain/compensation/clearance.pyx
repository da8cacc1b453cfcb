# Clearance of the tool path (the general gouge check): every piece of a chain's final
# tool path (each compensated part's move and each inserted corner part) must keep the
# tool radius, less tolerance[1], from the programmed contour of the chain: parts at
# most `depth` apart (counted round a closed contour) while the chain grows, the
# farther ones when it ends (_cl_far_check). A piece that comes closer gouges: error
# 504 on its line, with 0x80000 the chain is rebuilt from its regions (regions.pyx),
# and a lenient chain goes on with warning 601 and how deep the piece cuts
# (_cl_gouge).
#
# The path is read back from the parts and the queued insertions, so the check sees
# exactly what the merge will write: while the chain grows, the parts a loop cut can no
# longer reach (cl_chain_upto, beside the compiler), the rest when it ends
# (cl_chain_close), and then a closed contour's first parts against its last ones
# (_cl_seam: neighbours round its start). A rebuilt chain is checked against its
# whole contour (cl_check_chain). The contour is held CL_BLOCK parts (plus the window
# either side) at a time in part order, moved on with the chain, its elements' boxes in
# a box index (box_index.pxd); CL_BATCH consecutive pieces share one search of it.
# Cheap proofs (_cl_far) settle most pairs, the rest is measured exactly
# (_cl_piece_gap): O(n) on ordinary contours. At the chain's end its groups of parts
# are searched against the far groups' boxes in a box index too: O(n log n).
from libc.stdlib cimport free
from libc.string cimport memmove, memcpy
from libc.math cimport fabs, sqrt, M_PI


cdef inline bint _cl_within(const XPiece *q, double x, double y) noexcept nogil:
    """Whether the direction of point (x, y) from arc piece q's centre lies within the
    arc (cross products, no angles: this is the check's inner loop)."""
    cdef double ax, ay, px, py, bx, by
    if q.sweep >= 2.0 * M_PI - ANGLE_EPS:
        return True
    ax = q.s[0] - q.c[0]; ay = q.s[1] - q.c[1]
    bx = q.e[0] - q.c[0]; by = q.e[1] - q.c[1]
    px = x - q.c[0]; py = y - q.c[1]
    if q.sweep <= M_PI:
        return q.dir * (ax * py - ay * px) >= 0 and q.dir * (px * by - py * bx) >= 0
    # more than a half turn: not strictly inside the rest of the circle
    return not (q.dir * (bx * py - by * px) > 0 and q.dir * (px * ay - py * ax) > 0)


cdef inline double _cl_seg_d2(const XPiece *q, double x, double y) noexcept nogil:
    """Squared distance of a point from line piece q."""
    cdef double dx = q.e[0] - q.s[0], dy = q.e[1] - q.s[1]
    cdef double L2 = dx * dx + dy * dy
    cdef double t = ((x - q.s[0]) * dx + (y - q.s[1]) * dy) / L2 if L2 > 0 else 0.0
    t = 0.0 if t < 0 else (1.0 if t > 1 else t)
    dx = x - q.s[0] - t * dx
    dy = y - q.s[1] - t * dy
    return dx * dx + dy * dy


cdef inline double _cl_point_gap(const XPiece *q, double x, double y) noexcept nogil:
    """Distance of a point from piece q: from an arc, radial where the point faces the
    arc, else to its nearer end."""
    cdef double rho, a, b
    if q.kind == EL_LINE:
        return sqrt(_cl_seg_d2(q, x, y))
    rho = distance2d(x - q.c[0], y - q.c[1])
    if rho > 0 and _cl_within(q, x, y):
        return fabs(rho - q.r)
    a = (x - q.s[0]) * (x - q.s[0]) + (y - q.s[1]) * (y - q.s[1])
    b = (x - q.e[0]) * (x - q.e[0]) + (y - q.e[1]) * (y - q.e[1])
    return sqrt(a if a < b else b)


cdef double _cl_line_arc_inner(const XPiece *ln, const XPiece *a, double stop) noexcept nogil:
    """Where the least distance of line piece ln and arc piece a lies inside both: 0
    where they cross, else the distance of the circle's point nearest the line when
    it lies on the arc and faces the line piece; stop when neither (the ends decide).
    Inside both, the distance has no minimum elsewhere: past the line the circle's
    extreme point is a maximum."""
    cdef double dx = ln.e[0] - ln.s[0], dy = ln.e[1] - ln.s[1]
    cdef double L2 = dx * dx + dy * dy
    cdef double u, fx, fy, h, w, v
    cdef int k
    if L2 <= 0:
        return stop
    u = ((a.c[0] - ln.s[0]) * dx + (a.c[1] - ln.s[1]) * dy) / L2
    fx = ln.s[0] + u * dx - a.c[0]
    fy = ln.s[1] + u * dy - a.c[1]
    h = distance2d(fx, fy)
    if h >= a.r:
        if u < 0 or u > 1 or h - a.r >= stop:
            return stop
        return h - a.r if _cl_within(a, a.c[0] + a.r * fx / h, a.c[1] + a.r * fy / h) else stop
    w = sqrt((a.r * a.r - h * h) / L2)
    for k in range(2):
        v = u - w if k == 0 else u + w
        if v >= 0 and v <= 1 and _cl_within(a, ln.s[0] + v * dx, ln.s[1] + v * dy):
            return 0.0
    return stop


cdef double _cl_arc_arc_inner(const XPiece *p, const XPiece *q, double stop) noexcept nogil:
    """The same for two arcs: 0 where they cross, else the least distance of their
    points on the line through both centres that lie on the arcs (where every
    interior extreme of the distance lies); stop when none is below it."""
    cdef double dx = q.c[0] - p.c[0], dy = q.c[1] - p.c[1]
    cdef double D = distance2d(dx, dy)
    cdef double ux, uy, m, h, x, y, best = stop, d
    cdef double pp[4]
    cdef double qq[4]
    cdef int i, j, n_p = 0, n_q = 0
    if D <= ROUNDING_EPS:
        return stop             # concentric: the ends decide
    ux = dx / D; uy = dy / D
    if D <= p.r + q.r and D >= fabs(p.r - q.r):
        m = (p.r * p.r - q.r * q.r + D * D) / (2.0 * D)
        h = p.r * p.r - m * m
        h = sqrt(h) if h > 0 else 0.0
        for i in range(2):
            x = p.c[0] + m * ux - (h if i == 0 else -h) * uy
            y = p.c[1] + m * uy + (h if i == 0 else -h) * ux
            if _cl_within(p, x, y) and _cl_within(q, x, y):
                return 0.0
    for i in range(2):
        x = p.c[0] + (p.r if i == 0 else -p.r) * ux
        y = p.c[1] + (p.r if i == 0 else -p.r) * uy
        if _cl_within(p, x, y):
            pp[2 * n_p] = x; pp[2 * n_p + 1] = y
            n_p += 1
        x = q.c[0] + (q.r if i == 0 else -q.r) * ux
        y = q.c[1] + (q.r if i == 0 else -q.r) * uy
        if _cl_within(q, x, y):
            qq[2 * n_q] = x; qq[2 * n_q + 1] = y
            n_q += 1
    for i in range(n_p):
        for j in range(n_q):
            d = distance2d(pp[2 * i] - qq[2 * j], pp[2 * i + 1] - qq[2 * j + 1])
            if d < best:
                best = d
    return best


cdef double _cl_piece_gap(const XPiece *t, const XPiece *g, double stop) noexcept nogil:
    """The distance of pieces t and g where it is below `stop` (else a value >= stop):
    the least distance of two lines / arcs lies at an end of one of them, where they
    cross, or at an interior extreme (_cl_line_arc_inner, _cl_arc_arc_inner); lines
    have none."""
    cdef double d, o1, o2, o3, o4
    d = _cl_point_gap(g, t.s[0], t.s[1])
    if d < stop:
        return d
    d = _cl_point_gap(g, t.e[0], t.e[1])
    if d < stop:
        return d
    d = _cl_point_gap(t, g.s[0], g.s[1])
    if d < stop:
        return d
    d = _cl_point_gap(t, g.e[0], g.e[1])
    if d < stop:
        return d
    if t.kind == EL_LINE and g.kind == EL_LINE:
        # a crossing strictly inside both (a touch is an end at distance 0, above)
        o1 = (t.e[0] - t.s[0]) * (g.s[1] - t.s[1]) - (t.e[1] - t.s[1]) * (g.s[0] - t.s[0])
        o2 = (t.e[0] - t.s[0]) * (g.e[1] - t.s[1]) - (t.e[1] - t.s[1]) * (g.e[0] - t.s[0])
        o3 = (g.e[0] - g.s[0]) * (t.s[1] - g.s[1]) - (g.e[1] - g.s[1]) * (t.s[0] - g.s[0])
        o4 = (g.e[0] - g.s[0]) * (t.e[1] - g.s[1]) - (g.e[1] - g.s[1]) * (t.e[0] - g.s[0])
        return 0.0 if ((o1 < 0) != (o2 < 0)) and ((o3 < 0) != (o4 < 0)) else stop
    if t.kind == EL_LINE:
        return _cl_line_arc_inner(t, g, stop)
    if g.kind == EL_LINE:
        return _cl_line_arc_inner(g, t, stop)
    return _cl_arc_arc_inner(t, g, stop)


cdef inline double *_cl_group(Clearance *C, size_t part) noexcept nogil:
    """The boxes of the group of the chain's parts that holds `part` (C.gbox); NULL:
    no memory."""
    cdef size_t g = (part - C.first) >> C.group_shift
    if g < C.n_gbox:
        return &C.gbox[8 * g]
    return _cl_group_add(C, g)


cdef double *_cl_group_add(Clearance *C, size_t g) noexcept nogil:
    """_cl_group for a group beyond the last one: empty boxes up to group g."""
    cdef size_t k
    if not grow(<void **>&C.gbox, &C.cap_gbox, g + 1, 8 * sizeof(double)):
        return NULL
    for k in range(C.n_gbox, g + 1):
        box_empty(&C.gbox[8 * k])
        box_empty(&C.gbox[8 * k + 4])
    C.n_gbox = g + 1
    return &C.gbox[8 * g]


cdef bint cl_element(const CompState *S, size_t k, XPiece *g) noexcept nogil:
    """The programmed element of part k in the plane (a line or an arc, removed parts
    included: the tool keeps away from them too) with its exact box; False when part
    k draws nothing in the plane (a rapid, an M function, a move off the plane)."""
    cdef const Part *p = &S.prog.parts[k]
    cdef const PartExtra *x
    cdef const double *st
    if p.kind != PART_MOTION or p.func == 0:
        return False
    st = part_start_xyz(S.prog, k)
    g.part = k
    g.ins = False
    g.first = False
    g.prov = False
    g.gprog = False
    g.s[0] = st[S.first]; g.s[1] = st[S.second]
    g.e[0] = p.e[S.first]; g.e[1] = p.e[S.second]
    if p.func == 2 or p.func == 3:
        x = part_extra(S.prog, p)
        g.c[0] = x.cc[S.first]; g.c[1] = x.cc[S.second]
        g.r = distance2d(g.s[0] - g.c[0], g.s[1] - g.c[1])
        if g.r <= LENGTH_EPS:
            return False
        g.kind = EL_ARC
        g.dir = 1 if p.func == 3 else -1
        g.sweep = pseudo_sweep(g.s[0] - g.c[0], g.s[1] - g.c[1], g.e[0] - g.c[0], g.e[1] - g.c[1], g.dir)
    else:
        if (g.e[0] - g.s[0]) * (g.e[0] - g.s[0]) + (g.e[1] - g.s[1]) * (g.e[1] - g.s[1]) <= LENGTH_EPS * LENGTH_EPS:
            return False
        g.kind = EL_LINE
        g.dir = 0
        g.sweep = 0.0
    x_geometry(g)
    return True


cdef bint _cl_slide(CompState *S, Clearance *C, size_t lo, size_t hi) noexcept nogil:
    """Moves the window on to the contour of parts lo..hi (lo >= C.lo, hi >= C.hi):
    the elements it still holds stay, only the new parts are read; then its group
    boxes (_cl_boxes)."""
    cdef size_t drop = 0, start = lo
    if C.n > 0 and lo >= C.lo and lo <= C.hi + 1 and hi >= C.hi:
        while drop < C.n and C.el[drop].part < lo:
            drop += 1
        if drop > 0:
            memmove(C.el, &C.el[drop], (C.n - drop) * sizeof(XPiece))
            memmove(C.off, &C.off[drop], (C.n - drop) * sizeof(double))
            C.n -= drop
        start = C.hi + 1
    else:
        C.n = 0
    C.lo = lo
    C.hi = hi
    if not _cl_read(S, C, start, hi) or not _cl_boxes(C):
        return False
    C.el0 = 0
    C.el_end = C.n
    return True


cdef inline bint _cl_read(CompState *S, Clearance *C, size_t lo, size_t hi) noexcept nogil:
    """Appends the contour elements of parts lo..hi to the window."""
    cdef XPiece *el
    cdef size_t k, c1, c2, n0 = C.n
    for k in range(lo, hi + 1):
        if C.n == C.cap:
            # the two arrays grow alike from the same capacity
            c1 = c2 = C.cap
            if not grow(<void **>&C.el, &c1, C.n + 1, sizeof(XPiece)) or \
                    not grow(<void **>&C.off, &c2, C.n + 1, sizeof(double)):
                return False
            C.cap = c1
        if not cl_element(S, k, &C.el[C.n]):
            continue
        el = &C.el[C.n]
        C.off[C.n] = fabs(distance2d(el.e[0] - el.c[0], el.e[1] - el.c[1]) - el.r) if el.kind == EL_ARC else 0.0
        C.n += 1
    return not C.grouping or _cl_group_elements(C, n0)


cdef bint _cl_group_elements(Clearance *C, size_t n0) noexcept nogil:
    """The boxes of the window's elements from n0 on into the element boxes of their
    groups (False: no memory)."""
    cdef double box[4]
    cdef double *gb
    cdef size_t k, g, cur = <size_t>-1, cur_part = 0
    for k in range(n0, C.n + 1):
        g = (C.el[k].part - C.first) >> C.group_shift if k < C.n else <size_t>-2
        if g == cur:
            box_union(box, C.el[k].box)
            continue
        if cur != <size_t>-1:
            gb = _cl_group(C, cur_part)
            if gb == NULL:
                return False
            box_union(&gb[4], box)
        if k < C.n:
            cur = g
            cur_part = C.el[k].part
            box[0] = C.el[k].box[0]; box[1] = C.el[k].box[1]; box[2] = C.el[k].box[2]; box[3] = C.el[k].box[3]
    return True


cdef inline bint _cl_boxes(Clearance *C) noexcept nogil:
    """The window's box index (the elements' own boxes: a query box is grown by the
    piece's radius) and C.max_off."""
    cdef size_t k
    box_index_clear(&C.ix)
    C.max_off = 0.0
    for k in range(C.n):
        if not box_index_append(&C.ix, C.el[k].box):
            return False
        if C.off[k] > C.max_off:
            C.max_off = C.off[k]
    return True


cdef bint cl_load(CompState *S, Clearance *C, size_t lo, size_t hi) noexcept nogil:
    """The contour of parts lo..hi alone (see _cl_slide)."""
    C.n = 0
    return _cl_slide(S, C, lo, hi)


cdef inline bint _cl_in_window(const Clearance *C, size_t a, size_t b, size_t depth) noexcept nogil:
    """Whether parts a and b are at most `depth` apart (C.closed: round the chain)."""
    cdef size_t d = a - b if a > b else b - a
    if C.closed and C.span - d < d:
        d = C.span - d
    return d <= depth


cdef inline bint _cl_off_line(const XPiece *q, const XPiece *g, double stop) noexcept nogil:
    """Line piece q lies wholly on one side of g's line, at least `stop` (> 0) from it
    (cross products against stop x |g|, squared: no root)."""
    cdef double dx = g.e[0] - g.s[0], dy = g.e[1] - g.s[1]
    cdef double lim = stop * stop * (dx * dx + dy * dy)
    cdef double a = (q.s[0] - g.s[0]) * dy - (q.s[1] - g.s[1]) * dx
    cdef double b = (q.e[0] - g.s[0]) * dy - (q.e[1] - g.s[1]) * dx
    return lim > 0 and ((a > 0) == (b > 0)) and a != 0 and b != 0 and a * a >= lim and b * b >= lim


cdef inline bint _cl_off_ring(const XPiece *q, const double *c, double R, double stop) noexcept nogil:
    """Line piece q stays outside the ring of radii R -+ stop round c."""
    cdef double dmax = distance2d(q.s[0] - c[0], q.s[1] - c[1])
    cdef double d2 = distance2d(q.e[0] - c[0], q.e[1] - c[1])
    if d2 > dmax:
        dmax = d2
    return dmax <= R - stop or _cl_seg_d2(q, c[0], c[1]) >= (R + stop) * (R + stop)


cdef bint _cl_arc_off_line(const XPiece *q, const XPiece *ln, double stop) noexcept nogil:
    """Arc piece q lies wholly on one side of line piece ln's line, at least `stop`
    from it: its signed distance from the line is least and greatest at its ends or
    at the circle's points along the line's normal, where the arc holds them."""
    cdef double dx = ln.e[0] - ln.s[0], dy = ln.e[1] - ln.s[1]
    cdef double L = distance2d(dx, dy)
    cdef double nx, ny, a, b, lo, hi, sc
    if L <= 0:
        return False
    nx = -dy / L; ny = dx / L
    a = (q.s[0] - ln.s[0]) * nx + (q.s[1] - ln.s[1]) * ny
    b = (q.e[0] - ln.s[0]) * nx + (q.e[1] - ln.s[1]) * ny
    lo = a if a < b else b
    hi = b if a < b else a
    if lo < stop and hi > -stop:
        return False                # the ends alone straddle the band
    sc = (q.c[0] - ln.s[0]) * nx + (q.c[1] - ln.s[1]) * ny
    if _cl_within(q, q.c[0] + q.r * nx, q.c[1] + q.r * ny):
        hi = sc + q.r
    if _cl_within(q, q.c[0] - q.r * nx, q.c[1] - q.r * ny):
        lo = sc - q.r
    return lo >= stop or hi <= -stop


cdef bint _cl_far(const XPiece *t, const XPiece *g, double stop) noexcept nogil:
    """A cheap proof that pieces t and g are at least `stop` apart (False: measure):
    one lies beyond the band of `stop` round the other's line, or outside the ring of
    `stop` round the other's circle."""
    cdef double D
    if t.kind == EL_LINE and g.kind == EL_LINE:
        return _cl_off_line(t, g, stop) or _cl_off_line(g, t, stop)
    if t.kind == EL_LINE:
        return _cl_off_ring(t, g.c, g.r, stop) or _cl_arc_off_line(g, t, stop)
    if g.kind == EL_LINE:
        return _cl_off_ring(g, t.c, t.r, stop) or _cl_arc_off_line(t, g, stop)
    D = distance2d(t.c[0] - g.c[0], t.c[1] - g.c[1])
    return D >= t.r + g.r + stop or D + t.r <= g.r - stop or D + g.r <= t.r - stop


cdef bint _cl_cross(const XPiece *a, const XPiece *b) noexcept nogil:
    """Whether two programmed elements cross (not only meet at their ends)."""
    cdef double pts[4]
    cdef double pos
    cdef int m, k
    m = x_meet(a, b, 0.0, pts)
    for k in range(m):
        if x_on(a, pts[2 * k], pts[2 * k + 1], 0.0, &pos) and x_on(b, pts[2 * k], pts[2 * k + 1], 0.0, &pos) \
                and not ((x_near(a.s, pts[2 * k], pts[2 * k + 1], LENGTH_EPS)
                          or x_near(a.e, pts[2 * k], pts[2 * k + 1], LENGTH_EPS))
                         and (x_near(b.s, pts[2 * k], pts[2 * k + 1], LENGTH_EPS)
                              or x_near(b.e, pts[2 * k], pts[2 * k + 1], LENGTH_EPS))):
            return True
    return False


cdef inline double _cl_element_gap(const Clearance *C, const XPiece *t, const XPiece *g,
                                   const XPiece *own, size_t skip_a, size_t skip_b, size_t depth,
                                   double stop, bint *loose) noexcept nogil:
    """Piece t's distance from element g, whose box meets t's grown by the radius,
    where it counts and is below `stop` (else `stop`; see cl_gap). loose: set when
    g does not count because t's own element crosses it."""
    cdef double d
    if g.part == skip_a or g.part == skip_b or _cl_in_window(C, g.part, t.part, depth) == C.only_far \
            or _cl_far(t, g, stop):
        return stop
    d = _cl_piece_gap(t, g, stop)
    if d < stop and own != NULL and box_hit(g.box, own.box, 0.0) and _cl_cross(own, g):
        loose[0] = True
        return stop
    return d


cdef double cl_gap(const Clearance *C, XPiece *t, const XPiece *own, size_t skip_a, size_t skip_b,
                   double r, size_t depth, double stop) noexcept nogil:
    """Whether piece t comes closer than `stop` (<= r) to a contour element of the
    window within `depth` parts of t's part: the distance to the first element found
    closer, else r. own: t's programmed element when the elements it crosses do not
    count (an open path crossing itself: the tool crosses there too), else NULL.
    skip_a, skip_b: parts whose elements t keeps the radius from by construction (not
    measured; (size_t)-1 none)."""
    cdef double box[4]
    cdef double d
    cdef int64_t k = -1
    cdef bint loose = False
    box[0] = t.box[0] - r; box[1] = t.box[1] - r; box[2] = t.box[2] + r; box[3] = t.box[3] + r
    while True:
        k = box_index_next(&C.ix, <size_t>(k + 1), C.n, box, 0.0)
        if k < 0:
            return r
        d = _cl_element_gap(C, t, &C.el[k], own, skip_a, skip_b, depth, stop, &loose)
        if d < stop:
            return d


cdef bint _cl_collect(Clearance *C, const double *box) noexcept nogil:
    """C.cand: the elements whose boxes meet `box`, in order (False: no memory)."""
    cdef size_t c1, c2, n = 0
    cdef int64_t k = -1
    while True:
        k = box_index_next(&C.ix, <size_t>(k + 1), C.n, box, 0.0)
        if k < 0:
            break
        if n == C.cap_cand:
            c1 = c2 = C.cap_cand            # the two arrays grow alike
            if not grow(<void **>&C.cand, &c1, n + 1, sizeof(size_t)) or \
                    not grow(<void **>&C.cbox, &c2, n + 1, 4 * sizeof(double)):
                return False
            C.cap_cand = c1
        C.cand[n] = <size_t>k
        memcpy(&C.cbox[4 * n], C.el[k].box, 4 * sizeof(double))
        n += 1
    C.n_cand = n
    return True


cdef int64_t _cl_flush(Clearance *C, size_t depth) noexcept nogil:
    """Measures the queued pieces in order: the index of the first one that comes
    closer than its `stop`, -1 none, -2 out of memory. One search of the boxes for
    the whole batch (the pieces of neighbouring parts meet the same few elements)."""
    cdef double box[4]
    cdef double bb[4]
    cdef ClPiece *q
    cdef size_t b, n = C.n_batch
    C.n_batch = 0
    C.n_measured = n
    if n == 0:
        return -1
    box_empty(box)
    for b in range(n):
        q = &C.batch[b]
        bb[0] = q.t.box[0] - q.r; bb[1] = q.t.box[1] - q.r; bb[2] = q.t.box[2] + q.r; bb[3] = q.t.box[3] + q.r
        box_union(box, bb)
    if not _cl_collect(C, box) or (C.grouping and not _cl_group_pieces(C, box)):
        return -2
    return _cl_scan(C, 0, depth)


cdef bint _cl_group_pieces(Clearance *C, const double *box) noexcept nogil:
    """The batch's box (its pieces grown by their radius) into the piece boxes of the
    groups its pieces belong to (False: no memory)."""
    cdef size_t b, g, last_g = <size_t>-1
    cdef double *gb
    for b in range(C.n_measured):
        g = (C.batch[b].t.part - C.first) >> C.group_shift
        if g == last_g:
            continue
        last_g = g
        gb = _cl_group(C, C.batch[b].t.part)
        if gb == NULL:
            return False
        box_union(gb, box)
    return True


cdef inline int64_t _cl_scan(Clearance *C, size_t first, size_t depth) noexcept nogil:
    """The first piece of the batch _cl_flush measures, from `first` on, that comes
    closer than its `stop` to a candidate; -1 none."""
    cdef double x0, y0, x1, y1
    cdef const double *cb
    cdef ClPiece *q
    cdef size_t b, m
    for b in range(first, C.n_measured):
        q = &C.batch[b]
        x0 = q.t.box[0] - q.r; y0 = q.t.box[1] - q.r; x1 = q.t.box[2] + q.r; y1 = q.t.box[3] + q.r
        for m in range(C.n_cand):
            cb = &C.cbox[4 * m]
            if cb[0] <= x1 and x0 <= cb[2] and cb[1] <= y1 and y0 <= cb[3] and \
                    _cl_element_gap(C, &q.t, &C.el[C.cand[m]], q.own, q.skip_a, q.skip_b, depth, q.stop,
                                    &C.loose) < q.stop:
                return <int64_t>b
    return -1


cdef double _cl_least(Clearance *C, size_t b, size_t depth) noexcept nogil:
    """The least distance of piece b of the measured batch from the candidates that
    count, below its stop: _cl_element_gap again with the distance found as the bound
    until nothing is closer (the values it compares are finitely many)."""
    cdef ClPiece *q = &C.batch[b]
    cdef double best = q.stop, d
    cdef double x0 = q.t.box[0] - q.r, y0 = q.t.box[1] - q.r, x1 = q.t.box[2] + q.r, y1 = q.t.box[3] + q.r
    cdef const double *cb
    cdef size_t m
    for m in range(C.n_cand):
        cb = &C.cbox[4 * m]
        if not (cb[0] <= x1 and x0 <= cb[2] and cb[1] <= y1 and y0 <= cb[3]):
            continue
        while True:
            d = _cl_element_gap(C, &q.t, &C.el[C.cand[m]], q.own, q.skip_a, q.skip_b, depth, best, &C.loose)
            if d >= best:
                break
            best = d
    return best


cdef inline int64_t _cl_queue(Clearance *C, const XPiece *own, size_t skip_a, size_t skip_b,
                              double r, double stop, size_t depth) noexcept nogil:
    """Queues the piece built in the next batch slot (C.batch[C.n_batch].t) for
    _cl_flush with cl_gap's arguments; measures the batch when it is full:
    _cl_flush's result, -1 while it is not."""
    cdef ClPiece *q = &C.batch[C.n_batch]
    q.own = own
    q.skip_a = skip_a
    q.skip_b = skip_b
    q.r = r
    q.stop = stop
    C.n_batch += 1
    return _cl_flush(C, depth) if C.n_batch == CL_BATCH else -1


cdef inline void _cl_line(XPiece *t, const double *a, const double *b, size_t part) noexcept nogil:
    """t becomes a line piece of part `part` from a to b, its geometry (box, length)
    computed."""
    t.kind = EL_LINE
    t.s[0] = a[0]; t.s[1] = a[1]
    t.e[0] = b[0]; t.e[1] = b[1]
    t.part = part
    x_geometry(t)


cdef inline bint _cl_arc(XPiece *t, const double *a, const double *b, const double *c, double r,
                         int direction, size_t part, bint full) noexcept nogil:
    """An arc piece from a to b round c in `direction`; False for no piece. full: a
    part's arc (a = b: a full circle), with its exact box; else a corner arc (a = b:
    nothing), with its circle's box."""
    if r <= ROUNDING_EPS or (not full and distance2d(b[0] - a[0], b[1] - a[1]) <= ROUNDING_EPS):
        return False
    t.kind = EL_ARC
    t.dir = direction
    t.s[0] = a[0]; t.s[1] = a[1]
    t.e[0] = b[0]; t.e[1] = b[1]
    t.c[0] = c[0]; t.c[1] = c[1]
    t.r = r
    t.sweep = pseudo_sweep(a[0] - c[0], a[1] - c[1], b[0] - c[0], b[1] - c[1], direction)
    t.part = part
    if full:
        x_geometry(t)
    else:
        # a corner arc has the tool's radius: its circle's box is close enough (a box
        # only picks the elements to measure)
        t.box[0] = c[0] - r; t.box[1] = c[1] - r; t.box[2] = c[0] + r; t.box[3] = c[1] + r
    return True


cdef bint _cl_side_change(const CompState *S, size_t k, size_t last) noexcept nogil:
    """Whether the next element after part k is compensated on the other side or with
    another radius (the G1 between them crosses the contour on purpose)."""
    cdef size_t m
    for m in range(k + 1, last + 1):
        if S.role[m] == ROLE_SET:
            return comp_distance(S, &S.prog.parts[m]) != comp_distance(S, &S.prog.parts[k])
    return False


cdef bint _cl_gouge(CompState *S, int64_t found, size_t k) noexcept nogil:
    """The result of _cl_queue / _cl_flush: False with S.xs.err_* filled when a piece
    gouges (504 on its part's line, the tool radius) or on no memory (at part k). A
    lenient chain goes on: warning 601 for each piece of the batch that gouges, with
    how deep it cuts."""
    cdef const ClPiece *q
    if found == -1:
        return True
    if found == -2:
        S.xs.err_number = ERR_OUT_OF_MEMORY
        S.xs.err_part = k
        return False
    if S.lenient:
        while found >= 0:
            q = &S.cl.batch[found]
            comp_gouge(S, q.t.part, q.r - _cl_least(&S.cl, <size_t>found, S.cl.depth))
            found = _cl_scan(&S.cl, <size_t>found + 1, S.cl.depth)
        return True
    q = &S.cl.batch[found]
    S.xs.err_number = ERR_COMP_CROSSING
    S.xs.err_part = q.t.part
    S.xs.err_arg = q.r
    return False


cdef void cl_chain_open(CompState *S, size_t first, size_t ins0) noexcept nogil:
    """A chain starts at part `first` (its insertions from ins0 on): its path is checked
    by cl_chain_upto while it grows and by cl_chain_close at its end."""
    cdef Clearance *C = &S.cl
    C.first = first
    C.next = first
    C.ins0 = ins0
    C.started = False
    C.in_block = False
    C.loose = False
    C.n = 0
    C.n_batch = 0
    C.depth = S.cfg.depth
    C.span = 0
    C.closed = False
    C.only_far = False
    C.grouping = False
    C.n_gbox = 0
    # groups of at most a quarter of the depth: the parts of a group and of its
    # neighbours are near each other (16 .. CL_GROUP parts)
    C.group_shift = 4
    while (<size_t>4 << C.group_shift) <= C.depth and (1 << C.group_shift) < CL_GROUP:
        C.group_shift += 1


cdef inline void _cl_start(CompState *S, size_t at) noexcept nogil:
    """Where the tool stands before part `at` of the chain (the last part before it
    with a position, after the insertions queued there) and the next insertion."""
    cdef Clearance *C = &S.cl
    cdef size_t j = at, rec, hi = S.n_ins, mid
    while j > 0 and S.role[j - 1] == ROLE_FOLLOW:
        j -= 1
    if j > 0:
        j -= 1
        C.cur[0] = S.prog.parts[j].ce[S.first]; C.cur[1] = S.prog.parts[j].ce[S.second]
    else:
        C.cur[0] = S.prog.start[S.first]; C.cur[1] = S.prog.start[S.second]
    # the first insertion after part j or later (the queue is in part order): searched
    # among the chain's own insertions, not the whole queue (a binary search over all of
    # it costs a cache miss a step, on every chain); those before them only when part j
    # has some
    rec = C.ins0 if C.ins0 < hi else hi
    while rec > 0 and S.ins[rec - 1].after >= j:
        rec -= 1
    while rec < hi:
        mid = rec + (hi - rec) / 2
        if S.ins[mid].after < j:
            rec = mid + 1
        else:
            hi = mid
    while rec < S.n_ins and S.ins[rec].after < at:
        C.cur[0] = S.ins[rec].end[0]; C.cur[1] = S.ins[rec].end[1]
        rec += 1
    C.rec = rec
    C.started = True
    C.first_piece = at == C.first


cdef bint _cl_run(CompState *S, size_t upto, size_t end, bint strict, bint skip_first, bint skip_last,
                  size_t last_el) noexcept nogil:
    """Queues the pieces of parts C.next..upto for measuring (the window reaches to
    part `end` at most); a full batch is measured at once. strict: the elements a
    piece's own element crosses count too (a closed contour). skip_first / skip_last:
    the chain's first move / the move of part last_el is a ramp (strategy 1). False
    with S.xs.err_* filled on a gouge or no memory."""
    cdef Clearance *C = &S.cl
    cdef XState *X = &S.xs
    cdef Part *p
    cdef const PartExtra *x
    cdef XPiece *t
    cdef double end_pt[2]
    cdef double c[2]
    cdef double r
    cdef size_t k, j, lo, hi, na, nb, depth = C.depth
    cdef bint have, skip, has_own
    cdef const XPiece *own
    if not C.started:
        _cl_start(S, C.next)
    for k in range(C.next, upto + 1):
        if not C.in_block or k > C.bhi:
            # the next block of parts and the contour of its window (moved on: the
            # elements both windows share are read once)
            if not _cl_gouge(S, _cl_flush(C, depth), k):
                return False
            C.blo = k
            C.bhi = k + CL_BLOCK - 1 if upto - k >= CL_BLOCK else upto
            lo = C.blo - depth if C.blo - C.first > depth else C.first
            hi = C.bhi + depth if end - C.bhi > depth else end
            if not _cl_slide(S, C, lo, hi):
                X.err_number = ERR_OUT_OF_MEMORY
                X.err_part = k
                return False
            C.in_block = True
            C.allow = S.cfg.slack + S.cfg.min_arc + C.max_off
            C.ei = 0
        while C.ei < C.n and C.el[C.ei].part < k:
            C.ei += 1
        has_own = C.ei < C.n and C.el[C.ei].part == k
        own = &C.el[C.ei] if has_own and not strict else NULL
        p = &S.prog.parts[k]
        r = fabs(comp_distance(S, p))
        if S.role[k] == ROLE_SET and p.kind == PART_MOTION and p.func != 0:
            t = &C.batch[C.n_batch].t       # built where the batch keeps it
            end_pt[0] = p.ce[S.first]; end_pt[1] = p.ce[S.second]
            x = part_extra(S.prog, p)
            if (p.func == 2 or p.func == 3) and x.radius > 0:
                c[0] = x.cc[S.first]; c[1] = x.cc[S.second]
                have = _cl_arc(t, C.cur, end_pt, c, x.radius, 1 if p.func == 3 else -1, k, True)
            else:
                have = distance2d(end_pt[0] - C.cur[0], end_pt[1] - C.cur[1]) > ROUNDING_EPS
                if have:
                    _cl_line(t, C.cur, end_pt, k)
            skip = (C.first_piece and skip_first) or (k == last_el and skip_last)
            C.first_piece = False
            # a line on the offset of a line keeps the radius from it and, past a corner
            # of the chain (an intersection or an arc), from a line next to it (not from
            # a removed one: the corner joined an earlier part)
            # (a piece running back along its line, kept by a lenient chain, does not)
            nb = <size_t>-1
            if have and not skip and t.kind == EL_LINE and p.func == 1 and C.ei > C.el0 \
                    and S.prog.parts[C.el[C.ei - 1].part].func == 1 and S.role[C.el[C.ei - 1].part] == ROLE_SET \
                    and (not S.lenient or not has_own or
                         (t.e[0] - t.s[0]) * (C.el[C.ei].e[0] - C.el[C.ei].s[0])
                         + (t.e[1] - t.s[1]) * (C.el[C.ei].e[1] - C.el[C.ei].s[1]) > 0):
                nb = C.el[C.ei - 1].part
            if have and not skip and \
                    not _cl_gouge(S, _cl_queue(C, own, k, nb, r, r - C.allow, depth), k):
                return False
            C.cur[0] = end_pt[0]; C.cur[1] = end_pt[1]
        while C.rec < S.n_ins and S.ins[C.rec].after == k:
            t = &C.batch[C.n_batch].t
            end_pt[0] = S.ins[C.rec].end[0]; end_pt[1] = S.ins[C.rec].end[1]
            have = False
            if not S.ins[C.rec].no_centre:
                if S.ins[C.rec].func == INS_G1:
                    have = distance2d(end_pt[0] - C.cur[0], end_pt[1] - C.cur[1]) > ROUNDING_EPS \
                        and not _cl_side_change(S, k, end)
                    if have:
                        _cl_line(t, C.cur, end_pt, k)
                else:
                    have = _cl_arc(t, C.cur, end_pt, S.ins[C.rec].cc, r, 1 if S.ins[C.rec].func == INS_G3 else -1,
                                   k, False)
            # an arc round the corner at part k's end keeps the radius from the elements
            # that meet there (the next one unless it was removed)
            nb = <size_t>-1
            na = <size_t>-1
            if have and S.ins[C.rec].func != INS_G1 and S.ins[C.rec].cc[0] == p.e[S.first] \
                    and S.ins[C.rec].cc[1] == p.e[S.second]:
                na = k
                j = C.ei + 1 if has_own else C.ei
                if j < C.el_end and S.role[C.el[j].part] == ROLE_SET:
                    nb = C.el[j].part
            if have and not _cl_gouge(S, _cl_queue(C, NULL, na, nb, r, r - C.allow, depth), k):
                return False
            C.cur[0] = end_pt[0]; C.cur[1] = end_pt[1]
            C.rec += 1
    if upto + 1 > C.next:
        C.next = upto + 1
    return True


cdef bint cl_chain_upto(CompState *S, size_t written) noexcept nogil:
    """The open elements start at part `written`; the path before it can still be cut
    by a loop up to the search depth back: the pieces of the parts before the last
    element of the chain at least that far back are final and checked now (what
    _cl_side_change reads is final too). False with S.xs.err_* filled."""
    cdef size_t k, depth = S.cfg.depth
    if written <= depth + 1 + S.cl.next:
        return True
    k = written - depth - 1
    while k > S.cl.next and S.role[k] != ROLE_SET:
        k -= 1
    if k <= S.cl.next:
        return True
    S.cl.grouping = True        # more parts than the depth: the far check will need the boxes
    return _cl_run(S, k - 1, written - 1, False, S.chain_fixed, False, <size_t>-1)


cdef bint _cl_seam(CompState *S, size_t last, bint skip_first, bint skip_last, size_t last_el) noexcept nogil:
    """A closed chain longer than the search depth: its first parts and its last ones
    are neighbours round its start, which part order leaves out. The pieces of both
    ends are measured against the elements of both, distances counted round the chain
    (the pairs part order measured already come again: O(depth)). False with
    S.xs.err_* filled."""
    cdef Clearance *C = &S.cl
    cdef size_t depth = C.depth, first = C.first, head, tail
    cdef bint ok
    if depth == 0 or last - first <= depth:
        return True
    head = first + depth - 1
    tail = last - depth + 1
    if head + 1 >= tail:
        head = last             # the ends overlap: the chain in one walk
        tail = last + 1
    C.n = 0
    ok = _cl_read(S, C, first, head)
    C.el_end = C.n
    if not ok or (tail <= last and not _cl_read(S, C, tail, last)) or not _cl_boxes(C):
        S.xs.err_number = ERR_OUT_OF_MEMORY
        S.xs.err_part = last
        return False
    C.span = last - first + 1
    C.closed = True
    C.in_block = True           # the window stays (no block moves it)
    C.bhi = last
    C.allow = S.cfg.slack + S.cfg.min_arc + C.max_off
    C.el0 = 0
    C.ei = 0
    _cl_start(S, first)
    C.next = first
    ok = _cl_run(S, head, last, True, skip_first, skip_last, last_el)
    if ok and tail <= last:
        C.el0 = C.el_end
        C.el_end = C.n
        C.ei = C.el0
        _cl_start(S, tail)
        C.next = tail
        ok = _cl_run(S, last, last, True, skip_first, skip_last, last_el)
    ok = ok and _cl_gouge(S, _cl_flush(C, depth), last)
    C.closed = False
    C.n = 0                     # the next window is read afresh
    return ok


cdef bint cl_chain_close(CompState *S, size_t last, bint skip_first, bint skip_last) noexcept nogil:
    """Checks the rest of the chain's path, which ends at part `last` (skip_first /
    skip_last: see _cl_run). A closed contour counts the elements a piece's own
    element crosses: if an earlier piece left one out, the path is measured again from
    its start; its first and last parts are neighbours (_cl_seam). False with
    S.xs.err_* filled."""
    cdef Clearance *C = &S.cl
    cdef const double *st = part_start_xyz(S.prog, C.first)
    cdef const Part *p = &S.prog.parts[last]
    cdef bint is_open = distance2d(st[S.first] - p.e[S.first], st[S.second] - p.e[S.second]) > CLOSED_EPS
    cdef size_t last_el = last
    cdef XPiece g
    if not is_open and C.loose:
        cl_chain_open(S, C.first, C.ins0)
    if C.next == C.first:
        C.grouping = _cl_far_needed(C, last, not is_open)    # nothing measured yet
    while last_el > C.first and (S.role[last_el] != ROLE_SET or not cl_element(S, last_el, &g)):
        last_el -= 1
    if not _cl_run(S, last, last, not is_open, skip_first, skip_last, last_el) or \
            not _cl_gouge(S, _cl_flush(C, C.depth), last):
        return False
    if not is_open and not _cl_seam(S, last, skip_first, skip_last, last_el):
        return False
    return _cl_far_check(S, last, not is_open, skip_first, skip_last, last_el)


cdef inline bint _cl_all_near(const Clearance *C, size_t a0, size_t a1, size_t b0, size_t b1) noexcept nogil:
    """Whether every part of a0..a1 lies at most the depth from every part of b0..b1
    (C.closed: round the chain, C.span parts)."""
    cdef size_t lo, hi
    if a0 > b0:
        a0, a1, b0, b1 = b0, b1, a0, a1
    lo = b0 - a1 if b0 > a1 else 0
    hi = b1 - a0
    return hi <= C.depth or (C.closed and lo + C.depth >= C.span)


cdef inline bint _cl_far_needed(const Clearance *C, size_t last, bint closed) noexcept nogil:
    """Whether the chain of parts C.first..last has parts farther apart than the depth
    (both ways round when closed)."""
    cdef size_t span = last - C.first + 1
    return (span / 2 if closed else span - 1) > C.depth


cdef bint _cl_far_check(CompState *S, size_t last, bint closed, bint skip_first, bint skip_last,
                        size_t last_el) noexcept nogil:
    """The chain's path against the contour of the parts farther apart than the search
    depth (both ways round a closed contour), which the walks above leave out: the
    depth bounds how far back parts may be removed, not where a gouge is seen. Per
    group of parts (C.group_shift), the box of its pieces grown by their radius is
    searched in a box index of the groups' element boxes (C.far_groups): O(log n) a group on
    an ordinary contour, where only its neighbours' boxes meet it. Only a group that
    meets a far group is walked again, against those groups' elements, the near ones
    not counted (C.only_far). Nothing on a chain that short. False with S.xs.err_*
    filled."""
    cdef Clearance *C = &S.cl
    cdef size_t first = C.first, span = last - first + 1, n = C.n_gbox, G = (<size_t>1) << C.group_shift
    cdef size_t a, b, k, n_hot, a0, a1, b0
    cdef int64_t found
    cdef size_t *hot = NULL
    cdef const double *pa
    cdef bint ok = True
    if not _cl_far_needed(C, last, closed):
        return True
    hot = <size_t *>tc_malloc((n + 1) * sizeof(size_t))
    box_index_clear(&C.far_groups)
    for b in range(n):
        if hot == NULL or not box_index_append(&C.far_groups, &C.gbox[8 * b + 4]):
            free(hot)
            S.xs.err_number = ERR_OUT_OF_MEMORY
            S.xs.err_part = last
            return False
    C.span = span
    C.closed = closed
    for a in range(n):
        pa = &C.gbox[8 * a]
        a0 = first + a * G
        a1 = a0 + G - 1 if a0 + G - 1 < last else last
        # the far groups whose elements' box meets the group's pieces' box, in order,
        # and the group itself (its pieces' own and next elements) at its place
        n_hot = 0
        found = -1
        while True:
            found = box_index_next(&C.far_groups, <size_t>(found + 1), n, pa, 0.0)
            if found < 0:
                break
            b0 = first + <size_t>found * G
            if not _cl_all_near(C, a0, a1, b0, b0 + G - 1 if b0 + G - 1 < last else last):
                hot[n_hot] = <size_t>found
                n_hot += 1
        if n_hot == 0:
            continue
        k = n_hot
        while k > 0 and hot[k - 1] > a:
            k -= 1
        if k == 0 or hot[k - 1] != a:   # (a group of more parts than the depth is far from itself)
            memmove(&hot[k + 1], &hot[k], (n_hot - k) * sizeof(size_t))
            hot[k] = a
            n_hot += 1
        C.n = 0
        for k in range(n_hot):
            b = hot[k]
            b0 = first + b * G
            if b == a:
                C.el0 = C.n
            ok = _cl_read(S, C, b0, b0 + G - 1 if b0 + G - 1 < last else last)
            if b == a:
                C.el_end = C.n
            if not ok:
                break
        if not ok or not _cl_boxes(C):
            S.xs.err_number = ERR_OUT_OF_MEMORY
            S.xs.err_part = a0
            ok = False
            break
        C.only_far = True
        C.in_block = True       # the window stays (no block moves it)
        C.bhi = last
        C.allow = S.cfg.slack + S.cfg.min_arc + C.max_off
        C.ei = C.el0
        _cl_start(S, a0)
        C.next = a0
        ok = _cl_run(S, a1, last, closed, skip_first, skip_last, last_el) and \
            _cl_gouge(S, _cl_flush(C, C.depth), a1)
        C.only_far = False
        if not ok:
            break
    C.only_far = False
    C.closed = False
    C.n = 0                     # the next window is read afresh
    free(hot)
    return ok


cdef bint cl_check_chain(CompState *S, size_t first, size_t last, size_t ins0, bint skip_first,
                         bint skip_last, size_t depth) noexcept nogil:
    """Checks the final tool path of the chain of parts first..last (its insertions
    from ins0 on) at once, against the contour of the parts at most `depth` apart:
    cl_chain_open, cl_chain_close. False with S.xs.err_* filled: 504 on the line of
    the first piece that gouges (or out of memory).
    The allowance is tolerance[1], plus tolerance[4] (a removed small arc lets the
    neighbours meet closer to it) and how far an arc's end lies off its circle (the
    arc-centre tolerance of the compiler)."""
    cl_chain_open(S, first, ins0)
    S.cl.depth = depth
    return cl_chain_close(S, last, skip_first, skip_last)


cdef void cl_free(Clearance *C) noexcept nogil:
    """Frees the gouge check's arrays and leaves them NULL."""
    free(C.el)
    free(C.off)
    free(C.cand)
    free(C.cbox)
    C.off = NULL
    C.cand = NULL
    C.cbox = NULL
    free(C.gbox)
    C.gbox = NULL
    C.n_gbox = 0
    C.cap_gbox = 0
    C.el = NULL
    box_index_free(&C.ix)
    box_index_free(&C.far_groups)
