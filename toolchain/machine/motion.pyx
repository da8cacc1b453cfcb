# The offline machine's interpolator as a pure step: motion_step(m, dt) moves the
# machine dt seconds along the entries of its look-ahead ring and reports what
# happened (an entry began, an M function waits, the run ended). No threads, no
# locks, no callbacks: machine.pyx paces it and talks to the host.
#
# Each entry is one part of the program (or, backward, one part retraced), with the
# limits the compiled plan holds for it (PartPlan). When an entry begins -- or when
# what the host governs changes: the override, a stop, a breakpoint, more look-ahead
# in the ring -- its profile is planned again from the machine's present speed with
# the planner's own functions: the backward pass over the entries the window sees
# (plan_backward) and the part's profile (profile_plan), sampled by profile_at. The
# window counts motion entries as the plan's does, so with nothing changed the
# profile is the plan's: a run takes GetGCodeRunTime.
from libc.math cimport fabs, HUGE_VAL

cdef extern from *:
    # 64-bit counters shared by the feeder and the step (system.pxd's macros)
    uint64_t TC_LOAD_U64 "TC_ATOMIC_LOAD" (uint64_t *p) nogil
    void TC_STORE_U64 "TC_ATOMIC_STORE" (uint64_t *p, uint64_t v) nogil


cdef inline double _eq(double acc, int32_t ramp) noexcept nogil:
    """The constant acceleration equivalent to a ramp of `ramp`'s shape (ramp_equivalent_acc),
    short for the profiles here."""
    return ramp_equivalent_acc(acc, ramp)


cdef inline double entry_length(const Entry *e) noexcept nogil:
    """The length an entry traverses along its segment (forward or backward)."""
    return fabs(e.s_to - e.s_from)


cdef void entry_point(const Entry *e, double d, double v, double *out) noexcept nogil:
    """The point d along the traverse, at path speed v: the dynamic G41/G42
    correction moves it sideways by dyn_extra (1 - v / vmax), towards the side the
    tool is compensated to: all of it at rest, none at the entry's full speed."""
    cdef double s, extra
    cdef double t[AXES]
    if e.kind != PART_MOTION:
        return
    s = e.s_from + d if e.s_to >= e.s_from else e.s_from - d
    segment_point_at(&e.seg, s, out)
    if e.dyn_extra == 0.0 or e.seg.length <= 0.0:
        return
    extra = e.dyn_extra * (1.0 - min(v / e.node.vmax, 1.0)) if e.node.vmax > 0.0 else e.dyn_extra
    segment_tangent(&e.seg, s, t)
    # the way's own direction (not the traverse's): a backward run keeps the side
    out[e.dyn_first] -= e.dyn_side * extra * t[e.dyn_second]
    out[e.dyn_second] += e.dyn_side * extra * t[e.dyn_first]


cdef inline Entry *motion_entry(Motion *m, size_t k) noexcept nogil:
    """The k-th entry from the current one."""
    return &m.ring[(m.head + k) % LOOK_RING]


cdef inline double _cap(const Motion *m, const Entry *e) noexcept nogil:
    """The entry's speed limit under the override: its feed scaled, never past the
    limits no override passes (axes, centripetal acceleration, arc feed table); not
    scaled in rapids with disableG0FeedOverride, nor when the override scales time."""
    if m.ovr_timing or (e.rapid and m.ovr_off_in_rapids):
        return e.node.vmax
    return min(e.node.vmax * m.ovr, e.node.ceiling)


cdef void _plan_current(Motion *m) noexcept nogil:
    """Plans the current motion entry again from where the machine is: the nodes of
    the entries the window sees after it (motion entries up to the window's count,
    the ring's end, or a stop's end) -- their junctions under the override, stops
    where the machine stands (waiting M functions, dwells, M0, breakpoints), their
    braking -- and the backward pass over them, in the ring, give the highest exit;
    the profile of what is left of the entry runs from the present speed to it. Sets
    window_short when the ring's end, not the window's, ended what it saw."""
    cdef Entry *cur = motion_entry(m, 0)
    cdef Entry *e
    cdef PlanNode *nd
    cdef PlanNode now                   # the current entry: what is left of it
    cdef size_t k, last = m.count, base = <size_t>m.consumed
    cdef uint64_t window_end = cur.motion_seq + m.window
    cdef const PlanNode *next = NULL
    cdef double cap, cap_before = _cap(m, cur), length
    if m.stopping:
        last = m.stop_entry + 1
    k = 1
    while k < last:
        e = motion_entry(m, k)
        if e.motion_seq >= window_end:
            break
        nd = &e.node
        nd.entry2 = -1.0                # the nodes changed: the pass computes them all
        length = entry_length(e)
        if m.stopping and k == m.stop_entry:
            length = m.stop_d
        if e.kind == PART_MOTION and entry_length(e) > 0.0:
            cap = _cap(m, e)
            nd.jin = 0.0 if e.break_before else min(e.v_junction, min(cap_before, cap))
            nd.brake2 = 2.0 * (_eq(m.stop_dec, m.stop_ramp) if m.stopping else nd.dec) * length
            cap_before = cap
        else:                           # the speed passes through, or the machine stands there
            nd.jin = 0.0 if e.waits or e.m0 or e.kind == PART_DWELL or e.break_before else HUGE_VAL
            nd.brake2 = 0.0
        nd.jin2 = nd.jin * nd.jin
        k += 1
    e = motion_entry(m, k - 1)
    m.window_short = (k == m.count and not m.complete and not m.stopping
                      and e.motion_seq + (1 if e.kind == PART_MOTION else 0) < window_end)
    if k > 1:
        plan_backward(&m.ring[0].node, sizeof(Entry), LOOK_RING - 1, base, base + k)
        next = &motion_entry(m, 1).node
    # the current entry's node: what is left of it
    nd = &now
    length = entry_length(cur)
    nd.acc = cur.node.acc
    nd.dec = cur.node.dec
    nd.ramp = cur.node.ramp
    if m.stopping:
        nd.dec = _eq(m.stop_dec, m.stop_ramp)
        nd.ramp = m.stop_ramp
        if m.stop_entry == 0:
            length = m.stop_d
            next = NULL
    nd.length = length - m.d if length > m.d else 0.0
    nd.vmax = _cap(m, cur)
    nd.brake2 = 2.0 * nd.dec * nd.length
    profile_plan(&m.run, nd, m.v, next, &m.recip)
    m.run_t = 0.0
    m.run_d0 = m.d
    m.replan = False
    m.planned_count = m.count


cdef void motion_reset(Motion *m, const double *position) noexcept nogil:
    """An empty machine standing at `position` (no thread uses it meanwhile)."""
    cdef int k
    m.produced = 0
    m.consumed = 0
    m.fed_all = 0
    m.n_log = 0
    m.head = 0
    m.count = 0
    m.complete = False
    m.state = MS_STARVED
    m.d = 0.0
    m.v = 0.0
    m.run_t = 0.0
    m.run_d0 = 0.0
    m.replan = True
    m.window_short = False
    m.full_for = 0
    m.started = False
    m.wait_left = 0.0
    m.confirmed = 0
    m.stopping = False
    m.ovr = 1.0
    m.ovr_target = 1.0
    m.recip.acc = m.recip.dec = m.recip.vmax = 0.0      # none yet: every value differs from 0
    m.cut_len = m.rapid_len = m.run_time = 0.0
    for k in range(AXES):
        m.position[k] = position[k]


cdef void motion_stop(Motion *m) noexcept nogil:
    """StopCNCEx: brake along the path from the present speed with stop_dec; the
    machine stops after v^2 / 2 stop_dec (the ramp's equivalent for a sine ramp), or
    sooner where the path makes it stop anyway."""
    cdef double left, rest
    cdef size_t k
    cdef Entry *e
    if m.stopping:
        return
    if m.state != MS_RUNNING:
        m.state = MS_STOPPED
        return
    left = m.v * m.v / (2.0 * _eq(m.stop_dec, m.stop_ramp))
    rest = m.d
    k = 0
    while k < m.count:
        e = motion_entry(m, k)
        if e.kind == PART_MOTION:
            if entry_length(e) - rest >= left:
                break
            left -= entry_length(e) - rest
        rest = 0.0
        k += 1
    if k == m.count:                    # the ring ends first: stop where it ends
        k = m.count - 1
        rest = 0.0
        left = entry_length(motion_entry(m, k))
    m.stopping = True
    m.stop_entry = k
    m.stop_d = rest + left
    m.replan = True


cdef void motion_sync(Motion *m) noexcept nogil:
    """Takes in what the feeder has written meanwhile."""
    cdef bint complete = TC_ATOMIC_LOAD(&m.fed_all) != 0     # read before `produced`
    m.count = <size_t>(TC_LOAD_U64(&m.produced) - m.consumed)
    m.complete = complete


cdef void _end_entry(Motion *m) noexcept nogil:
    """The current entry is done: the next one becomes current."""
    TC_STORE_U64(&m.consumed, m.consumed + 1)
    m.head = m.consumed % LOOK_RING
    m.count -= 1
    m.d = 0.0
    m.started = False
    m.replan = True
    if m.stopping:
        m.stop_entry -= 1


cdef inline void _log(Motion *m, int32_t kind, size_t part) noexcept nogil:
    """Records an event (ME_ENTRY, ME_MFUNC, ME_PRINT) of part `part` for the machine's thread
    to tell the driver."""
    m.log_kind[m.n_log] = kind
    m.log_part[m.n_log] = part
    m.n_log += 1


cdef int motion_begin_entry(Motion *m) noexcept nogil:
    """Makes the current entry begin (or pass, for entries without motion). Returns
    the events; leaves m.state MS_RUNNING when the machine moves on."""
    cdef Entry *e
    cdef int events = 0
    while True:
        if m.count == 0:
            if m.complete:
                m.state = MS_END
                return events | ME_HALT
            m.state = MS_STARVED
            return events
        e = motion_entry(m, 0)
        if m.stopping and m.stop_entry == 0 and m.stop_d <= 0.0:
            m.stopping = False
            m.state = MS_STOPPED
            m.v = 0.0
            return events | ME_HALT
        if e.break_before and not m.started and m.v == 0.0:
            e.break_before = False      # stopped before it: the next start passes
            m.state = MS_STOPPED
            return events | ME_HALT
        if m.n_log > LOG_SIZE - 4:     # the log is full: go on once it was read
            m.state = MS_STARVED
            return events
        if not m.started:
            m.started = True
            _log(m, ME_ENTRY, e.part)
            events |= ME_ENTRY
        if e.kind == PART_MOTION and entry_length(e) > m.d:
            m.state = MS_RUNNING
            if m.replan:
                _plan_current(m)
            return events
        if m.stopping and (e.waits or e.m0 or e.kind == PART_DWELL):
            m.stopping = False          # it stands here anyway: the stop ends here
            m.state = MS_STOPPED
            m.v = 0.0
            return events | ME_HALT
        if e.kind == PART_MOTION:
            entry_point(e, m.d, m.v, m.position)    # no way left in it: the speed passes through
        elif e.kind == PART_PRINT:
            _log(m, ME_PRINT, e.part)
            events |= ME_PRINT
        elif e.kind == PART_MFUNC:
            _log(m, ME_MFUNC, e.part)
            events |= ME_MFUNC
            if e.m0:
                _end_entry(m)
                m.state = MS_M0
                m.v = 0.0
                return events | ME_HALT
            if e.waits:
                m.state = MS_WAIT_M
                m.v = 0.0
                return events
        elif e.kind == PART_DWELL:
            m.state = MS_DWELL
            m.wait_left = e.dwell
            m.v = 0.0
            return events
        _end_entry(m)
        return events | motion_begin_entry(m)


cdef void _move_override(Motion *m, double dt) noexcept nogil:
    """One step of dt seconds of the override towards its target, by overrideInc per 100 us:
    held at 1 in a rapid with disableG0FeedOverride, at most 1 when it scales time; a change of
    speed (not of time) replans."""
    cdef double step = m.ovr_inc * dt / (STEP_US * SECONDS_PER_US)
    cdef double target = m.ovr_target
    cdef Entry *e
    if m.ovr_timing and target > 1.0:
        target = 1.0                    # scaled time would take every speed and ramp past its limit
        m.ovr = min(m.ovr, 1.0)
    if m.count > 0:
        e = motion_entry(m, 0)
        if e.rapid and m.ovr_off_in_rapids:
            target = 1.0
    if m.ovr == target:
        return
    if fabs(target - m.ovr) <= step:
        m.ovr = target
    elif target > m.ovr:
        m.ovr += step
    else:
        m.ovr -= step
    if not m.ovr_timing:
        m.replan = True


cdef void motion_locate(Motion *m) noexcept nogil:
    """m.position where the machine is now (inside the current motion entry)."""
    cdef Entry *e
    if m.count > 0 and m.d > 0.0:
        e = motion_entry(m, 0)
        if e.kind == PART_MOTION:
            entry_point(e, m.d, m.v, m.position)


cdef inline bint motion_window_full(Motion *m) noexcept nogil:
    """The ring holds the whole window after the current entry (its motion entries,
    the window's count of them), the run's end, or as much as it can. Once it does,
    it does until the entry ends (the feeder only adds): asked every step, it looks at
    the ring once per entry."""
    cdef const Entry *first
    cdef const Entry *last
    if m.full_for == m.consumed + 1 or m.complete or m.count >= LOOK_RING:
        return True
    if m.count == 0:
        return False
    first = &m.ring[m.head]
    last = &m.ring[(m.head + m.count - 1) % LOOK_RING]
    if last.motion_seq + (1 if last.kind == PART_MOTION else 0) >= first.motion_seq + m.window:
        m.full_for = m.consumed + 1
        return True
    return False


cdef int motion_step(Motion *m, double dt) noexcept nogil:
    """Moves the machine dt seconds. Returns the events (MotionEvent bits); the
    speed and lengths are current afterwards, the position once motion_locate has
    been called (it costs trigonometry on arcs: once per tick, not per step)."""
    cdef int events = 0
    cdef Entry *e
    cdef double tau, total, d, v, before
    cdef int guard = 0
    motion_sync(m)
    _move_override(m, dt)
    if m.state == MS_WAIT_M:
        if not TC_ATOMIC_LOAD(&m.confirmed):
            return 0
        TC_ATOMIC_STORE(&m.confirmed, 0)
        _end_entry(m)
        events |= motion_begin_entry(m)
    elif m.state == MS_DWELL:
        m.wait_left -= dt
        m.run_time += dt
        if m.wait_left > 0.0:
            return 0
        _end_entry(m)
        return motion_begin_entry(m)
    elif m.state == MS_STARVED:
        events |= motion_begin_entry(m)
    if m.state != MS_RUNNING:
        return events
    m.run_time += dt
    tau = dt * m.ovr if m.ovr_timing else dt
    while tau > 0.0 and guard < 64:
        guard += 1
        e = motion_entry(m, 0)
        if m.replan or (m.window_short and m.count != m.planned_count):
            _plan_current(m)
        total = profile_time(&m.run)
        before = m.d
        if m.run_t + tau < total:
            m.run_t += tau
            profile_at(&m.run, m.run_t, &d, &v)
            m.d = m.run_d0 + d
            m.v = v
            tau = 0.0
        else:
            tau -= total - m.run_t
            m.d = m.run_d0 + m.run.length
            m.v = m.run.v_out
            m.run_t = total
        if e.rapid:
            m.rapid_len += m.d - before
        else:
            m.cut_len += m.d - before
        if m.run_t >= total:
            entry_point(e, m.d, m.v, m.position)    # the entry's slot is the feeder's once it ends
            if m.stopping and m.stop_entry == 0:
                m.stopping = False
                m.state = MS_STOPPED
                m.v = 0.0
                return events | ME_HALT
            _end_entry(m)
            events |= motion_begin_entry(m)
            if m.state != MS_RUNNING:
                return events
    return events
