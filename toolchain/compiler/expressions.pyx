# Expressions: recursive descent over one line, evaluated at once (no tree).
# Priority: brackets; functions; ^ (right-assoc); * / %; + -; unary minus.
# Angles are degrees. An operand list continues only while the next non-blank
# character is an operator, so `X10 Y-5` stays two words.
from libc.math cimport (sin, cos, tan, asin, acos, atan, atan2, fabs, sqrt, log10, log,
                        hypot, floor, ceil, pow, fmod, M_PI, isfinite)
from libc.string cimport memcpy


cdef int ex_error(CState *st, const char *start, const char *eol) noexcept nogil:
    """Syntax error: the rest of the line from `start` (up to 40 characters, without
    trailing blanks or CR) and its column."""
    return err_bad_expression(st.err, st.unit.file_idx, st.line, cword_rest(st, start, eol), column_of(st, start))


cdef int ex_plc_addr(CState *st, double addr, int size) noexcept nogil:
    """Byte address for a PLC access of `size` bytes, or -1 (error recorded)."""
    if not (addr >= 1.0) or addr != floor(addr) or addr + size > PLC_MEMORY_BYTES or st.inp.plc == NULL:
        return err_bad_plc_address(st.err, st.unit.file_idx, st.line, addr, PLC_MEMORY_BYTES - size)
    return <int>addr


cdef int ex_overflow(CState *st, const char *number, const char *after, const char *eol) noexcept nogil:
    """ERR_NUMBER_OVERFLOW: the number at [number, after) is too large for a double;
    the column counts from 1 at the start of the line."""
    cdef const char *line_start = st.unit.text + st.cur_pos
    return err_number_overflow(st.err, st.unit.file_idx, st.line, cword(st, number, eol, <int>(after - number)),
                               number - line_start + 1 if number >= line_start else 0)


cdef int ex_not_finite(CState *st, const char *start, const char *end) noexcept nogil:
    """ERR_NOT_FINITE_RESULT for the expression text [start, end)."""
    return err_not_finite_result(st.err, st.unit.file_idx, st.line, cword(st, start, end, <int>(end - start)))


cdef int ex_function(CState *st, const char *name, int n, double *args, int nargs,
                     double *out) noexcept nogil:
    """Applies function `name` (n chars) to its arguments."""
    cdef double x = args[0] if nargs > 0 else 0.0
    cdef double d2r = M_PI / 180.0
    cdef int addr
    cdef int32_t iv
    cdef double dv
    cdef int want = 1
    cdef char fname[16]
    cdef int i
    for i in range(n if n < 15 else 15):
        fname[i] = lx_upper(name[i])
    fname[n if n < 15 else 15] = 0
    if lx_eq(name, n, "PI"):
        want = 0
    elif lx_eq(name, n, "ATAN2") or lx_eq(name, n, "HYPOT") or lx_eq(name, n, "WRITEPLCLONG") \
            or lx_eq(name, n, "WRITEPLCDOUBLE"):
        want = 2
    if nargs != want:
        if lx_eq(name, n, "SIN") or lx_eq(name, n, "COS") or lx_eq(name, n, "TAN") \
                or lx_eq(name, n, "ASIN") or lx_eq(name, n, "ACOS") or lx_eq(name, n, "ATAN") \
                or lx_eq(name, n, "ABS") or lx_eq(name, n, "FABS") or lx_eq(name, n, "SQRT") \
                or lx_eq(name, n, "LOG10") or lx_eq(name, n, "LOG") or lx_eq(name, n, "FLOOR") \
                or lx_eq(name, n, "CEIL") or lx_eq(name, n, "READPLCLONG") \
                or lx_eq(name, n, "READPLCDOUBLE") or want != 1:
            return err_bad_expression(st.err, st.unit.file_idx, st.line, fname, column_of(st, name))
        return err_unknown_function(st.err, st.unit.file_idx, st.line, fname, column_of(st, name))
    if want == 0:
        out[0] = M_PI
    elif lx_eq(name, n, "SIN"): out[0] = sin(x * d2r)
    elif lx_eq(name, n, "COS"): out[0] = cos(x * d2r)
    elif lx_eq(name, n, "TAN"): out[0] = tan(x * d2r)
    elif lx_eq(name, n, "ASIN") or lx_eq(name, n, "ACOS"):
        if x < -1.0 or x > 1.0:
            return err_math_domain(st.err, st.unit.file_idx, st.line, fname, x)
        out[0] = (asin(x) if fname[1] == b'S' else acos(x)) / d2r
    elif lx_eq(name, n, "ATAN"): out[0] = atan(x) / d2r
    elif lx_eq(name, n, "ATAN2"): out[0] = atan2(args[0], args[1]) / d2r
    elif lx_eq(name, n, "ABS") or lx_eq(name, n, "FABS"): out[0] = fabs(x)
    elif lx_eq(name, n, "SQRT"):
        if x < 0.0:
            return err_math_domain(st.err, st.unit.file_idx, st.line, fname, x)
        out[0] = sqrt(x)
    elif lx_eq(name, n, "LOG10") or lx_eq(name, n, "LOG"):
        if x <= 0.0:
            return err_math_domain(st.err, st.unit.file_idx, st.line, fname, x)
        out[0] = log10(x) if n == 5 else log(x)
    elif lx_eq(name, n, "HYPOT"): out[0] = hypot(args[0], args[1])
    elif lx_eq(name, n, "FLOOR"): out[0] = floor(x)
    elif lx_eq(name, n, "CEIL"): out[0] = ceil(x)
    elif lx_eq(name, n, "READPLCLONG"):
        addr = ex_plc_addr(st, x, 4)
        if addr < 0:
            return R_ERR
        memcpy(&iv, st.inp.plc + addr, 4)
        out[0] = iv
    elif lx_eq(name, n, "READPLCDOUBLE"):
        addr = ex_plc_addr(st, x, 8)
        if addr < 0:
            return R_ERR
        memcpy(&dv, st.inp.plc + addr, 8)
        out[0] = dv
    elif lx_eq(name, n, "WRITEPLCLONG"):
        addr = ex_plc_addr(st, x, 4)
        if addr < 0:
            return R_ERR
        memcpy(&iv, st.inp.plc + addr, 4)
        out[0] = iv
        if not (args[1] >= -2147483648.0 and args[1] <= 2147483647.0):
            return err_math_domain(st.err, st.unit.file_idx, st.line, fname, args[1])
        iv = <int32_t>args[1]
        memcpy(st.inp.plc + addr, &iv, 4)
    elif lx_eq(name, n, "WRITEPLCDOUBLE"):
        addr = ex_plc_addr(st, x, 8)
        if addr < 0:
            return R_ERR
        memcpy(&dv, st.inp.plc + addr, 8)
        out[0] = dv
        memcpy(st.inp.plc + addr, &args[1], 8)
    else:
        return err_unknown_function(st.err, st.unit.file_idx, st.line, fname, column_of(st, name))
    return 0


cdef int ex_param_index(CState *st, const char **pp, const char *eol) noexcept nogil:
    """After 'P': the parameter number 0..99, or -1 (error recorded)."""
    cdef const char *p = pp[0]
    cdef int idx = 0, nd = 0
    while p < eol and lx_is_digit(p[0]) and nd < 6:
        idx = idx * 10 + (<int>p[0] - 48)
        nd += 1
        p += 1
    if nd == 0:
        err_unknown_word(st.err, st.unit.file_idx, st.line, "P", column_of(st, p - 1))
        return -1
    pp[0] = p
    if idx > 99 or (p < eol and lx_is_digit(p[0])):
        err_bad_parameter(st.err, st.unit.file_idx, st.line, idx, column_of(st, pp[0] - nd - 1))
        return -1
    return idx


cdef int ex_primary(CState *st, const char **pp, const char *eol, double *out, int depth) noexcept nogil:
    """A number, a ( ) bracket, a parameter Pnn or a function call name(a, b); errors for what
    is none of them, unbalanced brackets, a number out of range, a result that is not finite, or
    nesting past EXPR_DEPTH."""
    cdef const char *p = lx_skip_ws(pp[0], eol)
    cdef const char *name
    cdef const char *number_start
    cdef const char *open_at
    cdef int n, r, nargs, idx
    cdef double args[2]
    cdef double extra
    if depth > EXPR_DEPTH:
        return ex_error(st, p, eol)
    if p >= eol:
        return ex_error(st, pp[0], eol)
    if lx_is_digit(p[0]) or p[0] == b'.':
        number_start = p
        name = p
        r = lx_number(&p, eol, out)
        if r == -3:
            return ex_overflow(st, number_start, p, eol)
        if r != 0:
            return err_bad_number(st.err, st.unit.file_idx, st.line, cword_at(st, name, eol), column_of(st, name))
        pp[0] = p
        return 0
    if p[0] == b'(':
        name = p
        p += 1
        if ex_sum(st, &p, eol, out, depth + 1) != 0:
            return R_ERR
        p = lx_skip_ws(p, eol)
        if p >= eol or p[0] != b')':
            return err_unbalanced_brackets(st.err, st.unit.file_idx, st.line, column_of(st, name))
        pp[0] = p + 1
        return 0
    if (p[0] == b'P' or p[0] == b'p') and p + 1 < eol and lx_is_digit(p[1]):
        p += 1
        idx = ex_param_index(st, &p, eol)
        if idx < 0:
            return R_ERR
        out[0] = st.P[idx]
        pp[0] = p
        return 0
    n = lx_ident_run(p, eol)
    if n > 0:
        name = p
        p = lx_skip_ws(p + n, eol)
        if p >= eol or p[0] != b'(':
            return ex_error(st, name, eol)
        open_at = p
        p += 1
        nargs = 0
        p = lx_skip_ws(p, eol)
        if p < eol and p[0] == b')':
            p += 1
        else:
            while True:
                if nargs < 2:
                    r = ex_sum(st, &p, eol, &args[nargs], depth + 1)
                else:
                    r = ex_sum(st, &p, eol, &extra, depth + 1)
                if r != 0:
                    return R_ERR
                nargs += 1
                p = lx_skip_ws(p, eol)
                if p < eol and p[0] == b',':
                    p += 1
                    continue
                if p < eol and p[0] == b')':
                    p += 1
                    break
                return err_unbalanced_brackets(st.err, st.unit.file_idx, st.line, column_of(st, open_at))
        if ex_function(st, name, n, args, nargs, out) != 0:
            return R_ERR
        if not isfinite(out[0]):        # e.g. ReadPLCDouble of a NaN
            return ex_not_finite(st, name, p)
        pp[0] = p
        return 0
    return ex_error(st, p, eol)


cdef int ex_unary(CState *st, const char **pp, const char *eol, double *out, int depth) noexcept nogil:
    """Unary minus binds looser than '^': -2^2 = -4, 2^-1 = 0.5."""
    cdef const char *p = lx_skip_ws(pp[0], eol)
    if p < eol and (p[0] == b'-' or p[0] == b'+'):
        if depth > EXPR_DEPTH:
            return ex_error(st, p, eol)
        pp[0] = p + 1
        if ex_unary(st, pp, eol, out, depth + 1) != 0:
            return R_ERR
        if p[0] == b'-':
            out[0] = -out[0]
        return 0
    pp[0] = p
    return ex_power(st, pp, eol, out, depth)


cdef int ex_power(CState *st, const char **pp, const char *eol, double *out, int depth) noexcept nogil:
    """a ^ b (right-associative through ex_unary: 2^-1 = 0.5); error when the result is not
    finite."""
    cdef const char *p
    cdef double rhs
    if ex_primary(st, pp, eol, out, depth) != 0:
        return R_ERR
    p = lx_skip_ws(pp[0], eol)
    if p < eol and p[0] == b'^':
        pp[0] = p + 1
        if depth > EXPR_DEPTH:
            return ex_error(st, p, eol)
        if ex_unary(st, pp, eol, &rhs, depth + 1) != 0:
            return R_ERR
        out[0] = pow(out[0], rhs)
        if not isfinite(out[0]):
            return err_math_domain(st.err, st.unit.file_idx, st.line, "^", rhs)
    return 0


cdef int ex_product(CState *st, const char **pp, const char *eol, double *out, int depth) noexcept nogil:
    """Products: *, / and % left to right; division by zero and a result that is not finite are
    errors ('//' starts a comment, not an operator)."""
    cdef const char *p
    cdef const char *start = lx_skip_ws(pp[0], eol)
    cdef double rhs
    cdef char op
    if ex_unary(st, pp, eol, out, depth) != 0:
        return R_ERR
    while True:
        p = lx_skip_ws(pp[0], eol)
        if p >= eol or not (p[0] == b'*' or p[0] == b'/' or p[0] == b'%'):
            return 0
        if p[0] == b'/' and p + 1 < eol and p[1] == b'/':
            return 0        # '//' comment
        op = p[0]
        pp[0] = p + 1
        if ex_unary(st, pp, eol, &rhs, depth) != 0:
            return R_ERR
        if op == b'*':
            out[0] = out[0] * rhs
        elif rhs == 0.0:
            return err_division_by_zero(st.err, st.unit.file_idx, st.line)
        elif op == b'/':
            out[0] = out[0] / rhs
        else:
            out[0] = fmod(out[0], rhs)
        if not isfinite(out[0]):        # 1e308 * 10
            return ex_not_finite(st, start, pp[0])


cdef int ex_sum(CState *st, const char **pp, const char *eol, double *out, int depth) noexcept nogil:
    """Sums: + and - left to right over products; a result that is not finite is an error."""
    cdef const char *p
    cdef const char *start = lx_skip_ws(pp[0], eol)
    cdef double rhs
    cdef char op
    if ex_product(st, pp, eol, out, depth) != 0:
        return R_ERR
    while True:
        p = lx_skip_ws(pp[0], eol)
        if p >= eol or not (p[0] == b'+' or p[0] == b'-'):
            return 0
        op = p[0]
        pp[0] = p + 1
        if ex_product(st, pp, eol, &rhs, depth) != 0:
            return R_ERR
        if op == b'+':
            out[0] = out[0] + rhs
        else:
            out[0] = out[0] - rhs
        if not isfinite(out[0]):        # 1e308 + 1e308
            return ex_not_finite(st, start, pp[0])


cdef inline int ex_value(CState *st, const char **pp, const char *eol, double *out) noexcept nogil:
    """A word's value: a plain number takes the fast path, anything else the full
    expression parser."""
    cdef const char *p = pp[0]
    cdef const char *q
    cdef int r
    cdef bint neg = p < eol and p[0] == b'-'
    if neg:
        p += 1      # (not followed by a digit: the expression parser reads it from pp)
    if p < eol and lx_is_digit(p[0]):
        q = p
        r = lx_number(&q, eol, out)
        if neg:
            out[0] = -out[0]
        if r == 0:
            # done unless an operator follows (X10+P1)
            p = lx_skip_ws(q, eol)
            if p >= eol or not lx_is_operator(p[0]):
                pp[0] = q
                return 0
            if p[0] == b'/' and p + 1 < eol and p[1] == b'/':
                pp[0] = q
                return 0
    return ex_sum(st, pp, eol, out, 0)


cdef int ex_condition(CState *st, const char **pp, const char *eol, bint *out) noexcept nogil:
    """expr [op expr] with op one of > < == = != <> <= >=; a lone expr is true when != 0."""
    cdef double a, b
    cdef const char *p
    cdef int op = 0     # 1 > 2 < 3 == 4 != 5 <= 6 >=
    if ex_sum(st, pp, eol, &a, 0) != 0:
        return R_ERR
    p = lx_skip_ws(pp[0], eol)
    if p + 1 < eol and p[0] == b'=' and p[1] == b'=':
        op = 3; p += 2
    elif p + 1 < eol and p[0] == b'!' and p[1] == b'=':
        op = 4; p += 2
    elif p + 1 < eol and p[0] == b'<' and p[1] == b'>':
        op = 4; p += 2
    elif p + 1 < eol and p[0] == b'<' and p[1] == b'=':
        op = 5; p += 2
    elif p + 1 < eol and p[0] == b'>' and p[1] == b'=':
        op = 6; p += 2
    elif p < eol and p[0] == b'>':
        op = 1; p += 1
    elif p < eol and p[0] == b'<':
        op = 2; p += 1
    elif p < eol and p[0] == b'=':
        op = 3; p += 1
    if op == 0:
        out[0] = a != 0.0
        pp[0] = p
        return 0
    pp[0] = p
    if ex_sum(st, pp, eol, &b, 0) != 0:
        return R_ERR
    if op == 1: out[0] = a > b
    elif op == 2: out[0] = a < b
    elif op == 3: out[0] = a == b
    elif op == 4: out[0] = a != b
    elif op == 5: out[0] = a <= b
    else: out[0] = a >= b
    return 0
