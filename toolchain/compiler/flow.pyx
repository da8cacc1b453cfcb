# Program flow: FOR / WHILE / IF blocks, BREAK / CONTINUE, subroutine calls and
# jumps. Blocks are executed in place: a frame remembers where to come back to, and
# a skipped block is found by scanning forward and counting block openers and ENDs.
from libc.math cimport fabs


cdef int fl_line_kind(const char *p, const char *eol) noexcept nogil:
    """0 other, 1 block opener (FOR, WHILE, IF ... THEN), 2 ELSE, 3 END."""
    cdef int n
    cdef const char *q
    p = lx_skip_ws(p, eol)
    n = lx_alpha_run(p, eol)
    if n < 2:
        return 0
    if lx_eq(p, n, "FOR") or lx_eq(p, n, "WHILE"):
        return 1
    if lx_eq(p, n, "ELSE"):
        return 2
    if lx_eq(p, n, "END") or lx_eq(p, n, "ENDIF") or lx_eq(p, n, "ENDFOR") or lx_eq(p, n, "ENDWHILE"):
        return 3
    if lx_eq(p, n, "IF"):
        q = p + n
        while q < eol:
            if q[0] == b';' or (q[0] == b'/' and q + 1 < eol and q[1] == b'/'):
                break
            n = lx_alpha_run(q, eol)
            if n > 0:
                if lx_eq(q, n, "THEN"):
                    return 1
                q += n
            else:
                q += 1
    return 0


cdef bint fl_scan(CState *st, size_t pos, uint32_t line, line_test_fn test, void *ctx,
                  int *found) noexcept nogil:
    """The lines of the unit from `pos` (numbered from `line`) on, up to the first one
    `test` answers (not 0): found = its answer, st.skip_pos / skip_line that line,
    st.jpos / jline the line after it. False when the text ends first (nothing
    recorded). The one forward scan of skipped lines: a block's END or ELSE
    (fl_skip), an O label's statement (ngc_flow.pyx ow_scan)."""
    cdef Unit *u = st.unit
    cdef const char *eol
    cdef int kind
    while pos < u.len:
        eol = <const char *>memchr(u.text + pos, b'\n', u.len - pos)
        if eol == NULL:
            eol = u.text + u.len
        kind = test(ctx, u.text + pos, eol)
        if kind != 0:
            found[0] = kind
            st.skip_pos = pos
            st.skip_line = line
            st.jpos = <size_t>(eol - u.text) + 1
            st.jline = line + 1
            return True
        pos = <size_t>(eol - u.text) + 1
        line += 1
    return False


cdef int _block_end_test(void *ctx, const char *p, const char *eol) noexcept nogil:
    """fl_skip's line test: the blocks a line opens or closes counted; the END that
    closes the last (3), or an ELSE at depth 1 when one ends the scan (2), stops it."""
    cdef BlockSkip *b = <BlockSkip *>ctx
    cdef int kind = fl_line_kind(p, eol)
    if kind == 1:
        b.depth += 1
    elif kind == 3:
        b.depth -= 1
    elif kind == 2 and b.depth == 1 and b.stop_at_else:
        b.depth = 0
    return kind if b.depth == 0 else 0


cdef int fl_skip(CState *st, int depth, bint stop_at_else, const char *what, int *found) noexcept nogil:
    """Scans from the next line to the END closing `depth` (at least 1) open blocks (or
    an ELSE at depth 1). st.jpos/jline: the line after it; st.cur_pos/line of the
    END/ELSE itself in st.skip_pos/skip_line. found: 2 ELSE, 3 END."""
    cdef BlockSkip b
    b.depth = depth
    b.stop_at_else = stop_at_else
    if fl_scan(st, st.next_pos, st.next_line, _block_end_test, &b, found):
        return 0
    return err_missing_end(st.err, st.unit.file_idx, st.line, what)


cdef Frame *fl_push(CState *st, int kind) noexcept nogil:
    """A new frame of `kind` on the block stack; NULL with the stack overflow error when
    FRAME_DEPTH are open."""
    cdef Frame *f
    if st.n_frames >= FRAME_DEPTH:
        err_call_stack_overflow(st.err, st.unit.file_idx, st.line, FRAME_DEPTH)
        return NULL
    f = &st.frames[st.n_frames]
    st.n_frames += 1
    f.kind = kind
    return f


cdef int fl_for(CState *st, const char *p, const char *eol) noexcept nogil:
    """FOR Pn = a TO b [STEP s]"""
    cdef int idx, n, found
    cdef double a, b, s = 1.0
    cdef Frame *f
    p = lx_skip_ws(p, eol)
    if p >= eol or lx_upper(p[0]) != b'P':
        return err_bad_condition(st.err, st.unit.file_idx, st.line, cword_rest(st, p, eol), column_of(st, p))
    p += 1
    idx = ex_param_index(st, &p, eol)
    if idx < 0:
        return R_ERR
    p = lx_skip_ws(p, eol)
    if p >= eol or p[0] != b'=':
        return err_bad_condition(st.err, st.unit.file_idx, st.line, cword_rest(st, p, eol), column_of(st, p))
    p += 1
    if ex_sum(st, &p, eol, &a, 0) != 0:
        return R_ERR
    p = lx_skip_ws(p, eol)
    n = lx_alpha_run(p, eol)
    if not lx_eq(p, n, "TO"):
        return err_bad_condition(st.err, st.unit.file_idx, st.line, cword_rest(st, p, eol), column_of(st, p))
    p += n
    if ex_sum(st, &p, eol, &b, 0) != 0:
        return R_ERR
    p = lx_skip_ws(p, eol)
    n = lx_alpha_run(p, eol)
    if n > 0:
        if not lx_eq(p, n, "STEP"):
            return err_bad_condition(st.err, st.unit.file_idx, st.line, cword_rest(st, p, eol), column_of(st, p))
        p += n
        if ex_sum(st, &p, eol, &s, 0) != 0:
            return R_ERR
    if fl_rest_of_line(st, p, eol) != 0:
        return R_ERR
    st.P[idx] = a
    if (s > 0 and a > b) or (s < 0 and a < b):
        if fl_skip(st, 1, False, "FOR", &found) != 0:
            return R_ERR
        return R_JUMP
    f = fl_push(st, FR_FOR)
    if f == NULL:
        return R_ERR
    f.pos = st.next_pos
    f.line = st.next_line
    f.param = idx
    f.end = b
    f.step = s
    return R_NEXT


cdef int fl_rest_of_line(CState *st, const char *p, const char *eol) noexcept nogil:
    """Only blanks and comments may follow a flow statement."""
    cdef int status
    cdef const char *gap = p
    p = lx_skip_gap(p, eol, &status)
    if status:
        return cerr_open_comment(st, gap, eol)
    if p < eol:
        return err_unknown_word(st.err, st.unit.file_idx, st.line, cword_at(st, p, eol), column_of(st, p))
    return 0


cdef int fl_while(CState *st, const char *p, const char *eol) noexcept nogil:
    """WHILE cond: a true condition opens a loop frame (its END jumps back to this line), a
    false one skips past the matching END."""
    cdef bint cond
    cdef int found
    cdef Frame *f
    if ex_condition(st, &p, eol, &cond) != 0:
        return R_ERR
    if fl_rest_of_line(st, p, eol) != 0:
        return R_ERR
    if not cond:
        if fl_skip(st, 1, False, "WHILE", &found) != 0:
            return R_ERR
        return R_JUMP
    f = fl_push(st, FR_WHILE)
    if f == NULL:
        return R_ERR
    f.pos = st.cur_pos
    f.line = st.line
    return R_NEXT


cdef int fl_if(CState *st, const char *p, const char *eol) noexcept nogil:
    """IF cond THEN | BREAK | CONTINUE | RETURN | GOTO label | CALL label"""
    cdef bint cond
    cdef int n, found
    cdef Frame *f
    if ex_condition(st, &p, eol, &cond) != 0:
        return R_ERR
    p = lx_skip_ws(p, eol)
    n = lx_alpha_run(p, eol)
    if lx_eq(p, n, "THEN"):
        if fl_rest_of_line(st, p + n, eol) != 0:
            return R_ERR
        if cond:
            f = fl_push(st, FR_IF)
            if f == NULL:
                return R_ERR
            return R_NEXT
        if fl_skip(st, 1, True, "IF", &found) != 0:
            return R_ERR
        if found == 2:      # ELSE branch runs
            f = fl_push(st, FR_IF)
            if f == NULL:
                return R_ERR
        return R_JUMP
    if lx_eq(p, n, "BREAK") or lx_eq(p, n, "CONTINUE") or lx_eq(p, n, "RETURN"):
        if fl_rest_of_line(st, p + n, eol) != 0:
            return R_ERR
        if not cond:
            return R_NEXT
        if lx_eq(p, n, "RETURN"):
            return fl_return(st)
        return fl_break(st, lx_eq(p, n, "CONTINUE"))
    if lx_eq(p, n, "GOTO") or lx_eq(p, n, "CALL"):
        if not cond:
            return R_NEXT
        return fl_call_stmt(st, p + n, eol, lx_eq(p, n, "CALL"))
    return err_bad_condition(st.err, st.unit.file_idx, st.line, cword_rest(st, p, eol), column_of(st, p))


cdef int fl_else(CState *st) noexcept nogil:
    """ELSE reached from the IF's true branch: closes the IF's frame and skips past its END."""
    cdef int found
    if st.n_frames == 0 or st.frames[st.n_frames - 1].kind != FR_IF:
        return err_unbalanced_end(st.err, st.unit.file_idx, st.line)
    st.n_frames -= 1
    if fl_skip(st, 1, False, "ELSE", &found) != 0:
        return R_ERR
    return R_JUMP


cdef int fl_end(CState *st) noexcept nogil:
    """END of the innermost block: a FOR steps its parameter and jumps back while it is within
    its end (a step of 0 forever), a WHILE jumps back to test again, an IF is closed."""
    cdef Frame *f
    if st.n_frames == 0 or st.frames[st.n_frames - 1].kind == FR_CALL:
        return err_unbalanced_end(st.err, st.unit.file_idx, st.line)
    f = &st.frames[st.n_frames - 1]
    if f.kind == FR_FOR:
        st.P[f.param] += f.step
        if (f.step > 0 and st.P[f.param] <= f.end) or (f.step < 0 and st.P[f.param] >= f.end) \
                or (f.step == 0):
            st.jpos = f.pos
            st.jline = f.line
            return R_JUMP
        st.n_frames -= 1
        return R_NEXT
    if f.kind == FR_WHILE:
        st.n_frames -= 1
        st.jpos = f.pos
        st.jline = f.line
        return R_JUMP
    st.n_frames -= 1        # IF
    return R_NEXT


cdef int fl_break(CState *st, bint cont) noexcept nogil:
    """BREAK leaves the innermost loop, CONTINUE goes to its END."""
    cdef int k = st.n_frames - 1
    cdef int found
    while k >= 0 and st.frames[k].kind == FR_IF:
        k -= 1
    if k < 0 or st.frames[k].kind == FR_CALL:
        if cont:
            return err_break_outside_loop(st.err, st.unit.file_idx, st.line, "CONTINUE")
        return err_break_outside_loop(st.err, st.unit.file_idx, st.line, "BREAK")
    if fl_skip(st, st.n_frames - k, False, "FOR", &found) != 0:
        return R_ERR
    if cont:
        st.n_frames = k + 1
        st.jpos = st.skip_pos
        st.jline = st.skip_line
    else:
        st.n_frames = k
    return R_JUMP


cdef int fl_return(CState *st) noexcept nogil:
    """RETURN: leaves the blocks of the current call; a call repeated (G25 n) jumps to its
    target again, else back after the call. Error without a call."""
    cdef Frame *f
    while st.n_frames > 0 and st.frames[st.n_frames - 1].kind != FR_CALL:
        st.n_frames -= 1
    if st.n_frames == 0:
        return err_return_without_call(st.err, st.unit.file_idx, st.line)
    f = &st.frames[st.n_frames - 1]
    if f.repeat > 1:
        f.repeat -= 1
        st.jpos = f.target_pos
        st.jline = f.target_line
        return R_JUMP
    st.n_frames -= 1
    st.n_calls -= 1
    st.jpos = f.pos
    st.jline = f.line
    return R_JUMP


cdef int fl_target(CState *st, const char *name, int n, double num, bint has_num) noexcept nogil:
    """Finds a jump target (label name, or N number) into st.jpos/jline."""
    cdef Label *e = NULL
    cdef char buf[32]
    cdef int k
    if not st.unit.labels_built:
        if lb_build(st, st.unit) != 0:
            return R_ERR
    if has_num:
        if fabs(num) < 1e15 and num == <double>(<int64_t>num):
            e = lb_find(st.unit, NULL, 0, <int64_t>num)
        if e == NULL:
            k = c_snprintf(buf, sizeof(buf), "%.0f", num)
            if k > 0 and k < <int>sizeof(buf):
                e = lb_find(st.unit, buf, k, 0)
        if e == NULL:
            c_snprintf(buf, sizeof(buf), "N%g", num)
            return err_undefined_label(st.err, st.unit.file_idx, st.line, buf)
    else:
        e = lb_find(st.unit, name, n, 0)
        if e == NULL and n > 1 and (name[0] == b'L' or name[0] == b'l'):
            e = lb_find(st.unit, name + 1, n - 1, 0)    # G27 LNAME written without a blank
        if e == NULL:
            return err_undefined_label(st.err, st.unit.file_idx, st.line, cword(st, name, name + n, n))
    st.jpos = e.pos
    st.jline = e.line
    return 0


cdef int fl_call(CState *st, const char *name, int n, double num, bint has_num, bint call,
                 int64_t repeat) noexcept nogil:
    """CALL / G25 / G26 (repeat times) or GOTO / G27."""
    cdef Frame *f
    if fl_target(st, name, n, num, has_num) != 0:
        return R_ERR
    if not call:
        return R_JUMP
    if repeat <= 0:
        return R_NEXT
    if st.n_calls >= CALL_DEPTH:
        return err_call_stack_overflow(st.err, st.unit.file_idx, st.line, CALL_DEPTH)
    f = fl_push(st, FR_CALL)
    if f == NULL:
        return R_ERR
    st.n_calls += 1
    f.pos = st.next_pos
    f.line = st.next_line
    f.repeat = repeat
    f.target_pos = st.jpos
    f.target_line = st.jline
    return R_JUMP


cdef int fl_call_stmt(CState *st, const char *p, const char *eol, bint call) noexcept nogil:
    """CALL label / GOTO label (a number means an N number)."""
    cdef int n
    cdef double v
    p = lx_skip_ws(p, eol)
    n = lx_ident_run(p, eol)
    if n > 0:
        if fl_rest_of_line(st, p + n, eol) != 0:
            return R_ERR
        return fl_call(st, p, n, 0, False, call, 1)
    if p < eol and (lx_is_digit(p[0]) or p[0] == b'(' or p[0] == b'-'):
        if ex_sum(st, &p, eol, &v, 0) != 0:
            return R_ERR
        if fl_rest_of_line(st, p, eol) != 0:
            return R_ERR
        return fl_call(st, NULL, 0, v, True, call, 1)
    return err_undefined_label(st.err, st.unit.file_idx, st.line, cword_rest(st, p, eol))
