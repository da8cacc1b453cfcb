# Face of numbers.pyx: numbers in text, the same under every locale (a host under
# de_DE writes 0,5). Every conversion between a double and text goes through here or
# through the platform layer's c_strtod and c_snprintf (includes/platform.pxd: the C
# locale on each system). Called by every stage that reads or writes numbers: the
# lexer, the error texts, the INI keys, the connection search's messages.


# a whole text (blanks around allowed) as a number: False when it is none or out of range
cdef bint c_parse_double(const char *text, double *out) noexcept nogil
cdef bint c_parse_long(const char *text, long long lo, long long hi, long long *out) noexcept nogil
