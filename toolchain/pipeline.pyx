# Stages side by side: a stage that only needs the parts before the one it works on
# (the compensation) runs in a thread of its own on the parts the compiler has
# finished, so on a large program it costs little more than its tail once the
# compiler ends. Between batches the thread also faults in the memory the compiler
# and the compensation's merge will write next (program_prefault), which is most of
# the cost of writing fresh memory. The hand-over (Follow, pipeline.pxd):
#   - the compiler publishes the parts it will not touch again at its periodic check
#     (every 1024 blocks, when at least FOLLOW_BATCH new parts are final); the first
#     publication starts the thread;
#   - the consumer reads the published parts and the arrays the compiler only appends
#     to under follow_pause (parts, strategy regions), nothing else the compiler writes;
#   - follow_finish hands over the rest and joins; the consumer's first failure is
#     its result. A program that never published (small) is consumed in the
#     caller's thread: the same consumer, the same order;
#   - while no batch waits, the thread faults in the part memory ahead of the
#     compiler, as far as the consumer's queued insertions plus PREFAULT_AHEAD parts;
#     when less than PREFAULT_LOW parts are ready ahead of the published ones, that
#     comes first even when a batch waits (a busy consumer, as the compensation of
#     many short contours, would otherwise leave the zeroing to the compiler); a
#     consumer that fell behind takes at most FOLLOW_TAKE parts at a time.
# After the compiler, in the order they run: the extent measured beside the
# compensation's merge (ExtentBeside), then the plan made beside the joins (PlanAhead),
# else in two ranges beside the extent when that was not measured yet
# (plan_beside_extent).
from libc.string cimport memset


cdef void follow_init(Follow *F, ProgramBuilder *build, consume_fn consume, void *ctx) noexcept nogil:
    """A Follow for `consume` on build's parts, not started yet (follow_publish starts its
    thread at the first batch)."""
    memset(F, 0, sizeof(Follow))
    F.build = build
    F.consume = consume
    F.ctx = ctx
    F.result = COMPILE_OK
    pthread_mutex_init(&F.lock, NULL)
    pthread_cond_init(&F.cond, NULL)


cdef void follow_destroy(Follow *F) noexcept nogil:
    """Frees the Follow's lock and condition once its thread is joined."""
    pthread_cond_destroy(&F.cond)
    pthread_mutex_destroy(&F.lock)


cdef void *_follow_body(void *arg) noexcept nogil:
    """Takes the batches as they come; while there is none, or while the memory
    readied ahead of the compiler runs short, readies it a chunk at a time."""
    cdef Follow *F = <Follow *>arg
    cdef size_t taken = 0, upto, more = 0, ready = 0
    cdef bint last, low
    cdef int res
    tc_set_stage("the compensation")
    pthread_mutex_lock(&F.lock)
    while not F.stop:
        if F.paused:
            pthread_cond_wait(&F.cond, &F.lock)
            continue
        # while the consumer keeps up, the memory just ahead of the compiler comes
        # before a batch (a compiler that reaches memory not readied zeroes it itself,
        # on the path that counts); one that falls behind leaves it to the compiler,
        # which then waits for it less at the end
        low = not F.done and ready > 0 and F.build.prefaulted < F.published + PREFAULT_LOW \
            and F.published - taken <= FOLLOW_TAKE
        if low and ready < F.published + PREFAULT_AHEAD:
            ready = F.published + PREFAULT_AHEAD    # the compiler is ahead of the batches taken
        if (F.published > taken or F.done) and not low:
            upto = F.published
            last = F.done
            if upto - taken > FOLLOW_TAKE:
                # a consumer that fell behind takes the parts in steps, the memory
                # ahead of the compiler readied between them
                upto = taken + FOLLOW_TAKE
                last = False
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
    """The compiler, after it moved an array the consumer reads: the consumer may go on. F may
    be NULL."""
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


cdef void *_extent_beside_body(void *arg) noexcept nogil:
    """The extent's thread: measures each range of parts as the merge makes it final, from the
    top down (both extents, and as written when G168 rotates), until every part is measured or
    the merge failed."""
    cdef ExtentBeside *E = <ExtentBeside *>arg
    cdef const Program *prog = E.prog
    cdef size_t lo, hi, last
    cdef bint written = prog.n_rotations > 1
    tc_set_stage("the extent")
    pthread_mutex_lock(&E.lock)
    hi = E.total
    while True:
        while not (E.quit or E.done or E.final_from + 1 < hi):
            pthread_cond_wait(&E.cond, &E.lock)
        if E.quit:
            break
        lo = 0 if E.done else E.final_from + 1
        pthread_mutex_unlock(&E.lock)
        last = extent_range(prog, lo, hi, &E.programmed[0], &E.tool[0], True)
        if written:
            extent_range(prog, lo, hi, &E.programmed[1], &E.tool[1], False)
        if E.last == NO_MOTION:
            E.last = last                   # the ranges come from the top down
        pthread_mutex_lock(&E.lock)
        hi = lo
        if hi == 0:
            break
    pthread_mutex_unlock(&E.lock)
    return NULL


cdef void _extent_beside_final(void *ctx, size_t final_from, size_t total) noexcept nogil:
    """The merge's MergeWatch.final: parts [final_from, total) are final; the first call starts
    the extent's thread, later ones wake it."""
    cdef ExtentBeside *E = <ExtentBeside *>ctx
    pthread_mutex_lock(&E.lock)
    E.final_from = final_from
    if not E.started:
        E.total = total
        E.started = pthread_create(&E.thread, NULL, _extent_beside_body, E) == 0
    pthread_cond_broadcast(&E.cond)
    pthread_mutex_unlock(&E.lock)


cdef void extent_beside_begin(ExtentBeside *E, const Program *prog) noexcept nogil:
    """Before the compensation's merge: the extent's state, and the watch the merge calls as
    parts become final (its thread starts at the first)."""
    memset(E, 0, sizeof(ExtentBeside))
    E.prog = prog
    E.last = NO_MOTION
    E.watch.final = _extent_beside_final
    E.watch.ctx = E
    pthread_mutex_init(&E.lock, NULL)
    pthread_cond_init(&E.cond, NULL)
    extent_begin(prog, &E.programmed[0], &E.tool[0])
    extent_begin(prog, &E.programmed[1], &E.tool[1])


cdef bint extent_beside_end(ExtentBeside *E, bint merged, GCODE_INFO *extent) noexcept nogil:
    """After the merge (`merged`: it succeeded): True with `extent` filled when the
    thread measured the whole program, False when it never started (measure the
    extent otherwise)."""
    cdef bint measured
    pthread_mutex_lock(&E.lock)
    measured = E.started and merged
    E.done = measured
    E.quit = not measured
    pthread_cond_broadcast(&E.cond)
    pthread_mutex_unlock(&E.lock)
    if E.started:
        pthread_join(E.thread, NULL)
    pthread_cond_destroy(&E.cond)
    pthread_mutex_destroy(&E.lock)
    if not measured:
        return False
    extent_finish(E.prog, E.last, E.programmed, E.tool, extent)
    return True


cdef void *_plan_body(void *arg) noexcept nogil:
    """The plan's second thread: plans its range [first, n_parts) of the program."""
    cdef PlanJob *job = <PlanJob *>arg
    tc_set_stage("the plan")
    job.result = plan_range(job.prog, job.params, job.enhanced, job.window, job.first, job.prog.n_parts)
    return NULL


cdef int plan_beside_extent(ProgramBuilder *build, const GCODE_PARAMETERS *params, uint32_t enhanced,
                            int64_t window, GCODE_INFO *extent, bint measured) noexcept nogil:
    """plan_program's result; the extent is measured either way (after the plan's
    insertions when it makes some), unless `measured` says it is already (beside the
    merge): then the two threads share the plan alone, split near the middle."""
    cdef Program *prog = &build.prog
    cdef size_t n = prog.n_parts
    cdef int result
    if prog.n_parts < PLAN_BESIDE_MIN or mfunc_insert_wanted(params):
        result = plan_program(build, params, enhanced, window)
        if not measured or prog.n_parts != n:
            program_extent(prog, extent)
        return result
    if measured:
        return plan_in_two(prog, params, enhanced, window, plan_split_at(prog, prog.n_parts / 2), NULL)
    return plan_in_two(prog, params, enhanced, window, plan_split_at(prog, prog.n_parts / 8 * 3), extent)


cdef int plan_in_two(Program *prog, const GCODE_PARAMETERS *params, uint32_t enhanced, int64_t window,
                     size_t split, GCODE_INFO *extent) noexcept nogil:
    """Parts [split, n) planned in a thread of its own (all of them when split is 0)
    while this one measures the extent (unless `extent` is NULL) and plans [0,
    split). COMPILE_OK, or COMPILE_ERROR when out of memory (no plan)."""
    cdef PlanJob job
    cdef pthread_t thread
    cdef bint started
    cdef int result
    if not plan_alloc(prog, params, enhanced, window):
        if extent != NULL:
            program_extent(prog, extent)
        return COMPILE_ERROR
    job.prog = prog
    job.params = params
    job.enhanced = enhanced
    job.window = window
    job.first = split
    job.result = COMPILE_ERROR
    started = pthread_create(&thread, NULL, _plan_body, &job) == 0
    if extent != NULL:
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


cdef void _ahead_final(void *ctx, size_t upto) noexcept nogil:
    """The joins' watch (PartsWatch): parts [0, upto) are final; the thread is woken
    to plan them."""
    cdef PlanAhead *A = <PlanAhead *>ctx
    pthread_mutex_lock(&A.lock)
    A.final_upto = upto
    pthread_cond_broadcast(&A.cond)
    pthread_mutex_unlock(&A.lock)


cdef void *_ahead_body(void *arg) noexcept nogil:
    """Plans ranges from the front: each from `front` to a part where the machine
    stands at least PLAN_AHEAD_STEP parts on among the final ones, the rest up to
    `back` once the joins are over."""
    cdef PlanAhead *A = <PlanAhead *>arg
    cdef size_t first, end, limit, s
    cdef int res
    tc_set_stage("the plan")
    pthread_mutex_lock(&A.lock)
    while not A.stop and A.result == COMPILE_OK and A.front < A.back:
        first = A.front
        limit = A.back if A.joined else A.final_upto
        pthread_mutex_unlock(&A.lock)
        s = plan_split_between(&A.view, first + PLAN_AHEAD_STEP, limit) if first + PLAN_AHEAD_STEP < limit else 0
        pthread_mutex_lock(&A.lock)
        if A.stop or A.result != COMPILE_OK or A.front >= A.back:
            break
        if s == 0 or s > A.back:
            if not A.joined:
                pthread_cond_wait(&A.cond, &A.lock)     # more final parts, or the joins' end
                continue
            s = A.back                  # the rest: the other thread plans from back down
        end = s
        A.front = end
        pthread_mutex_unlock(&A.lock)
        res = plan_range(&A.view, A.params, A.enhanced, A.window, first, end)
        pthread_mutex_lock(&A.lock)
        if res != COMPILE_OK:
            A.result = res
    pthread_mutex_unlock(&A.lock)
    return NULL


cdef bint plan_ahead_begin(PlanAhead *A, ProgramBuilder *build, const GCODE_PARAMETERS *params,
                           uint32_t enhanced, int64_t window) noexcept nogil:
    """Allocates the plan for the parts as they are (the joins only take some away)
    and starts the thread; False (nothing started, the plan maybe allocated) when the
    program does not take this way or no thread can be had."""
    cdef Program *prog = &build.prog
    cdef double tol_angle = params.tolerance[2]
    memset(A, 0, sizeof(PlanAhead))
    if (prog.n_parts < PLAN_BESIDE_MIN or mfunc_insert_wanted(params) or prog.n_plan_regions > 0
            or not (tol_angle > 0.0 and tol_angle < 90.0)):
        return False
    if not plan_alloc(prog, params, enhanced, window):
        return False
    A.view = prog[0]
    A.params = params
    A.enhanced = enhanced
    A.window = window
    A.watch.final = _ahead_final
    A.watch.ctx = A
    A.back = prog.n_parts
    A.result = COMPILE_OK
    pthread_mutex_init(&A.lock, NULL)
    pthread_cond_init(&A.cond, NULL)
    A.started = pthread_create(&A.thread, NULL, _ahead_body, A) == 0
    if not A.started:
        pthread_cond_destroy(&A.cond)
        pthread_mutex_destroy(&A.lock)
    return A.started


cdef int plan_ahead_end(PlanAhead *A, ProgramBuilder *build, bint joined, GCODE_INFO *extent,
                        bint measured) noexcept nogil:
    """After join_lines: the extent (unless `measured`), then ranges from the end down
    until the thread's meet them; joins the thread. COMPILE_OK, or COMPILE_ERROR when
    out of memory (no plan) or the joins failed."""
    cdef Program *prog = &build.prog
    cdef size_t first, end, s
    cdef int res
    pthread_mutex_lock(&A.lock)
    if joined:
        A.joined = True
        A.back = prog.n_parts
        A.final_upto = prog.n_parts
    else:
        A.stop = True
    pthread_cond_broadcast(&A.cond)
    pthread_mutex_unlock(&A.lock)
    if joined:
        # (the thread reads the parts through its view of the program as it was, with
        # more parts: a range's plan does not depend on how many parts follow it)
        if not measured:
            program_extent(prog, extent)
        pthread_mutex_lock(&A.lock)
        while A.result == COMPILE_OK and A.front < A.back:
            first = A.front
            end = A.back
            pthread_mutex_unlock(&A.lock)
            s = plan_split_before(prog, end - PLAN_AHEAD_STEP, first) if end > first + PLAN_AHEAD_STEP else 0
            pthread_mutex_lock(&A.lock)
            if A.result != COMPILE_OK or A.front >= A.back:
                break
            if s <= A.front:
                s = A.front                 # the rest: the thread's front takes no more
            A.back = s
            pthread_mutex_unlock(&A.lock)
            res = plan_range(prog, A.params, A.enhanced, A.window, s, end)
            pthread_mutex_lock(&A.lock)
            if res != COMPILE_OK:
                A.result = res
        pthread_mutex_unlock(&A.lock)
    pthread_join(A.thread, NULL)
    pthread_cond_destroy(&A.cond)
    pthread_mutex_destroy(&A.lock)
    res = A.result if joined else COMPILE_ERROR
    if res != COMPILE_OK:
        plan_drop(prog)
        return res
    if prog.n_parts < A.view.n_parts:
        resize(<void **>&prog.plan, prog.n_parts, sizeof(PartPlan))    # the joins took parts away
    return COMPILE_OK
