# Reading the vendor's Windows-syntax INI files: [section] headers, key=value lines,
# ';' and '#' comments. Each entry is handed to a visitor; the core decides what
# it means (core.pyx: core_apply_ini).
from libc.stdio cimport FILE, fopen, fclose, fgets
from libc.string cimport strlen, strchr, memcpy

ctypedef void (*ini_visitor)(void *ctx, const char *section, const char *key, const char *value) noexcept nogil


cdef char *_strip(char *s) noexcept nogil:
    cdef size_t n
    while s[0] == b' ' or s[0] == b'\t':
        s += 1
    n = strlen(s)
    while n > 0 and (s[n - 1] == b' ' or s[n - 1] == b'\t' or s[n - 1] == b'\r' or s[n - 1] == b'\n'):
        n -= 1
    s[n] = 0
    return s


cdef int ini_read(const char *path, ini_visitor visit, void *ctx) noexcept nogil:
    """Visits every key of the file; -1 when it cannot be opened, else the number
    of keys read. A UTF-8 byte order mark is skipped."""
    cdef FILE *f = fopen(path, "rb")
    cdef char line[4096]
    cdef char section[256]
    cdef char *s
    cdef char *eq
    cdef char *end
    cdef int keys = 0
    cdef size_t n
    if f == NULL:
        return -1
    section[0] = 0
    while fgets(line, sizeof(line), f) != NULL:
        s = line
        if <unsigned char>s[0] == 0xEF and <unsigned char>s[1] == 0xBB and <unsigned char>s[2] == 0xBF:
            s += 3
        s = _strip(s)
        if s[0] == 0 or s[0] == b';' or s[0] == b'#':
            continue
        if s[0] == b'[':
            end = strchr(s, b']')
            if end != NULL:
                end[0] = 0
                n = strlen(s + 1)
                if n >= sizeof(section):
                    n = sizeof(section) - 1
                memcpy(section, s + 1, n)
                section[n] = 0
            continue
        eq = strchr(s, b'=')
        if eq == NULL:
            continue
        eq[0] = 0
        visit(ctx, section, _strip(s), _strip(eq + 1))
        keys += 1
    fclose(f)
    return keys
