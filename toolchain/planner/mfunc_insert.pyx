# mFuncInsertTable (MfuncInsertType 1): M functions the planner inserts where the
# planned speed crosses a share of the programmed feed, at a distance along the path
# (docs/planner.md, "M functions where the plan slows down"):
#   0 before a slow-down: `distance` mm before the point where the speed of a cut
#     falls below relFeed x its programmed feed;
#   1 after it: `distance` mm after the point where it is back at relFeed x its feed
#     (entry 1's relFeed) or more;
#   2 before G0: `distance` mm before the start of a rapid that follows a cut.
# The points come from the plan's profile of each part (the one the machine runs:
# profile.pyx), the distances are measured along the tool path, across parts. Where
# the place lies inside a motion part, the part is split there: its first piece keeps
# the part's place (a programmed part), the M function follows, then the rest of the
# part (FLAG_INSERTED, with the line's addresses on the last piece). Within MFI_SNAP of
# a part's start or end the M function goes between the parts. Numbers from 1001 on
# are continuous (never stop the motion), others wait like any waiting M function; all
# carry FLAG_INSERTED. The caller plans again afterwards.
from libc.stdlib cimport free, qsort
from libc.string cimport memcmp, memcpy
from libc.math cimport acos, M_PI

cdef extern from *:
    """
    /* mm: an inserted M function this close to a part's start or end goes between
       the parts (no piece of a part shorter than this) */
    #define TC_MFI_SNAP 1e-6
    /* a speed counts as at relFeed x the feed from this much below it: the plan keeps
       floats (7 digits), a cap of F6000 / 7 is a hair under the feed */
    #define TC_MFI_REL_TOL 1e-6
    """
    const double MFI_SNAP "TC_MFI_SNAP"
    const double MFI_REL_TOL "TC_MFI_REL_TOL"

cdef bint _mfi_target_add(MfuncTargets *t, size_t part, double q, int32_t mfunc) noexcept nogil:
    """One more place for M function `mfunc`: q mm into `part`, numbered in the order found
    (several at one place keep it). False when memory is exhausted."""
    if not grow(<void **>&t.items, &t.cap, t.n + 1, sizeof(MfuncTarget)):
        return False
    t.items[t.n].part = part
    t.items[t.n].q = q
    t.items[t.n].seq = t.n
    t.items[t.n].mfunc = mfunc
    t.n += 1
    return True


cdef size_t _mfi_next_with_length(const double *at, size_t k, size_t n) noexcept nogil:
    """The first part from k on that has length (n: none)."""
    while k < n and not (at[k + 1] > at[k]):
        k += 1
    return k


cdef bint _mfi_place(MfiScan *sc, double pos, int32_t mfunc) noexcept nogil:
    """The M function `mfunc` at path position pos (clamped to the path): in the motion
    part that holds it, or between parts within MFI_SNAP of a boundary."""
    cdef const double *at = sc.at
    cdef size_t n = sc.prog.n_parts, lo = 0, hi = n, mid, m
    if pos <= at[0] + MFI_SNAP:
        return _mfi_target_add(sc.targets, _mfi_next_with_length(at, 0, n), 0.0, mfunc)
    if pos >= at[n] - MFI_SNAP:
        return _mfi_target_add(sc.targets, n, 0.0, mfunc)
    while hi - lo > 1:                  # the last part that starts before pos: it has length
        mid = (lo + hi) // 2
        if at[mid] < pos:
            lo = mid
        else:
            hi = mid
    m = lo
    if pos - at[m] <= MFI_SNAP:
        return _mfi_target_add(sc.targets, m, 0.0, mfunc)
    if at[m + 1] - pos <= MFI_SNAP:     # its end: before the next part with length
        return _mfi_target_add(sc.targets, _mfi_next_with_length(at, m + 1, n), 0.0, mfunc)
    return _mfi_target_add(sc.targets, m, pos - at[m], mfunc)


cdef double _mfi_ramp_distance_to(double v0, double v1, double T, int32_t ramp, double v) noexcept nogil:
    """Distance into the ramp from v0 to v1 (T seconds) where its speed is v."""
    cdef double u, t
    if v1 == v0 or T <= 0.0:
        return 0.0
    u = (v - v0) / (v1 - v0)
    if u <= 0.0:
        return 0.0
    if u >= 1.0:
        t = T
    elif ramp == RAMP_SINE:             # v0 + (v1 - v0) (1 - cos(pi t / T)) / 2
        t = T / M_PI * acos(1.0 - 2.0 * u)
    else:
        t = u * T
    return ramp_distance_in(v0, v1, T, ramp, t)


cdef void _mfi_fall(MfiScan *sc, double pos) noexcept nogil:
    """The speed fell below the cut's first threshold at path position pos: slow from here, the
    table's M function before a slow-down placed its distance before pos."""
    sc.state = MFI_SLOW
    if sc.table[MFI_BEFORE_SLOW_DOWN].mFunc != 0:
        sc.ok = sc.ok and _mfi_place(sc, pos - sc.table[MFI_BEFORE_SLOW_DOWN].distance,
                                 sc.table[MFI_BEFORE_SLOW_DOWN].mFunc)


cdef void _mfi_rise(MfiScan *sc, double pos) noexcept nogil:
    """The speed is back at the second threshold at path position pos: fast from here, the
    table's M function after a slow-down placed its distance after pos."""
    sc.state = MFI_FAST
    if sc.table[MFI_AFTER_SLOW_DOWN].mFunc != 0:
        sc.ok = sc.ok and _mfi_place(sc, pos + sc.table[MFI_AFTER_SLOW_DOWN].distance,
                                 sc.table[MFI_AFTER_SLOW_DOWN].mFunc)


cdef void _mfi_at_point(MfiScan *sc, double v, double pos) noexcept nogil:
    """The speed at one point (a part's start)."""
    if sc.state == MFI_START and v >= sc.th0:
        sc.state = MFI_FAST
    elif sc.state == MFI_FAST and v < sc.th0:
        _mfi_fall(sc, pos)
    elif sc.state == MFI_SLOW and v >= sc.th1:
        _mfi_rise(sc, pos)


cdef void _mfi_along_ramp(MfiScan *sc, double v0, double v1, double T, int32_t ramp, double pos) noexcept nogil:
    """A ramp from v0 to v1 (T seconds) that starts at path position pos."""
    if v1 > v0:
        if sc.state == MFI_START and v1 >= sc.th0:
            sc.state = MFI_FAST
        elif sc.state == MFI_SLOW and v1 >= sc.th1:
            _mfi_rise(sc, pos + _mfi_ramp_distance_to(v0, v1, T, ramp, sc.th1))
    elif v1 < v0:
        if sc.state == MFI_FAST and v1 < sc.th0:
            _mfi_fall(sc, pos + _mfi_ramp_distance_to(v0, v1, T, ramp, sc.th0))


cdef void _mfi_profile(const Program *prog, size_t k, double length, Profile *pr) noexcept nogil:
    """Part k's profile as the plan holds it (the machine's, profile.pyx): from the
    previous part's exit, under its limits, to its exit."""
    cdef const PartPlan *pp = &prog.plan[k]
    cdef PlanNode nd, out
    cdef Reciprocals rc
    out.jin = pp.v_exit
    out.jin2 = out.entry2 = out.jin * out.jin
    nd.length = length
    nd.vmax = pp.v_cap
    nd.acc = pp.acc
    nd.dec = pp.dec
    nd.ramp = pp.ramp
    nd.brake2 = 2.0 * nd.dec * length
    rc.acc = rc.dec = rc.vmax = 0.0
    profile_plan(pr, &nd, prog.plan[k - 1].v_exit if k > 0 else 0.0, &out, &rc)


cdef bint _mfi_find_targets(const Program *prog, const GCODE_PARAMETERS *params, const double *at,
                        MfuncTargets *targets) noexcept nogil:
    """Walks the plan's profiles: the places of the table's M functions."""
    cdef const INTERNAL_MFUNC_INSERT_TABLE *t = params.mFuncInsertTable
    cdef MfiScan sc
    cdef const Part *p
    cdef Profile pr
    cdef size_t k
    cdef double v_prog, length
    cdef double rel0 = t[MFI_BEFORE_SLOW_DOWN].relFeed, rel1 = t[MFI_AFTER_SLOW_DOWN].relFeed
    cdef bint last_rapid = True
    if t[MFI_BEFORE_SLOW_DOWN].mFunc == 0:      # one entry alone: its speed both ways
        rel0 = rel1
    elif t[MFI_AFTER_SLOW_DOWN].mFunc == 0:
        rel1 = rel0
    sc.prog = prog
    sc.table = t
    sc.at = at
    sc.targets = targets
    sc.state = MFI_START
    sc.ok = True
    for k in range(prog.n_parts):
        p = &prog.parts[k]
        length = at[k + 1] - at[k]
        if p.kind != PART_MOTION or not (length > 0.0):
            continue
        if p.func == 0:
            if not last_rapid and t[MFI_BEFORE_RAPID].mFunc != 0:
                sc.ok = sc.ok and _mfi_place(&sc, at[k] - t[MFI_BEFORE_RAPID].distance, t[MFI_BEFORE_RAPID].mFunc)
            last_rapid = True
            continue
        last_rapid = False
        v_prog = part_feed(prog, p, params) / 60.0
        sc.th0 = rel0 * v_prog * (1.0 - MFI_REL_TOL)
        sc.th1 = rel1 * v_prog * (1.0 - MFI_REL_TOL)
        _mfi_profile(prog, k, length, &pr)
        _mfi_at_point(&sc, pr.v_in, at[k])
        _mfi_along_ramp(&sc, pr.v_in, pr.v_peak, pr.t1, pr.ramp, at[k])
        _mfi_along_ramp(&sc, pr.v_peak, pr.v_out, pr.t3, pr.ramp,
                    at[k + 1] - 0.5 * (pr.v_peak + pr.v_out) * pr.t3)   # the last ramp ends at the end
    return sc.ok


cdef int _mfi_target_compare(const void *a, const void *b) noexcept nogil:
    """qsort's order of the places: by part, then by distance into it, then in the order
    found."""
    cdef const MfuncTarget *x = <const MfuncTarget *>a
    cdef const MfuncTarget *y = <const MfuncTarget *>b
    if x.part != y.part:
        return -1 if x.part < y.part else 1
    if x.q != y.q:
        return -1 if x.q < y.q else 1
    return -1 if x.seq < y.seq else (1 if x.seq > y.seq else 0)


cdef bint _mfi_item_add(MfuncInsertions *ins, size_t after, const Part *made) noexcept nogil:
    """One more part for the merge to insert after part `after`: an M function or a piece of a
    split part. False when memory is exhausted."""
    if not grow(<void **>&ins.items, &ins.cap, ins.n + 1, sizeof(MfuncInsertion)):
        return False
    ins.items[ins.n].after = after
    ins.items[ins.n].made = made[0]
    ins.n += 1
    return True


cdef void _mfi_mfunc_at(Part *out, const Part *at_end_of, int32_t mfunc) noexcept nogil:
    """A continuous (>= 1001) or waiting M function where `at_end_of` ends (its position,
    file and line)."""
    out[0] = at_end_of[0]
    out.kind = PART_MFUNC
    out.func = mfunc
    out.flags = FLAG_INSERTED | (FLAG_CONTINUOUS_M if mfunc >= 1001 else 0)
    out.gcode_index = at_end_of.gcode_index | 1
    out.pars_mask = 0
    out.extra = 0                   # no record: radius and value 0


cdef bint _mfi_piece(ProgramBuilder *build, size_t m, const Segment *g, double q, Part *piece) noexcept nogil:
    """Part m (piece holds a copy) ending q mm into its tool path: the point there (all
    axes) as its compensated end, the point at the same share of the programmed path as
    its programmed end; no addresses but its own G (the last piece keeps the line's).
    False when out of memory."""
    cdef Program *prog = &build.prog
    cdef const PartExtra *x
    cdef double pt[AXES]
    cdef double ps[AXES]
    cdef double full[AXES]
    cdef double centre[2]
    cdef double plane[2]
    cdef double u = q / g.length, r
    cdef int k
    part_end(prog, piece, full)         # the axes g does not move stay there
    segment_point_at(g, q, pt)
    for k in range(g.n_axes):
        full[k] = pt[k]
    if m > 0:                           # the programmed start
        part_end(prog, &prog.parts[m - 1], ps)
    else:
        memcpy(ps, prog.start, sizeof(ps))
    if not (piece.e[0] == piece.ce[0] and piece.e[1] == piece.ce[1] and piece.e[2] == piece.ce[2]
            and (m == 0 or memcmp(prog.parts[m - 1].e, prog.parts[m - 1].ce, sizeof(piece.e)) == 0)):
        # compensated: the programmed end at the same share of the programmed path
        for k in range(3):
            full[k] = ps[k] + (piece.e[k] - ps[k]) * u
        if g.arc:
            x = part_extra(prog, piece)
            centre[0] = x.cc[g.first]
            centre[1] = x.cc[g.second]
            r = distance2d(ps[g.first] - centre[0], ps[g.second] - centre[1])
            arc_point_at(centre, r, ps[g.first], ps[g.second], u * g.sweep, plane)
            full[g.first] = plane[0]
            full[g.second] = plane[1]
    if not program_set_end(build, piece, full):
        return False
    piece.ce[0] = pt[0]
    piece.ce[1] = pt[1]
    piece.ce[2] = pt[2]
    piece.pars_mask = piece.pars_mask & (1u << part_own_cell(piece))
    return True


cdef bint _mfi_make_insertions(ProgramBuilder *build, MfuncTargets *targets, MfuncInsertions *ins,
                           MfiReplacement *repl, size_t *n_repl) noexcept nogil:
    """The parts program_merge inserts for the sorted targets, in part order, and the
    parts that change in place (the first piece of a split part; an M function before
    the program's first part takes part 0's place, part 0 following it)."""
    cdef Program *prog = &build.prog
    cdef size_t n = prog.n_parts, i = 0, j, b, m
    cdef Segment g
    cdef Part original, piece, made
    cdef bint have_first, pieces
    cdef double q
    n_repl[0] = 0
    while i < targets.n:
        m = targets.items[i].part
        j = i
        while j < targets.n and targets.items[j].part == m:
            j += 1
        if m >= n:                      # after the program's end
            for b in range(i, j):
                _mfi_mfunc_at(&made, &prog.parts[n - 1], targets.items[b].mfunc)
                if not _mfi_item_add(ins, n - 1, &made):
                    return False
            i = j
            continue
        original = prog.parts[m]
        b = i
        have_first = False              # the group's first part (it takes part m's place)
        while b < j and targets.items[b].q <= MFI_SNAP:    # just before part m
            if m > 0:
                _mfi_mfunc_at(&made, &prog.parts[m - 1], targets.items[b].mfunc)
                if not _mfi_item_add(ins, m - 1, &made):
                    return False
            else:                       # at the program's start
                _mfi_mfunc_at(&made, &original, targets.items[b].mfunc)
                if not program_set_end(build, &made, prog.start):
                    return False
                made.ce[0] = prog.start[0]
                made.ce[1] = prog.start[1]
                made.ce[2] = prog.start[2]
                if original.gcode_index > 0:
                    made.gcode_index = (original.gcode_index - 1) | 1
                if not have_first:
                    repl[n_repl[0]].part = m
                    repl[n_repl[0]].made = made
                    n_repl[0] += 1
                    have_first = True
                elif not _mfi_item_add(ins, m, &made):
                    return False
            b += 1
        pieces = False
        if b < j:
            segment_of_part(prog, m, &g)    # before any part changes
        while b < j:                    # inside part m: split it there
            q = targets.items[b].q
            piece = original
            if pieces:
                piece.flags = piece.flags | FLAG_INSERTED
                piece.gcode_index = piece.gcode_index | 1
            if not _mfi_piece(build, m, &g, q, &piece):
                return False
            if not have_first:
                repl[n_repl[0]].part = m
                repl[n_repl[0]].made = piece
                n_repl[0] += 1
                have_first = True
            elif not _mfi_item_add(ins, m, &piece):
                return False
            pieces = True
            while b < j and targets.items[b].q == q:
                _mfi_mfunc_at(&made, &piece, targets.items[b].mfunc)
                if not _mfi_item_add(ins, m, &made):
                    return False
                b += 1
        if have_first:                  # the rest of part m, to its end
            piece = original
            if pieces:
                piece.flags = piece.flags | FLAG_INSERTED
                piece.gcode_index = piece.gcode_index | 1
            if not _mfi_item_add(ins, m, &piece):
                return False
        i = j
    return True


cdef size_t _mfi_after_of(void *ctx, size_t rec) noexcept nogil:
    """program_merge's inserted_after_fn: the part insertion rec follows."""
    return (<MfuncInsertions *>ctx).items[rec].after


cdef void _mfi_make(void *ctx, size_t rec, Part *out, const Part *before, const Part *after) noexcept nogil:
    """program_merge's make_inserted_fn: insertion rec's part, made beforehand."""
    out[0] = (<MfuncInsertions *>ctx).items[rec].made


cdef bint mfunc_insert_wanted(const GCODE_PARAMETERS *params) noexcept nogil:
    """Whether the plan inserts M functions: MfuncInsertType 1 with some entry of
    mFuncInsertTable naming one (the pipeline then plans the program in one piece)."""
    cdef int k
    if params.MfuncInsertType != 1:
        return False
    for k in range(3):
        if params.mFuncInsertTable[k].mFunc != 0:
            return True
    return False


cdef int mfunc_insert(ProgramBuilder *build, const GCODE_PARAMETERS *params) noexcept nogil:
    """Inserts the table's M functions where prog.plan crosses the table's speeds;
    COMPILE_OK, or COMPILE_ERROR when out of memory. The caller plans again afterwards."""
    cdef Program *prog = &build.prog
    cdef size_t n = prog.n_parts, k
    cdef double *at
    cdef MfuncTargets targets
    cdef MfuncInsertions ins
    cdef MfiReplacement *repl = NULL
    cdef size_t n_repl = 0
    cdef bint ok
    if n == 0:
        return COMPILE_OK
    at = <double *>tc_malloc((n + 1) * sizeof(double))
    if at == NULL:
        return COMPILE_ERROR
    at[0] = 0.0
    for k in range(n):
        at[k + 1] = at[k] + part_length(prog, k)
    targets.items = NULL
    targets.n = targets.cap = 0
    ins.items = NULL
    ins.n = ins.cap = 0
    ok = _mfi_find_targets(prog, params, at, &targets)
    free(at)
    if ok and targets.n > 0:
        qsort(targets.items, targets.n, sizeof(MfuncTarget), _mfi_target_compare)
        repl = <MfiReplacement *>tc_malloc(targets.n * sizeof(MfiReplacement))     # at most one a target
        ok = repl != NULL and _mfi_make_insertions(build, &targets, &ins, repl, &n_repl)
    if ok:                              # every insertion is made: the parts that change in place
        for k in range(n_repl):
            prog.parts[repl[k].part] = repl[k].made
    if ok and ins.n > 0:
        ok = program_merge(build, ins.n, &ins, _mfi_after_of, _mfi_make, NULL, NULL)
    free(repl)
    free(targets.items)
    free(ins.items)
    return COMPILE_OK if ok else COMPILE_ERROR
