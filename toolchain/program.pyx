# The compiled program: growable arrays of parts, their addresses, zero offsets and
# texts, and the one place a Part becomes a SIMPLE_GM_PARAMS.
from libc.stdlib cimport free
from libc.string cimport memset, memcpy, memcmp
from includes.tgm_cnc cimport SIMPLE_GM_PARAMS, P10DOUBLE, P26FLOAT


cdef void program_init(Program *prog) noexcept nogil:
    """An empty program: no parts, no arrays, the main file unknown (-1)."""
    memset(prog, 0, sizeof(Program))
    prog.main_file_idx = -1


cdef void program_free(Program *prog) noexcept nogil:
    """Frees every array of the program and leaves it empty (program_init)."""
    free(prog.parts)
    free(prog.extras)
    free(prog.settings)
    free(prog.axes)
    free(prog.pars)
    free(prog.zeros)
    free(prog.shifts)
    free(prog.rotations)
    free(prog.texts)
    free(prog.arc_regions)
    free(prog.strategy_regions)
    free(prog.plan_regions)
    free(prog.plan)
    free(prog.radii)
    free(prog.tool_writes)
    program_init(prog)


cdef void program_builder_init(ProgramBuilder *build) noexcept nogil:
    """An empty builder: no capacity yet, an empty program."""
    memset(build, 0, sizeof(ProgramBuilder))
    program_init(&build.prog)


cdef void program_builder_free(ProgramBuilder *build) noexcept nogil:
    """Frees what a compilation left in the builder (nothing once its program is published)."""
    program_free(&build.prog)
    program_builder_init(build)


cdef void program_builder_trim(ProgramBuilder *build) noexcept nogil:
    """Gives back the spare room of the large arrays (parts, extras, addresses) before the
    plan takes its memory: their reserve (reserve_parts) and the memory the thread
    beside the compiler faulted in ahead (up to PREFAULT_AHEAD parts). A shrink copies
    nothing in glibc (the tail is split off or unmapped): about 0.1 ms on a million
    parts. When realloc refuses, the spare room stays."""
    cdef Program *prog = &build.prog
    if prog.n_parts > 0 and build.cap_parts > prog.n_parts:
        if resize(<void **>&prog.parts, prog.n_parts, sizeof(Part)):
            build.cap_parts = prog.n_parts
    if prog.n_extras > 0 and build.cap_extras > prog.n_extras:
        if resize(<void **>&prog.extras, prog.n_extras, sizeof(PartExtra)):
            build.cap_extras = prog.n_extras
    if prog.n_pars > 0 and build.cap_pars > prog.n_pars:
        if resize(<void **>&prog.pars, prog.n_pars, sizeof(float)):
            build.cap_pars = prog.n_pars


cdef inline void _part_defaults(Part *p) noexcept nogil:
    """A new part's fields: zeros (settings record 0, the defaults), plane G17, no compensation
    (G40)."""
    memset(p, 0, sizeof(Part))      # settings 0: the defaults
    p.plane = 17
    p.comp = 40


cdef inline uint32_t _settings_hash(const PartSettings *s) noexcept nogil:
    """FNV-1a over a PartSettings' words, folded to a slot of settings_seen
    (program_settings_index finds a recent record again by it)."""
    cdef uint32_t w[SETTINGS_HASH_WORDS]       # the words copied out (C's aliasing rule)
    cdef uint32_t h = 2166136261u
    cdef int k
    memcpy(w, s, sizeof(w))
    for k in range(SETTINGS_HASH_WORDS):
        h = (h ^ w[k]) * 16777619u
    return (h ^ (h >> 15)) % SETTINGS_SEEN


cdef bint _settings_begin(ProgramBuilder *build) noexcept nogil:
    """Entry 0 of the settings records, the defaults of program_add_part (FP 1, file
    -1, the rest 0), once; False out of memory."""
    cdef Program *prog = &build.prog
    if prog.n_settings > 0:
        return True
    if build.merging or not program_grow_shared(build, <void **>&prog.settings, &build.cap_settings, 8,
                                                sizeof(PartSettings)):
        return False
    memset(&prog.settings[0], 0, sizeof(PartSettings))
    prog.settings[0].fp = 1.0
    prog.settings[0].file_idx = -1
    prog.n_settings = 1             # settings_seen and settings_last (zeroed) name it
    return True


cdef int64_t program_settings_find(ProgramBuilder *build, const PartSettings *s) noexcept nogil:
    """program_settings_index past the record found last: one seen under the hash of s
    (most programs have a few dozen), else a new one; entry 0, the defaults, is added
    first. -1 out of memory."""
    cdef Program *prog = &build.prog
    cdef uint32_t slot
    cdef size_t i
    if not _settings_begin(build):
        return -1
    slot = _settings_hash(s)
    i = build.settings_seen[slot]
    if i < prog.n_settings and settings_equal(&prog.settings[i], s):
        build.settings_last = <uint32_t>i
        return <int64_t>i
    if prog.n_settings >= <size_t>0xFFFFFFFFu:
        return -1
    if prog.n_settings + 1 > build.cap_settings:
        if build.merging:
            return -1               # a maker took more than the merge reserved: a bug
        if not program_grow_shared(build, <void **>&prog.settings, &build.cap_settings, prog.n_settings + 1,
                                   sizeof(PartSettings)):
            return -1
    if not build.merging:
        ready_ahead(prog.settings, (prog.n_settings + 1) * sizeof(PartSettings), &build.ready_settings,
                    build.cap_settings * sizeof(PartSettings))
    i = prog.n_settings
    prog.settings[i] = s[0]
    prog.n_settings += 1
    build.settings_seen[slot] = <uint32_t>i
    build.settings_last = <uint32_t>i
    return <int64_t>i


cdef bint program_grow_shared(ProgramBuilder *build, void **buf, size_t *cap, size_t need,
                              size_t item) noexcept nogil:
    """grow for an array that a stage beside the compiler reads (ProgramBuilder.follow):
    the array moves only while that stage waits between batches."""
    cdef bint ok
    if need <= cap[0]:
        return True
    follow_pause(build.follow)
    ok = grow(buf, cap, need, item)
    follow_resume(build.follow)
    return ok


cdef inline Part *program_add_part(ProgramBuilder *build) noexcept nogil:
    """Appends a zeroed part (zero_idx 0, file -1); NULL when out of memory."""
    cdef Program *prog = &build.prog
    cdef Part *p
    if not _settings_begin(build):
        return NULL
    if not program_grow_shared(build, <void **>&prog.parts, &build.cap_parts, prog.n_parts + 1, sizeof(Part)):
        return NULL
    # where the thread beside the compiler did not ready the memory (it is busy), the
    # compiler readies it a chunk at a time
    ready_ahead(prog.parts, (prog.n_parts + 1) * sizeof(Part), &build.ready_parts, build.cap_parts * sizeof(Part))
    p = &prog.parts[prog.n_parts]
    prog.n_parts += 1
    _part_defaults(p)
    return p


cdef PartExtra *program_part_extra(ProgramBuilder *build, Part *p) noexcept nogil:
    """The record of part p, a zeroed one added when it has none (entry 0 stays unused)."""
    cdef Program *prog = &build.prog
    cdef size_t need
    if p.extra != 0:
        return &prog.extras[p.extra]
    need = prog.n_extras + 1 if prog.n_extras > 0 else 2
    if need > build.cap_extras:
        if build.merging:
            return NULL                 # a maker took more than the merge reserved: a bug
        if not program_grow_shared(build, <void **>&prog.extras, &build.cap_extras, need, sizeof(PartExtra)):
            return NULL
    ready_ahead(prog.extras, need * sizeof(PartExtra), &build.ready_extras, build.cap_extras * sizeof(PartExtra))
    if prog.n_extras == 0:
        memset(&prog.extras[0], 0, sizeof(PartExtra))
        prog.n_extras = 1
    p.extra = <uint32_t>prog.n_extras
    prog.n_extras += 1
    memset(&prog.extras[p.extra], 0, sizeof(PartExtra))
    return &prog.extras[p.extra]


cdef bint program_merge(ProgramBuilder *build, size_t n_ins, void *ctx, inserted_after_fn after_of,
                        make_inserted_fn make, settle_parts_fn settle, const MergeWatch *watch) noexcept nogil:
    """Inserts n_ins parts (in part order: after_of non-decreasing) in one backward pass
    over the grown array: every part moves up by the insertions before it, whole runs
    at a time (a Part holds doubles: its size is a multiple of 8). `settle` (may be
    NULL) sees every part once, the runs from the last down; `watch` (may be NULL)
    hears how far down the parts are final. False when memory is exhausted (the
    program unchanged)."""
    cdef Program *prog = &build.prog
    cdef size_t n = prog.n_parts, total = prog.n_parts + n_ins
    cdef size_t k, w, r, after, run, next_w, told
    cdef Part *parts
    cdef Part made
    if n_ins > 0:
        build.renumber = True           # the driver's G-code indexes are no longer the compiled ones
    if n_ins == 0:
        if settle != NULL:
            settle(ctx, 0, n, <size_t>NO_INSERTION)
        return True
    # room for a PartExtra and a PartSettings per insertion: the makers never move the
    # records (a stage may read them beside the merge)
    if not grow(<void **>&prog.extras, &build.cap_extras, (prog.n_extras if prog.n_extras > 0 else 1) + n_ins,
                sizeof(PartExtra)):
        return False
    if not grow(<void **>&prog.settings, &build.cap_settings, prog.n_settings + n_ins, sizeof(PartSettings)):
        return False
    if not resize(<void **>&prog.parts, total, sizeof(Part)):
        return False
    # the memory the merge writes beyond the old parts, readied at once (one call, not
    # a fault a page; the records its makers take are readied as they go)
    ready_memory(&prog.parts[n], n_ins * sizeof(Part))
    build.merging = True
    parts = prog.parts
    build.cap_parts = total
    # parts [0, k) have not moved yet; part k now lives at next_w (total: there is no
    # part after the last one). Every group but the first moves a run of at least its
    # own part.
    w = total
    k = n
    next_w = total
    r = n_ins
    told = total
    while r > 0:
        after = after_of(ctx, r - 1)
        run = k - (after + 1)
        if run > 0:
            if settle != NULL:
                settle(ctx, after + 1, k, r - 1)
            w -= run
            tc_stream_up(&parts[w], &parts[after + 1], run * sizeof(Part) // 8)
            next_w = w
        k = after + 1
        # the insertions after this part, last first; parts[w - 1] lies above both
        # `after` and next_w
        while r > 0 and after_of(ctx, r - 1) == after:
            w -= 1
            make(ctx, r - 1, &made, &parts[after], &parts[next_w] if next_w < total else NULL)
            tc_stream_up(&parts[w], &made, sizeof(Part) // 8)
            r -= 1
        if watch != NULL and told - w >= MERGE_WATCH_STEP:
            tc_stream_fence()                   # the streamed parts are seen by the watcher
            told = w
            watch.final(watch.ctx, w, total)
    if settle != NULL:
        settle(ctx, 0, k, <size_t>NO_INSERTION)     # the parts that stay where they are
    tc_stream_fence()
    prog.n_parts = total
    build.merging = False
    return True


cdef bint program_prefault(ProgramBuilder *build, size_t first, size_t count, size_t limit) noexcept nogil:
    """Faults in (zeroes) the memory of up to `count` parts from `first` on, or from
    where the last call stopped if that is further, below part `limit` and the
    capacity, without touching their contents: the thread beside the compiler does
    this ahead of it, so the compiler and the merge write into memory that is there.
    Only a hint; False when there is nothing left to do (or the kernel cannot)."""
    cdef Program *prog = &build.prog
    cdef size_t end
    if first < build.prefaulted:
        first = build.prefaulted
    end = first + count
    if end > limit:
        end = limit
    if end > build.cap_parts:
        end = build.cap_parts
    if first >= end:
        return False
    if not ready_memory(&prog.parts[first], (end - first) * sizeof(Part)):
        return False
    build.prefaulted = end
    return True


cdef int program_add_zero(ProgramBuilder *build, const double *offset, const double *shift) noexcept nogil:
    """Index of a zero offset holding the G92 `shift` (reusing the last one when both are
    equal); -1 out of memory, -2 beyond PROGRAM_TABLE_MAX offsets."""
    cdef Program *prog = &build.prog
    if prog.n_zeros == 0:
        if not grow(<void **>&prog.zeros, &build.cap_zeros, 1, sizeof(P10DOUBLE)) \
                or not grow(<void **>&prog.shifts, &build.cap_shifts, 1, sizeof(P10DOUBLE)):
            return -1
        memset(&prog.zeros[0], 0, sizeof(P10DOUBLE))
        memset(&prog.shifts[0], 0, sizeof(P10DOUBLE))
        prog.n_zeros = 1
    if memcmp(&prog.zeros[prog.n_zeros - 1], offset, sizeof(P10DOUBLE)) == 0 \
            and memcmp(&prog.shifts[prog.n_zeros - 1], shift, sizeof(P10DOUBLE)) == 0:
        return <int>prog.n_zeros - 1
    if prog.n_zeros >= PROGRAM_TABLE_MAX:
        return -2
    if not grow(<void **>&prog.zeros, &build.cap_zeros, prog.n_zeros + 1, sizeof(P10DOUBLE)) \
            or not grow(<void **>&prog.shifts, &build.cap_shifts, prog.n_zeros + 1, sizeof(P10DOUBLE)):
        return -1
    memcpy(&prog.zeros[prog.n_zeros], offset, sizeof(P10DOUBLE))
    memcpy(&prog.shifts[prog.n_zeros], shift, sizeof(P10DOUBLE))
    prog.n_zeros += 1
    return <int>prog.n_zeros - 1


cdef int program_add_rotation(ProgramBuilder *build, const double *centre, const double *matrix) noexcept nogil:
    """Index (>= 1) of a G168 rotation (reusing the last one when equal); -1 out of
    memory, -2 beyond PROGRAM_TABLE_MAX rotations."""
    cdef Program *prog = &build.prog
    cdef double *r
    if prog.n_rotations == 0:
        prog.n_rotations = 1                # entry 0: not rotated
    if prog.n_rotations > 1:
        r = prog.rotations + 12 * (prog.n_rotations - 1)
        if memcmp(r, centre, 3 * sizeof(double)) == 0 and memcmp(r + 3, matrix, 9 * sizeof(double)) == 0:
            return <int>prog.n_rotations - 1
    if prog.n_rotations >= PROGRAM_TABLE_MAX:
        return -2
    if not grow(<void **>&prog.rotations, &build.cap_rotations, 12 * (prog.n_rotations + 1), sizeof(double)):
        return -1
    r = prog.rotations + 12 * prog.n_rotations
    memcpy(r, centre, 3 * sizeof(double))
    memcpy(r + 3, matrix, 9 * sizeof(double))
    prog.n_rotations += 1
    return <int>prog.n_rotations - 1


cdef int program_add_radius(ProgramBuilder *build, double radius) noexcept nogil:
    """Index (>= 1) of a D word's signed radius (reusing the last one when equal); -1
    out of memory, -2 beyond PROGRAM_TABLE_MAX radii. The compensation reads the radii beside the compiler: the array
    moves only while it waits."""
    cdef Program *prog = &build.prog
    if prog.n_radii > 1 and prog.radii[prog.n_radii - 1] == radius:
        return <int>prog.n_radii - 1
    if prog.n_radii >= PROGRAM_TABLE_MAX:
        return -2
    if not program_grow_shared(build, <void **>&prog.radii, &build.cap_radii, prog.n_radii + 2, sizeof(double)):
        return -1
    if prog.n_radii == 0:
        prog.radii[0] = 0.0                 # entry 0: correction[] of the part's slot
        prog.n_radii = 1
    prog.radii[prog.n_radii] = radius
    prog.n_radii += 1
    return <int>prog.n_radii - 1


cdef bint program_add_tool_write(ProgramBuilder *build, const ToolWrite *write) noexcept nogil:
    """Appends a G92 D of the program; False = no memory."""
    cdef Program *prog = &build.prog
    if not grow(<void **>&prog.tool_writes, &build.cap_tool_writes, prog.n_tool_writes + 1, sizeof(ToolWrite)):
        return False
    prog.tool_writes[prog.n_tool_writes] = write[0]
    prog.n_tool_writes += 1
    return True


cdef int64_t program_add_text(ProgramBuilder *build, const char *text, size_t n) noexcept nogil:
    """Stores a NUL-terminated copy of text[0:n]; its offset, -1 out of memory."""
    cdef Program *prog = &build.prog
    cdef size_t off = prog.n_texts
    if not grow(<void **>&prog.texts, &build.cap_texts, prog.n_texts + n + 1, 1):
        return -1
    memcpy(&prog.texts[off], text, n)
    prog.texts[off + n] = 0
    prog.n_texts += n + 1
    return <int64_t>off


cdef inline bint program_set_end(ProgramBuilder *build, Part *p, const double *end) noexcept nogil:
    """Sets the programmed end of part p (all ten axes): x y z in the part, the other
    seven as an entry of Program.axes (the last one again when they did not move).
    False when memory is exhausted."""
    cdef Program *prog = &build.prog
    p.e[0] = end[0]; p.e[1] = end[1]; p.e[2] = end[2]
    if prog.n_axes > 0:
        # the other seven axes bit for bit as the last entry's: the C compiler inlines a
        # memcmp of fixed size tested for equality as word compares (no call)
        if memcmp(&prog.axes[OTHER_AXES * (prog.n_axes - 1)], end + 3, OTHER_AXES * sizeof(double)) == 0:
            p.axes_idx = <uint32_t>(prog.n_axes - 1)
            return True
    if not grow(<void **>&prog.axes, &build.cap_axes, OTHER_AXES * (prog.n_axes + 1), sizeof(double)):
        return False
    memcpy(&prog.axes[OTHER_AXES * prog.n_axes], end + 3, OTHER_AXES * sizeof(double))
    p.axes_idx = <uint32_t>prog.n_axes
    prog.n_axes += 1
    return True


cdef inline void part_start(const Program *prog, size_t i, double *out) noexcept nogil:
    """Programmed start of part i, all ten axes."""
    if i > 0:
        part_end(prog, &prog.parts[i - 1], out)
    else:
        memcpy(out, prog.start, AXES * sizeof(double))


cdef void part_inserted(ProgramBuilder *build, Part *q, const Part *after, const Part *src, int32_t func,
                        int16_t plane) noexcept nogil:
    """A motion part inserted after `after`: it starts where `after` ends (compensated),
    its programmed end is `after`'s (an inserted part adds no programmed move), and it
    belongs to src's line with src's feed, tool and compensation, under after's G168
    rotation (the rotation of its corner)."""
    cdef const Program *prog = &build.prog
    cdef PartSettings s
    cdef int64_t idx
    memset(q, 0, sizeof(Part))
    memcpy(q.e, after.e, sizeof(q.e))
    memcpy(q.ce, after.ce, sizeof(q.ce))
    q.axes_idx = after.axes_idx
    q.settings = src.settings
    if part_settings(prog, src).rot_idx != part_settings(prog, after).rot_idx:
        s = part_settings(prog, src)[0]
        s.rot_idx = part_settings(prog, after).rot_idx
        idx = program_settings_index(build, &s)     # from the merge's reserve: never -1 there
        if idx >= 0:
            q.settings = <uint32_t>idx
    q.gcode_index = after.gcode_index + 1
    q.func = func
    q.plane = plane
    q.kind = PART_MOTION
    q.flags = FLAG_INSERTED | (src.flags & FLAG_FEED_PER_MIN)
    q.line = src.line
    q.comp = src.comp
    q.comp_slot = src.comp_slot
    q.radius_idx = src.radius_idx


cdef void part_calc_start(const Program *prog, size_t i, double *out) noexcept nogil:
    """Compensated start of part i (all ten axes)."""
    cdef const Part *prev
    part_start(prog, i, out)
    if i > 0:
        prev = &prog.parts[i - 1]
        out[0] = prev.ce[0]
        out[1] = prev.ce[1]
        out[2] = prev.ce[2]


cdef void program_number_parts(Program *prog) noexcept nogil:
    """The G-code indexes the driver sees, once nothing more is inserted or joined:
    unique and increasing by 1 or 2 over the parts a driver callback gets (the
    structures description). A programmed part takes 2 more than the last part
    delivered when that was programmed too, 1 more after an inserted part (a
    compensation corner, a G167 arc, an mFuncInsertTable M function or a piece of a
    part it split); the first part and a part M-6 S numbered keep their compiled
    number. A part no callback gets (a PRINT line, an arc dropped from the cutting
    plan) takes the last number and moves none. So two inserted parts in a row no
    longer share a number, and PRINT lines, dropped arcs and parts joined away leave
    no gap. start_gindex follows its part. (join_lines numbers the parts it keeps
    the same way on its pass: numbering_begin, numbering_part, numbering_end.)"""
    cdef PartNumbering N
    cdef size_t i
    numbering_begin(&N, prog)
    for i in range(prog.n_parts):
        numbering_part(&N, prog, &prog.parts[i])
    numbering_end(&N, prog)


cdef void _numbering_next_start(PartNumbering *N) noexcept nogil:
    """The lowest compiled start index of an axis not yet mapped to its final number."""
    cdef int k
    N.next_start = INT32_MAX
    N.unmapped = False
    for k in range(AXES):
        if not N.mapped[k]:
            N.unmapped = True
            if N.starts[k] < N.next_start:
                N.next_start = N.starts[k]


cdef void numbering_begin(PartNumbering *N, const Program *prog) noexcept nogil:
    """Starts numbering the parts in their final order (program_number_parts, or the
    join's pass as it keeps them): nothing counted yet, the axes' start indexes to map."""
    cdef int k
    N.last = INT32_MIN
    N.last_programmed = False
    for k in range(AXES):
        N.starts[k] = prog.start_gindex[k]
        N.mapped[k] = N.starts[k] == INT32_MAX or N.starts[k] == 0
    _numbering_next_start(N)


cdef void numbering_part(PartNumbering *N, Program *prog, Part *p) noexcept nogil:
    """The next part in the program's final order (program_number_parts)."""
    cdef int32_t compiled = p.gcode_index
    cdef bint delivered = p.kind != PART_PRINT and not (p.flags & FLAG_DROPPED)
    cdef int k
    if N.last == INT32_MIN or (p.flags & FLAG_INDEX_SET):
        pass                                    # the count starts here
    elif not delivered:
        p.gcode_index = N.last
    elif p.flags & FLAG_INSERTED:
        p.gcode_index = N.last + 1
    else:
        p.gcode_index = N.last + (2 if N.last_programmed else 1)
    if N.unmapped and compiled >= N.next_start and not (p.flags & FLAG_INSERTED):
        for k in range(AXES):
            if not N.mapped[k] and compiled >= N.starts[k]:
                prog.start_gindex[k] = p.gcode_index
                N.mapped[k] = True
        _numbering_next_start(N)
    if delivered:
        N.last = p.gcode_index
        N.last_programmed = not (p.flags & FLAG_INSERTED)


cdef void numbering_end(PartNumbering *N, Program *prog) noexcept nogil:
    """After the last part: an axis start index no part reached is named after the last
    part (every part follows the start)."""
    cdef int k
    if not N.unmapped:
        return
    for k in range(AXES):
        if not N.mapped[k] and N.last != INT32_MIN:
            prog.start_gindex[k] = N.last + 2  # named after the last part: every part follows the start


cdef const double *part_shift(const Program *prog, const Part *p) noexcept nogil:
    """The G92 shift in force at part p (ten axes); NULL when the program has none."""
    cdef uint16_t k = part_settings(prog, p).zero_idx
    return <const double *>&prog.shifts[k] if prog.shifts != NULL and k < prog.n_zeros else NULL


cdef inline void _p10(P10DOUBLE *dst, const double *src) noexcept nogil:
    """Ten axes (a double[10]) into a P10DOUBLE of the ABI."""
    memcpy(dst, src, sizeof(P10DOUBLE))


cdef void part_to_gm(const Program *prog, size_t i, SIMPLE_GM_PARAMS *gm) noexcept nogil:
    """Builds the API view of part i: every field as docs/api.md and docs/structures.md describe."""
    cdef const Part *p = &prog.parts[i]
    cdef const PartSettings *s = part_settings(prog, p)
    cdef float *cells = <float *>&gm.m_pars
    cdef int letter, own
    cdef size_t k
    cdef double e[AXES]
    cdef const double *start
    cdef const PartExtra *x
    cdef int first, second, normal
    part_start(prog, i, <double *>&gm.m_s)
    part_end(prog, p, <double *>&gm.m_e)
    part_calc_start(prog, i, <double *>&gm.m_calcS)
    part_end(prog, p, e)
    e[0] = p.ce[0]; e[1] = p.ce[1]; e[2] = p.ce[2]
    _p10(&gm.m_calcE, e)
    if prog.n_zeros > s.zero_idx:
        gm.m_zero = prog.zeros[s.zero_idx]
    else:
        memset(&gm.m_zero, 0, sizeof(P10DOUBLE))
    memset(&gm.m_cc, 0, sizeof(P10DOUBLE))
    # addresses of the line, then the cells the callbacks define
    for letter in range(26):
        cells[letter] = INVALID_VALUE_F
    k = p.pars_off
    own = part_own_cell(p)
    for letter in range(26):
        if p.pars_mask & (1u << letter):
            if letter == own:
                cells[letter] = <float>p.func
            else:
                cells[letter] = prog.pars[k]
                k += 1
    gm.m_func = p.func
    gm.m_pars.F = <float>s.feed         # F, N and S at every callback (the structures description)
    gm.m_pars.N = 0.0                   # the part's length: dwells and M functions do not move
    if p.kind == PART_MOTION:
        gm.m_pars.G = <float>p.func
        gm.m_pars.N = <float>part_length(prog, i)
        if (p.func == 2 or p.func == 3) and plane_axes(p.plane, &first, &second, &normal):
            start = part_start_xyz(prog, i)
            x = part_extra(prog, p)
            gm.m_pars.R = <float>distance2d(start[first] - x.cc[first], start[second] - x.cc[second])
            gm.m_cc.x = x.cc[0]
            gm.m_cc.y = x.cc[1]
            gm.m_cc.z = x.cc[2]
            gm.m_cc.c = x.radius
            gm.m_pars.I = <float>x.cc[0]
            gm.m_pars.J = <float>x.cc[1]
            gm.m_pars.K = <float>x.cc[2]
    elif p.kind == PART_DWELL:
        gm.m_pars.G = <float>p.func
    gm.m_pars.S = s.spindle
    # tool in the high 16 bits, plane in the low 16 (docs/structures.md); shifted unsigned: a tool
    # of 32768 and more sets the sign bit, which a signed shift may not do
    gm.m_planeTool = <int32_t>((<uint32_t>s.tool << 16) | (<uint32_t>p.plane & 0xFFFF))
    gm.m_reserved = 0
    gm.m_editorLine = p.line
    gm.m_fileIdx = s.file_idx
    gm.m_gCodeIndex = p.gcode_index
    gm.m_bFeedIsMin = (<int32_t>p.comp << 16) | (1 if p.flags & FLAG_FEED_PER_MIN else 0)
    gm.m_fp = s.fp
