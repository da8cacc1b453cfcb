# Face of the box index (box_index.pyx): the one spatial index of the plane. It holds
# the boxes (x0, y0, x1, y1) of elements in the order they come (the pieces of a
# tool path, the elements of a contour, the groups of a chain) and the box of every
# group of 4, 16, 64 ... 4096 of them, so that a search for the elements whose boxes
# meet a box skips whole groups that lie away from it: O(log n + k) on a path that
# does not come back on itself, where a plain scan of the boxes is O(n) per search
# and O(n^2) over a contour. Why one index: the compensation's searches (a piece against
# the earlier path, the path against the contour's window, a chain's groups against
# its far groups, the band's pieces against each other) differ only in how their
# elements come and go, which the index's four operations cover: append at the end,
# cut back from the end, drop from the front (a window moved along a chain), and
# search forwards or backwards between two positions (so a range of neighbours can
# be left out). The elements' own data stay with their users, at the same positions.
# Called by the compensation: crossings.pyx, clearance.pyx, regions.pyx.

# ---- box_index.pyx
cdef enum:
    BOX_LEVELS = 6          # levels of groups: a group of level L holds 4 << 2L elements (4 .. 4096)

# Elements [base, n) are searched. The box of a group of level 0 covers its elements
# held; the box of a group of a higher level covers its complete subgroups (folded in
# as each completes): a search reads a higher group only once it is complete.
ctypedef struct BoxIndex:
    double *box             # the elements' boxes, 4 doubles each, in order
    double *g[BOX_LEVELS]   # the boxes of the groups of each level
    size_t n, cap           # elements held, and room for
    size_t base             # elements before it are dropped (not searched)


# ---- what other stages call
# boxes: whether a and b overlap or come within t of each other; a grown to cover b
# too; a box that covers nothing (any union makes it the other box)
cdef inline bint box_hit(const double *a, const double *b, double t) noexcept nogil:
    return a[0] <= b[2] + t and b[0] <= a[2] + t and a[1] <= b[3] + t and b[1] <= a[3] + t

cdef inline void box_union(double *a, const double *b) noexcept nogil:
    if b[0] < a[0]: a[0] = b[0]
    if b[1] < a[1]: a[1] = b[1]
    if b[2] > a[2]: a[2] = b[2]
    if b[3] > a[3]: a[3] = b[3]

cdef inline void box_empty(double *b) noexcept nogil:
    b[0] = 1e300; b[1] = 1e300; b[2] = -1e300; b[3] = -1e300

# the index: emptied (its memory kept); freed (and left empty, NULL)
cdef void box_index_clear(BoxIndex *I) noexcept nogil
cdef void box_index_free(BoxIndex *I) noexcept nogil
# the elements from n on removed (a cut back; n < I.base drops the base back to n)
cdef void box_index_truncate(BoxIndex *I, size_t n) noexcept nogil
# box_index_append's and box_index_drop's slower ways: room for one more element
# (False: out of memory, the index unchanged); whole top groups of the dropped
# elements moved out when they are more than half the elements, at least two top
# groups (every level's groups stay aligned): the count moved, else 0
cdef bint box_index_grow(BoxIndex *I) noexcept nogil
cdef size_t box_index_compact(BoxIndex *I) noexcept nogil

# The searches and the appends are the inner loops of their users: inline.
# elements of a group of level lev; the group of level lev that holds position j
cdef inline size_t box_group_size(int lev) noexcept nogil:
    return (<size_t>4) << (2 * lev)

cdef inline size_t box_group_of(size_t j, int lev) noexcept nogil:
    return j >> (2 * lev + 2)

# group c of level lev is complete: its box goes into its group of level lev + 1
# (the first subgroup sets it)
cdef inline void box_index_fold(BoxIndex *I, int lev, size_t c) noexcept nogil:
    cdef const double *b = &I.g[lev][4 * c]
    cdef double *g = &I.g[lev + 1][4 * (c >> 2)]
    if (c & 3) == 0:
        g[0] = b[0]; g[1] = b[1]; g[2] = b[2]; g[3] = b[3]
    else:
        box_union(g, b)

# an element's box appended as element I.n: its level-0 group takes it, each group it
# completes is folded into the group above (False: out of memory, the index unchanged)
cdef inline bint box_index_append(BoxIndex *I, const double *box) noexcept nogil:
    cdef size_t j = I.n
    cdef double *g
    cdef int lev = 0
    if j == I.cap and not box_index_grow(I):
        return False
    g = &I.box[4 * j]
    g[0] = box[0]; g[1] = box[1]; g[2] = box[2]; g[3] = box[3]
    g = &I.g[0][4 * box_group_of(j, 0)]
    if (j & 3) == 0:
        g[0] = box[0]; g[1] = box[1]; g[2] = box[2]; g[3] = box[3]
    else:
        box_union(g, box)
    I.n = j + 1
    while lev + 1 < BOX_LEVELS and (I.n & (box_group_size(lev) - 1)) == 0:
        box_index_fold(I, lev, box_group_of(I.n, lev) - 1)
        lev += 1
    return True

# the elements before `base` are no longer searched; when they are many, their memory
# is given back (box_index_compact): the count by which every position went down (the
# user moves its own data alike), else 0
cdef inline size_t box_index_drop(BoxIndex *I, size_t base) noexcept nogil:
    if base <= I.base:
        return 0                    # nothing newly dropped: compacting waits for the next drop
    I.base = base if base < I.n else I.n
    return box_index_compact(I)

# the first (next) / last (prev) element of positions [lo, hi) (and not before I.base)
# whose box comes within t of `box`; -1 none. Elements in order: next(j + 1, ...)
# and prev(..., j) go on from a found j. Where groups start (next: those complete,
# ending by I.n) or end (prev: complete as hi <= n), the largest group there is tested
# first and passed over whole when it misses (level 0: also the group that holds the
# last elements)
cdef inline int64_t box_index_next(const BoxIndex *I, size_t lo, size_t hi, const double *box,
                                   double t) noexcept nogil:
    cdef size_t j = lo if lo > I.base else I.base
    cdef size_t rest
    cdef int lev, fit
    if hi > I.n:
        hi = I.n
    while j < hi:
        if (j & 3) == 0:
            # the levels of the groups that start at j and end by I.n (level 0: always;
            # above it only where j is a multiple of 16)
            lev = 0
            if (j & 15) == 0:
                lev = BOX_LEVELS - 1 if j == 0 else (__builtin_ctzll(j) - 2) >> 1
                rest = I.n - j
                fit = (63 - __builtin_clzll(rest) - 2) >> 1 if rest >= 16 else 0
                if fit < lev:
                    lev = fit
                if lev >= BOX_LEVELS:
                    lev = BOX_LEVELS - 1
            while lev >= 0 and box_hit(&I.g[lev][4 * box_group_of(j, lev)], box, t):
                lev -= 1
            if lev >= 0:
                j += box_group_size(lev)
                continue
        if box_hit(&I.box[4 * j], box, t):
            return <int64_t>j
        j += 1
    return -1

cdef inline int64_t box_index_prev(const BoxIndex *I, size_t lo, size_t hi, const double *box,
                                   double t) noexcept nogil:
    cdef size_t j = hi if hi < I.n else I.n
    cdef size_t size
    cdef int lev
    if lo < I.base:
        lo = I.base
    while j > lo:
        if (j & 3) == 0:
            lev = 0
            if (j & 15) == 0:
                lev = (__builtin_ctzll(j) - 2) >> 1
                if lev >= BOX_LEVELS:
                    lev = BOX_LEVELS - 1
            while lev >= 0 and box_hit(&I.g[lev][4 * (box_group_of(j, lev) - 1)], box, t):
                lev -= 1
            if lev >= 0:
                size = box_group_size(lev)
                j = j - size if j - size > lo else lo
                continue
        j -= 1
        if box_hit(&I.box[4 * j], box, t):
            return <int64_t>j
    return -1
