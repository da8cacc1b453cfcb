# Runs of a compiled program in the core's worker: simulation (regime 10) hands
# every part to the driver callbacks as fast as possible; test (regime 20) does
# the same and checks the machine limits. Both keep GetPos current.
from libc.string cimport memset, memcpy
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


cdef void _update_position(Core *core, const Program *prog, size_t i, const SIMPLE_GM_PARAMS *gm,
                           double length, double run_time) noexcept nogil:
    """GetPos after part i: position, counters and lengths."""
    cdef const Part *p = &prog.parts[i]
    cdef GM_PARAMS_ENHANCED *enh = &core.enh
    cdef bint rapid
    pthread_mutex_lock(&core.lock)
    core.pos = gm[0]
    core.pos.m_calcS = gm.m_calcE
    memcpy(core.position, &gm.m_calcE, sizeof(core.position))
    if p.kind == PART_MOTION:
        rapid = p.func == 0
        if core.last_motion == 2 and rapid:
            enh.m_nWorkToG00Changes += 1
        elif core.last_motion == 1 and not rapid:
            enh.m_nG00ToWorkChanges += 1
        core.last_motion = 1 if rapid else 2
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
        enh.m_calcFeed = part_feed(p, &core.params)
    elif p.kind == PART_MFUNC:
        enh.m_nMCounter += 1
    enh.m_MasterEditorLine = p.line if p.file_idx == prog.main_file_idx else enh.m_MasterEditorLine
    enh.m_MasterFileIdx = <uint32_t>prog.main_file_idx
    enh.m_cncRunTime = run_time
    core.pos.m_pars.N = <float>enh.m_actWorkPartsLen
    core.pos.m_pars.T = <float>enh.m_actG00PartsLen
    core.pos.m_pars.P = 100.0
    pthread_mutex_unlock(&core.lock)


cdef void _send_add_code(Core *core, const char *code, TC_DriverMFunc send, intptr_t user) noexcept nogil:
    """StartCNCEx addCode: its M words become M parts sent before the program."""
    cdef SIMPLE_GM_PARAMS gm
    cdef char *end
    cdef long number
    cdef float *cells = <float *>&gm.m_pars
    cdef int k
    if code == NULL or send == NULL:
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
                memcpy(&gm.m_s, core.position, sizeof(P10DOUBLE))
                gm.m_e = gm.m_s
                gm.m_calcS = gm.m_s
                gm.m_calcE = gm.m_s
                send(user, &gm)
                code = end
                continue
        code += 1


cdef void *_run_body(void *arg) noexcept nogil:
    cdef Core *core = <Core *>arg
    cdef Program *prog = &core.program      # stable: nobody frees it while we run
    cdef Callback init_cb = core_callback(core, CB_DRIVER_INITIALIZE)
    cdef Callback g_cb = core_callback(core, CB_DRIVER_G_FUNC)
    cdef Callback m_cb = core_callback(core, CB_DRIVER_M_FUNC)
    cdef Callback end_cb = core_callback(core, CB_DRIVER_END)
    cdef GCODE_PARAMETERS params
    cdef MACHINE_PARAMETERS machine
    cdef SIMPLE_GM_PARAMS gm
    cdef ErrorInfo first_error
    cdef double start[10]
    cdef double run_time = 0.0, t, length
    cdef int32_t regime = core.run_regime
    cdef bint testing = regime == RUN_TEST
    cdef bint stopped = False
    cdef size_t i, n = prog.n_parts
    cdef uint32_t percent, last_percent = 0
    cdef const Part *p
    pthread_mutex_lock(&core.lock)
    params = core.params
    machine = core.machine
    memcpy(start, prog.start, sizeof(start))
    memset(&core.enh, 0, sizeof(GM_PARAMS_ENHANCED))
    core.enh.m_relFeed = core.rel_feed
    core.last_motion = 0
    pthread_mutex_unlock(&core.lock)
    memset(&first_error, 0, sizeof(first_error))
    if init_cb.fn != NULL:
        (<TC_DriverInitialize>init_cb.fn)(init_cb.user, start, 10, regime)
    _send_add_code(core, core.add_code, <TC_DriverMFunc>m_cb.fn, m_cb.user)
    for i in range(n):
        if TC_ATOMIC_LOAD(&core.cancel):
            break
        if TC_ATOMIC_LOAD(&core.stop):
            stopped = True
            break
        p = &prog.parts[i]
        part_to_gm(prog, i, &gm)
        length = gm.m_pars.N if p.kind == PART_MOTION else 0.0
        if params.calcTime:
            t = plan_part_time(prog, i)
            if t > 0:
                run_time += t
        if p.kind == PART_MOTION or p.kind == PART_DWELL:
            if testing and p.kind == PART_MOTION:
                check_limits(core, &machine, &gm, p, &first_error)
            if g_cb.fn != NULL:
                (<TC_DriverGFunc>g_cb.fn)(g_cb.user, &gm)
        elif p.kind == PART_MFUNC:
            if m_cb.fn != NULL:
                (<TC_DriverMFunc>m_cb.fn)(m_cb.user, &gm)
        elif p.kind == PART_PRINT:
            core_output(core, 2, prog.texts + p.aux)
        _update_position(core, prog, i, &gm, length, run_time)
        percent = <uint32_t>((i + 1) * 100 // n)
        if percent != last_percent:
            last_percent = percent
            core_progress(core, percent)
    if end_cb.fn != NULL:
        (<TC_DriverEnd>end_cb.fn)(end_cb.user)
    pthread_mutex_lock(&core.lock)
    if first_error.number != 0:
        core.error = first_error
    if params.calcTime and not stopped and TC_ATOMIC_LOAD(&core.cancel) == 0:
        if 0 <= prog.main_file_idx < MAX_FILES:
            core.run_times[prog.main_file_idx] = run_time
        core.enh.m_cncRunTime = run_time
    pthread_mutex_unlock(&core.lock)
    if TC_ATOMIC_LOAD(&core.cancel):
        return NULL                       # ResetCNC / DestroyCNC set the status
    if testing:
        core_set_status(core, CNC_STATUS_TEST_STOPPED if stopped else CNC_STATUS_TEST_DONE)
    else:
        core_set_status(core, CNC_STATUS_SIMULATION_STOPPED if stopped else CNC_STATUS_SIMULATION_DONE)
    return NULL


cdef int32_t core_start_run(Core *core, int32_t regime, const char *add_code) noexcept nogil:
    """StartCNCEx: simulation (10) and test (20) of the compiled program."""
    cdef int32_t status = core_status(core)
    if regime != RUN_SIMULATION and regime != RUN_TEST:
        if regime == RUN_FORWARD or regime == RUN_FORWARD_NO_M or regime == RUN_BACKWARD or regime == RUN_FORWARD_SKIP_FIRST_M:
            core_fail(core, ERR_NOT_IMPLEMENTED, "StartCNCEx of the offline machine (regimes 30-33)")
        else:
            core_fail(core, ERR_BAD_STATUS, "StartCNCEx regime")
        return TOOL_CHAIN_ERROR
    if not core.has_program or status == CNC_STATUS_NOTHING_LOADED:
        core_fail(core, ERR_NOTHING_COMPILED, NULL)
        return TOOL_CHAIN_ERROR
    if not core_claim(core, CNC_STATUS_SIMULATING if regime == RUN_SIMULATION else CNC_STATUS_TESTING):
        core_fail(core, ERR_BUSY, "compilation or run")
        return TOOL_CHAIN_ERROR
    pthread_mutex_lock(&core.lock)
    free(core.add_code)
    core.add_code = strdup(add_code) if add_code != NULL else NULL
    memset(&core.error, 0, sizeof(ErrorInfo))
    core.run_regime = regime
    pthread_mutex_unlock(&core.lock)
    if not core_launch(core, _run_body):
        core_set_status(core, status)
        core_fail(core, ERR_OUT_OF_MEMORY, NULL)
        return TOOL_CHAIN_ERROR
    return TOOL_CHAIN_SUCCESS
