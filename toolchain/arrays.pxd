# Face of arrays.pyx: the one growable array. Every buffer that grows -- the
# program's arrays, the compensation's stack, queues and windows, the planner's
# insertions, the machine's history, a file being read -- grows through grow
# (doubling, for appends) or resize (an exact size). Both leave the array as it
# was and return False when memory is exhausted; the caller then reports
# ERR_OUT_OF_MEMORY or goes without, as its stage documents.

# exactly `count` items of `item` bytes (grown or shrunk; realloc keeps the contents)
cdef bint resize(void **buf, size_t count, size_t item) noexcept nogil


# Memory readied ahead of an array's writer, a hint: when the writer comes within half
# a READY_CHUNK of the bytes faulted in so far, the next READY_CHUNK of the capacity is
# faulted in with one madvise(MADV_POPULATE_WRITE) instead of a page fault for each of
# its 32 pages (on this VM the fault's trap costs more than zeroing the page:
# docs/benchmarks.md, "Page faults"). `ready`: bytes from the array's start faulted in
# (0 for a new array; a realloc keeps them). False from ready_memory: the kernel cannot.
cdef enum:
    READY_CHUNK = 1 << 17   # 128 kB: what is readied beyond an array's end is in the peak memory

cdef bint ready_memory(void *start, size_t length) noexcept nogil
cdef void ready_more(void *buf, size_t used, size_t *ready, size_t cap) noexcept nogil

cdef inline void ready_ahead(void *buf, size_t used, size_t *ready, size_t cap) noexcept nogil:
    # bytes [0, used) of buf are written (or about to be), [0, cap) allocated
    if used + READY_CHUNK // 2 > ready[0] and ready[0] < cap:
        ready_more(buf, used, ready, cap)


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
