# The box index (toolchain/box_index.pyx): one index held by a Python object, each of
# its operations an entry point, so that tests can drive it against a plain scan.

cdef class Boxes:
    """A BoxIndex: append, truncate, drop, and the searches forwards and backwards."""
    cdef BoxIndex ix

    def __cinit__(self):
        memset(&self.ix, 0, sizeof(BoxIndex))

    def __dealloc__(self):
        box_index_free(&self.ix)

    @property
    def n(self):
        return self.ix.n

    @property
    def base(self):
        return self.ix.base

    def clear(self):
        box_index_clear(&self.ix)

    def append(self, box):
        cdef double b[4]
        _fill(b, box, 4)
        if not box_index_append(&self.ix, b):
            raise MemoryError()

    def truncate(self, size_t n):
        box_index_truncate(&self.ix, n)

    def drop(self, size_t base):
        """The count the positions went down by (box_index_drop)."""
        return box_index_drop(&self.ix, base)

    def box(self, size_t j):
        return [self.ix.box[4 * j + k] for k in range(4)]

    def next(self, size_t lo, size_t hi, box, double t=0.0):
        cdef double b[4]
        _fill(b, box, 4)
        return box_index_next(&self.ix, lo, hi, b, t)

    def prev(self, size_t lo, size_t hi, box, double t=0.0):
        cdef double b[4]
        _fill(b, box, 4)
        return box_index_prev(&self.ix, lo, hi, b, t)

    def all_next(self, size_t lo, size_t hi, box, double t=0.0):
        """Every element of [lo, hi) found by next(), in order."""
        cdef double b[4]
        cdef int64_t k = <int64_t>lo - 1
        _fill(b, box, 4)
        out = []
        while True:
            k = box_index_next(&self.ix, <size_t>(k + 1), hi, b, t)
            if k < 0:
                return out
            out.append(k)

    def all_prev(self, size_t lo, size_t hi, box, double t=0.0):
        """Every element of [lo, hi) found by prev(), last first."""
        cdef double b[4]
        cdef int64_t k = <int64_t>hi
        _fill(b, box, 4)
        out = []
        while True:
            k = box_index_prev(&self.ix, lo, <size_t>k, b, t)
            if k < 0:
                return out
            out.append(k)
