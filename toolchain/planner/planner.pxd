# Face of the feed planner (planner/): every motion part gets a peak and an exit
# speed such that the machine can still stop at the end of what it sees (the look-
# ahead window), and M functions the plan inserts where it slows down (a part's
# geometry, its Segment: geometry.pxd). Its files:
#   limits.pyx        static limits of a part: feed, arc table, centripetal, axes; G900 / M-5 regions
#   junctions.pyx     junction speeds: the angle slow-down, exact stops
#   mfunc_insert.pyx  mFuncInsertTable: continuous M functions inserted where the plan slows down
#   profile.pyx       one part's speed profile: planned (profile_plan) and sampled (profile_at)
#   passes.pyx        the look-ahead over the program (its backward pass: plan_backward), the
#                     times of the parts, the plan of a run placed away from the compile's start
# and the speed ramps' closed forms below. The plan is the one speed model: the
# offline machine runs the parts with the same profile and backward pass, from the
# limits the plan holds. Owns Program.plan (PartPlan per part) and the records of the
# passes. Called by the pipeline (plan a compiled program, whole or in two ranges),
# the compiler (G900 / M-5 regions), the simulator (part times), the machine (the
# profile, the backward pass, a placed run's plan).

from libc.math cimport cos, sin, M_PI, HUGE_VAL

# ---- speed ramps between two speeds, closed forms. rampType 1: trapezoid, constant
# acceleration a. rampType 2: sine, the acceleration is a half sine wave that starts
# and ends at 0 and peaks at a: v(t) = v0 + (v1 - v0) (1 - cos(pi t / T)) / 2 with
# T = pi |v1 - v0| / (2 a). Its time and distance are those of a trapezoid with
# 2a/pi, so the passes plan both with one "equivalent" acceleration (functions below).
cdef enum:
    RAMP_TRAPEZOID = 1
    RAMP_SINE = 2

# ---- limits.pyx
cdef enum:
    AXIS_MASK = 0x3FF
    ENH_ANGLE_SHIFT = 0         # enhancedInterpolatorParameters bits 0-9: no tangency slow-down
    ENH_FEED_SHIFT = 10         # bits 10-19: axis ignored for the feed
    ENH_STOP_FROM_REST = 1 << 20    # bit 20: an axis of bits 0-9 starts from rest: the others stop first
    ENH_STOP_ON_REVERSAL = 1 << 21  # bit 21: an axis of bits 0-9 reverses: all stop first

ctypedef struct PartLimits:
    double length           # mm
    double vmax             # mm/s, never 0 for a part with length
    double v_ceiling        # mm/s no feed override passes: axes' maxFeed, centripetal, arc feed table (inf: none)
    double acc, dec         # mm/s^2, peak of the ramps
    int32_t ramp            # rampType of the motion class (1 trapezoid, 2 sine)
    bint rapid

ctypedef struct PlanCursor:     # the settings of each part, parts visited in order
    const Program *prog
    PlanRegion cur
    size_t region           # next region to apply
    size_t programmed       # programmed parts before next_part
    size_t next_part        # the parts before it are counted (only while a region remains to apply)
    bint axes_limited       # some axis limit of cur is on
    double cos_start        # cosine of cur.startAngle (2 when every angle slows down)

# ---- junctions.pyx
cdef enum:
    STOP_MODE_EVERY_JUNCTION = 1    # G900 S12 A1: exact stop between any two motion parts
    STOP_MODE_RAPID_CHANGE = 2      # G900 S12 A2: exact stop where rapid and cut meet

# ---- mfunc_insert.pyx
cdef enum:
    MFI_BEFORE_SLOW_DOWN = 0
    MFI_AFTER_SLOW_DOWN = 1
    MFI_BEFORE_RAPID = 2

ctypedef struct MfuncTarget:    # where one inserted M function goes
    size_t part             # the motion part (with length) it lies in; n_parts: after the last part
    double q                # mm into that part (at most MFI_SNAP: just before it)
    size_t seq              # found in this order (several at one place keep it)
    int32_t mfunc

ctypedef struct MfuncTargets:
    MfuncTarget *items
    size_t n, cap

ctypedef struct MfuncInsertion: # one part program_merge inserts
    size_t after            # right after this part
    Part made               # an M function, or the rest of a part split where one lies

ctypedef struct MfuncInsertions:
    MfuncInsertion *items
    size_t n, cap

cdef enum:                      # where the speed stands against the table's shares
    MFI_START = 0               # from the program's start until it first reaches entry 0's
    MFI_FAST = 1
    MFI_SLOW = 2

ctypedef struct MfiScan:        # the walk over the plan's profiles
    const Program *prog
    const INTERNAL_MFUNC_INSERT_TABLE *table
    const double *at            # path position of each part's start; at[n_parts]: the path's length
    MfuncTargets *targets
    int state
    double th0, th1             # the current cut's thresholds (mm/s)
    bint ok

ctypedef struct MfiReplacement: # parts[part] becomes made (once every insertion is made)
    size_t part
    Part made

# ---- passes.pyx
cdef enum:
    VENDOR_WINDOW = 8           # the current part + 7 more
    RING_START = 256            # nodes; a deeper window grows the ring as far as it reaches
    PLAN_SPLIT_SEARCH = 65536   # parts plan_split_at looks through

ctypedef struct PlanNode:       # a motion part with length, as the passes see it (and each machine entry holds one)
    size_t part
    size_t seq                  # motion parts before it (the window counts motion parts)
    double length
    double vmax
    double ceiling              # PartLimits.v_ceiling
    double acc, dec             # equivalent constant accelerations of its ramps (the ramps above)
    int32_t ramp
    double jin                  # speed limit at its start (0: the machine stands there)
    double jin2                 # its square
    double brake2               # 2 dec length: what braking within it takes off the squared speed
    double entry2               # backward pass: squared highest entry speed that can still stop in the window
    bint barrier                # it can brake from its junction's limit to rest within itself: no
                                # part after it changes the limits of the parts before it

ctypedef struct NodeSource:     # makes the nodes, parts in order
    const Program *prog
    const GCODE_PARAMETERS *params
    uint32_t enhanced
    const Placement *pl         # a run placed away from the compile's start, else NULL
    size_t reshaped_end         # with pl: parts before it may change their shape there
    PlanCursor cursor
    size_t scan                 # next part to read
    size_t motions              # motion parts read
    bint have_prev, stop_pending, prev_rapid
    double prev_vmax
    size_t prev_part            # the last node's part
    bint prev_tangent_known     # prev_tangent holds its end tangent
    double prev_tangent[AXES]
    size_t class_region         # cursor.region the values below were taken at
    bint plain_lines            # no axis limit, no axis ignored for the feed: a line's limits are
                                # its feed and its motion class (part_limits' result, cheaper)
    double class_acc[2]         # equivalent accelerations of the classes' ramps, [0] rapid, [1] cut
    double class_dec[2]
    int32_t class_ramp[2]

ctypedef struct Reciprocals:    # of the last node's values: runs of parts share them
    double acc, dec, vmax
    double half_inv_acc, half_inv_dec, inv_vmax

# ---- profile.pyx: one part's speed over its length
ctypedef struct Profile:        # ramp from v_in to v_peak, cruise at v_peak, ramp to v_out
    double v_in, v_peak, v_out
    double t1, t2, t3           # seconds of the three phases
    double length
    int32_t ramp                # the ramps' shape (their times are the equivalent accelerations')

# ---- passes.pyx: the plan of a run placed away from the compile's start
ctypedef struct PlacedPlan:
    const PartPlan *plan        # the compile's
    PartPlan *head              # parts [0, n_head) planned again with their placed shape
    size_t n_head, cap_head


# ---- what other stages call
cdef inline double ramp_equivalent_acc(double acc, int32_t ramp_type) noexcept nogil:
    """The constant acceleration with the same time and distance as the ramp (a ramp
    from v0 to v1 takes |v1 - v0| / it seconds, (v0 + v1) / 2 times that mm)."""
    if ramp_type == RAMP_SINE:
        return acc * (2.0 / M_PI)
    return acc


cdef inline double ramp_speed_in(double v0, double v1, double T, int32_t ramp_type, double t) noexcept nogil:
    """Speed t seconds into the ramp from v0 to v1 that takes T seconds (t in [0, T])."""
    if T <= 0.0 or t >= T:
        return v1
    if t <= 0.0:
        return v0
    if ramp_type == RAMP_SINE:
        return v0 + (v1 - v0) * 0.5 * (1.0 - cos(M_PI * t / T))
    return v0 + (v1 - v0) * t / T


cdef inline double ramp_distance_in(double v0, double v1, double T, int32_t ramp_type, double t) noexcept nogil:
    """Path travelled t seconds into the ramp from v0 to v1 that takes T seconds."""
    if T <= 0.0 or t <= 0.0:
        return 0.0
    if t >= T:
        return 0.5 * (v0 + v1) * T
    if ramp_type == RAMP_SINE:
        return v0 * t + (v1 - v0) * 0.5 * (t - T / M_PI * sin(M_PI * t / T))
    return v0 * t + (v1 - v0) * 0.5 * t * t / T


# the compiler: G900 / M-5 settings from programmed part `first` on
cdef bint program_add_plan_region(ProgramBuilder *build, size_t first, const GCODE_PARAMETERS *p,
                                  uint32_t ignore_angle, uint32_t ignore_feed, uint32_t limits_off,
                                  int32_t stop_mode, int32_t arc_table) noexcept nogil

# one part's profile: planned from its entry speed to the highest exit allowed, and
# sampled; the backward pass over a window of nodes (the planner's ring of PlanNode, the
# machine's ring of entries that hold one: node k `stride` bytes after node k - 1)
cdef void profile_plan(Profile *p, const PlanNode *nd, double v_in, const PlanNode *next,
                       Reciprocals *rc) noexcept nogil
cdef void profile_at(const Profile *p, double t, double *d, double *v) noexcept nogil
cdef inline double profile_time(const Profile *p) noexcept nogil:
    return p.t1 + p.t2 + p.t3
cdef void plan_backward(PlanNode *ring, size_t stride, size_t mask, size_t first, size_t end) noexcept nogil

# the pipeline: plan the whole program, or in ranges split where the machine stands
# (plan_alloc first); whether the plan inserts M functions (then it plans in one piece)
cdef bint mfunc_insert_wanted(const GCODE_PARAMETERS *params) noexcept nogil

cdef int plan_program(ProgramBuilder *build, const GCODE_PARAMETERS *params, uint32_t enhanced,
                      int64_t window) noexcept nogil
cdef bint plan_alloc(Program *prog, const GCODE_PARAMETERS *params, uint32_t enhanced,
                     int64_t window) noexcept nogil
cdef void plan_drop(Program *prog) noexcept nogil
cdef size_t plan_split_at(const Program *prog, size_t near) noexcept nogil
cdef size_t plan_split_between(const Program *prog, size_t near, size_t end) noexcept nogil
cdef size_t plan_split_before(const Program *prog, size_t near, size_t floor) noexcept nogil
cdef int plan_range(const Program *prog, const GCODE_PARAMETERS *params, uint32_t enhanced,
                    int64_t window, size_t first, size_t end) noexcept nogil
# a planned part's feed (mm/min): its speed limit at 100 % override
cdef double plan_calc_feed(const Program *prog, size_t i) noexcept nogil
# the plan of a run from pl.start (the simulator, the machine): the parts the
# placement reshapes and those whose speeds that changes planned again, the rest the
# compile's; False when out of memory
cdef bint placed_plan_make(PlacedPlan *pp, const Program *prog, const Placement *pl) noexcept nogil
cdef void placed_plan_free(PlacedPlan *pp) noexcept nogil
cdef inline const PartPlan *placed_plan_part(const PlacedPlan *pp, size_t i) noexcept nogil:
    return &pp.head[i] if i < pp.n_head else &pp.plan[i]
