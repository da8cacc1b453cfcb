# The offline machine's output stage: what its drives are sent, step by step.
#
#   interpolator (motion_step) -> spline -> IIR filter -> axis corrections -> drives
#
# Each activity takes the core's smoothing and a reference to its axis correction
# tables (output_configure); each pacer runs the filters standing at the motion's
# start (output_start .. output_stop). With both filters off a step is the
# interpolator's step and one branch; the corrections are memoryless and applied
# where a position is shown (output_view), so they cost nothing per step.
#
# The spline delays the output by its buffer of N steps on every axis: the motion's
# events (a part begins, an M function, a PRINT) wait here N steps too, so the driver
# hears of an M function when the output reaches it. The IIR filter's delay depends
# on the motion and is not known ahead: events are not delayed for it, but the
# machine halts only once the filtered output has settled (smoother_settled).
# docs/machine.md ("The output stage") says what GetPos shows of each position.
from libc.stdlib cimport free
from libc.string cimport memcpy, memmove


cdef void output_configure(Output *o, Core *core) noexcept nogil:
    """With core.lock held, as an activity begins: the core's smoothing and a
    reference to its axis correction tables (the previous activity's released)."""
    cdef AxisCorrections *old = o.tables
    o.config = core.smoothing
    o.tables = axis_corrections_ref(core.axis_corrections)
    axis_corrections_release(old)


cdef void output_start(Output *o, Core *core, const double *start) noexcept nogil:
    """The filters standing at `start` since ever, no event waiting. Out of memory
    for the spline's buffer: the run goes unfiltered, error 4 kept."""
    cdef uint32_t iir_axes = <uint32_t>o.config.iir[3] & 0x3FF
    output_stop(o)
    memcpy(o.smoothed, start, sizeof(o.smoothed))
    o.steps = 0
    o.delay = 0
    if o.config.spline[0] == 0.0 and iir_axes == 0:
        return
    if not smoother_init(&o.smoother, &o.config, STEP_US * SECONDS_PER_US, start):
        core_keep_error(core, False, NULL)
        return
    o.filtering = True
    o.delay = <uint64_t>o.smoother.span


cdef void output_stop(Output *o) noexcept nogil:
    """The pacer ended: the filters' state and the events still waiting dropped (a
    run that halted has none; ResetCNC and DestroyCNC drop them)."""
    if o.filtering:
        smoother_free(&o.smoother)
    o.filtering = False
    free(o.events)
    o.events = NULL
    o.first = o.n = o.cap = 0


cdef void output_forget(Output *o) noexcept nogil:
    """With core.lock held and no activity (ResetCNC, DestroyCNC, a new program): no
    filter state, no reference to the tables."""
    output_stop(o)
    axis_corrections_release(o.tables)
    o.tables = NULL


cdef void _delay_events(Output *o, Motion *mo, int32_t logged) noexcept nogil:
    """The events the motion logged this step (mo.log[logged:]) wait `delay` steps;
    those due now go back to the log, as far as it has room (the pacer hands a
    full log to the notifier before it steps again). Out of memory an event stays
    in the log: it is told undelayed."""
    cdef int32_t k = logged, kept
    cdef OutputEvent *e
    while k < mo.n_log:
        if o.first + o.n == o.cap and o.first > 0:
            memmove(o.events, o.events + o.first, o.n * sizeof(OutputEvent))
            o.first = 0
        if not grow(<void **>&o.events, &o.cap, o.first + o.n + 1, sizeof(OutputEvent)):
            break
        e = &o.events[o.first + o.n]
        e.due = o.steps + o.delay
        e.kind = mo.log_kind[k]
        e.part = mo.log_part[k]
        o.n += 1
        k += 1
    kept = mo.n_log - k
    memmove(mo.log_kind + logged, mo.log_kind + k, kept * sizeof(int32_t))
    memmove(mo.log_part + logged, mo.log_part + k, kept * sizeof(size_t))
    mo.n_log = logged + kept
    while o.n > 0 and o.events[o.first].due <= o.steps and mo.n_log <= LOG_SIZE - 8:
        mo.log_kind[mo.n_log] = o.events[o.first].kind
        mo.log_part[mo.n_log] = o.events[o.first].part
        mo.n_log += 1
        o.first += 1
        o.n -= 1
    if o.n == 0:
        o.first = 0


cdef void output_step(Output *o, Motion *mo, double dt) noexcept nogil:
    """One step of the machine: the interpolator's (unless it has halted: the output
    may still be settling), then its position through the filters and its events
    through the spline's delay."""
    cdef int32_t logged = mo.n_log
    if mo.state < MS_STOPPED:
        motion_step(mo, dt)
    if not o.filtering:
        return
    motion_locate(mo)      # the position of every step, not only of the tick's last
    smoother_push(&o.smoother, mo.position, o.smoothed)
    o.steps += 1
    if o.delay > 0:
        _delay_events(o, mo, logged)


cdef bint output_settled(const Output *o) noexcept nogil:
    """The output stands where the interpolator stands (the filters' predicate,
    TC_SETTLED_MM) and no event waits for it."""
    return not o.filtering or (o.n == 0 and smoother_settled(&o.smoother))


cdef bint output_halted(const Output *o, const Motion *mo) noexcept nogil:
    """The machine halted: the interpolator stopped, paused at M0 or ended, and the
    output has settled there."""
    return mo.state >= MS_STOPPED and output_settled(o)


cdef void output_view(const Output *o, const Motion *mo, Standing *s) noexcept nogil:
    """GetPos's positions: m_s = m_e the interpolator's (commanded), m_calcS after
    the spline and the IIR filter (where the machine is), m_calcE that with the axis
    corrections (what the drives are sent)."""
    memcpy(&s.part.m_s, mo.position, sizeof(P10DOUBLE))
    s.part.m_e = s.part.m_s
    if o.filtering:
        memcpy(s.output, o.smoothed, sizeof(s.output))
    else:
        memcpy(s.output, mo.position, sizeof(s.output))
    axis_correction_apply(o.tables, s.output, s.drives)
