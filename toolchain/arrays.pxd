# Face of arrays.pyx: the one growable array. Every buffer that grows -- the
# program's arrays, the compensation's stack, queues and windows, the planner's
# insertions, the machine's history, a file being read -- grows through grow
# (doubling, for appends) or resize (an exact size). Both leave the array as it
# was and return False when memory is exhausted; the caller then reports
# ERR_OUT_OF_MEMORY or goes without, as its stage documents.

# exactly `count` items of `item` bytes (grown or shrunk; realloc keeps the contents)
cdef bint resize(void **buf, size_t count, size_t item) noexcept nogil


cdef inline bint grow(void **buf, size_t *cap, size_t need, size_t item) noexcept nogil:
    # room for `need` items: the capacity doubles (from 256) until it holds them
    cdef size_t new_cap
    if need <= cap[0]:
        return True
    new_cap = cap[0] * 2 if cap[0] else 256
    while new_cap < need:
        new_cap *= 2
    if not resize(buf, new_cap, item):
        return False
    cap[0] = new_cap
    return True
