# Where a compiled program runs. A program is compiled from the machine position of
# that moment; a run starts from the machine position of its own moment (ResetCNC
# may have moved it). An axis that the program has not yet named absolutely -- moved
# only by G91 increments, or not named at all -- follows the run's start: its parts
# [0, start_gindex[k]) move by the difference of the two positions. The program itself
# is never rewritten (it is shared, immutable); runs and GetGCodeSizeInfo apply the
# difference as they read it.
from libc.stdlib cimport free
from libc.string cimport memcpy


cdef void placement_init(Placement *pl, const Program *prog, const double *start) noexcept nogil:
    """A run of prog placed at `start`: the delta from the compile's start on each axis, and
    whether any is not 0."""
    cdef int k
    memcpy(pl.start, start, sizeof(pl.start))
    pl.moved = False
    for k in range(AXES):
        pl.delta[k] = start[k] - prog.start[k]
        if pl.delta[k] != 0.0:
            pl.moved = True


cdef size_t placement_reshaped_end(const Program *prog, const Placement *pl) noexcept nogil:
    """The parts a run from pl.start may reshape are before this one: a part changes
    its shape where its start follows the run's start in an axis and its end does not
    (the first part, the part where the axis is first named absolutely); after the
    last such part every part only moves (or stays). 0 when nothing moves."""
    cdef int32_t until = 0
    cdef size_t i = 1
    cdef int k
    if not pl.moved or prog.n_parts == 0:
        return 0
    for k in range(AXES):
        if pl.delta[k] != 0.0 and prog.start_gindex[k] != INT32_MAX and prog.start_gindex[k] > until:
            until = prog.start_gindex[k]
    while i < prog.n_parts and prog.parts[i - 1].gcode_index < until:
        i += 1
    return i


cdef void placed_part_to_gm(const Program *prog, size_t i, const Placement *pl,
                            SIMPLE_GM_PARAMS *gm) noexcept nogil:
    """part_to_gm for a run from pl.start: the axes that follow the start moved
    (geometry.pyx placement_shift)."""
    cdef const Part *p = &prog.parts[i]
    cdef bint arc = p.kind == PART_MOTION and (p.func == 2 or p.func == 3)
    cdef double start_shift[AXES]
    cdef double end_shift[AXES]
    cdef bint reshaped
    cdef int k
    part_to_gm(prog, i, gm)
    if not pl.moved:
        return
    reshaped = placement_shift(prog, i, pl, start_shift, end_shift)
    for k in range(AXES):
        (<double *>&gm.m_s)[k] += start_shift[k]
        (<double *>&gm.m_calcS)[k] += start_shift[k]
        (<double *>&gm.m_e)[k] += end_shift[k]
        (<double *>&gm.m_calcE)[k] += end_shift[k]
    if arc:
        for k in range(3):
            (<double *>&gm.m_cc)[k] += start_shift[k]     # the centre is relative to the start
        gm.m_pars.I = <float>gm.m_cc.x
        gm.m_pars.J = <float>gm.m_cc.y
        gm.m_pars.K = <float>gm.m_cc.z
    if reshaped:
        if p.kind != PART_MOTION:
            gm.m_e = gm.m_s                  # an M function stands where the motion ended
            gm.m_calcE = gm.m_calcS
        elif not arc:
            gm.m_pars.N = <float>placed_part_length(prog, i, pl)


cdef void _size_union(GCODE_INFO *into, const GCODE_INFO *later) noexcept nogil:
    """`into` widened by the extent of the parts after it (their end is the end)."""
    cdef int s, k
    cdef double *lo
    cdef double *hi
    for s in range(4):
        lo = <double *>&into.m_size[s].m_minimalPos
        hi = <double *>&into.m_size[s].m_maximalPos
        for k in range(AXES):
            if (<double *>&later.m_size[s].m_minimalPos)[k] < lo[k]:
                lo[k] = (<double *>&later.m_size[s].m_minimalPos)[k]
            if (<double *>&later.m_size[s].m_maximalPos)[k] > hi[k]:
                hi[k] = (<double *>&later.m_size[s].m_maximalPos)[k]
        into.m_size[s].m_endPos = later.m_size[s].m_endPos


cdef void _size_shift(GCODE_INFO *info, const double *delta) noexcept nogil:
    """Every position of the four extents of info moved by delta."""
    cdef int s, k
    for s in range(4):
        for k in range(AXES):
            (<double *>&info.m_size[s].m_startPos)[k] += delta[k]
            (<double *>&info.m_size[s].m_endPos)[k] += delta[k]
            (<double *>&info.m_size[s].m_minimalPos)[k] += delta[k]
            (<double *>&info.m_size[s].m_maximalPos)[k] += delta[k]


cdef bint placed_extent(const Program *prog, const Placement *pl, GCODE_INFO *info) noexcept nogil:
    """GetGCodeSizeInfo of the program run from pl.start, without rewriting it: the
    axes every part takes from the start (never named) move the whole extent; the
    parts before the last axis is named (a short head, e.g. a first `G0 Z5`) are
    copied and moved; the rest is measured where it is. False when out of memory.
    (C..O named only later than the first part are measured where the compilation
    left them.)"""
    cdef double whole[AXES]         # axes every part takes from the start
    cdef double head_delta[AXES]    # axes only the head takes from the start
    cdef int32_t head_until = 0     # gcode index where the head ends
    cdef size_t head = 0, i
    cdef Program part_view
    cdef Part *copy
    cdef PartExtra *copy_extras
    cdef GCODE_INFO rest
    cdef int k
    for k in range(AXES):
        whole[k] = 0.0
        head_delta[k] = 0.0
        if pl.delta[k] == 0.0 or prog.start_gindex[k] == 0:
            continue
        if prog.start_gindex[k] == INT32_MAX:
            whole[k] = pl.delta[k]
        else:
            head_delta[k] = pl.delta[k]
            if prog.start_gindex[k] > head_until:
                head_until = prog.start_gindex[k]
    while head < prog.n_parts and prog.parts[head].gcode_index < head_until:
        head += 1
    # measured in the frame of the compilation for the `whole` axes, shifted at the end
    part_view = prog[0]
    for k in range(AXES):
        part_view.start[k] = pl.start[k] - whole[k]
    if head > 0:
        copy = <Part *>tc_malloc(head * sizeof(Part))
        copy_extras = <PartExtra *>tc_calloc(head + 1, sizeof(PartExtra))     # entry 0 unused
        if copy == NULL or copy_extras == NULL:
            free(copy)
            free(copy_extras)
            return False
        memcpy(copy, prog.parts, head * sizeof(Part))
        for i in range(head):
            if copy[i].kind != PART_PRINT and copy[i].extra != 0:
                copy_extras[i + 1] = prog.extras[copy[i].extra]
                copy[i].extra = <uint32_t>(i + 1)
            for k in range(3):
                if head_delta[k] != 0.0 and follows_start(prog, &copy[i], k):
                    copy[i].e[k] += head_delta[k]
                    copy[i].ce[k] += head_delta[k]
                    copy_extras[i + 1].cc[k] += head_delta[k]
        part_view.parts = copy
        part_view.extras = copy_extras
        part_view.n_extras = head + 1
        part_view.n_parts = head
        program_extent(&part_view, info)
        # the rest starts where the head ended
        part_view.start[0] = copy[head - 1].e[0]
        part_view.start[1] = copy[head - 1].e[1]
        part_view.start[2] = copy[head - 1].e[2]
        memcpy(&part_view.start[3], &prog.axes[OTHER_AXES * copy[head - 1].axes_idx], OTHER_AXES * sizeof(double))
        free(copy)
        free(copy_extras)
        part_view.extras = prog.extras
        part_view.n_extras = prog.n_extras
        if head < prog.n_parts:
            part_view.parts = prog.parts + head
            part_view.n_parts = prog.n_parts - head
            program_extent(&part_view, &rest)
            _size_union(info, &rest)
    else:
        program_extent(&part_view, info)
    _size_shift(info, whole)
    return True
