# The offline machine of one core (Local_Core_Mode 2): StartCNCEx 30-33, StopCNCEx,
# the M-function handshake, the override, breakpoints, manual moves, live GetPos.
#
# A run is one activity of the core (core.pyx) with two threads:
#   - the activity's worker is the machine's *feeder and notifier*: it turns parts
#     into look-ahead entries (placed geometry, limits, the plan's speeds, the
#     breakpoint question), and it makes every driver callback (DriverInitialize,
#     DriverGFunc as a part begins, DriverMFunc, PRINT, DriverEnd);
#   - the *pacer* wakes every millisecond on the monotonic clock, runs the 100 us steps
#     of motion.pyx that the elapsed time (times the core's time scale) calls for,
#     hands what happened to the notifier and publishes GetPos once.
# Neither waits for the other: the ring of entries and the event queue are the only
# things they share. The machine's place on the path (part, distance, the parts it
# ran, for backward) outlives the run, so the next StartCNCEx continues there.
from libc.stdlib cimport free
from libc.string cimport memset, memcpy, memmove
from libc.math cimport fabs, isfinite


cdef Machine *machine_of(Core *core) noexcept nogil:
    """The core's machine, made on first use (with core.lock held)."""
    cdef Machine *m = core.offline
    if m == NULL:
        m = <Machine *>tc_calloc(1, sizeof(Machine))
        if m == NULL:
            return NULL
        pthread_mutex_init(&m.lock, NULL)
        pthread_cond_init(&m.wake, NULL)
        place_forget(&m.place)
        core.offline = m
    return m


cdef void machine_forget(Core *core) noexcept nogil:
    """With core.lock held and no activity: the machine's place is dropped (ResetCNC,
    a new program, DestroyCNC); the next forward run starts at the program's start."""
    cdef Machine *m = core.offline
    if m == NULL:
        return
    loaded_program_release(m.program)
    placed_plan_free(&m.plan)
    m.plan_made = False
    output_forget(&m.output)            # output stage: no filter state, no tables
    m.program = NULL
    place_forget(&m.place)


# ------------------------------------------------------------------ entries


cdef bint _is_breakpoint(Feeder *f, const Entry *e) noexcept nogil:
    """The run stops before the first part of a line the host marked (SetBreakpoint,
    the IsBreakpoint callback) -- never before the part it starts at."""
    cdef Callback cb
    cdef bint hit
    if f.first or (e.line == f.last_line and e.file_idx == f.last_file):
        return False
    f.last_line = e.line
    f.last_file = e.file_idx
    pthread_mutex_lock(&f.core.lock)
    hit = f.core.breakpoint_line != 0 and e.line == f.core.breakpoint_line and e.file_idx == f.core.breakpoint_file
    pthread_mutex_unlock(&f.core.lock)
    if not hit and callback_enter(f.core, SLOT_IS_BREAKPOINT, &cb):
        hit = (<TC_IsBreakpoint>cb.fn)(cb.user, e.line, e.file_idx) == 1
        callback_leave(f.core, SLOT_IS_BREAKPOINT)
    return hit


cdef void _entry_identity(Feeder *f, Entry *e, const Program *prog, const Part *p, size_t part) noexcept nogil:
    """An entry's identity for part `part` (its kind, function, line, file, G-code index, feed,
    the motion's sequence number) and zeroed motion fields (no speed, no limit, a trapezoid
    ramp) for the feeder to fill."""
    cdef const PartSettings *s = part_settings(prog, p)
    e.part = part
    e.motion_seq = f.motions
    if p.kind == PART_MOTION:
        f.motions += 1
    e.kind = p.kind
    e.func = p.func
    e.line = p.line
    e.file_idx = s.file_idx
    e.gcode_index = p.gcode_index
    e.feed = s.feed
    e.rapid = p.kind == PART_MOTION and p.func == 0
    e.waits = False
    e.m0 = False
    e.break_before = False
    e.dwell = 0.0
    e.s_from = e.s_to = 0.0
    e.node.vmax = e.node.ceiling = e.v_junction = 0.0
    e.node.acc = e.node.dec = NO_LIMIT
    e.node.ramp = RAMP_TRAPEZOID
    e.dyn_extra = 0.0


cdef void _dynamic_correction(Entry *e, const Program *prog, const Part *p, const GCODE_PARAMETERS *params) noexcept nogil:
    """dynamicG41/G42Correction_mm and _percent (of the tool radius in use) of a
    compensated motion part: how far the machine moves the tool further out at rest
    (motion.pyx entry_point; none at the part's full speed)."""
    cdef double mm, percent, radius
    cdef int normal
    if p.comp != 41 and p.comp != 42:
        return
    mm = params.dynamicG41Correction_mm if p.comp == 41 else params.dynamicG42Correction_mm
    percent = params.dynamicG41Correction_percent if p.comp == 41 else params.dynamicG42Correction_percent
    radius = fabs(part_tool_radius(prog, params, p))
    e.dyn_extra = mm + percent * 0.01 * radius
    if not plane_axes(p.plane, &e.dyn_first, &e.dyn_second, &normal) or not (e.dyn_extra == e.dyn_extra):
        e.dyn_extra = 0.0
    e.dyn_side = 1 if p.comp == 41 else -1


cdef void _entry_limits(Entry *e, const PartPlan *pp) noexcept nogil:
    """A motion entry's limits as the plan holds them (the profile is made from them).
    A part the plan passed through without length has none: only a placed plan that
    could not be made (out of memory) leaves one with length, which then creeps."""
    e.node.vmax = pp.v_cap if pp.v_cap > 0.0 else 1.0 / 60.0
    e.node.ceiling = max(<double>pp.v_ceiling, e.node.vmax)
    e.v_junction = pp.v_junction
    e.node.acc = pp.acc if pp.acc > 0.0 else NO_LIMIT
    e.node.dec = pp.dec if pp.dec > 0.0 else NO_LIMIT
    e.node.ramp = pp.ramp


cdef void _class_limits(Entry *e, const GCODE_FEED *cls) noexcept nogil:
    """A motion class's feed (when set) caps the entry, its ramps replace the plan's
    (motion[2] backward, motion[4] regime 31)."""
    if cls.feed > 0.0:
        e.node.vmax = min(e.node.vmax, cls.feed / 60.0)
        e.node.ceiling = min(e.node.ceiling, e.node.vmax)
        e.v_junction = min(e.v_junction, e.node.vmax)
    _class_ramps(e, cls)


cdef void _class_ramps(Entry *e, const GCODE_FEED *cls) noexcept nogil:
    """A motion class's ramps (an acceleration of 0: the entry's own)."""
    e.node.ramp = RAMP_SINE if cls.rampType == RAMP_SINE else RAMP_TRAPEZOID
    if 0.0 < cls.acc < NO_LIMIT:
        e.node.acc = ramp_equivalent_acc(cls.acc, e.node.ramp)
    if 0.0 < cls.dec < NO_LIMIT:
        e.node.dec = ramp_equivalent_acc(cls.dec, e.node.ramp)


cdef bint _forward_entry(Feeder *f, Entry *e) noexcept nogil:
    """The next part as a forward entry; False when the program ends. Parts the
    regime leaves out are skipped."""
    cdef const Program *prog = f.prog
    cdef const Part *p
    cdef size_t k
    while f.next < prog.n_parts:
        k = f.next
        f.next += 1
        p = &prog.parts[k]
        if p.kind == PART_MFUNC and (f.regime == RUN_FORWARD_NO_M
                                     or (f.regime == RUN_FORWARD_SKIP_FIRST_M and not f.any_motion)):
            continue
        _entry_identity(f, e, prog, p, k)
        e.break_before = _is_breakpoint(f, e)
        f.first = False
        if p.kind == PART_MFUNC:
            e.m0 = p.func == 0
            e.waits = not (p.flags & FLAG_CONTINUOUS_M) and p.func != 0
        elif p.kind == PART_DWELL:
            e.dwell = part_extra(prog, p).value
            e.waits = True
        elif p.kind == PART_MOTION:
            f.any_motion = True
            segment_of_placed_part(prog, k, &f.m.placement, &e.seg)
            e.s_from = 0.0
            e.s_to = e.seg.length
            _entry_limits(e, placed_plan_part(&f.m.plan, k))
            if f.regime == RUN_FORWARD_NO_M:
                _class_limits(e, &f.params.motion[4])
            _dynamic_correction(e, prog, p, f.params)
        return True
    return False


cdef bint _backward_entry(Feeder *f, Entry *e) noexcept nogil:
    """The next part back along the executed path; False when what the machine
    remembers ends. With `back_current`, entry 0 is the rest of the part it stands in.
    Its junction limit is the one where it meets the part retraced before it (that
    part's start)."""
    cdef Machine *m = f.m
    cdef const Place *at = &m.place
    cdef const Program *prog = f.prog
    cdef size_t k, back
    cdef double from_s = -1.0
    if f.back_current and f.next == 0:
        k = at.part
        from_s = at.s
    else:
        back = f.next - (1 if f.back_current else 0)
        if back >= at.n_history:
            return False
        k = at.history[at.n_history - 1 - back]
    _entry_identity(f, e, prog, &prog.parts[k], k)
    segment_of_placed_part(prog, k, &m.placement, &e.seg)
    e.s_from = from_s if from_s >= 0.0 else e.seg.length
    e.s_to = 0.0
    _entry_limits(e, placed_plan_part(&m.plan, k))
    e.v_junction = placed_plan_part(&m.plan, f.back_last).v_junction if f.next > 0 else 0.0
    _class_limits(e, &f.params.motion[2])
    _dynamic_correction(e, prog, &prog.parts[k], f.params)
    f.back_last = k
    f.next += 1
    return True


cdef void _feed(Feeder *f) noexcept nogil:
    """Writes entries while the ring has room."""
    cdef Motion *mo = &f.m.motion
    cdef uint64_t produced = mo.produced
    cdef bint more = True
    if TC_ATOMIC_LOAD(&mo.fed_all):
        return
    while produced - TC_LOAD_U64(&mo.consumed) < LOOK_RING:
        if f.regime == RUN_BACKWARD:
            more = _backward_entry(f, &mo.ring[produced % LOOK_RING])
        else:
            more = _forward_entry(f, &mo.ring[produced % LOOK_RING])
        if not more:
            TC_ATOMIC_STORE(&mo.fed_all, 1)
            return
        produced += 1
        TC_STORE_U64(&mo.produced, produced)


# ------------------------------------------------------------------ the pacer

cdef void _publish(Core *core, Machine *m) noexcept nogil:
    """GetPos from the machine's state (the pacer's thread; the worker's before and
    after the pacer runs): where it stands, the entry it is in, as the run's session
    counts them."""
    cdef Motion *mo = &m.motion
    cdef Standing s
    cdef Entry *e = motion_entry(mo, 0) if mo.count > 0 else NULL
    standing_clear(&s)
    output_view(&m.output, mo, &s)      # output stage: commanded, smoothed, corrected
    standing_part(&s, e.kind if e != NULL else -1, e.func if e != NULL else 0,
                  e != NULL and mo.state == MS_WAIT_M,
                  part_shift(&m.program.prog, &m.program.prog.parts[e.part])
                  if e != NULL and m.program != NULL and e.part < m.program.prog.n_parts else NULL)
    if e != NULL:
        s.part.m_editorLine = e.line
        s.part.m_fileIdx = e.file_idx
        s.part.m_gCodeIndex = e.gcode_index
        if e.kind == PART_MOTION:
            s.part_len = entry_length(e)
            s.part_remain = entry_length(e) - mo.d
            s.set_feed = e.feed
            s.calc_feed = e.node.vmax * 60.0
        if m.program != NULL and e.file_idx == m.program.prog.main_file_idx:
            s.master_line = e.line
    s.counts = m.place.counts
    s.cut_len = mo.cut_len
    s.rapid_len = mo.rapid_len
    s.fill = 100.0 * min(mo.count, mo.window) / mo.window if mo.window > 0 else 0.0
    s.act_feed = mo.v * 60.0 * (mo.ovr if mo.ovr_timing else 1.0)
    s.rel_feed = mo.ovr
    s.master_file = <uint32_t>(m.program.prog.main_file_idx if m.program != NULL else -1)
    s.status = core_status(core)
    s.run_time = mo.run_time
    getpos_publish(&core.snap, &s)


cdef void *_pacer_body(void *arg) noexcept nogil:
    """The pacer: each tick (a millisecond of wall time, or a grant of the stepped
    clock) runs the steps its time calls for, hands what happened to the notifier
    and publishes GetPos. A tick's work ends after a millisecond of wall time, so at
    any time scale GetPos moves, and a stop or an end is seen, every millisecond."""
    cdef Core *core = <Core *>arg
    cdef Machine *m = core.offline
    cdef Motion *mo = &m.motion
    cdef double last = clock_now(), budget = 0.0, scale, tick_end
    cdef double dt = STEP_US * SECONDS_PER_US
    cdef uint32_t n_steps = 0
    cdef bint halted = False, cut
    cdef uint64_t told = mo.consumed     # entries done when the notifier was last woken
    tc_set_stage("the offline machine")
    while not halted and not TC_ATOMIC_LOAD(&core.cancel):
        budget += clock_take(core, m, &last)
        tick_end = last + TICK_S
        scale = TC_ATOMIC_LOAD_D(&core.time_scale)
        if budget > 1.0 * scale and not clock_stepped(core):
            budget = 1.0 * scale            # the thread was held up: the machine does not jump
        mo.ovr_target = TC_ATOMIC_LOAD_D(&core.rel_feed)
        if TC_ATOMIC_LOAD(&core.stop) and mo.state < MS_STOPPED:
            motion_stop(mo)
        _take_answer(core, mo)
        cut = False
        # output stage: the steps go on after the interpolator halted until the output settled
        while budget >= dt and not output_halted(&m.output, mo):
            if mo.state == MS_WAIT_M and not TC_ATOMIC_LOAD(&mo.confirmed) and output_settled(&m.output):
                budget = 0.0                # settled at an unconfirmed M: it stands, no steps
                break
            motion_sync(mo)
            if mo.consumed - told >= LOOK_RING // 4:
                _hand_over(m, True)         # room in the ring: the feeder refills it
                told = mo.consumed
            if not motion_window_full(mo) and mo.state != MS_WAIT_M and mo.state < MS_STOPPED:
                break                       # time waits for the feeder (the plan needs its window)
            if mo.n_log > LOG_SIZE - 8:
                _hand_over(m, True)
                if mo.n_log > LOG_SIZE - 8:
                    break                   # the notifier is behind: the step waits for it
            output_step(&m.output, mo, dt)      # output stage: the interpolator's step and its output
            budget -= dt
            if output_halted(&m.output, mo):
                halted = True
                break
            if mo.state == MS_WAIT_M and output_settled(&m.output):
                _hand_over(m, True)         # it stands until the host confirms: no steps to run
                budget = 0.0
                break
            if TC_ATOMIC_LOAD(&core.stop) and mo.state < MS_STOPPED:
                motion_stop(mo)
            n_steps += 1
            if n_steps % 256 == 0 and clock_now() > tick_end:
                cut = True                  # the rest in the next tick, after GetPos
                break
        halted = halted or output_halted(&m.output, mo)
        motion_locate(mo)
        _hand_over(m, mo.consumed != told or halted)
        told = mo.consumed
        _publish(core, m)
        if not halted and not cut:
            clock_pause(core, m, &budget, mo.n_log == 0)
    motion_locate(mo)
    TC_ATOMIC_STORE(&m.pacer_done, 1)
    _hand_over(m, True)
    clock_pacer_ends(m)
    return NULL


cdef inline void _take_answer(Core *core, Motion *mo) noexcept nogil:
    """The step stands at a waiting M function the session got an answer for
    (DriverMFunc's 0, ConfirmMFunc): it goes on."""
    if mo.state == MS_WAIT_M and session_take_answer(core):
        TC_ATOMIC_STORE(&mo.confirmed, 1)


cdef void _hand_over(Machine *m, bint wake) noexcept nogil:
    """The step's log into the notifier's queue (as much as fits), each part that
    began counted for GetPos; wakes the notifier when there is news for it (events,
    or room in the ring: `wake`)."""
    cdef Motion *mo = &m.motion
    cdef int32_t k = 0, n = mo.n_log
    cdef size_t part
    if n == 0 and not wake:
        return
    pthread_mutex_lock(&m.lock)
    while k < n and m.ev_n < EVENT_QUEUE:
        part = mo.log_part[k]
        m.events[(m.ev_first + m.ev_n) % EVENT_QUEUE].kind = mo.log_kind[k]
        m.events[(m.ev_first + m.ev_n) % EVENT_QUEUE].part = part
        m.ev_n += 1
        if mo.log_kind[k] == ME_ENTRY and m.program != NULL and part < m.program.prog.n_parts:
            session_count(&m.place.counts, &m.program.prog.parts[part])
        k += 1
    m.news = True
    pthread_cond_broadcast(&m.wake)
    pthread_mutex_unlock(&m.lock)
    if k > 0:
        memmove(mo.log_kind, mo.log_kind + k, (n - k) * sizeof(int32_t))
        memmove(mo.log_part, mo.log_part + k, (n - k) * sizeof(size_t))
        mo.n_log = n - k


# ------------------------------------------------------------------ the notifier

cdef void _notify(Feeder *f, const MachineEvent *ev) noexcept nogil:
    """One event to the run's session: a move or a dwell as it begins, an M function
    or a PRINT as the machine reaches it (an M part's own ME_ENTRY says nothing)."""
    cdef Machine *m = f.m
    cdef const Part *p
    cdef SIMPLE_GM_PARAMS gm
    if f.prog == NULL or ev.part >= f.prog.n_parts:
        return
    p = &f.prog.parts[ev.part]
    if ev.kind == ME_ENTRY and p.kind != PART_MOTION and p.kind != PART_DWELL:
        return
    placed_part_to_gm(f.prog, ev.part, &m.placement, &gm)
    session_part(&m.session, f.prog, ev.part, &gm)


cdef bint _next_event(Machine *m, MachineEvent *ev) noexcept nogil:
    """The next queued event (False: none); the notifier is then inside it until
    _notified (the stepped clock waits for that)."""
    cdef bint got = False
    pthread_mutex_lock(&m.lock)
    if m.ev_n > 0:
        ev[0] = m.events[m.ev_first]
        m.ev_first = (m.ev_first + 1) % EVENT_QUEUE
        m.ev_n -= 1
        m.notifying = True
        got = True
    pthread_mutex_unlock(&m.lock)
    return got


cdef void _notified(Machine *m) noexcept nogil:
    """The notifier is done with its event; the stepped clock, waiting for an empty queue, is
    woken when none is left."""
    pthread_mutex_lock(&m.lock)
    m.notifying = False
    if m.ev_n == 0:
        pthread_cond_broadcast(&m.wake)
    pthread_mutex_unlock(&m.lock)


cdef int32_t _finish_event(Machine *m, int32_t regime) noexcept nogil:
    """The transition-table event the halted motion ends the run with."""
    cdef int32_t state = m.motion.state
    if state == MS_M0:
        return EV_M0
    if state == MS_END:
        if regime == RUN_BACKWARD and m.place.history_lost:
            return EV_STOPPED       # the remembered path ended before the program's start
        return EV_DONE
    return EV_STOPPED


cdef void _drain(Feeder *f) noexcept nogil:
    """Delivers every queued event; a motion part that begins pushes the one before
    it into the history."""
    cdef MachineEvent ev
    cdef Machine *m = f.m
    while _next_event(m, &ev):
        if (ev.kind == ME_ENTRY and f.regime != RUN_BACKWARD and f.prog != NULL and ev.part < f.prog.n_parts
                and f.prog.parts[ev.part].kind == PART_MOTION):
            place_motion_begins(&m.place, ev.part)
        _notify(f, &ev)
        _notified(m)


cdef void _motion_setup(Core *core, Motion *mo, const Feeder *f, const double *start) noexcept nogil:
    """An empty motion at `start` with the run's settings (override, stop), its
    look-ahead one entry (a run sets the plan's window)."""
    cdef const GCODE_PARAMETERS *params = f.params
    motion_reset(mo, start)
    output_start(&f.m.output, core, start)      # output stage: the filters stand at the start
    mo.window = 1
    mo.ovr = TC_ATOMIC_LOAD_D(&core.rel_feed) if TC_ATOMIC_LOAD_D(&core.rel_feed) > 0 else 1.0
    mo.ovr_inc = params.overrideInc if 0.0 < params.overrideInc <= 0.1 else 0.001
    mo.ovr_timing = (params.interpolatorConfig0 & 1) != 0
    mo.ovr_off_in_rapids = params.disableG0FeedOverride == 1
    mo.stop_dec = limit_or_none(params.motion[6].dec)
    mo.stop_ramp = RAMP_SINE if params.motion[6].rampType == RAMP_SINE else RAMP_TRAPEZOID


cdef size_t _window(int64_t planned) noexcept nogil:
    """The motion parts the machine's look-ahead sees: the window the program was
    planned with, as far as the ring holds it and the feeder's slack."""
    cdef size_t w = <size_t>planned if planned > 0 else (LOOK_RING if planned < 0 else VENDOR_WINDOW)
    return min(w, <size_t>(LOOK_RING - LOOK_RING // 4 - 1))


cdef int32_t machine_manual_move(Core *core, Machine *m, Feeder *f, const SIMPLE_GM_PARAMS *dest,
                          uint32_t n_dest, const GCODE_FEED *cls) noexcept nogil:
    """A move off the program at the motion class cls (GoToPosition: motion[5]; the
    way to a connection point: motion[3]), without override; the machine position
    follows it."""
    cdef Motion *mo = &m.motion
    cdef int32_t finish
    cdef double start[AXES]
    memcpy(start, mo.position, sizeof(start))
    _motion_setup(core, mo, f, start)
    mo.window = 1
    mo.ovr = 1.0
    _manual_entry(mo, dest, n_dest, cls)
    f.regime = RUN_MANUAL
    finish = _pace(core, m, f)
    pthread_mutex_lock(&core.lock)
    memcpy(core.position, mo.position, sizeof(core.position))
    pthread_mutex_unlock(&core.lock)
    return finish


cdef void _run_setup(Core *core, Machine *m, Feeder *f, int32_t regime, const double *start) noexcept nogil:
    """The feeder and the motion of a run along the program (regimes 30-33) from the
    machine's place, the machine at `start`."""
    cdef Motion *mo = &m.motion
    cdef const Program *prog = &m.program.prog
    f.prog = prog
    f.regime = regime
    f.first = True
    f.any_motion = False
    f.motions = 0
    f.next = m.place.part if regime != RUN_BACKWARD else 0
    f.back_current = place_inside_motion(&m.place, prog)
    if not m.plan_made:                 # the first run where the placement holds: its plan
        placed_plan_make(&m.plan, prog, &m.placement)
        m.plan_made = True
    session_open(&m.session, core, regime, True)
    _motion_setup(core, mo, f, start)
    mo.window = _window(prog.planned_with.window)
    place_resume(&m.place, mo, regime == RUN_BACKWARD)


cdef void _run_keep(Core *core, Machine *m, const Feeder *f) noexcept nogil:
    """With core.lock held, after a run along the program: the machine's place and
    the core's position follow the run."""
    place_after_run(&m.place, &m.motion, f.prog, f.regime == RUN_BACKWARD, f.next, m.session.signalled_m)
    memcpy(core.position, m.motion.position, sizeof(core.position))


cdef int32_t machine_program_run(Core *core, Machine *m, Feeder *f, int32_t regime, const char *add_code) noexcept nogil:
    """A run along the program (regimes 30-33) from the machine's place; the place
    and the machine position follow it. Its session: DriverInitialize; the start's
    M functions (status 70 while they are sent: one answered TC_MFUNC_LATER holds the
    start until it is confirmed); the parts; after a stop StopCNCEx's M functions
    (status 80, held the same way); DriverEnd. 31 and 32 send no M functions."""
    cdef Motion *mo = &m.motion
    cdef int32_t finish = EV_STOPPED
    cdef char *stop_code
    cdef bint sends_m = regime != RUN_FORWARD_NO_M and regime != RUN_BACKWARD
    cdef double start[AXES]
    memcpy(start, mo.position, sizeof(start))
    _run_setup(core, m, f, regime, start)
    _feed(f)
    motion_sync(mo)
    _publish(core, m)                   # GetPos shows this run from its start, not the last activity's
    session_begin(&m.session, start)
    if not sends_m or session_add_code(&m.session, add_code, start, CNC_STATUS_SENDING_START_M, False):
        if core_status(core) == CNC_STATUS_SENDING_START_M:
            core_set_status(core, regime)           # the start's M functions are done: it moves
        finish = _pace(core, m, f)
    pthread_mutex_lock(&core.lock)
    _run_keep(core, m, f)
    pthread_mutex_unlock(&core.lock)
    stop_code = session_take_stop_code(core)
    if finish == EV_STOPPED and sends_m and not TC_ATOMIC_LOAD(&core.cancel):
        session_add_code(&m.session, stop_code, mo.position, CNC_STATUS_SENDING_STOP_M, True)
    free(stop_code)
    session_end(&m.session)
    return finish


cdef Machine *machine_worker_begin(Job *job, Feeder *f) noexcept nogil:
    """The start of a run's worker: the feeder with a copy of the core's settings;
    NULL (the run's error set) when out of memory."""
    cdef Core *core = job.core
    cdef Machine *m
    worker_thread_mark(core)
    memset(f, 0, sizeof(Feeder))
    f.params = <GCODE_PARAMETERS *>tc_malloc(sizeof(GCODE_PARAMETERS))
    pthread_mutex_lock(&core.lock)
    m = core.offline           # machine_prepare made it and its place
    if f.params != NULL:
        f.params[0] = core.params
    if m != NULL:
        output_configure(&m.output, core)       # output stage: the core's smoothing and tables
    pthread_mutex_unlock(&core.lock)
    if f.params == NULL:
        core_keep_error(core, False, NULL)         # out of memory
    f.core = core
    f.m = m
    return m if f.params != NULL else NULL


cdef void *machine_run_body(void *arg) noexcept nogil:
    """The worker of a run along the program (StartCNCEx 30-33, a RunJob)."""
    cdef RunJob *job = <RunJob *>arg
    cdef Core *core = job.head.core
    cdef Feeder f
    cdef Machine *m = machine_worker_begin(&job.head, &f)
    cdef int32_t finish = EV_STOPPED
    tc_set_stage("the offline machine")
    if m != NULL:
        finish = machine_program_run(core, m, &f, job.regime, job.add_code)
    free(f.params)
    job_free(&job.head)
    core_finish(core, finish)
    return NULL


cdef void *machine_goto_body(void *arg) noexcept nogil:
    """The worker of a manual move (GoToPosition, GoToPositionEx: a GotoJob)."""
    cdef GotoJob *job = <GotoJob *>arg
    cdef Core *core = job.head.core
    cdef Feeder f
    cdef Machine *m = machine_worker_begin(&job.head, &f)
    cdef int32_t finish = EV_STOPPED
    tc_set_stage("the offline machine")
    if m != NULL:
        finish = machine_manual_move(core, m, &f, &job.dest, job.n_dest, &f.params.motion[5])
    free(f.params)
    job_free(&job.head)
    core_finish(core, finish)
    return NULL


cdef int32_t _pace(Core *core, Machine *m, Feeder *f) noexcept nogil:
    """Runs the pacer until the motion halts, feeding and notifying meanwhile;
    the transition-table event it ended with."""
    cdef bint started
    m.news = False
    TC_ATOMIC_STORE(&m.pacer_done, 0)
    clock_pacer_begins(m)
    started = pthread_create(&m.pacer, NULL, _pacer_body, core) == 0
    if not started:
        clock_pacer_ends(m)
        core_keep_error(core, False, NULL)         # out of memory
        return EV_STOPPED
    while not TC_ATOMIC_LOAD(&m.pacer_done):
        if f.prog != NULL:
            _feed(f)
        _drain(f)
        pthread_mutex_lock(&m.lock)
        while not m.news:
            pthread_cond_wait(&m.wake, &m.lock)
        m.news = False
        pthread_mutex_unlock(&m.lock)
    pthread_join(m.pacer, NULL)
    output_stop(&m.output)              # output stage: the filters' state ends with the pacer
    _drain(f)
    return _finish_event(m, f.regime)


cdef void _manual_gm(const double *start, const SIMPLE_GM_PARAMS *dest, uint32_t n_dest,
                     SIMPLE_GM_PARAMS *gm) noexcept nogil:
    """The path of a manual move from `start`: a line to the first n_dest axes of
    dest.m_calcE (the others stay), or an arc round dest.m_cc in the plane of
    m_planeTool's low 16 bits."""
    cdef double *end = <double *>&gm.m_calcE
    cdef const double *centre = <const double *>&dest.m_cc
    cdef int first, second, normal
    cdef int16_t plane = <int16_t>(dest.m_planeTool & 0xFFFF)
    memset(gm, 0, sizeof(SIMPLE_GM_PARAMS))
    memcpy(&gm.m_calcS, start, sizeof(P10DOUBLE))
    memcpy(end, start, sizeof(P10DOUBLE))
    memcpy(end, &dest.m_calcE, n_dest * sizeof(double))
    gm.m_func = dest.m_func
    if dest.m_func == 2 or dest.m_func == 3:
        if plane == 0:
            plane = 17
        gm.m_planeTool = plane
        gm.m_cc = dest.m_cc
        if plane_axes(plane, &first, &second, &normal):
            gm.m_cc.c = distance2d(start[first] - centre[first], start[second] - centre[second])


cdef inline double _manual_feed(const SIMPLE_GM_PARAMS *dest, const GCODE_FEED *cls) noexcept nogil:
    """mm/min: m_cc.a when not 0, else the motion class's."""
    return dest.m_cc.a if dest.m_cc.a > 0.0 else cls.feed


cdef const char *manual_path_not_finite(const double *start, const SIMPLE_GM_PARAMS *dest, uint32_t n_dest,
                                        const GCODE_FEED *cls) noexcept nogil:
    """Why a manual move from `start` at the motion class cls cannot run in finite
    numbers (NULL: it can): its length, its points (an arc's centre far away), or its
    feed (squared by the ramps)."""
    cdef SIMPLE_GM_PARAMS gm
    cdef Segment seg
    cdef double point[AXES]
    cdef double v = _manual_feed(dest, cls) / 60.0
    cdef int k
    _manual_gm(start, dest, n_dest, &gm)
    segment_of_gm(&gm, &seg)
    if not isfinite(seg.length) or not coordinates_finite(<const double *>&gm.m_cc, AXES):
        return "its length"
    for k in range(9):
        segment_point_at(&seg, seg.length * k / 8.0, point)
        if not coordinates_finite(point, AXES):
            return "its points"
    if not isfinite(v * v) or (v > 0.0 and not isfinite(seg.length / v)):
        return "its feed"
    return NULL


cdef void _manual_entry(Motion *mo, const SIMPLE_GM_PARAMS *dest, uint32_t n_dest,
                        const GCODE_FEED *cls) noexcept nogil:
    """The one entry of a manual move from where the machine stands (_manual_gm) at
    the feed of m_cc.a, else the motion class's."""
    cdef Entry *e = &mo.ring[0]
    cdef SIMPLE_GM_PARAMS gm
    cdef double feed
    _manual_gm(mo.position, dest, n_dest, &gm)
    memset(e, 0, sizeof(Entry))
    e.part = <size_t>PART_NONE
    e.kind = PART_MOTION
    e.func = dest.m_func
    e.file_idx = -1
    segment_of_gm(&gm, &e.seg)          # the host's record of the move
    e.s_from = 0.0
    e.s_to = e.seg.length
    feed = _manual_feed(dest, cls)
    e.node.vmax = feed / 60.0 if feed > 0.0 else 1.0 / 60.0
    e.node.ceiling = e.node.vmax
    e.feed = feed
    e.node.acc = e.node.dec = NO_LIMIT
    _class_ramps(e, cls)
    TC_STORE_U64(&mo.produced, 1)
    TC_ATOMIC_STORE(&mo.fed_all, 1)


cdef int32_t core_goto(Core *core, const SIMPLE_GM_PARAMS *dest, uint32_t n_dest, const double *coords) noexcept nogil:
    """GoToPosition / GoToPositionEx: a manual move; 50, then -50."""
    cdef GotoJob *job = <GotoJob *>job_new(CMD_GOTO)
    if job == NULL:
        err_out_of_memory(refusal(), -1, 0)
        return core_fail(core, refusal())
    job.dest = dest[0]
    if n_dest > 0:                      # GoToPosition(core, 0, NULL) moves nothing
        memcpy(&job.dest.m_calcE, coords, n_dest * sizeof(double))
    job.n_dest = n_dest
    return core_start(core, &job.head, "GoToPosition")


cdef bint machine_prepare(Core *core, Job *job, ErrorInfo *err) noexcept nogil:
    """The lifecycle's preparation of the machine's activities, with core.lock held
    before the worker starts: the machine exists and its place refers to the core's
    program (a new program: its start); a manual move's path is finite from where the
    machine stands. False (err set) refuses the activity."""
    cdef Machine *m = machine_of(core)
    cdef GotoJob *go = <GotoJob *>job
    cdef const char *unbounded
    if m == NULL:
        err_out_of_memory(err, -1, 0)
        return False
    if job.command == CMD_GOTO:
        unbounded = manual_path_not_finite(core.position, &go.dest, go.n_dest, &core.params.motion[5])
        if unbounded != NULL:
            err_path_not_finite(err, -1, 0, "GoToPosition", unbounded)
            return False
    if m.program != core.program:
        machine_forget(core)
        m.program = loaded_program_ref(core.program)
    if m.program != NULL and place_at_start(&m.place):
        placement_init(&m.placement, &m.program.prog, core.position)    # a run from the start
        placed_plan_free(&m.plan)       # the run makes the plan of this placement
        m.plan_made = False
    memcpy(m.motion.position, core.position, sizeof(core.position))
    return True
