# The box index (box_index.pxd): boxes of elements in order, with the boxes of their
# groups of 4, 16, 64 ... 4096 elements, level by level. A search steps through the
# positions and, where a group starts (forwards) or ends (backwards), tests the
# largest group there first: a group whose box misses the query box is passed over
# whole. The boxes a group covers are only ever unions (exact min / max), so passing
# over groups changes nothing of what a search finds, only how fast. The searches and
# the append are inline in the face (the inner loops of their users); here the rest.
from libc.stdlib cimport free
from libc.string cimport memmove, memcpy


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


cdef bint box_index_grow(BoxIndex *I) noexcept nogil:
    """Room for element I.n: the elements' boxes grow (doubling) and the group boxes of
    each level with them. False when memory is exhausted (what it holds stays)."""
    cdef size_t cap = I.cap
    cdef int lev
    if not grow(<void **>&I.box, &cap, I.n + 1, 4 * sizeof(double)):
        return False
    for lev in range(BOX_LEVELS):   # the group boxes of each level, for that capacity
        if not resize(<void **>&I.g[lev], cap / box_group_size(lev) + 1, 4 * sizeof(double)):
            return False
    I.cap = cap
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
        c0 = n & ~(<size_t>3)
        b = &I.g[0][4 * box_group_of(n, 0)]
        memcpy(b, &I.box[4 * c0], 4 * sizeof(double))
        for k in range(c0 + 1, n):
            box_union(b, &I.box[4 * k])
    for lev in range(1, BOX_LEVELS):
        # the group of level lev holding position n: its complete subgroups below n
        c0 = box_group_of(n, lev) << 2
        for c in range(c0, box_group_of(n, lev - 1)):
            box_index_fold(I, lev - 1, c)


cdef size_t box_index_compact(BoxIndex *I) noexcept nogil:
    """When the dropped elements are at least two top groups and more than half the
    elements, whole top groups of them are moved out (every level's groups stay
    aligned): their count, else 0."""
    cdef size_t shift, size, top = box_group_size(BOX_LEVELS - 1)
    cdef int lev
    if I.base < 2 * top or I.base <= I.n / 2:
        return 0
    shift = (I.base / top) * top
    memmove(I.box, &I.box[4 * shift], 4 * (I.n - shift) * sizeof(double))
    for lev in range(BOX_LEVELS):
        size = box_group_size(lev)
        memmove(I.g[lev], &I.g[lev][4 * (shift / size)], 4 * ((I.n - shift) / size + 1) * sizeof(double))
    I.n -= shift
    I.base -= shift
    return shift
