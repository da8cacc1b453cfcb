# Numbers in text, the same under every locale. A panel that runs under de_DE sets
# LC_NUMERIC to a decimal comma: libc's strtod would then read "0.5" as 0 and
# printf would write 15,62. Every conversion between a double and text in the
# library goes through c_strtod and c_snprintf (platform.h: a C locale_t on Linux,
# mingw-w64's locale-free strtod on Windows) and the parsers here. Integers and
# strings print the same in every locale: only conversions of doubles need this.
from libc.math cimport isfinite
from libc.stdlib cimport strtoll

cdef inline bint _num_only_blanks(const char *s) noexcept nogil:
    """Whether only blanks (space, tab) are left of s: a number's text must end there."""
    while s[0] == b' ' or s[0] == b'\t':
        s += 1
    return s[0] == 0


cdef bint c_parse_double(const char *text, double *out) noexcept nogil:
    """The whole of `text` (blanks around allowed) as a finite number; False for
    an empty text, trailing characters, or a value that overflows (inf, nan)."""
    cdef char *end
    cdef double value = c_strtod(text, &end)
    if end == text or not _num_only_blanks(end) or not isfinite(value):
        return False
    out[0] = value
    return True


cdef bint c_parse_long(const char *text, long long lo, long long hi, long long *out) noexcept nogil:
    """The whole of `text` as an integer in [lo, hi] (decimal, 0x hexadecimal); an
    overflow saturates at LLONG_MIN/LLONG_MAX, outside any [lo, hi] of the callers.
    long long, not long: long has 32 bits on Windows, too few for uint32 fields."""
    cdef char *end
    cdef long long value
    value = strtoll(text, &end, 0)
    if end == text or not _num_only_blanks(end) or value < lo or value > hi:
        return False
    out[0] = value
    return True
