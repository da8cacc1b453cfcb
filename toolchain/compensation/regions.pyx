# A closed chain rebuilt from the regions the tool fits in (strategy 0x80000), when
# the chain of corners and loop cuts could not give a path that keeps the tool radius
# (an entry on a part whose offset vanishes, an inside offset split in two, a loop of
# pieces that never cross their neighbours, a spike that crosses the contour itself).
#
# The tool centre may stand where it is at least the tool radius r from the contour
# (on the side the compensation puts it). The border of that set lies on the border
# of the band within r of the contour: the offsets of every element on both sides
# (arcs whose offset radius is negative turn round their centre on the other side)
# and the circles of radius r round the vertices. These pieces are split where they
# cross each other and at the points where they touch (the ends of the offsets on the
# vertex circles); a sub-piece whose middle is closer to the contour than r (less half
# of tolerance[1]) is dropped. Both see the whole contour, whatever the search depth:
# the rebuilt path keeps the radius from all of it. Every piece is oriented with
# the free side where the tool path has it (left for G41): the tool side offsets along
# the contour, the far side ones against it, the circles clockwise for G41. What
# remains are the borders of the free regions, closed loops joined at the nodes. The
# loop kept is the one that encloses the largest area turning the way the contour
# turns: for an inside offset the largest region the tool fits in, for an outside one
# the outer border (not a pocket the contour nearly closes, nor the far side).
#
# The path enters the loop at the first element (program order) whose tool side offset
# has a piece in it; the elements keep their pieces in program order, vertex arcs, far
# side lines and the tool side lines the loop reaches out of program order (a contour
# that crosses itself) become inserted parts (an arc out of order: the rebuild does not
# apply), elements without a piece on their own part are removed (warning 600 on their
# lines).
from libc.stdlib cimport free, qsort
from libc.math cimport fabs, fmax, sin, sqrt, M_PI
from libc.float cimport DBL_EPSILON


cdef int _r_split_cmp(const void *a, const void *b) noexcept nogil:
    """qsort's order of the split points: by piece, then by position along it."""
    cdef const RSplit *x = <const RSplit *>a
    cdef const RSplit *y = <const RSplit *>b
    if x.piece != y.piece:
        return -1 if x.piece < y.piece else 1
    if x.pos != y.pos:
        return -1 if x.pos < y.pos else 1
    return 0


cdef inline double _r_len(const XPiece *q) noexcept nogil:
    """Length of a piece: a line's, or an arc's sweep times its radius."""
    if q.kind == EL_LINE:
        return distance2d(q.e[0] - q.s[0], q.e[1] - q.s[1])
    return q.sweep * q.r


cdef void _r_point(const XPiece *q, double t, double *out) noexcept nogil:
    """The point at distance t along piece q."""
    cdef double L
    if q.kind == EL_LINE:
        L = distance2d(q.e[0] - q.s[0], q.e[1] - q.s[1])
        if L <= 0:
            out[0] = q.s[0]; out[1] = q.s[1]
            return
        out[0] = q.s[0] + (q.e[0] - q.s[0]) * t / L
        out[1] = q.s[1] + (q.e[1] - q.s[1]) * t / L
        return
    arc_point_at(q.c, q.r, q.s[0], q.s[1], q.dir * t / q.r, out)


cdef void regions_free(Regions *R) noexcept nogil:
    """Frees every array of the regions and leaves them empty."""
    free(R.els); free(R.pc); free(R.pel); free(R.pconn); free(R.pn0); free(R.pn1); free(R.sp)
    free(R.sub); free(R.alias); free(R.out_start); free(R.out_list); free(R.loop)
    box_index_free(&R.ix)
    memset(R, 0, sizeof(Regions))


cdef bint _r_piece_room(Regions *R, size_t need) noexcept nogil:
    """Room for `need` pieces in the five arrays that grow alike (the pieces, their elements,
    kinds and two nodes). False when memory is exhausted."""
    cdef size_t c1 = R.cap_pc, c2 = R.cap_pc, c3 = R.cap_pc, c4 = R.cap_pc, c5 = R.cap_pc
    if not grow(<void **>&R.pc, &c1, need, sizeof(XPiece)) or \
            not grow(<void **>&R.pel, &c2, need, sizeof(size_t)) or \
            not grow(<void **>&R.pconn, &c3, need, sizeof(uint8_t)) or \
            not grow(<void **>&R.pn0, &c4, need, sizeof(size_t)) or \
            not grow(<void **>&R.pn1, &c5, need, sizeof(size_t)):
        return False
    R.cap_pc = c1
    return True


cdef size_t _r_node(const Regions *R, size_t v) noexcept nogil:
    """The node v stands for: the end of its chain of aliases (nodes merged where pieces
    meet)."""
    while R.alias[v] != v:
        v = R.alias[v]
    return v


cdef XPiece *_r_new_piece(Regions *R, size_t el, int ptype, size_t n0, size_t n1) noexcept nogil:
    """A new zeroed piece of element el, of kind ptype, from node n0 to node n1; NULL when
    memory is exhausted."""
    cdef XPiece *q
    if not _r_piece_room(R, R.n_pc + 1):
        return NULL
    q = &R.pc[R.n_pc]
    memset(q, 0, sizeof(XPiece))
    q.part = R.els[el].part
    R.pel[R.n_pc] = el
    R.pconn[R.n_pc] = ptype
    R.pn0[R.n_pc] = n0
    R.pn1[R.n_pc] = n1
    R.n_pc += 1
    return q


cdef bint _r_offset_piece(Regions *R, size_t j, double d, int ptype) noexcept nogil:
    """The offset of element j by d (PIECE_FAR: run backwards); nodes 4j + 0/1 (tool
    side start / end), 4j + 2/3 (far side)."""
    cdef const CompEl *a = &R.els[j]
    cdef double ro, s[2], e[2]
    cdef size_t n0 = 4 * j + (0 if ptype == PIECE_TOOL else 2)
    cdef XPiece *q
    ro = el_offset_ends(a, d, s, e)
    if a.kind == EL_ARC and fabs(ro) <= ROUNDING_EPS:
        R.alias[n0 + 1] = n0            # a point: both ends are one node
        return True
    if ptype == PIECE_TOOL:
        q = _r_new_piece(R, j, ptype, n0, n0 + 1)
    else:
        q = _r_new_piece(R, j, ptype, n0 + 1, n0)
    if q == NULL:
        return False
    q.kind = a.kind
    if ptype == PIECE_TOOL:
        q.s[0] = s[0]; q.s[1] = s[1]; q.e[0] = e[0]; q.e[1] = e[1]
    else:
        q.s[0] = e[0]; q.s[1] = e[1]; q.e[0] = s[0]; q.e[1] = s[1]
    if a.kind == EL_ARC:
        q.c[0] = a.c[0]; q.c[1] = a.c[1]
        q.r = fabs(ro)
        q.dir = a.dir if ptype == PIECE_TOOL else -a.dir
        q.sweep = a.sweep
    x_geometry(q)
    return True


cdef bint _r_vertex(Regions *R, size_t j, double d) noexcept nogil:
    """The circle of radius |d| round the vertex after element j, in arcs between the
    offsets' ends on it, clockwise for d > 0 (the free side on the left)."""
    cdef const CompEl *a = &R.els[j]
    cdef size_t jn = (j + 1) % R.n_els
    cdef double pts[8]
    cdef double ang[4]
    cdef size_t nodes[4]
    cdef double tmp_a, t_[2]
    cdef size_t tmp_n, i, k, m = 0
    cdef int direction = -1 if d > 0 else 1
    cdef XPiece *q
    cdef double c[2]
    cdef const CompEl *b = &R.els[jn]
    cdef double ta[2]
    cdef double tb[2]
    c[0] = a.e[0]; c[1] = a.e[1]
    el_tangent(a, True, ta)
    el_tangent(b, False, tb)
    # the four ends on the circle: tool / far side end of j, start of jn
    for i in range(4):
        if i == 0:
            t_[0] = c[0] - d * ta[1]; t_[1] = c[1] + d * ta[0]; tmp_n = 4 * j + 1
        elif i == 1:
            t_[0] = c[0] + d * ta[1]; t_[1] = c[1] - d * ta[0]; tmp_n = 4 * j + 3
        elif i == 2:
            t_[0] = c[0] - d * tb[1]; t_[1] = c[1] + d * tb[0]; tmp_n = 4 * jn
        else:
            t_[0] = c[0] + d * tb[1]; t_[1] = c[1] - d * tb[0]; tmp_n = 4 * jn + 2
        for k in range(m):
            if distance2d(pts[2 * k] - t_[0], pts[2 * k + 1] - t_[1]) <= LENGTH_EPS:
                R.alias[_r_node(R, tmp_n)] = _r_node(R, nodes[k])     # touching ends: one node
                break
        else:
            pts[2 * m] = t_[0]; pts[2 * m + 1] = t_[1]
            nodes[m] = tmp_n
            m += 1
    # in the circle's direction from the first point
    for i in range(m):
        ang[i] = turn_from(pts[0] - c[0], pts[1] - c[1], pts[2 * i] - c[0], pts[2 * i + 1] - c[1], direction)
    for i in range(1, m):
        k = i
        while k > 0 and ang[k] < ang[k - 1]:
            tmp_a = ang[k]; ang[k] = ang[k - 1]; ang[k - 1] = tmp_a
            tmp_n = nodes[k]; nodes[k] = nodes[k - 1]; nodes[k - 1] = tmp_n
            t_[0] = pts[2 * k]; t_[1] = pts[2 * k + 1]
            pts[2 * k] = pts[2 * k - 2]; pts[2 * k + 1] = pts[2 * k - 1]
            pts[2 * k - 2] = t_[0]; pts[2 * k - 1] = t_[1]
            k -= 1
    for i in range(m):
        k = (i + 1) % m
        q = _r_new_piece(R, j, PIECE_VERTEX, nodes[i], nodes[k])
        if q == NULL:
            return False
        q.kind = EL_ARC
        q.s[0] = pts[2 * i]; q.s[1] = pts[2 * i + 1]
        q.e[0] = pts[2 * k]; q.e[1] = pts[2 * k + 1]
        q.c[0] = c[0]; q.c[1] = c[1]
        q.r = fabs(d)
        q.dir = direction
        q.sweep = ang[k] - ang[i] if k > i else 2.0 * M_PI - ang[i]
        x_geometry(q)
    return True


cdef bint _r_raw_curve(Regions *R, double d) noexcept nogil:
    """The border pieces of the band within |d| of the closed chain R.els."""
    cdef size_t j, cap = R.cap_alias
    if not grow(<void **>&R.alias, &cap, 4 * R.n_els, sizeof(size_t)):
        return False
    R.cap_alias = cap
    for j in range(4 * R.n_els):
        R.alias[j] = j
    R.n_pc = 0
    for j in range(R.n_els):
        if not _r_offset_piece(R, j, d, PIECE_TOOL) or not _r_offset_piece(R, j, -d, PIECE_FAR):
            return False
    for j in range(R.n_els):
        if not _r_vertex(R, j, d):
            return False
    for j in range(R.n_pc):
        R.pn0[j] = _r_node(R, R.pn0[j])
        R.pn1[j] = _r_node(R, R.pn1[j])
    return R.n_pc > 0


cdef bint _r_add_split(Regions *R, size_t piece, double pos, double x, double y, size_t node) noexcept nogil:
    """A split of `piece` at `pos` along it, the point (x, y) and its node; False when memory is
    exhausted."""
    cdef RSplit *s
    if not grow(<void **>&R.sp, &R.cap_sp, R.n_sp + 1, sizeof(RSplit)):
        return False
    s = &R.sp[R.n_sp]
    R.n_sp += 1
    s.piece = piece
    s.pos = pos
    s.x = x; s.y = y
    s.node = node
    return True


cdef double _r_end_slack(const Regions *R, double r) noexcept nogil:
    """Pieces that touch at a joint (an offset's end on its vertex circle) are tangent
    there: rounding the coordinates by delta (a few eps times the chain's largest
    coordinate m) moves their meets up to sqrt(2 r delta) from the joint; r = 0.15 mm
    1500 mm from the origin: about 3e-7 mm. The slack is 16 sqrt(r m eps), at least
    MEET_EPS."""
    cdef size_t j
    cdef double m = 1.0
    cdef const CompEl *el
    for j in range(R.n_els):
        el = &R.els[j]
        m = fmax(m, fmax(fmax(fabs(el.s[0]), fabs(el.s[1])), fmax(fabs(el.e[0]), fabs(el.e[1]))))
        if el.kind == EL_ARC:
            m = fmax(m, fmax(fabs(el.c[0]), fabs(el.c[1])))
    return fmax(MEET_EPS, 16.0 * sqrt(r * m * DBL_EPSILON))


cdef bint _r_touch(const Regions *R, size_t i, size_t k, double x, double y) noexcept nogil:
    """Whether pieces i and k meet at (x, y) only where they touch: both end there, or
    (a joint: tangent pieces) they share a node within end_slack of it. A meet this
    near the ends of pieces that share no node is a crossing."""
    cdef const XPiece *a = &R.pc[i]
    cdef const XPiece *b = &R.pc[k]
    if (x_near(a.s, x, y, MEET_EPS) or x_near(a.e, x, y, MEET_EPS)) and \
            (x_near(b.s, x, y, MEET_EPS) or x_near(b.e, x, y, MEET_EPS)):
        return True
    if (R.pn0[i] == R.pn0[k] or R.pn0[i] == R.pn1[k]) and x_near(a.s, x, y, R.end_slack):
        return True
    return (R.pn1[i] == R.pn0[k] or R.pn1[i] == R.pn1[k]) and x_near(a.e, x, y, R.end_slack)


cdef bint _r_crossings(Regions *R, size_t *n_nodes) noexcept nogil:
    """Splits where pieces cross (any two, whatever the search depth; not where both
    end: they touch there at a node already); crossing nodes are numbered after the
    end nodes (4 per element)."""
    cdef size_t i, k, n = R.n_pc
    cdef int64_t found
    cdef double pts[4]
    cdef double pi_, pk, Li, Lk
    cdef double eps = LENGTH_EPS
    cdef int m, h
    cdef XPiece *a
    cdef XPiece *b
    cdef size_t node = 4 * R.n_els
    box_index_clear(&R.ix)
    for i in range(n):
        if not box_index_append(&R.ix, R.pc[i].box):
            return False
    R.n_sp = 0
    for i in range(n):
        a = &R.pc[i]
        Li = _r_len(a)
        found = <int64_t>i
        while True:
            found = box_index_next(&R.ix, <size_t>(found + 1), n, a.box, eps)
            if found < 0:
                break
            k = <size_t>found
            b = &R.pc[k]
            Lk = _r_len(b)
            m = x_meet(a, b, eps, pts)
            for h in range(m):
                if not x_on(a, pts[2 * h], pts[2 * h + 1], eps, &pi_) or \
                        not x_on(b, pts[2 * h], pts[2 * h + 1], eps, &pk):
                    continue
                if _r_touch(R, i, k, pts[2 * h], pts[2 * h + 1]):
                    continue
                pi_ = 0.0 if pi_ < 0 else (Li if pi_ > Li else pi_)
                pk = 0.0 if pk < 0 else (Lk if pk > Lk else pk)
                if not _r_add_split(R, i, pi_, pts[2 * h], pts[2 * h + 1], node) or \
                        not _r_add_split(R, k, pk, pts[2 * h], pts[2 * h + 1], node):
                    return False
                node += 1
    n_nodes[0] = node
    qsort(R.sp, R.n_sp, sizeof(RSplit), _r_split_cmp)
    return True


cdef bint _r_subs(Regions *R) noexcept nogil:
    """The sub-pieces between the joints and the crossings."""
    cdef size_t i, k = 0, n = R.n_pc
    cdef RSub *u
    cdef double t0, p0[2]
    cdef size_t n0
    R.n_sub = 0
    for i in range(n):
        t0 = 0.0
        p0[0] = R.pc[i].s[0]; p0[1] = R.pc[i].s[1]
        n0 = R.pn0[i]
        while True:
            if not grow(<void **>&R.sub, &R.cap_sub, R.n_sub + 1, sizeof(RSub)):
                return False
            u = &R.sub[R.n_sub]
            R.n_sub += 1
            u.piece = i
            u.t0 = t0
            u.p0[0] = p0[0]; u.p0[1] = p0[1]
            u.n0 = n0
            u.next = -1
            u.valid = False
            u.seen = 0
            if k < R.n_sp and R.sp[k].piece == i:
                u.t1 = R.sp[k].pos
                u.p1[0] = R.sp[k].x; u.p1[1] = R.sp[k].y
                u.n1 = R.sp[k].node
                t0 = u.t1
                p0[0] = u.p1[0]; p0[1] = u.p1[1]
                n0 = u.n1
                k += 1
                continue
            u.t1 = _r_len(&R.pc[i])
            u.p1[0] = R.pc[i].e[0]; u.p1[1] = R.pc[i].e[1]
            u.n1 = R.pn1[i]
            break
    return True


cdef void _r_classify(Regions *R, const Clearance *C, double r, double slack) noexcept nogil:
    """A sub-piece is kept when its middle keeps the radius from the whole contour."""
    cdef size_t k
    cdef RSub *u
    cdef XPiece pt
    cdef double m[2]
    memset(&pt, 0, sizeof(pt))
    pt.kind = EL_LINE
    for k in range(R.n_sub):
        u = &R.sub[k]
        _r_point(&R.pc[u.piece], 0.5 * (u.t0 + u.t1), m)
        pt.s[0] = m[0]; pt.s[1] = m[1]; pt.e[0] = m[0]; pt.e[1] = m[1]
        pt.part = R.pc[u.piece].part
        x_geometry(&pt)
        u.valid = cl_gap(C, &pt, NULL, <size_t>-1, <size_t>-1, r, <size_t>-1, r - 0.5 * slack) >= r - 0.5 * slack


cdef bint _r_link(Regions *R, size_t n_nodes) noexcept nogil:
    """Each kept sub-piece's successor among the kept ones leaving its end node: one on
    another piece when there is one (at a crossing the border turns)."""
    cdef size_t k, v, i, c1 = R.cap_out_start, c2 = R.cap_out_list
    cdef RSub *u
    if not grow(<void **>&R.out_start, &c1, n_nodes + 1, sizeof(size_t)) or \
            not grow(<void **>&R.out_list, &c2, R.n_sub + 1, sizeof(size_t)):
        return False
    R.cap_out_start = c1
    R.cap_out_list = c2
    for v in range(n_nodes + 1):
        R.out_start[v] = 0
    for k in range(R.n_sub):
        if R.sub[k].valid:
            R.out_start[R.sub[k].n0 + 1] += 1
    for v in range(n_nodes):
        R.out_start[v + 1] += R.out_start[v]
    for k in range(R.n_sub):
        if R.sub[k].valid:
            v = R.sub[k].n0
            R.out_list[R.out_start[v]] = k
            R.out_start[v] += 1
    for v in range(n_nodes, 0, -1):
        R.out_start[v] = R.out_start[v - 1]
    R.out_start[0] = 0
    for k in range(R.n_sub):
        u = &R.sub[k]
        if not u.valid:
            continue
        v = u.n1
        for i in range(R.out_start[v], R.out_start[v + 1]):
            if u.next < 0 or R.sub[R.out_list[i]].piece != u.piece:
                u.next = <int64_t>R.out_list[i]
                if R.sub[R.out_list[i]].piece != u.piece:
                    break
    return True


cdef double _r_sub_area(const Regions *R, const RSub *u) noexcept nogil:
    """Twice the signed area a sub-piece adds to its loop (chord and arc segment)."""
    cdef const XPiece *q = &R.pc[u.piece]
    cdef double a = u.p0[0] * u.p1[1] - u.p1[0] * u.p0[1]
    cdef double al
    if q.kind == EL_ARC:
        al = q.dir * (u.t1 - u.t0) / q.r
        a += q.r * q.r * (al - sin(al))
    return a


cdef int64_t _r_best_loop(Regions *R, double orient, size_t *n_loop) noexcept nogil:
    """The kept loop enclosing the largest area turning like the contour (orient: its
    sign); its sub-pieces go to R.loop. -1 when there is none, -2 out of memory."""
    cdef size_t k, j, n, best_n = 0
    cdef int64_t best = -1, cur, c
    cdef double area, best_area = 0.0
    cdef uint32_t walk = 0
    for k in range(R.n_sub):
        if not R.sub[k].valid or R.sub[k].seen:
            continue
        # follow the successors until a sub-piece seen before: a loop when it was seen
        # on this walk (a tail leading into a loop is not part of it)
        walk += 1
        cur = <int64_t>k
        while cur >= 0 and R.sub[cur].seen == 0:
            R.sub[cur].seen = walk
            cur = R.sub[cur].next
        if cur < 0 or R.sub[cur].seen != walk:
            continue
        area = 0.0
        n = 0
        c = cur
        while True:
            area += _r_sub_area(R, &R.sub[c])
            n += 1
            c = R.sub[c].next
            if c == cur:
                break
        if area * orient > best_area:
            best_area = area * orient
            best = cur
            best_n = n
    if best < 0:
        return -1
    if not grow(<void **>&R.loop, &R.cap_loop, best_n, sizeof(size_t)):
        return -2
    cur = best
    for j in range(best_n):
        R.loop[j] = <size_t>cur
        cur = R.sub[cur].next
    n_loop[0] = best_n
    return best


cdef bint _r_chain_elements(CompState *S, Regions *R, double *d) noexcept nogil:
    """The elements of the chain S.chain_first .. S.chain_last; False when the chain
    is not closed or changes its tool radius (the rebuild does not apply)."""
    cdef size_t k
    cdef bint is_arc
    cdef CompEl el
    R.n_els = 0
    for k in range(S.chain_first, S.chain_last + 1):
        if not comp_part_element(S, k, &el):
            continue
        if R.n_els > 0 and el.d != R.els[0].d:
            return False
        if not grow(<void **>&R.els, &R.cap_els, R.n_els + 1, sizeof(CompEl)):
            return False
        R.els[R.n_els] = el
        R.n_els += 1
    if R.n_els == 0:
        return False
    d[0] = R.els[0].d
    return distance2d(R.els[0].s[0] - R.els[R.n_els - 1].e[0], R.els[0].s[1] - R.els[R.n_els - 1].e[1]) <= CLOSED_EPS


cdef double _r_contour_area(const Regions *R) noexcept nogil:
    """Twice the signed area the contour's elements enclose (shoelace over the chords, plus each
    arc's segment): its sign is the contour's turn."""
    cdef size_t j
    cdef double a = 0.0, al
    cdef const CompEl *el
    for j in range(R.n_els):
        el = &R.els[j]
        a += el.s[0] * el.e[1] - el.e[0] * el.s[1]
        if el.kind == EL_ARC:
            al = el.dir * el.sweep
            a += el.R * el.R * (al - sin(al))
    return a


cdef int regions_rebuild(CompState *S) noexcept nogil:
    """Rebuilds the chain S.chain_first .. S.chain_last (its insertions from
    S.chain_ins0 on are dropped): COMPILE_OK, COMPILE_ERROR with S.err filled (out of
    memory) or REGIONS_NOT_APPLICABLE (nothing changed)."""
    cdef Regions *R = &S.rg
    cdef Clearance *C = &S.cl
    cdef size_t n_nodes, n_loop, k, j, start, pc_i, last_part, el_i
    cdef int64_t best
    cdef double d, r, orient
    cdef double at[2]
    cdef RSub *u
    cdef XPiece *q
    cdef Part *p
    cdef uint8_t *kept          # per element: KEPT_ON_PART, KEPT_INSERTED or 0 (no piece)
    cdef size_t key, prev_key, prev_piece, first_el
    if not _r_chain_elements(S, R, &d):
        return REGIONS_NOT_APPLICABLE
    r = fabs(d)
    R.end_slack = _r_end_slack(R, r)
    orient = 1.0 if _r_contour_area(R) > 0 else -1.0
    # the contour of the whole chain for the distances
    if not cl_load(S, C, S.chain_first, S.chain_last) or not _r_raw_curve(R, d) \
            or not _r_crossings(R, &n_nodes) or not _r_subs(R):
        return err_out_of_memory(S.err, comp_file(S, S.chain_first), comp_line(S, S.chain_first))
    _r_classify(R, C, r, S.cfg.slack)
    if not _r_link(R, n_nodes):
        return err_out_of_memory(S.err, comp_file(S, S.chain_first), comp_line(S, S.chain_first))
    best = _r_best_loop(R, orient, &n_loop)
    if best == -2:
        return err_out_of_memory(S.err, comp_file(S, S.chain_first), comp_line(S, S.chain_first))
    if best < 0:
        return REGIONS_NOT_APPLICABLE   # the tool fits nowhere
    # enter at the first element (program order) whose tool side offset is in the loop
    start = n_loop
    for k in range(n_loop):
        pc_i = R.sub[R.loop[k]].piece
        if R.pconn[pc_i] != PIECE_TOOL:
            continue
        if start == n_loop or R.pel[pc_i] < R.pel[R.sub[R.loop[start]].piece] or \
                (pc_i == R.sub[R.loop[start]].piece and R.sub[R.loop[k]].t0 < R.sub[R.loop[start]].t0):
            start = k
    if start == n_loop:
        return REGIONS_NOT_APPLICABLE   # no element to hang the arcs on
    # the tool side pieces go to their elements' parts in program order; one that comes
    # out of order (a contour that crosses itself: the border passes its elements twice
    # or backwards) is inserted after the last part written, as far side pieces are:
    # both only of lines (an inserted arc has the tool radius)
    first_el = R.pel[R.sub[R.loop[start]].piece]
    prev_key = 0
    prev_piece = R.n_pc
    for j in range(n_loop):
        u = &R.sub[R.loop[(start + j) % n_loop]]
        el_i = R.pel[u.piece]
        u.on_part = False
        if R.pconn[u.piece] == PIECE_FAR and R.els[el_i].kind != EL_LINE:
            return REGIONS_NOT_APPLICABLE
        if R.pconn[u.piece] == PIECE_TOOL:
            if R.els[el_i].kind == EL_ARC and R.els[el_i].ro <= 0:
                return REGIONS_NOT_APPLICABLE
            key = el_i if el_i >= first_el else el_i + R.n_els
            if u.piece == prev_piece:
                u.on_part = R.sub[R.loop[(start + j - 1) % n_loop]].on_part      # the same run goes on
            else:
                u.on_part = j == 0 or key > prev_key
            if u.on_part:
                prev_key = key
            elif R.els[el_i].kind != EL_LINE:
                return REGIONS_NOT_APPLICABLE
        prev_piece = u.piece
    kept = <uint8_t *>tc_malloc(R.n_els)
    if kept == NULL:
        return err_out_of_memory(S.err, comp_file(S, S.chain_first), comp_line(S, S.chain_first))
    for j in range(R.n_els):
        kept[j] = 0
    # the queued insertions of the chain and the warnings of the failed attempt go
    S.n_ins = S.chain_ins0
    S.n_warnings = S.chain_warn0
    u = &R.sub[R.loop[start]]
    at[0] = u.p0[0]; at[1] = u.p0[1]
    if S.chain_entry >= 0 and not S.chain_fixed:
        p = &S.prog.parts[S.chain_entry]
        p.ce[S.first] = at[0]; p.ce[S.second] = at[1]
    elif not ins_line(S, S.chain_first - 1, S.chain_first, at):
        free(kept)
        return err_out_of_memory(S.err, comp_file(S, S.chain_first), comp_line(S, S.chain_first))
    last_part = S.chain_first
    for j in range(n_loop):
        u = &R.sub[R.loop[(start + j) % n_loop]]
        q = &R.pc[u.piece]
        el_i = R.pel[u.piece]
        if not u.on_part:
            if not ins_arc(S, last_part, u.p1, q.c, INS_G1 if R.pconn[u.piece] != PIECE_VERTEX else
                           (INS_G3 if q.dir > 0 else INS_G2)):
                free(kept)
                return err_out_of_memory(S.err, comp_file(S, last_part), comp_line(S, last_part))
            if R.pconn[u.piece] == PIECE_TOOL and not kept[el_i]:
                kept[el_i] = KEPT_INSERTED
            continue
        last_part = R.els[el_i].part
        kept[el_i] = KEPT_ON_PART
        p = &S.prog.parts[last_part]
        p.ce[S.first] = u.p1[0]; p.ce[S.second] = u.p1[1]
        if R.els[el_i].kind == EL_ARC:
            part_set_radius(S.prog, p, R.els[el_i].ro)
        S.role[last_part] = ROLE_SET
    for j in range(R.n_els):
        if kept[j] != KEPT_ON_PART:
            comp_discard(S, R.els[j].part)
            comp_warn(S, R.els[j].part, "part skipped: the tool does not fit there" if not kept[j] else
                      "part's tool path cut after a later line (the contour crosses itself)")
    free(kept)
    if S.chain_exit_fixed:
        at[0] = R.els[R.n_els - 1].e[0]; at[1] = R.els[R.n_els - 1].e[1]
        if not ins_line(S, last_part, last_part, at):
            return err_out_of_memory(S.err, comp_file(S, last_part), comp_line(S, last_part))
    return COMPILE_OK
