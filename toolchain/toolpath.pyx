# The compiled program as TC_TOOLPATH_RECORDs (ToolChainCore_GetToolpath): a host
# gets the whole toolpath in one copy into memory it owns (numpy), instead of one
# driver callback and one SIMPLE_GM_PARAMS per part.
from libc.string cimport memcpy


cdef LoadedProgram *toolpath_acquire(Core *core, Placement *placement) noexcept nogil:
    """A reference to the core's compiled program (NULL when there is none) and where
    it runs from (the machine position); the copy needs no lock."""
    cdef LoadedProgram *lp
    pthread_mutex_lock(&core.lock)
    lp = loaded_program_ref(core.program)
    if lp != NULL:
        placement_init(placement, &lp.prog, core.position)
    pthread_mutex_unlock(&core.lock)
    return lp


cdef inline uint32_t _record_flags(const Part *p) noexcept nogil:
    """The TC_TOOLPATH_* flags of a part's record (per minute, inserted, continuous M,
    helix)."""
    cdef uint32_t flags = 0
    if p.flags & FLAG_FEED_PER_MIN:
        flags |= TC_TOOLPATH_FEED_PER_MINUTE
    if p.flags & FLAG_INSERTED:
        flags |= TC_TOOLPATH_INSERTED
    if p.flags & FLAG_CONTINUOUS_M:
        flags |= TC_TOOLPATH_CONTINUOUS_M
    if p.flags & FLAG_HELIX:
        flags |= TC_TOOLPATH_HELIX
    return flags


cdef void _place_record(const Program *prog, size_t i, const Placement *pl, TC_TOOLPATH_RECORD *r) noexcept nogil:
    """Moves record r of part i to a run from pl (geometry.pyx placement_shift); a
    motion whose ends move apart is measured again (placed_part_length)."""
    cdef double shift[2 * AXES]          # the start's, then the end's
    cdef bint arc = r.kind == PART_MOTION and (r.number == 2 or r.number == 3)
    cdef int k
    if placement_shift(prog, i, pl, shift, shift + AXES) and r.kind == PART_MOTION:
        r.length = placed_part_length(prog, i, pl)
    for k in range(3):
        r.start[k] += shift[k]
        if arc:
            r.centre[k] += shift[k]     # the centre is relative to the start
        r.end[k] += shift[AXES + k]
        r.tool_end[k] += shift[AXES + k]


cdef void toolpath_record(const Program *prog, size_t i, const Placement *pl, TC_TOOLPATH_RECORD *r) noexcept nogil:
    """Record of part i: the fields as include/tgm_cnc.h documents them, placed at the
    machine position (placement.pyx)."""
    cdef const Part *p = &prog.parts[i]
    cdef const PartExtra *x = part_extra(prog, p)
    cdef const PartSettings *s = part_settings(prog, p)
    memcpy(r.start, part_start_xyz(prog, i), 3 * sizeof(double))
    memcpy(r.end, p.e, 3 * sizeof(double))
    memcpy(r.tool_end, p.ce, 3 * sizeof(double))
    if p.kind == PART_MOTION and (p.func == 2 or p.func == 3):
        memcpy(r.centre, x.cc, 3 * sizeof(double))
        r.radius = x.radius
    else:
        r.centre[0] = 0.0
        r.centre[1] = 0.0
        r.centre[2] = 0.0
        r.radius = 0.0
    r.length = part_length(prog, i)
    r.feed = s.feed if p.kind == PART_MOTION else 0.0
    r.value = x.value if p.kind == PART_DWELL or (p.kind == PART_MOTION and p.func == 33) else 0.0
    r.kind = p.kind
    r.number = p.func
    r.line = p.line
    r.file_index = s.file_idx
    r.plane = p.plane
    r.compensation = p.comp
    r.flags = _record_flags(p)
    r.tool = s.tool
    r.spindle = s.spindle
    r.feed_factor = s.fp
    if pl.moved:
        _place_record(prog, i, pl, r)


cdef int32_t toolpath_copy(Core *core, TC_TOOLPATH_RECORD *out, uint64_t capacity, uint64_t first,
                           uint64_t *total) noexcept nogil:
    """ToolChainCore_GetToolpath after its argument checks."""
    cdef Placement placement
    cdef LoadedProgram *lp = toolpath_acquire(core, &placement)
    cdef const Program *prog
    cdef uint64_t n, end, i
    if lp == NULL:
        return TOOL_CHAIN_ERROR
    prog = &lp.prog
    n = prog.n_parts
    if first > n:
        loaded_program_release(lp)
        return TOOL_CHAIN_ERROR
    end = n if capacity >= n - first else first + capacity
    for i in range(first, end):
        toolpath_record(prog, i, &placement, &out[i - first])
    loaded_program_release(lp)
    if total != NULL:
        total[0] = n
    return TOOL_CHAIN_SUCCESS
