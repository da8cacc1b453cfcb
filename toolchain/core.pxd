# Face of core.pyx and of the runtime's data: one CNC core (interpolator channel),
# what it holds and who may touch it. The core owns its configuration, its program,
# its errors and its one activity (a compilation or a run) in a worker thread; the
# runtime (runtime/, its own face) keeps the pieces declared here: the file table,
# the callbacks, the GetPos snapshot, the published program. The exports call the
# core for every API function; the machine and the simulator start, finish and fail
# activities through it. docs/threading.md draws the lifecycle; in short:
#   - `status`, `cancel` and `stop` are int32 read and written atomically: StatusCNC
#     polls `status` without any lock;
#   - `snap` (the GetPos view) is a double-buffered seqlock: its writers take
#     `snap.write_lock`, its readers never wait, not even for a writer that was
#     preempted in the middle of a copy;
#   - `lock` guards everything else. It is held only for copies and pointer swaps:
#     never during file I/O, a pass over the parts, a callback or a join;
#   - one activity (compilation or run) at a time, run by one worker thread; exactly
#     one thread joins it (`joining`), every caller that ends it waits for the join
#     on `changed` (runtime/lifecycle.pyx).

cdef enum:
    MAX_FILES = 64          # file names per core (FileToIdx); recycled when full
    N_CALLBACK_SLOTS = 24   # documented callback numbers

cdef extern from *:
    """
    /* the feed override's range: the interpolator's Rel_Speed, 0.01 .. 2 (1 % .. 200 %) */
    #define REL_FEED_MIN 0.01
    #define REL_FEED_MAX 2.0
    """
    double REL_FEED_MIN
    double REL_FEED_MAX

# What an ending call asks for once the activity is over (the commands of the
# transition table that end an activity; runtime/transitions.pyx).
cdef enum EndKind:
    END_NONE = 0
    END_RESET = 1           # ResetCNC: program kept, status -30 (or -1 / 0 without a program)
    END_DESTROY = 2         # DestroyCNC: program dropped, status 0
    END_DROP_PROGRAM = 3    # ResetStatusCNC mode 0: program dropped, status 0
    END_OUT_OF_TRAJECTORY = 4   # ResetStatusCNC mode 1: status -50

ctypedef struct Callback:
    void *fn
    intptr_t user

# An error kept for the host (GetLastError, GetLastCallError): written once, then only
# read, freed by its last holder (runtime/last_errors.pyx).
ctypedef struct PublishedError:
    int32_t refs            # atomic: the core while it keeps it, each thread that read it
    ErrorInfo info
    # info's text and args as the host's narrow texts (Windows' ANSI code page: made
    # when published, malloc'ed); NULL: the UTF-8 of info is the host's
    char *narrow_text
    char *narrow_args

# A compiled program, immutable once published, shared by the core and every run
# that reads it; the last release frees it (runtime/programs.pyx).
ctypedef struct LoadedProgram:
    int32_t refs            # atomic
    Program prog
    GCODE_INFO extent       # GetGCodeSizeInfo at the program's compile start
    int32_t files[3]        # file table entries it references: main, prefix, postfix (-1 none)

# GetPos: what a poller reads, published by whoever moves the position
# (runtime/snapshot.pyx).
ctypedef struct SnapshotData:
    SIMPLE_GM_PARAMS pos
    GM_PARAMS_ENHANCED enh

ctypedef struct RunCounts:      # GetPos's counters of a run so far (runtime/session.pyx session_count)
    int32_t n_work, n_rapid     # moves begun: G1 G2 G3, and G0
    int32_t rapid_to_work, work_to_rapid
    int32_t n_m                 # M functions
    int32_t last_motion         # the last move: 0 none yet, 1 a rapid, 2 a cut

# Where a run stands, as its publisher knows it: everything GetPos shows is made from
# it by one function (getpos_publish, runtime/snapshot.pyx), whoever publishes -- the
# machine's pacer, the simulation, an ending call, an addCode M function that waits.
# standing_clear gives a standing machine that shows nothing but its position;
# standing_part the part it is in.
ctypedef struct Standing:
    # the part as the driver got it (the simulation: GetPos shows its fields), else its
    # identity (m_editorLine, m_fileIdx -1: none, m_gCodeIndex); m_func the number shown
    # (standing_part); m_s, m_e: the part's start and end (the simulation), else the
    # commanded position (the interpolator's). Its m_pars, m_calcS, m_calcE are not shown
    SIMPLE_GM_PARAMS part
    double output[AXES]         # where the tool is (after the spline and the IIR filter): m_calcS, the axis cells
    double drives[AXES]         # what the drives are sent (the axis corrections added): m_calcE
    bint cells                  # m_pars shows the cells below (else all 26 are 0)
    bint shows_shift            # the part's G92 shift in the I J K L Q R D E S H cells
    double shift[AXES]
    float g_cell, m_cell        # the G and M cells (INVALID_VALUE_F: absent)
    RunCounts counts
    double cut_len, rapid_len   # so far, mm (the N and T cells too)
    double fill                 # how full the look-ahead is, percent (the P cell)
    double set_feed, calc_feed  # of the motion part it is in (mm/min): programmed, its limit at 100 %
    double part_len, part_remain
    double act_feed, rel_feed   # the actual feed (mm/min) and override
    uint32_t master_line, master_file
    int32_t status
    double run_time             # machine seconds of the run so far

ctypedef struct SnapshotSlot:
    uint32_t seq            # odd while a writer writes this slot
    SnapshotData data

ctypedef struct Snapshot:
    uint32_t current        # the slot readers read; a writer writes the other one
    pthread_mutex_t write_lock
    SnapshotSlot slots[2]
    Standing shown          # what the last publication was made from (write_lock)

# Every distinct file name a core has been given, each stored once and never moved
# or rewritten: the pointer IdxToFile returns stays valid while a host holds it
# (runtime/file_names.pyx).
cdef struct NameChunk:
    NameChunk *next
    size_t used
    char text[65520]

ctypedef struct FileTable:
    const char *names[MAX_FILES]    # into `store`
    NameChunk *store
    double run_times[MAX_FILES]
    uint64_t used[MAX_FILES]    # last use (FileToIdx, compile): the oldest unreferenced entry is recycled
    uint64_t clock
    int32_t n

# the offline machine of a core: machine/machine.pxd defines it; only machine/ looks inside
cdef struct Machine

# One core. Its fields are grouped by who owns them: each group's "owners:" line names
# the stages (a directory of toolchain/, or a top-level module) whose code may name
# `core.<field>` (tools/check_structure.py rejects any other; the exports own none: they
# validate and forward), and how the threads share the field: "lock" (read and written
# under core.lock), "atomic" (TC_ATOMIC_*), or "worker" (the activity's own thread).
ctypedef struct Core:
    # -- identity and the lock (owners: core runtime configuration machine simulator toolpath)
    int32_t index               # set once (core_get)
    pthread_mutex_t lock
    pthread_cond_t changed      # a worker was joined, a callback call ended
    # -- status and the activity's signals (owners: core runtime machine simulator; atomic)
    int32_t status              # cnc_status: core_status / core_set_status (core.pxd)
    int32_t cancel              # the activity must end now (reset, destroy)
    int32_t stop                # StopCNCEx calls during the activity (0: none)
    # -- the activity's thread (owners: runtime; lock)
    pthread_t worker
    bint has_worker             # a worker thread exists and nobody joined it yet
    bint joining                # a thread is joining it (the others wait on `changed`)
    uint64_t activity           # number of the current (or last) activity
    int32_t deferred_end        # EndKind asked from inside a callback: applied by the worker at its end
    # -- what the host set (owners: configuration core runtime machine simulator; lock:
    # -- configuration writes them, the others read them as an activity begins)
    GCODE_PARAMETERS params
    MACHINE_PARAMETERS machine
    double user_params[100]
    bint has_user_params
    char *prefix
    char *postfix
    bint ini_loaded
    char driver[256]
    int64_t plan_window         # look-ahead of the feed planner in parts (SetLookAhead, INI lookAheadParts)
    uint32_t breakpoint_line
    int32_t breakpoint_file
    # the machine builder's tables and smoothing (any status; the offline machine takes a copy
    # and a reference as an activity begins, machine/output.pyx; a compilation a copy of the
    # tool table, compiler/tools.pyx, docs/tool-table.md "In programs")
    ToolTable tool_table        # LoadToolTable, SetToolCorrection, INI [Corrections] ToolTable
    AxisCorrections *axis_corrections   # LoadAxisCorrections, INI AxisTable1..8; NULL none (tables.pxd: references)
    SmoothingConfig smoothing   # SetSmoothing, INI [Smoothing]
    # -- the host's speeds of the moment (owners: configuration core machine runtime simulator; atomic)
    double time_scale           # TC_ATOMIC_*_D: the offline machine runs this many times real time
    double rel_feed             # TC_ATOMIC_*_D; REL_FEED_MIN .. REL_FEED_MAX
    int32_t clock_stepped       # the offline machine runs on the test-only stepped clock (machine/clock.pyx)
    # -- callbacks, kept errors, file names (owners: runtime; lock)
    Callback callbacks[N_CALLBACK_SLOTS]
    int32_t in_flight[N_CALLBACK_SLOTS]     # calls of each slot running now, on any thread
    PublishedError *error       # error of the last activity (GetLastError); NULL none
    PublishedError *call_error  # error of the last refused call (GetLastCallError); NULL none
    FileTable files
    # -- the loaded program and where the machine stands (owners: core runtime machine simulator
    # -- toolpath; lock)
    int32_t compile_files[3]    # the file table entries the running compilation uses (never recycled meanwhile)
    LoadedProgram *program      # NULL: nothing compiled (or the compilation failed)
    GCODE_INFO size_info        # of `program` at the current start position
    bint size_info_stale        # a reset could not measure it (out of memory): measured when read
    double position[AXES]       # machine position: where the next run and compilation start
    double pending_position[AXES]   # ResetCNC's coordinates, applied once the activity it ends is over
    uint32_t n_pending
    Snapshot snap               # what GetPos reads (its own seqlock: runtime/snapshot.pyx)
    # -- the offline machine (owners: machine; made on first run, never freed)
    Machine *offline
    # -- a run's driver session (owners: runtime; runtime/session.pyx)
    char *stop_code             # StopCNCEx's addCode, sent once the run stands (lock; owned)
    int32_t m_waiting           # the M function DriverMFunc answered TC_MFUNC_LATER for (M0: -1), 0 none (lock)
    int32_t m_answered          # atomic: the waiting M function of the running activity was answered


# An activity's job: what its worker gets from the call that began it (the worker
# frees it). One type per activity, each opening with the same head; the table of
# runtime/lifecycle.pyx (activity_of) gives each command its worker and job type.
ctypedef struct Job:
    Core *core
    int32_t command             # the transition table's command that began it

ctypedef struct CompileJob:     # CompileFromFile, CompileFromMemory
    Job head
    char *text                  # the program text (owned); NULL: read `name`
    size_t length
    int32_t files[3]            # file table entries of main, prefix, postfix
    char *prefix                # GCodePrefixPostfix texts at the start (owned)
    char *postfix
    char name[252]

ctypedef struct RunJob:         # StartCNCEx 10, 20, 30-33
    Job head
    int32_t regime
    char *add_code              # StartCNCEx addCode (owned, may be NULL)

ctypedef struct GotoJob:        # GoToPosition, GoToPositionEx
    Job head
    SIMPLE_GM_PARAMS dest       # line (m_func 1) or arc (2, 3) to m_calcE, as GoToPositionEx
    uint32_t n_dest             # ... of which the first n_dest axes move (GoToPosition)

ctypedef struct ConnectJob:     # ConnectCNCEx_Plane's arguments
    Job head
    uint32_t n_type
    double coords[11]
    uint32_t n_coords
    uint32_t axes_calc, axes_connect
    int32_t state_after
    int32_t status_before       # the status it was called in
    char *add_code              # owned, may be NULL

ctypedef struct Activity:       # a row of the lifecycle's table
    void *(*body)(void *) noexcept nogil            # the worker, given its Job
    size_t job_size             # sizeof its job type
    bint needs_program          # refused (ERR_NOTHING_COMPILED) without a compiled program
    bint (*prepare)(Core *core, Job *job, ErrorInfo *err) noexcept nogil    # under core.lock before
                                # the worker starts (NULL: nothing); False refuses it (err set)


# ---- what other stages call
# ToolChainCore_Init's settings (the exports write them)
cdef int32_t g_core_mode           # Local_Core_Mode of ToolChainCore_Init (2 offline until Init)
cdef char g_macros_dir[1024]       # Macros_Dir of ToolChainCore_Init (external G functions: not used yet)

# the core of an index (NULL for none); its status, read and written atomically
cdef Core *core_get(uint32_t index) noexcept nogil

cdef inline int32_t core_status(Core *core) noexcept nogil:
    return TC_ATOMIC_LOAD(&core.status)


cdef inline void core_set_status(Core *core, int32_t status) noexcept nogil:
    TC_ATOMIC_STORE(&core.status, status)

# errors of refused calls: the calling thread's record for one (its constructor fills
# it: `err_...(refusal(), -1, 0, ...)`); a refused call's error kept (GetLastCallError)
# and reported, TOOL_CHAIN_ERROR; a call the transition table refuses in `status`
cdef ErrorInfo *refusal() noexcept nogil
cdef int32_t core_fail(Core *core, const ErrorInfo *err) noexcept nogil
cdef int32_t core_refuse(Core *core, const char *what, int32_t status) noexcept nogil
# CompileFromFile (text NULL: the worker reads the file `name`) and CompileFromMemory;
# the lifecycle's row of a compilation (runtime/lifecycle.pyx): its worker, and what is
# made ready under core.lock before it starts (a CompileJob)
cdef int32_t core_start_compile(Core *core, const char *name, char *text, size_t length) noexcept nogil
cdef void *compile_body(void *arg) noexcept nogil
cdef bint compile_prepare(Core *core, Job *job, ErrorInfo *err) noexcept nogil
