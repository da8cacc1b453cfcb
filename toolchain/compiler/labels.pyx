# Jump targets of one source (prefix, main or postfix): labels `name:` alone on a
# line, the first word of a G29 comment, and N numbers at the start of a line.
# Built lazily on the first CALL/GOTO, so straight programs never pay for it.
from libc.stdlib cimport free
from libc.stdint cimport uint64_t


cdef uint64_t lb_hash_name(const char *s, int n) noexcept nogil:
    """FNV-1a of a name, case-insensitive (labels, and the ISO mode's names and if labels, hash
    with it)."""
    cdef uint64_t h = 1469598103934665603ULL
    cdef int i
    for i in range(n):
        h = (h ^ <uint64_t>(<unsigned char>lx_upper(s[i]))) * 1099511628211ULL
    return h


cdef uint64_t lb_hash_num(int64_t v) noexcept nogil:
    """A number label's hash: Fibonacci multiplication with its high bits folded in."""
    cdef uint64_t h = <uint64_t>v * 0x9E3779B97F4A7C15ULL
    return h ^ (h >> 29) ^ 0x5bd1e995ULL


cdef Label *lb_find(Unit *u, const char *name, int n, int64_t nval) noexcept nogil:
    """Entry of a label (name != NULL) or an N number; NULL when absent."""
    cdef uint64_t h
    cdef size_t i, mask
    cdef Label *e
    if u.cap_labels == 0:
        return NULL
    h = lb_hash_name(name, n) if name != NULL else lb_hash_num(nval)
    mask = u.cap_labels - 1
    i = <size_t>h & mask
    while True:
        e = &u.labels[i]
        if not e.used:
            return NULL
        if name != NULL:
            if e.name != NULL and lx_same_name(e.name, e.len, name, n):
                return e
        elif e.name == NULL and e.nval == nval:
            return e
        i = (i + 1) & mask


cdef int lb_insert(CState *st, Unit *u, const char *name, int n, int64_t nval, size_t pos,
                   uint32_t line, bint strict) noexcept nogil:
    """Adds a target; the first definition wins (strict: a second `name:` is an error)."""
    cdef Label *e = lb_find(u, name, n, nval)
    cdef Label *old
    cdef Label entry
    cdef size_t old_cap, i
    if e != NULL:
        if strict:
            return err_duplicate_label(st.err, u.file_idx, line, cword(st, name, name + n, n), e.line)
        return 0
    if (u.n_labels + 1) * 2 > u.cap_labels:     # keep the load under 1/2
        old = u.labels
        old_cap = u.cap_labels
        u.cap_labels = old_cap * 2 if old_cap else 256
        u.labels = <Label *>tc_calloc(u.cap_labels, sizeof(Label))
        if u.labels == NULL:
            u.labels = old
            u.cap_labels = old_cap
            return err_out_of_memory(st.err, st.unit.file_idx, st.line)
        for i in range(old_cap):
            if old[i].used:
                _lb_raw_put(u, &old[i])
        free(old)
    entry.name = name
    entry.len = n
    entry.nval = nval
    entry.pos = pos
    entry.line = line
    entry.used = True
    _lb_raw_put(u, &entry)
    u.n_labels += 1
    return 0


cdef void _lb_raw_put(Unit *u, const Label *src) noexcept nogil:
    """A label into the open-addressed table by its hash (room for it is there; no duplicate
    check)."""
    cdef uint64_t h = lb_hash_name(src.name, src.len) if src.name != NULL else lb_hash_num(src.nval)
    cdef size_t mask = u.cap_labels - 1
    cdef size_t i = <size_t>h & mask
    while u.labels[i].used:
        i = (i + 1) & mask
    u.labels[i] = src[0]


cdef int lb_build(CState *st, Unit *u) noexcept nogil:
    """Scans the whole source once for labels and N numbers."""
    cdef size_t pos = 0
    cdef uint32_t line = 1
    cdef const char *p
    cdef const char *eol
    cdef const char *q
    cdef const char *base = u.text
    cdef int n
    cdef int64_t v
    cdef int status
    pos = lx_bom(base, u.len)
    while pos < u.len:
        eol = <const char *>memchr(base + pos, b'\n', u.len - pos)
        if eol == NULL:
            eol = base + u.len
        p = lx_skip_ws(base + pos, eol)
        n = lx_ident_run(p, eol)
        if n > 0:
            q = lx_skip_ws(p + n, eol)
            if q < eol and q[0] == b':':
                if lb_insert(st, u, p, n, 0, pos, line, True) != 0:
                    return R_ERR
            elif (p[0] == b'G' or p[0] == b'g') and lx_alpha_run(p, eol) == 1:
                q = p + 1
                while q < eol and q[0] == b'0':
                    q += 1
                if q + 1 < eol and q[0] == b'2' and q[1] == b'9' and (q + 2 >= eol or not lx_is_digit(q[2])):
                    q = lx_skip_ws(q + 2, eol)
                    n = lx_ident_run(q, eol)
                    if n > 0:
                        if lb_insert(st, u, q, n, 0, pos, line, False) != 0:
                            return R_ERR
        if p + 1 < eol and (p[0] == b'N' or p[0] == b'n') and lx_is_digit(p[1]):
            q = p + 1
            v = 0
            while q < eol and lx_is_digit(q[0]) and v < 1000000000000LL:
                v = v * 10 + (<int>q[0] - 48)
                q += 1
            if lb_insert(st, u, NULL, 0, v, pos, line, False) != 0:
                return R_ERR
        pos = <size_t>(eol - base) + 1
        line += 1
    u.labels_built = True
    return 0


cdef void lb_free(Unit *u) noexcept nogil:
    """Frees the unit's label table: built again when a jump needs it."""
    free(u.labels)
    u.labels = NULL
    u.cap_labels = 0
    u.n_labels = 0
    u.labels_built = False
