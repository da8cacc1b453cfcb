# One CNC core (interpolator channel): its configuration, its compiled program, its
# last error, its callbacks, and the worker thread that compiles or runs. The host's
# threads and the worker meet here:
#   - `status` and `cancel` are int32 read and written atomically (StatusCNC polls
#     status without any lock);
#   - `lock` guards everything else and is only held for short copies, never while
#     a callback runs or a thread is joined.
from libc.stdlib cimport malloc, calloc, free
from libc.string cimport memset, memcpy, strlen, strcmp, strncpy, strcasecmp
from libc.stdio cimport snprintf, FILE, fopen, fclose, fread, fseek, ftell, SEEK_END, SEEK_SET
from libc.stdlib cimport strtod, strtol, strtoul

cdef extern from "<pthread.h>" nogil:
    pthread_t pthread_self()
    int pthread_equal(pthread_t a, pthread_t b)

cdef extern from *:
    """
    #define TC_VERSION_STRING "SF_TCh 0.1.0 (open drop-in CNC module library, built " __DATE__ " " __TIME__ ")"
    """
    const char *TC_VERSION_STRING

cdef enum:
    MAX_FILES = 64          # file names per core (FileToIdx)
    N_CALLBACK_SLOTS = 24   # documented callback numbers

# the documented callback numbers, in slot order
cdef int32_t callback_slot(uint32_t number) noexcept nogil:
    if number == CB_ADD_OUTPUT_LOG: return 0
    if number == CB_SET_STATUS_BAR_TEXT: return 1
    if number == CB_IS_DEBUG_MODE: return 2
    if number == CB_IS_VERBOSE_MODE: return 3
    if number == CB_GET_LIB_PATH: return 4
    if number == CB_GET_TOOL_PATH: return 5
    if number == CB_GET_SYSTEM_PATH: return 6
    if number == CB_GET_FILE_TIME_STAMP: return 7
    if number == CB_DO_YIELD: return 8
    if number == CB_READ_INI_STRING: return 9
    if number == CB_READ_INI_DOUBLE: return 10
    if number == CB_READ_INI_INT: return 11
    if number == CB_IS_BREAKPOINT: return 12
    if number == CB_DISP_AND_LOCATE_ERROR: return 13
    if number == CB_ADD_OUTPUT_LOG_WITH_MSG_BOX: return 14
    if number == CB_SET_STATUS_BAR_PROGRESS: return 15
    if number == CB_DRIVER_INITIALIZE: return 16
    if number == CB_DRIVER_G_FUNC: return 17
    if number == CB_DRIVER_M_FUNC: return 18
    if number == CB_CONNECT_POINT_CALC_START: return 19
    if number == CB_CONNECT_POINT_CALC: return 20
    if number == CB_CONNECT_POINT_CALC_END: return 21
    if number == CB_DRIVER_END: return 22
    if number == CB_MATH_WARNING: return 23
    return -1

ctypedef struct Callback:
    void *fn
    intptr_t user

ctypedef struct Core:
    int32_t index
    int32_t status              # cnc_status, atomic
    int32_t cancel              # atomic: ask the worker to end (reset/destroy)
    int32_t stop                # atomic: StopCNCEx during a run
    pthread_mutex_t lock
    # worker thread
    pthread_t worker
    bint worker_started         # a thread was created and not yet joined
    int32_t run_regime
    char *add_code              # StartCNCEx addCode of the current run
    # configuration
    GCODE_PARAMETERS params
    MACHINE_PARAMETERS machine
    double user_params[100]
    bint has_user_params
    char *prefix
    char *postfix
    bint ini_loaded
    char driver[256]
    Callback callbacks[24]
    # files and run times
    char files[64][252]
    int32_t n_files
    double run_times[64]
    # compilation input (owned while the worker compiles)
    char *source
    size_t source_len
    int32_t source_idx
    char source_name[252]
    # result
    Program program
    bint has_program            # compiled without error
    ErrorInfo error             # last error (number 0 = none)
    GCODE_INFO size_info
    # machine
    double position[10]
    double rel_feed
    uint32_t breakpoint_line
    int32_t breakpoint_file
    # GetPos snapshot (written by the worker under lock)
    int32_t last_motion         # 0 none, 1 rapid, 2 cut: for the transition counters
    SIMPLE_GM_PARAMS pos
    GM_PARAMS_ENHANCED enh

cdef Core g_cores[3]
cdef pthread_once_t g_once
cdef int32_t g_core_mode           # Local_Core_Mode of ToolChainCore_Init (2 offline until Init)
cdef char g_macros_dir[1024]       # Macros_Dir of ToolChainCore_Init (external G functions: not used yet)


cdef void default_gcode_parameters(GCODE_PARAMETERS *p) noexcept nogil:
    """The documented defaults (ABI.md)."""
    cdef int i
    memset(p, 0, sizeof(GCODE_PARAMETERS))
    p.absMode = 1
    p.correctionStrategy = 0x600
    for i in range(8):
        p.motion[i].feed = 1000.0
        p.motion[i].acc = 500.0
        p.motion[i].dec = 500.0
        p.motion[i].rampType = 1
    p.motion[0].feed = 10000.0          # rapid
    p.motion[6].dec = 1000.0            # normal stop
    p.motion[7].dec = 5000.0            # emergency stop
    for i in range(8):
        p.correction[i].gCode = 41 + i
    p.maxConnectionDistance = 10.0
    p.startAngle = 360.0
    p.endAngle = 360.0
    p.overrideInc = 0.001
    p.M02_programEnd1 = 2
    p.M30_programEnd2 = 30
    p.M03_startSpindleCW = 3
    p.M04_startSpindleCCW = 4
    p.M05_stopSpindle = 5
    p.M06_changeTool = 6
    p.M07_coolOn = 7
    p.M08_oilOn = 8
    p.M09_coolOilOff = 9
    p.M17_return = 17
    p.M29_print = 29
    p.M80_mirrorOff = 80
    p.M81_mirrorX = 81
    p.M82_mirrorY = 82
    p.M83_mirrorZ = 83
    p.M84_mirrorXY = 84
    p.M85_mirrorXZ = 85
    p.M86_mirrorYZ = 86
    p.M87_mirrorXYZ = 87
    p.M99_defFeed = 99
    p.insertArcToleranceRMax = 0.03
    p.insertArcToleranceRMin = 0.03
    p.insertArcMaxAngle = 90.0
    p.tolerance[0] = 0.005
    p.tolerance[1] = 0.001
    p.tolerance[2] = 0.03
    p.tolerance[3] = 0.005
    p.tolerance[5] = 3.0
    p.tolerance[6] = 0.01


cdef void _init_cores() noexcept nogil:
    cdef int i
    cdef Core *core
    for i in range(TOOL_CHAIN_MAX_CORES):
        core = &g_cores[i]
        memset(core, 0, sizeof(Core))
        core.index = i
        pthread_mutex_init(&core.lock, NULL)
        default_gcode_parameters(&core.params)
        program_init(&core.program)
        core.rel_feed = 1.0
        core.source_idx = -1
        core.breakpoint_file = -1
        core.pos.m_fileIdx = -1
    g_core_mode = 2


cdef Core *core_get(uint32_t index) noexcept nogil:
    """The core, or NULL for an index that is not a core of this library."""
    pthread_once(&g_once, _init_cores)
    if index >= <uint32_t>TOOL_CHAIN_MAX_CORES:
        return NULL
    return &g_cores[index]


cdef inline int32_t core_status(Core *core) noexcept nogil:
    return TC_ATOMIC_LOAD(&core.status)


cdef inline void core_set_status(Core *core, int32_t status) noexcept nogil:
    TC_ATOMIC_STORE(&core.status, status)
    TC_ATOMIC_STORE(&core.enh.m_statusCNC, status)


cdef inline bint status_is_running(int32_t status) noexcept nogil:
    """Positive statuses: something works (compiling, running, moving)."""
    return status > 0


# ------------------------------------------------------------------ callbacks

cdef Callback core_callback(Core *core, uint32_t number) noexcept nogil:
    """A copy of the callback (fn NULL when unset); read under the lock so that a
    concurrent SetCallBack never tears the pair."""
    cdef Callback cb
    cdef int32_t slot = callback_slot(number)
    cb.fn = NULL
    cb.user = 0
    if slot < 0:
        return cb
    pthread_mutex_lock(&core.lock)
    cb = core.callbacks[slot]
    pthread_mutex_unlock(&core.lock)
    return cb


cdef void fill_callback_info(Core *core, const ErrorInfo *err, CALLBACK_INFO *info) noexcept nogil:
    info.stringId = err.number
    info.nLines = err.n_lines
    info.actLine = err.line
    info.fileIdx = err.file_idx
    info.m_fullError = err.text
    info.m_errorArguments = err.args


cdef void core_output(Core *core, uint32_t tab, const char *text) noexcept nogil:
    """A line for the host's output log (AddOutputLog), e.g. PRINT text on tab 2."""
    cdef Callback cb = core_callback(core, CB_ADD_OUTPUT_LOG)
    cdef CALLBACK_INFO info
    memset(&info, 0, sizeof(info))
    info.stringId = -1
    info.fileIdx = -1
    if cb.fn != NULL:
        (<TC_AddOutputLog>cb.fn)(cb.user, tab, text, &info)
    log_line(LOG_TOOLCHAIN, text)


cdef void core_report_error(Core *core, const ErrorInfo *err) noexcept nogil:
    """Every error reaches the host at once: DispAndLocateError, AddOutputLog tab 0
    and the log. The ErrorInfo must stay valid during the calls."""
    cdef Callback disp = core_callback(core, CB_DISP_AND_LOCATE_ERROR)
    cdef Callback out = core_callback(core, CB_ADD_OUTPUT_LOG)
    cdef CALLBACK_INFO info
    cdef char line[1400]
    fill_callback_info(core, err, &info)
    if disp.fn != NULL:
        (<TC_DispAndLocateError>disp.fn)(disp.user, <uint32_t>err.line, err.file_idx, err.text, &info)
    if out.fn != NULL:
        (<TC_AddOutputLog>out.fn)(out.user, 0, err.text, &info)
    snprintf(line, sizeof(line), "core %d: error %d at file %d line %d: %s",
             core.index, err.number, err.file_idx, err.line, err.text)
    log_line(LOG_TOOLCHAIN, line)


cdef void core_fail(Core *core, int32_t number, const char *text_arg) noexcept nogil:
    """Records and reports an error of the host's call (no file, no line)."""
    pthread_mutex_lock(&core.lock)
    set_error_text(&core.error, number, -1, 0, text_arg)
    pthread_mutex_unlock(&core.lock)
    core_report_error(core, &core.error)


cdef void core_progress(Core *core, uint32_t percent) noexcept nogil:
    cdef Callback cb = core_callback(core, CB_SET_STATUS_BAR_PROGRESS)
    if cb.fn != NULL:
        (<TC_SetStatusBarProgress>cb.fn)(cb.user, percent)


cdef void core_status_text(Core *core, const char *text) noexcept nogil:
    cdef Callback cb = core_callback(core, CB_SET_STATUS_BAR_TEXT)
    cdef CALLBACK_INFO info
    memset(&info, 0, sizeof(info))
    info.stringId = -1
    info.fileIdx = core.source_idx
    info.nLines = <int32_t>core.program.n_lines
    if cb.fn != NULL:
        (<TC_SetStatusBarText>cb.fn)(cb.user, 0, text, &info)


# ------------------------------------------------------------------ files

cdef int32_t core_file_to_idx(Core *core, const char *name) noexcept nogil:
    """FileToIdx under the core's lock."""
    cdef int32_t i, found = -1
    if name == NULL or name[0] == 0 or strlen(name) >= <size_t>TOOL_CHAIN_MAX_FILE_NAME:
        return -1
    if strcmp(name, "__unknown__") == 0: return -1
    if strcmp(name, "__end__") == 0: return -2
    if strcmp(name, "__stop__") == 0: return -3
    if strcmp(name, "__exec__") == 0: return -4
    pthread_mutex_lock(&core.lock)
    for i in range(core.n_files):
        if strcmp(core.files[i], name) == 0:
            found = i
            break
    if found < 0 and core.n_files < MAX_FILES:
        found = core.n_files
        strncpy(core.files[found], name, TOOL_CHAIN_MAX_FILE_NAME - 1)
        core.files[found][TOOL_CHAIN_MAX_FILE_NAME - 1] = 0
        core.run_times[found] = -1.0
        core.n_files += 1
    pthread_mutex_unlock(&core.lock)
    return found


cdef const char *core_idx_to_file(Core *core, int32_t idx) noexcept nogil:
    if idx == -2: return "__end__"
    if idx == -3: return "__stop__"
    if idx == -4: return "__exec__"
    if idx < 0 or idx >= core.n_files:
        return "__unknown__"
    return core.files[idx]


# ------------------------------------------------------------------ worker thread

cdef void core_end_activity(Core *core) noexcept nogil:
    """Interrupts a compilation or a run: asks the worker to end and waits for it
    (never from the worker itself, which only gets the request: it is calling back
    into the host)."""
    cdef pthread_t worker
    pthread_mutex_lock(&core.lock)
    if not core.worker_started:
        pthread_mutex_unlock(&core.lock)
        return
    worker = core.worker
    if pthread_equal(worker, pthread_self()):
        pthread_mutex_unlock(&core.lock)
        TC_ATOMIC_STORE(&core.cancel, 1)
        return
    core.worker_started = False
    pthread_mutex_unlock(&core.lock)
    TC_ATOMIC_STORE(&core.cancel, 1)
    pthread_join(worker, NULL)
    TC_ATOMIC_STORE(&core.cancel, 0)


cdef bint core_claim(Core *core, int32_t running_status) noexcept nogil:
    """Moves an idle core to `running_status` atomically; False when it is busy.
    The previous (finished) worker is joined first."""
    cdef int32_t current
    while True:
        current = core_status(core)
        if status_is_running(current):
            return False
        if TC_ATOMIC_CAS(&core.status, &current, running_status):
            TC_ATOMIC_STORE(&core.enh.m_statusCNC, running_status)
            return True


cdef bint core_launch(Core *core, void *(*body)(void *) noexcept nogil) noexcept nogil:
    """Starts the worker for a claimed core; False (and the status restored by the
    caller) when no thread can be created."""
    cdef pthread_t old
    cdef bint had_old
    pthread_mutex_lock(&core.lock)
    had_old = core.worker_started
    old = core.worker
    core.worker_started = False
    pthread_mutex_unlock(&core.lock)
    if had_old and not pthread_equal(old, pthread_self()):
        pthread_join(old, NULL)         # finished already: the status was not running
    TC_ATOMIC_STORE(&core.cancel, 0)
    TC_ATOMIC_STORE(&core.stop, 0)
    pthread_mutex_lock(&core.lock)
    if pthread_create(&core.worker, NULL, body, core) != 0:
        pthread_mutex_unlock(&core.lock)
        return False
    core.worker_started = True
    pthread_mutex_unlock(&core.lock)
    return True


# ------------------------------------------------------------------ compilation

cdef void _compile_progress(void *ctx, int percent) noexcept nogil:
    core_progress(<Core *>ctx, <uint32_t>percent)


cdef void _compile_output(void *ctx, int tab, const char *text) noexcept nogil:
    core_output(<Core *>ctx, <uint32_t>tab, text)


cdef void _compile_warn(void *ctx, const ErrorInfo *warning) noexcept nogil:
    """A numbered warning of a stage (e.g. the compensation) to MathWarning (2001)."""
    cdef Callback cb = core_callback(<Core *>ctx, CB_MATH_WARNING)
    cdef CALLBACK_INFO info
    if cb.fn != NULL:
        fill_callback_info(<Core *>ctx, warning, &info)
        (<TC_MathWarning>cb.fn)(cb.user, &info)


cdef int _compile_and_compensate(Core *core, CompileInput *inp, Program *prog, ErrorInfo *err) noexcept nogil:
    """The compiler, and the compensation's pass beside it in a thread of its own
    (pipeline.pyx), then the compensation's merge: COMPILE_OK, or the compiler's
    failure, else the compensation's (err filled)."""
    cdef CompState comp
    cdef Follow follow
    cdef ErrorInfo *comp_err = <ErrorInfo *>calloc(1, sizeof(ErrorInfo))
    cdef int result
    if comp_err == NULL:
        set_error(err, ERR_OUT_OF_MEMORY, inp.file_idx, 0, NULL, 0)
        return COMPILE_ERROR
    compensate_begin(&comp, prog, &inp.params, comp_err, _compile_output, _compile_warn, core)
    follow_init(&follow, prog, compensate_feed, &comp)
    prog.follow = &follow
    result = compile_program(inp, prog, err)
    if result == COMPILE_OK and prog.compensated:
        follow_finish(&follow, prog.n_parts)        # the pass takes the rest and ends
    else:
        follow_abandon(&follow)
    prog.follow = NULL
    follow_destroy(&follow)
    if result == COMPILE_OK and prog.compensated:
        result = compensate_end(&comp)
        if result != COMPILE_OK:
            err[0] = comp_err[0]
    else:
        compensate_free(&comp)
    free(comp_err)
    return result


cdef void *_compile_body(void *arg) noexcept nogil:
    cdef Core *core = <Core *>arg
    cdef CompileInput *inp = <CompileInput *>calloc(1, sizeof(CompileInput))
    cdef Program prog
    cdef ErrorInfo *err = <ErrorInfo *>calloc(1, sizeof(ErrorInfo))
    cdef int result
    cdef int32_t read_error = 0
    cdef GCODE_INFO extent
    cdef char text[400]
    program_init(&prog)
    if core.source == NULL and inp != NULL and err != NULL:
        core.source = read_whole_file(core.source_name, &core.source_len, &read_error)
    if read_error != 0:
        result = COMPILE_ERROR
        set_error_text(err, read_error, core.source_idx, 0, core.source_name)
    elif inp == NULL or err == NULL:
        result = COMPILE_ERROR
        if err != NULL:
            set_error(err, ERR_OUT_OF_MEMORY, core.source_idx, 0, NULL, 0)
    else:
        pthread_mutex_lock(&core.lock)
        inp.text = core.source
        inp.length = core.source_len
        inp.file_idx = core.source_idx
        inp.prefix = core.prefix
        inp.postfix = core.postfix
        inp.params = core.params
        if core.has_user_params:
            memcpy(inp.user_params, core.user_params, sizeof(inp.user_params))
        memcpy(inp.start, core.position, sizeof(inp.start))
        pthread_mutex_unlock(&core.lock)
        inp.prefix_idx = core_file_to_idx(core, "__prefix__") if inp.prefix != NULL else -1
        inp.postfix_idx = core_file_to_idx(core, "__postfix__") if inp.postfix != NULL else -1
        inp.plc = TGM_Data
        inp.cancel = &core.cancel
        inp.progress = _compile_progress
        inp.output = _compile_output
        inp.ctx = core
        snprintf(text, sizeof(text), "Compiling %s", core.source_name)
        core_status_text(core, text)
        core_progress(core, 0)
        result = _compile_and_compensate(core, inp, &prog, err)
        if result == COMPILE_OK:
            result = insert_arcs(&prog, &inp.params, err)
        if result == COMPILE_OK and plan_program(&prog, &inp.params, <uint32_t>core.machine.enhancedInterpolatorParameters,
                                                 inp.plan_window) != COMPILE_OK:
            result = COMPILE_ERROR
            set_error(err, ERR_OUT_OF_MEMORY, core.source_idx, 0, NULL, 0)
        if result == COMPILE_CANCELLED:
            set_error(err, ERR_CANCELLED, core.source_idx, 0, NULL, 0)
    if result == COMPILE_OK:
        program_extent(&prog, &extent)      # before taking the lock: GetPos never waits for it
    pthread_mutex_lock(&core.lock)
    program_free(&core.program)
    memset(&core.size_info, 0, sizeof(GCODE_INFO))
    if result == COMPILE_OK:
        core.program = prog
        core.has_program = True
        core.size_info = extent
        memset(&core.error, 0, sizeof(ErrorInfo))
    else:
        err.n_lines = <int32_t>prog.n_lines     # lines of the main file, counted before compiling
        program_free(&prog)
        program_init(&core.program)
        core.has_program = False
        core.error = err[0]
    free(core.source)
    core.source = NULL
    core.source_len = 0
    pthread_mutex_unlock(&core.lock)
    if result == COMPILE_OK:
        snprintf(text, sizeof(text), "Compiled %s: %lu parts", core.source_name,
                 <unsigned long>core.program.n_parts)
        core_progress(core, 100)
        core_status_text(core, text)
        log_line(LOG_COMPILER, text)
    elif result != COMPILE_CANCELLED or TC_ATOMIC_LOAD(&core.cancel) == 0:
        core_report_error(core, &core.error)
    free(inp)
    free(err)
    core_set_status(core, CNC_STATUS_COMPILED)
    return NULL


cdef int32_t core_start_compile(Core *core, const char *name, char *source, size_t length) noexcept nogil:
    """Takes ownership of `source` and compiles it in the worker; -1 when busy.
    source NULL: the worker reads the file `name`."""
    cdef int32_t idx
    if not core_claim(core, CNC_STATUS_COMPILING):
        free(source)
        core_fail(core, ERR_BUSY, "compilation")
        return TOOL_CHAIN_ERROR
    idx = core_file_to_idx(core, name)
    pthread_mutex_lock(&core.lock)
    free(core.source)
    core.source = source
    core.source_len = length
    core.source_idx = idx
    strncpy(core.source_name, name, sizeof(core.source_name) - 1)
    core.source_name[sizeof(core.source_name) - 1] = 0
    memset(&core.error, 0, sizeof(ErrorInfo))
    core.has_program = False
    pthread_mutex_unlock(&core.lock)
    if not core_launch(core, _compile_body):
        pthread_mutex_lock(&core.lock)
        free(core.source)
        core.source = NULL
        pthread_mutex_unlock(&core.lock)
        core_set_status(core, CNC_STATUS_NOTHING_LOADED)
        core_fail(core, ERR_OUT_OF_MEMORY, NULL)
        return TOOL_CHAIN_ERROR
    return TOOL_CHAIN_SUCCESS


cdef enum:
    MAX_SOURCE_BYTES = 1 << 30      # 1 GiB: larger G-code files are refused


cdef char *read_whole_file(const char *path, size_t *length, int32_t *error) noexcept nogil:
    """The file's bytes, NUL-terminated (malloc'ed); NULL with *error set
    (ERR_FILE_OPEN, ERR_FILE_READ, ERR_FILE_TOO_LARGE, ERR_OUT_OF_MEMORY)."""
    cdef FILE *f = fopen(path, "rb")
    cdef long size
    cdef char *buf
    if f == NULL:
        error[0] = ERR_FILE_OPEN
        return NULL
    if fseek(f, 0, SEEK_END) != 0:
        fclose(f)
        error[0] = ERR_FILE_READ
        return NULL
    size = ftell(f)
    if size < 0 or fseek(f, 0, SEEK_SET) != 0:
        fclose(f)
        error[0] = ERR_FILE_READ
        return NULL
    if size > MAX_SOURCE_BYTES:
        fclose(f)
        error[0] = ERR_FILE_TOO_LARGE
        return NULL
    buf = <char *>malloc(<size_t>size + 1)
    if buf == NULL:
        fclose(f)
        error[0] = ERR_OUT_OF_MEMORY
        return NULL
    if fread(buf, 1, <size_t>size, f) != <size_t>size:
        free(buf)
        fclose(f)
        error[0] = ERR_FILE_READ
        return NULL
    fclose(f)
    buf[size] = 0
    length[0] = <size_t>size
    return buf


# ------------------------------------------------------------------ reset / destroy

cdef bint core_on_worker(Core *core) noexcept nogil:
    """True inside the worker thread (a callback calling back into the library)."""
    cdef bint inside
    pthread_mutex_lock(&core.lock)
    inside = core.worker_started and pthread_equal(core.worker, pthread_self())
    pthread_mutex_unlock(&core.lock)
    return inside


cdef void core_destroy(Core *core) noexcept nogil:
    if core_on_worker(core):
        # called from a callback: the worker still uses the program; ask it to end
        # and leave the memory to the next DestroyCNC from a host thread
        TC_ATOMIC_STORE(&core.cancel, 1)
        return
    core_end_activity(core)
    pthread_mutex_lock(&core.lock)
    program_free(&core.program)
    core.has_program = False
    free(core.source)
    core.source = NULL
    memset(&core.size_info, 0, sizeof(GCODE_INFO))
    memset(&core.pos, 0, sizeof(SIMPLE_GM_PARAMS))
    core.pos.m_fileIdx = -1
    memset(&core.enh, 0, sizeof(GM_PARAMS_ENHANCED))
    core.enh.m_relFeed = core.rel_feed
    pthread_mutex_unlock(&core.lock)
    core_set_status(core, CNC_STATUS_NOTHING_LOADED)


# ------------------------------------------------------------------ INI

cdef void _apply_ini(void *ctx, const char *section, const char *key, const char *value) noexcept nogil:
    cdef Core *core = <Core *>ctx
    if strcasecmp(section, "CNC") == 0 and strcasecmp(key, "Driver") == 0:
        strncpy(core.driver, value, sizeof(core.driver) - 1)
    elif strcasecmp(section, "GCodeParameters") == 0:
        gcode_parameter_from_ini(&core.params, key, value)


cdef bint gcode_parameter_from_ini(GCODE_PARAMETERS *p, const char *key, const char *value) noexcept nogil:
    """[GCodeParameters] key = value for the scalar fields of GCODE_PARAMETERS and
    the radii correction0..correction7; False for an unknown key (ignored)."""
    cdef double d = strtod(value, NULL)
    cdef long i = strtol(value, NULL, 0)
    if strcasecmp(key, "absMode") == 0: p.absMode = <int32_t>i
    elif strcasecmp(key, "swapG2G3") == 0: p.swapG2G3 = <int32_t>i
    elif strcasecmp(key, "correctionStrategy") == 0: p.correctionStrategy = <uint32_t>strtoul(value, NULL, 0)
    elif strcasecmp(key, "forceMode") == 0: p.forceMode = <int32_t>i
    elif strcasecmp(key, "calcTime") == 0: p.calcTime = <int32_t>i
    elif strcasecmp(key, "insertArcMode") == 0: p.insertArcMode = <int32_t>i
    elif strcasecmp(key, "maxConnectionDistance") == 0: p.maxConnectionDistance = d
    elif strcasecmp(key, "startAngle") == 0: p.startAngle = d
    elif strcasecmp(key, "endAngle") == 0: p.endAngle = d
    elif strcasecmp(key, "minAngleFeed") == 0: p.minAngleFeed = d
    elif strcasecmp(key, "overrideInc") == 0: p.overrideInc = d
    elif strcasecmp(key, "rapidFeed") == 0: p.motion[0].feed = d
    elif strcasecmp(key, "forwardFeed") == 0: p.motion[1].feed = d
    elif strncasecmp_prefix(key, "correction") and key[10] >= b'0' and key[10] <= b'7' and key[11] == 0:
        p.correction[<int>key[10] - 48].size = d
    elif strncasecmp_prefix(key, "tolerance") and key[9] >= b'0' and key[9] <= b'9' and key[10] == 0:
        p.tolerance[<int>key[9] - 48] = d
    else:
        return False
    return True


cdef bint strncasecmp_prefix(const char *s, const char *prefix) noexcept nogil:
    cdef size_t i = 0
    while prefix[i] != 0:
        if s[i] == 0 or (s[i] | 0x20) != (prefix[i] | 0x20):
            return False
        i += 1
    return True
