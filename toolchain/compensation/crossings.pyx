# Crossings of the tool path with itself between parts that are not neighbours (a
# narrow neck of the contour, the arms of a U closer than the tool diameter): loops.
#
# Every element is checked when it becomes final (compensation.pyx `_write_el`): its
# tool path piece (ps -> pe) and then its inserted corner piece (pe -> ins_end) are
# intersected with the final pieces of the same chain whose part lies at most `depth`
# parts back (strategy 0x700). The pieces' boxes are kept in the box index
# (box_index.pxd), searched backwards from the newest piece, so the scan skips whole
# groups far away: O(n * k) with a small k on ordinary contours.
#
# A crossing at X of a later piece P (part B) with an earlier piece Q (part A) means a
# loop: with 0x80000 the path is cut there (Q ends at X, P starts at X, the parts
# between are removed and turned into zero-length moves, their insertions dropped) and
# a warning given; without it error 504 on B's line, or in a lenient chain the loop
# stays (the gouge check warns where it cuts into the contour; without 0x80000 the
# search does not run then). When P is B's inserted corner arc, B's own piece is
# removed too and the rest of its corner arc becomes an insertion after A. A cut that
# leaves nothing of the chain's first part needs 0x10000 (else 504, or kept).
# Not loops: a crossing where the programmed elements cross too (the contour itself
# crosses, the tool has to), and the crossing of the last part of a closed contour with
# the first one (a start at an inner corner: the entry and exit rules; with 0x80000
# compensation.pyx _chain_close_corner trims both to their intersection).
# At the chain's end its whole path is checked against the contour (clearance.pyx): a
# cut that kept the wrong side (a chain started inside a neck narrower than the tool)
# is a gouge, and the chain is rebuilt from its regions (0x80000, regions.pyx).
from libc.stdlib cimport free
from libc.string cimport memmove
from libc.math cimport fabs, M_PI


cdef inline double _x_angle(const XPiece *q, double x, double y) noexcept nogil:
    """Angle of point (x, y) from q's start in q's direction, in [0, 2pi)."""
    return turn_from(q.s[0] - q.c[0], q.s[1] - q.c[1], x - q.c[0], y - q.c[1], q.dir)


cdef inline void _x_sweep(XPiece *q) noexcept nogil:
    """Computes an arc's sweep left for later (< 0) by x_geometry."""
    if q.kind == EL_ARC and q.sweep < 0:
        q.sweep = _x_angle(q, q.e[0], q.e[1])


cdef void x_geometry(XPiece *q) noexcept nogil:
    """Bounding box from s, e (and c, r, dir for arcs: the axis points it passes,
    geometry.pxd arc_axis_points); an arc's sweep == 0 is computed, one < 0 (only
    corner arcs of at most a half turn) left for _x_sweep."""
    cdef unsigned passes
    q.box[0] = q.s[0] if q.s[0] < q.e[0] else q.e[0]
    q.box[2] = q.e[0] if q.s[0] < q.e[0] else q.s[0]
    q.box[1] = q.s[1] if q.s[1] < q.e[1] else q.e[1]
    q.box[3] = q.e[1] if q.s[1] < q.e[1] else q.s[1]
    if q.kind == EL_LINE:
        return
    if q.sweep == 0:
        q.sweep = _x_angle(q, q.e[0], q.e[1])
    passes = arc_axis_points(q.s[0] - q.c[0], q.s[1] - q.c[1], q.e[0] - q.c[0], q.e[1] - q.c[1],
                             q.dir > 0, q.sweep)
    if passes & 1: q.box[2] = q.c[0] + q.r
    if passes & 2: q.box[3] = q.c[1] + q.r
    if passes & 4: q.box[0] = q.c[0] - q.r
    if passes & 8: q.box[1] = q.c[1] - q.r


cdef bint x_on(const XPiece *q, double x, double y, double slack, double *pos) noexcept nogil:
    """Whether a point of q's line / circle lies on the piece; pos = distance along it."""
    cdef double L, t, a
    if q.kind == EL_LINE:
        L = distance2d(q.e[0] - q.s[0], q.e[1] - q.s[1])
        if L <= 0:
            return False
        t = ((x - q.s[0]) * (q.e[0] - q.s[0]) + (y - q.s[1]) * (q.e[1] - q.s[1])) / L
        pos[0] = t
        return t >= -slack and t <= L + slack
    a = _x_angle(q, x, y)
    if a > q.sweep + slack / q.r and a > 2.0 * M_PI - slack / q.r:
        a -= 2.0 * M_PI
    pos[0] = a * q.r
    return pos[0] >= -slack and pos[0] <= q.sweep * q.r + slack


cdef int x_meet(const XPiece *p, const XPiece *q, double slack, double *pts) noexcept nogil:
    """Points where the line / circle of p meets that of q (0, 1 or 2, in pts)."""
    cdef double dx, dy, ex, ey, den, t, L
    cdef double u[2]
    cdef const XPiece *ln
    cdef const XPiece *ci
    if p.kind == EL_LINE and q.kind == EL_LINE:
        dx = p.e[0] - p.s[0]; dy = p.e[1] - p.s[1]
        ex = q.e[0] - q.s[0]; ey = q.e[1] - q.s[1]
        den = dx * ey - dy * ex
        if den * den <= ANGLE_EPS * ANGLE_EPS * (dx * dx + dy * dy) * (ex * ex + ey * ey) + UNDERFLOW_EPS:
            return 0
        # both ends of one on the same side of the other: no crossing
        t = (q.s[0] - p.s[0]) * dy - (q.s[1] - p.s[1]) * dx
        L = (q.e[0] - p.s[0]) * dy - (q.e[1] - p.s[1]) * dx
        if (t > 0 and L > 0) or (t < 0 and L < 0):
            if t * t > slack * slack * (dx * dx + dy * dy) and L * L > slack * slack * (dx * dx + dy * dy):
                return 0
        t = ((q.s[0] - p.s[0]) * ey - (q.s[1] - p.s[1]) * ex) / den
        pts[0] = p.s[0] + t * dx; pts[1] = p.s[1] + t * dy
        return 1
    if p.kind == EL_LINE or q.kind == EL_LINE:
        ln = p if p.kind == EL_LINE else q
        ci = q if p.kind == EL_LINE else p
        L = distance2d(ln.e[0] - ln.s[0], ln.e[1] - ln.s[1])
        if L <= 0:
            return 0
        u[0] = (ln.e[0] - ln.s[0]) / L; u[1] = (ln.e[1] - ln.s[1]) / L
        return 2 if line_circle(ln.s, u, ci.c, ci.r, 0.0, pts) else 0
    return 2 if circle_circle(p.c, p.r, q.c, q.r, 0.0, pts) else 0


cdef inline bint x_near(const double *a, double x, double y, double slack) noexcept nogil:
    """Whether point a lies within `slack` of (x, y) (squared distances: no root)."""
    return (a[0] - x) * (a[0] - x) + (a[1] - y) * (a[1] - y) < slack * slack


cdef bint _x_prog_cross(const XPiece *p, const XPiece *q, double slack) noexcept nogil:
    """Whether the programmed elements of two bodies cross (the contour itself crosses
    there: the tool path has to as well, no loop)."""
    cdef XPiece a, b
    cdef double pts[4]
    cdef double pos
    cdef int m, k
    if not p.gprog or not q.gprog:
        return False
    a = p[0]; b = q[0]
    a.s[0] = p.gs[0]; a.s[1] = p.gs[1]; a.e[0] = p.ge[0]; a.e[1] = p.ge[1]; a.r = p.gR; a.sweep = p.gsweep
    b.s[0] = q.gs[0]; b.s[1] = q.gs[1]; b.e[0] = q.ge[0]; b.e[1] = q.ge[1]; b.r = q.gR; b.sweep = q.gsweep
    m = x_meet(&a, &b, slack, pts)
    for k in range(m):
        if x_on(&a, pts[2 * k], pts[2 * k + 1], slack, &pos) and x_on(&b, pts[2 * k], pts[2 * k + 1], slack, &pos):
            if (x_near(a.s, pts[2 * k], pts[2 * k + 1], slack) or x_near(a.e, pts[2 * k], pts[2 * k + 1], slack)) \
                    and (x_near(b.s, pts[2 * k], pts[2 * k + 1], slack) or x_near(b.e, pts[2 * k], pts[2 * k + 1], slack)):
                continue
            return True
    return False


cdef int64_t _x_find(const XState *X, XPiece *p, double slack, bint last, double *at) noexcept nogil:
    """The earlier piece p crosses first (nearest to p's start along p), -1 if none.
    The last piece (p's predecessor) is not searched; the others from the newest back,
    those whose boxes come within `slack` of p's (the box index)."""
    cdef int64_t best = -1, found
    cdef double best_pos = 1e300, pos, qpos
    cdef double pts[4]
    cdef XPiece *q
    cdef size_t j
    cdef int m, k
    if X.ix.n < 2:
        return -1
    j = X.ix.n - 1                      # candidates: indexes < j
    while True:
        found = box_index_prev(&X.ix, 0, j, p.box, slack)
        if found < 0:
            break
        j = <size_t>found
        q = &X.pc[j]
        if last and q.first:
            continue                    # start/end overlap of a chain: the entry rules
        _x_sweep(p)
        _x_sweep(<XPiece *>q)
        m = x_meet(p, q, slack, pts)
        for k in range(m):
            if not x_on(p, pts[2 * k], pts[2 * k + 1], slack, &pos) or pos >= best_pos:
                continue
            if not x_on(q, pts[2 * k], pts[2 * k + 1], slack, &qpos):
                continue
            # touching at the ends of both (the path passing a shared point) is no loop
            if (x_near(p.s, pts[2 * k], pts[2 * k + 1], slack) or x_near(p.e, pts[2 * k], pts[2 * k + 1], slack)) \
                    and (x_near(q.s, pts[2 * k], pts[2 * k + 1], slack) or x_near(q.e, pts[2 * k], pts[2 * k + 1], slack)):
                continue
            if _x_prog_cross(p, q, slack):
                continue
            best = <int64_t>j
            best_pos = pos
            at[0] = pts[2 * k]; at[1] = pts[2 * k + 1]
    return best


cdef bint _x_add(XState *X, const XPiece *q, size_t depth) noexcept nogil:
    """A final piece into the search: the window drops pieces more than `depth` parts back (a
    provisional join among them: ERR_COMP_NOT_FOUND, the loop round it lies farther back), the
    pieces move with the box index's positions, and the index takes its box. False when memory
    is exhausted or with X.err_* set."""
    cdef size_t cap, shift, base = X.ix.base, n = X.ix.n
    # the search window: parts at most `depth` back
    while base < n and q.part - X.pc[base].part > depth:
        if X.pc[base].prov:
            # the loop around a provisional join is farther back than the search depth
            X.err_number = ERR_COMP_NOT_FOUND
            X.err_part = X.pc[base].part
            return False
        base += 1
    shift = box_index_drop(&X.ix, base)
    if shift > 0:
        memmove(X.pc, &X.pc[shift], (n - shift) * sizeof(XPiece))
    if X.ix.n == X.cap:
        cap = X.cap
        if not grow(<void **>&X.pc, &cap, X.ix.n + 1, sizeof(XPiece)):
            return False
        X.cap = cap
    X.pc[X.ix.n] = q[0]
    return box_index_append(&X.ix, q.box)


cdef void cross_free(XState *X) noexcept nogil:
    """Frees the search's pieces, group boxes and provisional joins."""
    free(X.prov)
    free(X.pc)
    box_index_free(&X.ix)


cdef bint _x_cut(CompState *S, size_t qi, const double *at, size_t b_part, bint b_removed) noexcept nogil:
    """The path leaves piece qi at `at`: the pieces and parts after it up to part
    b_part (exclusive; inclusive when b_removed) are removed."""
    cdef XState *X = &S.xs
    cdef XPiece *q = &X.pc[qi]
    cdef Part *p
    cdef size_t k, stop
    cdef double slack = S.cfg.slack
    if q.ins:
        if x_near(q.s, at[0], at[1], slack):
            S.n_ins = q.rec             # nothing left of the inserted piece
        else:
            S.ins[q.rec].end[0] = at[0]; S.ins[q.rec].end[1] = at[1]
            S.n_ins = q.rec + 1
    else:
        p = &S.prog.parts[q.part]
        p.ce[S.first] = at[0]; p.ce[S.second] = at[1]
        if q.kind == EL_ARC and x_near(q.s, at[0], at[1], slack):
            part_set_radius(S.prog, p, 0.0)     # an arc of no length would read as a full circle
        while S.n_ins > 0 and S.ins[S.n_ins - 1].after >= q.part:
            S.n_ins -= 1
    stop = b_part + 1 if b_removed else b_part
    for k in range(q.part + 1, stop):
        if S.role[k] == ROLE_SET:
            comp_discard(S, k)
    if b_removed:
        comp_discard(S, b_part)
    q.e[0] = at[0]; q.e[1] = at[1]
    q.sweep = 0.0
    x_geometry(q)
    # q is the newest piece now, with its new box (it had room: no memory is taken)
    box_index_truncate(&X.ix, qi)
    return box_index_append(&X.ix, q.box)


cdef int _x_crossing(CompState *S, XPiece *pp, size_t b_part, bint closing, double *at,
                     int64_t *qi) noexcept nogil:
    """Searches a crossing of piece pp; X_WRITE when none, X_DONE when one is to be
    cut at `at`, X_FAIL on error. closing: pp closes the contour where the chain began."""
    cdef XState *X = &S.xs
    qi[0] = _x_find(X, pp, S.cfg.slack, closing, at)
    if qi[0] < 0:
        return X_WRITE
    if not (S.cfg.strategy & CORR_REMOVE_CROSSING) or \
            (X.pc[qi[0]].first and x_near(X.pc[qi[0]].s, at[0], at[1], S.cfg.slack)
             and not (S.cfg.strategy & CORR_ALLOW_FIRST_LAST_CROSS)):
        if S.lenient:
            return X_WRITE              # the loop stays: the gouge check measures it
        X.err_number = ERR_COMP_CROSSING
        X.err_part = b_part
        X.err_arg = fabs(comp_distance(S, &S.prog.parts[b_part]))
        return X_FAIL
    return X_DONE


cdef int cross_write(CompState *S, CompEl *el) noexcept nogil:
    """Hook of _write_el: checks the final element el (and its corner insertion)
    against the earlier path; may move el.ps to a crossing or remove el."""
    cdef XState *X = &S.xs
    cdef XPiece pb, pi
    cdef double at[2]
    cdef int64_t qi
    cdef int res
    cdef InsRec *rec
    cdef bint closing
    if S.lenient and not (S.cfg.strategy & CORR_REMOVE_CROSSING):
        return X_WRITE                  # nothing is cut: the gouge check measures the path
    if el.first:
        box_index_clear(&X.ix)
        X.start[0] = el.s[0]; X.start[1] = el.s[1]
    # the last part of a closed contour crosses the first one where they meet (an inner
    # corner): the start and end rules of the chain, no loop
    closing = el.part == X.last_part and distance2d(el.e[0] - X.start[0], el.e[1] - X.start[1]) < LENGTH_EPS
    # the element's own piece
    pb.part = el.part
    pb.after = 0
    pb.rec = 0
    pb.ins = False
    pb.prov = False
    pb.kind = el.kind
    pb.dir = el.dir
    pb.first = el.first
    pb.s[0] = el.ps[0]; pb.s[1] = el.ps[1]
    pb.e[0] = el.pe[0]; pb.e[1] = el.pe[1]
    pb.c[0] = el.c[0]; pb.c[1] = el.c[1]
    pb.r = el.ro
    pb.gprog = True
    pb.gs[0] = el.s[0]; pb.gs[1] = el.s[1]
    pb.ge[0] = el.e[0]; pb.ge[1] = el.e[1]
    pb.gR = el.R
    pb.gsweep = el.sweep
    if el.kind == EL_ARC:
        pb.sweep = el_path_sweep(el)
        if pb.sweep > 2.0 * M_PI:
            pb.sweep = 2.0 * M_PI
        if pb.sweep < TURN_EPS or pb.r <= 0:
            pb.kind = EL_LINE
            pb.gprog = False
    x_geometry(&pb)
    while True:
        res = _x_crossing(S, &pb, el.part, closing, at, &qi)
        if res != X_DONE:
            break
        comp_warn(S, el.part, "loop removed from the path (offsets of distant parts cross)")
        _x_cut(S, <size_t>qi, at, el.part, False)
        el.ps[0] = at[0]; el.ps[1] = at[1]
        pb.s[0] = at[0]; pb.s[1] = at[1]
        if pb.kind == EL_ARC:
            pb.sweep = 0.0
        x_geometry(&pb)
    if res == X_FAIL:
        return X_FAIL
    if not _x_add(X, &pb, S.cfg.depth):
        return X_FAIL
    if el.ins == INS_NONE:
        return X_WRITE
    # its corner insertion (the InsRec _write_el adds next)
    pi.part = el.part
    pi.after = el.part
    pi.rec = S.n_ins
    pi.ins = True
    pi.first = False
    pi.prov = False
    pi.gprog = False
    pi.sweep = -1.0                     # a corner: computed when the search needs it
    pi.kind = EL_LINE if el.ins == INS_G1 else EL_ARC
    pi.dir = 1 if el.ins == INS_G3 else -1
    pi.s[0] = el.pe[0]; pi.s[1] = el.pe[1]
    pi.e[0] = el.ins_end[0]; pi.e[1] = el.ins_end[1]
    pi.c[0] = el.e[0]; pi.c[1] = el.e[1]
    pi.r = fabs(el.d)
    while X.head_prov < X.n_prov and X.prov[X.head_prov] < el.part:
        X.head_prov += 1
    if X.head_prov < X.n_prov and X.prov[X.head_prov] == el.part:
        X.head_prov += 1
        pi.prov = el.ins == INS_G1 and not S.lenient    # lenient: a join left is measured, not refused
    if distance2d(pi.e[0] - pi.s[0], pi.e[1] - pi.s[1]) < ROUNDING_EPS:
        return X_WRITE
    x_geometry(&pi)
    res = _x_crossing(S, &pi, el.part, False, at, &qi)
    if res == X_FAIL:
        return X_FAIL
    if res == X_WRITE:
        return X_WRITE if _x_add(X, &pi, S.cfg.depth) else X_FAIL
    # the corner piece crosses: el's own piece is part of the loop; the rest of the
    # corner becomes an insertion after the earlier part
    comp_warn(S, el.part, "loop removed from the path (offsets of distant parts cross)")
    box_index_truncate(&X.ix, X.ix.n - 1)  # el's own piece
    _x_cut(S, <size_t>qi, at, el.part, True)
    if distance2d(at[0] - pi.e[0], at[1] - pi.e[1]) >= S.cfg.slack:
        if not ins_add(S, el):
            return X_FAIL
        rec = &S.ins[S.n_ins - 1]
        rec.after = X.pc[qi].part if not X.pc[qi].ins else X.pc[qi].after
        pi.rec = S.n_ins - 1
        pi.after = rec.after
        pi.s[0] = at[0]; pi.s[1] = at[1]
        pi.sweep = 0.0
        x_geometry(&pi)
        if not _x_add(X, &pi, S.cfg.depth):
            return X_FAIL
    return X_DONE


cdef bint cross_join(CompState *S, const CompEl *a, const CompEl *b) noexcept nogil:
    """Hook of _chain_add: no corner between a and b after parts between them were
    removed as crossing (0x80000; typically the parallel walls of a notch narrower than
    the tool). a is joined to b by a G1 that lies in a loop of the path: the crossing
    search must remove it, else error 500 on a's line (at the chain's end or once it
    is farther back than the search depth)."""
    cdef XState *X = &S.xs
    if not (S.cfg.strategy & CORR_REMOVE_CROSSING) or distance2d(a.e[0] - b.s[0], a.e[1] - b.s[1]) <= LENGTH_EPS:
        return False
    if X.head_prov == X.n_prov:
        X.head_prov = 0
        X.n_prov = 0
    if not grow(<void **>&X.prov, &X.cap_prov, X.n_prov + 1, sizeof(size_t)):
        return False
    X.prov[X.n_prov] = a.part
    X.n_prov += 1
    return True


cdef bint cross_chain_end(CompState *S) noexcept nogil:
    """Hook of _chain_end (after the last write): False (err filled in S.xs) when a
    provisional G1 join is still on the path."""
    cdef XState *X = &S.xs
    cdef size_t k
    X.last_part = <size_t>-1
    for k in range(X.ix.base, X.ix.n):
        if X.pc[k].prov:
            X.err_number = ERR_COMP_NOT_FOUND
            X.err_part = X.pc[k].part
            return False
    box_index_clear(&X.ix)
    return True
