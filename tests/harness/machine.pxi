# The offline machine without its threads: compile a program on one of this module's
# own cores and run the machine over it synchronously, the feeder, motion_step and
# the notifier's bookkeeping called in turn on one thread, one 100 us step at a
# time, every step recorded. The run is set up and kept as machine_program_run does
# (machine/machine.pyx _run_setup, _run_keep), with _pace's threads and sleeps
# replaced by this loop.

def compile_text(int core_idx, text, params=None, long long window=0, position=None):
    """Compiles `text` (str) on the module's core with GCODE_PARAMETERS `params`
    (bytes, else the core's), look-ahead `window`, from machine `position` (10
    floats, else where the machine stands). Returns None or (number, line, text)."""
    cdef bytes code = text.encode("latin-1")
    cdef bytes pb
    cdef double start[10]
    cdef CALLBACK_INFO info
    cdef int k
    if params is not None:
        pb = bytes(params)
        if len(pb) != sizeof(GCODE_PARAMETERS):
            raise ValueError("params: wrong size")
        if ToolChainCore_SetGCodeParameters(core_idx, <const GCODE_PARAMETERS *><const char *>pb) != 0:
            raise ValueError("params refused")
    if position is not None:
        for k in range(10):
            start[k] = position[k]
        if ToolChainCore_ResetCNC(core_idx, 0, 10, start) != 0:
            raise RuntimeError("ResetCNC refused")
    ToolChainCore_SetLookAhead(core_idx, <int32_t>window)
    if ToolChainCore_CompileFromMemory(core_idx, b"m.nc", code) != 0:
        raise RuntimeError("CompileFromMemory refused")
    while ToolChainCore_StatusCNC(core_idx) == CNC_STATUS_COMPILING:
        _time.sleep(0.001)
    if ToolChainCore_GetLastError(core_idx, &info) == 1:
        return (info.stringId, info.actLine, (<bytes>info.m_fullError).decode("latin-1"))
    return None


def set_machine_bits(int core_idx, unsigned int bits):
    """MACHINE_PARAMETERS.enhancedInterpolatorParameters of the module's core (the
    next compile plans with it, the machine runs that plan)."""
    cdef MACHINE_PARAMETERS m
    if ToolChainCore_GetMachineParameters(core_idx, &m) != 0:
        raise RuntimeError("GetMachineParameters refused")
    m.enhancedInterpolatorParameters = <int32_t>bits
    if ToolChainCore_SetMachineParameters(core_idx, &m) != 0:
        raise RuntimeError("SetMachineParameters refused")


def simulated_run_time(int core_idx):
    """StartCNCEx 10 (a simulation with calcTime) and GetGCodeRunTime of the main file."""
    if ToolChainCore_StartCNCEx(core_idx, RUN_SIMULATION, NULL) != 0:
        raise RuntimeError("StartCNCEx 10 refused")
    while ToolChainCore_StatusCNC(core_idx) == 10:
        _time.sleep(0.001)
    return ToolChainCore_GetGCodeRunTime(core_idx, 0)


def toolpath(int core_idx):
    """The program's TC_TOOLPATH_RECORDs (GetToolpath) as bytes."""
    cdef uint64_t total = 0
    cdef bytearray out
    if ToolChainCore_GetToolpath(core_idx, NULL, 0, 0, &total) != 0:
        raise RuntimeError("GetToolpath refused")
    out = bytearray(total * sizeof(TC_TOOLPATH_RECORD))
    if total and ToolChainCore_GetToolpath(core_idx, <TC_TOOLPATH_RECORD *><char *>out, total, 0, &total) != 0:
        raise RuntimeError("GetToolpath refused")
    return bytes(out)


def plan(int core_idx):
    """The compiled plan per part: (peak of its profile, v_exit, time), mm/s and s."""
    cdef Core *core = core_get(core_idx)
    cdef const Program *prog
    cdef size_t k
    if core.program == NULL or core.program.prog.plan == NULL:
        return []
    prog = &core.program.prog
    return [(planned_peak(prog, k), prog.plan[k].v_exit, prog.plan[k].time) for k in range(prog.n_parts)]


def part_plans(int core_idx):
    """The compiled PartPlan of every part as dicts (mm/s, mm/s^2, s)."""
    cdef Core *core = core_get(core_idx)
    cdef const Program *prog
    cdef size_t k
    if core.program == NULL or core.program.prog.plan == NULL:
        return []
    prog = &core.program.prog
    return [dict(prog.plan[k]) for k in range(prog.n_parts)]


def set_breakpoint(int core_idx, unsigned int line):
    ToolChainCore_SetBreakpoint(core_idx, line, 0)


def set_rel_feed(int core_idx, double rel_feed):
    """SetRelFeed: a run starts with this override (no ramp to it)."""
    ToolChainCore_SetRelFeed(core_idx, rel_feed)


def forget(int core_idx):
    """ResetCNC to the origin: the machine's place on the program is dropped (its start)."""
    cdef double origin[10]
    memset(origin, 0, sizeof(origin))
    ToolChainCore_ResetCNC(core_idx, 0, 10, origin)


def reset(int core_idx, position=None):
    """ResetCNC: the machine's place dropped (the next run starts at the program's
    start), the machine at `position` (10 floats), or where it stands (None)."""
    cdef double at[10]
    cdef int k
    if position is None:
        if ToolChainCore_ResetCNC(core_idx, 0, 0, NULL) != 0:
            raise RuntimeError("ResetCNC refused")
        return
    for k in range(10):
        at[k] = position[k]
    if ToolChainCore_ResetCNC(core_idx, 0, 10, at) != 0:
        raise RuntimeError("ResetCNC refused")


STATE_NAMES = {MS_RUNNING: "running", MS_WAIT_M: "wait_m", MS_DWELL: "dwell", MS_STARVED: "starved",
               MS_STOPPED: "stopped", MS_M0: "m0", MS_END: "end", MS_BUFFER_END: "buffer_end"}
FINISH = {EV_DONE: "done", EV_STOPPED: "stopped", EV_M0: "m0"}


def run(int core_idx, int regime, double stop_at=-1.0, overrides=(), double max_time=600.0,
        int feed_every=1):
    """One run of the machine (StartCNCEx `regime`) from where it stands, until it
    halts or `max_time` seconds of machine time. `stop_at`: StopCNCEx at that machine
    time; `overrides`: ((time, relFeed), ...) set at those times; `feed_every`: the
    feeder fills the ring only every that many steps (a feeder that lags).
    Returns dict(steps=[(t, part, d, v, ovr, x, y, z, state, cut+rapid length)] after
    every step, entries=[part of each entry begun], finish, stop_time, dt)."""
    cdef Core *core = core_get(core_idx)
    cdef Machine *m
    cdef Motion *mo
    cdef Feeder f
    cdef GCODE_PARAMETERS params
    cdef double start[10]
    cdef double dt = STEP_US * 1e-6
    cdef double t = 0.0, stop_time = -1.0
    cdef int events, k, n_steps = 0
    cdef int32_t finish
    cdef Entry *e
    cdef list steps = [], entries = []
    cdef list pending = sorted(overrides)
    cdef Job job
    cdef ErrorInfo refusal
    memset(&f, 0, sizeof(f))
    memset(&job, 0, sizeof(job))
    job.command = CMD_FORWARD
    pthread_mutex_lock(&core.lock)
    if core.program == NULL or not machine_prepare(core, &job, &refusal):
        pthread_mutex_unlock(&core.lock)
        raise RuntimeError("nothing compiled")
    session_forget_locked(core)         # as an activity begins: no M function waits
    m = <Machine *>core.offline
    params = core.params
    f.params = &params
    memcpy(start, m.motion.position, sizeof(start))
    pthread_mutex_unlock(&core.lock)
    mo = &m.motion
    f.core = core
    f.m = m
    _run_setup(core, m, &f, regime, start)
    mo.ovr_target = mo.ovr
    _feed(&f)
    while t < max_time:
        while pending and pending[0][0] <= t:
            mo.ovr_target = pending.pop(0)[1]
        if stop_at >= 0.0 and t >= stop_at and stop_time < 0.0:
            stop_time = t
            motion_stop(mo)
        if n_steps % feed_every == 0:
            _feed(&f)
        _take_answer(core, mo)
        events = motion_step(mo, dt)
        motion_locate(mo)               # the pacer does it once per tick; here after every step
        n_steps += 1
        t = n_steps * dt
        for k in range(mo.n_log):
            if mo.log_kind[k] == ME_ENTRY:
                entries.append(mo.log_part[k])
        _hand_over(m, True)
        _drain(&f)
        e = motion_entry(mo, 0) if mo.count > 0 else NULL
        steps.append((t, <long long>e.part if e != NULL else -1, mo.d, mo.v, mo.ovr,
                      mo.position[0], mo.position[1], mo.position[2], STATE_NAMES[mo.state],
                      mo.cut_len + mo.rapid_len))
        if events & ME_HALT or mo.state >= MS_STOPPED:
            break
    _drain(&f)
    finish = _finish_event(m, regime)
    pthread_mutex_lock(&core.lock)
    _run_keep(core, m, &f)
    pthread_mutex_unlock(&core.lock)
    return dict(steps=steps, entries=entries, finish=FINISH.get(finish, finish), stop_time=stop_time,
                dt=dt, state=STATE_NAMES[mo.state], run_time=mo.run_time)


def place(int core_idx):
    """Where the machine stands on its program: (part, distance along it, began,
    motion parts it remembers for backward, oldest first)."""
    cdef Core *core = core_get(core_idx)
    cdef Machine *m = <Machine *>core.offline
    cdef size_t k
    if m == NULL:
        return None
    return (m.place.part, m.place.s, m.place.began, [m.place.history[k] for k in range(m.place.n_history)])


def place_violations(int core_idx):
    """The invariants of the machine's place (machine.pxd Place) it breaks now: a list
    of texts, empty when it holds them all (lengths to 1e-9 mm)."""
    cdef Core *core = core_get(core_idx)
    cdef Machine *m = <Machine *>core.offline
    cdef const Place *p
    cdef const Program *prog
    cdef Segment seg
    cdef double length = 0.0
    cdef bint motion
    cdef size_t k
    cdef list bad = []
    if m == NULL or m.program == NULL:
        return bad
    p = &m.place
    prog = &m.program.prog
    if p.part > prog.n_parts:
        bad.append(f"part {p.part} > n_parts {prog.n_parts}")
        return bad
    motion = p.part < prog.n_parts and prog.parts[p.part].kind == PART_MOTION
    if p.part == prog.n_parts and (p.s != 0.0 or p.began):
        bad.append(f"after the last part with s {p.s}, began {p.began}")
    if motion:
        segment_of_placed_part(prog, p.part, &m.placement, &seg)
        length = seg.length
    if not (0.0 <= p.s <= length + 1e-9):
        bad.append(f"s {p.s} outside [0, {length}] of part {p.part}")
    if p.s > 0.0 and not (motion and p.began):
        bad.append(f"s {p.s} > 0 in part {p.part} (motion {motion}, began {p.began})")
    if p.current != (<int64_t>p.part if p.began and motion else PART_NONE):
        bad.append(f"current {p.current} in part {p.part} (motion {motion}, began {p.began})")
    if p.n_history > HISTORY_DEPTH:
        bad.append(f"{p.n_history} parts in the history")
    for k in range(p.n_history):
        if p.history[k] >= prog.n_parts or prog.parts[p.history[k]].kind != PART_MOTION:
            bad.append(f"history[{k}] = {p.history[k]} is no motion part")
        elif k > 0 and p.history[k] <= p.history[k - 1]:
            bad.append(f"history[{k}] = {p.history[k]} after {p.history[k - 1]}")
        elif p.history[k] >= p.part:
            bad.append(f"history[{k}] = {p.history[k]} not before part {p.part}")
    return bad


def destroy_all():
    """DestroyCNC on the module's cores: their finished compile workers are joined (a
    host ends so; ThreadSanitizer reports a thread nobody joined)."""
    cdef uint32_t k
    for k in range(TOOL_CHAIN_MAX_CORES):
        ToolChainCore_DestroyCNC(k)
