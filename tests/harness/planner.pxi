# The planner: compile G-code and plan it with any window and settings, the plan per
# part; the ramps' closed forms; a part's segment geometry.

cdef CompileInput *_input_for(bytes src, params, int32_t *cancel) except NULL:
    """A CompileInput (calloc; the caller frees it) for the text `src` with
    GCODE_PARAMETERS `params` (bytes, else the defaults)."""
    cdef CompileInput *inp
    cdef bytes pb
    if params is not None and len(bytes(params)) != sizeof(GCODE_PARAMETERS):
        raise ValueError("params: wrong size")
    inp = <CompileInput *>calloc(1, sizeof(CompileInput))
    if inp == NULL:
        raise MemoryError()
    if params is None:
        default_gcode_parameters(&inp.params)
    else:
        pb = bytes(params)
        memcpy(&inp.params, <const char *>pb, sizeof(GCODE_PARAMETERS))
    inp.text = src
    inp.length = len(src)
    inp.file_idx = 0
    inp.prefix_idx = -1
    inp.postfix_idx = -1
    inp.plc = TGM_Data
    inp.cancel = cancel
    return inp


cdef double planned_peak(const Program *prog, size_t k) noexcept nogil:
    """The highest speed of part k's planned profile: the profile the machine runs
    (profile.pyx profile_plan) from its entry speed to its exit under the limits the
    plan holds, over its length; the speed through for a part without motion."""
    cdef const PartPlan *pp = &prog.plan[k]
    cdef double v_in = prog.plan[k - 1].v_exit if k > 0 else 0.0
    cdef Segment g
    cdef PlanNode nd, exit
    cdef Profile pr
    cdef Reciprocals rc
    if prog.parts[k].kind != PART_MOTION or not (pp.acc > 0.0):
        return v_in
    exit.jin = pp.v_exit
    exit.jin2 = exit.entry2 = exit.jin * exit.jin
    segment_of_part(prog, k, &g)
    nd.length = g.length
    nd.vmax = pp.v_cap
    nd.acc = pp.acc
    nd.dec = pp.dec
    nd.ramp = pp.ramp
    nd.brake2 = 2.0 * nd.dec * nd.length
    rc.acc = rc.dec = rc.vmax = 0.0
    profile_plan(&pr, &nd, v_in, &exit, &rc)
    return pr.v_peak


def plan_text(text, params=None, long long window=0, unsigned int enhanced=0, bint detail=True,
              long long split_near=-1):
    """Compiles `text` (str) with GCODE_PARAMETERS `params` (bytes, else the defaults),
    inserts the G167 arcs, plans. Returns (parts, error, timing): parts: dicts kind,
    func, line, length, v_in, v_peak, v_out, time, calc_feed, end (compensated x y z),
    programmed_end, flags, gcode_index (detail), else one dict n_parts,
    run_time, plan_bytes, regions (planning regions); timing: CPU seconds of the compile (with the arcs) and of the planning.
    split_near >= 0: planned in two threads as the library does beside the extent
    (pipeline.pyx plan_in_two), split at plan_split_at(split_near); timing["split"], and
    wall seconds of the extent alone ("extent") and of the extent with the plan beside
    it ("beside"); split_near < -1: the same wall times with the plan in one piece
    before the extent, in this thread (as the library plans small programs)."""
    cdef int32_t cancel = 0
    cdef bytes src = text.encode("latin-1")
    cdef CompileInput *inp = _input_for(src, params, &cancel)
    cdef ProgramBuilder build
    cdef Program *prog = &build.prog
    cdef ErrorInfo err
    cdef int rc
    cdef size_t k
    cdef timespec t0, t1, t2
    cdef GCODE_INFO extent
    cdef bint kept              # (no extent measured before the joins)
    cdef size_t split = 0
    cdef double run_time = 0.0
    program_builder_init(&build)
    memset(&err, 0, sizeof(err))
    inp.plan_window = window
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t0)
    rc = compile_program(inp, &build, &err)
    if rc == COMPILE_OK:
        rc = insert_arcs(&build, &inp.params, &err)
    if rc == COMPILE_OK:
        rc = join_lines(&build, &inp.params, False, NULL, NULL, NULL, &kept)
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t1)
    timing = dict(compile=(t1.tv_sec - t0.tv_sec) + 1e-9 * (t1.tv_nsec - t0.tv_nsec), plan=0.0)
    if rc == COMPILE_OK:
        if split_near == -1:
            rc = plan_program(&build, &inp.params, enhanced, window)
        elif split_near < -1:                # one piece, then the extent, wall times as below
            clock_gettime(CLOCK_MONOTONIC, &t1)
            program_extent(prog, &extent)
            clock_gettime(CLOCK_MONOTONIC, &t2)
            timing["extent"] = (t2.tv_sec - t1.tv_sec) + 1e-9 * (t2.tv_nsec - t1.tv_nsec)
            rc = plan_program(&build, &inp.params, enhanced, window)
            program_extent(prog, &extent)
            clock_gettime(CLOCK_MONOTONIC, &t1)
            timing["beside"] = (t1.tv_sec - t2.tv_sec) + 1e-9 * (t1.tv_nsec - t2.tv_nsec)
        else:                           # wall times: the extent alone, then with the plan beside it
            clock_gettime(CLOCK_MONOTONIC, &t1)
            program_extent(prog, &extent)
            clock_gettime(CLOCK_MONOTONIC, &t2)
            timing["extent"] = (t2.tv_sec - t1.tv_sec) + 1e-9 * (t2.tv_nsec - t1.tv_nsec)
            split = plan_split_at(prog, <size_t>split_near)
            rc = plan_in_two(prog, &inp.params, enhanced, window, split, &extent)
            clock_gettime(CLOCK_MONOTONIC, &t1)
            timing["beside"] = (t1.tv_sec - t2.tv_sec) + 1e-9 * (t1.tv_nsec - t2.tv_nsec)
            timing["split"] = split
        clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t2)
        timing["plan"] = (t2.tv_sec - t1.tv_sec) + 1e-9 * (t2.tv_nsec - t1.tv_nsec)
    out = []
    if rc == COMPILE_OK and not detail:
        for k in range(prog.n_parts):
            run_time += prog.plan[k].time
        out = dict(n_parts=prog.n_parts, run_time=run_time, plan_bytes=prog.n_parts * sizeof(PartPlan),
                   regions=prog.n_plan_regions)
    elif rc == COMPILE_OK:
        for k in range(prog.n_parts):
            out.append(dict(kind=prog.parts[k].kind, func=prog.parts[k].func, line=prog.parts[k].line,
                            length=part_length(prog, k), v_in=prog.plan[k - 1].v_exit if k > 0 else 0.0,
                            v_peak=planned_peak(prog, k), v_out=prog.plan[k].v_exit,
                            time=prog.plan[k].time, calc_feed=plan_calc_feed(prog, k),
                            end=tuple(prog.parts[k].ce), programmed_end=tuple(prog.parts[k].e),
                            flags=prog.parts[k].flags, gcode_index=prog.parts[k].gcode_index))
    error = None if rc == COMPILE_OK else (err.number, err.line, err.text.decode("latin-1"))
    program_builder_free(&build)
    free(inp)
    return out, error, timing


def ramp(double v0, double v1, double acc, int ramp_type, double t=-1.0):
    """(time, distance) of a ramp with peak acceleration acc (planner.pxd: its time
    with the equivalent acceleration), or (speed, distance) t seconds into it."""
    cdef double T = fabs(v1 - v0) / ramp_equivalent_acc(acc, ramp_type)
    if t < 0.0:
        return T, ramp_distance_in(v0, v1, T, ramp_type, T)
    return ramp_speed_in(v0, v1, T, ramp_type, t), ramp_distance_in(v0, v1, T, ramp_type, t)


def profile(double length, double v_in, double cap, double v_out, double acc, double dec, int ramp, times):
    """(duration, peak, speeds at `times`) of planner/profile.pyx's profile over a part
    of `length` entered at v_in, under `cap`, ending at most at v_out (or as low as
    braking all the way allows), peak accelerations acc / dec of ramp type `ramp`:
    profile_plan, sampled with profile_at."""
    cdef Profile pr
    cdef PlanNode nd, exit
    cdef Reciprocals rc
    cdef double d, v
    rc.acc = rc.dec = rc.vmax = 0.0
    exit.jin = v_out
    exit.jin2 = exit.entry2 = v_out * v_out
    nd.length = length
    nd.vmax = cap
    nd.acc = ramp_equivalent_acc(acc, ramp)
    nd.dec = ramp_equivalent_acc(dec, ramp)
    nd.ramp = ramp
    nd.brake2 = 2.0 * nd.dec * length
    speeds = []
    profile_plan(&pr, &nd, v_in, &exit, &rc)
    for t in times:
        profile_at(&pr, t, &d, &v)
        speeds.append(v)
    return profile_time(&pr), pr.v_peak, speeds


def arc_factor(table, double radius, int state=-1):
    """arc_feed_factor with arcFeedTable = [(r, relFeed), ...]."""
    cdef GCODE_PARAMETERS p
    memset(&p, 0, sizeof(p))
    for i, (r, f) in enumerate(table):
        p.arcFeedTable[i].m_r = r
        p.arcFeedTable[i].m_relFeed = f
    return arc_feed_factor(&p, state, radius)


def segment_points(text, size_t part, distances, params=None):
    """Compiles `text` (absolute coordinates unless params say otherwise) and returns
    (length, [point (10 axes) at each path length of `distances`]) of motion part
    `part` (geometry.pyx segment_of_part, segment_point_at)."""
    cdef int32_t cancel = 0
    cdef bytes src = text.encode("latin-1")
    cdef CompileInput *inp = _input_for(src, params, &cancel)
    cdef ProgramBuilder build
    cdef ErrorInfo err
    cdef Segment g
    cdef double out[10]
    program_builder_init(&build)
    memset(&err, 0, sizeof(err))
    rc = compile_program(inp, &build, &err)
    free(inp)
    if rc != COMPILE_OK or part >= build.prog.n_parts:
        program_builder_free(&build)
        raise ValueError(err.text.decode("latin-1") or "no such part")
    segment_of_part(&build.prog, part, &g)
    points = []
    for s in distances:
        for k in range(10):
            out[k] = 0.0
        segment_point_at(&g, s, out)
        points.append([out[k] for k in range(g.n_axes)])
    length = g.length
    program_builder_free(&build)
    return length, points
