# The G-code compiler: runs prefix, main text and postfix line by line (the program
# is interpreted once, loops and calls included) and appends one Part per G/M
# function. Modal G functions and non-signalled M functions change the state only.
from libc.stdlib cimport free
from libc.string cimport memchr, memcpy, memset, strlen
from libc.stdio cimport snprintf
from libc.math cimport floor


# ------------------------------------------------------------- one line

cdef int cp_line(CState *st, const char *p, const char *eol) noexcept nogil:
    """One line: blank, '%', label, a flow statement (ISO mode: an O-word statement), or
    address words."""
    cdef int n, a
    cdef const char *q
    p = lx_skip_ws(p, eol)
    if p >= eol:
        return R_NEXT
    if p[0] == b'%':
        if st.ngc != NULL and st.cur_pos != st.percent_open:
            # (a program that starts with '%' ends at the next one: cp_percent_end)
            return R_ERR if ngc_refused(st, "%", column_of(st, p), "a '%' line inside a program that "
                                        "does not start with one", "ignores it") != 0 else R_NEXT
        return R_NEXT
    if st.ngc != NULL and (p[0] == b'O' or p[0] == b'o' or p[0] == b'N' or p[0] == b'n'):
        n = ow_statement(st, p, eol)
        if n != R_NOT_O:
            return n
    n = lx_ident_run(p, eol)
    if n > 0:
        q = lx_skip_ws(p + n, eol)
        if q < eol and q[0] == b':':
            if fl_rest_of_line(st, q + 1, eol) != 0:
                return R_ERR
            return R_NEXT
        if n >= 2 and lx_is_alpha(p[0]) and lx_is_alpha(p[1]):     # (a keyword: two letters at least)
            a = lx_alpha_run(p, eol)
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
    if st.ngc != NULL and st.ngc.n_settings > 0 and ngc_settings_apply(st) != 0:
        return R_ERR
    return cp_block(st, &st.lw)


# ------------------------------------------------------------- the run loop

cdef uint32_t count_lines(const char *text, size_t n) noexcept nogil:
    """Lines in text[0, n): its line breaks, and a last line without one; 0 for no text (text
    may then be NULL). A plain loop the C compiler vectorises: a memchr per line cost a call
    a line."""
    cdef uint32_t breaks = 0
    cdef size_t i
    if n == 0:
        return 0                        # text may be NULL (no prefix): no pointer arithmetic on it
    for i in range(n):
        breaks += text[i] == b'\n'
    return breaks + (text[n - 1] != b'\n')


cdef inline bint _percent_line(const char *p, const char *eol) noexcept nogil:
    """Whether the line at p starts, after blanks, with '%' (the ISO mode's program
    delimiter)."""
    p = lx_skip_ws(p, eol)
    return p < eol and p[0] == b'%'


cdef size_t cp_percent_end(CState *st, Unit *u, size_t pos) noexcept nogil:
    """ISO mode: a text whose first non-blank line is a '%' line ends at the next '%'
    line (LinuxCNC ignores what follows it). The end of the text, that line's start;
    u.len when the text starts otherwise or has no closing '%'. st.percent_open: the
    opening line's start (SIZE_MAX: none)."""
    cdef const char *text = u.text
    cdef const char *eol
    cdef const char *p
    st.percent_open = <size_t>-1
    while pos < u.len:
        eol = <const char *>memchr(text + pos, b'\n', u.len - pos)
        if eol == NULL:
            eol = text + u.len
        p = lx_skip_ws(text + pos, eol)
        if p < eol:
            break
        pos = <size_t>(eol - text) + 1
    if pos >= u.len or not _percent_line(text + pos, text + u.len):
        return u.len
    st.percent_open = pos
    while pos < u.len:
        eol = <const char *>memchr(text + pos, b'\n', u.len - pos)
        if eol == NULL:
            eol = text + u.len
        if pos != st.percent_open and _percent_line(text + pos, eol):
            return pos
        pos = <size_t>(eol - text) + 1
    return u.len


cdef int cp_run(CState *st, Unit *u, bint main) noexcept nogil:
    """Executes one source from its first line; COMPILE_OK / ERROR / CANCELLED."""
    cdef size_t pos = 0
    cdef const char *text = u.text
    cdef int r
    cdef size_t full_len = u.len
    st.unit = u
    st.n_frames = 0
    st.n_calls = 0
    pos = lx_bom(text, u.len)
    st.percent_open = <size_t>-1
    if st.ngc != NULL:
        u.len = cp_percent_end(st, u, pos)      # (restored below: the unit is the caller's)
    r = cp_run_lines(st, u, main, pos)
    if r == COMPILE_OK and st.ngc != NULL and st.percent_open != <size_t>-1 and u.len == full_len \
            and not st.program_end:
        st.line = count_lines(text, u.len)
        if ngc_refused(st, "%", 1, "the program starts with a '%' line and ends without its closing one "
                       "(or M2 / M30)", "ends the program at the end of its text") != 0:
            r = COMPILE_ERROR
    u.len = full_len
    return r


cdef int cp_run_lines(CState *st, Unit *u, bint main, size_t pos) noexcept nogil:
    """cp_run's loop over the lines of u from pos."""
    cdef uint32_t line = 1
    cdef const char *eol
    cdef const char *text = u.text
    cdef int r, percent, k
    while pos < u.len:
        st.blocks += 1
        if (st.blocks & 1023) == 0:
            if st.inp.cancel != NULL and TC_ATOMIC_LOAD(st.inp.cancel) != 0:
                return COMPILE_CANCELLED
            follow_publish(st.build.follow, st.prog.n_parts)         # between lines: all final
            if st.blocks > st.block_limit:
                st.line = line
                err_block_limit(st.err, st.unit.file_idx, st.line, <double>(st.block_limit))
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
            err_line_too_long(st.err, st.unit.file_idx, st.line, MAX_LINE_CHARS)
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
        elif st.inp.cancel != NULL and TC_ATOMIC_LOAD(st.inp.cancel) != 0:
            return COMPILE_CANCELLED        # em_part saw the ending call mid-line
        else:
            return COMPILE_ERROR
    # end of text: every block must have been closed
    k = st.n_frames - 1
    while k >= 0 and st.frames[k].kind == FR_CALL:
        k -= 1
    if k >= 0:
        st.line = line - 1 if line > 1 else 1
        if st.frames[k].kind == FR_FOR:
            err_missing_end(st.err, st.unit.file_idx, st.line, "FOR")
        elif st.frames[k].kind == FR_WHILE:
            err_missing_end(st.err, st.unit.file_idx, st.line, "WHILE")
        else:
            err_missing_end(st.err, st.unit.file_idx, st.line, "IF")
        return COMPILE_ERROR
    if ow_unclosed(st) != 0:
        return COMPILE_ERROR
    return COMPILE_OK


cdef void cp_init(CState *st, const CompileInput *inp, ProgramBuilder *build, ErrorInfo *err) noexcept nogil:
    """The compiler's state at the start of a compilation: the input's parameters, P values and
    start position, the modal defaults (G17, G1, G40, per minute; in the ISO mode LinuxCNC's G80
    and its state), the host's arc feed table."""
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
    st.comp_g = 40
    st.tools = inp.tools
    st.tool_d = -1
    st.last_percent = -1
    st.iso = (<uint32_t>inp.params.rezerva1 & GCODE_REZERVA1_ISO_COMPAT) != 0
    if st.iso:
        st.ngc = ngc_new()          # NULL: no memory, compile_program reports it
        st.motion = -1              # LinuxCNC starts in G80: axis words alone do not move
    st.unit_scale = 1.0
    st.g900_arc_table = -1          # the host's arcFeedTable until G900 S13


cdef void reserve_parts(ProgramBuilder *build, uint32_t lines) noexcept nogil:
    """Reserves room for about one part per line up front (one allocation instead of
    a doubling series), and half as many again for the parts the compensation may
    insert at corners (address space only until written: the array need not move).
    No transparent huge pages: on the project's VM a cold 2 MiB page costs several
    times what its 4 KiB pages do (docs/benchmarks.md, 2026-11-26). The arrays still
    grow on demand."""
    cdef Program *prog = &build.prog
    cdef size_t n = <size_t>lines + 64
    if lines < 100000:
        return
    grow(<void **>&prog.parts, &build.cap_parts, n + n // 2, sizeof(Part))
    grow(<void **>&prog.pars, &build.cap_pars, n * 4, sizeof(float))


cdef int compile_program(const CompileInput *inp, ProgramBuilder *build, ErrorInfo *err) noexcept nogil:
    """Compiles inp.text (prefix, main, postfix) into build.prog; COMPILE_OK, or COMPILE_ERROR
    with err filled, or COMPILE_CANCELLED when inp.cancel was set."""
    cdef Program *prog = &build.prog
    cdef CState *st = <CState *>tc_calloc(1, sizeof(CState))
    cdef Unit units[3]
    cdef int i, result = COMPILE_OK
    cdef uint64_t lines = 0
    if st == NULL:
        err_out_of_memory(err, inp.file_idx, 0)
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
    if st.iso and st.ngc == NULL:
        err_out_of_memory(err, inp.file_idx, 0)
        result = COMPILE_ERROR
    elif not update_zero(st):
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
    ngc_free(st.ngc)
    free(st)
    return result
