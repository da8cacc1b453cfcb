# The offline machine's time. The pacer (machine.pyx) runs the machine's 100 us
# steps as the wall clock (the platform's monotonic clock) times the core's time
# scale calls for -- or, in tests only, as a stepped clock grants them:
# ToolChainCore_TestClock (behind a key no host passes by accident) puts a core's
# machine on a clock only that function advances, and returns once the steps it
# granted have run, GetPos shows them and the driver callbacks they caused have
# returned. The stepper, the pacer and the notifier meet under Machine.lock; nothing
# here runs while the wall clock paces the machine but one atomic load per tick.


cdef inline double clock_now() noexcept nogil:
    """Seconds of the monotonic clock."""
    return tc_monotonic_seconds()


cdef inline bint clock_stepped(Core *core) noexcept nogil:
    """Whether the core's machine runs on the test-only stepped clock."""
    return TC_ATOMIC_LOAD(&core.clock_stepped) != 0


cdef double clock_take(Core *core, Machine *m, double *last) noexcept nogil:
    """The machine time (seconds) the pacer may run now: the wall time since `last`
    (updated) times the time scale, or the steps the stepped clock granted."""
    cdef double now, seconds
    cdef uint64_t steps
    if not clock_stepped(core):
        now = clock_now()
        seconds = (now - last[0]) * TC_ATOMIC_LOAD_D(&core.time_scale)
        last[0] = now
        return seconds
    pthread_mutex_lock(&m.lock)
    steps = m.granted
    m.granted = 0
    if steps > 0:
        m.pacer_state = PACER_BUSY
    pthread_mutex_unlock(&m.lock)
    last[0] = clock_now()
    # a whole number of steps: a margin far below one step keeps the last from rounding away
    return steps * (STEP_US * SECONDS_PER_US) + STEP_MARGIN_S if steps > 0 else 0.0


cdef void clock_pause(Core *core, Machine *m, double *budget, bint handed_over) noexcept nogil:
    """Between two ticks of the pacer, `budget` the machine time it has left,
    `handed_over`: the notifier has all its step's log. The wall clock: a
    millisecond's sleep (the budget carries over). The stepped clock: when the pacer
    ran what it was granted (less than a step left; also when it stands at a waiting
    M function, which drops its budget) and handed it all over, the stepper is told
    and the pacer waits for the next grant (a millisecond at most: a stop, an end or
    a confirmation may come meanwhile); otherwise it waits a moment for the feeder or
    the notifier."""
    if not clock_stepped(core):
        tc_sleep_seconds(0.001)
        return
    if budget[0] >= STEP_US * SECONDS_PER_US or not handed_over:
        tc_sleep_seconds(0.00005)
        return
    budget[0] = 0.0
    pthread_mutex_lock(&m.lock)
    if m.granted == 0:
        m.pacer_state = PACER_IDLE
        pthread_cond_broadcast(&m.wake)
        tc_cond_wait_seconds(&m.wake, &m.lock, 0.001)
    pthread_mutex_unlock(&m.lock)


cdef void clock_pacer_begins(Machine *m) noexcept nogil:
    """_pace, before it starts the pacer: nothing granted yet (a grant is for one pacer)."""
    pthread_mutex_lock(&m.lock)
    m.granted = 0
    m.pacer_state = PACER_BUSY
    m.pacer_runs += 1
    pthread_mutex_unlock(&m.lock)


cdef void clock_pacer_ends(Machine *m) noexcept nogil:
    """The pacer's last step: no pacer to grant steps to."""
    pthread_mutex_lock(&m.lock)
    m.granted = 0
    m.pacer_state = PACER_NONE
    pthread_cond_broadcast(&m.wake)
    pthread_mutex_unlock(&m.lock)


cdef bint _settled(Core *core, Machine *m, uint64_t run) noexcept nogil:
    """With m.lock held: the stepper may return -- the pacer of `run` ran its grant and
    idles, or stands, with every event delivered; or it ended and the worker finished
    the activity (or went on to the next pacer)."""
    if m.pacer_runs != run:
        return True
    if m.pacer_state == PACER_NONE:
        return not machine_moving(core_status(core))
    return m.granted == 0 and m.pacer_state == PACER_IDLE and m.ev_n == 0 and not m.notifying


cdef int32_t machine_test_clock(Core *core, uint64_t key, double seconds) noexcept nogil:
    """ToolChainCore_TestClock (test-only): the stepped clock on (seconds >= 0) and
    `seconds` of machine time run, or back to the wall clock (seconds < 0)."""
    cdef Machine *m
    cdef uint64_t run
    if key != TC_TEST_CLOCK_KEY or seconds != seconds or tc_worker_core != NULL:
        return TOOL_CHAIN_ERROR
    TC_ATOMIC_STORE(&core.clock_stepped, 1 if seconds >= 0.0 else 0)
    pthread_mutex_lock(&core.lock)
    m = core.offline                    # never freed once made; none: nothing moves yet
    pthread_mutex_unlock(&core.lock)
    if m == NULL:
        return TOOL_CHAIN_SUCCESS
    pthread_mutex_lock(&m.lock)
    pthread_cond_broadcast(&m.wake)
    if seconds > 0.0:
        # a run that is starting: its pacer comes
        while (m.pacer_state == PACER_NONE and machine_moving(core_status(core))
               and not TC_ATOMIC_LOAD(&core.cancel)):
            tc_cond_wait_seconds(&m.wake, &m.lock, 0.001)
        if m.pacer_state != PACER_NONE:
            run = m.pacer_runs
            m.granted += <uint64_t>(seconds / (STEP_US * SECONDS_PER_US) + 0.5)
            pthread_cond_broadcast(&m.wake)
            while not _settled(core, m, run):
                tc_cond_wait_seconds(&m.wake, &m.lock, 0.001)
    pthread_mutex_unlock(&m.lock)
    return TOOL_CHAIN_SUCCESS
