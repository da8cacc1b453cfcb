# Runs of a compiled program in the core's worker: simulation (regime 10) hands
# every part to the driver callbacks as fast as possible; test (regime 20) does
# the same and checks the machine limits. Both keep GetPos current. What the driver
# hears and GetPos shows is the run's session (runtime/session.pyx), as on the
# machine; a simulation does not wait for M functions answered TC_MFUNC_LATER.
from libc.string cimport memcpy
from libc.stdlib cimport free

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
    cdef bint inside = True
    cdef int k
    for k in range(AXES):
        if not enabled[k]:
            continue
        if end[k] < ref[k] + lo[k] - LENGTH_EPS or end[k] > ref[k] + hi[k] + LENGTH_EPS:
            err_machine_limit(&err, gm.m_fileIdx, <int32_t>p.line, axis_name(k), end[k], ref[k] + lo[k], ref[k] + hi[k])
            if first_error.number == 0:
                first_error[0] = err
            core_report_error(core, &err)
            inside = False
    return inside


cdef void _show_part(Standing *s, const Program *prog, size_t i, const SIMPLE_GM_PARAMS *gm,
                     double *lengths, double run_time) noexcept nogil:
    """Where the run stands after part i: at its end, the part as the driver got it,
    the counters and lengths so far; the feeds and lengths of the last motion part
    and the last line of the main file stay shown until another replaces them."""
    cdef const Part *p = &prog.parts[i]
    cdef double length
    s.part = gm[0]
    memcpy(s.output, &gm.m_calcE, sizeof(s.output))
    memcpy(s.drives, &gm.m_calcE, sizeof(s.drives))
    session_count(&s.counts, p)
    standing_part(s, p.kind, p.func, p.kind == PART_MFUNC and m_function_waits(
        p.func, (p.flags & FLAG_CONTINUOUS_M) != 0), part_shift(prog, p))
    if p.kind == PART_MOTION:
        length = gm.m_pars.N
        lengths[0 if p.func == 0 else 1] += length
        s.part_len = length
        s.part_remain = 0.0
        s.set_feed = part_settings(prog, p).feed
        s.calc_feed = plan_calc_feed(prog, i)
    s.cut_len = lengths[1]
    s.rapid_len = lengths[0]
    s.fill = 100.0
    if part_settings(prog, p).file_idx == prog.main_file_idx:
        s.master_line = p.line
    s.master_file = <uint32_t>prog.main_file_idx
    s.run_time = run_time


cdef void *simulation_body(void *arg) noexcept nogil:
    """The worker of a simulation (10) or test (20): every part of the program to the
    driver callbacks, in order, as fast as possible."""
    cdef RunJob *job = <RunJob *>arg
    cdef Core *core = job.head.core
    cdef LoadedProgram *loaded
    cdef const Program *prog
    cdef Session session
    cdef GCODE_PARAMETERS *params = <GCODE_PARAMETERS *>tc_malloc(sizeof(GCODE_PARAMETERS))
    cdef MACHINE_PARAMETERS *machine = <MACHINE_PARAMETERS *>tc_malloc(sizeof(MACHINE_PARAMETERS))
    cdef Standing *shown = <Standing *>tc_calloc(1, sizeof(Standing))
    cdef ErrorInfo *first_error = <ErrorInfo *>tc_calloc(1, sizeof(ErrorInfo))
    cdef SIMPLE_GM_PARAMS gm
    cdef char *stop_code
    cdef double start[AXES]
    cdef double lengths[2]              # rapids, cuts
    cdef Placement placement
    cdef PlacedPlan plan
    cdef double run_time = 0.0, t
    cdef bint testing = job.regime == RUN_TEST
    cdef bint stopped = False, complete = False
    cdef size_t i, n
    cdef uint32_t percent, last_percent = 0
    cdef const Part *p
    tc_set_stage("the simulation")
    worker_thread_mark(core)
    lengths[0] = lengths[1] = 0.0
    pthread_mutex_lock(&core.lock)
    loaded = loaded_program_ref(core.program)       # core_start made sure there is one
    if params != NULL and machine != NULL:
        params[0] = core.params
        machine[0] = core.machine
    memcpy(start, core.position, sizeof(start))
    pthread_mutex_unlock(&core.lock)
    if loaded == NULL or params == NULL or machine == NULL or shown == NULL or first_error == NULL:
        core_keep_error(core, False, NULL)         # out of memory
        stopped = True
    else:
        prog = &loaded.prog
        n = prog.n_parts
        placement_init(&placement, prog, start)
        placed_plan_make(&plan, prog, &placement)      # the times of a run from here
        standing_clear(shown)
        shown.rel_feed = TC_ATOMIC_LOAD_D(&core.rel_feed)
        getpos_publish(&core.snap, shown)
        session_open(&session, core, job.regime, False)
        session_begin(&session, start)
        session_add_code(&session, job.add_code, start, 0, False)
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
            if params.calcTime and prog.plan != NULL:
                t = placed_plan_part(&plan, i).time
                if t > 0:
                    run_time += t
            if testing and p.kind == PART_MOTION:
                check_limits(core, machine, &gm, p, first_error)
            session_part(&session, prog, i, &gm)
            _show_part(shown, prog, i, &gm, lengths, run_time)
            shown.rel_feed = TC_ATOMIC_LOAD_D(&core.rel_feed)
            getpos_publish(&core.snap, shown)
            percent = <uint32_t>((i + 1) * 100 // n)
            if percent != last_percent:
                last_percent = percent
                core_progress(core, percent)
        if stopped:
            stop_code = session_take_stop_code(core)
            session_add_code(&session, stop_code, shown.output, 0, True)
            free(stop_code)
        session_end(&session)
        if first_error.number != 0:
            core_keep_error(core, False, first_error)
        if params.calcTime and complete and 0 <= prog.main_file_idx < MAX_FILES:
            core_set_file_run_time(core, prog.main_file_idx, run_time)
        placed_plan_free(&plan)
    loaded_program_release(loaded)
    free(params)
    free(machine)
    free(shown)
    free(first_error)
    job_free(&job.head)
    core_finish(core, EV_STOPPED if stopped else EV_DONE)
    return NULL
