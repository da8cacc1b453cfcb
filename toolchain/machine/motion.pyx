# The offline machine's interpolator as a pure step: motion_step(m, dt) moves the
# machine dt seconds along the entries of its look-ahead ring and reports what
# happened (an entry began, an M function waits, the run ended). No threads, no
# locks, no callbacks: machine.pyx paces it and talks to the host.
#
# Each entry is one part of the program (or, backward, one part retraced). When an
# entry begins -- or when what governs its speed changes (override, stop, more
# look-ahead) -- its speed profile is planned again from the machine's present speed
# in closed form (the ramps of planner.pxd): up to the entry's cap, cruise, down to the highest
# exit that every entry visible after it can still brake from. With the window full
# and no override, that profile is the compiled plan's own: a run takes
# GetGCodeRunTime.
from libc.math cimport sqrt, fabs

cdef extern from *:
    # 64-bit counters shared by the feeder and the step (system.pxd's macros)
    uint64_t TC_LOAD_U64 "TC_ATOMIC_LOAD" (uint64_t *p) nogil
    void TC_STORE_U64 "TC_ATOMIC_STORE" (uint64_t *p, uint64_t v) nogil


cdef inline double _eq(double acc, int32_t ramp) noexcept nogil:
    return ramp_equivalent_acc(acc, ramp)


cdef inline double entry_length(const Entry *e) noexcept nogil:
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
    extra = e.dyn_extra * (1.0 - min(v / e.vmax, 1.0)) if e.vmax > 0.0 else e.dyn_extra
    segment_tangent(&e.seg, s, t)
    # the way's own direction (not the traverse's): a backward run keeps the side
    out[e.dyn_first] -= e.dyn_side * extra * t[e.dyn_second]
    out[e.dyn_second] += e.dyn_side * extra * t[e.dyn_first]


cdef void run_plan(Run *r, double length, double v_in, double cap, double out_cap,
                   double acc, double dec, int32_t ramp) noexcept nogil:
    """The fastest profile over `length` from v_in that stays under cap and ends at
    most at out_cap (or at the lowest speed braking with dec allows, if that is
    higher); both ramps with the ramp shape `ramp`."""
    cdef double ae = _eq(acc, ramp), de = _eq(dec, ramp)
    cdef double out, hi2 = v_in * v_in + 2.0 * ae * length, lo2 = v_in * v_in - 2.0 * de * length
    cdef double peak, up, down
    out = min(out_cap, sqrt(hi2))
    if lo2 > out * out:
        out = sqrt(lo2)
    if v_in <= cap:
        if out > cap:
            out = cap
        up = (cap * cap - v_in * v_in) / (2.0 * ae)
        down = (cap * cap - out * out) / (2.0 * de)
        if up + down <= length:
            peak = cap
        else:
            peak = sqrt((2.0 * ae * de * length + de * v_in * v_in + ae * out * out) / (ae + de))
            peak = max(peak, max(v_in, out))
    else:                               # above the cap (a lowered override): brake to it first
        up = (v_in * v_in - cap * cap) / (2.0 * de)
        down = (cap * cap - out * out) / (2.0 * de) if out <= cap else 0.0
        if up + down <= length and out <= cap:
            peak = cap
        else:
            peak = v_in
    r.v_in = v_in
    r.v_peak = peak
    r.v_out = out
    r.ramp = ramp
    r.a1 = acc if peak >= v_in else dec
    r.a3 = dec if peak >= out else acc
    r.t1 = ramp_time(v_in, peak, r.a1, ramp)
    r.t3 = ramp_time(peak, out, r.a3, ramp)
    r.d1 = 0.5 * (v_in + peak) * r.t1
    r.d3 = 0.5 * (peak + out) * r.t3
    r.d2 = length - r.d1 - r.d3
    if r.d2 < 0.0:
        r.d2 = 0.0
    r.t2 = r.d2 / peak if peak > 0.0 else 0.0


cdef inline double run_time_total(const Run *r) noexcept nogil:
    return r.t1 + r.t2 + r.t3


cdef void run_at(const Run *r, double t, double *d, double *v) noexcept nogil:
    """Distance and speed t seconds into the profile."""
    if t < r.t1:
        d[0] = ramp_distance_at(r.v_in, r.v_peak, r.a1, r.ramp, t)
        v[0] = ramp_speed_at(r.v_in, r.v_peak, r.a1, r.ramp, t)
        return
    t -= r.t1
    if t < r.t2:
        d[0] = r.d1 + r.v_peak * t
        v[0] = r.v_peak
        return
    t -= r.t2
    if t >= r.t3:
        d[0] = r.d1 + r.d2 + r.d3
        v[0] = r.v_out
        return
    d[0] = r.d1 + r.d2 + ramp_distance_at(r.v_peak, r.v_out, r.a3, r.ramp, t)
    v[0] = ramp_speed_at(r.v_peak, r.v_out, r.a3, r.ramp, t)


cdef inline Entry *motion_entry(Motion *m, size_t k) noexcept nogil:
    """The k-th entry from the current one."""
    return &m.ring[(m.head + k) % LOOK_RING]


cdef inline double _cap(const Motion *m, const Entry *e) noexcept nogil:
    """The entry's speed cap under the override (when it only acts on the feed)."""
    if m.ovr_timing or (e.rapid and m.ovr_off_in_rapids):
        return e.vmax
    return e.vmax * m.ovr


cdef double _exit_limit(Motion *m) noexcept nogil:
    """The highest speed the current entry may end with: what every entry the
    look-ahead sees after it can still brake from (to rest at the window's end, the
    ring's end, a stop, a breakpoint, a waiting M function), and its own junction
    speed. Sets window_short when the ring's end, not the window, limited it."""
    cdef Entry *cur = motion_entry(m, 0)
    cdef Entry *e
    cdef size_t k, last = m.count
    cdef double v2 = 0.0, dec, length, cap
    if m.stopping:
        last = m.stop_entry + 1
    m.window_short = False
    # the visible entries: those whose part is inside the window (backward: the same count)
    k = 1
    while k < last:
        e = motion_entry(m, k)
        if e.s_to >= e.s_from and e.part >= cur.part + m.window:
            break
        if k >= m.window:
            break
        k += 1
    if k == m.count and not m.complete and not m.stopping:
        m.window_short = True
    last = k
    # backward over them: v2 is the squared speed allowed at the start of entry k
    while k > 1:
        k -= 1
        e = motion_entry(m, k)
        length = entry_length(e)
        if m.stopping and k == m.stop_entry:
            length = m.stop_d
        if e.kind == PART_MOTION:
            dec = m.stop_dec if m.stopping else e.dec
            cap = _cap(m, e)
            v2 = min(v2 + 2.0 * _eq(dec, e.ramp if not m.stopping else m.stop_ramp) * length, cap * cap)
        elif e.waits or e.m0:
            v2 = 0.0
        if e.break_before:
            v2 = 0.0
        # the junction before it
        e = motion_entry(m, k - 1)
        if e.kind == PART_MOTION:
            v2 = min(v2, e.exit_cap * e.exit_cap)
    if m.stopping and m.stop_entry == 0:
        return 0.0
    return min(sqrt(v2), cur.exit_cap)


cdef void _plan_current(Motion *m) noexcept nogil:
    """Plans the current motion entry again from where the machine is."""
    cdef Entry *e = motion_entry(m, 0)
    cdef double length = entry_length(e)
    cdef double dec = e.dec
    cdef int32_t ramp = e.ramp
    if m.stopping and m.stop_entry == 0:
        length = m.stop_d
        dec = m.stop_dec
        ramp = m.stop_ramp
    elif m.stopping:
        dec = m.stop_dec
        ramp = m.stop_ramp
    run_plan(&m.run, length - m.d if length > m.d else 0.0, m.v, _cap(m, e), _exit_limit(m),
             e.acc, dec, ramp)
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
    m.started = False
    m.wait_left = 0.0
    m.confirmed = 0
    m.stopping = False
    m.ovr = 1.0
    m.ovr_target = 1.0
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
        if e.kind == PART_MOTION:
            m.state = MS_RUNNING
            if m.replan:
                _plan_current(m)
            return events
        if m.stopping and (e.waits or e.m0 or e.kind == PART_DWELL):
            m.stopping = False          # it stands here anyway: the stop ends here
            m.state = MS_STOPPED
            m.v = 0.0
            return events | ME_HALT
        if e.kind == PART_PRINT:
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
    cdef double step = m.ovr_inc * dt / (STEP_US * 1e-6)
    cdef double target = m.ovr_target
    cdef Entry *e
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


cdef inline bint motion_window_full(const Motion *m) noexcept nogil:
    """The ring holds the whole window after the current entry (or the run's end)."""
    return m.complete or m.count > m.window


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
        total = run_time_total(&m.run)
        before = m.d
        if m.run_t + tau < total:
            m.run_t += tau
            run_at(&m.run, m.run_t, &d, &v)
            m.d = m.run_d0 + d
            m.v = v
            tau = 0.0
        else:
            tau -= total - m.run_t
            m.d = m.run_d0 + m.run.d1 + m.run.d2 + m.run.d3
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
