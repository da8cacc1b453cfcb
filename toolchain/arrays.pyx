# The one growable array (arrays.pxd: grow doubles, resize sets a size).


cdef int32_t g_no_populate      # the kernel refused MADV_POPULATE_WRITE (before 5.14): a hint less


cdef bint ready_memory(void *start, size_t length) noexcept nogil:
    """Faults in the whole pages inside [start, start + length) (their contents
    untouched); False when the kernel cannot (then never again)."""
    cdef size_t lo = (<size_t>start + 0xFFF) & ~(<size_t>0xFFF)
    cdef size_t hi = (<size_t>start + length) & ~(<size_t>0xFFF)
    if TC_ATOMIC_LOAD(&g_no_populate):
        return False
    if lo < hi and madvise(<void *>lo, hi - lo, MADV_POPULATE_WRITE) != 0:
        TC_ATOMIC_STORE(&g_no_populate, 1)
        return False
    return True


cdef void ready_more(void *buf, size_t used, size_t *ready, size_t cap) noexcept nogil:
    """ready_ahead's call: the next READY_CHUNK bytes from max(ready, used) on."""
    cdef size_t lo = ready[0] if ready[0] > used else used
    cdef size_t hi = lo + READY_CHUNK
    if hi > cap:
        hi = cap
    if lo < hi and not ready_memory(<char *>buf + lo, hi - lo):
        hi = cap                    # no such hint here: not asked again
    ready[0] = hi


cdef bint resize(void **buf, size_t count, size_t item) noexcept nogil:
    """Exactly `count` items (count > 0); False, the array unchanged, when memory is
    exhausted."""
    cdef void *p = tc_realloc(buf[0], count * item)
    if p == NULL:
        return False
    buf[0] = p
    return True
