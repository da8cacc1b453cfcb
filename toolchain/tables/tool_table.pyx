# The tool correction table (docs/tool-table.md): 99 entries of a radius (what D
# selects for G41/G42) and the length corrections of axes 1..4 (what & selects),
# read from a TAB0.KOR file and written by G92 D. The file is text the operator
# edits: an optional comment, then the keyword $KOR, then one line per entry,
#
#     $KOR
#     01: R=10.0 X=20.0 Y=30.0 Z=40.0
#     95: R=0.0 1=12.55 2=0.0 3=0.0 4=0.0
#
# a value missing on its line is 0, an entry missing from the file is all 0. A later
# $KOR block may give an entry again: its line replaces the earlier one. The reader
# takes any bytes (NUL bytes, CRLF, lines of any length) and refuses, naming the
# line, whatever is not that format; the table it reads into is written only when
# the whole file is good.
from libc.stdlib cimport free
from libc.string cimport memset


cdef inline bint _blank(char c) noexcept nogil:
    """Whether c is a blank of a TAB0.KOR line (space, tab, CR)."""
    return c == b' ' or c == b'\t' or c == b'\r'


cdef void _quote(char *out, size_t size, const char *s, const char *end) noexcept nogil:
    """A piece of the file for an error text: at most 24 bytes of [s, end), the
    unprintable ones as '?', '...' when cut."""
    cdef size_t n = 0
    cdef unsigned char c
    while s < end and n + 4 < size and n < 24:
        c = <unsigned char>s[0]
        out[n] = <char>c if 0x20 <= c < 0x7F else b'?'
        n += 1
        s += 1
    if s < end and n + 4 <= size:
        out[n] = b'.'
        out[n + 1] = b'.'
        out[n + 2] = b'.'
        n += 3
    out[n] = 0


cdef bint _line_error(ErrorInfo *err, const char *name, int32_t line, const char *why) noexcept nogil:
    """ERR_TOOL_TABLE_LINE: the file, the line and why; returns False."""
    err_tool_table_line(err, -1, line, name, line, why)
    return False


cdef bint _is_keyword(const char *s, const char *end) noexcept nogil:
    """[s, end) is $KOR (any case) and blanks."""
    if end - s < 4 or s[0] != b'$' or (s[1] | 0x20) != b'k' or (s[2] | 0x20) != b'o' or (s[3] | 0x20) != b'r':
        return False
    s += 4
    while s < end and _blank(s[0]):
        s += 1
    return s == end


cdef int _value_slot(char name) noexcept nogil:
    """The value a word's name writes: 0 radius (R), 1..4 length of axes 1..4 (X Y Z U,
    the names the tool compensation manual gives axes 1..4, or the axis number); -1
    none."""
    cdef char c = name | 0x20 if b'A' <= name <= b'Z' else name
    if c == b'r': return 0
    if c == b'x' or c == b'1': return 1
    if c == b'y' or c == b'2': return 2
    if c == b'z' or c == b'3': return 3
    if c == b'u' or c == b'4': return 4
    return -1


cdef const char *_slot_name(int slot) noexcept nogil:
    """The name of a tool value slot for the errors: the radius, or the length of axis 1..4."""
    if slot == 0: return "radius"
    if slot == 1: return "length of axis 1"
    if slot == 2: return "length of axis 2"
    if slot == 3: return "length of axis 3"
    return "length of axis 4"


cdef bint _parse_entry(const char *s, const char *end, const char *name, int32_t line,
                       int32_t *given, ToolTable *table, ErrorInfo *err) noexcept nogil:
    """One line of a $KOR block, blanks stripped: `NN: name=value ...` into the table;
    False with err naming the line. given[n]: the line entry n was given on in this
    block (0: not yet)."""
    cdef char why[256]
    cdef char quoted[32]
    cdef char number_text[64]
    cdef const char *word
    cdef const char *p
    cdef double values[5]
    cdef double value
    cdef bint seen[5]
    cdef int entry, slot, k
    for k in range(TOOL_VALUES):
        values[k] = 0.0
        seen[k] = False
    if end - s < 3 or not (b'0' <= s[0] <= b'9') or not (b'0' <= s[1] <= b'9') or s[2] != b':':
        _quote(quoted, sizeof(quoted), s, end)
        c_snprintf(why, sizeof(why), "'%s' is no entry: a line of the table starts with its two digits 01..99 and ':'", quoted)
        return _line_error(err, name, line, why)
    entry = (s[0] - 48) * 10 + (s[1] - 48)
    if entry == 0:
        return _line_error(err, name, line, "entry 00 does not exist (01..99)")
    if given[entry] != 0:
        c_snprintf(why, sizeof(why), "entry %02d is given twice in this $KOR block (first on line %d)", entry, given[entry])
        return _line_error(err, name, line, why)
    s += 3
    while True:
        while s < end and _blank(s[0]):
            s += 1
        if s >= end:
            break
        word = s
        while s < end and not _blank(s[0]):
            s += 1
        slot = _value_slot(word[0])
        if s - word < 2 or word[1] != b'=' or slot < 0:
            _quote(quoted, sizeof(quoted), word, s)
            c_snprintf(why, sizeof(why), "'%s' is no value of an entry: R= (radius), X= Y= Z= or 1= 2= 3= 4= (lengths of axes 1..4)", quoted)
            return _line_error(err, name, line, why)
        if seen[slot]:
            c_snprintf(why, sizeof(why), "entry %02d: its %s is given twice", entry, _slot_name(slot))
            return _line_error(err, name, line, why)
        # a number of digits, sign, point and exponent only: no hexadecimal, inf, nan or decimal comma
        p = word + 2
        while p < s and (b'0' <= p[0] <= b'9' or p[0] == b'+' or p[0] == b'-' or p[0] == b'.'
                         or p[0] == b'e' or p[0] == b'E'):
            p += 1
        _quote(quoted, sizeof(quoted), word, s)
        if p != s or <size_t>(s - word - 2) >= sizeof(number_text) or s - word == 2:
            c_snprintf(why, sizeof(why), "'%s': the %s is not a number", quoted, _slot_name(slot))
            return _line_error(err, name, line, why)
        k = 0
        p = word + 2
        while p < s:
            number_text[k] = p[0]
            k += 1
            p += 1
        number_text[k] = 0
        if not c_parse_double(number_text, &value):
            c_snprintf(why, sizeof(why), "'%s': the %s is not a number", quoted, _slot_name(slot))
            return _line_error(err, name, line, why)
        if not (-TC_MAX_LENGTH <= value <= TC_MAX_LENGTH):
            c_snprintf(why, sizeof(why), "'%s': the %s is outside <-1e6, 1e6> mm", quoted, _slot_name(slot))
            return _line_error(err, name, line, why)
        values[slot] = value
        seen[slot] = True
    for k in range(TOOL_VALUES):
        table.entry[entry].value[k] = values[k]
    given[entry] = line
    return True


cdef bint _tool_table_parse(const char *text, size_t length, const char *name, ToolTable *out,
                           ErrorInfo *err) noexcept nogil:
    """The table of the file text [text, text + length) (any bytes) into *out, which
    is written only when the whole text is good; False with err naming the file
    `name` and the line (ERR_TOOL_TABLE_LINE) or saying it has no $KOR
    (ERR_TOOL_TABLE_NO_KEYWORD)."""
    cdef ToolTable table
    cdef int32_t given[100]
    cdef const char *end = text + length
    cdef const char *line = text
    cdef const char *raw
    cdef const char *eol
    cdef const char *s
    cdef const char *e
    cdef const char *p
    cdef char why[256]
    cdef int32_t number = 0
    cdef bint in_table = False
    memset(&table, 0, sizeof(ToolTable))
    memset(given, 0, sizeof(given))
    if length >= 3 and <unsigned char>text[0] == 0xEF and <unsigned char>text[1] == 0xBB \
            and <unsigned char>text[2] == 0xBF:
        line += 3                       # a UTF-8 byte order mark
    while line < end:
        number += 1
        eol = line
        while eol < end and eol[0] != b'\n':
            eol += 1
        raw = line
        s = line
        e = eol
        line = eol + 1
        while s < e and _blank(s[0]):
            s += 1
        while e > s and _blank((e - 1)[0]):
            e -= 1
        if _is_keyword(s, e):
            in_table = True
            memset(given, 0, sizeof(given))     # a new block may give an entry again
            continue
        if not in_table or s == e:
            continue                            # the comment before $KOR; blank lines
        p = s
        while p < e and (<unsigned char>p[0] >= 0x20 or p[0] == b'\t' or p[0] == b'\r') and p[0] != 0x7F:
            p += 1
        if p < e:
            c_snprintf(why, sizeof(why), "byte 0x%02x at column %d is no text", <unsigned char>p[0],
                       <int>(p - raw) + 1)
            return _line_error(err, name, number, why)
        if not _parse_entry(s, e, name, number, given, &table, err):
            return False
    if not in_table:
        err_tool_table_no_keyword(err, -1, 0, name)
        return False
    out[0] = table
    return True


cdef bint tool_table_read(const char *path, ToolTable *out, ErrorInfo *err) noexcept nogil:
    """_tool_table_parse of the regular file `path` (files.pyx); a file that cannot be
    read: False with its error (ERR_FILE_OPEN ...) naming it."""
    cdef size_t length
    cdef int32_t error = 0
    cdef char *text
    cdef bint good
    tc_set_stage("reading a tool table")       # (the host's thread: cleared again below)
    text = read_whole_file(path, MAX_TABLE_BYTES, &length, &error)
    if text == NULL:
        if error == ERR_FILE_TOO_LARGE:
            err_table_too_large(err, -1, 0, path)
        else:
            file_error(err, error, -1, path)
        good = False
    else:
        good = _tool_table_parse(text, length, path, out, err)
        free(text)
    tc_set_stage(NULL)
    return good


cdef bint tool_table_set(ToolTable *table, int64_t entry, uint32_t programmed, const double *values,
                         ErrorInfo *err) noexcept nogil:
    """G92 D: writes values[k] into the entry's value k for every bit k of
    `programmed` (R0..R4: radius, lengths of axes 1..4), the others stay. Nothing is
    written, False and err set, for an entry outside 1..99 (ERR_TOOL_ENTRY) or a
    programmed value that is not finite or beyond +-1e6 mm (ERR_NOT_FINITE,
    ERR_OUT_OF_RANGE naming `D<entry> R<k>`)."""
    cdef char field[32]
    cdef int k
    if entry < 1 or entry > TOOL_ENTRIES:
        err_tool_entry(err, -1, 0, <double>entry)
        return False
    for k in range(TOOL_VALUES):
        if programmed & (1u << k):
            c_snprintf(field, sizeof(field), "D%d R%d", <int>entry, k)
            if not isfinite(values[k]):
                err_not_finite(err, -1, 0, field, values[k])
                return False
            if not (-TC_MAX_LENGTH <= values[k] <= TC_MAX_LENGTH):
                err_out_of_range(err, -1, 0, field, values[k], -TC_MAX_LENGTH, TC_MAX_LENGTH)
                return False
    for k in range(TOOL_VALUES):
        if programmed & (1u << k):
            table.entry[entry].value[k] = values[k]
    return True
