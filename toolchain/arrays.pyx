# The one growable array (arrays.pxd: grow doubles, resize sets a size).


cdef bint resize(void **buf, size_t count, size_t item) noexcept nogil:
    """Exactly `count` items (count > 0); False, the array unchanged, when memory is
    exhausted."""
    cdef void *p = tc_realloc(buf[0], count * item)
    if p == NULL:
        return False
    buf[0] = p
    return True
