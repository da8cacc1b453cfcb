# ConnectCNCEx_Plane: the offline machine goes back onto its trajectory. One
# activity of the core: status 40 while the place is searched (connect_search.pyx,
# the ConnectPointCalc callbacks 1004-1006), 41 while the machine moves there in a
# straight line at motion[3] (connect to the trajectory; the axes of axesForConnect),
# 90 while addCode's M functions are sent there (one answered TC_MFUNC_LATER holds
# it until confirmed), then -31 on the trajectory (stateAfter 2: -50), or, for the
# types that continue (10 11 12 40 41 42 44), on into a forward run from there
# (status 30). The search failing leaves the status where it was, the error in
# GetLastError.

cdef inline bint _connect_continues(uint32_t n_type) noexcept nogil:
    """Whether a connect type goes on forward after the connection (10-12, 40-42, 44) rather
    than standing there."""
    return n_type in (10, 11, 12, 40, 41, 42, 44)


cdef bint _part_calc(void *ctx, size_t part, double *d2, double *point) noexcept nogil:
    """ConnectPointCalc (1005) for one part's candidate: 1 = use its changed values
    (refused, and the connection with them, when they are not finite)."""
    cdef PartCalc *pc = <PartCalc *>ctx
    cdef SIMPLE_GM_PARAMS gm
    cdef P10DOUBLE changed
    cdef double changed_d2 = d2[0]
    placed_part_to_gm(&pc.m.program.prog, part, &pc.m.placement, &gm)
    memcpy(&changed, point, sizeof(changed))
    if (<TC_ConnectPointCalc>pc.cb.fn)(pc.cb.user, &gm, &changed_d2, &changed) != 1:
        return False
    if not (isfinite(changed_d2) and coordinates_finite(<const double *>&changed, AXES)):
        pc.not_finite = True
        return False
    d2[0] = changed_d2
    memcpy(point, &changed, sizeof(changed))
    return True


cdef int _connect_search(Core *core, Machine *m, const GCODE_PARAMETERS *params, const ConnectJob *job,
                         const double *point, ConnectHit *hit, ErrorInfo *err) noexcept nogil:
    """The place the connection goes to, by the type's rule (connect_search.pyx). The
    nearest point of the trajectory offers every part to ConnectPointCalc when the host
    set it (without the index then: the host may change any part's distance)."""
    cdef const Program *prog = &m.program.prog
    cdef const Placement *pl = &m.placement
    cdef ConnectIndex ix
    cdef PartCalc pc
    cdef uint32_t t = job.n_type
    cdef int rc
    if t == 0 or t == 10 or t == 40:
        pc.core = core
        pc.m = m
        pc.not_finite = False
        if callback_enter(core, SLOT_CONNECT_POINT_CALC, &pc.cb):
            rc = connect_nearest_each(prog, pl, job.axes_calc, point, params.maxConnectionDistance,
                                      0, prog.n_parts, _part_calc, &pc, hit, err)
            callback_leave(core, SLOT_CONNECT_POINT_CALC)
            if pc.not_finite:
                err_connect_not_finite(err, -1, 0, "ConnectPointCalc")
                return CONNECT_BAD_ARGUMENT
            return rc
        rc = connect_index_build(&ix, prog, pl, job.axes_calc, err)
        if rc == CONNECT_FOUND:
            rc = connect_nearest(&ix, point, params.maxConnectionDistance, 0, prog.n_parts, hit, err)
        connect_index_free(&ix)
        return rc
    if t == 1 or t == 11 or t == 41:
        return connect_line(prog, pl, job.coords, job.n_coords, False, hit, err)
    if t == 2 or t == 12 or t == 42:
        return connect_line(prog, pl, job.coords, job.n_coords, True, hit, err)
    if t == 30 or t == 32:
        return connect_gindex(prog, pl, job.coords, job.n_coords, t == 32, hit, err)
    if t == 31 or t == 44:
        return connect_gindex_nearest(prog, pl, job.coords, job.n_coords, point, job.axes_calc,
                                      params.maxConnectionDistance, hit, err)
    if t == 20 or t == 21:
        return connect_mfunc(prog, pl, job.coords, job.n_coords, t == 21,
                             <int64_t>m.place.part if m.place.part < prog.n_parts else -1, job.status_before, hit, err)
    if t == 46:
        return connect_exact_point(prog, pl, job.coords, job.n_coords, job.axes_calc,
                                   params.tolerance[6] if params.tolerance[6] > 0.0 else 0.01, hit, err)
    return connect_bad_argument(err, "nType", t, "no such connect type")


cdef bint _connect_end_callback(Core *core, Machine *m, ConnectHit *hit, ErrorInfo *err) noexcept nogil:
    """ConnectPointCalcEnd (1006) with the part found: 1 = use the changed point.
    False (err set) when that point is not finite."""
    cdef Callback cb
    cdef SIMPLE_GM_PARAMS gm
    cdef P10DOUBLE point
    cdef bint finite = True
    if not callback_enter(core, SLOT_CONNECT_POINT_CALC_END, &cb):
        return True
    placed_part_to_gm(&m.program.prog, hit.part, &m.placement, &gm)
    memcpy(&point, hit.point, sizeof(point))
    if (<TC_ConnectPointCalcEnd>cb.fn)(cb.user, &gm, &point) == 1:
        finite = coordinates_finite(<const double *>&point, AXES)
        if finite:
            memcpy(hit.point, &point, sizeof(point))
        else:
            err_connect_not_finite(err, -1, 0, "ConnectPointCalcEnd")
    callback_leave(core, SLOT_CONNECT_POINT_CALC_END)
    return finite


cdef void *connect_body(void *arg) noexcept nogil:
    """The worker of a connection (ConnectCNCEx_Plane, a ConnectJob)."""
    cdef ConnectJob *job = <ConnectJob *>arg
    cdef Core *core = job.head.core
    cdef Feeder f
    cdef Machine *m = machine_worker_begin(&job.head, &f)
    cdef ConnectHit hit
    cdef ErrorInfo *err = <ErrorInfo *>tc_calloc(1, sizeof(ErrorInfo))
    cdef SIMPLE_GM_PARAMS dest
    cdef Callback cb
    cdef double point[AXES]
    cdef uint32_t moving, k
    cdef const char *unbounded
    cdef int32_t finish = EV_STOPPED, end_status = TC_KEEP
    cdef int rc
    tc_set_stage("the connection search")
    if m != NULL and err != NULL:
        memcpy(point, m.motion.position, sizeof(point))     # 31 / 44: nearest to where it stands
        if job.n_type == 0 or job.n_type == 10 or job.n_type == 40:
            memcpy(point, job.coords, min(job.n_coords, AXES) * sizeof(double))
        if callback_enter(core, SLOT_CONNECT_POINT_CALC_START, &cb):
            (<TC_ConnectPointCalcStart>cb.fn)(cb.user, job.n_type, job.n_coords, job.coords, job.axes_calc)
            callback_leave(core, SLOT_CONNECT_POINT_CALC_START)
        rc = _connect_search(core, m, f.params, job, point, &hit, err)
        if rc == CONNECT_FOUND and not TC_ATOMIC_LOAD(&core.cancel):
            if not _connect_end_callback(core, m, &hit, err):
                rc = CONNECT_BAD_ARGUMENT
            # the straight way there: the axes of axesForConnect (0: the first nCoords)
            moving = job.axes_connect if job.axes_connect != 0 else (1u << min(job.n_coords, AXES)) - 1
            memset(&dest, 0, sizeof(dest))
            dest.m_func = 1
            memcpy(&dest.m_calcE, m.motion.position, sizeof(P10DOUBLE))
            for k in range(AXES):
                if (moving >> k) & 1:
                    (<double *>&dest.m_calcE)[k] = hit.point[k]
            unbounded = manual_path_not_finite(m.motion.position, &dest, AXES, &f.params.motion[3]) if rc == CONNECT_FOUND else NULL
            if unbounded != NULL:
                err_path_not_finite(err, -1, 0, "ConnectCNCEx_Plane", unbounded)
                rc = CONNECT_BAD_ARGUMENT
        if rc != CONNECT_FOUND:
            core_keep_error(core, False, err)
            core_report_error(core, err)
            end_status = job.status_before
        elif not TC_ATOMIC_LOAD(&core.cancel):
            core_set_status(core, CNC_STATUS_CONNECT_MOVING)
            finish = machine_manual_move(core, m, &f, &dest, AXES, &f.params.motion[3])
            if finish == EV_DONE:
                pthread_mutex_lock(&core.lock)
                place_connect(&m.place, &m.program.prog, hit.part, hit.s)
                pthread_mutex_unlock(&core.lock)
                session_open(&m.session, core, RUN_FORWARD, True)
                if not session_add_code(&m.session, job.add_code, m.motion.position, CNC_STATUS_SENDING_CONNECT_M, False):
                    finish = EV_STOPPED         # stopped while they were sent: on the trajectory (-31)
                elif job.state_after == 2:
                    end_status = CNC_STATUS_OUT_OF_TRAJECTORY      # reported out of the trajectory
                elif _connect_continues(job.n_type) and not TC_ATOMIC_LOAD(&core.cancel):
                    core_set_status(core, CNC_STATUS_FORWARD)
                    finish = machine_program_run(core, m, &f, RUN_FORWARD, NULL)
    free(err)
    free(f.params)
    job_free(&job.head)
    if end_status != TC_KEEP:
        core_finish_to(core, end_status)
    else:
        core_finish(core, finish)
    return NULL


cdef int32_t core_connect(Core *core, uint32_t n_type, uint32_t n_coords, const double *coords,
                          const char *add_code, uint32_t axes_calc, uint32_t axes_connect,
                          int32_t state_after) noexcept nogil:
    """ConnectCNCEx_Plane: 40, 41, then -31 (or a forward run)."""
    cdef ConnectJob *job = <ConnectJob *>job_new(CMD_CONNECT)
    if job == NULL:
        err_out_of_memory(refusal(), -1, 0)
        return core_fail(core, refusal())
    job.n_type = n_type
    job.n_coords = n_coords
    if n_coords > 0:
        memcpy(job.coords, coords, n_coords * sizeof(double))
    job.axes_calc = axes_calc
    job.axes_connect = axes_connect
    job.state_after = state_after
    job.status_before = core_status(core)
    if add_code != NULL:
        job.add_code = tc_strdup(add_code)
    return core_start(core, &job.head, "ConnectCNCEx_Plane")
