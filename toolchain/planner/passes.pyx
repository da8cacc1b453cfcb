# The look-ahead: every motion part gets an entry, peak and exit speed such that
# the machine can still stop at the end of what it sees. The vendor's interpolator
# sees the current section and the next 7 (its look-ahead table, docs/vendor-sources.md;
# a section is a motion, continuous M functions ride inside one), so the default window
# is 8 motion parts; a deeper window only lets parts run faster. One sweep over the
# program with a ring of the visible parts:
#   backward: from a stop at the window's end (or the program's end), the highest
#             entry speed of each visible part (its junction limit, or what it can
#             still brake away within its length): plan_backward, which the offline
#             machine runs over its own look-ahead too;
#   forward:  from the previous exit, the part's profile (profile.pyx), exiting at
#             most at the next part's backward limit.
# The backward limits are recomputed only when the window's end moves (an
# unlimited window: once), and only back to the first that does not change: at most
# O(parts x window), O(parts) where the junctions' limits bind. The sweep may start
# and end at a part where the machine stands (plan_range): two ranges plan at once
# (pipeline.pyx) and give the same plan.
from libc.stdlib cimport free
from libc.math cimport sqrt, HUGE_VAL
from libc.string cimport memcpy

cdef extern from *:
    """
    /* the float nearest x from below, x >= 0 (or inf): one step down when the
       conversion rounded up */
    static inline float tc_float_below(double x) {
        float f = (float)x;
        uint32_t bits;
        if (f > x) {
            memcpy(&bits, &f, sizeof(bits));
            bits -= 1;
            memcpy(&f, &bits, sizeof(f));
        }
        return f;
    }
    """
    # the limits a node plans with, as PartPlan keeps them: the plan is made with what it holds
    float _float_below "tc_float_below" (double x) noexcept nogil


cdef void _take_classes(NodeSource *src, const PlanRegion *s) noexcept nogil:
    """The values every plain line of the settings s shares (as part_limits takes them)."""
    cdef const GCODE_FEED *cls
    cdef int32_t ramp
    cdef int c
    src.class_region = src.cursor.region
    src.plain_lines = (not src.cursor.axes_limited
                       and (s.ignore_feed | ((src.enhanced >> ENH_FEED_SHIFT) & AXIS_MASK)) == 0)
    for c in range(2):
        cls = &s.motion[c]
        ramp = RAMP_SINE if cls.rampType == RAMP_SINE else RAMP_TRAPEZOID
        src.class_ramp[c] = ramp
        src.class_acc[c] = _float_below(ramp_equivalent_acc(limit_or_none(cls.acc), ramp))
        src.class_dec[c] = _float_below(ramp_equivalent_acc(limit_or_none(cls.dec), ramp))


cdef inline void _node_segment(const NodeSource *src, size_t k, Segment *g) noexcept nogil:
    """Part k's geometry: as compiled, or as the placed run sees it where it may differ."""
    if src.pl != NULL and k < src.reshaped_end:
        segment_of_placed_part(src.prog, k, src.pl, g)
    else:
        segment_of_part(src.prog, k, g)


cdef bint _general_node(NodeSource *src, size_t k, const PlanRegion *s, bint want_tangent,
                        PlanNode *node, double *t_start, double *t_end) noexcept nogil:
    """Length and limits of a motion part that is not a plain line (its segment,
    part_limits), its end tangents when want_tangent; False when it has no length."""
    cdef Segment g
    cdef PartLimits lim
    _node_segment(src, k, &g)
    if g.length <= LENGTH_EPS:
        return False
    part_limits(&g, src.prog, &src.prog.parts[k], src.params, s, src.cursor.axes_limited, src.enhanced, &lim)
    node.length = g.length
    node.vmax = _float_below(lim.vmax)
    node.ceiling = _float_below(lim.v_ceiling)
    node.acc = _float_below(ramp_equivalent_acc(lim.acc, lim.ramp))
    node.dec = _float_below(ramp_equivalent_acc(lim.dec, lim.ramp))
    node.ramp = lim.ramp
    if want_tangent:
        segment_tangent(&g, 0.0, t_start)
        segment_tangent(&g, g.length, t_end)
    return True


cdef void _end_tangent(const NodeSource *src, size_t k, double *t) noexcept nogil:
    """The tangent of part k at its end (its segment as the plan sees it: placed or as
    compiled)."""
    cdef Segment g
    _node_segment(src, k, &g)
    segment_tangent(&g, g.length, t)


cdef bint _next_node(NodeSource *src, PlanNode *node) noexcept nogil:
    """Reads part `scan`; True when it is a node (filled in)."""
    cdef size_t k = src.scan
    cdef const Part *p = &src.prog.parts[k]
    cdef const Part *prev
    cdef const PlanRegion *s = cursor_settings(&src.cursor, k)
    cdef double t0[AXES]
    cdef double t1[AXES]
    cdef double jin, cosine, vmax, d0, d1, d2, inv
    cdef bint rapid, want_angle, want_tangent, plain
    cdef uint32_t stop_axes
    cdef int c
    src.scan += 1
    if p.kind != PART_MOTION:
        if part_stops_motion(p):
            src.stop_pending = True
        return False
    node.seq = src.motions
    src.motions += 1
    if src.class_region != src.cursor.region:
        _take_classes(src, s)
    want_angle = s.startAngle < 180.0           # below 180 some angle slows down
    stop_axes = axis_stop_axes(src.enhanced, s.ignore_angle)    # bits 20, 21
    want_tangent = want_angle or stop_axes != 0
    rapid = p.func == 0
    plain = (src.plain_lines and p.func != 2 and p.func != 3 and k > 0
             and src.prog.parts[k - 1].axes_idx == p.axes_idx and k >= src.reshaped_end)
    if plain:                                   # a line over x y z
        prev = &src.prog.parts[k - 1]
        d0 = p.ce[0] - prev.ce[0]
        d1 = p.ce[1] - prev.ce[1]
        d2 = p.ce[2] - prev.ce[2]
        node.length = sqrt(d0 * d0 + d1 * d1 + d2 * d2)     # segment_of_part's
        if node.length <= LENGTH_EPS:
            return False                        # no motion: the speed passes through
        vmax = part_feed(src.prog, p, src.params) / 60.0  # part_limits' limits of a plain line
        node.vmax = _float_below(vmax if vmax > 0.0 else 1.0 / 60.0)
        node.ceiling = HUGE_VAL                 # no axis limit, no arc
        c = 0 if rapid else 1
        node.acc = src.class_acc[c]
        node.dec = src.class_dec[c]
        node.ramp = src.class_ramp[c]
        if want_tangent:                        # segment_tangent's unit vector
            inv = 1.0 / node.length
            t0[0] = d0 * inv
            t0[1] = d1 * inv
            t0[2] = d2 * inv
            for c in range(3, AXES):
                t0[c] = 0.0
    elif not _general_node(src, k, s, want_tangent, node, t0, t1):
        return False
    node.part = k
    if not src.have_prev or src.stop_pending or junction_stops(src.prev_rapid, rapid, s, src.params):
        jin = 0.0
    elif not want_tangent:
        jin = min(src.prev_vmax, node.vmax)
    else:
        if not src.prev_tangent_known:  # the slow-down came on at this junction
            _end_tangent(src, src.prev_part, src.prev_tangent)
        jin = min(src.prev_vmax, node.vmax)
        if stop_axes != 0 and junction_axis_stops(src.prev_tangent, t0, stop_axes, src.enhanced):
            jin = 0.0
        elif want_angle:
            cosine = junction_cosine(src.prev_tangent, t0,
                                     s.ignore_angle | ((src.enhanced >> ENH_ANGLE_SHIFT) & AXIS_MASK))
            if not (cosine >= src.cursor.cos_start):      # beyond startAngle (acos only there)
                jin = _float_below(angle_feed(junction_degrees(cosine), jin, s))
    node.jin = jin                      # 0, the lower of two limits, or rounded above
    node.jin2 = node.jin * node.jin
    node.brake2 = 2.0 * node.dec * node.length
    node.entry2 = -1.0                  # not computed yet
    node.barrier = node.jin2 <= node.brake2
    src.prev_tangent_known = want_tangent    # the next junction likely needs it
    if want_tangent and plain:          # a line ends as it starts
        memcpy(src.prev_tangent, t0, sizeof(t0))
    elif want_tangent:
        memcpy(src.prev_tangent, t1, sizeof(t1))
    src.prev_part = k
    src.prev_vmax = node.vmax
    src.prev_rapid = rapid
    src.have_prev = True
    src.stop_pending = False
    return True


cdef double _plan_node(const PlanNode *nd, double v_in, const PlanNode *next, Reciprocals *rc,
                       PartPlan *out) noexcept nogil:
    """The plan of one node entered at v_in: its limits and its profile (next: the
    node after it in the window, or NULL: a stop at its end); its exit speed."""
    cdef Profile pr
    profile_plan(&pr, nd, v_in, next, rc)
    out.v_exit = _float_below(pr.v_out)  # a profile from it stays feasible
    out.time = <float>profile_time(&pr)
    out.v_cap = <float>nd.vmax          # floats already (_next_node)
    out.v_ceiling = <float>nd.ceiling
    out.v_junction = <float>nd.jin
    out.acc = <float>nd.acc
    out.dec = <float>nd.dec
    out.ramp = nd.ramp
    return pr.v_out


cdef inline void plan_backward(PlanNode *ring, size_t stride, size_t mask, size_t first, size_t end) noexcept nogil:
    """The backward pass over a window: each node j of (first, end) -- node j at
    (j & mask) * stride bytes from `ring` (stride: sizeof(PlanNode) in a ring of
    nodes, the record's size in a ring of records that hold one), node `first` the
    one being planned -- gets entry2, the highest
    squared speed it may be entered at: its junction's limit, or what it and the
    nodes after it can still brake away to rest at the window's end. The values only
    grow as the window's end moves on, and where one does not change none before it
    does: the pass stops there (a caller whose nodes changed sets entry2 < 0 first)."""
    cdef double v2 = 0.0
    cdef size_t j = end
    cdef PlanNode *nj
    while j > first + 1:
        j -= 1
        nj = <PlanNode *>(<char *>ring + (j & mask) * stride)
        v2 = min(nj.jin2, v2 + nj.brake2)
        if v2 == nj.entry2:
            break
        nj.entry2 = v2


cdef void _plan_passing(const Program *prog, size_t first, size_t end, double v, PartPlan *plan) noexcept nogil:
    """Parts without motion (or length) in [first, end): the speed passes through
    (none where the machine stands); dwells take their time."""
    cdef size_t k
    cdef const Part *p
    cdef PartPlan through
    through.v_exit = _float_below(v)
    through.time = 0.0
    through.v_cap = _float_below(v)
    through.v_ceiling = <float>HUGE_VAL
    through.v_junction = <float>HUGE_VAL
    through.acc = through.dec = 0.0
    through.ramp = RAMP_TRAPEZOID
    for k in range(first, end):
        p = &prog.parts[k]
        plan[k] = through
        if p.kind == PART_DWELL:
            plan[k].time = <float>part_extra(prog, p).value
        if part_stops_motion(p):
            plan[k].v_junction = 0.0


cdef PlanNode *_ring_grow(PlanNode *ring, size_t cap, size_t first, size_t end) noexcept nogil:
    """The ring of nodes [first, end) (node k at k & (cap - 1), cap a power of two)
    with twice the room; NULL (ring freed) when out of memory."""
    cdef PlanNode *grown = <PlanNode *>tc_malloc(2 * cap * sizeof(PlanNode))
    cdef size_t k
    if grown != NULL:
        for k in range(first, end):
            grown[k & (2 * cap - 1)] = ring[k & (cap - 1)]
    free(ring)
    return grown


cdef int plan_program(ProgramBuilder *build, const GCODE_PARAMETERS *params, uint32_t enhanced,
                      int64_t window) noexcept nogil:
    """Plans every part into build.prog.plan (replaced). window: parts the look-ahead sees
    (0 the vendor's 8, < 0 unlimited). With mFuncInsertTable on, inserts its M functions
    where the plan slows down and plans again.
    COMPILE_OK, or COMPILE_ERROR when out of memory."""
    cdef int result = _plan_once(&build.prog, params, enhanced, window)
    if result == COMPILE_OK and mfunc_insert_wanted(params):
        result = mfunc_insert(build, params)
        if result == COMPILE_OK:
            result = _plan_once(&build.prog, params, enhanced, window)
    return result


cdef int _plan_once(Program *prog, const GCODE_PARAMETERS *params, uint32_t enhanced,
                    int64_t window) noexcept nogil:
    """One plan of the whole program: prog.plan allocated and filled; COMPILE_ERROR (no plan)
    when out of memory."""
    if not plan_alloc(prog, params, enhanced, window):
        return COMPILE_ERROR
    if plan_range(prog, params, enhanced, window, 0, prog.n_parts) != COMPILE_OK:
        plan_drop(prog)
        return COMPILE_ERROR
    return COMPILE_OK


cdef bint plan_alloc(Program *prog, const GCODE_PARAMETERS *params, uint32_t enhanced,
                     int64_t window) noexcept nogil:
    """A new, unfilled plan for every part in prog.plan, in the memory of the old one
    (or of what the core handed over, core.pyx: memory already faulted in costs less
    than fresh), to be made with these settings (kept in prog.planned_with); False
    when out of memory (no plan)."""
    cdef PartPlan *plan
    prog.planned_with.params = params[0]
    prog.planned_with.enhanced = enhanced
    prog.planned_with.window = window
    if prog.n_parts == 0:
        plan_drop(prog)
        return True
    plan = <PartPlan *>tc_realloc(prog.plan, prog.n_parts * sizeof(PartPlan))
    if plan == NULL:
        plan_drop(prog)
        return False
    prog.plan = plan
    return True


cdef void plan_drop(Program *prog) noexcept nogil:
    """Frees the program's plan: it has none."""
    free(prog.plan)
    prog.plan = NULL


cdef size_t plan_split_at(const Program *prog, size_t near) noexcept nogil:
    """A part at or after `near` (within PLAN_SPLIT_SEARCH parts) where the machine
    stands, so that the parts before it and from it on plan alone (plan_range); 0
    when there is none."""
    return plan_split_between(prog, near, prog.n_parts)


cdef size_t plan_split_between(const Program *prog, size_t near, size_t end) noexcept nogil:
    """plan_split_at reading no part at or beyond `end`."""
    cdef size_t k, last = near + PLAN_SPLIT_SEARCH
    if last > end:
        last = end
    for k in range(near if near > 0 else 1, last):
        if prog.parts[k].kind != PART_MOTION and part_stops_motion(&prog.parts[k]):
            return k
    return 0


cdef size_t plan_split_before(const Program *prog, size_t near, size_t floor) noexcept nogil:
    """The last part above `floor` and at or before `near` (within PLAN_SPLIT_SEARCH
    parts) where the machine stands; 0 when there is none."""
    cdef size_t k = near, stop = near - PLAN_SPLIT_SEARCH if near > PLAN_SPLIT_SEARCH else 0
    if stop < floor:
        stop = floor
    while k > stop:
        if prog.parts[k].kind != PART_MOTION and part_stops_motion(&prog.parts[k]):
            return k
        k -= 1
    return 0


cdef int plan_range(const Program *prog, const GCODE_PARAMETERS *params, uint32_t enhanced,
                    int64_t window, size_t first, size_t end) noexcept nogil:
    """Plans parts [first, end) into prog.plan (plan_alloc): the whole program, or the
    parts before or from a part plan_split_at gave. The machine stands at such a part
    (every motion before it ends at rest, the next one starts from rest), so the window
    may end there: the plan is the same as the whole program's. Two ranges may be
    planned at once. COMPILE_OK, or COMPILE_ERROR when out of memory."""
    if end > first:
        # the range's plan memory beyond the source text it reuses is fresh: readied in
        # one call (each of the two threads its own range), not a fault a page
        ready_memory(&prog.plan[first], (end - first) * sizeof(PartPlan))
    return _sweep(prog, NULL, params, enhanced, window, first, end, NULL)


cdef bint _head_room(PlacedPlan *head, size_t need) noexcept nogil:
    """Room for `need` part plans in head.head; False when memory is exhausted."""
    return grow(<void **>&head.head, &head.cap_head, need, sizeof(PartPlan))


cdef int _sweep(const Program *prog, const Placement *pl, const GCODE_PARAMETERS *params,
                uint32_t enhanced, int64_t window, size_t first, size_t end, PlacedPlan *head) noexcept nogil:
    """The look-ahead over parts [first, end) into prog.plan; or, with `head` (and the
    placement pl), from the program's start into head.head, the parts pl reshapes with
    their placed shape, until the plan is the compile's again (head.n_head the parts
    planned). COMPILE_OK, or COMPILE_ERROR when out of memory."""
    cdef size_t n = prog.n_parts, depth, cap = 1, i = 0, made = 0, planned_made = 0, filled = first
    cdef size_t mask, window_end, room, settled
    cdef PartPlan *plan = prog.plan if head == NULL else head.head
    cdef PlanNode *ring
    cdef PlanNode *nd
    cdef NodeSource src
    cdef Reciprocals recip
    cdef double v_prev = 0.0
    cdef bint converging = False, converged = False
    if end <= first:
        return COMPILE_OK
    if window == 0:
        depth = VENDOR_WINDOW
    elif window < 0 or <uint64_t>window > n:
        depth = n
    else:
        depth = <size_t>window
    while cap < depth and cap < RING_START:     # a power of two: node k at k & mask
        cap *= 2
    mask = cap - 1
    ring = <PlanNode *>tc_malloc(cap * sizeof(PlanNode))   # nodes i.. (at most depth of them)
    if ring == NULL:
        return COMPILE_ERROR
    src.prog = prog
    src.params = params
    src.enhanced = enhanced
    src.pl = pl
    src.reshaped_end = placement_reshaped_end(prog, pl) if pl != NULL else 0
    room = n if head == NULL else head.cap_head         # parts `plan` holds
    settled = src.reshaped_end if head != NULL else <size_t>-1     # a head ends where it is the compile's
    cursor_init(&src.cursor, prog, params)
    if first > 0:
        cursor_settings(&src.cursor, first - 1)     # the regions before the range
    src.scan = first
    src.motions = 0
    src.have_prev = False
    src.stop_pending = False
    src.prev_rapid = False
    src.prev_vmax = 0.0
    src.prev_part = 0
    src.prev_tangent_known = False
    _take_classes(&src, &src.cursor.cur)
    recip.acc = 0.0                     # none yet: every value differs from 0
    recip.dec = 0.0
    recip.vmax = 0.0
    while True:
        while made <= i and src.scan < end:
            if _next_node(&src, &ring[made & mask]):
                made += 1
        if made <= i:
            break
        nd = &ring[i & mask]
        # the window: nd and the motion parts after it, depth in all, or up to a
        # barrier (the same limits)
        window_end = nd.seq + depth
        while (src.scan < end and src.motions < window_end
               and not (made > i + 1 and ring[(made - 1) & mask].barrier)):
            if made - i == cap:
                ring = _ring_grow(ring, cap, i, made)
                if ring == NULL:
                    return COMPILE_ERROR
                cap *= 2
                mask = cap - 1
                nd = &ring[i & mask]
            if _next_node(&src, &ring[made & mask]):
                made += 1
        if made != planned_made:        # the window's end moved
            plan_backward(ring, sizeof(PlanNode), mask, i, made)
            planned_made = made
        if nd.part >= room:             # the head's plan grows (the compile's holds every part)
            if not _head_room(head, nd.part + 1):
                free(ring)
                return COMPILE_ERROR
            plan = head.head
            room = head.cap_head
        if filled < nd.part:
            _plan_passing(prog, filled, nd.part, v_prev, plan)
        v_prev = _plan_node(nd, v_prev, &ring[(i + 1) & mask] if i + 1 < made else NULL, &recip, &plan[nd.part])
        filled = nd.part + 1
        i += 1
        if nd.part >= settled:
            # from the node after the first one the placement leaves as it was, every
            # node is the compile's: the same speed out, the same plan on
            if converging and _float_below(v_prev) == head.plan[nd.part].v_exit:
                converged = True
                break
            converging = True
    if head == NULL:
        _plan_passing(prog, filled, end, v_prev, plan)
    else:
        if not converged:               # the program ended first: its rest too
            if not _head_room(head, end):
                free(ring)
                return COMPILE_ERROR
            _plan_passing(prog, filled, end, v_prev, head.head)
            filled = end
        head.n_head = filled
    free(ring)
    return COMPILE_OK


cdef bint placed_plan_make(PlacedPlan *pp, const Program *prog, const Placement *pl) noexcept nogil:
    """The plan of a run from pl.start: where the placement reshapes parts (a first
    move from elsewhere than the compile's start, the part where an axis is first
    named absolutely), those parts are planned again with the settings of the
    compilation, and the parts after them until their speeds are the compile's
    again; the rest is the compile's plan. False when out of memory (pp then
    gives the compile's plan)."""
    pp.plan = prog.plan
    pp.head = NULL
    pp.n_head = 0
    pp.cap_head = 0
    if not pl.moved or prog.plan == NULL or prog.n_parts == 0:
        return True
    if _sweep(prog, pl, &prog.planned_with.params, prog.planned_with.enhanced, prog.planned_with.window,
              0, prog.n_parts, pp) != COMPILE_OK:
        placed_plan_free(pp)
        pp.plan = prog.plan
        return False
    return True


cdef void placed_plan_free(PlacedPlan *pp) noexcept nogil:
    """Frees a placed run's plan of its head and leaves it empty."""
    free(pp.head)
    pp.head = NULL
    pp.n_head = 0
    pp.cap_head = 0


cdef double plan_calc_feed(const Program *prog, size_t i) noexcept nogil:
    """The planned feed of part i, mm/min: its speed limit at 100 % override
    (GM_PARAMS_ENHANCED.m_calcFeed)."""
    return prog.plan[i].v_cap * 60.0 if prog.plan != NULL else 0.0
