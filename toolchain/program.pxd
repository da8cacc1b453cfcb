# Face of program.pyx: the data that flows through the pipeline, compiler ->
# compensation -> planner -> simulator / machine. One compact Part per compiled G or M
# function, kept in a growable C array; SIMPLE_GM_PARAMS (616 bytes) is only built at
# the API boundary (part_to_gm). Owns Program (published read-only once compiled),
# ProgramBuilder (while it is compiled), the merge of inserted parts, and the contract
# of the compile stages (CompileInput, CompileResult, their hooks). Every stage reads
# it; the compiler, the compensation and the planner write it through the builder.


cdef enum:
    AXES = 10               # x y z c b u v w a o
    OTHER_AXES = 7          # c b u v w a o: a Part holds x y z, Program.axes these
    PLC_MEMORY_BYTES = 524288
    PROGRAM_TABLE_MAX = 65535 # zero offsets, rotations, radii: a part names each with 16 bits

cdef extern from *:
    """
    /* the one bound of every number a part carries (docs/dialect.md, "Numbers"): the
       address words (not G, M, L), the ISO mode's positional parameters, the samples of
       the smoothing. Squares stay finite, and so do the floats of P26FLOAT, even the
       lengths summed over the MAX_PARTS parts of a program (2e7 x 2e30 < FLT_MAX) */
    #define TC_MAX_WORD_VALUE 1e30
    """
    double TC_MAX_WORD_VALUE

# Part.kind
cdef enum PartKind:
    PART_MOTION = 1         # G0 G1 G2 G3 G33: moves from the previous part's end to e
    PART_MFUNC = 2          # waiting (< 1000) or continuous (>= 1001) M function, M0, M1
    PART_DWELL = 3          # G4: func 4, dwell seconds in value
    PART_PRINT = 4          # M29 / PRINT: text in Program.texts at aux

# Part.flags
cdef enum PartFlags:
    FLAG_FEED_PER_MIN = 0x01     # G94 (else G95 mm/rev)
    FLAG_INSERTED = 0x02         # inserted by the system (compensation, G167 arcs)
    FLAG_CONTINUOUS_M = 0x04     # M >= 1001: signalled at the start of the next move, no wait
    FLAG_HELIX = 0x08            # arc with off-plane motion
    FLAG_CSS = 0x10              # G96 with G95: `value` holds the spindle speed (rev/min) S gives there
    FLAG_DROPPED = 0x20          # removed from the cutting plan (an arc whose offset has no radius): no callback
    FLAG_INDEX_SET = 0x40        # its G-code index is M-6 S's (the count restarts there)

# What every part needs (88 bytes: a CAM job's parts are most of a compiled program's
# memory, docs/benchmarks.md); what only some carry is in its PartExtra, what changes
# seldom in the PartSettings it shares with its neighbours.
ctypedef struct Part:
    double e[3]             # programmed end x y z, machine coordinates (program + zero offset); M parts: current position
    double ce[3]            # compensated end x y z (the other axes as programmed); = e when not compensated
    int32_t func            # G number (0 1 2 3 4 33) or M number
    int32_t gcode_index     # even for programmed parts, odd for inserted ones
    uint32_t line           # 1-based line in its file
    uint32_t pars_off       # offset of this part's addresses in Program.pars (see pars_mask)
    uint32_t pars_mask      # bit (letter - 'A') set for every address written on the line (part_own_cell)
    uint32_t extra          # its PartExtra in Program.extras (0: none, read as all zero: part_extra);
                            # PART_PRINT: the offset of its text in Program.texts
    uint32_t axes_idx       # the end's other seven axes (c b u v w a o): Program.axes[OTHER_AXES * axes_idx ...]
    uint32_t settings       # its PartSettings in Program.settings (part_settings)
    int16_t plane           # 17 18 19 -18
    uint8_t kind            # PartKind
    uint8_t flags           # PartFlags
    uint8_t comp            # 40 41 42 (side after the sign of the radius), see m_bFeedIsMin
    uint8_t comp_slot       # 0..7: index of correction[] used (G41 -> 0, G42 -> 1, G43 -> 2, ...)
    uint16_t radius_idx     # 0: the radius is correction[comp_slot]'s; else Program.radii[radius_idx] (a D word's)

# What a part is cut with that changes seldom, shared by the parts that agree
# (Program.settings, Part.settings; entry 0: the defaults of program_add_part).
ctypedef struct PartSettings:
    double feed             # F in mm/min (G94) or mm/rev (G95) after forceMode/M99; rapid: motion[0].feed; 0 but for motion
    float fp                # FP relative feed (1.0)
    float spindle           # S
    uint16_t tool           # T
    uint16_t zero_idx       # index into Program.zeros (active zero offset)
    uint16_t rot_idx        # index into Program.rotations (G168), 0 = not rotated
    int16_t file_idx        # file index (FileToIdx), -1 unknown
cdef enum:
    SETTINGS_HASH_WORDS = 6 # a PartSettings' 24 bytes, no padding: the 32-bit words _settings_hash reads

# What only some parts carry, in Program.extras (Part.extra): an arc's centre and
# radius, the value of a dwell, a thread or a G96 part. Parts without one (lines,
# M functions) read the zero record (part_extra): radius 0, value 0.
ctypedef struct PartExtra:
    double cc[3]            # arc centre x y z (machine coordinates), programmed
    double radius           # arc radius of the tool path (compensated); 0: a removed arc, or no arc
    double value            # dwell seconds (G4), thread pitch (G33), spindle rev/min under G96 (FLAG_CSS)

# G167 automatic arcs from the program: the settings in force from part `first` on
# (index among the programmed parts, i.e. not counting inserted ones).
ctypedef struct ArcRegion:
    size_t first
    bint on                 # False: bare G167 (off)
    int32_t plane           # Q: 17 18 19, 0 = the part's plane
    double tol_max, tol_min # E, A: distance corner <-> arc midpoint
    double max_angle        # U (degrees)

ctypedef struct StrategyRegion:   # G172 / G173: the compensation strategy from the program
    size_t first            # first part it applies to
    bint on                 # False: G173 (the host's strategy again)
    double corner_distance  # R: outer corners take the offsets' intersection when it lies this close (mm)
    double depth            # C: search depth in parts (0 = the host's)
    bint drop_arcs          # D1: drop arcs whose offset radius becomes negative (D0 keeps the host's bit)

# G92 D from the program: the values `programmed` (bit k: values[k], G92 D's Rk) of
# tool table entry `entry`, in the order the program wrote them (docs/tool-table.md).
ctypedef struct ToolWrite:
    int32_t entry           # 1..99
    uint32_t programmed
    double values[TOOL_VALUES]

cdef enum:
    SETTINGS_SEEN = 64      # records program_settings_index finds again without adding one

# Planning settings the program changes (G900, M-5), from programmed part `first` on
# (not counting inserted parts); before the first region the host's GCODE_PARAMETERS hold.
ctypedef struct PlanRegion:
    size_t first
    GCODE_FEED motion[8]    # G900 S20..S70
    AXIS_LIMITS axisLimits[AXES]    # G900 S7
    double startAngle, endAngle, minAngleFeed   # G900 S9
    uint32_t ignore_angle   # G900 S10: axes left out of the junction angle
    uint32_t ignore_feed    # G900 S11: axes left out of the feed's length
    uint32_t limits_off     # M-5: axes whose axisLimits are off
    int32_t stop_mode       # G900 S12 A
    int32_t arc_table       # G900 S13 A: -1 never given (the host's table), 0 off, else on

# The feed plan of one part (planner/), the one speed model of the compile and the
# run: its limits, and the speed it leaves with. Its profile -- from its entry speed
# (the previous part's exit, 0 for the first part) up to at most v_cap, a cruise,
# down to v_exit -- follows from them and the part's length (planner/profile.pyx),
# for the compile and for the offline machine alike, which plans a part again from
# these limits only where the host changed something (the start position, the
# override, a stop). Floats (7 digits), the limits each the float at or below the
# value it came from, and the plan made with them. Speeds mm/s, accelerations
# mm/s^2; M functions, dwells and parts without length pass the speed through
# (v_cap: that speed; acc, dec: 0). Packed, 29 bytes: the plan is a quarter of a
# CAM job's memory.
ctypedef packed struct PartPlan:
    float v_exit            # speed at its end
    float time              # seconds (dwell: its time)
    float v_cap             # its speed limit at 100 % override: feed, arc feed table, centripetal, axes
    float v_ceiling         # the limit no feed override passes: axes' maxFeed, centripetal, arc feed table (inf: none)
    float v_junction        # the junction limit at its start (0: the machine stands there; inf: none)
    float acc, dec          # equivalent constant accelerations of its ramps (planner.pxd)
    uint8_t ramp            # rampType of its ramps (1 trapezoid, 2 sine)

# What a plan was made with: a run that plans parts again (placed elsewhere) plans
# them with the same settings.
ctypedef struct PlanSettings:
    GCODE_PARAMETERS params
    uint32_t enhanced       # MACHINE_PARAMETERS.enhancedInterpolatorParameters
    int64_t window          # look-ahead in motion parts: 0 the vendor's 8, < 0 unlimited

cdef struct Follow                  # the stage beside the compiler (pipeline.pxd)

ctypedef struct Program:
    Part *parts
    size_t n_parts
    PartExtra *extras       # Part.extra's records; entry 0 unused (part_extra reads NO_EXTRA)
    size_t n_extras
    PartSettings *settings  # Part.settings' records, each once (mostly: program_settings_index)
    size_t n_settings
    float *pars             # addresses of all parts, packed in letter order per part (part_own_cell's not)
    size_t n_pars
    P10DOUBLE *zeros        # zero offsets referenced by Part.zero_idx (zeros[0] = none)
    P10DOUBLE *shifts       # of each zero offset, the G92 shift it holds (GetPos's I J K L Q R D E S H)
    size_t n_zeros
    double *rotations       # G168 rotations, 12 doubles each (centre x y z, 3x3 matrix by rows); entry 0 unused
    size_t n_rotations
    StrategyRegion *strategy_regions        # in part order
    size_t n_strategy_regions
    char *texts             # NUL-terminated PRINT texts
    size_t n_texts
    double *axes            # positions of the axes c b u v w a o, 7 doubles per entry (Part.axes_idx):
    size_t n_axes           # a new entry only when one of them moves, so most programs have one
    double start[AXES]      # machine position before the first part
    int32_t main_file_idx
    uint32_t n_lines        # lines of the main file
    bint compensated        # some part has comp != 40
    int32_t start_gindex[AXES]  # parts whose gcode_index is below it take axis k relative to the
                                # machine position a run starts from (the axis not yet named
                                # absolutely: G91 moves, or not named at all); INT32_MAX: every part
    ArcRegion *arc_regions  # G167 changes, in part order (compensation/insert_arcs.pyx)
    size_t n_arc_regions
    PlanRegion *plan_regions    # G900 / M-5 changes, in part order (compiler; planner/)
    size_t n_plan_regions
    PartPlan *plan          # one per part once planned (planner/plan_program), else NULL
    PlanSettings planned_with
    double *radii           # signed tool radii of D words (Part.radius_idx); entry 0 unused
    size_t n_radii
    ToolWrite *tool_writes  # the program's G92 D, for the core's table once compiled
    size_t n_tool_writes

# A Program while it is being compiled: the stages that add to its arrays (the
# compiler, the compensation's merge, insert_arcs, the planner's insertions) grow them
# through the builder, which keeps what only the compilation needs. Once compiled,
# the core publishes `prog` alone (runtime/programs.pyx loaded_program_new takes it
# over), the parts, extras and addresses trimmed to their n_* before the plan
# (program_builder_trim); the small arrays keep their spare room.
ctypedef struct ProgramBuilder:
    Program prog
    size_t cap_parts, cap_pars, cap_zeros, cap_shifts, cap_rotations    # allocated items of each array
    size_t cap_strategy_regions, cap_texts, cap_axes        # (axes, rotations: doubles)
    size_t cap_arc_regions, cap_plan_regions, cap_radii, cap_tool_writes
    size_t cap_extras, cap_settings
    bint merging            # program_merge runs: its makers take records from the room it reserved
    uint32_t settings_seen[SETTINGS_SEEN]   # program_settings_index's memory: a record's index by its hash,
    uint32_t settings_last                  # and the record it found last
    Follow *follow          # while a stage reads the parts beside the compiler, else NULL
    size_t prefaulted       # parts [0, prefaulted) of the capacity are faulted in (program_prefault)
    size_t ready_parts, ready_pars, ready_extras, ready_settings    # bytes of each array faulted in
                            # ahead of the compiler by the compiler itself (arrays.pxd ready_ahead)
    bint renumber           # the compiled G-code indexes are not the driver's (program_number_parts):
                            # a part was inserted (program_merge), joined away, dropped, or is a PRINT

# program_number_parts' count, one part at a time (numbering_part)
ctypedef struct PartNumbering:
    int32_t last            # the last delivered part's index (INT32_MIN: none yet)
    bint last_programmed    # ... and it was programmed (not inserted)
    int32_t starts[AXES]    # start_gindex as compiled
    bint mapped[AXES]       # start_gindex[k] is final
    bint unmapped           # some axis is not
    int32_t next_start      # the least starts[k] of those

# The merge of parts a stage inserts (program.pyx program_merge): where insertion
# `rec` goes (after which part), and how it is built from the part before it and the
# part after it (NULL after the last part).
ctypedef size_t (*inserted_after_fn)(void *ctx, size_t rec) noexcept nogil
ctypedef void (*make_inserted_fn)(void *ctx, size_t rec, Part *out, const Part *before,
                                  const Part *after) noexcept nogil
# ... and, optionally, a last change to parts [first, end) before they move (once per
# range, in cache then): rec is the last insertion right before part `first`
# (NO_INSERTION at the start of the program).
ctypedef void (*settle_parts_fn)(void *ctx, size_t first, size_t end, size_t rec) noexcept nogil
cdef enum:
    NO_INSERTION = -1
# ... and, optionally, a stage that reads the merged parts beside the merge: told,
# every MERGE_WATCH_STEP parts or so, that parts [final_from, total) are in their final
# place (the merge moves them from the last one down).
ctypedef void (*merge_final_fn)(void *ctx, size_t final_from, size_t total) noexcept nogil
ctypedef struct MergeWatch:
    merge_final_fn final
    void *ctx
cdef enum:
    MERGE_WATCH_STEP = 16384

# ... and a stage that reads the parts beside a pass that rewrites them from the first
# one up (join_lines): told, every PARTS_WATCH_STEP parts or so, that parts [0, upto)
# are in their final place and will not change.
ctypedef void (*parts_final_fn)(void *ctx, size_t upto) noexcept nogil
ctypedef struct PartsWatch:
    parts_final_fn final
    void *ctx
cdef enum:
    PARTS_WATCH_STEP = 16384

# Hooks a stage may call while it works (all optional: NULL function = none).
# warn_fn: a numbered warning of the catalogue (errors.pxd WARN_*) with its location.
ctypedef void (*warn_fn)(void *ctx, const ErrorInfo *warning) noexcept nogil
ctypedef void (*progress_fn)(void *ctx, int percent) noexcept nogil
ctypedef void (*output_fn)(void *ctx, int tab, const char *text) noexcept nogil

# What a compilation needs; the core fills it, the compiler reads it.
ctypedef struct CompileInput:
    const char *text        # main program (NUL-terminated)
    size_t length
    int32_t file_idx
    const char *prefix      # may be NULL
    const char *postfix     # may be NULL
    int32_t prefix_idx
    int32_t postfix_idx
    GCODE_PARAMETERS params
    double user_params[100] # P00..P99 at the start
    double start[AXES]      # machine position at the start
    ToolTable tools         # the core's tool table when the compilation started (D, &, G92 D)
    uint8_t *plc            # PLC memory (PLC_MEMORY_BYTES), shared with the host
    int32_t *cancel         # set non-zero (atomically) to interrupt: the compiler returns COMPILE_CANCELLED
    progress_fn progress
    output_fn output        # compile-time messages (warnings) to the output log
    warn_fn warn            # numbered compile warnings (errors.pxd 610..): MathWarning; may be NULL
    void *ctx
    int64_t max_blocks      # limit of executed blocks (endless loops); 0 = default
    int64_t plan_window     # look-ahead of the feed planner in motion parts: 0 the vendor's 8, -1 unlimited

cdef enum CompileResult:
    COMPILE_OK = 0
    COMPILE_ERROR = -1      # ErrorInfo filled
    COMPILE_CANCELLED = -2


# ---- what other stages call
from libc.string cimport memcpy, memcmp

# a Program and its builder: empty, freed (what a failed compilation left), the
# spare room of the large arrays given back before the plan is made (core.pyx)
cdef void program_init(Program *prog) noexcept nogil
cdef void program_free(Program *prog) noexcept nogil
cdef void program_builder_init(ProgramBuilder *build) noexcept nogil
cdef void program_builder_free(ProgramBuilder *build) noexcept nogil
cdef void program_builder_trim(ProgramBuilder *build) noexcept nogil
# the compiler appends: a part (NULL: out of memory), its end, a zero offset, a G168
# rotation, a PRINT text (index or offset; -1 out of memory)
cdef Part *program_add_part(ProgramBuilder *build) noexcept nogil
cdef bint program_set_end(ProgramBuilder *build, Part *p, const double *end) noexcept nogil
cdef int program_add_zero(ProgramBuilder *build, const double *offset, const double *shift) noexcept nogil
cdef const double *part_shift(const Program *prog, const Part *p) noexcept nogil
cdef void program_number_parts(Program *prog) noexcept nogil
# ... the same one part at a time, in the program's final order (a pass that visits the
# parts anyway numbers them on the way: join_lines)
cdef void numbering_begin(PartNumbering *N, const Program *prog) noexcept nogil
cdef void numbering_part(PartNumbering *N, Program *prog, Part *p) noexcept nogil
cdef void numbering_end(PartNumbering *N, Program *prog) noexcept nogil
cdef int program_add_rotation(ProgramBuilder *build, const double *centre, const double *matrix) noexcept nogil
cdef int64_t program_add_text(ProgramBuilder *build, const char *text, size_t n) noexcept nogil
# ... a D word's signed radius (index >= 1; -1 out of memory), a G92 D (False: no memory)
cdef int program_add_radius(ProgramBuilder *build, double radius) noexcept nogil
cdef bint program_add_tool_write(ProgramBuilder *build, const ToolWrite *write) noexcept nogil
# a stage inserts parts in one backward pass (the callbacks above); False: out of memory
cdef bint program_merge(ProgramBuilder *build, size_t n_ins, void *ctx, inserted_after_fn after_of,
                        make_inserted_fn make, settle_parts_fn settle, const MergeWatch *watch) noexcept nogil
# the PartExtra of part p, added when it has none (NULL: out of memory); a stage beside
# the compiler may read the records while the compiler adds (program_grow_shared). The
# makers of program_merge take theirs from the room the merge reserved (never NULL).
cdef PartExtra *program_part_extra(ProgramBuilder *build, Part *p) noexcept nogil
# the index of a PartSettings equal to s, added when none of the recent ones is (-1: out
# of memory); entry 0, the defaults, is there once a part is. A stage beside the
# compiler may read the records while the compiler adds; program_merge reserves room
# for its makers. Most parts share the record found last: checked inline, the rest in
# program_settings_find.
cdef int64_t program_settings_find(ProgramBuilder *build, const PartSettings *s) noexcept nogil

cdef inline bint settings_equal(const PartSettings *a, const PartSettings *b) noexcept nogil:
    # bit for bit (24 bytes, no padding): a fixed-size memcmp tested for equality is
    # inlined as word compares
    return memcmp(a, b, sizeof(PartSettings)) == 0

cdef inline int64_t program_settings_index(ProgramBuilder *build, const PartSettings *s) noexcept nogil:
    if build.settings_last < build.prog.n_settings and settings_equal(&build.prog.settings[build.settings_last], s):
        return build.settings_last
    return program_settings_find(build, s)
# a memory hint for the parts: pages faulted in ahead of their writer
cdef bint program_prefault(ProgramBuilder *build, size_t first, size_t count, size_t limit) noexcept nogil

# a part's programmed end and start (all ten axes; x y z of the start), its
# compensated start, and its API view (SIMPLE_GM_PARAMS); its length: geometry.pxd
cdef inline void part_end(const Program *prog, const Part *p, double *out) noexcept nogil:
    out[0] = p.e[0]; out[1] = p.e[1]; out[2] = p.e[2]
    memcpy(out + 3, &prog.axes[OTHER_AXES * p.axes_idx], OTHER_AXES * sizeof(double))


# the address cell a part's own function fills (G of a motion or a dwell, M of an M
# function or a PRINT): its bit is set in pars_mask, its value is Part.func and is not
# stored in Program.pars (a float a part less)
cdef inline int part_own_cell(const Part *p) noexcept nogil:
    return 6 if p.kind == PART_MOTION or p.kind == PART_DWELL else 12


cdef inline const PartSettings *part_settings(const Program *prog, const Part *p) noexcept nogil:
    return &prog.settings[p.settings]


# the zero record of the parts without a PartExtra (zero-initialised, never written)
cdef PartExtra NO_EXTRA

cdef inline bint part_has_extra(const Part *p) noexcept nogil:
    # a PRINT part's `extra` is its text's offset
    return p.extra != 0 and p.kind != PART_PRINT

cdef inline const PartExtra *part_extra(const Program *prog, const Part *p) noexcept nogil:
    return &prog.extras[p.extra] if part_has_extra(p) else &NO_EXTRA


# a compensated arc's tool-path radius (a part without a record is no arc: nothing to set)
cdef inline void part_set_radius(Program *prog, const Part *p, double radius) noexcept nogil:
    if part_has_extra(p):
        prog.extras[p.extra].radius = radius


cdef inline const double *part_start_xyz(const Program *prog, size_t i) noexcept nogil:
    # the previous part's end, or the program start
    if i > 0:
        return prog.parts[i - 1].e
    return prog.start

# the signed tool radius of a compensated part: its D word's, else correction[] of its
# slot (params: the G-code parameters the stage runs with)
cdef inline double part_tool_radius(const Program *prog, const GCODE_PARAMETERS *params,
                                    const Part *p) noexcept nogil:
    if p.radius_idx != 0:
        return prog.radii[p.radius_idx]
    return params.correction[p.comp_slot & 7].size

cdef void part_calc_start(const Program *prog, size_t i, double *out) noexcept nogil
cdef void part_to_gm(const Program *prog, size_t i, SIMPLE_GM_PARAMS *gm) noexcept nogil
# a part a stage inserts after `after` (starting at its end, its programmed end there),
# with the line, settings and compensation of `src` under `after`'s G168 rotation (a
# maker of program_merge: a settings record from its reserve when they differ); the
# caller sets its geometry
cdef void part_inserted(ProgramBuilder *build, Part *q, const Part *after, const Part *src, int32_t func,
                        int16_t plane) noexcept nogil
