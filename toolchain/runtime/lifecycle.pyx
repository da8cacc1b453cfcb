# The life of a core's activities: one table from each command that begins an
# activity to the worker that runs it (activity_of), the begin, the end and the
# join. docs/threading.md draws it:
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
from libc.stdlib cimport free
from libc.string cimport memset, memcpy, memcmp


cdef bint activity_of(int32_t command, Activity *a) noexcept nogil:
    """The table: for each command that begins an activity, its worker, its job's
    type (size), whether it needs a compiled program and what is made ready for it
    under core.lock before its worker starts. False for any other command."""
    memset(a, 0, sizeof(Activity))
    if command == CMD_COMPILE:
        a.body = compile_body
        a.job_size = sizeof(CompileJob)
        a.prepare = compile_prepare
    elif command == CMD_SIMULATE or command == CMD_TEST:
        a.body = simulation_body
        a.job_size = sizeof(RunJob)
        a.needs_program = True
    elif (command == CMD_FORWARD or command == CMD_FORWARD_NO_M or command == CMD_BACKWARD
          or command == CMD_FORWARD_SKIP_M):
        a.body = machine_run_body
        a.job_size = sizeof(RunJob)
        a.needs_program = True
        a.prepare = machine_prepare
    elif command == CMD_GOTO:
        a.body = machine_goto_body
        a.job_size = sizeof(GotoJob)
        a.prepare = machine_prepare
    elif command == CMD_CONNECT:
        a.body = connect_body
        a.job_size = sizeof(ConnectJob)
        a.needs_program = True
        a.prepare = machine_prepare
    else:
        return False
    return True


cdef int32_t run_command(int32_t regime) noexcept nogil:
    """The command of a StartCNCEx regime (-1 for none)."""
    if regime == RUN_SIMULATION: return CMD_SIMULATE
    if regime == RUN_TEST: return CMD_TEST
    if regime == RUN_FORWARD: return CMD_FORWARD
    if regime == RUN_FORWARD_NO_M: return CMD_FORWARD_NO_M
    if regime == RUN_BACKWARD: return CMD_BACKWARD
    if regime == RUN_FORWARD_SKIP_FIRST_M: return CMD_FORWARD_SKIP_M
    return -1


cdef Job *job_new(int32_t command) noexcept nogil:
    """An empty job of the activity `command` begins (its type from the table);
    NULL when out of memory or `command` begins no activity."""
    cdef Activity a
    cdef Job *job
    if not activity_of(command, &a):
        return NULL
    job = <Job *>tc_calloc(1, a.job_size)
    if job != NULL:
        job.command = command
    return job


cdef void job_free(Job *job) noexcept nogil:
    """A job and what it owns."""
    cdef CompileJob *c
    if job == NULL:
        return
    if job.command == CMD_COMPILE:
        c = <CompileJob *>job
        free(c.text)
        free(c.prefix)
        free(c.postfix)
    elif job.command == CMD_CONNECT:
        free((<ConnectJob *>job).add_code)
    elif job.command != CMD_GOTO:
        free((<RunJob *>job).add_code)
    free(job)


cdef int32_t core_start_run(Core *core, int32_t regime, const char *add_code) noexcept nogil:
    """StartCNCEx: a run of the regime (its addCode kept) as the core's activity."""
    cdef int32_t command = run_command(regime)
    cdef RunJob *job
    if command < 0:
        err_bad_regime(refusal(), -1, 0)
        return core_fail(core, refusal())
    job = <RunJob *>job_new(command)
    if job == NULL:
        err_out_of_memory(refusal(), -1, 0)
        return core_fail(core, refusal())
    job.regime = regime
    if add_code != NULL:
        job.add_code = tc_strdup(add_code)
    return core_start(core, &job.head, "StartCNCEx")


cdef int32_t core_stop(Core *core, const char *add_code) noexcept nogil:
    """StopCNCEx: asks the running activity to stop (it ends at EV_STOPPED); the run
    sends `add_code`'s M functions once it stands (session.pyx). A stop also answers
    an M function that waits for a confirmation."""
    cdef int32_t status = core_status(core)
    if status_after(status, CMD_STOP, False) == TC_REFUSED:
        return core_refuse(core, "StopCNCEx", status)
    if add_code != NULL and add_code[0] != 0:
        session_keep_stop_code(core, add_code)
    pthread_mutex_lock(&core.lock)
    TC_ATOMIC_STORE(&core.stop, TC_ATOMIC_LOAD(&core.stop) + 1)     # the count tells a new stop
    pthread_cond_broadcast(&core.changed)          # a worker waiting for a confirmation
    pthread_mutex_unlock(&core.lock)
    return TOOL_CHAIN_SUCCESS


cdef inline bint _on_worker_thread() noexcept nogil:
    """True inside a callback of any core's running activity (a library thread)."""
    return tc_worker_core != NULL


# ------------------------------------------------------------------ begin, end, join

cdef int32_t core_start(Core *core, Job *job, const char *what) noexcept nogil:
    """Starts the activity of `job` (its command's row of the table): checks the
    transition table, joins the finished worker of the last activity, prepares the
    activity, sets the running status and starts its worker -- all in one critical
    section. Takes ownership of `job` (freed here on refusal). TOOL_CHAIN_SUCCESS or
    TOOL_CHAIN_ERROR (with the call's error; `what` names the call)."""
    cdef int32_t status, after
    cdef bint nothing_compiled = False
    cdef int32_t command = job.command
    cdef PublishedError *old_error
    cdef ErrorInfo *why
    cdef Activity a
    activity_of(command, &a)
    if tc_worker_core == <void *>core:
        job_free(job)
        err_reentrant(refusal(), -1, 0, what)
        return core_fail(core, refusal())
    pthread_mutex_lock(&core.lock)
    while True:
        status = core_status(core)
        after = status_after(status, command, core.program != NULL)
        if after == TC_REFUSED:
            break
        if a.needs_program and core.program == NULL:
            nothing_compiled = True
            break
        if not core.has_worker:
            break
        _join_locked(core, core.activity)   # finished: the join is short
    if after == TC_REFUSED or nothing_compiled:
        pthread_mutex_unlock(&core.lock)
        job_free(job)
        if nothing_compiled:
            err_nothing_compiled(refusal(), -1, 0)
            return core_fail(core, refusal())
        return core_refuse(core, what, status)
    if a.prepare != NULL:
        why = <ErrorInfo *>tc_calloc(1, sizeof(ErrorInfo))
        if why == NULL or not a.prepare(core, job, why):
            pthread_mutex_unlock(&core.lock)
            job_free(job)
            if why != NULL:
                core_fail(core, why)
            free(why)
            return TOOL_CHAIN_ERROR
        free(why)
    core.activity += 1
    TC_ATOMIC_STORE(&core.cancel, 0)
    TC_ATOMIC_STORE(&core.stop, 0)
    core.deferred_end = END_NONE
    session_forget_locked(core)
    old_error = core_swap_error_locked(core, False, NULL)
    core_set_status(core, after)
    job.core = core
    if pthread_create(&core.worker, NULL, a.body, job) != 0:
        core.compile_files[0] = core.compile_files[1] = core.compile_files[2] = -1
        core_set_status(core, status)
        pthread_mutex_unlock(&core.lock)
        published_error_release(old_error)
        job_free(job)
        err_out_of_memory(refusal(), -1, 0)
        return core_fail(core, refusal())
    core.has_worker = True
    pthread_mutex_unlock(&core.lock)
    published_error_release(old_error)
    return TOOL_CHAIN_SUCCESS


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
        pthread_cond_broadcast(&core.changed)      # a worker waiting for a confirmation
        pthread_mutex_unlock(&core.lock)
        pthread_join(worker, NULL)
        pthread_mutex_lock(&core.lock)
        core.has_worker = False
        core.joining = False
        pthread_cond_broadcast(&core.changed)
    return core.activity == activity


cdef int32_t _end_command(int32_t kind) noexcept nogil:
    """The status table's command of an end kind (reset, destroy, drop program, out of the
    trajectory)."""
    if kind == END_RESET: return CMD_RESET
    if kind == END_DESTROY: return CMD_DESTROY
    if kind == END_DROP_PROGRAM: return CMD_DROP_PROGRAM
    return CMD_OUT_OF_TRAJECTORY


cdef void _publish_position(Core *core, const double *position) noexcept nogil:
    """With core.lock held, GetPos after an end: standing at `position` (m_calcE: with
    the axis corrections, what the drives are sent), counters cleared."""
    cdef Standing s                     # on the stack: an end never goes without it
    standing_clear(&s)
    memcpy(&s.part.m_s, position, sizeof(P10DOUBLE))
    s.part.m_e = s.part.m_s
    memcpy(s.output, position, sizeof(s.output))
    axis_correction_apply(core.axis_corrections, position, s.drives)
    getpos_publish(&core.snap, &s)


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


cdef int32_t core_size_info(Core *core, GCODE_INFO *out) noexcept nogil:
    """GetGCodeSizeInfo: the loaded program's extents at the current start position
    (measured now when a reset could not); TOOL_CHAIN_ERROR without a program, or with
    the error reported when there is no memory to measure them."""
    cdef bint stale
    cdef int32_t result = TOOL_CHAIN_ERROR
    pthread_mutex_lock(&core.lock)
    stale = core.program != NULL and core.size_info_stale
    pthread_mutex_unlock(&core.lock)
    if stale and not core_refresh_size_info(core):
        err_out_of_memory(refusal(), -1, 0)
        return core_fail(core, refusal())
    pthread_mutex_lock(&core.lock)
    if core.program != NULL:
        out[0] = core.size_info
        result = TOOL_CHAIN_SUCCESS
    pthread_mutex_unlock(&core.lock)
    return result


cdef bint core_refresh_size_info(Core *core) noexcept nogil:
    """GetGCodeSizeInfo of the core's program from the current machine position: a
    pass over the immutable program, outside the lock. False when out of memory: the
    extent is marked stale, and GetGCodeSizeInfo measures it before it answers."""
    cdef LoadedProgram *lp
    cdef Placement placement
    cdef GCODE_INFO extent                 # on the stack: a reset never goes without it
    cdef GCODE_INFO *info = &extent
    cdef bint ok = False
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
            core.size_info_stale = False
        elif not ok and core.program == lp:
            core.size_info_stale = True
        pthread_mutex_unlock(&core.lock)
        loaded_program_release(lp)
    return ok or lp == NULL


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
            err_reentrant(refusal(), -1, 0, what)
            return core_fail(core, refusal())
        return core_refuse(core, what, status)
    if n_coords > 0:                # applied after the activity (its worker stores where it stopped)
        memcpy(core.pending_position, coords, n_coords * sizeof(double))
        core.n_pending = n_coords
    if status > 0 and core.has_worker and _on_worker_thread():
        if kind == END_DESTROY or core.deferred_end == END_NONE:
            core.deferred_end = kind
        TC_ATOMIC_STORE(&core.cancel, 1)
        pthread_cond_broadcast(&core.changed)
        pthread_mutex_unlock(&core.lock)
        return TOOL_CHAIN_SUCCESS
    if _join_locked(core, core.activity):
        dropped = _apply_end_locked(core, kind)
    pthread_mutex_unlock(&core.lock)
    loaded_program_release(dropped)
    if kind == END_RESET:
        core_refresh_size_info(core)
    return TOOL_CHAIN_SUCCESS


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
    """An activity's end in its worker: an end deferred from a callback applied, else (unless an
    ending call cancelled it) the status of `event`, or `status` itself; the program a deferred
    end drops released, the extent measured again after a reset."""
    cdef LoadedProgram *dropped = NULL
    cdef int32_t kind, after
    pthread_mutex_lock(&core.lock)
    kind = core.deferred_end
    core.deferred_end = END_NONE
    session_forget_locked(core)
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
        core_refresh_size_info(core)
    worker_thread_mark(NULL)
