# The state of one compensation pass (CompState, compensation.pxd) and what every
# step of the pass does with it: keep a warning (600, or 601 where the tool cuts into
# the contour), fail, queue an insertion, discard a part from the path, read a part's
# offset element. Shared by the crossings, the clearance, the regions and the pass
# itself (compensation.pyx).
from libc.string cimport memset
from libc.math cimport fabs


cdef CompWarning *_comp_warning(CompState *S, size_t part, int32_t number) noexcept nogil:
    """A new kept warning about part `part`, NULL when no more are kept (the last slot
    says so)."""
    cdef CompWarning *w
    if S.n_warnings >= MAX_WARNINGS:
        return NULL
    w = &S.warnings[S.n_warnings]
    S.n_warnings += 1
    w.number = number if S.n_warnings < MAX_WARNINGS else 0
    w.what = NULL
    w.depth = 0.0
    w.line = S.prog.parts[part].line
    w.file_idx = part_settings(S.prog, &S.prog.parts[part]).file_idx
    return w if w.number != 0 else NULL


cdef void comp_warn(CompState *S, size_t part, const char *what) noexcept nogil:
    """Keeps a warning about part `part` (`what`: a literal) for _comp_deliver."""
    cdef CompWarning *w = _comp_warning(S, part, WARN_COMP)
    if w != NULL:
        w.what = what


cdef void comp_gouge(CompState *S, size_t part, double depth) noexcept nogil:
    """Keeps warning 601: the tool path of part `part` cuts `depth` mm into the
    contour. One per line of the chain, with the deepest cut of its pieces (the check
    may measure a piece twice: round a closed contour's start)."""
    cdef CompWarning *w
    cdef const Part *p = &S.prog.parts[part]
    cdef int k
    for k in range(S.chain_warn0, S.n_warnings):
        w = &S.warnings[k]
        if w.number == WARN_COMP_GOUGE and w.line == p.line and w.file_idx == part_settings(S.prog, p).file_idx:
            if depth > w.depth:
                w.depth = depth
            return
    w = _comp_warning(S, part, WARN_COMP_GOUGE)
    if w != NULL:
        w.depth = depth


cdef int32_t comp_file(const CompState *S, size_t part) noexcept nogil:
    """The file of part `part`'s line for an error (the main file when there is no such part)."""
    if part >= S.prog.n_parts:
        return S.prog.main_file_idx
    return part_settings(S.prog, &S.prog.parts[part]).file_idx


cdef int32_t comp_line(const CompState *S, size_t part) noexcept nogil:
    """Part `part`'s line for an error (0 when there is no such part)."""
    return <int32_t>S.prog.parts[part].line if part < S.prog.n_parts else 0


cdef int comp_search_error(CompState *S) noexcept nogil:
    """The error the crossing search left in S.xs (number, part, argument) recorded;
    COMPILE_ERROR."""
    cdef size_t part = S.xs.err_part
    if S.xs.err_number == ERR_COMP_CROSSING:
        return err_comp_crossing(S.err, comp_file(S, part), comp_line(S, part), S.xs.err_arg)
    if S.xs.err_number == ERR_COMP_NOT_FOUND:
        return err_comp_not_found(S.err, comp_file(S, part), comp_line(S, part))
    return err_out_of_memory(S.err, comp_file(S, part), comp_line(S, part))


cdef double comp_distance(const CompState *S, const Part *p) noexcept nogil:
    """Signed offset distance of a part: left (41) positive, |its tool radius|."""
    cdef double r = fabs(part_tool_radius(S.prog, S.params, p))
    return r if p.comp == 41 else -r


cdef bint ins_add(CompState *S, const CompEl *el) noexcept nogil:
    """Records el's corner insertion (el.ins: a line or an arc round the programmed corner el.e,
    to el.ins_end) as a part after el's part, with el's attributes; False when memory is
    exhausted."""
    cdef InsRec *rec
    if S.n_ins == S.cap_ins:
        if not grow(<void **>&S.ins, &S.cap_ins, S.n_ins + 1, sizeof(InsRec)):
            return False
    ready_ahead(S.ins, (S.n_ins + 1) * sizeof(InsRec), &S.ready_ins, S.cap_ins * sizeof(InsRec))
    rec = &S.ins[S.n_ins]
    S.n_ins += 1
    rec.after = el.part
    rec.func = el.ins
    rec.end[0] = el.ins_end[0]; rec.end[1] = el.ins_end[1]
    rec.cc[0] = el.e[0]; rec.cc[1] = el.e[1]
    rec.src_next = False
    rec.no_centre = False
    return True


cdef bint ins_line(CompState *S, size_t after, size_t src, const double *end) noexcept nogil:
    """Queues a G1 after part `after` (switching on or off next to an arc); src is
    `after` or `after` + 1."""
    cdef CompEl tmp
    memset(&tmp, 0, sizeof(tmp))
    tmp.part = after
    tmp.ins = INS_G1
    tmp.ins_end[0] = end[0]; tmp.ins_end[1] = end[1]
    if not ins_add(S, &tmp):
        return False
    S.ins[S.n_ins - 1].src_next = src == after + 1
    S.ins[S.n_ins - 1].no_centre = True
    return True


cdef bint ins_arc(CompState *S, size_t after, const double *end, const double *centre, int func) noexcept nogil:
    """Queues an arc of the tool radius round `centre` after part `after` (a vertex of
    a chain rebuilt from its regions)."""
    cdef CompEl tmp
    memset(&tmp, 0, sizeof(tmp))
    tmp.part = after
    tmp.ins = func
    tmp.ins_end[0] = end[0]; tmp.ins_end[1] = end[1]
    tmp.e[0] = centre[0]; tmp.e[1] = centre[1]
    return ins_add(S, &tmp)


cdef void comp_discard(CompState *S, size_t part) noexcept nogil:
    """A part removed from the path: it stays in the program with no motion in the plane."""
    S.role[part] = ROLE_FOLLOW
    S.has_followers = True
    part_set_radius(S.prog, &S.prog.parts[part], 0.0)


cdef bint comp_part_element(const CompState *S, size_t k, CompEl *el) noexcept nogil:
    """The offset element of part k when it is a line or an arc that moves in the plane
    (not a rapid); a removed arc counts (its radius is read from its centre)."""
    cdef const Part *p = &S.prog.parts[k]
    cdef const double *s
    cdef const double *centre
    cdef double ps[2]
    cdef double pe[2]
    cdef double pc[2]
    cdef double sweep
    if p.kind != PART_MOTION or p.func == 0:
        return False
    s = part_start_xyz(S.prog, k)
    ps[0] = s[S.first]; ps[1] = s[S.second]
    pe[0] = p.e[S.first]; pe[1] = p.e[S.second]
    if p.func == 2 or p.func == 3:
        centre = part_extra(S.prog, p).cc
        pc[0] = centre[S.first]; pc[1] = centre[S.second]
        if distance2d(ps[0] - pc[0], ps[1] - pc[1]) <= LENGTH_EPS:
            return False
        sweep = arc_sweep(ps[0] - pc[0], ps[1] - pc[1], pe[0] - pc[0], pe[1] - pc[1], p.func == 3)
        return el_init(el, k, EL_ARC, 1 if p.func == 3 else -1, comp_distance(S, p), ps, pe, pc, sweep)
    if (pe[0] - ps[0]) * (pe[0] - ps[0]) + (pe[1] - ps[1]) * (pe[1] - ps[1]) <= LENGTH_EPS * LENGTH_EPS:
        return False
    return el_init(el, k, EL_LINE, 0, comp_distance(S, p), ps, pe, pc, 0.0)
