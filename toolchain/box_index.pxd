# Face of the box index (box_index.pyx): the one spatial index of the plane. It holds
# the boxes (x0, y0, x1, y1) of elements in the order they come (the pieces of a
# tool path, the elements of a contour, the groups of a chain) and the box of every
# group of 4, 16, 64 ... of them, so that a search for the elements whose boxes meet
# a box skips whole groups that lie away from it: O(log n + k) on a path that does
# not come back on itself, where a plain scan of the boxes is O(n) per search and
# O(n^2) over a contour. Why one index: the compensation's searches (a piece against
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
# an element's box appended as element I.n (False: out of memory, the index unchanged)
cdef bint box_index_append(BoxIndex *I, const double *box) noexcept nogil
# the elements from n on removed (a cut back; n < I.base drops the base back to n)
cdef void box_index_truncate(BoxIndex *I, size_t n) noexcept nogil
# the elements before `base` are no longer searched; when they are many, their memory
# is given back by moving the rest to the front: the returned count, by which every
# position went down (the user moves its own data alike), else 0
cdef size_t box_index_drop(BoxIndex *I, size_t base) noexcept nogil
# the first (next) / last (prev) element of positions [lo, hi) (and not before I.base)
# whose box comes within t of `box`; -1 none. Elements in order: next(j + 1, ...)
# and prev(..., j) go on from a found j
cdef int64_t box_index_next(const BoxIndex *I, size_t lo, size_t hi, const double *box, double t) noexcept nogil
cdef int64_t box_index_prev(const BoxIndex *I, size_t lo, size_t hi, const double *box, double t) noexcept nogil
