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
    /* The blanks (space, tab, CR, form feed, vertical tab) as bits of their codes. */
    static const uint64_t sf_lx_blanks = (1ULL << ' ') | (1ULL << '\\t') | (1ULL << '\\r')
        | (1ULL << '\\f') | (1ULL << '\\v');
    /* The operators an expression continues with (+ - * / % ^) as bits of their codes
       from '%' (37) on: all lie below '%' + 64. */
    static const uint64_t sf_lx_operators = (1ULL << ('+' - '%')) | (1ULL << ('-' - '%'))
        | (1ULL << ('*' - '%')) | (1ULL << ('/' - '%')) | (1ULL << 0) | (1ULL << ('^' - '%'));
    /* The characters of identifiers (letters, digits, '_') at their codes, '.' elsewhere. */
    static const char sf_lx_ident_chars[129] =
        "................................................0123456789......."
        "ABCDEFGHIJKLMNOPQRSTUVWXYZ...._.abcdefghijklmnopqrstuvwxyz.....";
    """
    const double sf_pow10_exact[23]
    const char sf_lx_ident_chars[129]
    const uint64_t sf_lx_blanks
    const uint64_t sf_lx_operators


cdef inline bint lx_is_digit(char c) noexcept nogil:
    """Whether c is a decimal digit (one unsigned compare)."""
    return <unsigned int>(<unsigned char>c) - 48u <= 9u


cdef inline bint lx_is_alpha(char c) noexcept nogil:
    """Whether c is an ASCII letter: with bit 5 set (lower case) it lies in 'a'..'z'
    (one unsigned compare)."""
    return <unsigned int>(<unsigned char>c | 32u) - 97u < 26u


cdef inline bint lx_is_blank(char c) noexcept nogil:
    """Whether c is a blank (space, tab, CR, form feed, vertical tab): a character above
    ' ', the usual one, costs one compare."""
    return <unsigned char>c <= 32 and (sf_lx_blanks >> <unsigned char>c) & 1


cdef inline bint lx_is_ident(char c) noexcept nogil:
    """Whether c may continue an identifier: a letter, a digit or '_' (one look-up)."""
    return <unsigned char>c < 128 and sf_lx_ident_chars[<unsigned char>c] != b'.'


cdef inline char lx_upper(char c) noexcept nogil:
    """c in upper case (ASCII letters only)."""
    if c >= b'a' and c <= b'z':
        return c - 32
    return c


cdef inline bint lx_is_operator(char c) noexcept nogil:
    """Whether c is an operator an expression continues with: + - * / % ^ (two compares
    for a letter or a digit)."""
    cdef unsigned int k = <unsigned int>(<unsigned char>c) - 37u
    return k < 64u and (sf_lx_operators >> k) & 1


cdef inline const char *lx_skip_ws(const char *p, const char *eol) noexcept nogil:
    """p past the blanks (space, tab, CR, form feed, vertical tab), at most to eol."""
    while p < eol and lx_is_blank(p[0]):
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
        if lx_is_alpha(p[0]):
            return p            # a word's letter (the usual)
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


cdef int _lx_number_strtod(const char *start, const char *end, double *out) noexcept nogil:
    """lx_number's number [start, end) that is no exact one (more than 19 digits, a
    mantissa above 2^53 or more than 22 decimals): strtod (C locale) on a copy. 0 ok,
    -2 longer than NUMBER_MAX_CHARS, -3 too large for a double."""
    cdef char buf[NUMBER_MAX_CHARS + 1]
    cdef int n = <int>(end - start)
    if n > NUMBER_MAX_CHARS:
        return -2
    memcpy(buf, start, n)
    buf[n] = 0
    out[0] = c_strtod(buf, NULL)
    if not isfinite(out[0]):
        return -3
    return 0


cdef int lx_number(const char **pp, const char *eol, double *out) noexcept nogil:
    """Plain decimal number (digits, optional '.', digits; no sign, no exponent: 'E'
    is an address). Fast exact path when the digits fit 2^53 and at most 22 decimals,
    else strtod (C locale) on a copy. 0 ok, -1 not a number, -2 bad number (e.g.
    '1.2.3'), -3 a number too large for a double (pp is then past it)."""
    cdef const char *p = pp[0]
    cdef const char *start = p
    cdef const char *dot
    cdef unsigned long long mant = 0
    cdef int frac = 0, ndig
    cdef unsigned int d
    # every digit goes into mant: past 19 digits it wraps (unsigned arithmetic), but
    # such a number is no exact one and _lx_number_strtod reads it
    while p < eol:
        d = <unsigned int>(<unsigned char>p[0]) - 48u
        if d > 9u:
            break
        mant = mant * 10u + d
        p += 1
    ndig = <int>(p - start)
    if p != eol and p[0] == b'.':       # (!=: the loop's own test, no flag kept through it)
        p += 1
        dot = p
        while p < eol:
            d = <unsigned int>(<unsigned char>p[0]) - 48u
            if d > 9u:
                break
            mant = mant * 10u + d
            p += 1
        frac = <int>(p - dot)
        ndig += frac
    if ndig == 0:
        return -1
    pp[0] = p
    if p != eol and p[0] == b'.':       # a second '.' (a digit cannot follow: the loops took them)
        return -2
    # up to 15 digits are below 2^53 with at most 15 decimals: one test for most numbers
    if ndig <= 15 or (ndig <= 19 and mant <= 9007199254740992ULL and frac <= 22):
        out[0] = <double>mant / sf_pow10_exact[frac]
        return 0
    return _lx_number_strtod(start, p, out)
