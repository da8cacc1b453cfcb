# Reading the vendor's Windows-syntax INI files: [section] headers, key=value lines,
# ';' and '#' comments. The whole file is read first (files.pyx: regular files
# only, never blocking), then parsed in memory, so a line is as long as it is:
# never cut into two. Each entry goes to a visitor, which decides what it means
# (parameters.pyx) and may stop the reading with an error.
from libc.stdlib cimport free
from libc.string cimport strchr


cdef char *_ini_strip(char *s) noexcept nogil:
    """s without its leading blanks and trailing blanks and CR (cut in place)."""
    cdef char *end
    while s[0] == b' ' or s[0] == b'\t':
        s += 1
    end = s
    while end[0] != 0:
        end += 1
    while end > s and ((end - 1)[0] == b' ' or (end - 1)[0] == b'\t' or (end - 1)[0] == b'\r'):
        end -= 1
    end[0] = 0
    return s


cdef int32_t ini_parse(char *text, size_t length, ini_visitor visit, void *ctx) noexcept nogil:
    """Visits every key of the NUL-terminated `text` (changed in place); 0, or the
    first non-zero result of the visitor. A UTF-8 byte order mark is skipped; a NUL
    byte inside a line ends that line's content."""
    cdef char *end = text + length
    cdef char *line = text
    cdef char *eol
    cdef char *s
    cdef char *eq
    cdef char *close
    cdef const char *section = ""
    cdef int32_t number = 0, result
    if length >= 3 and <unsigned char>text[0] == 0xEF and <unsigned char>text[1] == 0xBB \
            and <unsigned char>text[2] == 0xBF:
        line += 3
    while line < end:
        number += 1
        eol = line
        while eol < end and eol[0] != b'\n':
            eol += 1
        eol[0] = 0                  # '\n', or the terminating NUL at the end
        s = _ini_strip(line)
        line = eol + 1
        if s[0] == 0 or s[0] == b';' or s[0] == b'#':
            continue
        if s[0] == b'[':
            close = strchr(s, b']')
            if close != NULL:
                close[0] = 0
                section = s + 1
            continue
        eq = strchr(s, b'=')
        if eq == NULL:
            continue
        eq[0] = 0
        result = visit(ctx, section, _ini_strip(s), _ini_strip(eq + 1), number)
        if result != 0:
            return result
    return 0


cdef int32_t ini_read(const char *path, ini_visitor visit, void *ctx) noexcept nogil:
    """Reads the INI file `path` and visits its keys: 0, the error number of the
    reading (files.pyx), or the first non-zero result of the visitor."""
    cdef size_t length
    cdef int32_t error = 0
    cdef char *text = read_whole_file(path, MAX_FILE_BYTES, &length, &error)
    if text == NULL:
        return error
    error = ini_parse(text, length, visit, ctx)
    free(text)
    return error
