# The connection search of ConnectCNCEx_Plane (docs/api.md): the place on a program, as a
# run places it (placement.pyx), where the machine connects to. Pure and typed, no
# GIL, no Python objects: the machine calls it from its own thread and does the
# moving, the statuses and the callbacks. Rules and costs: docs/connect.md.
#
# Each search fills a ConnectHit (the part, the path length s from the part's start,
# the point in all ten axes, the distance in the chosen axes) and returns
# CONNECT_FOUND, or another ConnectResult with the catalogue's error (700..705) in
# `err` (err may be NULL). `axes` is axesForCalc (bit k = axis k in X Y Z C B U V W
# A O order, 0 = all ten); distances are measured in those axes only.
#
#   connect_index_build(ix, prog, pl, axes, err)     index of the motion parts
#   connect_index_free(ix)
#   connect_nearest(ix, point, max_distance, first, end, hit, err)    nType 0 10 40
#   connect_nearest_each(prog, pl, axes, point, max_distance, first, end, hook, ctx,
#                        hit, err)    the same without an index, each part's candidate
#                                     offered to `hook` (ConnectPointCalc, 1005)
#   connect_line(prog, pl, coords, n_coords, at_end, hit, err)       1 2 11 12 41 42
#   connect_mfunc(prog, pl, coords, n_coords, relative, current, status, hit, err)
#                                                                     20 21
#   connect_gindex(prog, pl, coords, n_coords, at_end, hit, err)     30 32
#   connect_gindex_nearest(prog, pl, coords, n_coords, point, axes, max_distance,
#                          hit, err)                                  31 44
#   connect_exact_point(prog, pl, coords, n_coords, axes, tolerance, hit, err)   46
#   connect_bad_argument(err, name, value, why)   error 700 for an argument the caller checks
#
# maxConnectionDistance (docs/structures.md, the vendor's text): a part farther than it from the
# point counts by its two end points only, so a far point connects to a vertex of
# the trajectory, never into the middle of a part; <= 0 (or not finite) = no limit.
from libc.math cimport sqrt, floor, isfinite, INFINITY
from libc.stdlib cimport free
from libc.string cimport memset


# ---- errors ------------------------------------------------------------------------

cdef int connect_bad_argument(ErrorInfo *err, const char *name, double value, const char *why) noexcept nogil:
    """Error 700 naming the argument, its value and why (e.g. "nType", 7, "no such
    connect type"); returns CONNECT_BAD_ARGUMENT."""
    if err != NULL:
        err_connect_bad_argument(err, -1, 0, name, value, why)
    return CONNECT_BAD_ARGUMENT


cdef int _cs_bad_coord(ErrorInfo *err, int k, double value, const char *why) noexcept nogil:
    """The bad-argument error naming coords[k], its value and why."""
    cdef char name[16]
    c_snprintf(name, sizeof(name), "coords[%d]", k)
    return connect_bad_argument(err, name, value, why)


cdef int _cs_no_motion(ErrorInfo *err, size_t first, size_t end, size_t n_parts) noexcept nogil:
    """The error of a range [first, end) (clamped to the program) without a motion part to
    connect to: CONNECT_NOT_FOUND. err may be NULL."""
    if err != NULL:
        err_connect_no_motion(err, -1, 0, min(first, n_parts), min(end, n_parts), n_parts)
    return CONNECT_NOT_FOUND


cdef int _cs_no_memory(ErrorInfo *err) noexcept nogil:
    """Out of memory: the error (err may be NULL) and CONNECT_NO_MEMORY."""
    if err != NULL:
        err_out_of_memory(err, -1, 0)
    return CONNECT_NO_MEMORY


cdef bint _cs_whole(const double *coords, int k, double lo, double hi, int64_t *out,
                 ErrorInfo *err) noexcept nogil:
    """coords[k] as a whole number in [lo, hi]; else the bad-argument error."""
    cdef double v = coords[k]
    if not (v >= lo and v <= hi) or v != floor(v):          # NaN fails too
        _cs_bad_coord(err, k, v, "not a whole number in range")
        return False
    out[0] = <int64_t>v
    return True


cdef bint _cs_finite_point(const double *point, uint32_t axes, ErrorInfo *err) noexcept nogil:
    """Whether the point's coordinates on the axes of the mask are finite; else the bad-argument
    error of the first that is not."""
    cdef int k
    for k in range(AXES):
        if (axes >> k) & 1 and not isfinite(point[k]):
            _cs_bad_coord(err, k, point[k], "not a finite number")
            return False
    return True


cdef inline uint32_t _cs_mask(uint32_t axes) noexcept nogil:
    """The mask of axes the distance is measured in: 0 means all (CONNECT_ALL_AXES)."""
    return CONNECT_ALL_AXES if axes == 0 else axes


# ---- where a part stands as the run places it (a motion part: geometry.pyx
# segment_of_placed_part) ------------------------------------------------------------------

cdef void _cs_part_position(const Program *prog, const Placement *pl, size_t i,
                         double *out) noexcept nogil:
    """Where a part that does not move (M function, dwell, text) stands: the
    compensated end of the motion before it, as the run places it."""
    cdef double start_shift[AXES]
    cdef double end_shift[AXES]
    cdef int k
    part_calc_start(prog, i, out)
    if pl.moved:
        placement_shift(prog, i, pl, start_shift, end_shift)
        for k in range(AXES):
            out[k] += start_shift[k]


# ---- the nearest point of one part (geometry.pyx segment_nearest) ------------------------

cdef double _cs_part_nearest(const Segment *g, uint32_t axes, const double *q,
                          double max_d2, double *s) noexcept nogil:
    """Squared distance from q to the part by the vendor's rule (beyond max_d2 the
    nearer end counts) and the path length s of that point."""
    cdef double point[AXES]
    cdef double d2, d2_start, d2_end
    s[0] = segment_nearest(g, axes, q)
    d2 = segment_distance2_at(g, s[0], axes, q, point)
    if d2 <= max_d2:
        return d2
    d2_start = segment_distance2_at(g, 0.0, axes, q, point)
    d2_end = segment_distance2_at(g, g.length, axes, q, point)
    if d2_end < d2_start:
        s[0] = g.length
        return d2_end
    s[0] = 0.0
    return d2_start


# ---- hits ------------------------------------------------------------------------------

cdef void _cs_hit_at(const Program *prog, const Placement *pl, size_t i, bint at_end,
                  ConnectHit *hit) noexcept nogil:
    """The start (end) of part i."""
    cdef Segment g
    hit.part = i
    hit.distance = 0.0
    if prog.parts[i].kind == PART_MOTION:
        segment_of_placed_part(prog, i, pl, &g)
        hit.length = g.length
        hit.s = g.length if at_end else 0.0
        segment_point_at(&g, hit.s, hit.point)
    else:
        hit.length = 0.0
        hit.s = 0.0
        _cs_part_position(prog, pl, i, hit.point)


cdef void _cs_hit_nearest(const Program *prog, const Placement *pl, size_t i, uint32_t axes,
                       const double *q, double max_d2, ConnectHit *hit) noexcept nogil:
    """The point of part i nearest q (by the rule of max_d2)."""
    cdef Segment g
    cdef double d2 = 0.0, d
    cdef int k
    hit.part = i
    if prog.parts[i].kind == PART_MOTION:
        segment_of_placed_part(prog, i, pl, &g)
        _cs_part_nearest(&g, axes, q, max_d2, &hit.s)
        hit.length = g.length
        d2 = segment_distance2_at(&g, hit.s, axes, q, hit.point)
    else:
        hit.length = 0.0
        hit.s = 0.0
        _cs_part_position(prog, pl, i, hit.point)
        for k in range(AXES):
            if (axes >> k) & 1:
                d = hit.point[k] - q[k]
                d2 += d * d
    hit.distance = sqrt(d2)


cdef inline double _cs_limit_d2(double max_distance) noexcept nogil:
    """maxConnectionDistance squared, the bound the search compares with; 0, negative or not
    finite: no bound (INFINITY)."""
    if max_distance > 0.0 and isfinite(max_distance):
        return max_distance * max_distance
    return INFINITY


# ---- every part, in program order -------------------------------------------------------


cdef int connect_nearest_each(const Program *prog, const Placement *pl, uint32_t axes,
                              const double *point, double max_distance, size_t first, size_t end,
                              connect_part_fn hook, void *ctx, ConnectHit *hit,
                              ErrorInfo *err) noexcept nogil:
    """connect_nearest without an index: every motion part of [first, end) in program
    order, each candidate offered to `hook` (may be NULL) before it is compared --
    O(n), for a host whose ConnectPointCalc may change any part's distance. The hit
    takes a changed point; its s stays the part's own nearest point's."""
    cdef Segment g
    cdef ConnectHit candidate
    cdef double max_d2 = _cs_limit_d2(max_distance), d2
    cdef bint found = False
    cdef size_t i
    if axes & ~(<uint32_t>CONNECT_ALL_AXES):
        return connect_bad_argument(err, "axesForCalc", axes, "bits above 0x3FF")
    axes = _cs_mask(axes)
    if not _cs_finite_point(point, axes, err):
        return CONNECT_BAD_ARGUMENT
    if end > prog.n_parts:
        end = prog.n_parts
    i = first
    while i < end:
        if prog.parts[i].kind == PART_MOTION:
            _cs_hit_nearest(prog, pl, i, axes, point, max_d2, &candidate)
            d2 = candidate.distance * candidate.distance
            if hook != NULL and hook(ctx, i, &d2, candidate.point):
                candidate.distance = sqrt(d2) if d2 > 0.0 else 0.0
            if not found or candidate.distance < hit.distance:
                hit[0] = candidate
                found = True
        i += 1
    if not found:
        return _cs_no_motion(err, first, end, prog.n_parts)
    return CONNECT_FOUND


# ---- the index -------------------------------------------------------------------------

cdef void _cs_choose_dims(ConnectIndex *ix) noexcept nogil:
    """X Y Z of the mask always; C..O of the mask when some part may move them: their
    positions are the program's axis entries (Program.axes), the compile's start,
    moved by the placement for the parts that follow the run's start."""
    cdef const Program *prog = ix.prog
    cdef double lo, hi, v, delta
    cdef size_t e
    cdef int k
    ix.n_dims = 0
    ix.n_fixed = 0
    for k in range(AXES):
        if not (ix.axes >> k) & 1:
            continue
        if k < 3:
            ix.dims[ix.n_dims] = k
            ix.n_dims += 1
            continue
        delta = ix.pl.delta[k]
        lo = prog.start[k]
        hi = lo
        for e in range(prog.n_axes):
            v = prog.axes[OTHER_AXES * e + k - 3]
            lo = min(lo, v)
            hi = max(hi, v)
        if delta != 0.0 or lo != hi:
            ix.dims[ix.n_dims] = k
            ix.n_dims += 1
        else:
            ix.fixed[ix.n_fixed] = k
            ix.fixed_at[ix.n_fixed] = lo
            ix.n_fixed += 1


cdef void _cs_part_box(const Segment *g, const int *dims, int n_dims, double *box) noexcept nogil:
    """The box (low corner, then high) of a part in the axes dims (geometry.pyx
    segment_box: an arc's true extremes)."""
    cdef double lo[AXES]
    cdef double hi[AXES]
    cdef int d
    segment_box(g, lo, hi)
    for d in range(n_dims):
        box[d] = lo[dims[d]]
        box[n_dims + d] = hi[dims[d]]


cdef inline uint64_t _cs_spread3(uint64_t x) noexcept nogil:
    """10 bits to every third bit of 30."""
    x &= 0x3FF
    x = (x | (x << 16)) & 0x030000FF
    x = (x | (x << 8)) & 0x0300F00F
    x = (x | (x << 4)) & 0x030C30C3
    x = (x | (x << 2)) & 0x09249249
    return x


cdef inline uint64_t _cs_spread2(uint64_t x) noexcept nogil:
    """16 bits to every other bit of 32."""
    x &= 0xFFFF
    x = (x | (x << 8)) & 0x00FF00FF
    x = (x | (x << 4)) & 0x0F0F0F0F
    x = (x | (x << 2)) & 0x33333333
    x = (x | (x << 1)) & 0x55555555
    return x


cdef void _cs_radix_sort_high(uint64_t *keys, uint64_t *spare, size_t n) noexcept nogil:
    """Sorts by the high 32 bits, stable (four passes of 8 bits; the result in keys)."""
    cdef size_t count[256]
    cdef size_t r, total, c
    cdef uint64_t *src = keys
    cdef uint64_t *dst = spare
    cdef uint64_t *swap
    cdef int digit, shift
    for shift in range(32, 64, 8):
        memset(count, 0, sizeof(count))
        for r in range(n):
            count[(src[r] >> shift) & 0xFF] += 1
        total = 0
        for digit in range(256):
            c = count[digit]
            count[digit] = total
            total += c
        for r in range(n):
            digit = (src[r] >> shift) & 0xFF
            dst[count[digit]] = src[r]
            count[digit] += 1
        swap = src
        src = dst
        dst = swap


cdef void _cs_morton_keys(const double *part_box, size_t m, int n_dims, uint64_t *keys) noexcept nogil:
    """keys[j] = Morton code of the centre of box j (its first three axes) << 32 | j."""
    cdef int md = min(n_dims, 3), d
    cdef int bits = 10 if md == 3 else (16 if md == 2 else 31)
    cdef double lo[3]
    cdef double scale[3]
    cdef double hi, c, top = <double>((1u << bits) - 1)
    cdef uint64_t cell[3]
    cdef uint64_t code
    cdef size_t j
    cdef const double *box
    for d in range(md):
        lo[d] = INFINITY
        hi = -INFINITY
        for j in range(m):
            box = &part_box[2 * n_dims * j]
            c = 0.5 * (box[d] + box[n_dims + d])
            lo[d] = min(lo[d], c)
            hi = max(hi, c)
        scale[d] = top / (hi - lo[d]) if hi > lo[d] else 0.0
    for j in range(m):
        box = &part_box[2 * n_dims * j]
        for d in range(md):
            c = (0.5 * (box[d] + box[n_dims + d]) - lo[d]) * scale[d]
            cell[d] = <uint64_t>min(max(c, 0.0), top)
        if md == 3:
            code = _cs_spread3(cell[0]) | (_cs_spread3(cell[1]) << 1) | (_cs_spread3(cell[2]) << 2)
        elif md == 2:
            code = _cs_spread2(cell[0]) | (_cs_spread2(cell[1]) << 1)
        elif md == 1:
            code = cell[0]
        else:
            code = 0
        keys[j] = (code << 32) | j


cdef void connect_index_free(ConnectIndex *ix) noexcept nogil:
    """Frees the connection index's arrays and leaves it empty."""
    free(ix.items)
    free(ix.boxes)
    free(ix.span)
    ix.items = NULL
    ix.boxes = NULL
    ix.span = NULL
    ix.n_items = 0
    ix.first_leaf = 0


cdef int connect_index_build(ConnectIndex *ix, const Program *prog, const Placement *pl,
                             uint32_t axes, ErrorInfo *err) noexcept nogil:
    """Indexes the motion parts of prog run from pl (copied; prog must outlive the
    index) for distances in `axes`. O(n) plus a radix sort; connect_index_free
    releases it, also after a failure."""
    cdef Segment g
    cdef size_t n = prog.n_parts, m = 0, i, j, r, leaf, node, n_leaves, first_leaf, stop
    cdef int D, width, d
    cdef double *part_box = NULL
    cdef double *box
    cdef double *child
    cdef uint64_t *keys = NULL
    cdef uint64_t *spare = NULL
    cdef uint32_t *order = NULL
    cdef uint32_t lo_part, hi_part
    memset(ix, 0, sizeof(ConnectIndex))
    if axes & ~(<uint32_t>CONNECT_ALL_AXES):
        return connect_bad_argument(err, "axesForCalc", axes, "bits above 0x3FF")
    ix.prog = prog
    ix.pl = pl[0]
    ix.axes = _cs_mask(axes)
    _cs_choose_dims(ix)
    D = ix.n_dims
    width = 2 * D
    for i in range(n):
        if prog.parts[i].kind == PART_MOTION:
            m += 1
    ix.n_items = m
    if m == 0:
        return CONNECT_FOUND
    n_leaves = (m + CONNECT_LEAF_PARTS - 1) // CONNECT_LEAF_PARTS
    first_leaf = 1
    while first_leaf < n_leaves:
        first_leaf <<= 1
    ix.first_leaf = first_leaf
    ix.items = <uint32_t *>tc_malloc(m * sizeof(uint32_t))
    ix.boxes = <double *>tc_malloc((2 * first_leaf * width + 1) * sizeof(double))
    ix.span = <uint32_t *>tc_malloc(4 * first_leaf * sizeof(uint32_t))
    order = <uint32_t *>tc_malloc(m * sizeof(uint32_t))
    keys = <uint64_t *>tc_malloc(m * sizeof(uint64_t))
    spare = <uint64_t *>tc_malloc(m * sizeof(uint64_t))
    part_box = <double *>tc_malloc((m * width + 1) * sizeof(double))
    if (ix.items == NULL or ix.boxes == NULL or ix.span == NULL or order == NULL or keys == NULL
            or spare == NULL or part_box == NULL):
        free(order)
        free(keys)
        free(spare)
        free(part_box)
        connect_index_free(ix)
        return _cs_no_memory(err)
    j = 0
    for i in range(n):
        if prog.parts[i].kind != PART_MOTION:
            continue
        segment_of_placed_part(prog, i, pl, &g)
        _cs_part_box(&g, ix.dims, D, &part_box[width * j])
        order[j] = <uint32_t>i
        j += 1
    _cs_morton_keys(part_box, m, D, keys)
    _cs_radix_sort_high(keys, spare, m)
    # leaves: CONNECT_LEAF_PARTS parts each in Morton order; empty ones after them
    for leaf in range(first_leaf):
        node = first_leaf + leaf
        box = &ix.boxes[width * node]
        for d in range(D):
            box[d] = INFINITY
            box[D + d] = -INFINITY
        lo_part = <uint32_t>-1
        hi_part = 0
        stop = min(m, (leaf + 1) * CONNECT_LEAF_PARTS)
        r = leaf * CONNECT_LEAF_PARTS
        while r < stop:
            j = <size_t>(keys[r] & <uint64_t>0xFFFFFFFFu)
            ix.items[r] = order[j]
            lo_part = min(lo_part, order[j])
            hi_part = max(hi_part, order[j])
            for d in range(D):
                box[d] = min(box[d], part_box[width * j + d])
                box[D + d] = max(box[D + d], part_box[width * j + D + d])
            r += 1
        ix.span[2 * node] = lo_part
        ix.span[2 * node + 1] = hi_part
    node = first_leaf - 1
    while node >= 1:
        box = &ix.boxes[width * node]
        child = &ix.boxes[width * 2 * node]
        for d in range(D):
            box[d] = min(child[d], child[width + d])
            box[D + d] = max(child[D + d], child[width + D + d])
        ix.span[2 * node] = min(ix.span[4 * node], ix.span[4 * node + 2])
        ix.span[2 * node + 1] = max(ix.span[4 * node + 1], ix.span[4 * node + 3])
        node -= 1
    free(order)
    free(keys)
    free(spare)
    free(part_box)
    return CONNECT_FOUND


cdef inline double _cs_node_d2(const ConnectIndex *ix, size_t node, const double *q,
                            size_t first, size_t end, double fixed_d2) noexcept nogil:
    """Squared distance from q to node's box (and the fixed axes); infinite when none
    of its parts is in [first, end)."""
    cdef const double *box = &ix.boxes[2 * ix.n_dims * node]
    cdef double d2 = fixed_d2, t
    cdef int d
    if ix.span[2 * node] >= end or ix.span[2 * node + 1] < first:
        return INFINITY
    for d in range(ix.n_dims):
        t = q[ix.dims[d]]
        if t < box[d]:
            d2 += (box[d] - t) * (box[d] - t)
        elif t > box[ix.n_dims + d]:
            d2 += (t - box[ix.n_dims + d]) * (t - box[ix.n_dims + d])
    return d2


cdef int connect_nearest(const ConnectIndex *ix, const double *point, double max_distance,
                         size_t first, size_t end, ConnectHit *hit, ErrorInfo *err) noexcept nogil:
    """nType 0 / 10 / 40: the point of the trajectory nearest `point` (ten axes; the
    machine fills the axes beyond nCoords with its position) among the motion parts
    [first, end) (end is clipped to the program), by the rule of max_distance. Ties
    go to the lower part index, on a part to the smaller s."""
    cdef const Program *prog = ix.prog
    cdef size_t stack_node[CONNECT_STACK]
    cdef double stack_d2[CONNECT_STACK]
    cdef size_t top = 0, node, left, r, stop, i
    cdef size_t best_part = <size_t>-1
    cdef double best_d2 = INFINITY, best_s = 0.0, max_d2 = _cs_limit_d2(max_distance)
    cdef double fixed_d2 = 0.0, d2, s, d_left, d_right, t
    cdef Segment g
    cdef int k
    if not _cs_finite_point(point, ix.axes, err):
        return CONNECT_BAD_ARGUMENT
    if end > prog.n_parts:
        end = prog.n_parts
    if ix.n_items == 0 or first >= end:
        return _cs_no_motion(err, first, end, prog.n_parts)
    for k in range(ix.n_fixed):
        t = point[ix.fixed[k]] - ix.fixed_at[k]
        fixed_d2 += t * t
    if ix.n_dims == 0:              # every point of every part is as far: the first one
        i = first
        while i < end and prog.parts[i].kind != PART_MOTION:
            i += 1
        if i < end:
            best_part = i
    else:
        d2 = _cs_node_d2(ix, 1, point, first, end, fixed_d2)
        if d2 < INFINITY:
            stack_node[0] = 1
            stack_d2[0] = d2
            top = 1
    while top > 0:
        top -= 1
        node = stack_node[top]
        if stack_d2[top] > best_d2:
            continue
        if node >= ix.first_leaf:
            r = (node - ix.first_leaf) * CONNECT_LEAF_PARTS
            stop = min(ix.n_items, r + CONNECT_LEAF_PARTS)
            while r < stop:
                i = ix.items[r]
                r += 1
                if i < first or i >= end:
                    continue
                segment_of_placed_part(prog, i, &ix.pl, &g)
                d2 = _cs_part_nearest(&g, ix.axes, point, max_d2, &s)
                if d2 < best_d2 or (d2 == best_d2 and i < best_part):
                    best_d2 = d2
                    best_part = i
                    best_s = s
            continue
        left = 2 * node
        d_left = _cs_node_d2(ix, left, point, first, end, fixed_d2)
        d_right = _cs_node_d2(ix, left + 1, point, first, end, fixed_d2)
        if d_left <= d_right:           # the nearer child on top
            if d_right <= best_d2:
                stack_node[top] = left + 1
                stack_d2[top] = d_right
                top += 1
            if d_left <= best_d2:
                stack_node[top] = left
                stack_d2[top] = d_left
                top += 1
        else:
            if d_left <= best_d2:
                stack_node[top] = left
                stack_d2[top] = d_left
                top += 1
            if d_right <= best_d2:
                stack_node[top] = left + 1
                stack_d2[top] = d_right
                top += 1
    if best_part == <size_t>-1:
        return _cs_no_motion(err, first, end, prog.n_parts)
    _cs_hit_nearest(prog, &ix.pl, best_part, ix.axes, point, max_d2, hit)
    return CONNECT_FOUND


# ---- lookups ---------------------------------------------------------------------------

cdef int64_t _cs_part_of_gindex(const Program *prog, int64_t gindex) noexcept nogil:
    """The part with G-code index gindex, -1 if none: a binary search (the indexes
    rise), a scan where M-6 S restarted the numbering."""
    cdef size_t lo = 0, hi = prog.n_parts, mid, i
    while lo < hi:
        mid = lo + (hi - lo) // 2
        if prog.parts[mid].gcode_index < gindex:
            lo = mid + 1
        else:
            hi = mid
    if lo < prog.n_parts and prog.parts[lo].gcode_index == gindex:
        return <int64_t>lo
    for i in range(prog.n_parts):
        if prog.parts[i].gcode_index == gindex:
            return <int64_t>i
    return -1


cdef int _cs_find_gindex(const Program *prog, const double *coords, int k, int64_t *part,
                      ErrorInfo *err) noexcept nogil:
    """The part with the G-code index coords[k]."""
    cdef int64_t gindex
    if not _cs_whole(coords, k, -2147483648.0, 2147483647.0, &gindex, err):
        return CONNECT_BAD_ARGUMENT
    part[0] = _cs_part_of_gindex(prog, gindex)
    if part[0] < 0:
        if err != NULL:
            err_connect_no_gindex(err, -1, 0, gindex)
        return CONNECT_NOT_FOUND
    return CONNECT_FOUND


cdef int connect_gindex(const Program *prog, const Placement *pl, const double *coords,
                        uint32_t n_coords, bint at_end, ConnectHit *hit, ErrorInfo *err) noexcept nogil:
    """nType 30 / 32: the start (at_end: the end) of the part with G-code index
    coords[0]."""
    cdef int64_t part
    cdef int rc
    if n_coords < 1:
        return connect_bad_argument(err, "nCoords", n_coords, "a G-code index needs coords[0]")
    rc = _cs_find_gindex(prog, coords, 0, &part, err)
    if rc != CONNECT_FOUND:
        return rc
    _cs_hit_at(prog, pl, <size_t>part, at_end, hit)
    return CONNECT_FOUND


cdef int connect_gindex_nearest(const Program *prog, const Placement *pl, const double *coords,
                                uint32_t n_coords, const double *point, uint32_t axes,
                                double max_distance, ConnectHit *hit, ErrorInfo *err) noexcept nogil:
    """nType 31 / 44: the point of the part with G-code index coords[0] nearest
    `point` (ten axes: the machine's position) in `axes`, by the rule of max_distance."""
    cdef int64_t part
    cdef int rc
    if n_coords < 1:
        return connect_bad_argument(err, "nCoords", n_coords, "a G-code index needs coords[0]")
    if axes & ~(<uint32_t>CONNECT_ALL_AXES):
        return connect_bad_argument(err, "axesForCalc", axes, "bits above 0x3FF")
    axes = _cs_mask(axes)
    if not _cs_finite_point(point, axes, err):
        return CONNECT_BAD_ARGUMENT
    rc = _cs_find_gindex(prog, coords, 0, &part, err)
    if rc != CONNECT_FOUND:
        return rc
    _cs_hit_nearest(prog, pl, <size_t>part, axes, point, _cs_limit_d2(max_distance), hit)
    return CONNECT_FOUND


cdef int connect_exact_point(const Program *prog, const Placement *pl, const double *coords,
                             uint32_t n_coords, uint32_t axes, double tolerance,
                             ConnectHit *hit, ErrorInfo *err) noexcept nogil:
    """nType 46: coords[0..9] on the part with G-code index coords[10]: the part's
    point nearest them in `axes`, which must lie within `tolerance` (mm) of them;
    else CONNECT_OFF_PART with the hit filled (its distance tells how far)."""
    cdef int64_t part
    cdef int rc
    cdef const Part *p
    if n_coords < 11:
        return connect_bad_argument(err, "nCoords", n_coords, "nType 46 needs 11 coordinates")
    if axes & ~(<uint32_t>CONNECT_ALL_AXES):
        return connect_bad_argument(err, "axesForCalc", axes, "bits above 0x3FF")
    if not (tolerance >= 0.0) or not isfinite(tolerance):
        return connect_bad_argument(err, "tolerance", tolerance, "must be finite and >= 0")
    axes = _cs_mask(axes)
    if not _cs_finite_point(coords, axes, err):
        return CONNECT_BAD_ARGUMENT
    rc = _cs_find_gindex(prog, coords, 10, &part, err)
    if rc != CONNECT_FOUND:
        return rc
    _cs_hit_nearest(prog, pl, <size_t>part, axes, coords, INFINITY, hit)
    if hit.distance > tolerance:
        p = &prog.parts[part]
        if err != NULL:
            err_connect_off_part(err, part_settings(prog, p).file_idx, <int32_t>p.line, hit.distance,
                                 <int64_t>coords[10], tolerance)
        return CONNECT_OFF_PART
    return CONNECT_FOUND


cdef int connect_line(const Program *prog, const Placement *pl, const double *coords,
                      uint32_t n_coords, bint at_end, ConnectHit *hit, ErrorInfo *err) noexcept nogil:
    """nType 1 / 2 (11 12 41 42): the first part at editor line coords[0] of file
    coords[1] (the main file without it); at_end: the end of the last part of the run
    of parts on that line that starts there."""
    cdef int64_t line, file_idx
    cdef size_t i, n = prog.n_parts
    if n_coords < 1:
        return connect_bad_argument(err, "nCoords", n_coords, "a line needs coords[0]")
    if not _cs_whole(coords, 0, 1.0, 4294967295.0, &line, err):
        return CONNECT_BAD_ARGUMENT
    if n_coords >= 2:
        if not _cs_whole(coords, 1, -1.0, 32767.0, &file_idx, err):
            return CONNECT_BAD_ARGUMENT
    else:
        file_idx = prog.main_file_idx
    i = 0
    while i < n and not (prog.parts[i].line == line and part_settings(prog, &prog.parts[i]).file_idx == file_idx):
        i += 1
    if i == n:
        if err != NULL:
            err_connect_no_line(err, <int32_t>file_idx, <int32_t>line, line, file_idx)
        return CONNECT_NOT_FOUND
    if at_end:
        while i + 1 < n and prog.parts[i + 1].line == line \
                and part_settings(prog, &prog.parts[i + 1]).file_idx == file_idx:
            i += 1
    _cs_hit_at(prog, pl, i, at_end, hit)
    return CONNECT_FOUND


cdef int connect_mfunc(const Program *prog, const Placement *pl, const double *coords,
                       uint32_t n_coords, bint relative, int64_t current, int32_t status,
                       ConnectHit *hit, ErrorInfo *err) noexcept nogil:
    """nType 20 / 21: occurrence n = coords[0] of M function coords[1] (programmed
    ones; those the system inserts do not count). n > 0 counts forward: absolute from
    the program's start (1 = the first), relative from the part after `current`;
    n <= 0 counts back: absolute from the end (0 = the last), relative from `current`
    itself (0 = the last one at or before it). current = -1: before the first part.
    The vendor's rule: at the start (status -30) only n > 0, at the end (-32) only
    n <= 0. The hit is where the M function stands."""
    cdef int64_t n, mfunc, seen = 0, need
    cdef int64_t i, last = <int64_t>prog.n_parts - 1
    cdef int64_t step
    cdef const Part *p
    if n_coords < 2:
        return connect_bad_argument(err, "nCoords", n_coords, "nType 20 and 21 need n and M")
    if not _cs_whole(coords, 0, -2147483648.0, 2147483647.0, &n, err):
        return CONNECT_BAD_ARGUMENT
    if not _cs_whole(coords, 1, -2147483648.0, 2147483647.0, &mfunc, err):
        return CONNECT_BAD_ARGUMENT
    if status == CNC_STATUS_AT_START and n <= 0:
        return _cs_bad_coord(err, 0, coords[0], "at the start of the trajectory only n > 0")
    if status == CNC_STATUS_AT_END and n > 0:
        return _cs_bad_coord(err, 0, coords[0], "at the end of the trajectory only n <= 0")
    if current < -1:
        current = -1
    if current > last:
        current = last
    if n > 0:
        i = current + 1 if relative else 0
        step = 1
        need = n
    else:
        i = current if relative else last
        step = -1
        need = 1 - n
    while 0 <= i <= last:
        p = &prog.parts[i]
        if p.kind == PART_MFUNC and p.func == mfunc and not (p.flags & FLAG_INSERTED):
            seen += 1
            if seen == need:
                _cs_hit_at(prog, pl, <size_t>i, False, hit)
                return CONNECT_FOUND
        i += step
    if err != NULL:
        err_connect_no_mfunc(err, -1, 0, n, mfunc, seen)
    return CONNECT_NOT_FOUND
