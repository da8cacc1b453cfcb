# The offline machine of one core (Local_Core_Mode 2): StartCNCEx 30-33, StopCNCEx,
# the M-function handshake, the override, breakpoints, manual moves, live GetPos.
#
# A run is one activity of the core (core.pyx) with two threads:
#   - the activity's worker is the machine's *feeder and notifier*: it turns parts
#     into look-ahead entries (placed geometry, limits, the plan's speeds, the
#     breakpoint question), and it makes every driver callback (DriverInitialize,
#     DriverGFunc as a part begins, DriverMFunc, PRINT, DriverEnd);
#   - the *pacer* wakes every millisecond on CLOCK_MONOTONIC, runs the 100 us steps
#     of motion.pyx that the elapsed time (times the core's time scale) calls for,
#     hands what happened to the notifier and publishes GetPos once.
# Neither waits for the other: the ring of entries and the event queue are the only
# things they share. The machine's place on the path (part, distance, the parts it
# ran, for backward) outlives the run, so the next StartCNCEx continues there.
from libc.stdlib cimport malloc, calloc, free
from libc.string cimport memset, memcpy, memmove, strdup
from libc.math cimport fabs
from posix.time cimport clock_gettime, nanosleep, timespec, CLOCK_MONOTONIC


cdef Machine *machine_of(Core *core) noexcept nogil:
    """The core's machine, made on first use (with core.lock held)."""
    cdef Machine *m = <Machine *>core.offline
    if m == NULL:
        m = <Machine *>calloc(1, sizeof(Machine))
        if m == NULL:
            return NULL
        pthread_mutex_init(&m.lock, NULL)
        pthread_cond_init(&m.wake, NULL)
        m.cur_motion = PART_NONE
        core.offline = m
    return m


cdef void machine_forget(Core *core) noexcept nogil:
    """With core.lock held and no activity: the machine's place is dropped (ResetCNC,
    a new program, DestroyCNC); the next forward run starts at the program's start."""
    cdef Machine *m = <Machine *>core.offline
    if m == NULL:
        return
    loaded_program_release(m.program)
    placed_plan_free(&m.plan)
    m.plan_made = False
    m.cur_motion = PART_NONE
    m.program = NULL
    m.part = 0
    m.part_s = 0.0
    m.began = False
    m.n_history = 0
    m.history_lost = False
    m.cut_len = m.rapid_len = m.run_time = 0.0
    TC_ATOMIC_STORE(&m.m_pending, 0)


cdef void machine_history_push(Machine *m, size_t part) noexcept nogil:
    """Remembers a motion part run (for backward runs): when HISTORY_DEPTH are held,
    the oldest tenth goes at once."""
    cdef size_t cap
    if m.n_history == HISTORY_DEPTH:
        memmove(m.history, m.history + HISTORY_DEPTH // 10,
                (HISTORY_DEPTH - HISTORY_DEPTH // 10) * sizeof(size_t))
        m.n_history -= HISTORY_DEPTH // 10
        m.history_lost = True
    if m.n_history == m.cap_history:
        cap = min(max(2 * m.cap_history, <size_t>1024), <size_t>HISTORY_DEPTH)
        if not resize(<void **>&m.history, cap, sizeof(size_t)):
            m.history_lost = True
            return
        m.cap_history = cap
    m.history[m.n_history] = part
    m.n_history += 1


# ------------------------------------------------------------------ entries


cdef bint _is_breakpoint(Feeder *f, const Part *p) noexcept nogil:
    """The run stops before the first part of a line the host marked (SetBreakpoint,
    the IsBreakpoint callback) -- never before the part it starts at."""
    cdef Callback cb
    cdef bint hit
    if f.first or (p.line == f.last_line and p.file_idx == f.last_file):
        return False
    f.last_line = p.line
    f.last_file = p.file_idx
    pthread_mutex_lock(&f.core.lock)
    hit = f.core.breakpoint_line != 0 and p.line == f.core.breakpoint_line and p.file_idx == f.core.breakpoint_file
    pthread_mutex_unlock(&f.core.lock)
    if not hit and callback_enter(f.core, SLOT_IS_BREAKPOINT, &cb):
        hit = (<TC_IsBreakpoint>cb.fn)(cb.user, p.line, p.file_idx) == 1
        callback_leave(f.core, SLOT_IS_BREAKPOINT)
    return hit


cdef void _entry_identity(Feeder *f, Entry *e, const Part *p, size_t part) noexcept nogil:
    e.part = part
    e.motion_seq = f.motions
    if p.kind == PART_MOTION:
        f.motions += 1
    e.kind = p.kind
    e.func = p.func
    e.line = p.line
    e.file_idx = p.file_idx
    e.gcode_index = p.gcode_index
    e.feed = p.feed
    e.rapid = p.kind == PART_MOTION and p.func == 0
    e.waits = False
    e.m0 = False
    e.break_before = False
    e.dwell = 0.0
    e.s_from = e.s_to = 0.0
    e.vmax = e.v_ceiling = e.jin = 0.0
    e.acc = e.dec = 1e12
    e.ramp = RAMP_TRAPEZOID
    e.dyn_extra = 0.0


cdef void _dynamic_correction(Entry *e, const Part *p, const GCODE_PARAMETERS *params) noexcept nogil:
    """dynamicG41/G42Correction_mm and _percent (of the tool radius in use) of a
    compensated motion part: how far the machine moves the tool further out at rest
    (motion.pyx entry_point; none at the part's full speed)."""
    cdef double mm, percent, radius
    cdef int normal
    if p.comp != 41 and p.comp != 42:
        return
    mm = params.dynamicG41Correction_mm if p.comp == 41 else params.dynamicG42Correction_mm
    percent = params.dynamicG41Correction_percent if p.comp == 41 else params.dynamicG42Correction_percent
    radius = fabs(params.correction[p.comp_slot & 7].size)
    e.dyn_extra = mm + percent * 0.01 * radius
    if not plane_axes(p.plane, &e.dyn_first, &e.dyn_second, &normal) or not (e.dyn_extra == e.dyn_extra):
        e.dyn_extra = 0.0
    e.dyn_side = 1 if p.comp == 41 else -1


cdef void _entry_limits(Entry *e, const PartPlan *pp) noexcept nogil:
    """A motion entry's limits as the plan holds them (the profile is made from them).
    A part the plan passed through without length has none: only a placed plan that
    could not be made (out of memory) leaves one with length, which then creeps."""
    e.vmax = pp.v_cap if pp.v_cap > 0.0 else 1.0 / 60.0
    e.v_ceiling = max(<double>pp.v_ceiling, e.vmax)
    e.jin = pp.v_junction
    e.acc = pp.acc if pp.acc > 0.0 else 1e12
    e.dec = pp.dec if pp.dec > 0.0 else 1e12
    e.ramp = pp.ramp


cdef void _class_limits(Entry *e, const GCODE_FEED *cls) noexcept nogil:
    """A motion class's feed (when set) caps the entry, its ramps replace the plan's
    (motion[2] backward, motion[4] regime 31)."""
    if cls.feed > 0.0:
        e.vmax = min(e.vmax, cls.feed / 60.0)
        e.v_ceiling = min(e.v_ceiling, e.vmax)
        e.jin = min(e.jin, e.vmax)
    _class_ramps(e, cls)


cdef void _class_ramps(Entry *e, const GCODE_FEED *cls) noexcept nogil:
    """A motion class's ramps (an acceleration of 0: the entry's own)."""
    e.ramp = RAMP_SINE if cls.rampType == RAMP_SINE else RAMP_TRAPEZOID
    if 0.0 < cls.acc < 1e12:
        e.acc = ramp_equivalent_acc(cls.acc, e.ramp)
    if 0.0 < cls.dec < 1e12:
        e.dec = ramp_equivalent_acc(cls.dec, e.ramp)


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
        _entry_identity(f, e, p, k)
        e.break_before = _is_breakpoint(f, p)
        f.first = False
        if p.kind == PART_MFUNC:
            e.m0 = p.func == 0
            e.waits = not (p.flags & FLAG_CONTINUOUS_M) and p.func != 0
        elif p.kind == PART_DWELL:
            e.dwell = p.value
            e.waits = True
        elif p.kind == PART_MOTION:
            f.any_motion = True
            placed_segment(prog, &f.m.placement, k, &e.seg)
            e.s_from = 0.0
            e.s_to = e.seg.length
            _entry_limits(e, placed_plan_part(&f.m.plan, k))
            if f.regime == RUN_FORWARD_NO_M:
                _class_limits(e, &f.params.motion[4])
            _dynamic_correction(e, p, f.params)
        return True
    return False


cdef bint _backward_entry(Feeder *f, Entry *e) noexcept nogil:
    """The next part back along the executed path; False when what the machine
    remembers ends. With `back_current`, entry 0 is the rest of the part it stands in.
    Its junction limit is the one where it meets the part retraced before it (that
    part's start)."""
    cdef Machine *m = f.m
    cdef const Program *prog = f.prog
    cdef size_t k, back
    cdef double from_s = -1.0
    if f.back_current and f.next == 0:
        k = m.part
        from_s = m.part_s
    else:
        back = f.next - (1 if f.back_current else 0)
        if back >= m.n_history:
            return False
        k = m.history[m.n_history - 1 - back]
    _entry_identity(f, e, &prog.parts[k], k)
    placed_segment(prog, &m.placement, k, &e.seg)
    e.s_from = from_s if from_s >= 0.0 else e.seg.length
    e.s_to = 0.0
    _entry_limits(e, placed_plan_part(&m.plan, k))
    e.jin = placed_plan_part(&m.plan, f.back_last).v_junction if f.next > 0 else 0.0
    _class_limits(e, &f.params.motion[2])
    _dynamic_correction(e, &prog.parts[k], f.params)
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

cdef inline double _now() noexcept nogil:
    cdef timespec ts
    clock_gettime(CLOCK_MONOTONIC, &ts)
    return <double>ts.tv_sec + <double>ts.tv_nsec * 1e-9


cdef void _publish(Core *core, Machine *m) noexcept nogil:
    """GetPos from the machine's state (the pacer's thread)."""
    cdef Motion *mo = &m.motion
    cdef SnapshotData view
    cdef Entry *e
    cdef float *cells = <float *>&view.pos.m_pars
    cdef int k
    memset(&view, 0, sizeof(view))
    for k in range(26):
        cells[k] = INVALID_VALUE_F
    view.pos.m_fileIdx = -1
    memcpy(&view.pos.m_calcS, mo.position, sizeof(P10DOUBLE))
    view.pos.m_calcE = view.pos.m_calcS
    for k in range(10):
        cells[_AXIS_CELLS[k]] = <float>mo.position[k]
    if mo.count > 0:
        e = motion_entry(mo, 0)
        view.pos.m_func = e.func if e.kind != PART_MFUNC else e.func + 10000
        view.pos.m_editorLine = e.line
        view.pos.m_fileIdx = e.file_idx
        view.pos.m_gCodeIndex = e.gcode_index
        if e.kind == PART_MOTION:
            view.pos.m_pars.G = <float>e.func
            view.enh.m_actPartLen = entry_length(e)
            view.enh.m_actPartRemain = entry_length(e) - mo.d
            view.enh.m_setFeed = e.feed
            view.enh.m_calcFeed = e.vmax * 60.0
        elif e.kind == PART_MFUNC and mo.state == MS_WAIT_M:
            view.pos.m_pars.M = <float>e.func
        if m.program != NULL and e.file_idx == m.program.prog.main_file_idx:
            view.enh.m_MasterEditorLine = e.line
    view.pos.m_pars.N = <float>mo.cut_len
    view.pos.m_pars.T = <float>mo.rapid_len
    view.pos.m_pars.P = <float>(100.0 * min(mo.count, m.motion.window) / m.motion.window) if m.motion.window > 0 else 0.0
    view.enh.m_actFeed = mo.v * 60.0 * (mo.ovr if mo.ovr_timing else 1.0)
    view.enh.m_relFeed = mo.ovr
    view.enh.m_actWorkPartsLen = mo.cut_len
    view.enh.m_actG00PartsLen = mo.rapid_len
    view.enh.m_actPartsLen = mo.cut_len + mo.rapid_len
    view.enh.m_MasterFileIdx = <uint32_t>(m.program.prog.main_file_idx if m.program != NULL else -1)
    view.enh.m_statusCNC = core_status(core)
    view.enh.m_cncRunTime = mo.run_time
    snapshot_publish(&core.snap, &view)


cdef extern from *:
    """
    /* m_pars cells of the ten axes X Y Z C B U V W A O (letter - 'A') */
    static const int tc_axis_cells[10] = {23, 24, 25, 2, 1, 20, 21, 22, 0, 14};
    """
    const int *_AXIS_CELLS "tc_axis_cells"


cdef void *_pacer_body(void *arg) noexcept nogil:
    cdef Core *core = <Core *>arg
    cdef Machine *m = <Machine *>core.offline
    cdef Motion *mo = &m.motion
    cdef double last = _now(), now, budget = 0.0, scale
    cdef double dt = STEP_US * 1e-6
    cdef timespec nap
    cdef int events
    cdef bint halted = False
    cdef uint64_t told = mo.consumed     # entries done when the notifier was last woken
    nap.tv_sec = 0
    nap.tv_nsec = 1000000
    while not halted and not TC_ATOMIC_LOAD(&core.cancel):
        now = _now()
        scale = TC_ATOMIC_LOAD_D(&core.time_scale)
        budget += (now - last) * scale
        last = now
        if budget > 1.0 * scale:            # the thread was held up: the machine does not jump
            budget = 1.0 * scale
        mo.ovr_target = TC_ATOMIC_LOAD_D(&core.rel_feed)
        if TC_ATOMIC_LOAD(&core.stop):
            motion_stop(mo)
        while budget >= dt and mo.state < MS_STOPPED:
            motion_sync(mo)
            if mo.consumed - told >= LOOK_RING // 4:
                _hand_over(m, True)         # room in the ring: the feeder refills it
                told = mo.consumed
            if not motion_window_full(mo) and mo.state != MS_WAIT_M:
                break                       # time waits for the feeder (the plan needs its window)
            if mo.n_log > LOG_SIZE - 8:
                _hand_over(m, True)
                if mo.n_log > LOG_SIZE - 8:
                    break                   # the notifier is behind: the step waits for it
            events = motion_step(mo, dt)
            budget -= dt
            if events & ME_HALT:
                halted = True
                break
            if mo.state == MS_WAIT_M:       # it stands until the host confirms: no steps to run
                _hand_over(m, True)
                budget = 0.0
                break
            if TC_ATOMIC_LOAD(&core.stop):
                motion_stop(mo)
        halted = halted or mo.state >= MS_STOPPED
        motion_locate(mo)
        _hand_over(m, mo.consumed != told or halted)
        told = mo.consumed
        _publish(core, m)
        if not halted:
            nanosleep(&nap, NULL)
    motion_locate(mo)
    TC_ATOMIC_STORE(&m.pacer_done, 1)
    _hand_over(m, True)
    return NULL


cdef void _hand_over(Machine *m, bint wake) noexcept nogil:
    """The step's log into the notifier's queue (as much as fits); wakes the
    notifier when there is news for it (events, or room in the ring: `wake`)."""
    cdef Motion *mo = &m.motion
    cdef int32_t k = 0, n = mo.n_log
    if n == 0 and not wake:
        return
    pthread_mutex_lock(&m.lock)
    while k < n and m.ev_n < EVENT_QUEUE:
        m.events[(m.ev_first + m.ev_n) % EVENT_QUEUE].kind = mo.log_kind[k]
        m.events[(m.ev_first + m.ev_n) % EVENT_QUEUE].part = mo.log_part[k]
        m.ev_n += 1
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
    """One event as the vendor's driver gets it."""
    cdef Core *core = f.core
    cdef Machine *m = f.m
    cdef const Part *p
    cdef SIMPLE_GM_PARAMS gm
    cdef Callback cb
    cdef int32_t answer = 0
    if f.prog == NULL or ev.part >= f.prog.n_parts:
        return
    p = &f.prog.parts[ev.part]
    if ev.kind == ME_PRINT:
        core_output(core, 2, f.prog.texts + p.aux)
        return
    placed_part_to_gm(f.prog, ev.part, &m.placement, &gm)
    if ev.kind == ME_ENTRY:
        if p.kind == PART_MOTION or p.kind == PART_DWELL:
            if callback_enter(core, SLOT_DRIVER_G_FUNC, &cb):
                (<TC_DriverGFunc>cb.fn)(cb.user, &gm)
                callback_leave(core, SLOT_DRIVER_G_FUNC)
        return
    # an M function: a waiting one is confirmed by DriverMFunc's 0, or later by ConfirmMFunc
    if callback_enter(core, SLOT_DRIVER_M_FUNC, &cb):
        answer = (<TC_DriverMFunc>cb.fn)(cb.user, &gm)
        callback_leave(core, SLOT_DRIVER_M_FUNC)
    if p.flags & FLAG_CONTINUOUS_M or p.func == 0:
        return
    if answer == MFUNC_LATER:
        TC_ATOMIC_STORE(&m.m_pending, p.func if p.func != 0 else -1)
    else:
        TC_ATOMIC_STORE(&m.motion.confirmed, 1)


cdef bint _next_event(Machine *m, MachineEvent *ev) noexcept nogil:
    cdef bint got = False
    pthread_mutex_lock(&m.lock)
    if m.ev_n > 0:
        ev[0] = m.events[m.ev_first]
        m.ev_first = (m.ev_first + 1) % EVENT_QUEUE
        m.ev_n -= 1
        got = True
    pthread_mutex_unlock(&m.lock)
    return got


cdef int32_t _finish_event(Machine *m, int32_t regime) noexcept nogil:
    """The transition-table event the halted motion ends the run with."""
    cdef int32_t state = m.motion.state
    if state == MS_M0:
        return EV_M0
    if state == MS_END:
        if regime == RUN_BACKWARD and m.history_lost:
            return EV_STOPPED       # the remembered path ended before the program's start
        return EV_DONE
    return EV_STOPPED


cdef void _keep_place(Machine *m, const Feeder *f) noexcept nogil:
    """After the run: where the machine is on the program, and what it ran before."""
    cdef Motion *mo = &m.motion
    cdef const Program *prog = f.prog
    cdef Entry *e
    cdef size_t removed
    cdef bint inside
    if f.regime == RUN_BACKWARD:
        # entries [0, consumed) were retraced; the current one, if any, is the part it is in now
        removed = <size_t>mo.consumed + (1 if mo.count > 0 else 0)
        removed -= 1 if f.back_current and removed > 0 else 0
        m.n_history -= min(removed, m.n_history)
        if mo.count > 0:
            e = motion_entry(mo, 0)
            m.part = e.part
            m.part_s = e.s_from - mo.d
            m.began = True
        elif not m.history_lost:
            m.part = 0                  # back at the start: a run begins with the program again
            m.part_s = 0.0
            m.began = False
        elif mo.consumed > 0:
            m.part = mo.ring[(mo.consumed - 1) % LOOK_RING].part
            m.part_s = 0.0
            m.began = False
        m.cur_motion = m.part if m.began else PART_NONE
        return
    if mo.count > 0:
        e = motion_entry(mo, 0)
        m.part = e.part
        m.part_s = mo.d
        m.began = mo.started
    elif not mo.complete:               # it stands where the feeder is to go on
        m.part = f.next
        m.part_s = 0.0
        m.began = False
    else:
        m.part = prog.n_parts
        m.part_s = 0.0
        m.began = False
    inside = mo.count > 0 and m.began and motion_entry(mo, 0).kind == PART_MOTION
    if not inside and m.cur_motion != PART_NONE:
        machine_history_push(m, <size_t>m.cur_motion)      # it stands after the part it ran last
        m.cur_motion = PART_NONE


cdef void _drain(Feeder *f) noexcept nogil:
    """Delivers every queued event; a motion part that begins pushes the one before
    it into the history."""
    cdef MachineEvent ev
    cdef Machine *m = f.m
    while _next_event(m, &ev):
        if (ev.kind == ME_ENTRY and f.regime != RUN_BACKWARD and f.prog != NULL and ev.part < f.prog.n_parts
                and f.prog.parts[ev.part].kind == PART_MOTION):
            if m.cur_motion != PART_NONE:
                machine_history_push(m, <size_t>m.cur_motion)
            m.cur_motion = <int64_t>ev.part
        _notify(f, &ev)


cdef void _motion_setup(Core *core, Motion *mo, const GCODE_PARAMETERS *params, const double *start) noexcept nogil:
    """An empty motion at `start` with the run's settings (override, stop)."""
    motion_reset(mo, start)
    mo.window = 1
    mo.ovr = TC_ATOMIC_LOAD_D(&core.rel_feed) if TC_ATOMIC_LOAD_D(&core.rel_feed) > 0 else 1.0
    mo.ovr_inc = params.overrideInc if 0.0 < params.overrideInc <= 0.1 else 0.001
    mo.ovr_timing = (params.interpolatorConfig0 & 1) != 0
    mo.ovr_off_in_rapids = params.disableG0FeedOverride == 1
    mo.stop_dec = params.motion[6].dec if 0.0 < params.motion[6].dec < 1e12 else 1e12
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
    cdef double start[10]
    memcpy(start, mo.position, sizeof(start))
    _motion_setup(core, mo, f.params, start)
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
    f.next = m.part if regime != RUN_BACKWARD else 0
    f.back_current = m.part < prog.n_parts and m.part_s > 0.0 and prog.parts[m.part].kind == PART_MOTION
    if not m.plan_made:                 # the first run where the placement holds: its plan
        placed_plan_make(&m.plan, prog, &m.placement)
        m.plan_made = True
    _motion_setup(core, mo, f.params, start)
    mo.window = _window(prog.planned_with.window)
    mo.d = m.part_s if regime != RUN_BACKWARD else 0.0
    mo.started = m.began and regime != RUN_BACKWARD
    mo.cut_len = m.cut_len
    mo.rapid_len = m.rapid_len
    mo.run_time = m.run_time


cdef void _run_keep(Core *core, Machine *m, const Feeder *f) noexcept nogil:
    """With core.lock held, after a run along the program: the machine's place, its
    lengths and times, and the core's position follow the run."""
    _keep_place(m, f)
    m.cut_len = m.motion.cut_len
    m.rapid_len = m.motion.rapid_len
    m.run_time = m.motion.run_time
    memcpy(core.position, m.motion.position, sizeof(core.position))


cdef int32_t machine_program_run(Core *core, Machine *m, Feeder *f, int32_t regime, const char *add_code) noexcept nogil:
    """A run along the program (regimes 30-33) from the machine's place; the place
    and the machine position follow it."""
    cdef Motion *mo = &m.motion
    cdef Callback cb
    cdef int32_t finish
    cdef char *stop_code
    cdef double start[10]
    memcpy(start, mo.position, sizeof(start))
    _run_setup(core, m, f, regime, start)
    _feed(f)
    motion_sync(mo)
    _publish(core, m)                   # GetPos shows this run from its start, not the last activity's
    if callback_enter(core, SLOT_DRIVER_INITIALIZE, &cb):
        (<TC_DriverInitialize>cb.fn)(cb.user, start, 10, regime)
        callback_leave(core, SLOT_DRIVER_INITIALIZE)
    if regime != RUN_FORWARD_NO_M and regime != RUN_BACKWARD:
        send_add_code(core, add_code, start)
    finish = _pace(core, m, f)
    pthread_mutex_lock(&core.lock)
    _run_keep(core, m, f)
    stop_code = m.stop_code
    m.stop_code = NULL
    pthread_mutex_unlock(&core.lock)
    if (finish == EV_STOPPED and stop_code != NULL and not TC_ATOMIC_LOAD(&core.cancel)
            and regime != RUN_FORWARD_NO_M and regime != RUN_BACKWARD):
        send_add_code(core, stop_code, mo.position)
    free(stop_code)
    if callback_enter(core, SLOT_DRIVER_END, &cb):
        (<TC_DriverEnd>cb.fn)(cb.user)
        callback_leave(core, SLOT_DRIVER_END)
    return finish


cdef Machine *machine_worker_begin(Job *job, Feeder *f) noexcept nogil:
    """The start of a run's worker: the feeder with a copy of the core's settings;
    NULL (the run's error set) when out of memory."""
    cdef Core *core = job.core
    cdef Machine *m
    worker_thread_mark(core)
    memset(f, 0, sizeof(Feeder))
    f.params = <GCODE_PARAMETERS *>malloc(sizeof(GCODE_PARAMETERS))
    pthread_mutex_lock(&core.lock)
    m = <Machine *>core.offline           # machine_prepare made it and its place
    if f.params != NULL:
        f.params[0] = core.params
    else:
        set_error(&core.error, ERR_OUT_OF_MEMORY, -1, 0, NULL, 0)
    pthread_mutex_unlock(&core.lock)
    f.core = core
    f.m = m
    return m if f.params != NULL else NULL


cdef void *machine_body(void *arg) noexcept nogil:
    cdef Job *job = <Job *>arg
    cdef Core *core = job.core
    cdef Feeder f
    cdef Machine *m = machine_worker_begin(job, &f)
    cdef int32_t finish = EV_STOPPED
    if m != NULL:
        if job.regime == RUN_MANUAL:
            finish = machine_manual_move(core, m, &f, &job.dest, job.n_dest, &f.params.motion[5])
        else:
            finish = machine_program_run(core, m, &f, job.regime, job.add_code)
    free(f.params)
    job_free(job)
    core_finish(core, finish)
    return NULL


cdef int32_t _pace(Core *core, Machine *m, Feeder *f) noexcept nogil:
    """Runs the pacer until the motion halts, feeding and notifying meanwhile;
    the transition-table event it ended with."""
    cdef bint started
    m.news = False
    TC_ATOMIC_STORE(&m.pacer_done, 0)
    started = pthread_create(&m.pacer, NULL, _pacer_body, core) == 0
    if not started:
        pthread_mutex_lock(&core.lock)
        set_error(&core.error, ERR_OUT_OF_MEMORY, -1, 0, NULL, 0)
        pthread_mutex_unlock(&core.lock)
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
    _drain(f)
    return _finish_event(m, f.regime)


cdef void _manual_entry(Motion *mo, const SIMPLE_GM_PARAMS *dest, uint32_t n_dest,
                        const GCODE_FEED *cls) noexcept nogil:
    """The one entry of a manual move from where the machine stands: a line to the
    first n_dest axes of dest.m_calcE (the others stay), or an arc round dest.m_cc in
    the plane of m_planeTool's low 16 bits; the feed of m_cc.a, else the class's."""
    cdef Entry *e = &mo.ring[0]
    cdef SIMPLE_GM_PARAMS gm
    cdef double *end = <double *>&gm.m_calcE
    cdef const double *centre = <const double *>&dest.m_cc
    cdef int first, second, normal
    cdef int16_t plane = <int16_t>(dest.m_planeTool & 0xFFFF)
    cdef double feed
    memset(&gm, 0, sizeof(gm))
    memcpy(&gm.m_calcS, mo.position, sizeof(P10DOUBLE))
    memcpy(end, mo.position, sizeof(P10DOUBLE))
    memcpy(end, &dest.m_calcE, n_dest * sizeof(double))
    gm.m_func = dest.m_func
    if dest.m_func == 2 or dest.m_func == 3:
        if plane == 0:
            plane = 17
        gm.m_planeTool = plane
        gm.m_cc = dest.m_cc
        if plane_axes(plane, &first, &second, &normal):
            gm.m_cc.c = distance2d(mo.position[first] - centre[first], mo.position[second] - centre[second])
    memset(e, 0, sizeof(Entry))
    e.part = <size_t>PART_NONE
    e.kind = PART_MOTION
    e.func = dest.m_func
    e.file_idx = -1
    segment_of_gm(&gm, &e.seg)          # the host's record of the move
    e.s_from = 0.0
    e.s_to = e.seg.length
    feed = dest.m_cc.a if dest.m_cc.a > 0.0 else cls.feed
    e.vmax = feed / 60.0 if feed > 0.0 else 1.0 / 60.0
    e.v_ceiling = e.vmax
    e.feed = feed
    e.acc = e.dec = 1e12
    _class_ramps(e, cls)
    TC_STORE_U64(&mo.produced, 1)
    TC_ATOMIC_STORE(&mo.fed_all, 1)


cdef int32_t core_goto(Core *core, const SIMPLE_GM_PARAMS *dest, uint32_t n_dest, const double *coords) noexcept nogil:
    """GoToPosition / GoToPositionEx: a manual move; 50, then -50."""
    cdef Job *job = job_new()
    if job == NULL:
        return core_fail(core, ERR_OUT_OF_MEMORY, NULL)
    job.regime = RUN_MANUAL
    job.dest = dest[0]
    memcpy(&job.dest.m_calcE, coords, n_dest * sizeof(double))
    job.n_dest = n_dest
    return core_begin(core, CMD_GOTO, "GoToPosition", machine_body, job)


cdef void machine_keep_stop_code(Core *core, const char *code) noexcept nogil:
    """StopCNCEx's addCode, sent by the run once the machine stands."""
    cdef Machine *m
    cdef char *copy = strdup(code)
    pthread_mutex_lock(&core.lock)
    m = <Machine *>core.offline
    if m != NULL:
        free(m.stop_code)
        m.stop_code = copy
        copy = NULL
    pthread_mutex_unlock(&core.lock)
    free(copy)


cdef int32_t machine_send_m(Core *core, const SIMPLE_GM_PARAMS *fun) noexcept nogil:
    """ToolChainCore_MFunc: an M function to the machine (DriverMFunc) while it
    stands; answered TC_MFUNC_LATER, it is pending until ToolChainCore_ConfirmMFunc."""
    cdef int32_t status = core_status(core)
    cdef Machine *m
    cdef Callback cb
    cdef int32_t answer = 0
    if status > 0:
        return core_refuse(core, "MFunc", status)
    pthread_mutex_lock(&core.lock)
    m = machine_of(core)
    pthread_mutex_unlock(&core.lock)
    if m == NULL:
        return core_fail(core, ERR_OUT_OF_MEMORY, NULL)
    if TC_ATOMIC_LOAD(&m.m_pending) != 0:
        return core_fail(core, ERR_M_PENDING, NULL)
    if callback_enter(core, SLOT_DRIVER_M_FUNC, &cb):
        answer = (<TC_DriverMFunc>cb.fn)(cb.user, fun)
        callback_leave(core, SLOT_DRIVER_M_FUNC)
    if answer == MFUNC_LATER:
        TC_ATOMIC_STORE(&m.m_pending, fun.m_func if fun.m_func != 0 else -1)
    return TOOL_CHAIN_SUCCESS


cdef int32_t machine_command(int32_t regime) noexcept nogil:
    """The transition table's command of StartCNCEx 30-33."""
    if regime == RUN_FORWARD:
        return CMD_FORWARD
    if regime == RUN_FORWARD_NO_M:
        return CMD_FORWARD_NO_M
    if regime == RUN_BACKWARD:
        return CMD_BACKWARD
    return CMD_FORWARD_SKIP_M


cdef bint machine_prepare(Core *core) noexcept nogil:
    """With core.lock held, before a run starts (core_begin): the machine exists and
    its place refers to the core's program (a new program: its start)."""
    cdef Machine *m = machine_of(core)
    if m == NULL:
        return False
    if m.program != core.program:
        machine_forget(core)
        m.program = loaded_program_ref(core.program)
    if m.program != NULL and m.part == 0 and m.part_s == 0.0 and m.n_history == 0:
        placement_init(&m.placement, &m.program.prog, core.position)    # a run from the start
        placed_plan_free(&m.plan)       # the run makes the plan of this placement
        m.plan_made = False
    memcpy(m.motion.position, core.position, sizeof(core.position))
    return True


# ------------------------------------------------------------------ M functions

cdef int32_t machine_confirm_m(Core *core) noexcept nogil:
    """ToolChainCore_ConfirmMFunc: ends the M function that waits for the host."""
    cdef Machine *m
    cdef int32_t pending
    pthread_mutex_lock(&core.lock)
    m = <Machine *>core.offline         # never freed once made
    pthread_mutex_unlock(&core.lock)
    pending = TC_ATOMIC_LOAD(&m.m_pending) if m != NULL else 0
    if pending == 0 or not TC_ATOMIC_CAS(&m.m_pending, &pending, 0):
        return core_fail(core, ERR_NO_M_PENDING, NULL)
    TC_ATOMIC_STORE(&m.motion.confirmed, 1)
    return TOOL_CHAIN_SUCCESS
