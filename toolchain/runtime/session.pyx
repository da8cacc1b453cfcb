# A run's driver session: what the host's driver hears of a run, and what GetPos
# shows of it -- written once for the simulation (regimes 10, 20) and the offline
# machine (30-33, and the connections that run it). The order of the calls:
#
#   DriverInitialize -> addCode's M functions -> every part as it begins (DriverGFunc,
#   DriverMFunc, PRINT on AddOutputLog) -> after a stop: StopCNCEx's M functions ->
#   DriverEnd
#
# The M-function handshake: DriverMFunc answers a waiting M function 0 (done) or
# TC_MFUNC_LATER; later holds the machine at it until ToolChainCore_ConfirmMFunc (a
# simulation does not wait). A stop answers a handshake that waits (the M function
# stays sent: the next run goes on after it), the end of the activity drops it, and
# the next activity begins without one. The core keeps the handshake's state
# (core.pxd: m_waiting, m_answered) so that ConfirmMFunc reaches it from any thread.
from libc.string cimport memset, memcpy
from libc.stdlib cimport strtol, free


# ------------------------------------------------------------------ the calls

cdef void session_open(Session *s, Core *core, int32_t regime, bint holds) noexcept nogil:
    """A session of a run in `regime`; `holds`: waiting M functions hold it until
    they are confirmed (the machine)."""
    s.core = core
    s.regime = regime
    s.holds = holds
    s.signalled_m = <size_t>-1


cdef void session_begin(Session *s, const double *start) noexcept nogil:
    """DriverInitialize: the start position (ten axes) and the regime."""
    cdef Callback cb
    if callback_enter(s.core, SLOT_DRIVER_INITIALIZE, &cb):
        (<TC_DriverInitialize>cb.fn)(cb.user, <double *>start, AXES, s.regime)
        callback_leave(s.core, SLOT_DRIVER_INITIALIZE)


cdef void session_end(Session *s) noexcept nogil:
    """DriverEnd, the last call of a run."""
    cdef Callback cb
    if callback_enter(s.core, SLOT_DRIVER_END, &cb):
        (<TC_DriverEnd>cb.fn)(cb.user)
        callback_leave(s.core, SLOT_DRIVER_END)


cdef int32_t session_part(Session *s, const Program *prog, size_t i, const SIMPLE_GM_PARAMS *gm) noexcept nogil:
    """Part i as the driver gets it when it begins (gm: its placed view): a move or a
    dwell to DriverGFunc, an M function to DriverMFunc (a waiting one starts the
    handshake), a PRINT to AddOutputLog tab 2. The callbacks are looked up now: a
    removed one is never called again. DriverMFunc's answer (0 for other parts)."""
    cdef const Part *p = &prog.parts[i]
    cdef Callback cb
    cdef int32_t answer = 0
    if p.kind == PART_PRINT:
        core_output(s.core, 2, prog.texts + p.extra)
    elif (p.kind == PART_MOTION and not (p.flags & FLAG_DROPPED)) or p.kind == PART_DWELL:
        if callback_enter(s.core, SLOT_DRIVER_G_FUNC, &cb):
            (<TC_DriverGFunc>cb.fn)(cb.user, gm)
            callback_leave(s.core, SLOT_DRIVER_G_FUNC)
    elif p.kind == PART_MFUNC:
        if callback_enter(s.core, SLOT_DRIVER_M_FUNC, &cb):
            answer = (<TC_DriverMFunc>cb.fn)(cb.user, gm)
            callback_leave(s.core, SLOT_DRIVER_M_FUNC)
        if m_function_waits(p.func, (p.flags & FLAG_CONTINUOUS_M) != 0):
            s.signalled_m = i
            _handshake(s, p.func, answer)
    return answer


cdef bint session_add_code(Session *s, const char *code, const double *position, int32_t status,
                           bint after_stop) noexcept nogil:
    """StartCNCEx's, StopCNCEx's (`after_stop`) or ConnectCNCEx_Plane's addCode: its M
    words to DriverMFunc in order, as M functions of the file __exec__ standing at
    `position`. `status` (70, 80, 90; 0: none) is the core's status while they are
    sent. A waiting one answered TC_MFUNC_LATER holds the session (when it holds)
    until ConfirmMFunc, a stop (after_stop: a further one) or the end of the activity.
    False when such a stop or an end came: the rest is not sent."""
    cdef SIMPLE_GM_PARAMS gm
    cdef Callback cb
    cdef char *end
    cdef long number
    cdef int32_t answer
    cdef uint32_t stops = <uint32_t>TC_ATOMIC_LOAD(&s.core.stop) if after_stop else 0
    if code == NULL:
        return True
    while code[0] != 0:
        if TC_ATOMIC_LOAD(&s.core.cancel) or <uint32_t>TC_ATOMIC_LOAD(&s.core.stop) != stops:
            return False
        if code[0] != b'M' and code[0] != b'm':
            code += 1
            continue
        number = strtol(code + 1, &end, 10)
        if end == code + 1:
            code += 1
            continue
        code = end
        if status != 0:
            core_set_status(s.core, status)
        _add_code_part(&gm, <int32_t>number, position)
        answer = 0
        if callback_enter(s.core, SLOT_DRIVER_M_FUNC, &cb):
            answer = (<TC_DriverMFunc>cb.fn)(cb.user, &gm)
            callback_leave(s.core, SLOT_DRIVER_M_FUNC)
        if m_function_waits(<int32_t>number, number >= 1001):
            _handshake(s, <int32_t>number, answer)
            if not _wait_answer(s, &gm, stops):
                return False
    return True


cdef void _add_code_part(SIMPLE_GM_PARAMS *gm, int32_t number, const double *position) noexcept nogil:
    """The SIMPLE_GM_PARAMS of addCode's M function `number`: its M cell alone set (the
    others INVALID_VALUE_F), file __exec__, standing at `position`."""
    cdef float *cells = <float *>&gm.m_pars
    cdef int k
    memset(gm, 0, sizeof(SIMPLE_GM_PARAMS))
    for k in range(26):
        cells[k] = INVALID_VALUE_F
    gm.m_func = number
    gm.m_pars.M = <float>number
    gm.m_fileIdx = TOOL_CHAIN_FILE_EXEC
    gm.m_fp = 1.0
    memcpy(&gm.m_s, position, sizeof(P10DOUBLE))
    gm.m_e = gm.m_s
    gm.m_calcS = gm.m_s
    gm.m_calcE = gm.m_s


cdef void session_keep_stop_code(Core *core, const char *code) noexcept nogil:
    """StopCNCEx's addCode, for the run to send once it stands."""
    cdef char *copy = tc_strdup(code)
    pthread_mutex_lock(&core.lock)
    free(core.stop_code)
    core.stop_code = copy
    pthread_mutex_unlock(&core.lock)


cdef char *session_take_stop_code(Core *core) noexcept nogil:
    """The run stands after a stop: StopCNCEx's addCode (NULL: none) for it to send
    and free."""
    cdef char *code
    pthread_mutex_lock(&core.lock)
    code = core.stop_code
    core.stop_code = NULL
    pthread_mutex_unlock(&core.lock)
    return code


# ------------------------------------------------------------------ the M-function handshake

cdef void _handshake(Session *s, int32_t m, int32_t answer) noexcept nogil:
    """A waiting M function was signalled: answered 0 it is done, TC_MFUNC_LATER it
    waits for ConfirmMFunc (in a session that holds)."""
    if not s.holds:
        return
    pthread_mutex_lock(&s.core.lock)
    if answer == TC_MFUNC_LATER:
        s.core.m_waiting = m
    else:
        TC_ATOMIC_STORE(&s.core.m_answered, 1)
    pthread_mutex_unlock(&s.core.lock)


cdef bint _wait_answer(Session *s, const SIMPLE_GM_PARAMS *gm, uint32_t stops) noexcept nogil:
    """An addCode M function answered TC_MFUNC_LATER: the session stands until it is
    confirmed (GetPos shows it), a stop answers it (a StopCNCEx after `stops`) or the
    activity ends. False unless confirmed."""
    cdef Core *core = s.core
    cdef Standing at
    cdef bint confirmed
    pthread_mutex_lock(&core.lock)
    if core.m_waiting == 0:
        TC_ATOMIC_STORE(&core.m_answered, 0)
        pthread_mutex_unlock(&core.lock)
        return not TC_ATOMIC_LOAD(&core.cancel)
    pthread_mutex_unlock(&core.lock)
    getpos_shown(&core.snap, &at)       # where the machine stands, at the M: m_func M + 10000, the M cell
    at.part.m_func = gm.m_func + 10000
    at.m_cell = gm.m_pars.M
    at.part.m_editorLine = 0
    at.part.m_fileIdx = TOOL_CHAIN_FILE_EXEC
    at.act_feed = 0.0
    getpos_publish(&core.snap, &at)
    pthread_mutex_lock(&core.lock)
    while (core.m_waiting != 0 and not TC_ATOMIC_LOAD(&core.cancel)
           and <uint32_t>TC_ATOMIC_LOAD(&core.stop) == stops):
        pthread_cond_wait(&core.changed, &core.lock)
    confirmed = core.m_waiting == 0 and not TC_ATOMIC_LOAD(&core.cancel)
    core.m_waiting = 0                  # a stop answered it, an end dropped it
    TC_ATOMIC_STORE(&core.m_answered, 0)
    pthread_mutex_unlock(&core.lock)
    return confirmed and <uint32_t>TC_ATOMIC_LOAD(&core.stop) == stops


cdef bint session_take_answer(Core *core) noexcept nogil:
    """The machine's step stands at a waiting M function: True (once) when it was
    answered (DriverMFunc's 0, or ConfirmMFunc)."""
    cdef int32_t answered = 1
    return TC_ATOMIC_LOAD(&core.m_answered) != 0 and TC_ATOMIC_CAS(&core.m_answered, &answered, 0)


cdef int32_t session_confirm(Core *core) noexcept nogil:
    """ToolChainCore_ConfirmMFunc: the M function that waits is done."""
    pthread_mutex_lock(&core.lock)
    if core.m_waiting == 0:
        pthread_mutex_unlock(&core.lock)
        err_no_m_pending(refusal(), -1, 0)
        return core_fail(core, refusal())
    core.m_waiting = 0
    if core_status(core) > 0:           # a running activity takes the answer
        TC_ATOMIC_STORE(&core.m_answered, 1)
    pthread_cond_broadcast(&core.changed)
    pthread_mutex_unlock(&core.lock)
    return TOOL_CHAIN_SUCCESS


cdef int32_t session_standing_m(Core *core, const SIMPLE_GM_PARAMS *fun) noexcept nogil:
    """ToolChainCore_MFunc: an M function to DriverMFunc while nothing runs, on the
    caller's thread; answered TC_MFUNC_LATER it waits for ConfirmMFunc (until then a
    second one is refused; an activity that begins drops it)."""
    cdef Callback cb
    cdef int32_t answer = 0
    cdef uint64_t activity
    pthread_mutex_lock(&core.lock)
    if core_status(core) > 0:
        pthread_mutex_unlock(&core.lock)
        return core_refuse(core, "MFunc", core_status(core))
    if core.m_waiting != 0:
        pthread_mutex_unlock(&core.lock)
        err_m_pending(refusal(), -1, 0)
        return core_fail(core, refusal())
    activity = core.activity
    pthread_mutex_unlock(&core.lock)
    if callback_enter(core, SLOT_DRIVER_M_FUNC, &cb):
        answer = (<TC_DriverMFunc>cb.fn)(cb.user, fun)
        callback_leave(core, SLOT_DRIVER_M_FUNC)
    if answer == TC_MFUNC_LATER:
        pthread_mutex_lock(&core.lock)
        if core.activity == activity and core_status(core) <= 0:
            core.m_waiting = fun.m_func if fun.m_func != 0 else -1
        pthread_mutex_unlock(&core.lock)
    return TOOL_CHAIN_SUCCESS


cdef void session_forget_locked(Core *core) noexcept nogil:
    """With core.lock held, as an activity begins or ends: no M function waits, no
    StopCNCEx addCode is kept."""
    core.m_waiting = 0
    TC_ATOMIC_STORE(&core.m_answered, 0)
    free(core.stop_code)
    core.stop_code = NULL


# ------------------------------------------------------------------ what GetPos shows

cdef void session_count(RunCounts *c, const Part *p) noexcept nogil:
    """Part p began: the GetPos counters of moves, rapids, their changes and M functions."""
    cdef int32_t now
    if p.kind == PART_MOTION:
        now = 1 if p.func == 0 else 2
        if now == 1:
            c.n_rapid += 1
            c.work_to_rapid += 1 if c.last_motion == 2 else 0
        else:
            c.n_work += 1
            c.rapid_to_work += 1 if c.last_motion == 1 else 0
        c.last_motion = now
    elif p.kind == PART_MFUNC:
        c.n_m += 1
