# Runs of a compiled program in the core's worker: simulation (regime 10) hands
# every part to the driver callbacks as fast as possible; test (regime 20) does
# the same and checks the machine limits. Both keep GetPos current.
from libc.string cimport memset, memcpy, strdup
from libc.stdlib cimport malloc, calloc, free
from libc.stdlib cimport strtol
from libc.stdio cimport snprintf

cdef bint check_limits(Core *core, const MACHINE_PARAMETERS *machine, const SIMPLE_GM_PARAMS *gm,
                       const Part *p, ErrorInfo *first_error) noexcept nogil:
    """Regime 20: the compensated end point of a part against the soft limits
    (refCoords + min/max, axes of enableMask). Reports every violation; the first
    one stays the core's error. True when the part is inside."""
    cdef const double *end = <const double *>&gm.m_calcE
    cdef const double *lo = <const double *>&machine.minCoords
    cdef const double *hi = <const double *>&machine.maxCoords
    cdef const double *ref = <const double *>&machine.refCoords
    cdef const int32_t *enabled = <const int32_t *>&machine.enableMask
    cdef ErrorInfo err
    cdef ErrArg args[4]
    cdef bint inside = True
    cdef int k
    for k in range(10):
        if not enabled[k]:
            continue
        if end[k] < ref[k] + lo[k] - 1e-9 or end[k] > ref[k] + hi[k] + 1e-9:
            args[0].text = axis_name(k)
            args[1].text = NULL
            args[1].num = end[k]
            args[2].text = NULL
            args[2].num = ref[k] + lo[k]
            args[3].text = NULL
            args[3].num = ref[k] + hi[k]
            set_error(&err, ERR_MACHINE_LIMIT, p.file_idx, <int32_t>p.line, args, 4)
            if first_error.number == 0:
                first_error[0] = err
            core_report_error(core, &err)
            inside = False
    return inside


cdef void _count_part(SnapshotData *view, const Program *prog, size_t i, const SIMPLE_GM_PARAMS *gm,
                      double length, double run_time, int32_t *last_motion) noexcept nogil:
    """GetPos after part i: position, counters and lengths (the run's own copy,
    published after each part)."""
    cdef const Part *p = &prog.parts[i]
    cdef GM_PARAMS_ENHANCED *enh = &view.enh
    cdef bint rapid
    view.pos = gm[0]
    view.pos.m_calcS = gm.m_calcE
    if p.kind == PART_MOTION:
        rapid = p.func == 0
        if last_motion[0] == 2 and rapid:
            enh.m_nWorkToG00Changes += 1
        elif last_motion[0] == 1 and not rapid:
            enh.m_nG00ToWorkChanges += 1
        last_motion[0] = 1 if rapid else 2
        if rapid:
            enh.m_actG00PartsLen += length
            enh.m_nG00Counter += 1
        else:
            enh.m_actWorkPartsLen += length
            enh.m_nWorkCounter += 1
        enh.m_actPartsLen += length
        enh.m_actPartLen = length
        enh.m_actPartRemain = 0.0
        enh.m_setFeed = p.feed
        enh.m_calcFeed = plan_calc_feed(prog, i)
    elif p.kind == PART_MFUNC:
        enh.m_nMCounter += 1
    enh.m_MasterEditorLine = p.line if p.file_idx == prog.main_file_idx else enh.m_MasterEditorLine
    enh.m_MasterFileIdx = <uint32_t>prog.main_file_idx
    enh.m_cncRunTime = run_time
    view.pos.m_pars.N = <float>enh.m_actWorkPartsLen
    view.pos.m_pars.T = <float>enh.m_actG00PartsLen
    view.pos.m_pars.P = 100.0


cdef void send_add_code(Core *core, const char *code, const double *position) noexcept nogil:
    """StartCNCEx addCode: its M words become M parts sent before the program."""
    cdef SIMPLE_GM_PARAMS gm
    cdef Callback cb
    cdef char *end
    cdef long number
    cdef float *cells = <float *>&gm.m_pars
    cdef int k
    if code == NULL:
        return
    while code[0] != 0:
        if code[0] == b'M' or code[0] == b'm':
            number = strtol(code + 1, &end, 10)
            if end != code + 1:
                memset(&gm, 0, sizeof(gm))
                for k in range(26):
                    cells[k] = INVALID_VALUE_F
                gm.m_func = <int32_t>number
                gm.m_pars.M = <float>number
                gm.m_fileIdx = TOOL_CHAIN_FILE_EXEC
                gm.m_fp = 1.0
                memcpy(&gm.m_s, position, sizeof(P10DOUBLE))
                gm.m_e = gm.m_s
                gm.m_calcS = gm.m_s
                gm.m_calcE = gm.m_s
                if callback_enter(core, SLOT_DRIVER_M_FUNC, &cb):
                    (<TC_DriverMFunc>cb.fn)(cb.user, &gm)
                    callback_leave(core, SLOT_DRIVER_M_FUNC)
                code = end
                continue
        code += 1


cdef void _deliver(Core *core, const Program *prog, size_t i, const SIMPLE_GM_PARAMS *gm) noexcept nogil:
    """Hands part i to its driver callback, looked up now: a removed callback is
    never called again."""
    cdef const Part *p = &prog.parts[i]
    cdef Callback cb
    cdef int32_t slot
    if p.kind == PART_PRINT:
        core_output(core, 2, prog.texts + p.aux)
        return
    if p.kind == PART_MOTION or p.kind == PART_DWELL:
        slot = SLOT_DRIVER_G_FUNC
    elif p.kind == PART_MFUNC:
        slot = SLOT_DRIVER_M_FUNC
    else:
        return
    if callback_enter(core, slot, &cb):
        (<TC_DriverGFunc>cb.fn)(cb.user, gm)
        callback_leave(core, slot)


cdef void *_run_body(void *arg) noexcept nogil:
    cdef Job *job = <Job *>arg
    cdef Core *core = job.core
    cdef LoadedProgram *loaded
    cdef const Program *prog
    cdef Callback cb
    cdef GCODE_PARAMETERS *params = <GCODE_PARAMETERS *>malloc(sizeof(GCODE_PARAMETERS))
    cdef MACHINE_PARAMETERS *machine = <MACHINE_PARAMETERS *>malloc(sizeof(MACHINE_PARAMETERS))
    cdef SnapshotData *view = <SnapshotData *>calloc(1, sizeof(SnapshotData))
    cdef ErrorInfo *first_error = <ErrorInfo *>calloc(1, sizeof(ErrorInfo))
    cdef SIMPLE_GM_PARAMS gm
    cdef double start[10]
    cdef Placement placement
    cdef PlacedPlan plan
    cdef double run_time = 0.0, t, length
    cdef bint testing = job.regime == RUN_TEST
    cdef bint stopped = False, complete = False
    cdef int32_t last_motion = 0
    cdef size_t i, n
    cdef uint32_t percent, last_percent = 0
    cdef const Part *p
    worker_thread_mark(core)
    pthread_mutex_lock(&core.lock)
    loaded = loaded_program_ref(core.program)       # core_begin made sure there is one
    if params != NULL and machine != NULL:
        params[0] = core.params
        machine[0] = core.machine
    memcpy(start, core.position, sizeof(start))
    pthread_mutex_unlock(&core.lock)
    if loaded == NULL or params == NULL or machine == NULL or view == NULL or first_error == NULL:
        pthread_mutex_lock(&core.lock)
        set_error(&core.error, ERR_OUT_OF_MEMORY, -1, 0, NULL, 0)
        pthread_mutex_unlock(&core.lock)
        stopped = True
    else:
        prog = &loaded.prog
        n = prog.n_parts
        placement_init(&placement, prog, start)
        placed_plan_make(&plan, prog, &placement)      # the times of a run from here
        view.pos.m_fileIdx = -1
        view.enh.m_relFeed = TC_ATOMIC_LOAD_D(&core.rel_feed)
        snapshot_publish(&core.snap, view)
        if callback_enter(core, SLOT_DRIVER_INITIALIZE, &cb):
            (<TC_DriverInitialize>cb.fn)(cb.user, start, 10, job.regime)
            callback_leave(core, SLOT_DRIVER_INITIALIZE)
        send_add_code(core, job.add_code, start)
        complete = True
        for i in range(n):
            if TC_ATOMIC_LOAD(&core.cancel):
                complete = False
                break
            if TC_ATOMIC_LOAD(&core.stop):
                stopped = True
                complete = False
                break
            p = &prog.parts[i]
            placed_part_to_gm(prog, i, &placement, &gm)
            length = gm.m_pars.N if p.kind == PART_MOTION else 0.0
            if params.calcTime and prog.plan != NULL:
                t = placed_plan_part(&plan, i).time
                if t > 0:
                    run_time += t
            if testing and p.kind == PART_MOTION:
                check_limits(core, machine, &gm, p, first_error)
            _deliver(core, prog, i, &gm)
            _count_part(view, prog, i, &gm, length, run_time, &last_motion)
            view.enh.m_relFeed = TC_ATOMIC_LOAD_D(&core.rel_feed)
            snapshot_publish(&core.snap, view)
            percent = <uint32_t>((i + 1) * 100 // n)
            if percent != last_percent:
                last_percent = percent
                core_progress(core, percent)
        if callback_enter(core, SLOT_DRIVER_END, &cb):
            (<TC_DriverEnd>cb.fn)(cb.user)
            callback_leave(core, SLOT_DRIVER_END)
        pthread_mutex_lock(&core.lock)
        if first_error.number != 0:
            core.error = first_error[0]
        if params.calcTime and complete and 0 <= prog.main_file_idx < MAX_FILES:
            core.files.run_times[prog.main_file_idx] = run_time
        pthread_mutex_unlock(&core.lock)
        placed_plan_free(&plan)
    loaded_program_release(loaded)
    free(params)
    free(machine)
    free(view)
    free(first_error)
    job_free(job)
    core_finish(core, EV_STOPPED if stopped else EV_DONE)
    return NULL


cdef int32_t core_start_run(Core *core, int32_t regime, const char *add_code) noexcept nogil:
    """StartCNCEx: simulation (10) and test (20) here, 30-33 the offline machine
    (machine/machine.pyx), each as the core's activity."""
    cdef int32_t command
    cdef void *(*body)(void *) noexcept nogil
    cdef Job *job
    if regime == RUN_SIMULATION or regime == RUN_TEST:
        command = CMD_SIMULATE if regime == RUN_SIMULATION else CMD_TEST
        body = _run_body
    elif regime == RUN_FORWARD or regime == RUN_FORWARD_NO_M or regime == RUN_BACKWARD or regime == RUN_FORWARD_SKIP_FIRST_M:
        command = machine_command(regime)
        body = machine_body
    else:
        return core_fail(core, ERR_BAD_REGIME, NULL)
    job = job_new()
    if job == NULL:
        return core_fail(core, ERR_OUT_OF_MEMORY, NULL)
    job.regime = regime
    if add_code != NULL:
        job.add_code = strdup(add_code)
    return core_begin(core, command, "StartCNCEx", body, job)
