# Stages side by side: a stage that only needs the parts before the one it works on
# (the compensation) runs in a thread of its own on the parts the compiler has
# finished, so on a large program it costs little more than its tail once the
# compiler ends. Between batches the thread also faults in the memory the compiler
# and the compensation's merge will write next (program_prefault), which is most of
# the cost of writing fresh memory. The hand-over (Follow, program.pxd):
#   - the compiler publishes the parts it will not touch again at its periodic check
#     (every 1024 blocks, when at least FOLLOW_BATCH new parts are final); the first
#     publication starts the thread;
#   - the consumer reads the published parts and the arrays the compiler only appends
#     to under follow_pause (parts, strategy regions), nothing else the compiler writes;
#   - follow_finish hands over the rest and joins; the consumer's first failure is
#     its result. A program that never published (small) is consumed in the
#     caller's thread: the same consumer, the same order;
#   - while no batch waits, the thread faults in the part memory ahead of the
#     compiler, as far as the consumer's queued insertions plus PREFAULT_AHEAD parts.
from libc.string cimport memset

cdef enum:
    FOLLOW_BATCH = 4096     # parts: fewer are not worth waking the thread for
    PREFAULT_AHEAD = 65536  # parts (10 MB) whose memory the thread readies ahead of the compiler
    PREFAULT_CHUNK = 16384  # parts (2.4 MB) readied at a time between batches


cdef void follow_init(Follow *F, ProgramBuilder *build, consume_fn consume, void *ctx) noexcept nogil:
    memset(F, 0, sizeof(Follow))
    F.build = build
    F.consume = consume
    F.ctx = ctx
    F.result = COMPILE_OK
    pthread_mutex_init(&F.lock, NULL)
    pthread_cond_init(&F.cond, NULL)


cdef void follow_destroy(Follow *F) noexcept nogil:
    pthread_cond_destroy(&F.cond)
    pthread_mutex_destroy(&F.lock)


cdef void *_follow_body(void *arg) noexcept nogil:
    """Takes the batches as they come; while there is none, readies memory ahead of
    the compiler a chunk at a time (the batches come first)."""
    cdef Follow *F = <Follow *>arg
    cdef size_t taken = 0, upto, more = 0, ready = 0
    cdef bint last
    cdef int res
    pthread_mutex_lock(&F.lock)
    while not F.stop:
        if F.paused:
            pthread_cond_wait(&F.cond, &F.lock)
            continue
        if F.published > taken or F.done:
            upto = F.published
            last = F.done
            F.busy = True
            pthread_mutex_unlock(&F.lock)
            res = F.consume(F.ctx, upto, last, &more)
            pthread_mutex_lock(&F.lock)
            F.busy = False
            taken = upto
            ready = upto + more + PREFAULT_AHEAD
            pthread_cond_broadcast(&F.cond)     # a compiler waiting in follow_pause
            if res != COMPILE_OK:
                F.result = res
                break
            if last:
                break
        elif F.build.prefaulted < ready:
            upto = F.published                  # the compiler is at least there
            F.busy = True
            pthread_mutex_unlock(&F.lock)
            if not program_prefault(F.build, upto, PREFAULT_CHUNK, ready):
                ready = 0                       # nothing more to do (or not supported)
            pthread_mutex_lock(&F.lock)
            F.busy = False
            pthread_cond_broadcast(&F.cond)
        else:
            pthread_cond_wait(&F.cond, &F.lock)
    F.ended = True
    pthread_mutex_unlock(&F.lock)
    return NULL


cdef void follow_publish(Follow *F, size_t n) noexcept nogil:
    """The compiler: parts [0, n) are final. F may be NULL."""
    if F == NULL:
        return
    if not F.started:
        if n < FOLLOW_BATCH:
            return
        F.published = n
        # no thread (resources): follow_finish consumes everything in the caller's thread
        F.started = pthread_create(&F.thread, NULL, _follow_body, F) == 0
        return
    pthread_mutex_lock(&F.lock)
    if n >= F.published + FOLLOW_BATCH and not F.ended:
        F.published = n
        pthread_cond_broadcast(&F.cond)
    pthread_mutex_unlock(&F.lock)


cdef void follow_pause(Follow *F) noexcept nogil:
    """The compiler, before it moves an array the consumer reads: waits until the
    consumer is between batches and keeps it there until follow_resume. F may be
    NULL (no stage beside the compiler)."""
    if F == NULL or not F.started:
        return
    pthread_mutex_lock(&F.lock)
    F.paused = True
    while F.busy:
        pthread_cond_wait(&F.cond, &F.lock)
    pthread_mutex_unlock(&F.lock)


cdef void follow_resume(Follow *F) noexcept nogil:
    if F == NULL or not F.started:
        return
    pthread_mutex_lock(&F.lock)
    F.paused = False
    pthread_cond_broadcast(&F.cond)
    pthread_mutex_unlock(&F.lock)


cdef int follow_finish(Follow *F, size_t n) noexcept nogil:
    """All n parts are final: the consumer takes the rest and ends; its result."""
    cdef size_t more
    if not F.started:
        return F.consume(F.ctx, n, True, &more)
    pthread_mutex_lock(&F.lock)
    F.published = n
    F.done = True
    pthread_cond_broadcast(&F.cond)
    pthread_mutex_unlock(&F.lock)
    pthread_join(F.thread, NULL)
    F.started = False
    return F.result


cdef void follow_abandon(Follow *F) noexcept nogil:
    """The compilation failed or was cancelled: the consumer stops after its batch."""
    if not F.started:
        return
    pthread_mutex_lock(&F.lock)
    F.stop = True
    pthread_cond_broadcast(&F.cond)
    pthread_mutex_unlock(&F.lock)
    pthread_join(F.thread, NULL)
    F.started = False


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


cdef void *_plan_body(void *arg) noexcept nogil:
    cdef PlanJob *job = <PlanJob *>arg
    job.result = plan_range(job.prog, job.params, job.enhanced, job.window, job.first, job.prog.n_parts)
    return NULL


cdef int plan_beside_extent(ProgramBuilder *build, const GCODE_PARAMETERS *params, uint32_t enhanced,
                            int64_t window, GCODE_INFO *extent) noexcept nogil:
    """plan_program's result; the extent is measured either way (after the plan's
    insertions when it makes some)."""
    cdef Program *prog = &build.prog
    cdef int result
    if prog.n_parts < PLAN_BESIDE_MIN or mfunc_insert_wanted(params):
        result = plan_program(build, params, enhanced, window)
        program_extent(prog, extent)
        return result
    return plan_in_two(prog, params, enhanced, window, plan_split_at(prog, prog.n_parts / 8 * 3), extent)


cdef int plan_in_two(Program *prog, const GCODE_PARAMETERS *params, uint32_t enhanced, int64_t window,
                     size_t split, GCODE_INFO *extent) noexcept nogil:
    """Parts [split, n) planned in a thread of its own (all of them when split is 0)
    while this one measures the extent and plans [0, split). COMPILE_OK, or
    COMPILE_ERROR when out of memory (no plan)."""
    cdef PlanJob job
    cdef pthread_t thread
    cdef bint started
    cdef int result
    if not plan_alloc(prog):
        program_extent(prog, extent)
        return COMPILE_ERROR
    job.prog = prog
    job.params = params
    job.enhanced = enhanced
    job.window = window
    job.first = split
    job.result = COMPILE_ERROR
    started = pthread_create(&thread, NULL, _plan_body, &job) == 0
    program_extent(prog, extent)
    result = plan_range(prog, params, enhanced, window, 0, split)
    if started:
        pthread_join(thread, NULL)
    else:
        _plan_body(&job)
    if result != COMPILE_OK or job.result != COMPILE_OK:
        plan_drop(prog)
        return COMPILE_ERROR
    return COMPILE_OK
