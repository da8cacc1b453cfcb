# One CNC core (interpolator channel): its configuration, its program, its errors,
# and the life of its one activity (a compilation or a run) in a worker thread.
# core.pxd says who may touch what; docs/threading.md draws the lifecycle:
#
#   idle --begin--> running --(done | stopped | cancelled)--> finished --join--> idle
#
# A call that starts an activity joins the finished worker of the last one first; a
# call that ends one (DestroyCNC, ResetCNC, ResetStatusCNC) cancels it, waits until
# it is joined (by itself, or by the thread that already joins it) and then applies
# its own end, in the same critical section, so no start can slip in between. A call
# made inside a callback of a running activity (on any worker thread) never waits
# for a worker: it leaves its end to the worker, which applies it when the callback
# has returned.
from libc.stdlib cimport malloc, calloc, free
from libc.string cimport memset, memcpy, memcmp, strlen, strcmp, strncpy, strdup
from libc.stdio cimport snprintf

cdef Core g_cores[3]
cdef pthread_once_t g_once

# PLC memory of the offline machine (TGM_Data): the G-code's ReadPLC*/WritePLC* and
# the host (ctypes: (c_ubyte * 524288).in_dll(lib, "TGM_Data")) share it.
cdef public uint8_t TGM_Data[524288]


cdef void _init_cores() noexcept nogil:
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


cdef inline bint on_worker_thread() noexcept nogil:
    """True inside a callback of any core's running activity (a library thread)."""
    return tc_worker_core != NULL


# ------------------------------------------------------------------ refused calls

cdef int32_t core_fail(Core *core, int32_t number, const char *text_arg) noexcept nogil:
    """Records and reports the error of a refused call (no file, no line) in the
    call's slot (GetLastCallError); the activity's error (GetLastError) stays.
    Returns TOOL_CHAIN_ERROR."""
    cdef ErrorInfo *err = <ErrorInfo *>malloc(sizeof(ErrorInfo))
    if err == NULL:
        return TOOL_CHAIN_ERROR
    set_error_text(err, number, -1, 0, text_arg)
    core_fail_with(core, err)
    free(err)
    return TOOL_CHAIN_ERROR


cdef int32_t core_refuse(Core *core, const char *what, int32_t status) noexcept nogil:
    """A call the transition table refuses in `status`: ERR_BUSY while an activity
    runs, ERR_BAD_STATUS (the status' number and name) otherwise."""
    cdef ErrorInfo *err
    if status > 0:
        return core_fail(core, ERR_BUSY, status_name(status))
    err = <ErrorInfo *>malloc(sizeof(ErrorInfo))
    if err == NULL:
        return TOOL_CHAIN_ERROR
    set_error_status(err, what, status)
    core_fail_with(core, err)
    free(err)
    return TOOL_CHAIN_ERROR


cdef int32_t core_read_error(Core *core, const ErrorInfo *slot, CALLBACK_INFO *info) noexcept nogil:
    """GetLastError / GetLastCallError: 1 and info filled from `slot` (core.error or
    core.call_error), 0 when it holds no error."""
    cdef int32_t result = 0
    pthread_mutex_lock(&core.lock)
    if slot.number != 0:
        fill_callback_info(slot, info)
        result = 1
    pthread_mutex_unlock(&core.lock)
    return result


cdef void core_fail_with(Core *core, const ErrorInfo *err) noexcept nogil:
    """Records `err` as the error of a refused call (GetLastCallError) and reports it."""
    pthread_mutex_lock(&core.lock)
    core.call_error = err[0]
    pthread_mutex_unlock(&core.lock)
    core_report_error(core, err)


# ------------------------------------------------------------------ the activity

cdef bint _join_locked(Core *core, uint64_t activity) noexcept nogil:
    """With core.lock held: waits until the worker of `activity` (if it still has
    one) is joined, joining it itself unless another thread already does. False
    when a newer activity began meanwhile (it is not touched)."""
    cdef pthread_t worker
    while core.has_worker and core.activity == activity:
        if core.joining:
            pthread_cond_wait(&core.changed, &core.lock)
            continue
        core.joining = True
        worker = core.worker
        TC_ATOMIC_STORE(&core.cancel, 1)
        pthread_mutex_unlock(&core.lock)
        pthread_join(worker, NULL)
        pthread_mutex_lock(&core.lock)
        core.has_worker = False
        core.joining = False
        pthread_cond_broadcast(&core.changed)
    return core.activity == activity


cdef int32_t _end_command(int32_t kind) noexcept nogil:
    if kind == END_RESET: return CMD_RESET
    if kind == END_DESTROY: return CMD_DESTROY
    if kind == END_DROP_PROGRAM: return CMD_DROP_PROGRAM
    return CMD_OUT_OF_TRAJECTORY


cdef void _publish_position(Core *core, const double *position) noexcept nogil:
    """GetPos after an end: standing at `position`, counters cleared."""
    cdef SnapshotData *data = <SnapshotData *>calloc(1, sizeof(SnapshotData))
    if data == NULL:
        return
    data.pos.m_fileIdx = -1
    memcpy(&data.pos.m_s, position, sizeof(P10DOUBLE))
    data.pos.m_e = data.pos.m_s
    data.pos.m_calcS = data.pos.m_s
    data.pos.m_calcE = data.pos.m_s
    snapshot_publish(&core.snap, data)
    free(data)


cdef LoadedProgram *_apply_end_locked(Core *core, int32_t kind) noexcept nogil:
    """With core.lock held and no activity running: the end `kind` (status from the
    table). Returns the program reference the caller must release after unlocking."""
    cdef LoadedProgram *dropped = NULL
    cdef int32_t after = status_after(core_status(core), _end_command(kind), core.program != NULL)
    if kind == END_DESTROY or kind == END_DROP_PROGRAM:
        dropped = core.program
        core.program = NULL
        memset(&core.size_info, 0, sizeof(GCODE_INFO))
        after = status_after(core_status(core), _end_command(kind), False)
    if kind == END_RESET and core.n_pending > 0:
        memcpy(core.position, core.pending_position, core.n_pending * sizeof(double))
    core.n_pending = 0
    if kind != END_OUT_OF_TRAJECTORY:
        machine_forget(core)
    if kind == END_DESTROY or kind == END_RESET:
        _publish_position(core, core.position)
    if after != TC_KEEP and after != TC_REFUSED:
        core_set_status(core, after)
    return dropped


cdef void _refresh_size_info(Core *core) noexcept nogil:
    """GetGCodeSizeInfo of the core's program from the current machine position: a
    pass over the immutable program, outside the lock."""
    cdef LoadedProgram *lp
    cdef Placement placement
    cdef GCODE_INFO *info = <GCODE_INFO *>malloc(sizeof(GCODE_INFO))
    cdef bint ok = False
    if info == NULL:
        return
    pthread_mutex_lock(&core.lock)
    lp = loaded_program_ref(core.program)
    if lp != NULL:
        placement_init(&placement, &lp.prog, core.position)
    pthread_mutex_unlock(&core.lock)
    if lp != NULL:
        ok = placed_extent(&lp.prog, &placement, info)
        pthread_mutex_lock(&core.lock)
        if ok and core.program == lp and memcmp(placement.start, core.position, sizeof(placement.start)) == 0:
            core.size_info = info[0]
        pthread_mutex_unlock(&core.lock)
        loaded_program_release(lp)
    free(info)


cdef int32_t core_end(Core *core, int32_t kind, const char *what, uint32_t n_coords,
                      const double *coords) noexcept nogil:
    """DestroyCNC, ResetCNC (with the coordinates of the new start position),
    ResetStatusCNC: ends the activity and applies `kind`. Inside a callback of a
    running activity the end is left to that activity's worker (it applies it once
    the callback returns). TOOL_CHAIN_SUCCESS, or the table's refusal."""
    cdef int32_t status
    cdef LoadedProgram *dropped = NULL
    pthread_mutex_lock(&core.lock)
    status = core_status(core)
    if status_after(status, _end_command(kind), core.program != NULL) == TC_REFUSED:
        pthread_mutex_unlock(&core.lock)
        if tc_worker_core == <void *>core:
            return core_fail(core, ERR_REENTRANT, what)
        return core_refuse(core, what, status)
    if n_coords > 0:                # applied after the activity (its worker stores where it stopped)
        memcpy(core.pending_position, coords, n_coords * sizeof(double))
        core.n_pending = n_coords
    if status > 0 and core.has_worker and on_worker_thread():
        if kind == END_DESTROY or core.deferred_end == END_NONE:
            core.deferred_end = kind
        TC_ATOMIC_STORE(&core.cancel, 1)
        pthread_mutex_unlock(&core.lock)
        return TOOL_CHAIN_SUCCESS
    if _join_locked(core, core.activity):
        dropped = _apply_end_locked(core, kind)
    pthread_mutex_unlock(&core.lock)
    loaded_program_release(dropped)
    if kind == END_RESET:
        _refresh_size_info(core)
    return TOOL_CHAIN_SUCCESS


cdef int32_t core_begin(Core *core, int32_t command, const char *what,
                        void *(*body)(void *) noexcept nogil, Job *job) noexcept nogil:
    """Starts an activity: checks the transition table, joins the finished worker of
    the last activity, sets the running status and starts `body(job)` -- all in one
    critical section. Takes ownership of `job` (freed here on refusal).
    TOOL_CHAIN_SUCCESS or TOOL_CHAIN_ERROR (with the call's error)."""
    cdef int32_t status, after, err = 0
    if tc_worker_core == <void *>core:
        job_free(job)
        return core_fail(core, ERR_REENTRANT, what)
    pthread_mutex_lock(&core.lock)
    while True:
        status = core_status(core)
        after = status_after(status, command, core.program != NULL)
        if after == TC_REFUSED:
            break
        if (command == CMD_SIMULATE or command == CMD_TEST or _machine_run(command)) and core.program == NULL:
            err = ERR_NOTHING_COMPILED
            break
        if not core.has_worker:
            break
        _join_locked(core, core.activity)   # finished: the join is short
    if after == TC_REFUSED or err != 0:
        pthread_mutex_unlock(&core.lock)
        job_free(job)
        if err != 0:
            return core_fail(core, err, NULL)
        return core_refuse(core, what, status)
    if (_machine_run(command) or command == CMD_GOTO) and not machine_prepare(core):
        pthread_mutex_unlock(&core.lock)
        job_free(job)
        return core_fail(core, ERR_OUT_OF_MEMORY, NULL)
    core.activity += 1
    TC_ATOMIC_STORE(&core.cancel, 0)
    TC_ATOMIC_STORE(&core.stop, 0)
    core.deferred_end = END_NONE
    memset(&core.error, 0, sizeof(ErrorInfo))
    if command == CMD_COMPILE:
        memcpy(core.compile_files, job.files, sizeof(core.compile_files))
    core_set_status(core, after)
    job.core = core
    if pthread_create(&core.worker, NULL, body, job) != 0:
        core.compile_files[0] = core.compile_files[1] = core.compile_files[2] = -1
        core_set_status(core, status)
        pthread_mutex_unlock(&core.lock)
        job_free(job)
        return core_fail(core, ERR_OUT_OF_MEMORY, NULL)
    core.has_worker = True
    pthread_mutex_unlock(&core.lock)
    return TOOL_CHAIN_SUCCESS


cdef inline bint _machine_run(int32_t command) noexcept nogil:
    return (command == CMD_FORWARD or command == CMD_FORWARD_NO_M or command == CMD_BACKWARD
            or command == CMD_FORWARD_SKIP_M or command == CMD_CONNECT)


cdef void core_finish(Core *core, int32_t event) noexcept nogil:
    """The worker's last step: an end asked from inside a callback, else the status
    of `event` (EV_DONE, EV_STOPPED) unless an ending call cancelled the activity
    (that call sets the status once it has joined the worker)."""
    _finish(core, event, TC_KEEP)


cdef void core_finish_to(Core *core, int32_t status) noexcept nogil:
    """core_finish for an activity that gave up before it changed anything: the
    status it began in comes back."""
    _finish(core, -1, status)


cdef void _finish(Core *core, int32_t event, int32_t status) noexcept nogil:
    cdef LoadedProgram *dropped = NULL
    cdef int32_t kind, after
    pthread_mutex_lock(&core.lock)
    kind = core.deferred_end
    core.deferred_end = END_NONE
    core.compile_files[0] = core.compile_files[1] = core.compile_files[2] = -1
    if kind != END_NONE:
        dropped = _apply_end_locked(core, kind)
    elif not TC_ATOMIC_LOAD(&core.cancel):
        after = status if status != TC_KEEP else status_after(core_status(core), event, core.program != NULL)
        if after != TC_KEEP and after != TC_REFUSED:
            core_set_status(core, after)
    pthread_mutex_unlock(&core.lock)
    loaded_program_release(dropped)
    if kind == END_RESET:
        _refresh_size_info(core)
    worker_thread_mark(NULL)


cdef Job *job_new() noexcept nogil:
    cdef Job *job = <Job *>calloc(1, sizeof(Job))
    if job != NULL:
        job.files[0] = job.files[1] = job.files[2] = -1
    return job


cdef void job_free(Job *job) noexcept nogil:
    if job != NULL:
        free(job.text)
        free(job.prefix)
        free(job.postfix)
        free(job.add_code)
        free(job)


# ------------------------------------------------------------------ compilation

cdef void _compile_progress(void *ctx, int percent) noexcept nogil:
    core_progress(<Core *>ctx, <uint32_t>percent)


cdef void _compile_output(void *ctx, int tab, const char *text) noexcept nogil:
    core_output(<Core *>ctx, <uint32_t>tab, text)


cdef void _compile_warn(void *ctx, const ErrorInfo *warning) noexcept nogil:
    core_warning(<Core *>ctx, warning)


cdef int _compile_and_compensate(Core *core, CompileInput *inp, ProgramBuilder *build, ErrorInfo *err,
                                 GCODE_INFO *extent, bint *measured) noexcept nogil:
    """The compiler, and the compensation's pass beside it in a thread of its own
    (pipeline.pyx), then the compensation's merge with the extent measured beside it
    (*measured: `extent` is filled): COMPILE_OK, or the compiler's failure, else the
    compensation's (err filled)."""
    cdef CompState comp
    cdef Follow follow
    cdef ExtentBeside beside
    cdef ErrorInfo *comp_err = <ErrorInfo *>calloc(1, sizeof(ErrorInfo))
    cdef int result
    measured[0] = False
    if comp_err == NULL:
        set_error(err, ERR_OUT_OF_MEMORY, inp.file_idx, 0, NULL, 0)
        return COMPILE_ERROR
    compensate_begin(&comp, build, &inp.params, comp_err, _compile_output, _compile_warn, core)
    follow_init(&follow, build, compensate_feed, &comp)
    build.follow = &follow
    result = compile_program(inp, build, err)
    if result == COMPILE_OK and build.prog.compensated:
        follow_finish(&follow, build.prog.n_parts)  # the pass takes the rest and ends
    else:
        follow_abandon(&follow)
    build.follow = NULL
    follow_destroy(&follow)
    if result == COMPILE_OK and build.prog.compensated:
        extent_beside_begin(&beside, &build.prog)
        result = compensate_end(&comp, &beside.watch)
        measured[0] = extent_beside_end(&beside, result == COMPILE_OK, extent)
        if result != COMPILE_OK:
            err[0] = comp_err[0]
    else:
        compensate_free(&comp)
    free(comp_err)
    return result


cdef int _compile_job(Core *core, Job *job, ProgramBuilder *build, GCODE_INFO *extent, ErrorInfo *err) noexcept nogil:
    """Reads (if need be), compiles, compensates, inserts arcs and measures the
    program of `job`; no lock is held but for copying the core's settings."""
    cdef CompileInput *inp
    cdef int32_t read_error = 0
    cdef uint32_t machine_bits
    cdef size_t n_parts
    cdef bint measured
    cdef int result
    cdef char text[400]
    if job.text == NULL:
        job.text = read_whole_file(job.name, &job.length, &read_error)
        if job.text == NULL:
            set_error_text(err, read_error, job.files[0], 0, job.name)
            return COMPILE_ERROR
    inp = <CompileInput *>calloc(1, sizeof(CompileInput))
    if inp == NULL:
        set_error(err, ERR_OUT_OF_MEMORY, job.files[0], 0, NULL, 0)
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
    result = _compile_and_compensate(core, inp, build, err, extent, &measured)
    # the source is not read again: its memory is given back before the plan takes as
    # much (freshly freed memory is cheaper to fault in than new)
    free(job.text)
    job.text = NULL
    inp.text = NULL
    n_parts = build.prog.n_parts
    if result == COMPILE_OK:
        result = insert_arcs(build, &inp.params, err)
    measured = measured and build.prog.n_parts == n_parts      # no automatic arcs came in since
    if result == COMPILE_OK and plan_beside_extent(build, &inp.params, machine_bits, inp.plan_window,
                                                   extent, measured) != COMPILE_OK:
        result = COMPILE_ERROR
        set_error(err, ERR_OUT_OF_MEMORY, job.files[0], 0, NULL, 0)
    if result == COMPILE_OK and TC_ATOMIC_LOAD(&core.cancel):
        result = COMPILE_CANCELLED          # ended while it finished: nothing is published
    if result == COMPILE_CANCELLED:
        set_error(err, ERR_CANCELLED, job.files[0], 0, NULL, 0)
    free(inp)
    return result


cdef void *_compile_body(void *arg) noexcept nogil:
    cdef Job *job = <Job *>arg
    cdef Core *core = job.core
    cdef ProgramBuilder build
    cdef ErrorInfo *err = <ErrorInfo *>calloc(1, sizeof(ErrorInfo))
    cdef GCODE_INFO *extent = <GCODE_INFO *>calloc(1, sizeof(GCODE_INFO))
    cdef LoadedProgram *loaded = NULL
    cdef LoadedProgram *old
    cdef int result = COMPILE_ERROR
    cdef char text[400]
    worker_thread_mark(core)
    program_builder_init(&build)
    if err != NULL and extent != NULL:
        result = _compile_job(core, job, &build, extent, err)
        if result == COMPILE_OK:
            program_builder_trim(&build)
            loaded = loaded_program_new(&build.prog, extent, job.files)     # the program alone
            if loaded == NULL:
                result = COMPILE_ERROR
                set_error(err, ERR_OUT_OF_MEMORY, job.files[0], 0, NULL, 0)
    if result != COMPILE_OK and err != NULL:
        err.n_lines = <int32_t>build.prog.n_lines   # lines of the main file, counted before compiling
    pthread_mutex_lock(&core.lock)
    old = core.program
    core.program = loaded
    if loaded != NULL:
        core.size_info = loaded.extent
        memset(&core.error, 0, sizeof(ErrorInfo))
    else:
        memset(&core.size_info, 0, sizeof(GCODE_INFO))
        if err != NULL:
            core.error = err[0]
        else:
            set_error(&core.error, ERR_OUT_OF_MEMORY, job.files[0], 0, NULL, 0)
    pthread_mutex_unlock(&core.lock)
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
    job_free(job)
    core_finish(core, EV_DONE)
    return NULL


cdef int32_t core_start_compile(Core *core, const char *name, char *text, size_t length) noexcept nogil:
    """CompileFromFile (text NULL: the worker reads the file `name`) and
    CompileFromMemory (takes ownership of `text`)."""
    cdef Job *job = job_new()
    if job == NULL:
        free(text)
        return core_fail(core, ERR_OUT_OF_MEMORY, NULL)
    job.text = text
    job.length = length
    strncpy(job.name, name, sizeof(job.name) - 1)
    job.files[0] = core_file_to_idx(core, name)
    pthread_mutex_lock(&core.lock)
    job.prefix = strdup(core.prefix) if core.prefix != NULL else NULL
    job.postfix = strdup(core.postfix) if core.postfix != NULL else NULL
    pthread_mutex_unlock(&core.lock)
    if job.prefix != NULL:
        job.files[1] = core_file_to_idx(core, "__prefix__")
    if job.postfix != NULL:
        job.files[2] = core_file_to_idx(core, "__postfix__")
    return core_begin(core, CMD_COMPILE, "compilation", _compile_body, job)


