# Numbers in text, the same under every locale. A panel that runs under de_DE sets
# LC_NUMERIC to a decimal comma: libc's strtod would then read "0.5" as 0 and
# printf would write 15,62. Every conversion between a double and text in the
# library goes through here: one C locale object, created once, used by strtod_l
# and, per call and per thread, around vsnprintf (uselocale only changes the
# calling thread, so a host thread gets its own locale back at once). Integers and
# strings print the same in every locale: only conversions of doubles need this.
from libc.math cimport isfinite
from libc.stdlib cimport strtol

cdef extern from *:
    """
    #include <locale.h>
    #include <stdarg.h>
    #include <stdio.h>
    #include <stdlib.h>
    #include <pthread.h>

    static locale_t tc_c_locale_obj = (locale_t)0;
    static pthread_once_t tc_c_locale_once = PTHREAD_ONCE_INIT;

    static void tc_c_locale_create(void) {
        tc_c_locale_obj = newlocale(LC_ALL_MASK, "C", (locale_t)0);
    }

    /* The C locale, or 0 when it could not be created (out of memory). */
    static locale_t tc_c_locale(void) {
        pthread_once(&tc_c_locale_once, tc_c_locale_create);
        return tc_c_locale_obj;
    }

    static double tc_c_strtod(const char *s, char **end) {
        locale_t c = tc_c_locale();
        locale_t old;
        double value;
        if (c != (locale_t)0)
            return strtod_l(s, end, c);
        /* no locale object: the global one, which is "C" unless the host changed it */
        old = uselocale(LC_GLOBAL_LOCALE);
        value = strtod(s, end);
        uselocale(old);
        return value;
    }

    static int tc_c_snprintf(char *buf, size_t size, const char *fmt, ...) {
        locale_t c = tc_c_locale();
        locale_t old = (locale_t)0;
        va_list ap;
        int n;
        if (c != (locale_t)0)
            old = uselocale(c);
        va_start(ap, fmt);
        n = vsnprintf(buf, size, fmt, ap);
        va_end(ap);
        if (c != (locale_t)0)
            uselocale(old);
        return n;
    }
    """


cdef inline bint _num_only_blanks(const char *s) noexcept nogil:
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


cdef bint c_parse_long(const char *text, long lo, long hi, long *out) noexcept nogil:
    """The whole of `text` as an integer in [lo, hi] (decimal, 0x hexadecimal); an
    overflow saturates at LONG_MIN/LONG_MAX, outside any [lo, hi] of the callers."""
    cdef char *end
    cdef long value
    value = strtol(text, &end, 0)
    if end == text or not _num_only_blanks(end) or value < lo or value > hi:
        return False
    out[0] = value
    return True
