# The host's callbacks of a core. Every call is counted while it runs (in_flight,
# under core.lock; and per thread, for calls nested in a callback), so that
# SetCallBack can return only once no call of the slot runs on another thread: a
# host may free its function as soon as it has removed it (SetCallBack made inside a
# callback does not wait). A worker looks a callback up at each call, never caching it
# across calls. Text arguments reach the host in its text type (TGM_LPCTSTR: UTF-16 on
# Windows), converted for the call (text_to_host).
from libc.string cimport memset
from libc.stdio cimport snprintf
from libc.stdlib cimport free

cdef extern from *:
    """
    /* The core whose worker runs on this thread (NULL on the host's threads), and how
       many callback calls this thread is inside of. */
    static __thread void *tc_worker_core = 0;
    static __thread int tc_in_callbacks = 0;
    """
    int tc_in_callbacks


cdef void worker_thread_mark(Core *core) noexcept nogil:
    """Marks the calling thread as `core`'s worker (NULL: no longer)."""
    global tc_worker_core
    tc_worker_core = core


cdef int32_t callback_slot(uint32_t number) noexcept nogil:
    """The slot of a documented callback number, -1 for any other number."""
    if number == CB_ADD_OUTPUT_LOG: return SLOT_ADD_OUTPUT_LOG
    if number == CB_SET_STATUS_BAR_TEXT: return SLOT_SET_STATUS_BAR_TEXT
    if number == CB_IS_DEBUG_MODE: return SLOT_IS_DEBUG_MODE
    if number == CB_IS_VERBOSE_MODE: return SLOT_IS_VERBOSE_MODE
    if number == CB_GET_LIB_PATH: return SLOT_GET_LIB_PATH
    if number == CB_GET_TOOL_PATH: return SLOT_GET_TOOL_PATH
    if number == CB_GET_SYSTEM_PATH: return SLOT_GET_SYSTEM_PATH
    if number == CB_GET_FILE_TIME_STAMP: return SLOT_GET_FILE_TIME_STAMP
    if number == CB_DO_YIELD: return SLOT_DO_YIELD
    if number == CB_READ_INI_STRING: return SLOT_READ_INI_STRING
    if number == CB_READ_INI_DOUBLE: return SLOT_READ_INI_DOUBLE
    if number == CB_READ_INI_INT: return SLOT_READ_INI_INT
    if number == CB_IS_BREAKPOINT: return SLOT_IS_BREAKPOINT
    if number == CB_DISP_AND_LOCATE_ERROR: return SLOT_DISP_AND_LOCATE_ERROR
    if number == CB_ADD_OUTPUT_LOG_WITH_MSG_BOX: return SLOT_ADD_OUTPUT_LOG_WITH_MSG_BOX
    if number == CB_SET_STATUS_BAR_PROGRESS: return SLOT_SET_STATUS_BAR_PROGRESS
    if number == CB_DRIVER_INITIALIZE: return SLOT_DRIVER_INITIALIZE
    if number == CB_DRIVER_G_FUNC: return SLOT_DRIVER_G_FUNC
    if number == CB_DRIVER_M_FUNC: return SLOT_DRIVER_M_FUNC
    if number == CB_CONNECT_POINT_CALC_START: return SLOT_CONNECT_POINT_CALC_START
    if number == CB_CONNECT_POINT_CALC: return SLOT_CONNECT_POINT_CALC
    if number == CB_CONNECT_POINT_CALC_END: return SLOT_CONNECT_POINT_CALC_END
    if number == CB_DRIVER_END: return SLOT_DRIVER_END
    if number == CB_MATH_WARNING: return SLOT_MATH_WARNING
    return -1


cdef bint callback_enter(Core *core, int32_t slot, Callback *cb) noexcept nogil:
    """The callback of `slot` for one call (False when none is set); the call must be
    closed with callback_leave."""
    global tc_in_callbacks
    pthread_mutex_lock(&core.lock)
    cb[0] = core.callbacks[slot]
    if cb.fn != NULL:
        core.in_flight[slot] += 1
    pthread_mutex_unlock(&core.lock)
    if cb.fn == NULL:
        return False
    tc_in_callbacks += 1
    return True


cdef void callback_leave(Core *core, int32_t slot) noexcept nogil:
    """Closes a call callback_enter opened: one call fewer in flight on the slot (SetCallBack
    waits for none before it returns) and on this thread."""
    global tc_in_callbacks
    tc_in_callbacks -= 1
    pthread_mutex_lock(&core.lock)
    core.in_flight[slot] -= 1
    if core.in_flight[slot] == 0:
        pthread_cond_broadcast(&core.changed)
    pthread_mutex_unlock(&core.lock)


cdef void callback_set(Core *core, int32_t slot, void *fn, intptr_t user) noexcept nogil:
    """SetCallBack: the new function is used by every later call; returns once the
    calls of the old one on other threads have returned. Made from inside a callback
    it does not wait: two callbacks that each replace the other's function would
    wait for each other for ever."""
    pthread_mutex_lock(&core.lock)
    core.callbacks[slot].fn = fn
    core.callbacks[slot].user = user if fn != NULL else 0
    while tc_in_callbacks == 0 and core.in_flight[slot] > 0:
        pthread_cond_wait(&core.changed, &core.lock)
    pthread_mutex_unlock(&core.lock)


cdef void fill_callback_info(const ErrorInfo *err, CALLBACK_INFO *info) noexcept nogil:
    """The CALLBACK_INFO of an error: number, lines, line, file index, and its texts (err's own:
    valid while err is)."""
    info.stringId = err.number
    info.nLines = err.n_lines
    info.actLine = err.line
    info.fileIdx = err.file_idx
    info.m_fullError = <const char *>err.text
    info.m_errorArguments = <const char *>err.args


cdef void core_output(Core *core, uint32_t tab, const char *text) noexcept nogil:
    """A line for the host's output log (AddOutputLog), e.g. PRINT text on tab 2."""
    cdef Callback cb
    cdef CALLBACK_INFO info
    cdef void *owned
    memset(&info, 0, sizeof(info))
    info.stringId = -1
    info.fileIdx = -1
    if callback_enter(core, SLOT_ADD_OUTPUT_LOG, &cb):
        (<TC_AddOutputLog>cb.fn)(cb.user, tab, text_to_host(text, &owned), &info)
        free(owned)
        callback_leave(core, SLOT_ADD_OUTPUT_LOG)
    log_line(LOG_TOOLCHAIN, text)


cdef void _one_line(char *out, size_t cap, const char *text) noexcept nogil:
    """text into out (cap bytes, truncated, terminated), a line break as "; ": a log line
    stays one line (the vendor's error 400 has three)."""
    cdef size_t n = 0
    while text[0] != 0 and n + 1 < cap:
        if text[0] == b'\n':
            if n + 2 >= cap:
                break
            out[n] = b';'
            out[n + 1] = b' '
            n += 2
        else:
            out[n] = text[0]
            n += 1
        text += 1
    out[n] = 0


cdef void core_report_error(Core *core, const ErrorInfo *err) noexcept nogil:
    """Every error reaches the host at once: DispAndLocateError, AddOutputLog tab 0
    and the log. `err` must stay valid during the calls (a copy of the caller's)."""
    cdef Callback cb
    cdef CALLBACK_INFO info
    cdef char line[1400]
    cdef int n
    cdef void *owned
    cdef char *narrow_text = narrow_to_host(err.text)
    cdef char *narrow_args = narrow_to_host(err.args)
    fill_callback_info(err, &info)
    if narrow_text != NULL:
        info.m_fullError = narrow_text
    if narrow_args != NULL:
        info.m_errorArguments = narrow_args
    if callback_enter(core, SLOT_DISP_AND_LOCATE_ERROR, &cb):
        (<TC_DispAndLocateError>cb.fn)(cb.user, <uint32_t>err.line, err.file_idx, text_to_host(err.text, &owned), &info)
        free(owned)
        callback_leave(core, SLOT_DISP_AND_LOCATE_ERROR)
    if callback_enter(core, SLOT_ADD_OUTPUT_LOG, &cb):
        (<TC_AddOutputLog>cb.fn)(cb.user, 0, text_to_host(err.text, &owned), &info)
        free(owned)
        callback_leave(core, SLOT_ADD_OUTPUT_LOG)
    free(narrow_text)
    free(narrow_args)
    n = snprintf(line, sizeof(line), "core %d: error %d at file %d line %d: ",
                 core.index, err.number, err.file_idx, err.line)
    _one_line(line + n, sizeof(line) - n, err.text)
    log_line(LOG_TOOLCHAIN, line)


cdef void core_progress(Core *core, uint32_t percent) noexcept nogil:
    """SetStatusBarProgress (32): the percent done of a compilation or a simulation, when the
    host set it."""
    cdef Callback cb
    if callback_enter(core, SLOT_SET_STATUS_BAR_PROGRESS, &cb):
        (<TC_SetStatusBarProgress>cb.fn)(cb.user, percent)
        callback_leave(core, SLOT_SET_STATUS_BAR_PROGRESS)


cdef void core_status_text(Core *core, const char *text, int32_t file_idx, int32_t n_lines) noexcept nogil:
    """SetStatusBarText (2): a status text on pane 0 in the host's text, with the file and
    number of lines, when the host set it."""
    cdef Callback cb
    cdef CALLBACK_INFO info
    cdef void *owned
    memset(&info, 0, sizeof(info))
    info.stringId = -1
    info.fileIdx = file_idx
    info.nLines = n_lines
    if callback_enter(core, SLOT_SET_STATUS_BAR_TEXT, &cb):
        (<TC_SetStatusBarText>cb.fn)(cb.user, 0, text_to_host(text, &owned), &info)
        free(owned)
        callback_leave(core, SLOT_SET_STATUS_BAR_TEXT)


cdef void core_warning(Core *core, const ErrorInfo *warning) noexcept nogil:
    """A numbered warning of a stage (e.g. the compensation) to MathWarning (2001)."""
    cdef Callback cb
    cdef CALLBACK_INFO info
    cdef char *narrow_text
    cdef char *narrow_args
    if callback_enter(core, SLOT_MATH_WARNING, &cb):
        fill_callback_info(warning, &info)
        narrow_text = narrow_to_host(warning.text)
        narrow_args = narrow_to_host(warning.args)
        if narrow_text != NULL:
            info.m_fullError = narrow_text
        if narrow_args != NULL:
            info.m_errorArguments = narrow_args
        (<TC_MathWarning>cb.fn)(cb.user, &info)
        free(narrow_text)
        free(narrow_args)
        callback_leave(core, SLOT_MATH_WARNING)
