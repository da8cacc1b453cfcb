# The box index (box_index.pxd): boxes of elements in order, with the boxes of their
# groups of 4, 16, 64 ... elements, level by level. A search steps through the
# positions and, where a group starts (forwards) or ends (backwards), tests the
# largest group there first: a group whose box misses the query box is passed over
# whole. The boxes a group covers are only ever unions (exact min / max), so passing
# over groups changes nothing of what a search finds, only how fast.
from libc.stdlib cimport free
from libc.string cimport memmove, memcpy

cdef extern from *:
    int __builtin_ctzll(unsigned long long) nogil


cdef inline size_t _box_group_size(int lev) noexcept nogil:
    """Elements of a group of level lev."""
    return (<size_t>4) << (2 * lev)


cdef inline int _box_top_level(size_t j) noexcept nogil:
    """The largest level whose groups start (and end) at position j (a multiple of 4)."""
    cdef int lev
    if j == 0:
        return BOX_LEVELS - 1
    lev = (__builtin_ctzll(j) - 2) >> 1
    return lev if lev < BOX_LEVELS else BOX_LEVELS - 1


cdef inline void _box_fold(BoxIndex *I, int lev, size_t c) noexcept nogil:
    """Group c of level lev is complete: its box goes into its group of level lev + 1."""
    cdef const double *b = &I.g[lev][4 * c]
    cdef double *g = &I.g[lev + 1][4 * (c >> 2)]
    if (c & 3) == 0:
        g[0] = b[0]; g[1] = b[1]; g[2] = b[2]; g[3] = b[3]
    else:
        box_union(g, b)


cdef void box_index_clear(BoxIndex *I) noexcept nogil:
    """No elements (the memory is kept for the next ones)."""
    I.n = 0
    I.base = 0


cdef void box_index_free(BoxIndex *I) noexcept nogil:
    """Frees the boxes and leaves the index empty."""
    cdef int lev
    free(I.box)
    I.box = NULL
    for lev in range(BOX_LEVELS):
        free(I.g[lev])
        I.g[lev] = NULL
    I.n = 0
    I.cap = 0
    I.base = 0


cdef bint box_index_append(BoxIndex *I, const double *box) noexcept nogil:
    """Appends an element's box: its level-0 group takes it, and each group it
    completes is folded into the group above. False when memory is exhausted."""
    cdef size_t cap, j
    cdef double *g
    cdef int lev
    if I.n == I.cap:
        cap = I.cap
        if not grow(<void **>&I.box, &cap, I.n + 1, 4 * sizeof(double)):
            return False
        for lev in range(BOX_LEVELS):   # the group boxes of each level, for that capacity
            if not resize(<void **>&I.g[lev], cap / _box_group_size(lev) + 1, 4 * sizeof(double)):
                return False
        I.cap = cap
    j = I.n
    memcpy(&I.box[4 * j], box, 4 * sizeof(double))
    g = &I.g[0][4 * (j >> 2)]
    if (j & 3) == 0:
        g[0] = box[0]; g[1] = box[1]; g[2] = box[2]; g[3] = box[3]
    else:
        box_union(g, box)
    I.n = j + 1
    lev = 0
    while lev + 1 < BOX_LEVELS and (I.n & (_box_group_size(lev) - 1)) == 0:
        _box_fold(I, lev, (I.n >> (2 * lev + 2)) - 1)
        lev += 1
    return True


cdef void box_index_truncate(BoxIndex *I, size_t n) noexcept nogil:
    """Keeps the first n elements: the groups that held the removed ones cover their
    complete subgroups below n again (the level-0 group its elements)."""
    cdef size_t k, c, c0
    cdef double *b
    cdef int lev
    if n >= I.n:
        return
    I.n = n
    if I.base > n:
        I.base = n
    if n & 3:
        b = &I.g[0][4 * (n >> 2)]
        c0 = (n >> 2) << 2
        memcpy(b, &I.box[4 * c0], 4 * sizeof(double))
        for k in range(c0 + 1, n):
            box_union(b, &I.box[4 * k])
    for lev in range(1, BOX_LEVELS):
        # the group of level lev holding position n: its complete subgroups below n
        c0 = (n / _box_group_size(lev)) * 4
        for c in range(c0, n / _box_group_size(lev - 1)):
            _box_fold(I, lev - 1, c)


cdef size_t box_index_drop(BoxIndex *I, size_t base) noexcept nogil:
    """Elements before `base` are no longer searched; when at least two top groups of
    them are more than half the elements, whole top groups are moved out (every
    level's groups stay aligned) and their count returned."""
    cdef size_t shift, size, top = _box_group_size(BOX_LEVELS - 1)
    cdef int lev
    if base > I.base:
        I.base = base if base < I.n else I.n
    if I.base < 2 * top or I.base <= I.n / 2:
        return 0
    shift = (I.base / top) * top
    memmove(I.box, &I.box[4 * shift], 4 * (I.n - shift) * sizeof(double))
    for lev in range(BOX_LEVELS):
        size = _box_group_size(lev)
        memmove(I.g[lev], &I.g[lev][4 * (shift / size)], 4 * ((I.n - shift) / size + 1) * sizeof(double))
    I.n -= shift
    I.base -= shift
    return shift


cdef int64_t box_index_next(const BoxIndex *I, size_t lo, size_t hi, const double *box, double t) noexcept nogil:
    """The first element of [lo, hi) whose box comes within t of `box`, -1 none: at a
    position where groups start, the largest complete one that misses is passed over
    (the level-0 group covers what it holds, complete or not)."""
    cdef size_t j = lo if lo > I.base else I.base
    cdef size_t size, c
    cdef int lev
    cdef bint passed
    if hi > I.n:
        hi = I.n
    while j < hi:
        if (j & 3) == 0:
            passed = False
            lev = _box_top_level(j)
            while lev >= 0:
                size = _box_group_size(lev)
                c = j >> (2 * lev + 2)
                if (lev == 0 or (c + 1) * size <= I.n) and not box_hit(&I.g[lev][4 * c], box, t):
                    j += size
                    passed = True
                    break
                lev -= 1
            if passed:
                continue
        if box_hit(&I.box[4 * j], box, t):
            return <int64_t>j
        j += 1
    return -1


cdef int64_t box_index_prev(const BoxIndex *I, size_t lo, size_t hi, const double *box, double t) noexcept nogil:
    """The last element of [lo, hi) whose box comes within t of `box`, -1 none: at a
    position where groups end (complete ones: hi <= n), the largest one that misses
    is passed over."""
    cdef size_t j = hi if hi < I.n else I.n
    cdef size_t size
    cdef int lev
    cdef bint passed
    if lo < I.base:
        lo = I.base
    while j > lo:
        if (j & 3) == 0:
            passed = False
            lev = _box_top_level(j)
            while lev >= 0:
                if not box_hit(&I.g[lev][4 * ((j >> (2 * lev + 2)) - 1)], box, t):
                    size = _box_group_size(lev)
                    j = j - size if j - size > lo else lo
                    passed = True
                    break
                lev -= 1
            if passed:
                continue
        j -= 1
        if box_hit(&I.box[4 * j], box, t):
            return <int64_t>j
    return -1
