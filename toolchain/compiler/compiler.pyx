# The G-code compiler: runs prefix, main text and postfix line by line (the program
# is interpreted once, loops and calls included) and appends one Part per G/M
# function. Modal G functions and non-signalled M functions change the state only.
from libc.stdlib cimport calloc, free
from libc.string cimport memchr, memcpy, memset, strlen
from libc.stdio cimport snprintf
from libc.math cimport floor


# ------------------------------------------------------------------ words

cdef int cp_text(CState *st, const char *p, const char *eol, LineWords *lw) noexcept nogil:
    """Text of PRINT / M29: "quoted", or the rest of the line without trailing blanks."""
    cdef const char *q
    p = lx_skip_ws(p, eol)
    if p < eol and p[0] == b'"':
        p += 1
        q = p
        while q < eol and q[0] != b'"':
            q += 1
    else:
        q = eol
        while q > p and ((q - 1)[0] == b' ' or (q - 1)[0] == b'\t' or (q - 1)[0] == b'\r'):
            q -= 1
    lw.text = p
    lw.text_len = <int>(q - p)
    lw.has_text = True
    return 0


cdef bint _value_starts(const char *q, const char *eol) noexcept nogil:
    """A word's value may start at q: a number, a sign, a bracket, a parameter or function."""
    return q < eol and (lx_is_digit(q[0]) or q[0] == b'.' or q[0] == b'-' or q[0] == b'+'
                        or q[0] == b'(' or lx_is_alpha(q[0]))


cdef bint _o_word_keyword(const char *p, int n) noexcept nogil:
    return (lx_eq(p, n, "SUB") or lx_eq(p, n, "ENDSUB") or lx_eq(p, n, "CALL") or lx_eq(p, n, "RETURN")
            or lx_eq(p, n, "DO") or lx_eq(p, n, "WHILE") or lx_eq(p, n, "ENDWHILE") or lx_eq(p, n, "IF")
            or lx_eq(p, n, "ELSEIF") or lx_eq(p, n, "ELSE") or lx_eq(p, n, "ENDIF") or lx_eq(p, n, "REPEAT")
            or lx_eq(p, n, "ENDREPEAT") or lx_eq(p, n, "BREAK") or lx_eq(p, n, "CONTINUE"))


cdef int cp_bad_word(CState *st, const char *p, const char *eol, int col, const LineWords *lw) noexcept nogil:
    """A word the dialect does not know: says what TG expects where the word is
    another dialect's (LinuxCNC O-words and # parameters, [ ] expressions)."""
    cdef int n = lx_ident_run(p, eol)
    if p[0] == b'#':
        return cerr_hint(st, ERR_NOT_TG, cword_at(st, p, eol), col,
                         "TG parameters are P00..P99 (P1 = value, X P1)")
    if p[0] == b'[':
        return cerr_hint(st, ERR_NOT_TG, cword_at(st, p, eol), col,
                         "TG expressions are written in ( ) brackets: X (P1 * 2)")
    if lw.first_is_o and n > 0 and _o_word_keyword(p, n):
        return cerr_hint(st, ERR_NOT_TG, cword(st, p, eol, n), col,
                         "O-word subroutines and loops are LinuxCNC G-code; TG uses labels "
                         "(name:) with CALL / RETURN, and FOR / WHILE / IF ... END")
    return cerr_at(st, ERR_UNKNOWN_WORD, cword_at(st, p, eol), col)


cdef int cp_words(CState *st, const char *p, const char *eol, LineWords *lw) noexcept nogil:
    """Reads the address words of a line into lw (values evaluated)."""
    cdef int status, n, idx, L, col, digits
    cdef const char *q
    cdef const char *w
    cdef double v
    cdef bint jump_g = False, first = True
    cdef char letter[2]
    lw.mask = 0
    lw.ng = 0
    lw.nm = 0
    lw.has_ff = False
    lw.has_fp = False
    lw.has_text = False
    lw.label = NULL
    lw.label_len = 0
    lw.has_pword = False
    lw.first_is_o = False
    while True:
        w = p
        p = lx_skip_gap(p, eol, &status)
        if status:
            return cerr_open_comment(st, w, eol)
        if p >= eol:
            return 0
        w = p
        col = column_of(st, p)
        if not lx_is_alpha(p[0]):
            return cp_bad_word(st, p, eol, col, lw)
        n = lx_alpha_run(p, eol)
        if n >= 2:
            if lx_eq(p, n, "REM"):
                return 0
            if jump_g and lx_ident_run(p, eol) > 0:
                # G25 / G26 / G27 followed by a label name
                lw.label = p
                lw.label_len = lx_ident_run(p, eol)
                p += lw.label_len
                continue
            if (n == 2 or lx_is_digit(p[2]) or p[2] == b'.') and lx_upper(p[0]) == b'F' \
                    and (lx_upper(p[1]) == b'F' or lx_upper(p[1]) == b'P'):
                q = lx_skip_ws(p + 2, eol)
                if ex_value(st, &q, eol, &v) != 0:
                    return R_ERR
                if lx_upper(p[1]) == b'F':
                    lw.has_ff = True
                    lw.ff = v
                else:
                    lw.has_fp = True
                    lw.fp = v
                p = q
                first = False
                continue
            return cp_bad_word(st, p, eol, col, lw)
        L = <int>lx_upper(p[0])
        p += 1
        if L == 80:     # 'P': parameter assignment Pnn = expression
            digits = 0
            while p + digits < eol and lx_is_digit(p[digits]):
                digits += 1
            q = lx_skip_ws(p + digits, eol)
            if digits > 0 and q < eol and q[0] == b'=' and not (q + 1 < eol and q[1] == b'='):
                idx = ex_param_index(st, &p, eol)
                if idx < 0:
                    return R_ERR
                p = lx_skip_ws(p, eol) + 1
                if ex_sum(st, &p, eol, &st.P[idx], 0) != 0:
                    return R_ERR
                first = False
                continue
            # a P word with a value (ISO: dwell seconds, G64 tolerance, an M function's
            # argument): cp_block decides, after the G functions of the line
            q = lx_skip_ws(p, eol)
            if not _value_starts(q, eol):
                return cerr_hint(st, ERR_P_WORD, cword_at(st, w, eol), col,
                                 "an assignment is written Pnn = value")
            if ex_value(st, &q, eol, &v) != 0:
                return R_ERR
            lw.has_pword = True
            lw.pword = v
            lw.pword_at = w
            lw.pword_len = <int>(q - w)
            lw.col[15] = col
            p = q
            first = False
            continue
        q = lx_skip_ws(p, eol)
        if L == 76 and q < eol and (lx_is_alpha(q[0]) or q[0] == b'_') \
                and not ((q[0] == b'P' or q[0] == b'p') and q + 1 < eol and lx_is_digit(q[1])):
            n = lx_ident_run(q, eol)
            if lx_skip_ws(q + n, eol) >= eol or lx_skip_ws(q + n, eol)[0] != b'(':
                lw.label = q          # L name: a label target
                lw.label_len = n
                p = q + n
                first = False
                continue
        if L == 79 and q < eol and q[0] == b'<':
            return cerr_hint(st, ERR_NOT_TG, cword_at(st, w, eol), col,
                             "O-word subroutines are LinuxCNC G-code; TG uses labels (name:) with CALL")
        if q < eol and q[0] == b'[':
            return cp_bad_word(st, q, eol, column_of(st, q), lw)
        if not _value_starts(q, eol):
            letter[0] = <char>L
            letter[1] = 0
            return cerr_at(st, ERR_MISSING_VALUE, letter, col)
        if ex_value(st, &q, eol, &v) != 0:
            return R_ERR
        if not (v >= -TC_MAX_WORD_VALUE and v <= TC_MAX_WORD_VALUE) and L != 71 and L != 77 and L != 76:
            letter[0] = <char>L
            letter[1] = 0
            return _bad_value(st, v, letter)
        p = q
        if L == 71:     # G
            if lw.ng >= MAX_WORD_LIST:
                return _too_many(st, "G")
            lw.g[lw.ng] = v
            lw.gcol[lw.ng] = col
            lw.ng += 1
            if v == 29.0:
                return 0        # G29: the rest of the line is a comment
            if v == 25.0 or v == 26.0 or v == 27.0:
                jump_g = True
        elif L == 77:   # M
            if lw.nm >= MAX_WORD_LIST:
                return _too_many(st, "M")
            lw.m[lw.nm] = v
            lw.mcol[lw.nm] = col
            lw.nm += 1
            if st.params.M29_print != 0 and v == st.params.M29_print:
                return cp_text(st, p, eol, lw)
        else:
            lw.v[L - 65] = v
            lw.mask |= 1u << (L - 65)
            lw.col[L - 65] = col
            if first and L == 79:
                lw.first_is_o = True
        first = False


cdef int _too_many(CState *st, const char *what) noexcept nogil:
    cdef ErrArg a[2]
    a[0].num = MAX_WORD_LIST; a[0].text = NULL
    a[1].num = 0; a[1].text = what
    set_error(st.err, ERR_TOO_MANY_WORDS, st.unit.file_idx, st.line, a, 2)
    return R_ERR


# ------------------------------------------------------------- G functions

cdef inline uint32_t bit_of(char c) noexcept nogil:
    return 1u << (<int>c - 65)


cdef uint32_t axes_mask() noexcept nogil:
    return (bit_of(b'X') | bit_of(b'Y') | bit_of(b'Z') | bit_of(b'C') | bit_of(b'B') | bit_of(b'U')
            | bit_of(b'V') | bit_of(b'W') | bit_of(b'A') | bit_of(b'O'))


cdef void cp_reframe(CState *st) noexcept nogil:
    """After a change of zero offset, mirroring or rotation the machine stays where
    it is: its program coordinates are recomputed."""
    update_identity(st)
    to_program(st, st.mpos, st.ppos)


cdef int cp_zero(CState *st, const LineWords *lw, int g) noexcept nogil:
    """G53 off, G54..G57 set (absent axes 0), G59 set (absent axes kept)."""
    cdef int a, bit
    for a in range(AXES):
        bit = <int>letter_of_axis(a) - 65
        if g == 53:
            st.zero[a] = 0.0
        elif (lw.mask >> bit) & 1:
            st.zero[a] = lw.v[bit]
        elif g != 59:
            st.zero[a] = 0.0
    cp_reframe(st)
    if not update_zero(st):
        return cerr(st, ERR_OUT_OF_MEMORY)
    return 0


cdef int cp_g92(CState *st, const LineWords *lw) noexcept nogil:
    """G92 / G98: the current point gets the given program coordinates (shift)."""
    cdef int a, bit
    cdef double t[AXES]
    for a in range(AXES):
        bit = <int>letter_of_axis(a) - 65
        if (lw.mask >> bit) & 1:
            st.ppos[a] = lw.v[bit]
            # a shift taken where the machine follows the start follows it too
            st.shift_follows[a] = not st.fixed[a]
    to_machine(st, st.ppos, t)
    for a in range(AXES):
        st.shift[a] += st.mpos[a] - t[a]
    if not update_zero(st):
        return cerr(st, ERR_OUT_OF_MEMORY)
    return 0


cdef int cp_g168(CState *st, const LineWords *lw) noexcept nogil:
    """Rotation by R degrees about (X Y Z), axis IJK or the normal of plane Q."""
    cdef double ax = 0.0, ay = 0.0, az = 1.0
    cdef int plane = st.plane
    if has(lw, b'I') or has(lw, b'J') or has(lw, b'K'):
        ax = val(lw, b'I') if has(lw, b'I') else 0.0
        ay = val(lw, b'J') if has(lw, b'J') else 0.0
        az = val(lw, b'K') if has(lw, b'K') else 0.0
    else:
        if has(lw, b'Q'):
            plane = to_int(val(lw, b'Q'))
        if plane == 17:
            ax = 0.0; ay = 0.0; az = 1.0
        elif plane == 18:
            ax = 0.0; ay = -1.0; az = 0.0
        elif plane == 19:
            ax = 1.0; ay = 0.0; az = 0.0
        elif plane == -18:
            ax = 0.0; ay = 1.0; az = 0.0
        else:
            return cerr_num(st, ERR_BAD_PLANE, plane)
    if not set_rotation(st, val(lw, b'X') if has(lw, b'X') else 0.0, val(lw, b'Y') if has(lw, b'Y') else 0.0,
                        val(lw, b'Z') if has(lw, b'Z') else 0.0, ax, ay, az,
                        val(lw, b'R') if has(lw, b'R') else 0.0):
        return cerr(st, ERR_OUT_OF_MEMORY)
    cp_reframe(st)
    return 0


cdef void _feed_set(CState *st, const LineWords *lw, int k) noexcept nogil:
    if has(lw, b'F'): st.params.motion[k].feed = val(lw, b'F')
    if has(lw, b'C'): st.params.motion[k].acc = val(lw, b'C')
    if has(lw, b'D'): st.params.motion[k].dec = val(lw, b'D')
    if has(lw, b'R'): st.params.motion[k].rampType = to_int(val(lw, b'R'))


cdef uint32_t _axis_flags(const LineWords *lw) noexcept nogil:
    cdef uint32_t m = 0
    cdef int a, bit
    for a in range(AXES):
        bit = <int>letter_of_axis(a) - 65
        if (lw.mask >> bit) & 1 and lw.v[bit] != 0.0:
            m |= 1u << a
    return m


cdef int cp_g900(CState *st, const LineWords *lw, int col) noexcept nogil:
    """G900 S..: changes the working copy of GCODE_PARAMETERS (col: the G900's column)."""
    cdef int s, a
    cdef double sv
    if not has(lw, b'S'):
        return cerr_at(st, ERR_MISSING_VALUE, "S", col)
    sv = val(lw, b'S')
    s = to_int(sv)
    if s == 1:
        if st.n_pstack >= PARAM_STACK_DEPTH:
            return cerr_text(st, ERR_PARAM_STACK, "overflow")
        st.pstack[st.n_pstack] = st.params
        st.n_pstack += 1
    elif s == 2:
        if st.n_pstack == 0:
            return cerr_text(st, ERR_PARAM_STACK, "empty")
        st.n_pstack -= 1
        st.params = st.pstack[st.n_pstack]
    elif s == 7:
        a = to_int(val(lw, b'A')) if has(lw, b'A') else -1
        if a < 0 or a > 9:
            return _bad_value(st, val(lw, b'A') if has(lw, b'A') else -1.0, "A")
        if has(lw, b'F'): st.params.axisLimits[a].maxFeed = val(lw, b'F')
        if has(lw, b'C'): st.params.axisLimits[a].maxAcc = val(lw, b'C')
        if has(lw, b'D'): st.params.axisLimits[a].maxDec = val(lw, b'D')
    elif s == 9:
        if has(lw, b'A'): st.params.startAngle = val(lw, b'A')
        if has(lw, b'B'): st.params.endAngle = val(lw, b'B')
        if has(lw, b'F'): st.params.minAngleFeed = val(lw, b'F')
    elif s == 10:
        st.g900_ignore_angle = _axis_flags(lw)
    elif s == 11:
        st.g900_ignore_feed = _axis_flags(lw)
    elif s == 12:
        st.g900_stop_mode = to_int(val(lw, b'A')) if has(lw, b'A') else 0
    elif s == 13:
        st.g900_arc_table = to_int(val(lw, b'A')) if has(lw, b'A') else 0
    elif s == 20: _feed_set(st, lw, 0)
    elif s == 30: _feed_set(st, lw, 1)
    elif s == 31: _feed_set(st, lw, 4)
    elif s == 32: _feed_set(st, lw, 2)
    elif s == 41: _feed_set(st, lw, 3)
    elif s == 50: _feed_set(st, lw, 5)
    elif s == 60:
        if has(lw, b'D'): st.params.motion[6].dec = val(lw, b'D')
    elif s == 70:
        if has(lw, b'D'): st.params.motion[7].dec = val(lw, b'D')
    else:
        return _bad_value(st, sv, "S")
    return 0


cdef bint cp_plan_region(CState *st) noexcept nogil:
    """The planning settings from the next part on (G900, M-5), for the planner."""
    return program_add_plan_region(st.build, st.prog.n_parts, &st.params, st.g900_ignore_angle,
                                   st.g900_ignore_feed, st.limits_off, st.g900_stop_mode, st.g900_arc_table)


cdef int _bad_value(CState *st, double v, const char *letter) noexcept nogil:
    cdef ErrArg a[2]
    a[0].num = v; a[0].text = NULL
    a[1].num = 0; a[1].text = letter
    set_error(st.err, ERR_BAD_VALUE, st.unit.file_idx, st.line, a, 2)
    return R_ERR


cdef void cp_comp(CState *st, int g) noexcept nogil:
    """G40 off; G41..G48: side 41/42 (a negative radius swaps it), slot 0..7."""
    cdef int slot, side
    if g == 40:
        st.comp = 40
        st.comp_slot = 0
        return
    slot = g - 41
    side = 41 if (slot & 1) == 0 else 42
    if st.params.correction[slot].size < 0.0:
        side = 83 - side
    st.comp = side
    st.comp_slot = slot


# ------------------------------------------------------------- one block

cdef bint _is_m(const GCODE_PARAMETERS *pr, int m, int32_t number) noexcept nogil:
    return number != 0 and m == number


cdef int cp_g167(CState *st, const LineWords *lw) noexcept nogil:
    """G167 [E] [A] [U] [Q]: automatic arcs on with these values (E/A default to the
    host's tolerances, U to 90 degrees, Q to insertArcPlane); bare G167: off. Recorded
    in Program.arc_regions from the next part on (compensation/insert_arcs.pyx)."""
    cdef int ga, gb, gc
    cdef uint32_t letters = bit_of(b'E') | bit_of(b'A') | bit_of(b'U') | bit_of(b'Q')
    st.g167_on = (lw.mask & letters) != 0
    st.g167[0] = val(lw, b'E') if has(lw, b'E') else st.params.insertArcToleranceRMax
    st.g167[1] = val(lw, b'A') if has(lw, b'A') else st.params.insertArcToleranceRMin
    st.g167[2] = val(lw, b'U') if has(lw, b'U') else 90.0
    st.g167[3] = val(lw, b'Q') if has(lw, b'Q') else <double>st.params.insertArcPlane
    if has(lw, b'Q') and not (to_int(st.g167[3]) == 0 or plane_axes(to_int(st.g167[3]), &ga, &gb, &gc)):
        return cerr_num(st, ERR_BAD_PLANE, st.g167[3])
    if not program_add_arc_region(st.build, st.prog.n_parts, st.g167_on, to_int(st.g167[3]),
                                  st.g167[0], st.g167[1], st.g167[2]):
        return cerr(st, ERR_OUT_OF_MEMORY)
    return 0


# ------------------------------------------------- other dialects (ISO, LinuxCNC)

cdef const char *iso_g_hint(double gv) noexcept nogil:
    """What TG expects instead of an ISO G function it does not have; NULL: no ISO meaning."""
    if gv == 20.0:
        return "TG works in millimetres (isoCompat reads G20 as inches)"
    if gv == 28.0 or gv == 30.0:
        return "returns to a home position do not exist in TG (G98 is TG's reference run)"
    if gv == 49.0 or gv == 43.1:
        return "TG has no tool length offsets (isoCompat ignores G43 H and G49)"
    if gv == 61.0 or gv == 61.1 or gv == 64.0:
        return "path blending is set by GCODE_PARAMETERS (isoCompat ignores G61 and G64)"
    if gv == 80.0:
        return "TG has no canned cycles (isoCompat ignores G80)"
    if gv == 73.0 or gv == 76.0 or (gv >= 81.0 and gv <= 89.0 and gv == <double>(<int>gv)):
        return "TG has no canned drilling cycles: write the moves (G0 / G1)"
    if gv == 90.1:
        return "TG's arc centres are relative; Q70 on the arc's line makes I J K absolute"
    if gv == 91.1:
        return "TG's arc centres are relative already (isoCompat ignores G91.1)"
    if gv == 92.1 or gv == 92.2:
        return "TG resets a G92 shift with G92 and the axes (isoCompat: G92.1 clears the shift)"
    if gv == 10.0:
        return "TG sets zero offsets with G54..G59 and the axes"
    if gv >= 38.2 and gv <= 38.5:
        return "TG has no probing moves"
    if gv == 93.0:
        return "TG has no inverse time feed (G94 mm/min, G95 mm/rev)"
    return NULL


cdef int cp_unknown_g(CState *st, double gv, int col) noexcept nogil:
    cdef const char *hint = iso_g_hint(gv)
    cdef ErrArg a[3]
    if hint == NULL:
        return cerr_num_at(st, ERR_BAD_G, gv, col)
    a[0].num = gv; a[0].text = NULL
    a[1].num = col; a[1].text = NULL
    a[2].num = 0; a[2].text = hint
    set_error(st.err, ERR_ISO_G, st.unit.file_idx, st.line, a, 3)
    return R_ERR


cdef const char *word_at_column(CState *st, int col) noexcept nogil:
    """The source word at column col of the current line, for messages."""
    return cword_at(st, st.unit.text + st.cur_pos + col - 1, st.unit.text + st.next_pos - 1)


cdef void iso_units(CState *st, LineWords *lw) noexcept nogil:
    """ISO mode: G20 / G21 of the line switch inches / millimetres; in inches the
    lengths of the line (X Y Z U V W, I J K, R, F, FF) are converted to mm. Not on G4
    (times), G900 (parameters), nor G168's R (degrees)."""
    cdef int i, bit
    cdef bint rotation = False
    cdef uint32_t letters, bits
    for i in range(lw.ng):
        if lw.g[i] == 20.0:
            st.unit_scale = 25.4
        elif lw.g[i] == 21.0:
            st.unit_scale = 1.0
    if st.unit_scale == 1.0:
        return
    for i in range(lw.ng):
        if lw.g[i] == 4.0 or lw.g[i] == 900.0:
            return
        if lw.g[i] == 168.0:
            rotation = True
    letters = (bit_of(b'X') | bit_of(b'Y') | bit_of(b'Z') | bit_of(b'U') | bit_of(b'V') | bit_of(b'W')
               | bit_of(b'I') | bit_of(b'J') | bit_of(b'K') | bit_of(b'F'))
    if not rotation:
        letters |= bit_of(b'R')
    bits = lw.mask & letters
    while bits:
        bit = SF_CTZ(bits)
        bits &= bits - 1
        lw.v[bit] *= st.unit_scale
    if lw.has_ff:
        lw.ff *= st.unit_scale


cdef int cp_iso_g(CState *st, const LineWords *lw, int i) noexcept nogil:
    """ISO mode: G function i of the line read as ISO G-code. 1 done, 0 TG's meaning,
    R_ERR (error recorded)."""
    cdef double gv = lw.g[i]
    cdef int col = lw.gcol[i], a
    if gv == 20.0 or gv == 21.0 or gv == 91.1:
        return 1                    # units: iso_units; relative centres: TG's own
    if gv == 18.0:
        st.plane = -18              # ISO's G18 is the ZX plane
        return 1
    if gv == 43.0 or gv == 44.0 or gv == 49.0 or gv == 61.0 or gv == 61.1 or gv == 64.0 or gv == 80.0:
        cwarn_at(st, WARN_ISO_IGNORED, word_at_column(st, col), col)
        return 1
    if gv == 92.1:
        for a in range(AXES):
            st.shift[a] = 0.0
        cp_reframe(st)
        if not update_zero(st):
            return cerr(st, ERR_OUT_OF_MEMORY)
        return 1
    if gv == 53.0 or (gv >= 54.0 and gv <= 59.0 and gv == <double>(<int>gv)):
        return 1                    # no table of offsets: the offset stays and the axes move
    return 0


cdef int cp_pword(CState *st, LineWords *lw, bint dwell) noexcept nogil:
    """A P word without '=': in ISO mode dwell seconds (given to the part as H), G64's
    tolerance, or an M function's argument ignored with a warning; else an error that
    says what TG expects."""
    cdef int i
    cdef const char *hint
    cdef const char *word
    if st.iso:
        if dwell:
            if not (lw.mask & (bit_of(b'W') | bit_of(b'H') | bit_of(b'X') | bit_of(b'T'))):
                lw.v[7] = lw.pword          # TG's H seconds: the driver sees a G4 it knows
                lw.mask |= bit_of(b'H')
                lw.col[7] = lw.col[15]
            return 0
        for i in range(lw.ng):
            if lw.g[i] == 64.0:
                return 0            # ignored with its G64 (warned)
        if lw.nm > 0:
            word = cword(st, lw.pword_at, lw.pword_at + lw.pword_len, lw.pword_len)
            cwarn_at(st, WARN_ISO_IGNORED, word, lw.col[15])
            return 0
    if dwell:
        hint = "G4 takes W (milliseconds), H, X or T (seconds)"
    elif lw.nm > 0:
        hint = "M functions take no P word (isoCompat ignores it)"
    else:
        hint = "a P word without '=' is ISO G-code (isoCompat reads G4 P and G64 P)"
    word = cword(st, lw.pword_at, lw.pword_at + lw.pword_len, lw.pword_len)
    return cerr_hint(st, ERR_P_WORD, word, lw.col[15], hint)


cdef void cp_dialect_warnings(CState *st, const LineWords *lw, int motion, int zero_g,
                              int zero_col) noexcept nogil:
    """Default mode: warnings where the line looks written for ISO G-code and TG reads
    it otherwise (docs/compiler.md)."""
    cdef int arc = motion if motion >= 0 else st.motion
    cdef int col
    cdef ErrArg a[2]
    if lw.first_is_o and st.prog.n_parts == 0:
        a[0].num = val(lw, b'O'); a[0].text = NULL
        a[1].num = lw.col[14]; a[1].text = NULL
        cwarn(st, WARN_O_AT_START, a, 2)
    if zero_g != 0 and motion >= 0 and (lw.mask & axes_mask()):
        a[0].num = zero_g; a[0].text = NULL
        a[1].num = zero_col; a[1].text = NULL
        cwarn(st, WARN_ZERO_WITH_MOVE, a, 2)
    if st.plane == 18 and (arc == 2 or arc == 3) and (has(lw, b'I') or has(lw, b'K')) \
            and st.iso_header and not st.warned_g18:
        st.warned_g18 = True
        col = lw.col[8] if has(lw, b'I') else lw.col[10]
        a[0].num = col; a[0].text = NULL
        cwarn(st, WARN_G18_ARC, a, 1)


cdef int cp_block(CState *st, LineWords *lw) noexcept nogil:
    """Executes the words of one line: G settings, modal values, continuous M,
    motion or dwell, then the other M functions and the flow words."""
    cdef int i, k, g, m, r, motion = -1, jump = 0, jump_col = 0, zero_g = 0, zero_col = 0
    cdef bint dwell = False, g9x = False, end = False, ret = False, g900 = False, g168 = False
    cdef uint32_t consumed = 0, saved
    cdef uint32_t axes = axes_mask()
    cdef const GCODE_PARAMETERS *pr = &st.params
    cdef double gv
    cdef int32_t iv
    cdef int addr
    # consumed letters of M functions with addresses of their own
    for i in range(lw.nm):
        m = to_int(lw.m[i])
        if m == -5 or _is_m(pr, m, pr.M06_changeTool):
            consumed |= axes
        elif m == -6:
            consumed |= bit_of(b'A') | bit_of(b'S')
        elif _is_m(pr, m, pr.M99_defFeed):
            consumed |= bit_of(b'F')
    if st.iso:
        iso_units(st, lw)
        if lw.first_is_o:
            lw.mask &= ~bit_of(b'O')        # a program number
    # G functions, in the order written
    for i in range(lw.ng):
        gv = lw.g[i]
        g = to_int(gv)
        if st.iso:
            r = cp_iso_g(st, lw, i)
            if r < 0:
                return R_ERR
            if r > 0:
                continue
        if gv != <double>g:
            return cp_unknown_g(st, gv, lw.gcol[i])
        if g == 0 or g == 1 or g == 2 or g == 3 or g == 33:
            motion = g
            st.motion = g
            if g == 33:
                consumed |= bit_of(b'K') | bit_of(b'F')
        elif g == 4:
            dwell = True
            consumed |= bit_of(b'W') | bit_of(b'H') | bit_of(b'X') | bit_of(b'T')
        elif g == 17 or g == 18 or g == 19 or g == -18:
            st.plane = g
        elif g == 21 or g == 29:
            st.iso_header = st.iso_header or g == 21
        elif g == 24:
            st.lathe_radius = True
        elif g == 25 or g == 26 or g == 27:
            jump = g
            jump_col = lw.gcol[i]
            consumed |= bit_of(b'L') | bit_of(b'H')
        elif g >= 40 and g <= 48:
            if g == 43 and has(lw, b'H'):     # (the ISO mode took G43 above)
                cwarn_num_col(st, WARN_G43_H, lw.gcol[i])
            cp_comp(st, g)
        elif g == 53 or (g >= 54 and g <= 57) or g == 59:
            consumed |= axes
            if g != 53:
                zero_g = g
                zero_col = lw.gcol[i]
            if cp_zero(st, lw, g) != 0:
                return R_ERR
        elif g == 90 or g == 91:
            st.absolute = g == 90
            st.iso_header = st.iso_header or (g == 90 and st.prog.n_parts == 0)
            g9x = True
        elif g == 92 or g == 98:
            consumed |= axes
            if cp_g92(st, lw) != 0:
                return R_ERR
        elif g == 94 or g == 95:
            st.per_min = g == 94
        elif g == 96 or g == 97:
            st.css = g == 96
        elif g == 167:
            consumed |= bit_of(b'E') | bit_of(b'A') | bit_of(b'U') | bit_of(b'Q')
            if cp_g167(st, lw) != 0:
                return R_ERR
        elif g == 168:
            consumed |= (bit_of(b'X') | bit_of(b'Y') | bit_of(b'Z') | bit_of(b'I') | bit_of(b'J')
                         | bit_of(b'K') | bit_of(b'R') | bit_of(b'Q'))
            g168 = True
            if cp_g168(st, lw) != 0:
                return R_ERR
        elif g == 169:
            st.rot_on = False
            st.rot_idx = 0
            cp_reframe(st)
        elif g == 172 or g == 173:
            consumed |= bit_of(b'R') | bit_of(b'C') | bit_of(b'D')
            if not program_add_strategy_region(st.build, st.prog.n_parts, g == 172,
                                               val(lw, b'R') if has(lw, b'R') else 0.0,
                                               val(lw, b'C') if has(lw, b'C') else 0.0,
                                               has(lw, b'D') and val(lw, b'D') != 0.0):
                return cerr(st, ERR_OUT_OF_MEMORY)
        elif g == 900:
            g900 = True
            consumed = ~(<uint32_t>0)
            if cp_g900(st, lw, lw.gcol[i]) != 0:
                return R_ERR
            if not cp_plan_region(st):
                return cerr(st, ERR_OUT_OF_MEMORY)
        else:
            return cp_unknown_g(st, gv, lw.gcol[i])
    if lw.has_pword and cp_pword(st, lw, dwell) != 0:
        return R_ERR
    if not st.iso:
        cp_dialect_warnings(st, lw, motion, zero_g, zero_col)
    # modal values
    if not (consumed & bit_of(b'F')) and has(lw, b'F'):
        st.feed = val(lw, b'F')
    if not (consumed & bit_of(b'S')) and has(lw, b'S'):
        st.spindle = <float>val(lw, b'S')
    if not (consumed & bit_of(b'T')) and has(lw, b'T'):
        st.tool = to_int(val(lw, b'T'))
    if lw.has_fp and pr.forceMode != 1:
        st.fp = lw.fp
    if lw.has_ff:
        st.ff = lw.ff
        st.ff_set = True
    # continuous M functions go before the motion of their line
    for i in range(lw.nm):
        m = to_int(lw.m[i])
        if lw.m[i] != <double>m or m == 1000 or m < -6 or m > 1000000000 or (m < 0 and m != -5 and m != -6):
            return cerr_num_at(st, ERR_BAD_M, lw.m[i], lw.mcol[i])
        if m >= 1001:
            if em_mfunc(st, lw, m, True) != 0:
                return R_ERR
    # motion / dwell
    if dwell:
        if em_dwell(st, lw) != 0:
            return R_ERR
    elif not g900:
        if motion < 0:
            motion = 1 if (g9x and (lw.mask & axes & ~consumed)) else st.motion
        saved = lw.mask
        # words a G/M function of this line used are not axis moves (G168 also takes I J K R)
        lw.mask &= ~(consumed & axes)
        if g168:
            lw.mask &= ~(bit_of(b'I') | bit_of(b'J') | bit_of(b'K') | bit_of(b'R'))
        r = em_motion(st, lw, motion)
        lw.mask = saved
        if r != 0:
            return R_ERR
    # the other M functions, in the order written
    for i in range(lw.nm):
        m = to_int(lw.m[i])
        if m >= 1001:
            continue
        if m == -5:
            # per written axis: 0 switches its limits off, anything else on again
            for k in range(AXES):
                if has(lw, letter_of_axis(k)):
                    if val(lw, letter_of_axis(k)) == 0.0:
                        st.limits_off |= 1u << k
                    else:
                        st.limits_off &= ~(1u << k)
            if not cp_plan_region(st):
                return cerr(st, ERR_OUT_OF_MEMORY)
        elif m == -6:
            if has(lw, b'A'):
                addr = ex_plc_addr(st, val(lw, b'A'), 4)
                if addr < 0:
                    return R_ERR
                iv = st.gindex
                memcpy(st.inp.plc + addr, &iv, 4)
            if has(lw, b'S'):
                st.gindex = to_int(val(lw, b'S'))
                if st.gindex > 0x40000000:          # leave room: the index is an int32
                    st.gindex = 0x40000000
                elif st.gindex < -0x40000000:
                    st.gindex = -0x40000000
                st.gindex += st.gindex & 1
        elif _is_m(pr, m, pr.M29_print):
            if em_print(st, lw, m, lw.text, lw.text_len) != 0:
                return R_ERR
        elif _is_m(pr, m, pr.M17_return):
            ret = True
        elif _is_m(pr, m, pr.M80_mirrorOff):
            st.mirror = 0; cp_reframe(st)
        elif _is_m(pr, m, pr.M81_mirrorX):
            st.mirror = 1; cp_reframe(st)
        elif _is_m(pr, m, pr.M82_mirrorY):
            st.mirror = 2; cp_reframe(st)
        elif _is_m(pr, m, pr.M83_mirrorZ):
            st.mirror = 4; cp_reframe(st)
        elif _is_m(pr, m, pr.M84_mirrorXY):
            st.mirror = 3; cp_reframe(st)
        elif _is_m(pr, m, pr.M85_mirrorXZ):
            st.mirror = 5; cp_reframe(st)
        elif _is_m(pr, m, pr.M86_mirrorYZ):
            st.mirror = 6; cp_reframe(st)
        elif _is_m(pr, m, pr.M87_mirrorXYZ):
            st.mirror = 7; cp_reframe(st)
        elif _is_m(pr, m, pr.M99_defFeed):
            if has(lw, b'F'):
                st.def_feed = val(lw, b'F')
        else:
            if em_mfunc(st, lw, m, False) != 0:
                return R_ERR
            if _is_m(pr, m, pr.M02_programEnd1) or _is_m(pr, m, pr.M30_programEnd2):
                end = True
    if end:
        return R_END
    if jump:
        if lw.label != NULL:
            r = fl_call(st, lw.label, lw.label_len, 0, False, jump != 27,
                        to_int(val(lw, b'H')) if (jump == 26 and has(lw, b'H')) else 1)
        elif has(lw, b'L'):
            r = fl_call(st, NULL, 0, val(lw, b'L'), True, jump != 27,
                        to_int(val(lw, b'H')) if (jump == 26 and has(lw, b'H')) else 1)
        else:
            return cerr_at(st, ERR_MISSING_VALUE, "L", jump_col)
        return r
    if ret:
        return fl_return(st)
    return R_NEXT


cdef int cp_line(CState *st, const char *p, const char *eol) noexcept nogil:
    """One line: blank, '%', label, a flow statement, or address words."""
    cdef int n, a
    cdef const char *q
    p = lx_skip_ws(p, eol)
    if p >= eol or p[0] == b'%':
        return R_NEXT
    n = lx_ident_run(p, eol)
    if n > 0:
        q = lx_skip_ws(p + n, eol)
        if q < eol and q[0] == b':':
            if fl_rest_of_line(st, q + 1, eol) != 0:
                return R_ERR
            return R_NEXT
        a = lx_alpha_run(p, eol)
        if a >= 2:
            q = p + a
            if lx_eq(p, a, "IF"):
                return fl_if(st, q, eol)
            if lx_eq(p, a, "FOR"):
                return fl_for(st, q, eol)
            if lx_eq(p, a, "WHILE"):
                return fl_while(st, q, eol)
            if lx_eq(p, a, "END") or lx_eq(p, a, "ENDIF") or lx_eq(p, a, "ENDFOR") or lx_eq(p, a, "ENDWHILE"):
                q = lx_skip_ws(q, eol)
                n = lx_alpha_run(q, eol)
                if lx_eq(q, n, "IF") or lx_eq(q, n, "FOR") or lx_eq(q, n, "WHILE"):
                    q += n
                if fl_rest_of_line(st, q, eol) != 0:
                    return R_ERR
                return fl_end(st)
            if lx_eq(p, a, "ELSE"):
                if fl_rest_of_line(st, q, eol) != 0:
                    return R_ERR
                return fl_else(st)
            if lx_eq(p, a, "CALL") or lx_eq(p, a, "GOTO"):
                return fl_call_stmt(st, q, eol, lx_eq(p, a, "CALL"))
            if lx_eq(p, a, "RETURN"):
                if fl_rest_of_line(st, q, eol) != 0:
                    return R_ERR
                return fl_return(st)
            if lx_eq(p, a, "BREAK") or lx_eq(p, a, "CONTINUE"):
                if fl_rest_of_line(st, q, eol) != 0:
                    return R_ERR
                return fl_break(st, lx_eq(p, a, "CONTINUE"))
            if lx_eq(p, a, "REM"):
                return R_NEXT
            if lx_eq(p, a, "PRINT"):
                cp_text(st, q, eol, &st.lw)
                st.lw.mask = 0
                return em_print(st, &st.lw, st.params.M29_print if st.params.M29_print != 0 else 29,
                                st.lw.text, st.lw.text_len)
    if cp_words(st, p, eol, &st.lw) != 0:
        return R_ERR
    return cp_block(st, &st.lw)


# ------------------------------------------------------------- the run loop

cdef uint32_t count_lines(const char *text, size_t n) noexcept nogil:
    cdef const char *p = text
    cdef const char *end = text + n
    cdef const char *q
    cdef uint32_t lines = 0
    if n == 0:
        return 0
    while p < end:
        q = <const char *>memchr(p, b'\n', end - p)
        lines += 1
        if q == NULL:
            break
        p = q + 1
    return lines


cdef int cp_run(CState *st, Unit *u, bint main) noexcept nogil:
    """Executes one source from its first line; COMPILE_OK / ERROR / CANCELLED."""
    cdef size_t pos = 0
    cdef uint32_t line = 1
    cdef const char *eol
    cdef const char *text = u.text
    cdef int r, percent, k
    cdef ErrArg a
    st.unit = u
    st.n_frames = 0
    st.n_calls = 0
    while pos < u.len:
        st.blocks += 1
        if (st.blocks & 1023) == 0:
            if st.inp.cancel != NULL and TC_ATOMIC_LOAD(st.inp.cancel) != 0:
                return COMPILE_CANCELLED
            follow_publish(st.build.follow, st.prog.n_parts)         # between lines: all final
            if st.blocks > st.block_limit:
                st.line = line
                cerr_num(st, ERR_BLOCK_LIMIT, <double>(st.block_limit))
                return COMPILE_ERROR
            if main and st.inp.progress != NULL:
                percent = <int>(pos * 100 / u.len)
                if percent != st.last_percent:
                    st.last_percent = percent
                    st.inp.progress(st.inp.ctx, percent)
        eol = <const char *>memchr(text + pos, b'\n', u.len - pos)
        if eol == NULL:
            eol = text + u.len
        st.line = line
        if <size_t>(eol - text) - pos > MAX_LINE_CHARS:
            cerr_num(st, ERR_LINE_TOO_LONG, MAX_LINE_CHARS)
            return COMPILE_ERROR
        st.cur_pos = pos
        st.next_pos = <size_t>(eol - text) + 1
        st.next_line = line + 1
        r = cp_line(st, text + pos, eol)
        if r == R_NEXT:
            pos = st.next_pos
            line = st.next_line
        elif r == R_JUMP:
            pos = st.jpos
            line = st.jline
        elif r == R_END:
            st.program_end = True
            return COMPILE_OK
        else:
            return COMPILE_ERROR
    # end of text: every block must have been closed
    k = st.n_frames - 1
    while k >= 0 and st.frames[k].kind == FR_CALL:
        k -= 1
    if k >= 0:
        st.line = line - 1 if line > 1 else 1
        if st.frames[k].kind == FR_FOR:
            cerr_text(st, ERR_MISSING_END, "FOR")
        elif st.frames[k].kind == FR_WHILE:
            cerr_text(st, ERR_MISSING_END, "WHILE")
        else:
            cerr_text(st, ERR_MISSING_END, "IF")
        return COMPILE_ERROR
    return COMPILE_OK


cdef void cp_init(CState *st, const CompileInput *inp, ProgramBuilder *build, ErrorInfo *err) noexcept nogil:
    cdef int a
    st.inp = inp
    st.build = build
    st.prog = &build.prog
    st.err = err
    st.params = inp.params
    memcpy(st.P, inp.user_params, sizeof(st.P))
    memcpy(st.ppos, inp.start, sizeof(st.ppos))
    memcpy(st.mpos, inp.start, sizeof(st.mpos))
    st.absolute = inp.params.absMode != 0
    st.plane = 17
    st.motion = 1
    st.per_min = True
    st.fp = 1.0
    st.comp = 40
    st.last_percent = -1
    st.iso = (<uint32_t>inp.params.rezerva1 & GCODE_REZERVA1_ISO_COMPAT) != 0
    st.unit_scale = 1.0
    st.g900_arc_table = -1          # the host's arcFeedTable until G900 S13


cdef void reserve_parts(ProgramBuilder *build, uint32_t lines) noexcept nogil:
    """Reserves room for about one part per line up front (one allocation instead of
    a doubling series), and half as many again for the parts the compensation may
    insert at corners (address space only until written: the array need not move),
    and asks for transparent huge pages: on large programs most of the compile time
    is otherwise spent faulting in fresh 4 KiB pages. Only a hint; the arrays still
    grow on demand."""
    cdef Program *prog = &build.prog
    cdef size_t n = <size_t>lines + 64
    if lines < 100000:
        return
    if grow(<void **>&prog.parts, &build.cap_parts, n + n // 2, sizeof(Part)):
        program_advise_huge(prog.parts, build.cap_parts * sizeof(Part))
    if grow(<void **>&prog.pars, &build.cap_pars, n * 4, sizeof(float)):
        program_advise_huge(prog.pars, build.cap_pars * sizeof(float))


cdef int compile_program(const CompileInput *inp, ProgramBuilder *build, ErrorInfo *err) noexcept nogil:
    """Compiles inp.text (prefix, main, postfix) into build.prog; COMPILE_OK, or COMPILE_ERROR
    with err filled, or COMPILE_CANCELLED when inp.cancel was set."""
    cdef Program *prog = &build.prog
    cdef CState *st = <CState *>calloc(1, sizeof(CState))
    cdef Unit units[3]
    cdef int i, result = COMPILE_OK
    cdef uint64_t lines = 0
    if st == NULL:
        set_error(err, ERR_OUT_OF_MEMORY, inp.file_idx, 0, NULL, 0)
        return COMPILE_ERROR
    memset(units, 0, sizeof(units))
    units[0].text = inp.prefix
    units[0].len = strlen(inp.prefix) if inp.prefix != NULL else 0
    units[0].file_idx = inp.prefix_idx
    units[1].text = inp.text
    units[1].len = inp.length if inp.text != NULL else 0
    units[1].file_idx = inp.file_idx
    units[2].text = inp.postfix
    units[2].len = strlen(inp.postfix) if inp.postfix != NULL else 0
    units[2].file_idx = inp.postfix_idx
    memcpy(prog.start, inp.start, sizeof(prog.start))
    prog.main_file_idx = inp.file_idx
    prog.n_lines = count_lines(units[1].text, units[1].len)
    prog.compensated = False
    lines = prog.n_lines + count_lines(units[0].text, units[0].len) + count_lines(units[2].text, units[2].len)
    cp_init(st, inp, build, err)
    reserve_parts(build, prog.n_lines)
    st.unit = &units[1]
    st.block_limit = (inp.max_blocks if inp.max_blocks > 0 else DEFAULT_MAX_BLOCKS) + <int64_t>lines
    if not update_zero(st):
        set_error(err, ERR_OUT_OF_MEMORY, inp.file_idx, 0, NULL, 0)
        result = COMPILE_ERROR
    for i in range(3):
        if result != COMPILE_OK or st.program_end:
            break
        if units[i].len > 0:
            result = cp_run(st, &units[i], i == 1)
    for i in range(3):
        lb_free(&units[i])
    if result == COMPILE_OK:
        for i in range(AXES):
            if not st.fixed[i]:
                prog.start_gindex[i] = INT32_MAX    # never named: every part follows the start
    free(st)
    return result
