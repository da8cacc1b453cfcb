# Face of pipeline.pyx: the compile stages side by side. The compensation runs in a
# thread of its own on the parts the compiler has finished (Follow); the extent is
# measured beside the compensation's merge (ExtentBeside); the plan runs in two ranges
# beside the extent (plan_beside_extent). Owns the hand-over between the threads.
# Called by the core's compile worker (it wires the stages), the compiler (it
# publishes its parts) and whoever grows an array the thread beside the compiler
# reads (program.pyx, strategy.pyx: follow_pause / follow_resume).

# A stage that reads the parts while the compiler still writes them, in a thread of
# its own (pipeline.pyx; the compensation): the compiler hands over the parts as they
# become final, and growth of an array the stage reads waits until it is between
# batches. Everything but `started` is guarded by `lock`.
ctypedef int (*consume_fn)(void *ctx, size_t upto, bint last, size_t *more) noexcept nogil

cdef struct Follow:
    consume_fn consume      # takes parts [previous upto, upto); last: the program is complete;
    void *ctx               # more: parts it will insert later (their memory is readied too)
    ProgramBuilder *build
    pthread_mutex_t lock
    pthread_cond_t cond
    pthread_t thread
    size_t published        # parts [0, published) are final
    int result              # the consumer's first result other than COMPILE_OK
    bint started            # the thread runs (only the compiler's thread reads or writes it)
    bint done               # published is the whole program
    bint stop               # give up (compile error, cancel)
    bint paused             # the compiler grows an array: start no batch
    bint busy               # a batch is being consumed
    bint ended              # the thread has consumed its last batch

cdef enum:
    FOLLOW_BATCH = 4096     # parts: fewer are not worth waking the thread for
    FOLLOW_TAKE = 4096      # parts the thread consumes at most between two looks at the memory ahead
    # (the compiler readies what the thread has not a megabyte at a time itself, and
    # what is readied beyond the last part is in the peak memory: docs/benchmarks.md)
    PREFAULT_AHEAD = 16384  # parts (1.4 MB) whose memory the thread readies ahead of the compiler
    PREFAULT_CHUNK = 4096   # parts (360 kB) readied at a time between batches
    PREFAULT_LOW = 8192     # parts readied ahead of the published ones below which that comes before a batch

# The extent measured beside the compensation's merge (program_merge), which moves
# the parts from the last one down: a thread measures each range of parts as soon as
# the merge tells it is final, on the core that has nothing else to do then (the
# compensation's own thread has ended). Each range starts one part above the lowest
# final one, whose end is its start; the merge's end makes the rest final. The thread
# starts with the merge's first notice (programs of fewer than MERGE_WATCH_STEP moved
# parts get none: their extent is measured beside the plan, below).
ctypedef struct ExtentBeside:
    const Program *prog
    MergeWatch watch        # given to program_merge
    pthread_mutex_t lock
    pthread_cond_t cond
    pthread_t thread
    bint started            # the thread runs (set under `lock` by the merge's thread)
    size_t final_from       # parts [final_from, total) are final (guarded by `lock`)
    size_t total
    bint done               # the merge ended: every part is final
    bint quit               # the merge failed: stop
    # the thread's: both extents as the machine runs the program, [1] as it is
    # written (with G168 rotations only), and the last motion part
    GCODE_SIZE programmed[2]
    GCODE_SIZE tool[2]
    size_t last

# The finished program's plan (planner/) and its extent (extent.pyx) side by side:
# both only read the parts. A thread of its own plans the program from a part where
# the machine stands (plan_split_at) on, while this thread measures the extent and
# then plans the parts before that part; the plan is the same as in one piece. The
# split is taken near 3/8 of the parts: the extent's pass costs about a quarter of the
# planner's per part, so both threads end about together. Small programs, and
# programs whose plan inserts M functions (mFuncInsertTable), plan in one piece in
# this thread, as does everything when no thread can be had.
cdef enum:
    PLAN_BESIDE_MIN = 4096      # parts: fewer are not worth a thread

ctypedef struct PlanJob:
    Program *prog
    const GCODE_PARAMETERS *params
    uint32_t enhanced
    int64_t window
    size_t first
    int result


# The plan made beside the joins (join_lines), which rewrite the parts from the first
# one up: a thread plans the parts the joins have finished, a range at a time from a
# part where the machine stands to the next one at least PLAN_AHEAD_STEP parts on (the
# plan is the same as in one piece); once the joins are done, their thread measures
# the extent (when the merge's thread has not) and plans from the program's end down
# while the other goes on up, each range claimed under `lock`, until they meet. Taken
# when the joins run (tolerance[2]) and the plan would be split anyway: not for small
# programs, programs whose plan inserts M functions, or programs with G900 / M-5
# regions (the joins renumber them).
cdef enum:
    PLAN_AHEAD_STEP = 32768     # parts: a range at least this long, where the program allows

ctypedef struct PlanAhead:
    Program view            # the program's header when the joins began: the plan reads the
                            # parts through it (the joins change prog.n_parts)
    const GCODE_PARAMETERS *params
    uint32_t enhanced
    int64_t window
    PartsWatch watch        # given to join_lines
    pthread_mutex_t lock
    pthread_cond_t cond
    pthread_t thread
    bint started
    size_t final_upto       # parts [0, final_upto) are final (guarded by `lock`)
    size_t front            # the thread plans the parts from here on (guarded)
    size_t back             # ... below here: the joins' thread planned the rest (guarded)
    bint joined             # the joins are over: back is the program's end at first (guarded)
    bint stop               # the joins failed: plan no more
    int result              # COMPILE_ERROR: a range ran out of memory (guarded)

# ---- what other stages call
# the stage beside the compiler: set up, torn down; the compiler publishes parts
# [0, n), pauses the thread while it grows an array it reads, hands over the rest and
# joins (the consumer's first failure), or abandons it (a compile error, a cancel)
cdef void follow_init(Follow *F, ProgramBuilder *build, consume_fn consume, void *ctx) noexcept nogil
cdef void follow_destroy(Follow *F) noexcept nogil
cdef void follow_publish(Follow *F, size_t n) noexcept nogil
cdef void follow_pause(Follow *F) noexcept nogil
cdef void follow_resume(Follow *F) noexcept nogil
cdef int follow_finish(Follow *F, size_t n) noexcept nogil
cdef void follow_abandon(Follow *F) noexcept nogil
# the extent beside the compensation's merge, and the plan beside the extent
cdef void extent_beside_begin(ExtentBeside *E, const Program *prog) noexcept nogil
cdef bint extent_beside_end(ExtentBeside *E, bint merged, GCODE_INFO *extent) noexcept nogil
cdef int plan_beside_extent(ProgramBuilder *build, const GCODE_PARAMETERS *params, uint32_t enhanced,
                            int64_t window, GCODE_INFO *extent, bint measured) noexcept nogil
# ... or the plan beside the joins: begun before join_lines (False: not taken, plan
# beside the extent afterwards), ended after it (`joined`: it succeeded) with the
# extent measured unless `measured`; plan_ahead_end's result is plan_program's
cdef bint plan_ahead_begin(PlanAhead *A, ProgramBuilder *build, const GCODE_PARAMETERS *params,
                           uint32_t enhanced, int64_t window) noexcept nogil
cdef int plan_ahead_end(PlanAhead *A, ProgramBuilder *build, bint joined, GCODE_INFO *extent,
                        bint measured) noexcept nogil
