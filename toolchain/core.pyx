# One CNC core (interpolator channel): its configuration, its refused calls, and
# its compilation activity (the worker that compiles, compensates and plans).
# core.pxd says who may touch what; the life of an activity (begin, end, join) is
# runtime/lifecycle.pyx.
from libc.stdlib cimport abort, free
from libc.string cimport memset, memcpy, memcmp, strlen, strcmp, strncpy
from libc.stdio cimport snprintf

cdef Core g_cores[3]
cdef pthread_once_t g_once

# PLC memory of the offline machine (TGM_Data): the G-code's ReadPLC*/WritePLC* and
# the host (ctypes: (c_ubyte * 524288).in_dll(lib, "TGM_Data")) share it.
cdef public uint8_t TGM_Data[524288]


cdef void _init_cores() noexcept nogil:
    """Every core's initial state: locks, default parameters, override and time scale 1, no
    breakpoint, no files, an empty snapshot; the core mode 2."""
    cdef int i
    cdef Core *core
    for i in range(TOOL_CHAIN_MAX_CORES):
        core = &g_cores[i]
        memset(core, 0, sizeof(Core))
        core.index = i
        pthread_mutex_init(&core.lock, NULL)
        pthread_cond_init(&core.changed, NULL)
        default_gcode_parameters(&core.params)
        core.rel_feed = 1.0
        core.time_scale = 1.0
        core.breakpoint_file = -1
        core.compile_files[0] = core.compile_files[1] = core.compile_files[2] = -1
        snapshot_init(&core.snap)
    g_core_mode = 2


cdef Core *core_get(uint32_t index) noexcept nogil:
    """The core, or NULL for an index that is not a core of this library."""
    pthread_once(&g_once, _init_cores)
    if index >= <uint32_t>TOOL_CHAIN_MAX_CORES:
        return NULL
    return &g_cores[index]


# ------------------------------------------------------------------ refused calls

cdef extern from *:
    """
    /* each thread's record of a refused call's error (an ErrorInfo: refusal() checks
       that it fits), between its constructor and core_fail */
    static __thread double tc_refusal_store[256];
    """
    double tc_refusal_store[256]


cdef ErrorInfo *refusal() noexcept nogil:
    """The calling thread's record for the error of a call it refuses."""
    if sizeof(ErrorInfo) > sizeof(tc_refusal_store):    # constant: the C compiler folds it
        abort()
    return <ErrorInfo *>tc_refusal_store


cdef int32_t core_fail(Core *core, const ErrorInfo *err) noexcept nogil:
    """Keeps `err` as the error of a refused call (GetLastCallError; the activity's
    error, GetLastError, stays) and reports it. The thread's refusal() record is
    reported from a copy: a host's callback may refuse a call of its own meanwhile.
    Returns TOOL_CHAIN_ERROR."""
    cdef ErrorInfo *copy = NULL
    core_keep_error(core, True, err)
    if err == refusal():
        copy = <ErrorInfo *>tc_malloc(sizeof(ErrorInfo))
        if copy == NULL:
            return TOOL_CHAIN_ERROR     # kept, not reported: no memory for the report
        copy[0] = err[0]
        err = copy
    core_report_error(core, err)
    free(copy)
    return TOOL_CHAIN_ERROR


cdef int32_t core_refuse(Core *core, const char *what, int32_t status) noexcept nogil:
    """A call the transition table refuses in `status`: ERR_BUSY while an activity
    runs, ERR_BAD_STATUS (the status' number and name) otherwise."""
    if status > 0:
        err_busy(refusal(), -1, 0, status_name(status))
    else:
        err_bad_status(refusal(), -1, 0, what, status, status_name(status))
    return core_fail(core, refusal())


# ------------------------------------------------------------------ compilation

cdef void _compile_progress(void *ctx, int percent) noexcept nogil:
    """The compiler's progress callback: SetStatusBarProgress of the core."""
    core_progress(<Core *>ctx, <uint32_t>percent)


cdef void _compile_output(void *ctx, int tab, const char *text) noexcept nogil:
    """The compiler's output callback (PRINT and the like): AddOutputLog of the core."""
    core_output(<Core *>ctx, <uint32_t>tab, text)


cdef void _compile_warn(void *ctx, const ErrorInfo *warning) noexcept nogil:
    """The compiler's warning callback: MathWarning (2001) of the core."""
    core_warning(<Core *>ctx, warning)


cdef int _compile_and_compensate(Core *core, CompileInput *inp, ProgramBuilder *build, ErrorInfo *err,
                                 GCODE_INFO *extent, bint *measured, uint8_t **settle) noexcept nogil:
    """The compiler, and the compensation's pass beside it in a thread of its own
    (pipeline.pyx), then the compensation's merge with the extent measured beside it
    (*measured: `extent` is filled): COMPILE_OK, or the compiler's failure, else the
    compensation's (err filled). With no G167 arcs to insert, a merge that would only
    settle the parts without motion in the plane leaves that to join_lines (*settle:
    the roles it needs, else NULL)."""
    # the pass's state is written by the thread beside the compiler all the time: on
    # the heap, not on the compiler's stack next to the frames it writes
    cdef CompState *comp = <CompState *>tc_malloc(sizeof(CompState))
    cdef Follow follow
    cdef ExtentBeside beside
    cdef ErrorInfo *comp_err = <ErrorInfo *>tc_calloc(1, sizeof(ErrorInfo))
    cdef int result
    measured[0] = False
    if comp_err == NULL or comp == NULL:
        free(comp)
        free(comp_err)
        err_out_of_memory(err, inp.file_idx, 0)
        return COMPILE_ERROR
    compensate_begin(comp, build, &inp.params, comp_err, _compile_output, _compile_warn, core)
    follow_init(&follow, build, compensate_feed, comp)
    build.follow = &follow
    result = compile_program(inp, build, err)
    if result == COMPILE_OK and build.prog.compensated:
        follow_finish(&follow, build.prog.n_parts)  # the pass takes the rest and ends
    else:
        follow_abandon(&follow)
    build.follow = NULL
    follow_destroy(&follow)
    if result == COMPILE_OK and build.prog.compensated:
        tc_set_stage("the compensation")
        extent_beside_begin(&beside, &build.prog)
        result = compensate_end(comp, &beside.watch, settle if insert_arcs_idle(&build.prog, &inp.params) else NULL)
        measured[0] = extent_beside_end(&beside, result == COMPILE_OK, extent)
        if result != COMPILE_OK:
            err[0] = comp_err[0]
    else:
        compensate_free(comp)
    free(comp)
    free(comp_err)
    return result


cdef int _compile_job(Core *core, CompileJob *job, ProgramBuilder *build, GCODE_INFO *extent, ErrorInfo *err) noexcept nogil:
    """Reads (if need be), compiles, compensates, inserts arcs and measures the
    program of `job`; no lock is held but for copying the core's settings."""
    cdef CompileInput *inp
    cdef int32_t read_error = 0
    cdef uint32_t machine_bits
    cdef size_t n_parts
    cdef bint measured
    cdef int result
    cdef char text[400]
    cdef uint8_t *settle = NULL
    cdef PlanAhead plan_ahead
    cdef bint ahead
    if job.text == NULL:
        job.text = read_whole_file(job.name, MAX_FILE_BYTES, &job.length, &read_error)
        if job.text == NULL:
            file_error(err, read_error, job.files[0], job.name)
            return COMPILE_ERROR
    if job.length >= 2 and <unsigned char>job.text[0] == 0x1f and <unsigned char>job.text[1] == 0x8b:
        err_compressed_file(err, job.files[0], 0, job.name)    # gzip's magic bytes
        return COMPILE_ERROR
    inp = <CompileInput *>tc_calloc(1, sizeof(CompileInput))
    if inp == NULL:
        err_out_of_memory(err, job.files[0], 0)
        return COMPILE_ERROR
    inp.text = job.text
    inp.length = job.length
    inp.file_idx = job.files[0]
    inp.prefix_idx = job.files[1]
    inp.postfix_idx = job.files[2]
    inp.prefix = job.prefix
    inp.postfix = job.postfix
    pthread_mutex_lock(&core.lock)
    inp.params = core.params
    if core.has_user_params:
        memcpy(inp.user_params, core.user_params, sizeof(inp.user_params))
    memcpy(inp.start, core.position, sizeof(inp.start))
    inp.tools = core.tool_table
    inp.plan_window = core.plan_window
    machine_bits = <uint32_t>core.machine.enhancedInterpolatorParameters
    pthread_mutex_unlock(&core.lock)
    inp.plc = TGM_Data
    inp.cancel = &core.cancel
    inp.progress = _compile_progress
    inp.output = _compile_output
    inp.warn = _compile_warn
    inp.ctx = core
    snprintf(text, sizeof(text), "Compiling %s", job.name)
    core_status_text(core, text, job.files[0], 0)
    core_progress(core, 0)
    result = _compile_and_compensate(core, inp, build, err, extent, &measured, &settle)
    n_parts = build.prog.n_parts
    tc_set_stage("the automatic arcs")
    if result == COMPILE_OK:
        result = insert_arcs(build, &inp.params, err)
    # the spare room of the parts (the reserve, what was faulted in ahead) goes back
    # before the plan takes its memory: the peak is the parts and their plan
    if result == COMPILE_OK:
        program_builder_trim(build)
    # the source is not read again: its memory, faulted in already, becomes the plan's
    # (plan_alloc reallocates it; fresh memory costs more to fault in than the plan's
    # passes take, docs/benchmarks.md)
    inp.text = NULL
    if result == COMPILE_OK and build.prog.plan == NULL:
        build.prog.plan = <PartPlan *>job.text
    else:
        free(job.text)
    job.text = NULL
    # the plan made beside the joins where it can (pipeline.pyx), else after them
    tc_set_stage("the plan")
    ahead = result == COMPILE_OK and plan_ahead_begin(&plan_ahead, build, &inp.params, machine_bits,
                                                      inp.plan_window)
    # the joins number the parts they keep on their pass, unless the plan inserts M
    # functions (then the count comes after it)
    tc_set_stage("the automatic arcs")
    if result != COMPILE_OK:
        free(settle)
    else:
        measured = measured and build.prog.n_parts == n_parts  # no automatic arcs came in
        if join_lines(build, &inp.params, not mfunc_insert_wanted(&inp.params), settle,
                      &plan_ahead.watch if ahead else NULL, extent if measured else NULL,
                      &measured) != COMPILE_OK:
            result = COMPILE_ERROR
            err_out_of_memory(err, job.files[0], 0)
    tc_set_stage("the plan")
    if ahead:
        if plan_ahead_end(&plan_ahead, build, result == COMPILE_OK, extent, measured) != COMPILE_OK \
                and result == COMPILE_OK:
            result = COMPILE_ERROR
            err_out_of_memory(err, job.files[0], 0)
        if result == COMPILE_OK:
            program_builder_trim(build)         # what the joins took away
    else:
        if result == COMPILE_OK:
            program_builder_trim(build)
        if result == COMPILE_OK and plan_beside_extent(build, &inp.params, machine_bits, inp.plan_window,
                                                       extent, measured) != COMPILE_OK:
            result = COMPILE_ERROR
            err_out_of_memory(err, job.files[0], 0)
    if result == COMPILE_OK and build.renumber:
        program_number_parts(&build.prog)   # the plan's insertions are in: the driver's indexes
    if result == COMPILE_OK and TC_ATOMIC_LOAD(&core.cancel):
        result = COMPILE_CANCELLED          # ended while it finished: nothing is published
    if result == COMPILE_CANCELLED:
        err_cancelled(err, job.files[0], 0)
    free(inp)
    return result


cdef void _apply_tool_writes(Core *core, const Program *prog) noexcept nogil:
    """With core.lock held: the program's G92 D writes into the core's tool table, in
    the order written, once it compiled (the compiler checked every value)."""
    cdef ErrorInfo unused
    cdef size_t k
    for k in range(prog.n_tool_writes):
        tool_table_set(&core.tool_table, prog.tool_writes[k].entry, prog.tool_writes[k].programmed,
                       prog.tool_writes[k].values, &unused)


cdef void *compile_body(void *arg) noexcept nogil:
    """The worker of a compilation: compiles, compensates and plans the CompileJob's
    program, then publishes it (or its error)."""
    cdef CompileJob *job = <CompileJob *>arg
    cdef Core *core = job.head.core
    cdef ProgramBuilder build
    cdef ErrorInfo *err = <ErrorInfo *>tc_calloc(1, sizeof(ErrorInfo))
    cdef GCODE_INFO *extent = <GCODE_INFO *>tc_calloc(1, sizeof(GCODE_INFO))
    cdef LoadedProgram *loaded = NULL
    cdef LoadedProgram *old
    cdef PublishedError *kept = NULL
    cdef int result = COMPILE_ERROR
    cdef char text[400]
    tc_set_stage("compiling")
    worker_thread_mark(core)
    program_builder_init(&build)
    if err != NULL and extent != NULL:
        result = _compile_job(core, job, &build, extent, err)
        if result == COMPILE_OK:
            loaded = loaded_program_new(&build.prog, extent, job.files)     # the program alone
            if loaded == NULL:
                result = COMPILE_ERROR
                err_out_of_memory(err, job.files[0], 0)
    elif err != NULL:
        err_out_of_memory(err, job.files[0], 0)     # no memory for the extent
    if result != COMPILE_OK and err != NULL:
        err.n_lines = <int32_t>build.prog.n_lines   # lines of the main file, counted before compiling
    if loaded == NULL:
        kept = published_error_new(err)            # err NULL: out of memory
    pthread_mutex_lock(&core.lock)
    old = core.program
    core.program = loaded
    if loaded != NULL:
        core.size_info = loaded.extent
        core.size_info_stale = False
        _apply_tool_writes(core, &loaded.prog)
    else:
        memset(&core.size_info, 0, sizeof(GCODE_INFO))
    kept = core_swap_error_locked(core, False, kept)
    pthread_mutex_unlock(&core.lock)
    published_error_release(kept)
    program_builder_free(&build)        # what a failed compilation left
    loaded_program_release(old)
    if loaded != NULL:
        snprintf(text, sizeof(text), "Compiled %s: %lu parts", job.name, <unsigned long>loaded.prog.n_parts)
        core_progress(core, 100)
        core_status_text(core, text, job.files[0], <int32_t>loaded.prog.n_lines)
        log_line(LOG_COMPILER, text)
    elif err != NULL and (result != COMPILE_CANCELLED or TC_ATOMIC_LOAD(&core.cancel) == 0):
        core_report_error(core, err)
    free(err)
    free(extent)
    job_free(&job.head)
    core_finish(core, EV_DONE)
    return NULL


cdef bint compile_prepare(Core *core, Job *job, ErrorInfo *err) noexcept nogil:
    """With core.lock held before the worker starts: the file table entries the
    compilation uses are not recycled while it runs."""
    memcpy(core.compile_files, (<CompileJob *>job).files, sizeof(core.compile_files))
    return True


cdef int32_t core_start_compile(Core *core, const char *name, char *text, size_t length) noexcept nogil:
    """CompileFromFile (text NULL: the worker reads the file `name`) and
    CompileFromMemory (takes ownership of `text`)."""
    cdef CompileJob *job = <CompileJob *>job_new(CMD_COMPILE)
    cdef bint lost
    if job == NULL:
        free(text)
        err_out_of_memory(refusal(), -1, 0)
        return core_fail(core, refusal())
    job.files[0] = job.files[1] = job.files[2] = -1
    job.text = text
    job.length = length
    strncpy(job.name, name, sizeof(job.name) - 1)
    job.files[0] = core_file_to_idx(core, name)
    pthread_mutex_lock(&core.lock)
    job.prefix = tc_strdup(core.prefix) if core.prefix != NULL else NULL
    job.postfix = tc_strdup(core.postfix) if core.postfix != NULL else NULL
    lost = (job.prefix == NULL and core.prefix != NULL) or (job.postfix == NULL and core.postfix != NULL)
    pthread_mutex_unlock(&core.lock)
    if lost:                            # no memory for a copy: not compiled without it
        job_free(&job.head)
        err_out_of_memory(refusal(), -1, 0)
        return core_fail(core, refusal())
    if job.prefix != NULL:
        job.files[1] = core_file_to_idx(core, "__prefix__")
    if job.postfix != NULL:
        job.files[2] = core_file_to_idx(core, "__postfix__")
    return core_start(core, &job.head, "compilation")


