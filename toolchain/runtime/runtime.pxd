# Face of the runtime of a core (runtime/): what every activity of a core needs
# besides the core itself. Its files:
#   transitions.pyx  the status machine as one table: the status a command leads to
#   snapshot.pyx     the GetPos view: a double-buffered seqlock readers never wait on, and the
#                    one function that makes it from where a run stands (Standing)
#   programs.pyx     compiled programs with an owner count (published, shared, released)
#   callbacks.pyx    the host's callbacks: counted while they run, the reports they carry
#   last_errors.pyx  GetLastError / GetLastCallError: errors published by pointer swap
#   lifecycle.pyx    the activities: command -> worker table, begin, end, join
#   session.pyx      a run's driver session: callbacks in order, addCode, M handshakes, GetPos counters
#   file_names.pyx   the file table (FileToIdx / IdxToFile)
# The data it works on belongs to the core (core.pxd: Core, its Snapshot, FileTable,
# Callback and LoadedProgram); the runtime owns the commands of the status machine and
# the callback slots. Called by the core, the exports, the simulator and the machine.

cdef extern from *:                 # C in transitions.pyx and callbacks.pyx
    # what status_after gives besides a status: the command is refused in this
    # status; it is accepted and the status stays; -30 (program compiled), else -1
    int32_t TC_REFUSED, TC_KEEP, TC_AT_START
    # the core whose worker runs on this thread (NULL on the host's threads)
    void *tc_worker_core

# ---- transitions.pyx: the commands of the status machine
cdef enum Command:
    CMD_COMPILE = 0             # CompileFromFile / CompileFromMemory
    CMD_SIMULATE = 1            # StartCNCEx 10 (also needs a compiled program)
    CMD_TEST = 2                # StartCNCEx 20 (also needs a compiled program)
    CMD_STOP = 3                # StopCNCEx: the worker ends with EV_STOPPED
    CMD_RESET = 4               # ResetCNC
    CMD_DESTROY = 5             # DestroyCNC
    CMD_DROP_PROGRAM = 6        # ResetStatusCNC mode 0
    CMD_OUT_OF_TRAJECTORY = 7   # ResetStatusCNC mode 1
    CMD_SET_PARAMETERS = 8      # SetGCodeParameters (while stopped on the path: feeds only)
    CMD_LOAD_INI = 9            # LoadFromIni
    CMD_SET_PREFIX = 10         # GCodePrefixPostfix
    EV_DONE = 11                # the worker finished its activity
    EV_STOPPED = 12             # the worker stopped on StopCNCEx (the machine: also a breakpoint)
    CMD_FORWARD = 13            # StartCNCEx 30 (also needs a compiled program)
    CMD_FORWARD_NO_M = 14       # StartCNCEx 31
    CMD_BACKWARD = 15           # StartCNCEx 32
    CMD_FORWARD_SKIP_M = 16     # StartCNCEx 33
    CMD_GOTO = 17               # GoToPosition / GoToPositionEx
    CMD_CONNECT = 18            # ConnectCNCEx_Plane
    EV_M0 = 19                  # the machine stopped at M0
    N_COMMANDS = 20

# ---- callbacks.pyx: slots of the callback table, in the order of the documented numbers
cdef enum CallbackSlot:
    SLOT_ADD_OUTPUT_LOG = 0
    SLOT_SET_STATUS_BAR_TEXT = 1
    SLOT_IS_DEBUG_MODE = 2
    SLOT_IS_VERBOSE_MODE = 3
    SLOT_GET_LIB_PATH = 4
    SLOT_GET_TOOL_PATH = 5
    SLOT_GET_SYSTEM_PATH = 6
    SLOT_GET_FILE_TIME_STAMP = 7
    SLOT_DO_YIELD = 8
    SLOT_READ_INI_STRING = 9
    SLOT_READ_INI_DOUBLE = 10
    SLOT_READ_INI_INT = 11
    SLOT_IS_BREAKPOINT = 12
    SLOT_DISP_AND_LOCATE_ERROR = 13
    SLOT_ADD_OUTPUT_LOG_WITH_MSG_BOX = 14
    SLOT_SET_STATUS_BAR_PROGRESS = 15
    SLOT_DRIVER_INITIALIZE = 16
    SLOT_DRIVER_G_FUNC = 17
    SLOT_DRIVER_M_FUNC = 18
    SLOT_CONNECT_POINT_CALC_START = 19
    SLOT_CONNECT_POINT_CALC = 20
    SLOT_CONNECT_POINT_CALC_END = 21
    SLOT_DRIVER_END = 22
    SLOT_MATH_WARNING = 23


# ---- session.pyx: a run's driver session
ctypedef struct Session:
    Core *core
    int32_t regime              # StartCNCEx's
    bint holds                  # waiting M functions hold the run until answered (the machine)
    size_t signalled_m          # the part of the last waiting M function DriverMFunc got (-1: none)


cdef inline bint m_function_waits(int32_t m, bint continuous) noexcept nogil:
    """The machine stands at a waiting M function until it is answered: every M but
    M0 (a pause) and the continuous ones (M1001 and above)."""
    return m != 0 and not continuous


# ---- what other stages call
# the status `command` leads to from `status`: a status, TC_KEEP or TC_REFUSED
cdef int32_t status_after(int32_t status, int32_t command, bint has_program) noexcept nogil

# GetPos: a snapshot set up, read by anyone; what it shows published from where a
# run stands (core.pxd Standing: the one place that makes the view), by whoever
# moves the position; the standing of the last publication; a standing that shows
# only its position, the part it is in (its kind, -1: none; waiting at an M
# function; its G92 shift, NULL: none)
cdef void snapshot_init(Snapshot *snap) noexcept nogil
cdef void snapshot_read(Snapshot *snap, SnapshotData *out) noexcept nogil
cdef void core_read_position(Core *core, SIMPLE_GM_PARAMS *pos, GM_PARAMS_ENHANCED *enh) noexcept nogil
cdef void getpos_publish(Snapshot *snap, const Standing *s) noexcept nogil
cdef void getpos_shown(Snapshot *snap, Standing *out) noexcept nogil
cdef void standing_clear(Standing *s) noexcept nogil
cdef void standing_part(Standing *s, int32_t kind, int32_t func, bint waiting, const double *shift) noexcept nogil

# a compiled program published (it takes prog over), one more reader, one reader less
cdef LoadedProgram *loaded_program_new(Program *prog, const GCODE_INFO *extent,
                                       const int32_t *files) noexcept nogil
cdef LoadedProgram *loaded_program_ref(LoadedProgram *lp) noexcept nogil
cdef void loaded_program_release(LoadedProgram *lp) noexcept nogil

# callbacks: the calling thread marked as a core's worker; a documented number's slot;
# a call counted while it runs (enter: False when none is set; leave); SetCallBack;
# an error as the API's CALLBACK_INFO; what a callback is told: output lines, an
# error, progress, the status bar, a warning
cdef void worker_thread_mark(Core *core) noexcept nogil
cdef int32_t callback_slot(uint32_t number) noexcept nogil
cdef bint callback_enter(Core *core, int32_t slot, Callback *cb) noexcept nogil
cdef void callback_leave(Core *core, int32_t slot) noexcept nogil
cdef void callback_set(Core *core, int32_t slot, void *fn, intptr_t user) noexcept nogil
cdef void fill_callback_info(const ErrorInfo *err, CALLBACK_INFO *info) noexcept nogil
cdef void core_output(Core *core, uint32_t tab, const char *text) noexcept nogil
cdef void core_report_error(Core *core, const ErrorInfo *err) noexcept nogil
cdef void core_progress(Core *core, uint32_t percent) noexcept nogil
cdef void core_status_text(Core *core, const char *text, int32_t file_idx, int32_t n_lines) noexcept nogil
cdef void core_warning(Core *core, const ErrorInfo *warning) noexcept nogil

# the errors a core keeps (GetLastError: of_calls False; GetLastCallError: True): a
# copy to publish (err number 0: none, NULL; err NULL: "out of memory"), a reference
# dropped, one published, one swapped in with core.lock held (the old one returned,
# to release after unlocking), one read for the host (the calling thread holds it
# until it reads again), the column of the one the host would read
cdef PublishedError *published_error_new(const ErrorInfo *err) noexcept nogil
cdef void published_error_release(PublishedError *e) noexcept nogil
cdef void core_keep_error(Core *core, bint of_calls, const ErrorInfo *err) noexcept nogil
cdef PublishedError *core_swap_error_locked(Core *core, bint of_calls, PublishedError *e) noexcept nogil
cdef int32_t core_read_error(Core *core, bint of_calls, CALLBACK_INFO *info) noexcept nogil
cdef int32_t core_read_error_column(Core *core, bint of_calls, int32_t *column) noexcept nogil

# the activities (lifecycle.pyx): the table's row of a command (False: it begins no
# activity); the command of a StartCNCEx regime (-1: none); an empty job of a command
# and its release; StartCNCEx; an activity started (takes the job; `what` names the
# call in errors); StopCNCEx; the worker's last step (an event of the table; or, when it gave up
# before it changed anything, back to the status it began in); the calls that end it
# (DestroyCNC, ResetCNC, ResetStatusCNC: an EndKind)
cdef bint activity_of(int32_t command, Activity *a) noexcept nogil
cdef int32_t run_command(int32_t regime) noexcept nogil
cdef Job *job_new(int32_t command) noexcept nogil
cdef void job_free(Job *job) noexcept nogil
cdef int32_t core_start_run(Core *core, int32_t regime, const char *add_code) noexcept nogil
cdef int32_t core_start(Core *core, Job *job, const char *what) noexcept nogil
cdef int32_t core_stop(Core *core, const char *add_code) noexcept nogil
cdef void core_finish(Core *core, int32_t event) noexcept nogil
cdef void core_finish_to(Core *core, int32_t status) noexcept nogil
cdef int32_t core_end(Core *core, int32_t kind, const char *what, uint32_t n_coords,
                      const double *coords) noexcept nogil
# GetGCodeSizeInfo's extent measured again from the start position (False: out of memory,
# size_info_stale set)
cdef bint core_refresh_size_info(Core *core) noexcept nogil
cdef int32_t core_size_info(Core *core, GCODE_INFO *out) noexcept nogil

# a run's driver session (session.pyx): opened for a run in a regime (holds: waiting M
# functions hold it until answered); DriverInitialize, DriverEnd; a part as it begins
# (DriverMFunc's answer); an addCode sent with the core in `status` (0: unchanged;
# after_stop: StopCNCEx's; False: a stop or an end came meanwhile); StopCNCEx's addCode kept, taken (the caller
# frees it). The handshake: the machine's step takes an answer; ConfirmMFunc; MFunc
# while nothing runs; none waits and no stop addCode is kept (an activity begins or
# ends). GetPos: a part began (the counters)
cdef void session_open(Session *s, Core *core, int32_t regime, bint holds) noexcept nogil
cdef void session_begin(Session *s, const double *start) noexcept nogil
cdef void session_end(Session *s) noexcept nogil
cdef int32_t session_part(Session *s, const Program *prog, size_t i, const SIMPLE_GM_PARAMS *gm) noexcept nogil
cdef bint session_add_code(Session *s, const char *code, const double *position, int32_t status,
                           bint after_stop) noexcept nogil
cdef void session_keep_stop_code(Core *core, const char *code) noexcept nogil
cdef char *session_take_stop_code(Core *core) noexcept nogil
cdef bint session_take_answer(Core *core) noexcept nogil
cdef int32_t session_confirm(Core *core) noexcept nogil
cdef int32_t session_standing_m(Core *core, const SIMPLE_GM_PARAMS *fun) noexcept nogil
cdef void session_forget_locked(Core *core) noexcept nogil
cdef void session_count(RunCounts *c, const Part *p) noexcept nogil

# the file table: FileToIdx, IdxToFile, a file's run time read (-1: no such entry)
# and set (False: no such entry)
cdef int32_t core_file_to_idx(Core *core, const char *name) noexcept nogil
cdef const char *core_idx_to_file(Core *core, int32_t idx) noexcept nogil
cdef double core_file_run_time(Core *core, int32_t idx) noexcept nogil
cdef bint core_set_file_run_time(Core *core, int32_t idx, double seconds) noexcept nogil
