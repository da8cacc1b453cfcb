# The words of one line: address letters with their values (evaluated at once),
# the G and M functions in the order written, P assignments, label names of jumps,
# FF / FP and the text of PRINT / M29. What the words mean is block.pyx's.

from libc.string cimport memchr


cdef inline uint32_t bit_of(char c) noexcept nogil:
    """The bit of an address letter (A..Z) in a word mask."""
    return 1u << (<int>c - 65)


cdef uint32_t axes_mask() noexcept nogil:
    """The mask of the ten axis letters X Y Z C B U V W A O."""
    return (bit_of(b'X') | bit_of(b'Y') | bit_of(b'Z') | bit_of(b'C') | bit_of(b'B') | bit_of(b'U')
            | bit_of(b'V') | bit_of(b'W') | bit_of(b'A') | bit_of(b'O'))


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


cdef inline bint _value_starts(CState *st, const char *q, const char *eol) noexcept nogil:
    """A word's value may start at q: a number, a sign, a bracket, a parameter or function
    (ISO mode: also LinuxCNC's [expression] and #parameter)."""
    return q < eol and (lx_is_digit(q[0]) or q[0] == b'.' or q[0] == b'-' or q[0] == b'+'
                        or q[0] == b'(' or lx_is_alpha(q[0]) or (st.iso and (q[0] == b'[' or q[0] == b'#')))


cdef inline int _word_value(CState *st, const char **pp, const char *eol, double *out) noexcept nogil:
    """A word's value: TG's, or in the ISO mode also LinuxCNC's."""
    if st.iso:
        return ngc_word_value(st, pp, eol, out)
    return ex_value(st, pp, eol, out)


cdef bint _o_word_keyword(const char *p, int n) noexcept nogil:
    """Whether the n letters at p are a LinuxCNC O word's keyword (sub, call, while, if ...): a
    TG line that uses one is told so."""
    return (lx_eq(p, n, "SUB") or lx_eq(p, n, "ENDSUB") or lx_eq(p, n, "CALL") or lx_eq(p, n, "RETURN")
            or lx_eq(p, n, "DO") or lx_eq(p, n, "WHILE") or lx_eq(p, n, "ENDWHILE") or lx_eq(p, n, "IF")
            or lx_eq(p, n, "ELSEIF") or lx_eq(p, n, "ELSE") or lx_eq(p, n, "ENDIF") or lx_eq(p, n, "REPEAT")
            or lx_eq(p, n, "ENDREPEAT") or lx_eq(p, n, "BREAK") or lx_eq(p, n, "CONTINUE"))


cdef int cp_bad_word(CState *st, const char *p, const char *eol, int col, const LineWords *lw) noexcept nogil:
    """A word the dialect does not know: says what TG expects where the word is
    another dialect's (LinuxCNC O-words and # parameters, [ ] expressions)."""
    cdef int n = lx_ident_run(p, eol)
    if p[0] == b'#':
        return err_not_tg(st.err, st.unit.file_idx, st.line, cword_at(st, p, eol), col, "TG parameters are P00..P99 (P1 = value, X P1)")
    if p[0] == b'[':
        return err_not_tg(st.err, st.unit.file_idx, st.line, cword_at(st, p, eol), col, "TG expressions are written in ( ) brackets: X (P1 * 2)")
    if lw.first_is_o and n > 0 and _o_word_keyword(p, n):
        return err_not_tg(st.err, st.unit.file_idx, st.line, cword(st, p, eol, n), col, "O-word subroutines and loops are LinuxCNC G-code; TG uses labels "
                         "(name:) with CALL / RETURN, and FOR / WHILE / IF ... END")
    return err_unknown_word(st.err, st.unit.file_idx, st.line, cword_at(st, p, eol), col)


cdef void _words_clear(LineWords *lw) noexcept nogil:
    """An empty line of words: no addresses, G or M words, texts, label, P words, polar words or
    tool values."""
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
    lw.has_polar_r = False
    lw.has_polar_a = False
    lw.has_amp = False
    lw.tool_values = 0


cdef bint _jump_read(const LineWords *lw) noexcept nogil:
    """A G25 / G26 / G27 was read: a name that follows is its label."""
    cdef int i
    for i in range(lw.ng):
        if lw.g[i] == 25.0 or lw.g[i] == 26.0 or lw.g[i] == 27.0:
            return True
    return False


cdef int _word_of_letters(CState *st, const char **pp, const char *eol, int n, LineWords *lw) noexcept nogil:
    """A run of n >= 2 letters: REM, the label of a jump, FF / FP with a value."""
    cdef const char *p = pp[0]
    cdef const char *q
    cdef double v
    if lx_eq(p, n, "REM"):
        return WORDS_DONE
    if _jump_read(lw) and lx_ident_run(p, eol) > 0:
        lw.label = p
        lw.label_len = lx_ident_run(p, eol)
        pp[0] = p + lw.label_len
        return WORDS_MORE
    if (n == 2 or lx_is_digit(p[2]) or p[2] == b'.') and lx_upper(p[0]) == b'F' \
            and (lx_upper(p[1]) == b'F' or lx_upper(p[1]) == b'P'):
        q = lx_skip_ws(p + 2, eol)
        if _word_value(st, &q, eol, &v) != 0:
            return R_ERR
        if lx_upper(p[1]) == b'F':
            lw.has_ff = True
            lw.ff = v
        else:
            lw.has_fp = True
            lw.fp = v
        pp[0] = q
        return WORDS_MORE
    return cp_bad_word(st, p, eol, column_of(st, p), lw)


cdef int _word_p(CState *st, const char **pp, const char *eol, LineWords *lw) noexcept nogil:
    """P: a parameter assignment Pnn = expression, or a P word with a value (ISO: dwell
    seconds, G64's tolerance, an M function's argument) that cp_block judges after
    the G functions of the line."""
    cdef const char *w = pp[0]
    cdef const char *p = w + 1
    cdef const char *q
    cdef int digits = 0, idx
    cdef double v
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
        pp[0] = p
        return WORDS_MORE
    q = lx_skip_ws(p, eol)
    if not _value_starts(st, q, eol):
        return err_p_word(st.err, st.unit.file_idx, st.line, cword_at(st, w, eol), column_of(st, w), "an assignment is written Pnn = value")
    if _word_value(st, &q, eol, &v) != 0 or number_gate(st, v, "P") != 0:
        return R_ERR
    lw.has_pword = True
    lw.pword = v
    lw.pword_at = w
    lw.pword_len = <int>(q - w)
    lw.col[15] = column_of(st, w)
    pp[0] = q
    return WORDS_MORE


cdef int _word_address(CState *st, const char **pp, const char *eol, LineWords *lw, bint first) noexcept nogil:
    """A single address letter other than P with its value; L may name a label.
    first: no word was read before on this line."""
    cdef const char *w = pp[0]
    cdef const char *q = lx_skip_ws(w + 1, eol)
    cdef int L = <int>lx_upper(w[0]), col = column_of(st, w), n
    cdef double v
    cdef char letter[2]
    letter[0] = <char>L
    letter[1] = 0
    # a digit after the letter (most words) is a value: none of the cases below
    if q >= eol or not lx_is_digit(q[0]):
        if L == 76 and q < eol and (lx_is_alpha(q[0]) or q[0] == b'_') \
                and not ((q[0] == b'P' or q[0] == b'p') and q + 1 < eol and lx_is_digit(q[1])):
            n = lx_ident_run(q, eol)
            if lx_skip_ws(q + n, eol) >= eol or lx_skip_ws(q + n, eol)[0] != b'(':
                lw.label = q          # L name: a label target
                lw.label_len = n
                pp[0] = q + n
                return WORDS_MORE
        if L == 79 and q < eol and q[0] == b'<':
            return err_not_tg(st.err, st.unit.file_idx, st.line, cword_at(st, w, eol), col, "O-word subroutines are LinuxCNC G-code; TG uses labels (name:) with CALL")
        if not st.iso and q < eol and (q[0] == b'[' or q[0] == b'#'):
            return cp_bad_word(st, q, eol, column_of(st, q), lw)      # LinuxCNC's (F#<_hal[..]>)
        if not _value_starts(st, q, eol):
            return err_missing_value(st.err, st.unit.file_idx, st.line, letter, col)
    if _word_value(st, &q, eol, &v) != 0:
        return R_ERR
    if L != 71 and L != 77 and L != 76 and number_gate(st, v, letter) != 0:
        return R_ERR
    pp[0] = q
    if L == 71:     # G
        if lw.ng >= MAX_WORD_LIST:
            return err_too_many_words(st.err, st.unit.file_idx, st.line, MAX_WORD_LIST, "G")
        lw.g[lw.ng] = v
        lw.gcol[lw.ng] = col
        lw.ng += 1
        if v == 29.0:
            return WORDS_DONE       # G29: the rest of the line is a comment
    elif L == 77:   # M
        if lw.nm >= MAX_WORD_LIST:
            return err_too_many_words(st.err, st.unit.file_idx, st.line, MAX_WORD_LIST, "M")
        lw.m[lw.nm] = v
        lw.mcol[lw.nm] = col
        lw.nm += 1
        if st.params.M29_print != 0 and v == st.params.M29_print:
            cp_text(st, q, eol, lw)
            return WORDS_DONE
    else:
        lw.v[L - 65] = v
        lw.mask |= 1u << (L - 65)
        lw.col[L - 65] = col
        if L == 79 and (first or (st.iso and (lw.mask & ~bit_of(b'O')) == bit_of(b'N') and lw.ng == 0
                                  and lw.nm == 0)):
            lw.first_is_o = True            # (ISO: N1 O003 is a program number too)
    return WORDS_MORE


cdef int _word_polar(CState *st, const char **pp, const char *eol, LineWords *lw) noexcept nogil:
    """ISO mode: LinuxCNC's polar words, @ the distance and ^ the angle (degrees) of the
    XY position from the program zero."""
    cdef const char *w = pp[0]
    cdef const char *q = lx_skip_ws(w + 1, eol)
    cdef double v
    cdef char letter[2]
    letter[0] = w[0]
    letter[1] = 0
    if not _value_starts(st, q, eol):
        return err_missing_value(st.err, st.unit.file_idx, st.line, letter, column_of(st, w))
    if _word_value(st, &q, eol, &v) != 0 or number_gate(st, v, letter) != 0:
        return R_ERR
    if not (lw.has_polar_r or lw.has_polar_a):
        lw.polar_col = column_of(st, w)     # the first polar word of the line
    if w[0] == b'@':
        lw.has_polar_r = True
        lw.polar_r = v
    else:
        lw.has_polar_a = True
        lw.polar_a = v
    pp[0] = q
    return WORDS_MORE


cdef int _word_amp(CState *st, const char **pp, const char *eol, LineWords *lw) noexcept nogil:
    """& n: the length corrections of tool table entry n (block.pyx judges n)."""
    cdef const char *w = pp[0]
    cdef const char *q = lx_skip_ws(w + 1, eol)
    if not _value_starts(st, q, eol):
        return err_missing_value(st.err, st.unit.file_idx, st.line, "&", column_of(st, w))
    if _word_value(st, &q, eol, &lw.amp) != 0:
        return R_ERR
    lw.has_amp = True
    lw.amp_col = column_of(st, w)
    pp[0] = q
    return WORDS_MORE


cdef inline bint _is_r_assignment(const char *p, const char *eol) noexcept nogil:
    """TG: R digits = (G92 D's R0= .. R4=), not R digits == (a comparison)."""
    cdef const char *q = p + 1
    if q >= eol or not lx_is_digit(q[0]):
        return False
    while q < eol and lx_is_digit(q[0]):
        q += 1
    q = lx_skip_ws(q, eol)
    return q < eol and q[0] == b'=' and not (q + 1 < eol and q[1] == b'=')


cdef int _word_r_assignment(CState *st, const char **pp, const char *eol, LineWords *lw) noexcept nogil:
    """Rk = value: value k of the tool table entry a G92 D on the line writes (block.pyx
    checks that it is there); k 0..4."""
    cdef const char *w = pp[0]
    cdef const char *q = w + 1
    cdef int k = 0, col = column_of(st, w)
    while lx_is_digit(q[0]):
        if k < 100:
            k = 10 * k + (q[0] - 48)
        q += 1
    if k >= TOOL_VALUES or q - w > 2:
        return err_tool_word(st.err, st.unit.file_idx, st.line, cword(st, w, eol, <int>(q - w)), col, "G92 D writes R0 (the radius) .. R4 (the length of axis 4)")
    q = lx_skip_ws(lx_skip_ws(q, eol) + 1, eol)
    if not _value_starts(st, q, eol):
        return err_missing_value(st.err, st.unit.file_idx, st.line, cword(st, w, eol, 2), col)
    if _word_value(st, &q, eol, &lw.tool_value[k]) != 0:
        return R_ERR
    if lw.tool_values == 0:
        lw.tool_values_col = col
    lw.tool_values |= 1u << k
    pp[0] = q
    return WORDS_MORE


cdef int _ngc_nested_comments(CState *st, const char **pp, const char *eol) noexcept nogil:
    """ISO mode: comments at pp[0] that hold a '(' (`(part (2) done)`), which LinuxCNC
    refuses (comments do not nest): read to the ')' that closes them, warning 621 (error
    414 in the strict ISO mode). Other comments are lx_skip_gap's."""
    cdef const char *p = lx_skip_ws(pp[0], eol)
    cdef const char *q
    cdef const char *inner
    cdef int depth
    while p < eol and p[0] == b'(':
        q = <const char *>memchr(p, b')', eol - p)
        if q == NULL:
            break
        inner = <const char *>memchr(p + 1, b'(', q - p - 1)
        if inner != NULL:
            depth = 0
            q = p
            while q < eol:
                if q[0] == b'(':
                    depth += 1
                elif q[0] == b')':
                    depth -= 1
                    if depth == 0:
                        break
                q += 1
            if q >= eol:
                break                   # not closed: lx_skip_gap reads it as LinuxCNC's first ')'
            if ngc_refused(st, "(", column_of(st, inner), "a '(' inside a comment (comments do not nest)",
                           "reads the comment to the ')' that closes it") != 0:
                return R_ERR
        p = lx_skip_ws(q + 1, eol)
    pp[0] = p
    return 0


cdef int cp_words(CState *st, const char *p, const char *eol, LineWords *lw) noexcept nogil:
    """Reads the words of a line into lw, in the order written."""
    cdef int status, r
    cdef const char *gap
    cdef bint first = True
    _words_clear(lw)
    while True:
        gap = p
        if st.iso and _ngc_nested_comments(st, &p, eol) != 0:
            return R_ERR
        p = lx_skip_gap(p, eol, &status)
        if status:
            return cerr_open_comment(st, gap, eol)
        if p >= eol:
            return 0
        if not lx_is_alpha(p[0]):
            if st.iso and p[0] == b'#':
                r = ngc_setting_read(st, &p, eol)   # taken after the line is read
            elif st.iso and (p[0] == b'@' or p[0] == b'^'):
                r = _word_polar(st, &p, eol, lw)
            elif p[0] == b'&':
                r = _word_amp(st, &p, eol, lw)
            else:
                return cp_bad_word(st, p, eol, column_of(st, p), lw)
        elif p + 1 < eol and lx_is_alpha(p[1]):
            r = _word_of_letters(st, &p, eol, lx_alpha_run(p, eol), lw)
        elif lx_upper(p[0]) == b'P':
            r = _word_p(st, &p, eol, lw)
        elif lx_upper(p[0]) == b'R' and not st.iso and _is_r_assignment(p, eol):
            r = _word_r_assignment(st, &p, eol, lw)
        else:
            r = _word_address(st, &p, eol, lw, first)
        if r == WORDS_DONE:
            return 0
        if r != WORDS_MORE:
            return R_ERR
        first = False



