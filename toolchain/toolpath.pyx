# The compiled program as TC_TOOLPATH_RECORDs (ToolChainCore_GetToolpath): a host
# gets the whole toolpath in one copy into memory it owns (numpy), instead of one
# driver callback and one SIMPLE_GM_PARAMS per part.
from libc.string cimport memcpy


cdef const Program *toolpath_acquire(Core *core) noexcept nogil:
    """The core's compiled program, held until toolpath_release; NULL (nothing held)
    when there is none. With these two the only places this module reaches into the
    core: for now the core's lock keeps the program from being replaced or freed
    (a compilation's end, DestroyCNC) while it is copied."""
    pthread_mutex_lock(&core.lock)
    if not core.has_program:
        pthread_mutex_unlock(&core.lock)
        return NULL
    return &core.program


cdef void toolpath_release(Core *core, const Program *prog) noexcept nogil:
    """Lets go of what toolpath_acquire returned (prog: what a reference-counted
    program will release)."""
    pthread_mutex_unlock(&core.lock)


cdef inline uint32_t _record_flags(const Part *p) noexcept nogil:
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


cdef void toolpath_record(const Program *prog, size_t i, TC_TOOLPATH_RECORD *r) noexcept nogil:
    """Record of part i: the fields as include/tgm_cnc.h documents them."""
    cdef const Part *p = &prog.parts[i]
    cdef bint arc = p.kind == PART_MOTION and (p.func == 2 or p.func == 3)
    memcpy(r.start, part_start_xyz(prog, i), 3 * sizeof(double))
    memcpy(r.end, p.e, 3 * sizeof(double))
    memcpy(r.tool_end, p.ce, 3 * sizeof(double))
    if arc:
        memcpy(r.centre, p.cc, 3 * sizeof(double))
        r.radius = p.radius
    else:
        r.centre[0] = 0.0
        r.centre[1] = 0.0
        r.centre[2] = 0.0
        r.radius = 0.0
    r.length = part_length(prog, i)
    r.feed = p.feed if p.kind == PART_MOTION else 0.0
    r.value = p.value if p.kind == PART_DWELL or (p.kind == PART_MOTION and p.func == 33) else 0.0
    r.kind = p.kind
    r.number = p.func
    r.line = p.line
    r.file_index = p.file_idx
    r.plane = p.plane
    r.compensation = p.comp
    r.flags = _record_flags(p)
    r.tool = p.tool
    r.spindle = p.spindle
    r.feed_factor = p.fp


cdef int32_t toolpath_copy(Core *core, TC_TOOLPATH_RECORD *out, uint64_t capacity, uint64_t first,
                           uint64_t *total) noexcept nogil:
    """ToolChainCore_GetToolpath after its argument checks."""
    cdef const Program *prog = toolpath_acquire(core)
    cdef uint64_t n, end, i
    if prog == NULL:
        return TOOL_CHAIN_ERROR
    n = prog.n_parts
    if first > n:
        toolpath_release(core, prog)
        return TOOL_CHAIN_ERROR
    end = n if capacity >= n - first else first + capacity
    for i in range(first, end):
        toolpath_record(prog, i, &out[i - first])
    toolpath_release(core, prog)
    if total != NULL:
        total[0] = n
    return TOOL_CHAIN_SUCCESS
