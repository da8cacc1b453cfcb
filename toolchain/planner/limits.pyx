# Static limits of each part, before any look-ahead: the programmed feed, the arc
# feed table, the centripetal acceleration and the axes' limits projected on the
# tangent over the whole part; the planning settings in force (PlanRegion).
from libc.math cimport sqrt, cos, M_PI, HUGE_VAL
from libc.string cimport memcpy, memcmp, memset


cdef void plan_settings_from_params(PlanRegion *s, const GCODE_PARAMETERS *p) noexcept nogil:
    """The host's settings, before the program changes any."""
    s.first = 0
    memcpy(s.motion, p.motion, sizeof(s.motion))
    memcpy(s.axisLimits, p.axisLimits, sizeof(s.axisLimits))
    s.startAngle = p.startAngle
    s.endAngle = p.endAngle
    s.minAngleFeed = p.minAngleFeed
    s.ignore_angle = 0
    s.ignore_feed = 0
    s.limits_off = 0
    s.stop_mode = 0
    s.arc_table = -1


cdef bint _same_settings(const PlanRegion *a, const PlanRegion *b) noexcept nogil:
    """Every setting but `first` equal (byte for byte: regions are zeroed before they are filled)."""
    return memcmp(<const char *>a + sizeof(size_t), <const char *>b + sizeof(size_t),
                  sizeof(PlanRegion) - sizeof(size_t)) == 0


cdef bint program_add_plan_region(ProgramBuilder *build, size_t first, const GCODE_PARAMETERS *p,
                                  uint32_t ignore_angle, uint32_t ignore_feed, uint32_t limits_off,
                                  int32_t stop_mode, int32_t arc_table) noexcept nogil:
    """Records the planning settings in force from programmed part `first` on (the
    compiler, after G900 or M-5); False when out of memory."""
    cdef Program *prog = &build.prog
    cdef PlanRegion made
    memset(&made, 0, sizeof(PlanRegion))   # the tail padding too: regions compare with memcmp
    plan_settings_from_params(&made, p)
    made.first = first
    made.ignore_angle = ignore_angle
    made.ignore_feed = ignore_feed
    made.limits_off = limits_off
    made.stop_mode = stop_mode
    made.arc_table = arc_table
    if prog.n_plan_regions > 0 and prog.plan_regions[prog.n_plan_regions - 1].first == first:
        prog.n_plan_regions -= 1         # several changes before the same part: the last one counts
    if prog.n_plan_regions > 0 and _same_settings(&prog.plan_regions[prog.n_plan_regions - 1], &made):
        return True                      # nothing changed (a G900 in a loop): no new region
    if not grow(<void **>&prog.plan_regions, &build.cap_plan_regions, prog.n_plan_regions + 1,
                 sizeof(PlanRegion)):
        return False
    memcpy(&prog.plan_regions[prog.n_plan_regions], &made, sizeof(PlanRegion))
    prog.n_plan_regions += 1
    return True


cdef inline bint _axes_limited(const PlanRegion *s) noexcept nogil:
    """Some axis has a limit that is on."""
    cdef int k
    for k in range(AXES):
        if not ((s.limits_off >> k) & 1) and (s.axisLimits[k].maxFeed > 0.0 or s.axisLimits[k].maxAcc > 0.0
                                               or s.axisLimits[k].maxDec > 0.0):
            return True
    return False


cdef inline double _cos_start(const PlanRegion *s) noexcept nogil:
    """Junctions whose tangents' cosine is at least this run at full speed."""
    if s.startAngle > 0.0 and s.startAngle < 180.0:
        return cos(s.startAngle * (M_PI / 180.0))
    return 2.0


cdef void cursor_init(PlanCursor *c, const Program *prog, const GCODE_PARAMETERS *params) noexcept nogil:
    """A cursor at the program's start: the host's settings in force, no plan region applied
    yet."""
    c.prog = prog
    plan_settings_from_params(&c.cur, params)
    c.region = 0
    c.programmed = 0
    c.next_part = 0
    c.axes_limited = _axes_limited(&c.cur)
    c.cos_start = _cos_start(&c.cur)


cdef inline const PlanRegion *cursor_settings(PlanCursor *c, size_t part) noexcept nogil:
    """The settings part `part` runs with; parts in increasing order."""
    if c.region == c.prog.n_plan_regions:  # nothing left to apply: no need to count (every part)
        return &c.cur
    return _cursor_advance(c, part)


cdef const PlanRegion *_cursor_advance(PlanCursor *c, size_t part) noexcept nogil:
    """The settings in force at part `part` (later than the last one asked): the plan regions
    (G900) that begin by then applied, counted in programmed parts (inserted ones do not
    count)."""
    cdef const Program *prog = c.prog
    while c.next_part <= part:
        if not (prog.parts[c.next_part].flags & FLAG_INSERTED):
            while c.region < prog.n_plan_regions and prog.plan_regions[c.region].first <= c.programmed:
                c.cur = prog.plan_regions[c.region]
                c.region += 1
                c.axes_limited = _axes_limited(&c.cur)
                c.cos_start = _cos_start(&c.cur)
            c.programmed += 1
        c.next_part += 1
    return &c.cur


cdef double part_feed(const Program *prog, const Part *p, const GCODE_PARAMETERS *params) noexcept nogil:
    """mm/min: rapids their feed (FF or motion[0], the compiler chose by forceMode);
    threads (G33) pitch times S; cuts F (or motion[1], M99 as the compiler resolved), per revolution times S
    (G96: the spindle speed S gives at the part, emit.pyx em_css), times FP."""
    cdef const PartSettings *s = part_settings(prog, p)
    cdef double feed = s.feed
    cdef double value = part_extra(prog, p).value
    if p.func == 0:
        return feed if feed > 0.0 else params.motion[0].feed
    if p.func == 33 and value > 0.0:
        return value * s.spindle        # a thread: its pitch per spindle turn, no override
    if not (p.flags & FLAG_FEED_PER_MIN):
        feed = feed * (value if p.flags & FLAG_CSS else s.spindle)     # per revolution
    feed = feed * s.fp
    if feed <= 0.0:
        feed = params.motion[1].feed
    return feed


cdef double arc_feed_factor(const GCODE_PARAMETERS *params, int32_t state, double radius) noexcept nogil:
    """Relative feed of an arc of `radius` by arcFeedTable, 0 when the table is off
    (empty, or G900 S13 A0). Its entries are [radius, relative feed]; the first of
    radius 0 is the last (it counts when its feed is not 0: it reaches down to radius
    0, so (0, 0.5) alone runs every arc at 50 %; a negative or NaN radius ends the
    table without counting). Sorted by radius: an arc at or above the largest entry's
    radius takes its feed, at or below the smallest's its feed, between two entries
    the feed linear in the radius -- (10, 1.25), (0.9, 0.1): 125 % from R10 on, down
    to 10 % at R0.9 and below."""
    cdef double r[5]
    cdef double f[5]
    cdef int n = 0, i, j
    cdef double tr, tf, rel
    if state == 0:
        return 0.0
    for i in range(5):
        rel = params.arcFeedTable[i].m_relFeed
        if not (params.arcFeedTable[i].m_r >= 0.0):
            break
        if params.arcFeedTable[i].m_r == 0.0 and not (rel > 0.0):
            break
        r[n] = params.arcFeedTable[i].m_r
        f[n] = rel if rel >= 0.001 and rel < 1e6 else (1e6 if rel >= 1e6 else 0.001)
        j = n
        while j > 0 and r[j - 1] > r[j]:            # keep them sorted by radius
            tr = r[j]; r[j] = r[j - 1]; r[j - 1] = tr
            tf = f[j]; f[j] = f[j - 1]; f[j - 1] = tf
            j -= 1
        n += 1
        if params.arcFeedTable[i].m_r == 0.0:
            break
    if n == 0:
        return 0.0
    if radius <= r[0]:
        return f[0]
    for i in range(1, n):
        if radius <= r[i]:
            return f[i - 1] + (f[i] - f[i - 1]) * (radius - r[i - 1]) / (r[i] - r[i - 1])
    return f[n - 1]


cdef void part_limits(const Segment *g, const Program *prog, const Part *p, const GCODE_PARAMETERS *params,
                      const PlanRegion *s, bint axes_limited, uint32_t enhanced, PartLimits *out) noexcept nogil:
    """The static limits of a motion part with geometry g (axes_limited: _axes_limited(s))."""
    cdef const GCODE_FEED *cls
    cdef double reach[AXES]
    cdef double v, feed_len, factor
    cdef uint32_t ignore_feed = s.ignore_feed | ((enhanced >> ENH_FEED_SHIFT) & AXIS_MASK)
    cdef int k
    out.rapid = p.func == 0
    cls = &s.motion[0] if out.rapid else &s.motion[1]
    out.length = g.length
    out.ramp = RAMP_SINE if cls.rampType == RAMP_SINE else RAMP_TRAPEZOID
    out.acc = limit_or_none(cls.acc)
    out.dec = limit_or_none(cls.dec)
    v = part_feed(prog, p, params) / 60.0
    out.v_ceiling = HUGE_VAL
    feed_len = segment_feed_length(g, ignore_feed)
    if feed_len > ROUNDING_EPS and feed_len < g.length:
        v = v * g.length / feed_len     # the feed holds on the other axes: the path runs faster
    if g.arc and not out.rapid:
        factor = arc_feed_factor(params, s.arc_table, g.radius)
        if factor > 0.0:
            v = v * factor
            out.v_ceiling = v           # the table's speed for this radius is a limit, not a feed
        if params.centripetalAcc > 0.0 and (<uint32_t>params.rezerva1 & GCODE_REZERVA1_APPLY_UNIMPLEMENTED):
            out.v_ceiling = min(out.v_ceiling, sqrt(params.centripetalAcc / segment_curvature(g)))
            v = min(v, out.v_ceiling)
    if not axes_limited:
        out.vmax = v if v > 0.0 else 1.0 / 60.0
        out.v_ceiling = max(out.v_ceiling, out.vmax)
        return
    segment_axis_reach(g, reach)
    for k in range(AXES):
        if (s.limits_off >> k) & 1 or reach[k] <= ANGLE_EPS:
            continue
        if s.axisLimits[k].maxFeed > 0.0:
            out.v_ceiling = min(out.v_ceiling, s.axisLimits[k].maxFeed / 60.0 / reach[k])
            v = min(v, out.v_ceiling)
        if s.axisLimits[k].maxAcc > 0.0:
            out.acc = min(out.acc, s.axisLimits[k].maxAcc / reach[k])
        if s.axisLimits[k].maxDec > 0.0:
            out.dec = min(out.dec, s.axisLimits[k].maxDec / reach[k])
    if not (v > 0.0):
        v = 1.0 / 60.0                  # no feed anywhere: 1 mm/min rather than never arriving
    out.vmax = v
    out.v_ceiling = max(out.v_ceiling, v)
