# Face of numbers.pyx: numbers in text, the same under every locale (a host under
# de_DE writes 0,5). Owns the library's C locale; every conversion between a double
# and text goes through here. Called by every stage that reads or writes numbers:
# the lexer, the error texts, the INI keys, the connection search's messages.

cdef extern from *:                 # C in numbers.pyx
    # strtod with a '.' decimal point whatever the process's locale
    double c_strtod "tc_c_strtod"(const char *s, char **end) nogil
    # snprintf with a '.' decimal point whatever the calling thread's locale
    int c_snprintf "tc_c_snprintf"(char *buf, size_t size, const char *fmt, ...) nogil


# a whole text (blanks around allowed) as a number: False when it is none or out of range
cdef bint c_parse_double(const char *text, double *out) noexcept nogil
cdef bint c_parse_long(const char *text, long lo, long hi, long *out) noexcept nogil
