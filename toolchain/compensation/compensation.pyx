# Tool radius compensation G41-G48 / G40: the tool centre path of every compensated
# part (Part.ce, PartExtra.radius) and the parts inserted at outer corners.
#
# One pass over the program, O(n), that takes the parts in batches as the compiler
# finishes them (compensate_feed, run beside the compiler by pipeline.pyx):
#   1. split the program into runs of parts with comp 41/42 (strategy 0x80000000 first
#      merges G40..G41 pairs without a move between and drops a leading G41: that
#      needs the whole program, so the pass then waits for its end);
#   2. inside a run, the motion parts in the plane become offset elements; they form
#      chains between the entry ramp (G41 block or G0) and the exit (G40 block or G0);
#   3. each new element resolves its corner with the top of a stack of open elements;
#      an element the corners trimmed past itself (crossing offsets) is popped and the
#      corner recomputed with the one before, at most `depth` times (strategy 0x700;
#      0x80000), or kept as the offsets give it (a lenient chain: the default, the
#      vendor's, with warning 601 where the path cuts into the contour), or error 504
#      (the strict mode);
#   4. elements deeper than the search depth are final: their ends are written to the
#      parts and their corner insertions queued;
#   5. one merge pass rebuilds the part array with the insertions and gives the parts
#      without motion in the plane the compensated position they sit at.
from libc.stdlib cimport free
from libc.string cimport memcpy, memset, memchr
from libc.stdio cimport snprintf
from libc.math cimport fabs, sin, M_PI


cdef void _comp_deliver(CompState *S) noexcept nogil:
    """The kept warnings, in order, to `output` (text) and `warn` (numbered)."""
    cdef char text[300]
    cdef ErrorInfo info
    cdef const CompWarning *w
    cdef int k
    for k in range(S.n_warnings):
        w = &S.warnings[k]
        if w.number == 0:
            snprintf(text, sizeof(text), "Warning: tool radius compensation: further warnings suppressed")
        else:
            if w.number == WARN_COMP:
                warn_comp(&info, w.file_idx, <int32_t>w.line, w.what)
                snprintf(text, sizeof(text), "Warning: tool radius compensation, line %u: %s", w.line, w.what)
            else:       # WARN_COMP_GOUGE
                warn_comp_gouge(&info, w.file_idx, <int32_t>w.line, w.line, w.depth)
                snprintf(text, sizeof(text), "Warning: tool radius compensation, line %u: %s", w.line, info.text)
            if S.warn != NULL:
                info.n_lines = <int32_t>S.prog.n_lines
                S.warn(S.ctx, &info)
        if S.output != NULL:
            S.output(S.ctx, 0, text)


cdef bint _write_el(CompState *S, const CompEl *el) noexcept nogil:
    """The element is final: its end goes to the part, its insertion to the queue."""
    cdef Part *p = &S.prog.parts[el.part]
    cdef Part *entry
    cdef int xres = cross_write(S, <CompEl *>el)     # loops: may move el's start or remove el
    if xres != X_WRITE:
        return xres == X_DONE
    p.ce[S.first] = el.pe[0]
    p.ce[S.second] = el.pe[1]
    if el.kind == EL_ARC:
        # a trimmed arc of no length would read as a full circle: it becomes a point
        # (one trimmed past itself, kept by a lenient chain, turns the long way round:
        # what its offset gives from its start to its end)
        part_set_radius(S.prog, p, el.ro if fabs(el_path_sweep(el)) > TURN_EPS else 0.0)
    S.role[el.part] = ROLE_SET
    if el.first and S.entry_part >= 0:
        entry = &S.prog.parts[S.entry_part]
        entry.ce[S.first] = el.ps[0]
        entry.ce[S.second] = el.ps[1]
        S.entry_part = -1
    if el.ins != INS_NONE:
        return ins_add(S, el)
    return True


cdef bint _flush(CompState *S, size_t keep) noexcept nogil:
    """Writes all open elements but the last `keep`; they can no longer change."""
    cdef size_t n, k
    if S.n_st <= keep:
        return True
    n = S.n_st - keep
    for k in range(n):
        if not _write_el(S, &S.st[k]):
            return False
    memcpy(S.st, &S.st[n], keep * sizeof(CompEl))
    S.n_st = keep
    return True


cdef bint _push(CompState *S, const CompEl *el) noexcept nogil:
    """One more open element on the stack; past about four times the search depth, all but the
    last depth + 1 are written (they can no longer change) and a chain's path before them is
    checked for gouges at once. False when memory is exhausted or the check fails."""
    if not grow(<void **>&S.st, &S.cap_st, S.n_st + 1, sizeof(CompEl)):
        return False
    S.st[S.n_st] = el[0]
    S.n_st += 1
    # flushing in batches of 3 x depth keeps the copying of the kept tail small; the
    # path that can no longer change is checked at once, beside the compiler
    if S.cfg.depth < (<size_t>-1) / 8 and S.n_st > 4 * S.cfg.depth + 2:
        return _flush(S, S.cfg.depth + 1) and \
            (not S.chain_open or S.chain_global or S.chain_radius == 0 or cl_chain_upto(S, S.st[0].part))
    return True


cdef inline bint _can_pop(const CompState *S, const CompEl *a) noexcept nogil:
    """Whether a crossing may remove element a: the first of a chain only with
    CORR_ALLOW_FIRST_LAST_CROSS (0x10000) and a perpendicular entry (its start not fixed)."""
    if a.first:
        return (S.cfg.strategy & CORR_ALLOW_FIRST_LAST_CROSS) != 0 and not a.fixed_start
    return True


cdef void _start_chain(CompState *S, CompEl *b) noexcept nogil:
    """Element b opens a chain: its tool path starts at its offset point, or where it was
    programmed when the entry is fixed (a ramp, strategy 1, G0)."""
    b.first = True
    b.fixed_start = S.next_fixed
    if b.fixed_start:
        b.ps[0] = b.s[0]; b.ps[1] = b.s[1]
    else:
        b.ps[0] = b.os[0]; b.ps[1] = b.os[1]
    S.next_fixed = False


cdef int _chain_add(CompState *S, CompEl *b) noexcept nogil:
    """Joins element b to the open chain (steps 3 and 4)."""
    cdef CompEl *a
    cdef size_t pops = 0
    cdef int res
    if S.n_st == 0:
        _start_chain(S, b)
        return COMPILE_OK if _push(S, b) else err_out_of_memory(S.err, comp_file(S, b.part), comp_line(S, b.part))
    while True:
        a = &S.st[S.n_st - 1]
        res = corner_resolve(a, b, &S.cfg)
        if res == CORNER_NOT_FOUND:
            if (S.cfg.strategy & CORR_ALLOW_REVERSE_SEARCH) and _can_pop(S, a) and pops < S.cfg.depth \
                    and S.n_st > 1:
                # search back: the offsets may meet an earlier element's
                comp_warn(S, a.part, "part removed: no intersection with the next part")
                comp_discard(S, a.part)
                S.n_st -= 1
                pops += 1
                continue
            if (S.cfg.strategy & CORR_JOIN_BY_G1) or cross_join(S, a, b):
                a.pe[0] = a.oe[0]; a.pe[1] = a.oe[1]
                a.ins = INS_G1
                a.ins_end[0] = b.os[0]; a.ins_end[1] = b.os[1]
                b.ps[0] = b.os[0]; b.ps[1] = b.os[1]
                comp_warn(S, a.part, "intersection of equidistants not found, joined by G1")
            elif S.cfg.strategy & CORR_JOIN_BY_MOVING_START:
                a.pe[0] = a.oe[0]; a.pe[1] = a.oe[1]
                b.ps[0] = a.oe[0]; b.ps[1] = a.oe[1]
                comp_warn(S, a.part, "intersection of equidistants not found, start point moved")
            else:
                return err_comp_not_found(S.err, comp_file(S, a.part), comp_line(S, a.part))
        if el_path_length(a) < -S.cfg.slack:
            # the corners trimmed a past itself: the offsets cross here
            if not (S.cfg.strategy & CORR_REMOVE_CROSSING) or not _can_pop(S, a) or pops >= S.cfg.depth:
                if S.lenient:
                    break           # a stays as the offsets give it: the gouge check measures it
                return err_comp_crossing(S.err, comp_file(S, a.part), comp_line(S, a.part), fabs(a.d))
            comp_warn(S, a.part, "crossing part removed from the path")
            comp_discard(S, a.part)
            S.n_st -= 1
            pops += 1
            if S.n_st == 0:
                _start_chain(S, b)
                break
            continue
        break
    return COMPILE_OK if _push(S, b) else err_out_of_memory(S.err, comp_file(S, b.part), comp_line(S, b.part))


cdef void _chain_close_corner(CompState *S) noexcept nogil:
    """0x80000: a closed contour entered and left on perpendiculars (strategy 0, or
    a G0) at a corner where its tool path turns inwards: the last element's end and
    the first one's start cross there, the tool cutting into both lines. They are
    trimmed to the offsets' intersection, the entry ramp ends there and the exit
    leaves from there, as for any two neighbours whose offsets cross (what the
    regions would give, without rebuilding). Only while the first element is still
    open (a chain of at most 4 x depth + 2 elements); otherwise, or when the trim
    would take either element past itself, the gouge check and the regions decide."""
    cdef CompEl *a
    cdef CompEl *b
    cdef double ta[2]
    cdef double tb[2]
    cdef double ref[2]
    cdef double x[2]
    cdef double a_pe[2]
    cdef double b_ps[2]
    cdef double cr
    if not (S.cfg.strategy & CORR_REMOVE_CROSSING) or S.lenient or S.n_st < 2 or S.entry_part < 0:
        return
    a = &S.st[S.n_st - 1]
    b = &S.st[0]
    if not b.first or b.fixed_start or a.d != b.d or a.ins != INS_NONE \
            or distance2d(a.e[0] - b.s[0], a.e[1] - b.s[1]) > LENGTH_EPS:
        return
    el_tangent(a, True, ta)
    el_tangent(b, False, tb)
    cr = ta[0] * tb[1] - ta[1] * tb[0]
    if a.d * cr <= 0 or fabs(cr) < S.cfg.sin_tol:
        return                      # tangent, or the tool outside the turn: no crossing
    ref[0] = 0.5 * (a.oe[0] + b.os[0])
    ref[1] = 0.5 * (a.oe[1] + b.os[1])
    if not el_intersect(a, b, ref, S.cfg.slack, x):
        return
    a_pe[0] = a.pe[0]; a_pe[1] = a.pe[1]
    b_ps[0] = b.ps[0]; b_ps[1] = b.ps[1]
    a.pe[0] = x[0]; a.pe[1] = x[1]
    b.ps[0] = x[0]; b.ps[1] = x[1]
    if el_path_length(a) < -S.cfg.slack or el_path_length(b) < -S.cfg.slack:
        a.pe[0] = a_pe[0]; a.pe[1] = a_pe[1]
        b.ps[0] = b_ps[0]; b.ps[1] = b_ps[1]


cdef int _chain_end_corners(CompState *S, bint fixed_end) noexcept nogil:
    """Closes the chain of corners: the last element ends on its perpendicular, or
    (strategy 1, before G40) at its programmed end."""
    cdef CompEl *a
    while S.n_st > 0:
        a = &S.st[S.n_st - 1]
        a.ins = INS_NONE
        if fixed_end:
            a.pe[0] = a.e[0]; a.pe[1] = a.e[1]
            break
        a.pe[0] = a.oe[0]; a.pe[1] = a.oe[1]
        if el_path_length(a) >= -S.cfg.slack:
            break
        if not (S.cfg.strategy & CORR_REMOVE_CROSSING) or not (S.cfg.strategy & CORR_ALLOW_FIRST_LAST_CROSS) \
                or S.n_st == 1:
            if S.lenient:
                break
            return err_comp_crossing(S.err, comp_file(S, a.part), comp_line(S, a.part), fabs(a.d))
        comp_warn(S, a.part, "crossing last part removed from the path")
        comp_discard(S, a.part)
        S.n_st -= 1
    if not fixed_end:
        _chain_close_corner(S)
    S.xs.last_part = S.st[S.n_st - 1].part if S.n_st > 0 else <size_t>-1
    if not _flush(S, 0):
        # no memory, or a crossing _chain_fallback reports (S.xs.err_*)
        return err_out_of_memory(S.err, comp_file(S, S.chain_first), comp_line(S, S.chain_first))
    if not cross_chain_end(S):
        return comp_search_error(S)
    S.entry_part = -1
    return COMPILE_OK


cdef void _chain_open(CompState *S, size_t k) noexcept nogil:
    """Part k is the first element of a chain."""
    S.chain_open = True
    S.chain_global = False
    S.chain_first = k
    S.chain_last = k
    S.chain_entry = S.entry_part
    S.chain_fixed = S.next_fixed
    S.chain_entry_arc = S.entry_arc
    S.chain_ins0 = S.n_ins
    S.chain_warn0 = S.n_warnings
    S.chain_radius = 0.0
    if not S.retrying:
        S.lenient = not S.strict and not (S.cfg.strategy & CORR_REMOVE_CROSSING)
    cl_chain_open(S, k, S.n_ins)


cdef int _chain_fallback(CompState *S, int res) noexcept nogil:
    """A failure of the chain of corners: with 0x80000 a crossing or gouge it could
    not cut (504, 500) makes the chain global (rebuilt from its regions at its end;
    a lenient chain is not)."""
    if res == COMPILE_OK:
        return res
    if S.xs.err_number != 0:
        comp_search_error(S)
        S.xs.err_number = 0
    if not (S.cfg.strategy & CORR_REMOVE_CROSSING) or not S.chain_open or S.lenient or \
            (S.err.number != ERR_COMP_CROSSING and S.err.number != ERR_COMP_NOT_FOUND):
        return res
    memcpy(&S.chain_err, S.err, sizeof(ErrorInfo))
    S.chain_global = True
    S.n_st = 0
    box_index_clear(&S.xs.ix)
    S.xs.n_prov = 0
    S.xs.head_prov = 0
    return COMPILE_OK


cdef int _chain_rebuild(CompState *S) noexcept nogil:
    """The global chain from its regions, its path checked (a gouge left: warning 601,
    strict: error 504); REGIONS_NOT_APPLICABLE when the regions do not give a path."""
    cdef int res = regions_rebuild(S)
    cdef bint lenient = S.lenient
    if res != COMPILE_OK:
        return res
    S.chain_rebuilt = True
    # the rebuilt path keeps the radius from the whole contour, not only within the depth
    S.lenient = not S.strict
    if not cl_check_chain(S, S.chain_first, S.chain_last, S.chain_ins0, False, False,
                          S.chain_last - S.chain_first):
        res = comp_search_error(S)
        S.xs.err_number = 0
    S.lenient = lenient
    return res


cdef int _chain_retry(CompState *S, bint fixed_end, bint exit_fixed) noexcept nogil:
    """0x80000 without the strict switch: a chain its regions cannot rebuild (an open
    one, one that changes its radius, ...) is read again from its first part, lenient:
    the corners and the loop search remove what they can, the rest stays as the
    offsets give it, with warning 601 where the tool cuts into the contour. Everything
    the first reading wrote for the chain's parts is written again."""
    cdef size_t k, last = S.chain_last
    cdef const PartExtra *x
    cdef int res = COMPILE_OK
    cdef Part *p
    cdef const double *st
    S.n_ins = S.chain_ins0
    S.n_warnings = S.chain_warn0
    for k in range(S.chain_first, last + 1):
        p = &S.prog.parts[k]
        if p.kind == PART_MOTION and (p.func == 2 or p.func == 3):
            # a removed arc (radius 0) is an arc again (_in_plane_motion)
            st = part_start_xyz(S.prog, k)
            x = part_extra(S.prog, p)
            part_set_radius(S.prog, p, distance2d(st[S.first] - x.cc[S.first], st[S.second] - x.cc[S.second]))
    S.entry_part = S.chain_entry
    S.next_fixed = S.chain_fixed
    S.entry_arc = S.chain_entry_arc
    S.idle = 0
    S.n_st = 0
    box_index_clear(&S.xs.ix)
    S.xs.n_prov = 0
    S.xs.head_prov = 0
    S.xs.err_number = 0
    S.xs.last_part = <size_t>-1
    S.chain_open = False
    S.chain_global = False
    S.retrying = True
    S.lenient = True
    k = S.chain_first
    while k <= last and res == COMPILE_OK:
        res = _run_part(S, k)
        k += 1
    if res == COMPILE_OK:
        res = _chain_end(S, fixed_end, exit_fixed)
    S.retrying = False
    return res


cdef int _chain_end(CompState *S, bint fixed_end, bint exit_fixed) noexcept nogil:
    """Closes the chain (fixed_end: its last line ends at its programmed end;
    exit_fixed: strategy 1 before G40), checks that its path keeps the tool radius
    from the contour, and rebuilds it from its regions when it does not (0x80000);
    when they do not apply, the error that made it global stands (strict) or the
    chain is read again, lenient (_chain_retry)."""
    cdef int res = COMPILE_OK
    S.chain_rebuilt = False
    S.chain_exit_fixed = exit_fixed
    if not S.chain_global:
        res = _chain_end_corners(S, fixed_end)
        if res == COMPILE_OK and S.chain_open and S.chain_radius > 0 and \
                not cl_chain_close(S, S.chain_last, S.chain_fixed, fixed_end):
            res = COMPILE_ERROR
        res = _chain_fallback(S, res)
    if res == COMPILE_OK and S.chain_global:
        res = _chain_rebuild(S)
        if res == REGIONS_NOT_APPLICABLE and S.strict:
            memcpy(S.err, &S.chain_err, sizeof(ErrorInfo))
            res = COMPILE_ERROR
        elif res == REGIONS_NOT_APPLICABLE:
            return _chain_retry(S, fixed_end, exit_fixed)
    S.chain_open = False
    S.chain_global = False
    S.n_st = 0
    S.entry_part = -1
    return res


cdef bint _in_plane_motion(const CompState *S, size_t k, bint *is_arc) noexcept nogil:
    """Whether part k moves in the compensation plane (arcs always do)."""
    cdef const Part *p = &S.prog.parts[k]
    cdef const double *s
    cdef double dx, dy
    is_arc[0] = False
    if p.kind != PART_MOTION:
        return False
    if (p.func == 2 or p.func == 3) and part_extra(S.prog, p).radius > 0:
        is_arc[0] = True
        return True
    s = part_start_xyz(S.prog, k)
    dx = p.e[S.first] - s[S.first]
    dy = p.e[S.second] - s[S.second]
    return dx * dx + dy * dy > LENGTH_EPS * LENGTH_EPS


cdef int _run_begin(CompState *S, size_t i) noexcept nogil:
    """A run of parts with comp 41/42 starts at part i."""
    S.g0_never = (S.cfg.strategy & CORR_G0_NEVER_COMPENSATED) != 0
    S.plane = S.prog.parts[i].plane
    if not plane_axes(S.plane, &S.first, &S.second, &S.normal):
        return err_comp_plane_change(S.err, comp_file(S, i), comp_line(S, i))
    S.entry_part = -1
    S.next_fixed = False
    S.n_st = 0
    S.first_motion = True
    S.entry_arc = False
    S.idle = 0
    S.in_run = True
    S.chain_open = False
    S.chain_global = False
    return COMPILE_OK


cdef int _run_part(CompState *S, size_t k) noexcept nogil:
    """Part k of the run: an element of the chain, a ramp, a rapid or a part without
    motion in the plane."""
    cdef Program *prog = S.prog
    cdef Part *p = &prog.parts[k]
    cdef CompEl el
    cdef bint is_arc
    cdef int res
    if p.plane != S.plane:
        return err_comp_plane_change(S.err, comp_file(S, k), comp_line(S, k))
    S.role[k] = ROLE_FOLLOW
    if not _in_plane_motion(S, k, &is_arc):
        S.has_followers = True
        S.idle += 1
        if S.idle > LOOKAHEAD_PARTS and S.n_st > 0:
            return err_comp_lookahead(S.err, comp_file(S, k), comp_line(S, k), LOOKAHEAD_PARTS)
        return COMPILE_OK
    S.idle = 0
    if S.first_motion and is_arc:
        # G41/G42 without a move of its own before an arc: an inserted line goes
        # to the arc's perpendicular and the arc is compensated whole
        S.first_motion = False
        if k == 0:
            return err_comp_on_arc(S.err, comp_file(S, k), comp_line(S, k))
        S.entry_arc = True
    elif S.first_motion:
        # the G41/G42 block: a line to the perpendicular of the next part (strategy 0)
        # or an uncompensated move (strategy 1, G0 never compensated)
        S.first_motion = False
        S.role[k] = ROLE_SET
        if S.cfg.mode == 1 or (p.func == 0 and S.g0_never):
            S.next_fixed = True
        else:
            S.entry_part = k
        return COMPILE_OK
    if p.func == 0:
        # a rapid leaves the contour on the perpendicular and re-enters it like G41
        res = _chain_end(S, False, False)
        if res != COMPILE_OK:
            return res
        S.role[k] = ROLE_SET
        if S.g0_never:
            S.next_fixed = True
        else:
            S.next_fixed = False
            S.entry_part = k
        return COMPILE_OK
    if not comp_part_element(S, k, &el):
        return COMPILE_OK           # an arc about its own start: nothing to offset
    if not S.chain_open:
        _chain_open(S, k)
    S.chain_last = k
    if fabs(el.d) > S.chain_radius:
        S.chain_radius = fabs(el.d)
    if S.chain_global:
        return COMPILE_OK           # rebuilt from the regions at the chain's end
    if is_arc:
        if el.ro <= LENGTH_EPS * el.R:
            if el.ro < -LENGTH_EPS * el.R:
                if not (S.cfg.strategy & CORR_DROP_NEGATIVE_ARCS):
                    return err_comp_negative_arc(S.err, comp_file(S, k), comp_line(S, k), el.R, fabs(el.d))
                comp_warn(S, k, "arc with negative equidistant removed")
            # an offset of no radius is a point the neighbours' offsets pass through; the
            # arc leaves the cutting plan (correctionStrategy 0x200000): no driver sees it
            comp_discard(S, k)
            if not (S.prog.parts[k].flags & FLAG_HELIX):
                S.prog.parts[k].flags |= FLAG_DROPPED
                S.dropped = True
            return COMPILE_OK
        if el.ro < S.cfg.min_arc:
            # below the minimum arc radius (tolerance[4]): removed the same way
            comp_warn(S, k, "arc with an offset radius below tolerance[4] removed")
            comp_discard(S, k)
            return COMPILE_OK
        if S.entry_arc or (S.n_st == 0 and S.next_fixed):
            # the chain starts on an arc: switch on by a line to its perpendicular
            S.entry_arc = False
            S.next_fixed = False
            S.entry_part = -1
            if not _flush(S, 0) or not ins_line(S, k - 1, k, el.os):
                return err_out_of_memory(S.err, comp_file(S, k), comp_line(S, k))
            S.chain_fixed = False
            comp_warn(S, k, "compensation switched on before an arc: line to its perpendicular inserted")
    return _chain_fallback(S, _chain_add(S, &el))


cdef int _run_end(CompState *S, size_t j, bint g40) noexcept nogil:
    """The run ends before part j: at a part with comp 40 (g40), or at the end of the
    program. Strategy 1 ends the last part before G40 uncompensated (a line)."""
    cdef size_t k
    cdef double pe[2]
    cdef int res
    cdef bint exit_fixed = S.cfg.mode == 1 and g40
    S.in_run = False
    if exit_fixed and not S.chain_global and S.n_st > 0 and S.st[S.n_st - 1].kind == EL_LINE:
        res = _chain_end(S, True, True)
    elif exit_fixed and not S.chain_global and S.n_st > 0:
        # the last move before G40 is an arc: it stays compensated, a line leaves it
        k = S.st[S.n_st - 1].part
        pe[0] = S.st[S.n_st - 1].e[0]; pe[1] = S.st[S.n_st - 1].e[1]
        res = _chain_end(S, False, True)
        if res == COMPILE_OK and not S.chain_rebuilt:
            if not ins_line(S, k, k, pe):
                return err_out_of_memory(S.err, comp_file(S, k), comp_line(S, k))
            comp_warn(S, k, "compensation switched off after an arc: line to the programmed end inserted")
    else:
        res = _chain_end(S, False, exit_fixed)
    # G40 only on a linear move: checked on the parts from j on (compensate_feed)
    S.exit_check = g40
    S.exit_from = j
    return res


cdef int _exit_part(CompState *S, size_t k) noexcept nogil:
    """Part k after a run: the first move in the plane within LOOKAHEAD_PARTS must
    not be an arc; the check ends there or at the next compensated part."""
    cdef bint is_arc
    if k - S.exit_from > LOOKAHEAD_PARTS or S.prog.parts[k].comp != 40:
        S.exit_check = False
    elif _in_plane_motion(S, k, &is_arc):
        S.exit_check = False
        if is_arc:
            return err_comp_on_arc(S.err, comp_file(S, k), comp_line(S, k))
    return COMPILE_OK


cdef void _compatibility(Program *prog) noexcept nogil:
    """Strategy 0x80000000: ignore a G41/G42 before any move, and G40 .. G41/G42 pairs
    with no move between them."""
    cdef size_t k, m, b, n = prog.n_parts
    cdef bint moved = False
    cdef Part *p
    k = 0
    while k < n:
        p = &prog.parts[k]
        if p.comp != 40 and not moved:
            while k < n and prog.parts[k].comp != 40:
                prog.parts[k].comp = 40
                if prog.parts[k].kind == PART_MOTION:
                    moved = True
                k += 1
            continue
        if p.kind == PART_MOTION:
            moved = True
        if p.comp != 40 and k + 1 < n and prog.parts[k + 1].comp == 40:
            # after the run: a bridge of parts without motion up to the next G41/G42?
            m = k + 1
            while m < n and prog.parts[m].comp == 40 and prog.parts[m].kind != PART_MOTION:
                m += 1
            if m < n and prog.parts[m].comp != 40:
                for b in range(k + 1, m):
                    prog.parts[b].comp = p.comp
                    prog.parts[b].comp_slot = p.comp_slot
                    prog.parts[b].radius_idx = p.radius_idx
        k += 1


cdef void _inserted_part(ProgramBuilder *build, Part *q, const Part *p, const Part *src, const InsRec *rec,
                         const GCODE_PARAMETERS *params) noexcept nogil:
    """An inserted part after p (its programmed end is p's end), with the line, feed
    and compensation of src; an arc goes round its corner (rec.cc) with p's tool
    radius, its record from the room the merge reserved."""
    cdef int first, second, normal
    cdef PartExtra *arc
    part_inserted(build, q, p, src, rec.func, src.plane)
    plane_axes(p.plane, &first, &second, &normal)
    q.ce[first] = rec.end[0]; q.ce[second] = rec.end[1]
    if rec.func == INS_G1:
        return
    arc = program_part_extra(build, q)
    memcpy(arc.cc, p.e, sizeof(arc.cc))
    # the corner it goes round: normally p's end, but a loop cut may have moved
    # the remainder of a corner arc behind an earlier part
    arc.cc[first] = rec.cc[0]; arc.cc[second] = rec.cc[1]
    arc.radius = fabs(part_tool_radius(&build.prog, params, p))


cdef inline size_t _next_follow(const CompState *S, size_t k, size_t n) noexcept nogil:
    """The first part from k on with ROLE_FOLLOW, n when none."""
    cdef const uint8_t *hit
    if k >= n:
        return n
    hit = <const uint8_t *>memchr(&S.role[k], ROLE_FOLLOW, n - k)
    return <size_t>(hit - S.role) if hit != NULL else n


cdef size_t _ins_after(void *ctx, size_t rec) noexcept nogil:
    """program_merge's inserted_after_fn: the part insertion rec follows."""
    return (<CompState *>ctx).ins[rec].after


cdef void _ins_make(void *ctx, size_t rec, Part *out, const Part *before, const Part *after) noexcept nogil:
    """program_merge's make_inserted_fn: insertion rec's part (an arc round its corner or a
    line of the tool path), with the line, feed and compensation of the part before it or, by
    src_next, after it."""
    cdef CompState *S = <CompState *>ctx
    cdef const InsRec *r = &S.ins[rec]
    _inserted_part(S.build, out, before, after if r.src_next else before, r, S.params)


cdef void _settle(void *ctx, size_t first, size_t end, size_t rec) noexcept nogil:
    """Parts without motion in the plane (ROLE_FOLLOW) among [first, end) take the
    compensated position they sit at: their predecessor's (already final), after the
    insertion `rec` for one at the start of the range."""
    cdef CompState *S = <CompState *>ctx
    cdef Program *prog = S.prog
    cdef Part *p
    cdef Part *prev
    cdef double cur[3]
    cdef int a, b, c
    cdef size_t k = _next_follow(S, first, end)
    while k < end:
        p = &prog.parts[k]
        if k == 0:
            cur[0] = prog.start[0]; cur[1] = prog.start[1]; cur[2] = prog.start[2]
        else:
            prev = &prog.parts[k - 1]
            cur[0] = prev.ce[0]; cur[1] = prev.ce[1]; cur[2] = prev.ce[2]
            if k == first and rec != <size_t>NO_INSERTION and plane_axes(prev.plane, &a, &b, &c):
                cur[a] = S.ins[rec].end[0]
                cur[b] = S.ins[rec].end[1]
        settle_follower(p, cur)
        k = _next_follow(S, k + 1, end)


cdef void settle_follower(Part *p, const double *cur) noexcept nogil:
    """A part without motion in the plane inside a compensated run: its compensated end
    on the plane's two axes is where the tool stands (`cur`)."""
    cdef int a, b, c
    if plane_axes(p.plane, &a, &b, &c):
        p.ce[a] = cur[a]
        p.ce[b] = cur[b]


cdef int _merge(CompState *S, const MergeWatch *watch, uint8_t **settle_later) noexcept nogil:
    """Step 5: the inserted parts go into the program (program_merge; `watch` may
    read the merged parts beside it), and on the way the parts without motion in the
    plane take the compensated position they sit at -- with nothing to insert, in
    join_lines' pass when settle_later takes the roles."""
    cdef settle_parts_fn settle = NULL
    if S.n_ins == 0 and not S.has_followers:
        return COMPILE_OK
    if S.n_ins == 0 and settle_later != NULL:
        settle_later[0] = S.role       # join_lines frees them
        S.role = NULL
        S.cap_role = 0
        return COMPILE_OK
    if S.has_followers:
        settle = _settle
    if not program_merge(S.build, S.n_ins, S, _ins_after, _ins_make, settle, watch):
        return err_out_of_memory(S.err, comp_file(S, 0), comp_line(S, 0))
    return COMPILE_OK


cdef void compensate_begin(CompState *S, ProgramBuilder *build, const GCODE_PARAMETERS *params, ErrorInfo *err,
                           output_fn output, warn_fn warn, void *ctx) noexcept nogil:
    """Prepares the pass over build.prog; compensate_end gives its warnings to `output`
    (text) and `warn` (numbered, WARN_COMP)."""
    memset(S, 0, sizeof(CompState))
    S.build = build
    S.prog = &build.prog
    S.params = params
    S.err = err
    S.output = output
    S.warn = warn
    S.ctx = ctx
    S.strict = (<uint32_t>params.rezerva1 & GCODE_REZERVA1_COMP_STRICT) != 0
    S.xs.last_part = <size_t>-1
    comp_config(&S.host, params)
    S.cfg = S.host
    S.result = COMPILE_OK


cdef bint _role_room(CompState *S, size_t n) noexcept nogil:
    """S.role covers parts [0, n), new entries ROLE_NONE."""
    cdef size_t old = S.cap_role
    if n <= old:
        return True
    if not grow(<void **>&S.role, &S.cap_role, n, 1):
        return False
    ready_memory(S.role + old, S.cap_role - old)        # one call, not a fault a page
    memset(S.role + old, ROLE_NONE, S.cap_role - old)
    return True


cdef void _view_take(CompState *S, size_t upto) noexcept nogil:
    """S.prog becomes S.view: what the pass reads of the program's header, copied (the
    arrays move only between batches; the counts the compiler writes meanwhile are
    not read: they stay 0 here, but for n_parts: the parts the batch may read)."""
    cdef const Program *prog = &S.build.prog
    S.view.parts = prog.parts
    S.view.n_parts = upto
    S.view.extras = prog.extras
    S.view.settings = prog.settings
    S.view.radii = prog.radii
    S.view.strategy_regions = prog.strategy_regions
    S.view.n_strategy_regions = prog.n_strategy_regions
    memcpy(S.view.start, prog.start, sizeof(prog.start))
    S.view.main_file_idx = prog.main_file_idx
    S.prog = &S.view


cdef int compensate_feed(void *ctx, size_t upto, bint last, size_t *more) noexcept nogil:
    """Steps 1-4 on parts [S.next, upto), which the compiler has finished; `last`:
    upto is the end of the program; `more`: the insertions queued so far. COMPILE_OK,
    or the first failure (err filled), after which nothing more is taken (consume_fn
    of pipeline.pyx)."""
    cdef CompState *S = <CompState *>ctx
    cdef Program *prog
    cdef size_t k
    cdef int res = COMPILE_OK
    more[0] = S.n_ins
    if S.result != COMPILE_OK:
        return S.result
    if S.host.strategy & CORR_OLD_COMPATIBILITY:
        if not last:
            return COMPILE_OK
        _compatibility(S.prog)
    if not _role_room(S, upto):
        S.result = err_out_of_memory(S.err, comp_file(S, S.next if S.next < upto else 0), comp_line(S, S.next if S.next < upto else 0))
        return S.result
    _view_take(S, upto)
    prog = S.prog
    k = S.next
    while k < upto and res == COMPILE_OK:
        if S.exit_check:
            res = _exit_part(S, k)
            if res != COMPILE_OK:
                break
        if S.in_run:
            if prog.parts[k].comp == 40:
                res = _run_end(S, k, True)
                continue                    # part k is the first after the run
            res = _run_part(S, k)
        elif prog.parts[k].comp != 40:
            run_config(prog, &S.host, k, &S.region, &S.cfg)
            res = _run_begin(S, k)
            continue                        # part k is the run's first
        k += 1
    S.next = k
    if res == COMPILE_OK and last and S.in_run:
        res = _run_end(S, upto, False)
    if res != COMPILE_OK and S.xs.err_number != 0:
        comp_search_error(S)
    S.result = res
    more[0] = S.n_ins
    S.prog = &S.build.prog
    return res


cdef int compensate_end(CompState *S, const MergeWatch *watch, uint8_t **settle) noexcept nogil:
    """Step 5 after compensate_feed took the whole program: the merge (`watch`: see
    program_merge, may be NULL); then the warnings. Frees the state; COMPILE_OK or
    COMPILE_ERROR with err filled."""
    cdef int res = S.result
    if res == COMPILE_OK and not _role_room(S, S.prog.n_parts):
        res = err_out_of_memory(S.err, comp_file(S, 0), comp_line(S, 0))
    if res == COMPILE_OK:
        res = _merge(S, watch, settle)
    if S.dropped:
        S.build.renumber = True
    _comp_deliver(S)
    compensate_free(S)
    return res


cdef void compensate_free(CompState *S) noexcept nogil:
    """Frees the pass's state (crossings, clearance, regions, its arrays); safe to call
    twice."""
    cross_free(&S.xs)
    cl_free(&S.cl)
    regions_free(&S.rg)
    free(S.role)
    free(S.st)
    free(S.ins)
    S.role = NULL
    S.st = NULL
    S.ins = NULL
