# Face of the offline machine (machine/, Local_Core_Mode 2): runs a compiled program
# in real time (times the core's time scale) as the vendor's interpolator would,
# StartCNCEx 30-33, StopCNCEx, the M-function handshake, breakpoints, manual moves,
# ConnectCNCEx_Plane. Its files:
#   motion.pyx          the interpolator as a pure step: motion_step(m, dt) along a ring of entries
#   place.pyx           where the machine is on its program (Place): dropped, resumed, left by a run
#   clock.pyx           the machine's time: the wall clock times the scale, or the test-only stepped clock
#   output.pyx          the output stage: each step's position through the spline, the IIR filter and
#                       the axis corrections to the drives (and GetPos); the spline's delay of the events
#   machine.pyx         a run: the feeder and notifier (the activity's worker) and the pacer thread
#   connect_search.pyx  where on a program ConnectCNCEx_Plane connects to (pure, typed)
#   connect.pyx         the connection as an activity: search, move there, run on
# Owns Machine (the machine of one core, Core.offline), its Place on the program
# (outlives the runs), Motion and the search's index. Called by the lifecycle
# (runtime/lifecycle.pyx: prepare and forget a core's machine, its workers) and the
# exports (GoTo, M confirmations, ConnectCNCEx_Plane, StopCNCEx's addCode).

# ---- motion.pyx: the step and its ring of entries
cdef enum:
    LOOK_RING = 64              # entries held ahead (the plan's window of 8 and room for the feeder)
    STEP_US = 100               # the vendor's time base: overrideInc is per 100 us

cdef extern from *:
    """
    #define TC_SECONDS_PER_US 1e-6
    #define TC_TICK_S 1e-3
    #define TC_STEP_MARGIN_S 1e-9
    """
    const double SECONDS_PER_US "TC_SECONDS_PER_US"     # a step in seconds: STEP_US * SECONDS_PER_US
    # s of wall time a tick of the machine's thread works before it publishes GetPos
    # and looks for a stop or an end
    const double TICK_S "TC_TICK_S"
    # s: added to a whole number of granted steps so that rounding does not lose the last
    # (far below one step)
    const double STEP_MARGIN_S "TC_STEP_MARGIN_S"

cdef enum MotionState:
    MS_RUNNING = 0
    MS_WAIT_M = 1               # a waiting M function: stands until it is confirmed
    MS_DWELL = 2                # G4
    MS_STARVED = 3              # the next entry is not in the ring yet (the feeder is behind)
    MS_STOPPED = 4              # StopCNCEx or a breakpoint: -31
    MS_M0 = 5                   # M0: -33
    MS_END = 6                  # the last entry ended: -32 forward, -30 backward at the start
    MS_BUFFER_END = 7           # backward: the executed path it remembers ended: -31

cdef enum MotionEvent:          # motion_step's report (bits; the entries in Motion.log)
    ME_ENTRY = 0x1              # an entry began
    ME_MFUNC = 0x2              # an M function was reached (waiting or continuous)
    ME_PRINT = 0x4
    ME_HALT = 0x8               # the state left MS_RUNNING for good (stopped, M0, end)
    LOG_SIZE = 256

# One entry of the look-ahead ring: what the step needs of a part, nothing it would
# have to derive again. `node` is the entry as the planner's profile and backward pass
# see it: the feeder writes its limits (vmax, ceiling, acc, dec, ramp), the step's
# plan its junction under the override and its braking (jin, jin2, brake2, entry2)
# whenever it plans the entries before it; its other fields are not used.
ctypedef struct Entry:
    size_t part
    uint64_t motion_seq         # motion entries of the run before it (the window counts motion parts)
    int32_t kind                # PartKind
    int32_t func                # G or M number
    uint32_t line               # of the part (GetPos)
    int32_t file_idx
    int32_t gcode_index
    double feed                 # programmed feed, mm/min (GetPos m_setFeed)
    bint rapid
    bint waits                  # the machine stands at it: waiting M (< 1000), M1, dwell
    bint m0                     # M0: the run pauses (-33)
    bint break_before           # a breakpoint: the machine stops before this part
    double dwell                # seconds
    Segment seg                 # placed geometry of a motion part
    double s_from, s_to         # the traverse along seg: forward 0 -> length, backward s -> 0
    PlanNode node               # node.vmax: its limit at 100 % override, mm/s (the plan's v_cap, or the
                                # regime's feed); node.ceiling: the limit no override passes (the plan's);
                                # node.acc, node.dec: equivalent accelerations of its ramps (planner.pxd)
    double v_junction           # mm/s: the junction limit at its start, the way it runs (the plan's)
    double dyn_extra            # the dynamic G41/G42 correction at rest, mm (0: none)
    int32_t dyn_side            # +1 G41 (the tool left of its way), -1 G42
    int dyn_first, dyn_second   # the plane's axes

ctypedef struct Motion:
    Entry ring[LOOK_RING]       # entry k of the run at ring[k % LOOK_RING]
    uint64_t produced           # atomic: entries written (the feeder)
    uint64_t consumed           # atomic: entries done (the step)
    int32_t fed_all             # atomic: the feeder wrote its last entry
    size_t head                 # ring index of the current entry (consumed % LOOK_RING)
    size_t count                # entries in the ring, the current one included (motion_sync)
    bint complete               # no entry will follow the ring's last
    size_t window               # motion parts the look-ahead sees (the plan's window)
    int32_t state
    # the current entry
    Profile run                 # planned from where it was planned (planner/profile.pyx)
    Reciprocals recip
    double run_t                # seconds into `run`
    double run_d0               # distance along the entry where `run` was planned
    double d                    # distance along the entry done
    double v                    # path speed now, mm/s
    bint replan                 # plan the current entry again before the next step
    bint window_short           # its exit was limited by the ring's end: plan again when more arrives
    size_t planned_count        # `count` when it was planned
    uint64_t full_for           # consumed + 1 when the ring was found to hold its window (0: not yet)
    bint started                # the current entry began (ME_ENTRY reported)
    double wait_left            # dwell seconds left
    int32_t confirmed           # a waiting M function was confirmed (set by the machine's thread)
    # the override
    double ovr, ovr_target, ovr_inc
    bint ovr_timing             # interpolatorConfig0 bit 0: override scales time (acc and dec too)
    bint ovr_off_in_rapids      # disableG0FeedOverride
    # a stop (StopCNCEx): at `stop_entry` (ring index), `stop_d` along it
    bint stopping
    size_t stop_entry
    double stop_d
    double stop_dec
    int32_t stop_ramp
    # what the run did (GetPos)
    double position[AXES]
    double cut_len, rapid_len, run_time
    # what happened since the machine's thread last read it (the driver callbacks)
    int32_t n_log
    int32_t log_kind[LOG_SIZE]  # ME_ENTRY, ME_MFUNC, ME_PRINT
    size_t log_part[LOG_SIZE]

# ---- output.pyx: the output stage (interpolator -> spline -> IIR -> axis corrections -> drives)
ctypedef struct OutputEvent:    # a motion event held back by the spline's delay
    uint64_t due                # the output step it is told at
    int32_t kind                # ME_ENTRY, ME_MFUNC, ME_PRINT
    size_t part

ctypedef struct Output:
    # the activity's settings (output_configure, under core.lock)
    SmoothingConfig config
    AxisCorrections *tables     # a reference; NULL: none
    # the filters over one pacer's steps (output_start .. output_stop)
    bint filtering              # a filter is on: every step's position passes the smoother
    Smoother smoother
    double smoothed[AXES]       # the filters' last output
    uint64_t steps              # steps since output_start
    uint64_t delay              # the spline's delay of the events, steps (0: none)
    OutputEvent *events         # events[first .. first + n) wait for their step
    size_t first, n, cap

# ---- place.pyx: where the machine is on its program
cdef enum:
    HISTORY_DEPTH = 100000      # motion parts a backward run can retrace
    PART_NONE = -1              # no part: an entry that is no part of the program (a manual move)

# The machine's place on its program (Machine.place): one record that outlives the
# runs. A run along the program starts from it (place_resume) and leaves it where the
# run stood (place_after_run); the notifier moves `current` into the history as
# motion parts begin (place_motion_begins) and the pacer counts them (counts); a
# connection puts it where it connects (place_connect); ResetCNC, DestroyCNC and a new
# program drop it (place_forget). Nothing else writes it. Between activities it holds:
#   - part <= n_parts of Machine.program; part == n_parts: after the last part, with
#     s == 0 and not began;
#   - 0 <= s <= the part's length; s > 0 only in a motion part that began
#     (place_inside_motion): a forward run goes on s along it, a backward run retraces
#     it from there first;
#   - began: the part's start was told to the driver (DriverGFunc): a forward run that
#     goes on in it does not tell it again;
#   - current: the motion part it stands in and began (not in the history yet), else
#     PART_NONE -- forward, the last one the notifier saw begin, so after a run that
#     ResetStatusCNC cut short it may be the last one whose start was told;
#   - history: the motion parts run before, oldest first, each once, at most
#     HISTORY_DEPTH (history_lost: older ones were dropped, or memory ran out): what a
#     backward run retraces, newest first;
#   - at the program's start (place_at_start): part 0, s 0, nothing run;
#   - cut_len, rapid_len, run_time, counts: the totals of the runs since it was dropped
#     (GetPos; a run moves them on from these).
ctypedef struct Place:
    size_t part                 # the part it is in
    double s                    # path length done along it (mm)
    bint began
    int64_t current
    size_t *history             # history[0 .. n_history), a buffer of cap_history
    size_t n_history, cap_history
    bint history_lost
    double cut_len, rapid_len, run_time
    RunCounts counts            # GetPos's counters (the pacer's while a run moves)

# ---- machine.pyx: a run's threads
cdef enum:
    EVENT_QUEUE = 1024          # events between the pacer and the notifier
    RUN_MANUAL = 50             # the regime of a manual move (GoToPosition), as its status

cdef enum PacerState:            # what the stepped clock's stepper waits for (clock.pyx)
    PACER_NONE = 0              # no pacer runs
    PACER_BUSY = 1              # running the steps it was granted (or starting)
    PACER_IDLE = 2              # it ran them (or stands at a waiting M function): waits for more

ctypedef struct MachineEvent:
    int32_t kind                # ME_ENTRY, ME_MFUNC, ME_PRINT
    size_t part

cdef struct Machine:
    Motion motion
    Output output               # the step's position to the drives (output.pyx)
    pthread_t pacer
    int32_t pacer_done          # atomic: the pacer has left its loop
    # where the machine is on the program (outlives the runs)
    LoadedProgram *program      # the program the place refers to (a reference); NULL: none
    Placement placement         # where that program runs (the machine position of its first start)
    PlacedPlan plan             # its plan as a run placed there sees it (made by the first run)
    bint plan_made
    Place place                 # where it is on that program (place.pyx)
    # the run's driver session (the worker's: feeder and notifier)
    Session session
    # pacer -> notifier
    pthread_mutex_t lock
    pthread_cond_t wake         # the notifier sleeps on it until the pacer has news; the stepper too
    bint news                   # events queued, entries consumed or the pacer done (lock)
    MachineEvent events[EVENT_QUEUE]
    size_t ev_first, ev_n
    bint notifying              # the notifier is inside an event's callbacks (lock)
    # the stepped clock (clock.pyx), under lock
    uint64_t granted            # steps granted and not taken yet
    int32_t pacer_state         # PacerState
    uint64_t pacer_runs         # pacers started

ctypedef struct Feeder:         # what the notifier thread reads parts with
    Core *core
    Machine *m
    const Program *prog
    GCODE_PARAMETERS *params
    int32_t regime
    size_t next                 # forward: next part; backward: entries made so far
    uint64_t motions            # motion entries made so far
    size_t back_last            # backward: the part of the last entry made
    bint any_motion             # regime 33: a motion part was fed
    uint32_t last_line          # the breakpoint question is asked once per line
    int32_t last_file
    bint first
    bint back_current           # backward: the machine stands inside a motion part

# ---- connect_search.pyx, connect.pyx: the connection search
cdef enum:
    CONNECT_ALL_AXES = 0x3FF
    CONNECT_LEAF_PARTS = 4      # parts per leaf of the index
    CONNECT_STACK = 128         # the walk holds at most depth + 1 nodes (< 40 for 2**33 parts)

cdef enum ConnectResult:
    CONNECT_FOUND = 0
    CONNECT_NOT_FOUND = -1      # no such line, G-code index or occurrence; no motion in the range
    CONNECT_OFF_PART = -2       # nType 46: the point lies farther than the tolerance from its part
    CONNECT_BAD_ARGUMENT = -3
    CONNECT_NO_MEMORY = -4

ctypedef struct ConnectHit:
    size_t part                 # index into prog.parts
    double s                    # path length from the part's start (mm, the compensated path)
    double length               # the part's length (0 for M functions, dwells, texts)
    double point[AXES]          # the point, machine coordinates of the run, all ten axes
    double distance             # from the asked point in the chosen axes (0 for lookups)

# A bounding-volume hierarchy over the motion parts' boxes in the chosen axes that
# move: the parts sorted by the Morton code of their box centres, CONNECT_LEAF_PARTS
# of them to a leaf, and a complete binary tree over the leaves (node 1 the root,
# node k's children 2k and 2k+1, leaf l at node first_leaf + l). Each node keeps its
# box and the lowest and highest part index below it, so that a search restricted
# to a range of parts skips whole subtrees.
ctypedef struct ConnectIndex:
    const Program *prog
    Placement pl
    uint32_t axes               # axesForCalc, 0x3FF for all
    int n_dims                  # axes of the boxes: X Y Z of the mask, and the others
    int dims[AXES]              # of the mask that the program moves
    int n_fixed                 # axes of the mask that stand still everywhere: their
    int fixed[AXES]             # distance is the same to every part
    double fixed_at[AXES]
    size_t n_items              # motion parts
    uint32_t *items             # their indexes, in Morton order
    size_t first_leaf           # a power of two; nodes 1 .. 2 * first_leaf - 1
    double *boxes               # node k: low corner at boxes[2 * n_dims * k], high after it
    uint32_t *span              # node k: lowest part index span[2k], highest span[2k + 1]

# A look at each part's candidate: `d2` (squared distance) and `point` (ten axes) may
# be changed; True = use the changed values (ConnectPointCalc, callback 1005).
ctypedef bint (*connect_part_fn)(void *ctx, size_t part, double *d2, double *point) noexcept nogil

ctypedef struct PartCalc:          # what the ConnectPointCalc hook needs
    Core *core
    Machine *m
    Callback cb
    bint not_finite             # the host gave a point or distance that is not finite


# ---- what other stages call
cdef inline bint machine_moving(int32_t status) noexcept nogil:
    """The offline machine moves in this status (its thread publishes GetPos)."""
    return (30 <= status <= 33 or status == CNC_STATUS_CONNECT_CALCULATING
            or status == CNC_STATUS_CONNECT_MOVING or status == CNC_STATUS_MANUAL_MOVE)


# the lifecycle, with core.lock held: the core's machine made ready for an activity
# (False: refused, err set); its place on the program dropped (ResetCNC, a new program,
# DestroyCNC). The workers of its table: a run (RunJob), a manual move (GotoJob), a
# connection (ConnectJob)
cdef bint machine_prepare(Core *core, Job *job, ErrorInfo *err) noexcept nogil
cdef void machine_forget(Core *core) noexcept nogil
cdef void *machine_run_body(void *arg) noexcept nogil
cdef void *machine_goto_body(void *arg) noexcept nogil
cdef void *connect_body(void *arg) noexcept nogil
# the exports: GoToPosition(Ex), ConnectCNCEx_Plane, ToolChainCore_TestClock (test-only)
cdef int32_t core_goto(Core *core, const SIMPLE_GM_PARAMS *dest, uint32_t n_dest, const double *coords) noexcept nogil
# the connection: why its straight way from `start` at motion class cls cannot run in
# finite numbers (NULL: it can)
cdef const char *manual_path_not_finite(const double *start, const SIMPLE_GM_PARAMS *dest, uint32_t n_dest,
                                        const GCODE_FEED *cls) noexcept nogil
cdef int32_t machine_test_clock(Core *core, uint64_t key, double seconds) noexcept nogil
cdef int32_t core_connect(Core *core, uint32_t n_type, uint32_t n_coords, const double *coords,
                          const char *add_code, uint32_t axes_calc, uint32_t axes_connect,
                          int32_t state_after) noexcept nogil
