# G-code lexer: character classes, words, comments and numbers. Works on one line
# [p, eol) of the source at a time, never past eol (lines are not NUL-terminated).
from libc.string cimport memcpy, memchr
from libc.math cimport isfinite

cdef extern from *:
    """
    /* Exact powers of ten: mantissa / 10^k is then correctly rounded (one IEEE
       division of two exact values), i.e. identical to strtod's result. */
    static const double sf_pow10_exact[23] = {
        1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14,
        1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
    """
    const double sf_pow10_exact[23]


cdef inline bint lx_is_digit(char c) noexcept nogil:
    """Whether c is a decimal digit."""
    return c >= b'0' and c <= b'9'


cdef inline bint lx_is_alpha(char c) noexcept nogil:
    """Whether c is an ASCII letter."""
    return (c >= b'A' and c <= b'Z') or (c >= b'a' and c <= b'z')


cdef inline bint lx_is_ident(char c) noexcept nogil:
    """Whether c may continue an identifier: a letter, a digit or '_'."""
    return lx_is_alpha(c) or lx_is_digit(c) or c == b'_'


cdef inline char lx_upper(char c) noexcept nogil:
    """c in upper case (ASCII letters only)."""
    if c >= b'a' and c <= b'z':
        return c - 32
    return c


cdef inline const char *lx_skip_ws(const char *p, const char *eol) noexcept nogil:
    """p past the blanks (space, tab, CR, form feed, vertical tab), at most to eol."""
    while p < eol and (p[0] == b' ' or p[0] == b'\t' or p[0] == b'\r' or p[0] == b'\f' or p[0] == b'\v'):
        p += 1
    return p


cdef inline int lx_alpha_run(const char *p, const char *eol) noexcept nogil:
    """Number of letters starting at p."""
    cdef int n = 0
    while p + n < eol and lx_is_alpha(p[n]):
        n += 1
    return n


cdef inline int lx_ident_run(const char *p, const char *eol) noexcept nogil:
    """Length of an identifier (letter or '_' first, then letters, digits, '_')."""
    cdef int n = 0
    if p >= eol or not (lx_is_alpha(p[0]) or p[0] == b'_'):
        return 0
    while p + n < eol and lx_is_ident(p[n]):
        n += 1
    return n


cdef inline size_t lx_bom(const char *text, size_t n) noexcept nogil:
    """Length of a UTF-8 byte-order mark at the start of a text (Windows editors, CAM
    posts write one): 3, or 0 without."""
    if n >= 3 and <unsigned char>text[0] == 0xEF and <unsigned char>text[1] == 0xBB \
            and <unsigned char>text[2] == 0xBF:
        return 3
    return 0


cdef bint lx_eq(const char *p, int n, const char *kw) noexcept nogil:
    """Case-insensitive: p[0:n] equals the upper-case keyword kw."""
    cdef int i = 0
    while i < n:
        if kw[i] == 0 or lx_upper(p[i]) != kw[i]:
            return False
        i += 1
    return kw[n] == 0


cdef bint lx_same_name(const char *a, int na, const char *b, int nb) noexcept nogil:
    """Whether two names of given lengths are equal, case-insensitive."""
    cdef int i
    if na != nb:
        return False
    for i in range(na):
        if lx_upper(a[i]) != lx_upper(b[i]):
            return False
    return True


cdef inline const char *lx_skip_gap(const char *p, const char *eol, int *status) noexcept nogil:
    """Skips blanks and comments between words: '( ... )' inline; '//' and ';' end
    the line. status: 0 ok, 1 unterminated '('."""
    cdef const char *q
    status[0] = 0
    while True:
        p = lx_skip_ws(p, eol)
        if p >= eol:
            return eol
        if p[0] == b'(':
            q = <const char *>memchr(p, b')', eol - p)
            if q == NULL:
                status[0] = 1
                return eol
            p = q + 1
            continue
        if p[0] == b';' or (p[0] == b'/' and p + 1 < eol and p[1] == b'/'):
            return eol
        return p


cdef int lx_number(const char **pp, const char *eol, double *out) noexcept nogil:
    """Plain decimal number (digits, optional '.', digits; no sign, no exponent: 'E'
    is an address). Fast exact path when the digits fit 2^53 and at most 22 decimals,
    else strtod (C locale) on a copy. 0 ok, -1 not a number, -2 bad number (e.g.
    '1.2.3'), -3 a number too large for a double (pp is then past it)."""
    cdef const char *p = pp[0]
    cdef const char *start = p
    cdef unsigned long long mant = 0
    cdef int frac = 0, ndig = 0
    cdef bint exact
    cdef char buf[NUMBER_MAX_CHARS + 1]
    cdef int n
    cdef unsigned int d
    # up to 19 digits fit a uint64 exactly; more digits go to c_strtod
    while p < eol:
        d = <unsigned int>(<unsigned char>p[0]) - 48u
        if d > 9u:
            break
        if ndig < 19:
            mant = mant * 10u + d
        ndig += 1
        p += 1
    if p < eol and p[0] == b'.':
        p += 1
        while p < eol:
            d = <unsigned int>(<unsigned char>p[0]) - 48u
            if d > 9u:
                break
            if ndig < 19:
                mant = mant * 10u + d
                frac += 1
            ndig += 1
            p += 1
    if ndig == 0:
        return -1
    if p < eol and (p[0] == b'.' or lx_is_digit(p[0])):
        pp[0] = p
        return -2
    exact = ndig <= 19
    pp[0] = p
    if exact and mant <= 9007199254740992ULL and frac <= 22:
        out[0] = <double>mant / sf_pow10_exact[frac]
        return 0
    n = <int>(p - start)
    if n > NUMBER_MAX_CHARS:
        return -2
    memcpy(buf, start, n)
    buf[n] = 0
    out[0] = c_strtod(buf, NULL)
    if not isfinite(out[0]):
        return -3
    return 0
