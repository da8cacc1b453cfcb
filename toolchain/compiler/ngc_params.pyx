# ISO mode: LinuxCNC's parameters and expressions (docs/compiler.md, "ISO compatibility
# mode"). Numbered parameters #1..#5601, named ones: #<name> belongs to the call level
# that set it, #<_name> is global, and the interpreter's state reads as read-only
# #<_x>, #<_motion_mode>, ... Values in [ ] expressions with LinuxCNC's operators and
# functions. Everything on a line is evaluated when the line is read; the parameter
# settings of the line take effect after that (so `#1=5 X#1` moves to the old #1).
from libc.stdlib cimport free
from libc.string cimport memcmp, memcpy
from libc.math cimport (sin, cos, tan, asin, acos, atan2, fabs, sqrt, log, exp, floor, ceil,
                        pow, fmod, round, M_PI, isfinite)

cdef extern from *:
    """
    /* LinuxCNC's TOLERANCE_EQUAL: EQ and NE compare within it */
    #define NGC_TOLERANCE_EQUAL 1e-6
    /* a value this close to a whole number is that number where one is wanted (a
       parameter number, a computed O label), as LinuxCNC reads one */
    #define NGC_TOLERANCE_WHOLE 1e-4
    """
    double NGC_TOLERANCE_EQUAL
    double NGC_TOLERANCE_WHOLE


cdef NgcState *ngc_new() noexcept nogil:
    """The ISO mode's state at the start of a program: every parameter 0, G54, G98."""
    cdef NgcState *n = <NgcState *>tc_calloc(1, sizeof(NgcState))
    if n == NULL:
        return NULL
    n.coord = 1
    n.retract = 98
    return n


cdef void ngc_free(NgcState *n) noexcept nogil:
    """Frees the ISO mode's state and its arrays; n may be NULL."""
    if n != NULL:
        free(n.name_slots)
        free(n.names)
        free(n.subs)
        free(n.if_keys)
        free(n.nurbs)
        free(n)


# ------------------------------------------------------------------ names

cdef int ngc_name_read(CState *st, const char **pp, const char *eol, char *out, int *out_len) noexcept nogil:
    """At '<': the name up to '>', lower case, blanks removed (LinuxCNC's rule)."""
    cdef const char *p = pp[0] + 1
    cdef int n = 0
    while p < eol and p[0] != b'>':
        if p[0] != b' ' and p[0] != b'\t':
            if n >= NGC_NAME_CHARS - 1:
                return err_bad_expression(st.err, st.unit.file_idx, st.line, cword_at(st, pp[0], eol), column_of(st, pp[0]))
            out[n] = p[0] + 32 if (p[0] >= b'A' and p[0] <= b'Z') else p[0]
            n += 1
        p += 1
    if p >= eol or n == 0:
        return err_bad_expression(st.err, st.unit.file_idx, st.line, cword_at(st, pp[0], eol), column_of(st, pp[0]))
    out[n] = 0
    out_len[0] = n
    pp[0] = p + 1
    return 0


cdef bint _same(const char *a, int na, const char *b, int nb) noexcept nogil:
    """Whether two names of given lengths are the same bytes."""
    return na == nb and memcmp(a, b, na) == 0


cdef size_t _name_hash(int level, const char *name, int nlen) noexcept nogil:
    """The name's hash (the labels' FNV-1a) mixed with its call level."""
    cdef uint64_t h = lb_hash_name(name, nlen) ^ (<uint64_t><uint32_t>level * 0x9E3779B97F4A7C15ULL)
    return <size_t>(h ^ (h >> 29))


cdef void _name_slot_put(NgcState *n, size_t i) noexcept nogil:
    """names[i] into the index (room for it is there)."""
    cdef size_t mask = n.n_slots - 1
    cdef size_t k = _name_hash(n.names[i].level, n.names[i].name, n.names[i].len) & mask
    while n.name_slots[k] != 0:
        k = (k + 1) & mask
    n.name_slots[k] = <uint32_t>(i + 1)


cdef bint ngc_names_index(NgcState *n) noexcept nogil:
    """The index of names[] built anew (after a return dropped names, or to grow it);
    False: no memory (the names stay, the index is gone: lookups find nothing new)."""
    cdef size_t want = 64, i
    while want < 2 * n.n_names + 2:
        want *= 2
    free(n.name_slots)
    n.name_slots = <uint32_t *>tc_calloc(want, sizeof(uint32_t))
    n.n_slots = want if n.name_slots != NULL else 0
    if n.name_slots == NULL:
        return False
    for i in range(n.n_names):
        _name_slot_put(n, i)
    return True


cdef NgcName *ngc_name_find(NgcState *n, const char *name, int nlen) noexcept nogil:
    """The named parameter a line of the current call level sees; NULL: none. One
    probe sequence of the index: programs set tens of thousands of names."""
    cdef int level = -1 if name[0] == b'_' else n.level
    cdef size_t mask = n.n_slots - 1, k
    cdef NgcName *e
    if n.n_slots == 0:
        return NULL
    k = _name_hash(level, name, nlen) & mask
    while n.name_slots[k] != 0:
        e = &n.names[n.name_slots[k] - 1]
        if e.level == level and _same(e.name, e.len, name, nlen):
            return e
        k = (k + 1) & mask
    return NULL


cdef int ngc_name_set(CState *st, const char *name, int nlen, double value) noexcept nogil:
    """Sets a named parameter, adding it when the current call level does not see one (#<_name>
    global, others local to the level); error 4 when memory is exhausted."""
    cdef NgcState *n = st.ngc
    cdef NgcName *e = ngc_name_find(n, name, nlen)
    if e == NULL:
        if not grow(<void **>&n.names, &n.cap_names, n.n_names + 1, sizeof(NgcName)):
            return err_out_of_memory(st.err, st.unit.file_idx, st.line)
        e = &n.names[n.n_names]
        n.n_names += 1
        e.level = -1 if name[0] == b'_' else n.level
        e.len = nlen
        memcpy(e.name, name, nlen + 1)
        if e.level >= 1:
            n.n_locals += 1
        if 2 * n.n_names + 2 > n.n_slots:
            if not ngc_names_index(n):
                return err_out_of_memory(st.err, st.unit.file_idx, st.line)
        else:
            _name_slot_put(n, n.n_names - 1)
    e.value = value
    return 0


cdef bint _axis_value(const char *name, int nlen, const char *prefix, int plen, int *axis) noexcept nogil:
    """name is prefix + one axis letter of LinuxCNC (x y z a b c u v w): its TG index."""
    cdef char c
    if nlen != plen + 1 or memcmp(name, prefix, plen) != 0:
        return False
    c = name[plen] - 32 if (name[plen] >= b'a' and name[plen] <= b'z') else name[plen]
    axis[0] = axis_of_letter(c)
    return axis[0] >= 0 and axis[0] != 9        # O is no LinuxCNC axis


cdef bint ngc_predefined(CState *st, const char *name, int nlen, double *out) noexcept nogil:
    """The read-only named parameters of LinuxCNC's interpreter state; False: not one."""
    cdef NgcState *n = st.ngc
    cdef int a
    if _axis_value(name, nlen, "_abs_", 5, &a):
        out[0] = st.mpos[a] / st.unit_scale
        return True
    if _axis_value(name, nlen, "_", 1, &a):
        out[0] = st.ppos[a] / st.unit_scale
        return True
    if lx_eq(name, nlen, "_VMAJOR"): out[0] = 2.9
    elif lx_eq(name, nlen, "_VMINOR"): out[0] = 0.0
    elif lx_eq(name, nlen, "_LINE"): out[0] = st.line
    elif lx_eq(name, nlen, "_MOTION_MODE"): out[0] = 800.0 if st.motion < 0 else st.motion * 10.0
    elif lx_eq(name, nlen, "_PLANE"): out[0] = 180.0 if st.plane == -18 else (170.0 if st.plane == 17 else 190.0)
    elif lx_eq(name, nlen, "_CCOMP"): out[0] = 400.0 if st.comp == 40 else st.comp * 10.0
    elif lx_eq(name, nlen, "_METRIC"): out[0] = 1.0 if st.unit_scale == 1.0 else 0.0
    elif lx_eq(name, nlen, "_IMPERIAL"): out[0] = 0.0 if st.unit_scale == 1.0 else 1.0
    elif lx_eq(name, nlen, "_ABSOLUTE"): out[0] = 1.0 if st.absolute else 0.0
    elif lx_eq(name, nlen, "_INCREMENTAL"): out[0] = 0.0 if st.absolute else 1.0
    elif lx_eq(name, nlen, "_INVERSE_TIME"): out[0] = 1.0 if n.inverse_time else 0.0
    elif lx_eq(name, nlen, "_UNITS_PER_MINUTE"): out[0] = 1.0 if st.per_min and not n.inverse_time else 0.0
    elif lx_eq(name, nlen, "_UNITS_PER_REV"): out[0] = 0.0 if st.per_min else 1.0
    elif lx_eq(name, nlen, "_COORD_SYSTEM"):
        out[0] = 530.0 + 10.0 * n.coord if n.coord <= 6 else 584.0 + n.coord
    elif lx_eq(name, nlen, "_TOOL_OFFSET"): out[0] = 0.0
    elif lx_eq(name, nlen, "_RETRACT_R_PLANE"): out[0] = 1.0 if n.retract == 99 else 0.0
    elif lx_eq(name, nlen, "_RETRACT_OLD_Z"): out[0] = 1.0 if n.retract == 98 else 0.0
    elif lx_eq(name, nlen, "_SPINDLE_RPM_MODE"): out[0] = 0.0 if st.css else 1.0
    elif lx_eq(name, nlen, "_SPINDLE_CSS_MODE"): out[0] = 1.0 if st.css else 0.0
    elif lx_eq(name, nlen, "_IJK_ABSOLUTE_MODE"): out[0] = 1.0 if n.ijk_absolute else 0.0
    elif lx_eq(name, nlen, "_LATHE_DIAMETER_MODE") or lx_eq(name, nlen, "_LATHE_RADIUS_MODE"): out[0] = 0.0
    elif lx_eq(name, nlen, "_SPINDLE_ON"): out[0] = 1.0 if n.spindle != 0 else 0.0
    elif lx_eq(name, nlen, "_SPINDLE_CW"): out[0] = 1.0 if n.spindle == 3 else 0.0
    elif lx_eq(name, nlen, "_MIST"): out[0] = 1.0 if n.mist else 0.0
    elif lx_eq(name, nlen, "_FLOOD"): out[0] = 1.0 if n.flood else 0.0
    elif lx_eq(name, nlen, "_SPEED_OVERRIDE") or lx_eq(name, nlen, "_FEED_OVERRIDE"): out[0] = 1.0
    elif lx_eq(name, nlen, "_ADAPTIVE_FEED") or lx_eq(name, nlen, "_FEED_HOLD"): out[0] = 0.0
    elif lx_eq(name, nlen, "_FEED"): out[0] = st.feed / st.unit_scale
    elif lx_eq(name, nlen, "_RPM"): out[0] = st.spindle
    elif lx_eq(name, nlen, "_CURRENT_TOOL") or lx_eq(name, nlen, "_SELECTED_TOOL"): out[0] = st.tool
    elif lx_eq(name, nlen, "_CURRENT_POCKET") or lx_eq(name, nlen, "_SELECTED_POCKET"): out[0] = st.tool
    elif lx_eq(name, nlen, "_VALUE"): out[0] = n.value
    elif lx_eq(name, nlen, "_VALUE_RETURNED"): out[0] = 1.0 if n.value_returned else 0.0
    elif lx_eq(name, nlen, "_TASK"): out[0] = 0.0           # as LinuxCNC's preview and rs274
    elif lx_eq(name, nlen, "_CALL_LEVEL"): out[0] = n.level
    elif lx_eq(name, nlen, "_REMAP_LEVEL"): out[0] = 0.0
    else:
        return False
    return True


cdef bint _host_value(const char *name, int nlen) noexcept nogil:
    """#<_hal[...]> and #<_ini[...]>: values of LinuxCNC's HAL and INI file."""
    return nlen > 5 and (memcmp(name, "_hal[", 5) == 0 or memcmp(name, "_ini[", 5) == 0)


# ------------------------------------------------------------- numbered

cdef bint _computed(int idx) noexcept nogil:
    """#5220 (the coordinate system), #5400 (the tool), #5420..#5428 (the position)
    follow the program's state: read-only."""
    return idx == 5220 or idx == 5400 or (idx >= 5420 and idx <= 5428)


cdef bint _positional(int idx) noexcept nogil:
    """The parameters that become positions of parts when a G function reads them: the
    G28 / G30 homes (#5161.., #5181..), the G92 offsets (#5211..) and the work offsets
    of G54..G59.3 (#5221..#5389). They pass the address words' bound when set."""
    return (5161 <= idx <= 5169 or 5181 <= idx <= 5189 or 5211 <= idx <= 5219
            or (5221 <= idx <= 5389 and (idx - 5221) % 20 < 9))


cdef double ngc_number_get(CState *st, int idx) noexcept nogil:
    """The value of numbered parameter idx: the few LinuxCNC computes (5220 the coordinate
    system, 5400 the tool, 5420-5428 the position in program units) from the compiler's state,
    the rest as set."""
    cdef int a
    cdef const char *axes = "XYZABCUVW"
    if idx == 5220:
        return st.ngc.coord
    if idx == 5400:
        return st.tool
    if idx >= 5420 and idx <= 5428:
        a = axis_of_letter(axes[idx - 5420])
        return st.ppos[a] / st.unit_scale
    return st.ngc.params[idx]


cdef int ngc_index(CState *st, double v, const char *at, const char *eol) noexcept nogil:
    """A parameter number: an integer (within NGC_TOLERANCE_WHOLE, as LinuxCNC reads one) in
    1..5601."""
    cdef double r = floor(v + 0.5)
    if not (fabs(v - r) < NGC_TOLERANCE_WHOLE and r >= 1.0 and r < NGC_PARAMS):
        return err_ngc_parameter(st.err, st.unit.file_idx, st.line, v, column_of(st, at))
    return <int>r


# ------------------------------------------------------------- reading

cdef int ngc_param_read(CState *st, const char **pp, const char *eol, double *out, int depth) noexcept nogil:
    """At '#': the value of #n, #[expression], ##n or #<name>."""
    cdef const char *at = pp[0]
    cdef const char *p = lx_skip_ws(at + 1, eol)
    cdef char name[NGC_NAME_CHARS]
    cdef int nlen, idx
    cdef NgcName *e
    cdef double v
    if p < eol and p[0] == b'<':
        if ngc_name_read(st, &p, eol, name, &nlen) != 0:
            return R_ERR
        pp[0] = p
        if _host_value(name, nlen):
            return err_ngc_unreadable(st.err, st.unit.file_idx, st.line, cword(st, at, eol, <int>(p - at)), column_of(st, at), "HAL pins and INI values are LinuxCNC's own")
        e = ngc_name_find(st.ngc, name, nlen)
        if e != NULL:
            out[0] = e.value
            return 0
        if name[0] == b'_' and ngc_predefined(st, name, nlen, out):
            return 0
        return err_ngc_undefined(st.err, st.unit.file_idx, st.line, cword(st, at, eol, <int>(p - at)), column_of(st, at))
    if ngc_value(st, &p, eol, &v, depth + 1) != 0:
        return R_ERR
    idx = ngc_index(st, v, at, eol)
    if idx < 0:
        return R_ERR
    out[0] = ngc_number_get(st, idx)
    pp[0] = p
    return 0


cdef int ngc_function(CState *st, const char **pp, const char *eol, int n, double *out, int depth) noexcept nogil:
    """At a function name of n letters followed by '[': ABS ACOS ASIN ATAN[y]/[x] COS EXP
    FIX FUP ROUND LN SIN SQRT TAN EXISTS[#<name>]; angles in degrees."""
    cdef const char *name = pp[0]
    cdef const char *p = lx_skip_ws(name + n, eol)
    cdef double x, y
    cdef double d2r = M_PI / 180.0
    cdef char fname[8]
    cdef char pname[NGC_NAME_CHARS]
    cdef int i, nlen
    for i in range(n if n < 7 else 7):
        fname[i] = lx_upper(name[i])
    fname[n if n < 7 else 7] = 0
    if lx_eq(name, n, "EXISTS"):
        p = lx_skip_ws(p + 1, eol)
        if p < eol and p[0] == b'#':
            p = lx_skip_ws(p + 1, eol)
        if p < eol and p[0] == b'<':
            if ngc_name_read(st, &p, eol, pname, &nlen) != 0:
                return R_ERR
            p = lx_skip_ws(p, eol)
            if p < eol and p[0] == b']':
                out[0] = 1.0 if (ngc_name_find(st.ngc, pname, nlen) != NULL or
                                 (pname[0] == b'_' and ngc_predefined(st, pname, nlen, &x))) else 0.0
                pp[0] = p + 1
                return 0
        return ex_error(st, name, eol)      # LinuxCNC: EXISTS takes one named parameter
    if ngc_expression(st, &p, eol, &x, depth + 1) != 0:
        return R_ERR
    if lx_eq(name, n, "ATAN"):
        p = lx_skip_ws(p, eol)
        if p >= eol or p[0] != b'/':
            return ex_error(st, p, eol)
        p = lx_skip_ws(p + 1, eol)
        if ngc_expression(st, &p, eol, &y, depth + 1) != 0:
            return R_ERR
        out[0] = atan2(x, y) / d2r
    elif lx_eq(name, n, "ABS"): out[0] = fabs(x)
    elif lx_eq(name, n, "ACOS") or lx_eq(name, n, "ASIN"):
        if x < -1.0 or x > 1.0:
            return err_math_domain(st.err, st.unit.file_idx, st.line, fname, x)
        out[0] = (acos(x) if fname[1] == b'C' else asin(x)) / d2r
    elif lx_eq(name, n, "COS"): out[0] = cos(x * d2r)
    elif lx_eq(name, n, "SIN"): out[0] = sin(x * d2r)
    elif lx_eq(name, n, "TAN"): out[0] = tan(x * d2r)
    elif lx_eq(name, n, "EXP"): out[0] = exp(x)
    elif lx_eq(name, n, "FIX"): out[0] = floor(x)
    elif lx_eq(name, n, "FUP"): out[0] = ceil(x)
    elif lx_eq(name, n, "ROUND"): out[0] = round(x)
    elif lx_eq(name, n, "LN"):
        if x <= 0.0:
            return err_math_domain(st.err, st.unit.file_idx, st.line, fname, x)
        out[0] = log(x)
    elif lx_eq(name, n, "SQRT"):
        if x < 0.0:
            return err_math_domain(st.err, st.unit.file_idx, st.line, fname, x)
        out[0] = sqrt(x)
    else:
        return err_unknown_function(st.err, st.unit.file_idx, st.line, fname, column_of(st, name))
    if not isfinite(out[0]):
        return ex_not_finite(st, name, p)
    pp[0] = p
    return 0


cdef int ngc_value(CState *st, const char **pp, const char *eol, double *out, int depth) noexcept nogil:
    """A real value as LinuxCNC reads one: a number, [expression], #parameter or a
    function, each after any number of signs (a sign binds tighter than **)."""
    cdef const char *p = lx_skip_ws(pp[0], eol)
    cdef const char *q
    cdef int n, r
    if depth > NGC_DEPTH or p >= eol:
        return ex_error(st, pp[0] if p >= eol else p, eol)
    if p[0] == b'[':
        r = ngc_expression(st, &p, eol, out, depth)
    elif p[0] == b'#':
        r = ngc_param_read(st, &p, eol, out, depth)
    elif p[0] == b'-' or p[0] == b'+':
        q = p + 1
        r = ngc_value(st, &q, eol, out, depth + 1)
        if r == 0 and p[0] == b'-':
            out[0] = -out[0]
        p = q
    elif lx_is_alpha(p[0]):
        n = lx_alpha_run(p, eol)
        q = lx_skip_ws(p + n, eol)
        if q >= eol or q[0] != b'[':
            return ex_error(st, p, eol)
        r = ngc_function(st, &p, eol, n, out, depth)
    else:
        q = p
        r = lx_number(&q, eol, out)
        if r == -3:
            return ex_overflow(st, p, q, eol)
        if r != 0:
            return err_bad_number(st.err, st.unit.file_idx, st.line, cword_at(st, p, eol), column_of(st, p))
        p = q
        r = 0
    if r != 0:
        return R_ERR
    pp[0] = p
    return 0


cdef int _operator(const char **pp, const char *eol) noexcept nogil:
    """The binary operator at pp (advanced past it), OP_NONE when none."""
    cdef const char *p = lx_skip_ws(pp[0], eol)
    cdef int n, op = OP_NONE
    if p >= eol:
        return OP_NONE
    if p[0] == b'*':
        if p + 1 < eol and p[1] == b'*':
            pp[0] = p + 2
            return OP_POWER
        op = OP_TIMES
    elif p[0] == b'/': op = OP_DIVIDE
    elif p[0] == b'+': op = OP_PLUS
    elif p[0] == b'-': op = OP_MINUS
    if op != OP_NONE:
        pp[0] = p + 1
        return op
    n = lx_alpha_run(p, eol)
    if lx_eq(p, n, "MOD"): op = OP_MOD
    elif lx_eq(p, n, "EQ"): op = OP_EQ
    elif lx_eq(p, n, "NE"): op = OP_NE
    elif lx_eq(p, n, "GT"): op = OP_GT
    elif lx_eq(p, n, "GE"): op = OP_GE
    elif lx_eq(p, n, "LT"): op = OP_LT
    elif lx_eq(p, n, "LE"): op = OP_LE
    elif lx_eq(p, n, "AND"): op = OP_AND
    elif lx_eq(p, n, "OR"): op = OP_OR
    elif lx_eq(p, n, "XOR"): op = OP_XOR
    if op != OP_NONE:
        pp[0] = p + n
    return op


cdef int _precedence(int op) noexcept nogil:
    """An operator's binding, LinuxCNC's: ** 6, * / MOD 5, + - 4, the comparisons 3, AND OR XOR
    2."""
    if op == OP_POWER: return 6
    if op <= OP_MOD: return 5
    if op <= OP_MINUS: return 4
    if op <= OP_LE: return 3
    return 2


cdef int _apply(CState *st, int op, double *left, double right, const char *at, const char *end) noexcept nogil:
    """left = left op right, as LinuxCNC computes them (EQ / NE within NGC_TOLERANCE_EQUAL, MOD
    never negative); the error of a division by zero, a negative to a fractional power or a
    result that is not finite."""
    cdef double a = left[0]
    if op == OP_POWER:
        if a < 0.0 and right != floor(right):
            return err_math_domain(st.err, st.unit.file_idx, st.line, "**", right)       # LinuxCNC: a negative to a non-integer power
        left[0] = pow(a, right)
    elif op == OP_TIMES: left[0] = a * right
    elif op == OP_DIVIDE:
        if right == 0.0:
            return err_division_by_zero(st.err, st.unit.file_idx, st.line)
        left[0] = a / right
    elif op == OP_MOD:
        if right == 0.0:
            return err_division_by_zero(st.err, st.unit.file_idx, st.line)
        left[0] = fmod(a, right)
        if left[0] < 0.0:                           # LinuxCNC's MOD is never negative
            left[0] += fabs(right)
    elif op == OP_PLUS: left[0] = a + right
    elif op == OP_MINUS: left[0] = a - right
    elif op == OP_EQ: left[0] = 1.0 if fabs(a - right) < NGC_TOLERANCE_EQUAL else 0.0
    elif op == OP_NE: left[0] = 1.0 if fabs(a - right) >= NGC_TOLERANCE_EQUAL else 0.0
    elif op == OP_GT: left[0] = 1.0 if a > right else 0.0
    elif op == OP_GE: left[0] = 1.0 if a >= right else 0.0
    elif op == OP_LT: left[0] = 1.0 if a < right else 0.0
    elif op == OP_LE: left[0] = 1.0 if a <= right else 0.0
    elif op == OP_AND: left[0] = 0.0 if (a == 0.0 or right == 0.0) else 1.0
    elif op == OP_OR: left[0] = 1.0 if (a != 0.0 or right != 0.0) else 0.0
    else: left[0] = 1.0 if ((a == 0.0) != (right == 0.0)) else 0.0
    if not isfinite(left[0]):
        return ex_not_finite(st, at, end)
    return 0


cdef int _binary(CState *st, const char **pp, const char *eol, int min_prec, double *out, int depth) noexcept nogil:
    """Operands and operators of precedence >= min_prec, left to right within a level."""
    cdef const char *start = lx_skip_ws(pp[0], eol)
    cdef const char *p
    cdef int op, prec
    cdef double rhs
    if ngc_value(st, pp, eol, out, depth + 1) != 0:
        return R_ERR
    while True:
        p = pp[0]
        op = _operator(&p, eol)
        if op == OP_NONE:
            return 0
        prec = _precedence(op)
        if prec < min_prec:
            return 0
        pp[0] = p
        if _binary(st, pp, eol, prec + 1, &rhs, depth + 1) != 0:
            return R_ERR
        if _apply(st, op, out, rhs, start, pp[0]) != 0:
            return R_ERR


cdef int ngc_expression(CState *st, const char **pp, const char *eol, double *out, int depth) noexcept nogil:
    """At '[': the expression up to its ']'."""
    cdef const char *open_at = pp[0]
    cdef const char *p = open_at + 1
    if depth > NGC_DEPTH:
        return ex_error(st, open_at, eol)
    if _binary(st, &p, eol, 1, out, depth) != 0:
        return R_ERR
    p = lx_skip_ws(p, eol)
    if p >= eol or p[0] != b']':
        return ex_error(st, p if p < eol else open_at, eol)
    pp[0] = p + 1
    return 0


cdef bint ngc_value_starts(const char *p, const char *eol) noexcept nogil:
    """A word's value at p is LinuxCNC's ([..], #.., a function with [..], after signs);
    otherwise the TG reader reads it (numbers, P parameters, ( ) expressions)."""
    cdef int n
    p = lx_skip_ws(p, eol)
    while p < eol and (p[0] == b'-' or p[0] == b'+'):
        p = lx_skip_ws(p + 1, eol)
    if p >= eol:
        return False
    if p[0] == b'[' or p[0] == b'#':
        return True
    n = lx_alpha_run(p, eol)
    return n > 0 and lx_skip_ws(p + n, eol) < eol and lx_skip_ws(p + n, eol)[0] == b'['


cdef int ngc_word_value(CState *st, const char **pp, const char *eol, double *out) noexcept nogil:
    """The value of an address word in the ISO mode: LinuxCNC's, or TG's (numbers, P
    parameters, ( ) expressions). A number followed by ^ ends there: ^ is LinuxCNC's
    polar angle word, not TG's power."""
    cdef const char *p = pp[0]
    cdef const char *q
    cdef bint neg
    if ngc_value_starts(p, eol):
        return ngc_value(st, pp, eol, out, 0)
    neg = p + 1 < eol and p[0] == b'-'
    q = p + 1 if neg else p
    if q < eol and (lx_is_digit(q[0]) or q[0] == b'.') and lx_number(&q, eol, out) == 0 \
            and lx_skip_ws(q, eol) < eol and lx_skip_ws(q, eol)[0] == b'^':
        if neg:
            out[0] = -out[0]
        pp[0] = q
        return 0
    return ex_value(st, pp, eol, out)


# ------------------------------------------------------------- settings

cdef int ngc_setting_read(CState *st, const char **pp, const char *eol) noexcept nogil:
    """At '#': `#n = value` or `#<name> = value`, kept until the line is read."""
    cdef NgcState *n = st.ngc
    cdef const char *at = pp[0]
    cdef const char *p = lx_skip_ws(at + 1, eol)
    cdef NgcSetting *s
    cdef double v, x
    cdef char address[16]
    if n.n_settings >= NGC_LINE_SETTINGS:
        return err_too_many_words(st.err, st.unit.file_idx, st.line, NGC_LINE_SETTINGS, "#")
    s = &n.settings[n.n_settings]
    s.number = 0
    if p < eol and p[0] == b'<':
        if ngc_name_read(st, &p, eol, s.name, &s.len) != 0:
            return R_ERR
        if s.name[0] == b'_' and (_host_value(s.name, s.len) or ngc_predefined(st, s.name, s.len, &x)):
            return err_ngc_read_only(st.err, st.unit.file_idx, st.line, cword(st, at, eol, <int>(p - at)), column_of(st, at))
    else:
        if ngc_value(st, &p, eol, &v, 1) != 0:
            return R_ERR
        s.number = ngc_index(st, v, at, eol)
        if s.number < 0:
            return R_ERR
        if _computed(s.number):
            return err_ngc_read_only(st.err, st.unit.file_idx, st.line, cword(st, at, eol, <int>(p - at)), column_of(st, at))
    p = lx_skip_ws(p, eol)
    if p >= eol or p[0] != b'=':
        return err_unknown_word(st.err, st.unit.file_idx, st.line, cword_at(st, at, eol), column_of(st, at))
    p += 1
    if ngc_value(st, &p, eol, &s.value, 0) != 0:
        return R_ERR
    if _positional(s.number):
        c_snprintf(address, sizeof(address), "#%d", s.number)
        if number_gate(st, s.value, address) != 0:
            return R_ERR
    n.n_settings += 1
    pp[0] = p
    return 0


cdef int ngc_settings_apply(CState *st) noexcept nogil:
    """The parameter settings of the line just read, in the order written."""
    cdef NgcState *n = st.ngc
    cdef int i
    for i in range(n.n_settings):
        if n.settings[i].number > 0:
            n.params[n.settings[i].number] = n.settings[i].value
        elif ngc_name_set(st, n.settings[i].name, n.settings[i].len, n.settings[i].value) != 0:
            return R_ERR
    n.n_settings = 0
    return 0
