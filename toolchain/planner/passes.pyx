# The look-ahead: every motion part gets an entry, peak and exit speed such that
# the machine can still stop at the end of what it sees. The vendor's interpolator
# sees the current part and the next 7 (its look-ahead table, seed 003), so the
# default window is 8 parts (M functions count); a deeper window only lets parts
# run faster. One sweep over the program with a ring of the visible parts:
#   backward: from a stop at the window's end (or the program's end), the highest
#             entry speed of each visible part (its junction limit, or what it can
#             still brake away within its length);
#   forward:  from the previous exit, accelerate within the part, exit at most at
#             the next part's backward limit.
# The backward limits are recomputed only when the window's end moves (an
# unlimited window: once), and only back to the first that does not change: at most
# O(parts x window), O(parts) where the junctions' limits bind. The sweep may start
# and end at a part where the machine stands (plan_range): two ranges plan at once
# (pipeline.pyx) and give the same plan.
from libc.stdlib cimport malloc, free
from libc.math cimport sqrt
from libc.string cimport memcpy


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
        src.class_acc[c] = ramp_equivalent_acc(limit_or_none(cls.acc), ramp)
        src.class_dec[c] = ramp_equivalent_acc(limit_or_none(cls.dec), ramp)


cdef bint _general_node(NodeSource *src, size_t k, const PlanRegion *s, bint want_tangent,
                        PlanNode *node, double *t_start, double *t_end) noexcept nogil:
    """Length and limits of a motion part that is not a plain line (segment_of_part,
    part_limits), its end tangents when want_tangent; False when it has no length."""
    cdef Segment g
    cdef PartLimits lim
    segment_of_part(src.prog, k, &g)
    if g.length <= LENGTH_EPS:
        return False
    part_limits(&g, &src.prog.parts[k], src.params, s, src.cursor.axes_limited, src.enhanced, &lim)
    node.length = g.length
    node.vmax = lim.vmax
    node.acc = ramp_equivalent_acc(lim.acc, lim.ramp)
    node.dec = ramp_equivalent_acc(lim.dec, lim.ramp)
    if want_tangent:
        segment_tangent(&g, 0.0, t_start)
        segment_tangent(&g, g.length, t_end)
    return True


cdef void _end_tangent(const Program *prog, size_t k, double *t) noexcept nogil:
    cdef Segment g
    segment_of_part(prog, k, &g)
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
    cdef bint rapid, want_tangent, plain
    cdef int c
    src.scan += 1
    if p.kind != PART_MOTION:
        if part_stops_motion(p):
            src.stop_pending = True
        return False
    if src.class_region != src.cursor.region:
        _take_classes(src, s)
    want_tangent = s.startAngle < 180.0         # below 180 some angle slows down
    rapid = p.func == 0
    plain = (src.plain_lines and p.func != 2 and p.func != 3 and k > 0
             and src.prog.parts[k - 1].axes_idx == p.axes_idx)
    if plain:                                   # a line over x y z
        prev = &src.prog.parts[k - 1]
        d0 = p.ce[0] - prev.ce[0]
        d1 = p.ce[1] - prev.ce[1]
        d2 = p.ce[2] - prev.ce[2]
        node.length = sqrt(d0 * d0 + d1 * d1 + d2 * d2)     # segment_of_part's
        if node.length <= LENGTH_EPS:
            return False                        # no motion: the speed passes through
        vmax = part_feed(p, src.params) / 60.0  # part_limits' limits of a plain line
        node.vmax = vmax if vmax > 0.0 else 1.0 / 60.0
        c = 0 if rapid else 1
        node.acc = src.class_acc[c]
        node.dec = src.class_dec[c]
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
            _end_tangent(src.prog, src.prev_part, src.prev_tangent)
        jin = min(src.prev_vmax, node.vmax)
        cosine = junction_cosine(src.prev_tangent, t0,
                                 s.ignore_angle | ((src.enhanced >> ENH_ANGLE_SHIFT) & AXIS_MASK))
        if not (cosine >= src.cursor.cos_start):      # beyond startAngle (acos only there)
            jin = angle_feed(junction_degrees(cosine), jin, s)
    node.jin = jin
    node.jin2 = jin * jin
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


cdef void _plan_node(const PlanNode *nd, double v_in, const PlanNode *next, Reciprocals *rc,
                     PartPlan *out) noexcept nogil:
    """Entry v_in, exit as fast as allowed (next: the node after it in the window, or
    NULL: a stop), peak and time of one node (closed forms; a part that cruises into
    its junction's limit takes no square root)."""
    cdef double a = nd.acc, d = nd.dec, L = nd.length
    cdef double in2 = v_in * v_in
    cdef double exit2 = next.entry2 if next != NULL else 0.0
    cdef double out2 = min(exit2, in2 + 2.0 * a * L)
    cdef double peak = nd.vmax, peak2 = nd.vmax * nd.vmax, cruise, v_out
    if next != NULL and out2 == next.jin2:
        v_out = next.jin
    else:
        v_out = sqrt(out2)
    if a != rc.acc:
        rc.acc = a
        rc.half_inv_acc = 0.5 / a
    if d != rc.dec:
        rc.dec = d
        rc.half_inv_dec = 0.5 / d
    if peak != rc.vmax:
        rc.vmax = peak
        rc.inv_vmax = 1.0 / peak
    cruise = L - (peak2 - in2) * rc.half_inv_acc - (peak2 - out2) * rc.half_inv_dec
    if cruise >= 0.0:
        out.time = cruise * rc.inv_vmax
    else:                               # no room to cruise: the ramps meet below the limit
        peak2 = (2.0 * a * d * L + d * in2 + a * out2) / (a + d)
        peak = sqrt(peak2)
        if peak < v_in:
            peak = v_in
        if peak < v_out:
            peak = v_out
        out.time = 0.0
    out.v_peak = peak
    out.v_exit = v_out
    out.time += (peak - v_in) * 2.0 * rc.half_inv_acc + (peak - v_out) * 2.0 * rc.half_inv_dec


cdef void _plan_passing(const Program *prog, size_t first, size_t end, double v, PartPlan *plan) noexcept nogil:
    """Parts without motion in [first, end): the speed passes through; dwells take their time."""
    cdef size_t k
    for k in range(first, end):
        plan[k].v_peak = v
        plan[k].v_exit = v
        plan[k].time = prog.parts[k].value if prog.parts[k].kind == PART_DWELL else 0.0


cdef PlanNode *_ring_grow(PlanNode *ring, size_t cap, size_t first, size_t end) noexcept nogil:
    """The ring of nodes [first, end) (node k at k & (cap - 1), cap a power of two)
    with twice the room; NULL (ring freed) when out of memory."""
    cdef PlanNode *grown = <PlanNode *>malloc(2 * cap * sizeof(PlanNode))
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
    where the plan slows down and plans again (they count in the window).
    COMPILE_OK, or COMPILE_ERROR when out of memory."""
    cdef int result = _plan_once(&build.prog, params, enhanced, window)
    if result == COMPILE_OK and mfunc_insert_wanted(params):
        result = mfunc_insert(build, params)
        if result == COMPILE_OK:
            result = _plan_once(&build.prog, params, enhanced, window)
    return result


cdef int _plan_once(Program *prog, const GCODE_PARAMETERS *params, uint32_t enhanced,
                    int64_t window) noexcept nogil:
    if not plan_alloc(prog):
        return COMPILE_ERROR
    if plan_range(prog, params, enhanced, window, 0, prog.n_parts) != COMPILE_OK:
        plan_drop(prog)
        return COMPILE_ERROR
    return COMPILE_OK


cdef bint plan_alloc(Program *prog) noexcept nogil:
    """A new, unfilled plan for every part in prog.plan (the old one freed);
    False when out of memory."""
    free(prog.plan)
    prog.plan = NULL
    if prog.n_parts == 0:
        return True
    prog.plan = <PartPlan *>malloc(prog.n_parts * sizeof(PartPlan))
    if prog.plan != NULL and prog.n_parts * sizeof(PartPlan) >= HUGE_ADVICE_MIN:
        program_advise_huge(prog.plan, prog.n_parts * sizeof(PartPlan))
    return prog.plan != NULL


cdef void plan_drop(Program *prog) noexcept nogil:
    free(prog.plan)
    prog.plan = NULL


cdef size_t plan_split_at(const Program *prog, size_t near) noexcept nogil:
    """A part at or after `near` (within PLAN_SPLIT_SEARCH parts) where the machine
    stands, so that the parts before it and from it on plan alone (plan_range); 0
    when there is none."""
    cdef size_t k, last = near + PLAN_SPLIT_SEARCH
    if last > prog.n_parts:
        last = prog.n_parts
    for k in range(near if near > 0 else 1, last):
        if prog.parts[k].kind != PART_MOTION and part_stops_motion(&prog.parts[k]):
            return k
    return 0


cdef int plan_range(const Program *prog, const GCODE_PARAMETERS *params, uint32_t enhanced,
                    int64_t window, size_t first, size_t end) noexcept nogil:
    """Plans parts [first, end) into prog.plan (plan_alloc): the whole program, or the
    parts before or from a part plan_split_at gave. The machine stands at such a part
    (every motion before it ends at rest, the next one starts from rest), so the window
    may end there: the plan is the same as the whole program's. Two ranges may be
    planned at once. COMPILE_OK, or COMPILE_ERROR when out of memory."""
    cdef size_t n = prog.n_parts, depth, cap = 1, i = 0, made = 0, planned_made = 0, filled = first
    cdef size_t mask, window_end
    cdef PartPlan *plan = prog.plan
    cdef PlanNode *ring
    cdef PlanNode *nd
    cdef PlanNode *nj
    cdef NodeSource src
    cdef Reciprocals recip
    cdef double v_prev = 0.0, v2
    cdef size_t j
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
    ring = <PlanNode *>malloc(cap * sizeof(PlanNode))   # nodes i.. (at most depth of them)
    if ring == NULL:
        return COMPILE_ERROR
    src.prog = prog
    src.params = params
    src.enhanced = enhanced
    cursor_init(&src.cursor, prog, params)
    if first > 0:
        cursor_settings(&src.cursor, first - 1)     # the regions before the range
    src.scan = first
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
        # the window: parts up to node i's part + depth, or up to a barrier (the same limits)
        window_end = nd.part + depth
        while (src.scan < end and src.scan < window_end
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
        if made != planned_made:        # the window's end moved: backward pass over the window
            # squared speeds; the limits only grow with the window, and where one did not
            # change, none before it does
            v2 = 0.0
            j = made
            while j > i + 1:
                j -= 1
                nj = &ring[j & mask]
                v2 = min(nj.jin2, v2 + nj.brake2)
                if v2 == nj.entry2:
                    break
                nj.entry2 = v2
            planned_made = made
        if filled < nd.part:
            _plan_passing(prog, filled, nd.part, v_prev, plan)
        _plan_node(nd, v_prev, &ring[(i + 1) & mask] if i + 1 < made else NULL, &recip, &plan[nd.part])
        v_prev = plan[nd.part].v_exit
        filled = nd.part + 1
        i += 1
    _plan_passing(prog, filled, end, v_prev, plan)
    free(ring)
    return COMPILE_OK


cdef double plan_part_time(const Program *prog, size_t i) noexcept nogil:
    """Planned seconds of part i (0 when the program has no plan)."""
    return prog.plan[i].time if prog.plan != NULL else 0.0


cdef double plan_entry_speed(const Program *prog, size_t i) noexcept nogil:
    """mm/s at the start of part i."""
    if prog.plan == NULL or i == 0:
        return 0.0
    return prog.plan[i - 1].v_exit


cdef double plan_calc_feed(const Program *prog, size_t i) noexcept nogil:
    """The planned feed of part i, mm/min: the highest speed it reaches
    (GM_PARAMS_ENHANCED.m_calcFeed)."""
    return prog.plan[i].v_peak * 60.0 if prog.plan != NULL else 0.0
