# ISO mode: LinuxCNC's O-word flow. `o100 sub` ... `o100 endsub` defines a subroutine
# (its body is skipped until called; a call of one not read yet searches the rest of the
# text for its definition, as LinuxCNC does),
# `o100 call [a] [b]` runs it with #1, #2 .. set (the caller's #1..#30 come back after
# `return` / `endsub`, its local named parameters vanish), `if / elseif / else / endif`,
# `while / endwhile`, `do / while`, `repeat / endrepeat`, `break`, `continue`. The
# statements of a construct share its O number or name; a skipped part is found by
# scanning forward for that label (flow.pyx fl_scan, the scan of TG's skipped blocks
# too), as LinuxCNC does, so labels are literal (o100, o<name>), and only a call may
# compute its label (o[#1 + 2] call).
from libc.math cimport floor, fabs


cdef int ow_keyword(const char *p, int n) noexcept nogil:
    """The O word's keyword of the n letters at p (OW_SUB .. OW_CONTINUE), case-insensitive; 0
    for none."""
    if lx_eq(p, n, "SUB"): return OW_SUB
    if lx_eq(p, n, "ENDSUB"): return OW_ENDSUB
    if lx_eq(p, n, "CALL"): return OW_CALL
    if lx_eq(p, n, "RETURN"): return OW_RETURN
    if lx_eq(p, n, "IF"): return OW_IF
    if lx_eq(p, n, "ELSEIF"): return OW_ELSEIF
    if lx_eq(p, n, "ELSE"): return OW_ELSE
    if lx_eq(p, n, "ENDIF"): return OW_ENDIF
    if lx_eq(p, n, "WHILE"): return OW_WHILE
    if lx_eq(p, n, "ENDWHILE"): return OW_ENDWHILE
    if lx_eq(p, n, "DO"): return OW_DO
    if lx_eq(p, n, "REPEAT"): return OW_REPEAT
    if lx_eq(p, n, "ENDREPEAT"): return OW_ENDREPEAT
    if lx_eq(p, n, "BREAK"): return OW_BREAK
    if lx_eq(p, n, "CONTINUE"): return OW_CONTINUE
    return 0


cdef inline uint32_t kw_bit(int kw) noexcept nogil:
    """A keyword's bit in a mask of the keywords a scan looks for."""
    return 1u << kw


cdef const char *ow_literal_label(const char *p, const char *eol, NgcLabel *lab) noexcept nogil:
    """After 'o': a literal label (digits, or <name>: lower case, blanks dropped); the
    text after it, NULL when there is none."""
    cdef int64_t v = 0
    cdef int n = 0
    p = lx_skip_ws(p, eol)
    if p < eol and lx_is_digit(p[0]):
        while p < eol and lx_is_digit(p[0]):
            if v < 1000000000000LL:
                v = v * 10 + (<int>p[0] - 48)
            p += 1
        lab.number = v
        lab.len = 0
        lab.name[0] = 0
        return p
    if p < eol and p[0] == b'<':
        p += 1
        while p < eol and p[0] != b'>':
            if p[0] != b' ' and p[0] != b'\t':
                if n >= NGC_NAME_CHARS - 1:
                    return NULL
                lab.name[n] = p[0] + 32 if (p[0] >= b'A' and p[0] <= b'Z') else p[0]
                n += 1
            p += 1
        if p >= eol or n == 0:
            return NULL
        lab.number = -1
        lab.len = n
        lab.name[n] = 0
        return p + 1
    return NULL


cdef const char *ow_line(const char *p, const char *eol, NgcLabel *lab, int *kw) noexcept nogil:
    """The line [p, eol) is an O-word statement with a literal label (an N number may come
    first): its keyword, and the text after it; NULL when the line is none."""
    cdef int n
    p = lx_skip_ws(p, eol)
    if p < eol and (p[0] == b'N' or p[0] == b'n') and p + 1 < eol and lx_is_digit(p[1]):
        p += 1
        while p < eol and (lx_is_digit(p[0]) or p[0] == b'.'):
            p += 1
        p = lx_skip_ws(p, eol)
    if p >= eol or not (p[0] == b'O' or p[0] == b'o'):
        return NULL
    p = ow_literal_label(p + 1, eol, lab)
    if p == NULL:
        return NULL
    p = lx_skip_ws(p, eol)
    n = lx_alpha_run(p, eol)
    kw[0] = ow_keyword(p, n)
    return p + n if kw[0] != 0 else NULL


cdef bint ow_same(const NgcLabel *a, const NgcLabel *b) noexcept nogil:
    """Whether two O labels are the same: equal numbers, or (both named) equal names."""
    if a.number >= 0 or b.number >= 0:
        return a.number == b.number
    return a.len == b.len and memcmp(a.name, b.name, a.len) == 0


cdef const char *ow_label_text(CState *st, const NgcLabel *lab) noexcept nogil:
    """o100 / o<name> for messages."""
    if lab.number >= 0:
        c_snprintf(st.word, sizeof(st.word), "o%lld", <long long>lab.number)
    else:
        c_snprintf(st.word, sizeof(st.word), "o<%s>", lab.name)
    return st.word


cdef int ow_error(CState *st, const NgcLabel *lab, const char *what) noexcept nogil:
    """Error 310 naming the construct, its column (the O word's) and what is wrong."""
    return err_o_word(st.err, st.unit.file_idx, st.line, ow_label_text(st, lab), st.ngc.col, what)


cdef int _label_test(void *ctx, const char *p, const char *eol) noexcept nogil:
    """ow_scan's line test: the keyword (not 0) of a statement of the label with one of
    the keywords wanted, else 0."""
    cdef const LabelScan *want = <const LabelScan *>ctx
    cdef NgcLabel other
    cdef int kw
    if ow_line(p, eol, &other, &kw) != NULL and (want.kinds & kw_bit(kw)) and ow_same(&other, want.label):
        return kw
    return 0


cdef int ow_scan(CState *st, const NgcLabel *lab, uint32_t kinds, size_t pos, uint32_t line,
                 int *found) noexcept nogil:
    """From the line at pos on: the first statement of label lab with a keyword in kinds.
    st.skip_pos / skip_line: that line; st.jpos / jline: the line after it. 0 found,
    1 not found (nothing recorded)."""
    cdef Unit *u = st.unit
    cdef NgcScan *seen = &st.ngc.scans[(pos ^ (pos >> 6) ^ kinds) % NGC_SCANS]
    cdef LabelScan want
    if seen.text == u.text and seen.pos == pos and seen.kinds == kinds and ow_same(&seen.label, lab) \
            and seen.label.number == lab.number:
        return _scan_answer(st, seen, line, found)
    want.label = lab
    want.kinds = kinds
    if fl_scan(st, pos, line, _label_test, &want, found):
        _scan_remember(seen, u.text, pos, kinds, lab, found[0], st.skip_pos, st.jpos, st.skip_line - line)
        return 0
    _scan_remember(seen, u.text, pos, kinds, lab, 0, 0, 0, 0)
    return 1


cdef void _scan_remember(NgcScan *seen, const char *text, size_t pos, uint32_t kinds, const NgcLabel *lab,
                         int found, size_t skip_pos, size_t jpos, uint32_t lines) noexcept nogil:
    """Records a scan in its slot: what it looked for from where, and what it found (found 0:
    nothing), its lines counted from the start so a scan from the same place of another pass
    answers at once."""
    seen.text = text
    seen.pos = pos
    seen.kinds = kinds
    seen.label = lab[0]
    seen.found = found
    seen.skip_pos = skip_pos
    seen.jpos = jpos
    seen.lines = lines


cdef int _scan_answer(CState *st, const NgcScan *seen, uint32_t line, int *found) noexcept nogil:
    """ow_scan's answer from a remembered scan that started on `line`."""
    if seen.found == 0:
        return 1
    found[0] = seen.found
    st.skip_pos = seen.skip_pos
    st.skip_line = line + seen.lines
    st.jpos = seen.jpos
    st.jline = line + seen.lines + 1
    return 0


cdef int ow_skip_to(CState *st, const NgcLabel *lab, uint32_t kinds, const char *missing) noexcept nogil:
    """Jump past the next statement of lab with a keyword in kinds; error `missing`."""
    cdef int found
    if ow_scan(st, lab, kinds, st.next_pos, st.next_line, &found) != 0:
        return ow_error(st, lab, missing)
    return R_JUMP


cdef NgcFrame *ow_push(CState *st, int kind, const NgcLabel *lab) noexcept nogil:
    """A new frame of kind `kind` for label lab on the O word stack; NULL with the error when
    NGC_FRAMES are open."""
    cdef NgcState *n = st.ngc
    cdef NgcFrame *f
    if n.n_frames >= NGC_FRAMES:
        err_call_stack_overflow(st.err, st.unit.file_idx, st.line, NGC_FRAMES)
        return NULL
    f = &n.frames[n.n_frames]
    n.n_frames += 1
    f.kind = kind
    f.label = lab[0]
    f.count = 0
    return f


cdef int ow_loop_frame(CState *st, const NgcLabel *lab) noexcept nogil:
    """Index of the innermost open loop of label lab within the current call; -1 none."""
    cdef NgcState *n = st.ngc
    cdef int k = n.n_frames - 1
    while k >= 0 and n.frames[k].kind != OF_CALL:
        if ow_same(&n.frames[k].label, lab):
            return k
        k -= 1
    return -1


cdef int ow_condition(CState *st, const char *p, const char *eol, bint *out) noexcept nogil:
    """The condition of if / elseif / while: a value (an expression in [ ]), then nothing."""
    cdef double v
    if ngc_value(st, &p, eol, &v, 0) != 0:
        return R_ERR
    if fl_rest_of_line(st, p, eol) != 0:
        return R_ERR
    out[0] = v != 0.0
    return 0


cdef int ow_if_false(CState *st, const NgcLabel *lab) noexcept nogil:
    """The branch not taken: on to the first elseif whose condition holds, the else, or
    past the endif."""
    cdef size_t pos = st.next_pos
    cdef uint32_t line = st.next_line
    cdef const char *eol
    cdef const char *rest
    cdef NgcLabel other
    cdef int kw, found
    cdef bint cond
    while True:
        if ow_scan(st, lab, kw_bit(OW_ELSEIF) | kw_bit(OW_ELSE) | kw_bit(OW_ENDIF), pos, line, &found) != 0:
            return ow_error(st, lab, "if without endif")
        if found != OW_ELSEIF:
            return R_JUMP
        # the elseif's condition, read as that line (its columns, its line number)
        st.line = st.skip_line
        st.cur_pos = st.skip_pos
        eol = st.unit.text + st.jpos - 1
        rest = ow_line(st.unit.text + st.skip_pos, eol, &other, &kw)
        if ow_condition(st, rest, eol, &cond) != 0:
            return R_ERR
        if cond:
            return R_JUMP
        pos = st.jpos
        line = st.jline


cdef NgcSub *ow_sub_ahead(CState *st, const NgcLabel *lab) noexcept nogil:
    """A call of a subroutine not defined yet: its `sub` line searched from the call on
    to the end of the text, as LinuxCNC skips ahead to it (a common layout defines the
    subroutines after M2 / M30); found, it is defined from then on. NULL: error 311."""
    cdef NgcState *n = st.ngc
    cdef NgcSub *sub
    cdef int found
    if ow_scan(st, lab, kw_bit(OW_SUB), st.next_pos, st.next_line, &found) != 0:
        err_o_undefined(st.err, st.unit.file_idx, st.line, ow_label_text(st, lab), st.ngc.col)
        return NULL
    if not grow(<void **>&n.subs, &n.cap_subs, n.n_subs + 1, sizeof(NgcSub)):
        err_out_of_memory(st.err, st.unit.file_idx, st.line)
        return NULL
    sub = &n.subs[n.n_subs]
    n.n_subs += 1
    sub.label = lab[0]
    sub.text = st.unit.text
    sub.pos = st.jpos               # the line after `sub`
    sub.line = st.jline
    return sub


cdef int ow_call(CState *st, const NgcLabel *lab, const char *p, const char *eol) noexcept nogil:
    """`call [a] [b] ..`: #1.. of the callee set, the caller's #1..#30 saved."""
    cdef NgcState *n = st.ngc
    cdef NgcSub *sub = NULL
    cdef NgcFrame *f
    cdef double args[NGC_ARGS]
    cdef int nargs = 0, i, status
    cdef size_t s
    p = lx_skip_gap(p, eol, &status)
    while p < eol:
        if nargs >= NGC_ARGS:
            return ow_error(st, lab, "more than 30 arguments")
        if ngc_value(st, &p, eol, &args[nargs], 0) != 0:
            return R_ERR
        nargs += 1
        p = lx_skip_gap(p, eol, &status)
    if status:
        return cerr_open_comment(st, p, eol)
    for s in range(n.n_subs):
        if ow_same(&n.subs[s].label, lab) and n.subs[s].text == st.unit.text:
            sub = &n.subs[s]
    if sub == NULL:
        sub = ow_sub_ahead(st, lab)
        if sub == NULL:
            return R_ERR
    if n.level + 1 >= NGC_CALL_LEVELS:
        return err_call_stack_overflow(st.err, st.unit.file_idx, st.line, NGC_CALL_LEVELS - 1)
    f = ow_push(st, OF_CALL, lab)
    if f == NULL:
        return R_ERR
    f.pos = st.next_pos
    f.line = st.next_line
    memcpy(n.saved[n.level], &n.params[1], NGC_ARGS * sizeof(double))
    n.level += 1
    for i in range(nargs):
        n.params[1 + i] = args[i]
    n.value = 0.0                   # cleared before each call (LinuxCNC)
    n.value_returned = False
    st.jpos = sub.pos
    st.jline = sub.line
    return R_JUMP


cdef int ow_return(CState *st, const NgcLabel *lab, const char *p, const char *eol) noexcept nogil:
    """`return [v]` / `endsub [v]`: back to the caller, #<_value> = v."""
    cdef NgcState *n = st.ngc
    cdef int k = n.n_frames - 1, status
    cdef size_t i, kept = 0
    cdef double v
    cdef bint given = False
    while k >= 0 and n.frames[k].kind != OF_CALL:
        k -= 1
    if k < 0:
        return ow_error(st, lab, "return or endsub outside a called subroutine")
    if not ow_same(&n.frames[k].label, lab):
        return ow_error(st, lab, "returns from another subroutine than the one called")
    p = lx_skip_gap(p, eol, &status)
    if p < eol:
        if ngc_value(st, &p, eol, &v, 0) != 0:
            return R_ERR
        given = True
    if fl_rest_of_line(st, p, eol) != 0:
        return R_ERR
    if given:
        n.value = v
        n.value_returned = True
    n.n_frames = k
    n.level -= 1
    memcpy(&n.params[1], n.saved[n.level], NGC_ARGS * sizeof(double))
    if n.n_locals > 0:                  # the callee's local named parameters vanish
        n.n_locals = 0
        for i in range(n.n_names):
            if n.names[i].level <= n.level:
                n.names[kept] = n.names[i]
                n.n_locals += n.names[i].level >= 1
                kept += 1
        n.n_names = kept
        if not ngc_names_index(n):
            return err_out_of_memory(st.err, st.unit.file_idx, st.line)
    st.jpos = n.frames[k].pos
    st.jline = n.frames[k].line
    return R_JUMP


cdef int ow_sub(CState *st, const NgcLabel *lab, const char *p, const char *eol) noexcept nogil:
    """`sub`: the definition is recorded and its body skipped."""
    cdef NgcState *n = st.ngc
    cdef NgcSub *sub = NULL
    cdef size_t i
    if fl_rest_of_line(st, p, eol) != 0:
        return R_ERR
    if n.level > 0:
        return ow_error(st, lab, "subroutine definitions do not nest")
    for i in range(n.n_subs):
        if ow_same(&n.subs[i].label, lab) and n.subs[i].text == st.unit.text:
            sub = &n.subs[i]
    if sub == NULL:
        if not grow(<void **>&n.subs, &n.cap_subs, n.n_subs + 1, sizeof(NgcSub)):
            return err_out_of_memory(st.err, st.unit.file_idx, st.line)
        sub = &n.subs[n.n_subs]
        n.n_subs += 1
    sub.label = lab[0]
    sub.text = st.unit.text
    sub.pos = st.next_pos
    sub.line = st.next_line
    return ow_skip_to(st, lab, kw_bit(OW_ENDSUB), "sub without endsub")


cdef int ow_while(CState *st, const NgcLabel *lab, const char *p, const char *eol) noexcept nogil:
    """`while`: the end of a do loop of the same label, else a while loop's test."""
    cdef NgcState *n = st.ngc
    cdef NgcFrame *f
    cdef bint cond
    if ow_condition(st, p, eol, &cond) != 0:
        return R_ERR
    if n.n_frames > 0 and n.frames[n.n_frames - 1].kind == OF_DO and ow_same(&n.frames[n.n_frames - 1].label, lab):
        f = &n.frames[n.n_frames - 1]
        if cond:
            st.jpos = f.pos
            st.jline = f.line
            return R_JUMP
        n.n_frames -= 1
        return R_NEXT
    if not cond:
        return ow_skip_to(st, lab, kw_bit(OW_ENDWHILE), "while without endwhile")
    f = ow_push(st, OF_WHILE, lab)
    if f == NULL:
        return R_ERR
    f.pos = st.cur_pos
    f.line = st.line
    return R_NEXT


cdef int ow_end_loop(CState *st, const NgcLabel *lab, int kind, const char *what) noexcept nogil:
    """endwhile / endrepeat: back to the loop's test / the next pass."""
    cdef NgcState *n = st.ngc
    cdef NgcFrame *f
    if n.n_frames == 0 or n.frames[n.n_frames - 1].kind != kind or not ow_same(&n.frames[n.n_frames - 1].label, lab):
        return ow_error(st, lab, what)
    f = &n.frames[n.n_frames - 1]
    if kind == OF_REPEAT:
        f.count -= 1
        if f.count <= 0:
            n.n_frames -= 1
            return R_NEXT
    else:
        n.n_frames -= 1
    st.jpos = f.pos
    st.jline = f.line
    return R_JUMP


cdef int ow_break(CState *st, const NgcLabel *lab, bint cont) noexcept nogil:
    """break: past the loop's end; continue: to the loop's next test."""
    cdef NgcState *n = st.ngc
    cdef int k = ow_loop_frame(st, lab), found
    cdef int kind
    cdef uint32_t end
    if k < 0:
        return ow_error(st, lab, "continue outside its loop" if cont else "break outside its loop")
    kind = n.frames[k].kind
    end = kw_bit(OW_ENDWHILE) if kind == OF_WHILE else (kw_bit(OW_WHILE) if kind == OF_DO else kw_bit(OW_ENDREPEAT))
    n.n_frames = k + 1
    if cont and kind == OF_WHILE:
        n.n_frames = k                  # the while line tests again and reopens the loop
        st.jpos = n.frames[k].pos
        st.jline = n.frames[k].line
        return R_JUMP
    if ow_scan(st, lab, end, st.next_pos, st.next_line, &found) != 0:
        return ow_error(st, lab, "loop without its end")
    if cont:
        st.jpos = st.skip_pos           # the do's while / the endrepeat runs the next pass
        st.jline = st.skip_line
    else:
        n.n_frames = k
    return R_JUMP


cdef uint64_t ow_if_key(const NgcLabel *lab) noexcept nogil:
    """A label as a key of NgcState.if_keys: a number + 1, a name's hash (the labels'
    FNV-1a) with the top bit set (never 0)."""
    if lab.number >= 0:
        return <uint64_t>lab.number + 1
    return lb_hash_name(lab.name, lab.len) | (1ULL << 63)


cdef bint ow_if_seen(NgcState *n, const NgcLabel *lab, bint add) noexcept nogil:
    """Whether an `if` of label lab was executed; add: record that one is (False only
    when out of memory)."""
    cdef uint64_t key = ow_if_key(lab)
    cdef uint64_t *old = n.if_keys
    cdef size_t cap = n.cap_if_keys, i, k
    if cap > 0:
        i = <size_t>(key * 11400714819323198485ULL) & (cap - 1)
        while n.if_keys[i] != 0:
            if n.if_keys[i] == key:
                return True
            i = (i + 1) & (cap - 1)
    if not add:
        return False
    if 2 * (n.n_if_keys + 1) > cap:
        n.cap_if_keys = 64 if cap == 0 else 2 * cap
        n.if_keys = <uint64_t *>tc_calloc(n.cap_if_keys, sizeof(uint64_t))
        if n.if_keys == NULL:
            n.if_keys = old
            n.cap_if_keys = cap
            return False
        n.n_if_keys = 0
        for k in range(cap):
            if old[k] != 0:
                _if_key_put(n, old[k])
        free(old)
    _if_key_put(n, key)
    return True


cdef void _if_key_put(NgcState *n, uint64_t key) noexcept nogil:
    """Puts an `if` label's key into the open-addressed table of executed ones (room for it is
    there)."""
    cdef size_t i = <size_t>(key * 11400714819323198485ULL) & (n.cap_if_keys - 1)
    while n.if_keys[i] != 0:
        i = (i + 1) & (n.cap_if_keys - 1)
    n.if_keys[i] = key
    n.n_if_keys += 1


cdef int ow_statement(CState *st, const char *p, const char *eol) noexcept nogil:
    """An O-word line in the ISO mode: R_NEXT / R_JUMP / R_ERR, or R_NOT_O when the line
    is no O-word statement (an O word alone is a program number)."""
    cdef NgcState *n = st.ngc
    cdef NgcLabel lab
    cdef NgcFrame *f
    cdef const char *o = lx_skip_ws(p, eol)
    cdef const char *q
    cdef int kw = 0, k
    cdef double v
    cdef bint cond
    cdef char why[112]
    q = ow_line(o, eol, &lab, &kw)
    if q == NULL:
        # o[expression] call: the label computed
        if o < eol and (o[0] == b'O' or o[0] == b'o') and lx_skip_ws(o + 1, eol) < eol \
                and lx_skip_ws(o + 1, eol)[0] == b'[':
            q = lx_skip_ws(o + 1, eol)
            st.ngc.col = column_of(st, o)
            if ngc_expression(st, &q, eol, &v, 0) != 0:
                return R_ERR
            q = lx_skip_ws(q, eol)
            k = lx_alpha_run(q, eol)
            if ow_keyword(q, k) != OW_CALL:
                return err_ngc_unsupported(st.err, st.unit.file_idx, st.line, cword_rest(st, o, eol), column_of(st, o), "a computed O-word label is read on a call only")
            if not (fabs(v - floor(v + 0.5)) < NGC_TOLERANCE_WHOLE and v > -0.5 and v < 999999999999.5):
                c_snprintf(why, sizeof(why), "the computed label %g is no subroutine number "
                           "(a whole number 0 .. 999999999999)", v)
                return err_ngc_word(st.err, st.unit.file_idx, st.line, cword_rest(st, o, eol), column_of(st, o), why)
            lab.number = <int64_t>floor(v + 0.5)
            lab.len = 0
            lab.name[0] = 0
            return ow_call(st, &lab, q + k, eol)
        return R_NOT_O
    while o < eol and not (o[0] == b'O' or o[0] == b'o'):
        o += 1                          # past an N number
    st.ngc.col = column_of(st, o)
    if kw == OW_SUB:
        return ow_sub(st, &lab, q, eol)
    if kw == OW_ENDSUB or kw == OW_RETURN:
        return ow_return(st, &lab, q, eol)
    if kw == OW_CALL:
        return ow_call(st, &lab, q, eol)
    if kw == OW_IF:
        if ow_condition(st, q, eol, &cond) != 0:
            return R_ERR
        if not ow_if_seen(n, &lab, True):
            return err_out_of_memory(st.err, st.unit.file_idx, st.line)
        return R_NEXT if cond else ow_if_false(st, &lab)
    if kw == OW_ELSEIF or kw == OW_ELSE:
        # reached from a branch that ran: past the endif
        return ow_skip_to(st, &lab, kw_bit(OW_ENDIF), "else without endif")
    if kw == OW_ENDIF:
        if fl_rest_of_line(st, q, eol) != 0:
            return R_ERR
        if not ow_if_seen(n, &lab, False) and ngc_refused(st, ow_label_text(st, &lab), st.ngc.col,
                                                          "an endif whose label no if has",
                                                          "ignores it") != 0:
            return R_ERR
        return R_NEXT
    if kw == OW_WHILE:
        return ow_while(st, &lab, q, eol)
    if kw == OW_ENDWHILE:
        if fl_rest_of_line(st, q, eol) != 0:
            return R_ERR
        return ow_end_loop(st, &lab, OF_WHILE, "endwhile without its while")
    if kw == OW_DO:
        if fl_rest_of_line(st, q, eol) != 0:
            return R_ERR
        f = ow_push(st, OF_DO, &lab)
        if f == NULL:
            return R_ERR
        f.pos = st.next_pos
        f.line = st.next_line
        return R_NEXT
    if kw == OW_REPEAT:
        if ngc_value(st, &q, eol, &v, 0) != 0 or fl_rest_of_line(st, q, eol) != 0:
            return R_ERR
        if not (floor(v + 0.5) >= 1.0):
            return ow_skip_to(st, &lab, kw_bit(OW_ENDREPEAT), "repeat without endrepeat")
        f = ow_push(st, OF_REPEAT, &lab)
        if f == NULL:
            return R_ERR
        f.pos = st.next_pos
        f.line = st.next_line
        f.count = <int64_t>floor(v + 0.5) if v < 1e15 else <int64_t>1000000000000000
        return R_NEXT
    if kw == OW_ENDREPEAT:
        if fl_rest_of_line(st, q, eol) != 0:
            return R_ERR
        return ow_end_loop(st, &lab, OF_REPEAT, "endrepeat without its repeat")
    if fl_rest_of_line(st, q, eol) != 0:
        return R_ERR
    return ow_break(st, &lab, kw == OW_CONTINUE)


cdef int ow_unclosed(CState *st) noexcept nogil:
    """At the end of a text: an O-word loop still open is an error on its line."""
    cdef NgcState *n = st.ngc
    cdef NgcFrame *f
    if n == NULL or n.n_frames == 0:
        return 0
    f = &n.frames[n.n_frames - 1]
    st.line = f.line if f.kind == OF_WHILE else f.line - 1     # do / repeat keep the line after them
    st.ngc.col = 1
    if f.kind == OF_WHILE:
        return ow_error(st, &f.label, "while without endwhile")
    if f.kind == OF_DO:
        return ow_error(st, &f.label, "do without its while")
    if f.kind == OF_REPEAT:
        return ow_error(st, &f.label, "repeat without endrepeat")
    return ow_error(st, &f.label, "the text ends inside the subroutine")
