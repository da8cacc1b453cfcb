# The one way an error is recorded: the generated constructors (catalogue.pxi) call
# record_error, which formats the catalogue's English text (error_format, generated
# from errors.toml) and its arguments separated by line feeds (numbers with a "."
# decimal point under any locale: numbers.pyx c_snprintf).
from libc.string cimport memset, strlen


cdef int _whole(double v) noexcept nogil:
    """A %d argument as C's int: NaN 0, beyond int's range its nearest end (no undefined
    cast)."""
    if not (v == v):
        return 0
    if v >= 2147483647.0:
        return 2147483647
    if v <= -2147483648.0:
        return -2147483647 - 1
    return <int>v


cdef size_t _append(char *buf, size_t cap, size_t pos, const char *s, size_t n) noexcept nogil:
    """Copies n bytes of s to buf[pos], truncated at cap - 1, buf kept terminated; the new
    end."""
    cdef size_t i = 0
    while i < n and pos + 1 < cap:
        buf[pos] = s[i]
        pos += 1
        i += 1
    buf[pos] = 0
    return pos


cdef void record_error(ErrorInfo *err, int32_t number, int32_t file_idx, int32_t line, int64_t column,
                       const ErrArg *args, int n_args) noexcept nogil:
    """Records error `number` at file/line/column: the catalogue's format with `args`
    substituted in order (numbers for %g %f %d ..., texts for %s). Only the generated
    constructors call it, each with exactly its format's arguments."""
    cdef const char *fmt = error_format(number)
    cdef char spec[16]
    cdef char piece[256]
    cdef size_t tpos = 0, apos = 0, k
    cdef int used = 0, n
    cdef const char *p = fmt
    cdef char conv
    cdef const char *text_arg
    cdef ErrArg stage
    if number == ERR_OUT_OF_MEMORY:
        stage.num = 0                   # the stage the thread works in (tc_set_stage), whatever the caller gave
        stage.text = tc_stage()
        args = &stage
        n_args = 1
    err.number = number
    err.file_idx = file_idx
    err.line = line
    err.column = <int32_t>column if 0 < column <= 0x7fffffff else 0
    err.text[0] = 0
    err.args[0] = 0
    if fmt == NULL:  # not in the catalogue: keep the number visible
        n = c_snprintf(piece, sizeof(piece), "Error %d", number)
        _append(err.text, ERROR_TEXT_BYTES, 0, piece, <size_t>n)
        return
    while p[0] != 0:
        if p[0] != b'%':
            tpos = _append(err.text, ERROR_TEXT_BYTES, tpos, p, 1)
            p += 1
            continue
        if p[1] == b'%':
            tpos = _append(err.text, ERROR_TEXT_BYTES, tpos, p, 1)
            p += 2
            continue
        # copy the conversion spec: flags, width, precision, then the conversion letter
        k = 0
        while p[k] != 0 and k < 15 and not (p[k] in b'gGfFeEdisx' and k > 0):
            spec[k] = p[k]
            k += 1
        if p[k] == 0 or k >= 15:
            break
        conv = p[k]
        spec[k] = conv
        spec[k + 1] = 0
        p += k + 1
        if used < n_args:
            if conv == b's':
                text_arg = args[used].text
                if text_arg == NULL:
                    text_arg = "(null)"
                n = c_snprintf(piece, sizeof(piece), spec, text_arg)
            elif conv == b'd' or conv == b'i' or conv == b'x':
                n = c_snprintf(piece, sizeof(piece), spec, _whole(args[used].num))
            else:
                n = c_snprintf(piece, sizeof(piece), spec, args[used].num)
            used += 1
        else:
            n = c_snprintf(piece, sizeof(piece), "?")
        if n < 0:
            n = 0
        if n >= <int>sizeof(piece):
            n = sizeof(piece) - 1
        tpos = _append(err.text, ERROR_TEXT_BYTES, tpos, piece, <size_t>n)
        if apos > 0:
            apos = _append(err.args, ERROR_ARGS_BYTES, apos, "\n", 1)
        apos = _append(err.args, ERROR_ARGS_BYTES, apos, piece, <size_t>n)


cdef void clear_error(ErrorInfo *err) noexcept nogil:
    """No error: every field of err zeroed (number 0)."""
    memset(err, 0, sizeof(ErrorInfo))
