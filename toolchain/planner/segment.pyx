# Segment geometry of one compiled part as the tool runs it (compensated path):
# unit tangents at its ends, the point at a path length, and how much of the path
# speed each axis takes at most over the whole part. The planner's limits and
# junctions read it; the machine (machine/) moves along it.
from libc.math cimport atan2, sqrt, fabs, sin, cos, ceil, M_PI
from libc.string cimport memcpy


cdef inline double _arc_turn(double sa, double sb, double ea, double eb, bint ccw) noexcept nogil:
    """Signed sweep from radius (sa, sb) to radius (ea, eb), in (0, 2pi] in the arc's
    direction, a full turn when they coincide (geometry.arc_sweep with one atan2)."""
    cdef double d = atan2(sa * eb - sb * ea, sa * ea + sb * eb)
    if ccw:
        if d <= 1e-12:
            d += 2.0 * M_PI
    elif d >= -1e-12:
        d -= 2.0 * M_PI
    return d


cdef void _segment_shape(Segment *g, double radius, double centre_a, double centre_b, bint ccw) noexcept nogil:
    """Length of g from its start and end over n_axes; for an arc (g.arc, its plane
    axes set) also its radius, centre (in the plane), sweep and lead."""
    cdef double rest = 0.0, d
    cdef int k
    if not g.arc:
        for k in range(g.n_axes):
            d = g.end[k] - g.start[k]
            rest += d * d
        g.length = sqrt(rest)
        return
    g.radius = radius
    g.centre[0] = centre_a
    g.centre[1] = centre_b
    g.sweep = _arc_turn(g.start[g.first] - centre_a, g.start[g.second] - centre_b,
                        g.end[g.first] - centre_a, g.end[g.second] - centre_b, ccw)
    for k in range(g.n_axes):
        if k != g.first and k != g.second:
            d = g.end[k] - g.start[k]
            rest += d * d
    g.lead = sqrt(rest) / fabs(g.sweep)
    g.length = fabs(g.sweep) * sqrt(radius * radius + g.lead * g.lead)


cdef void segment_of_part(const Program *prog, size_t i, Segment *g) noexcept nogil:
    """The geometry of motion part i (its length as part_length measures it)."""
    cdef const Part *p = &prog.parts[i]
    cdef const Part *prev
    if i > 0 and prog.parts[i - 1].axes_idx == p.axes_idx:
        prev = &prog.parts[i - 1]       # the seven other axes stand: x y z alone
        g.n_axes = 3
        g.start[0] = prev.ce[0]; g.start[1] = prev.ce[1]; g.start[2] = prev.ce[2]
    else:
        g.n_axes = 10
        part_calc_start(prog, i, g.start)
        part_end(prog, p, g.end)
    g.end[0] = p.ce[0]; g.end[1] = p.ce[1]; g.end[2] = p.ce[2]
    g.arc = ((p.func == 2 or p.func == 3) and p.radius > 0
             and plane_axes(p.plane, &g.first, &g.second, &g.normal))
    if g.arc:
        _segment_shape(g, p.radius, p.cc[g.first], p.cc[g.second], p.func == 3)
    else:
        _segment_shape(g, 0.0, 0.0, 0.0, False)


cdef void placed_segment(const Program *prog, const Placement *pl, size_t i, Segment *g) noexcept nogil:
    """Geometry of motion part i as a run from pl.start places it, all ten axes: the
    part's own (segment_of_part), its start moved in the axes the part before follows
    the run's start in (an arc's centre with it), its end in those the part itself
    follows (placement.pyx); measured again where the two moved apart (the part where
    an axis is first named absolutely), as the API's record of the part gives it."""
    cdef const Part *p = &prog.parts[i]
    cdef const Part *prev = &prog.parts[i - 1] if i > 0 else NULL
    cdef const double *other
    cdef bint s_moves, e_moves, reshaped = False
    cdef double d
    cdef int k
    segment_of_part(prog, i, g)
    if g.n_axes == 3:               # the seven other axes stand where the part before left them
        other = &prog.axes[7 * p.axes_idx]
        memcpy(&g.start[3], other, 7 * sizeof(double))
        memcpy(&g.end[3], other, 7 * sizeof(double))
        g.n_axes = 10
    if not pl.moved:
        return
    for k in range(10):
        d = pl.delta[k]
        if d == 0.0:
            continue
        s_moves = prev == NULL or follows_start(prog, prev, k)
        e_moves = follows_start(prog, p, k)
        if s_moves:
            g.start[k] += d
            if g.arc and k == g.first:
                g.centre[0] += d
            elif g.arc and k == g.second:
                g.centre[1] += d
        if e_moves:
            g.end[k] += d
        reshaped = reshaped or s_moves != e_moves
    if reshaped and g.arc:
        _segment_shape(g, g.radius, g.centre[0], g.centre[1], p.func == 3)
    elif reshaped:
        _segment_shape(g, 0.0, 0.0, 0.0, False)


cdef void segment_of_gm(const SIMPLE_GM_PARAMS *gm, Segment *g) noexcept nogil:
    """The geometry of a motion part as a run places it (placed_part_to_gm): ten axes
    from m_calcS to m_calcE; an arc round m_cc with the tool path's radius in m_cc.c."""
    cdef const double *c = <const double *>&gm.m_cc
    g.n_axes = 10
    memcpy(g.start, <const double *>&gm.m_calcS, sizeof(g.start))
    memcpy(g.end, <const double *>&gm.m_calcE, sizeof(g.end))
    g.arc = ((gm.m_func == 2 or gm.m_func == 3) and gm.m_cc.c > 0
             and plane_axes(<int16_t>(gm.m_planeTool & 0xFFFF), &g.first, &g.second, &g.normal))
    if g.arc:
        _segment_shape(g, gm.m_cc.c, c[g.first], c[g.second], gm.m_func == 3)
    else:
        _segment_shape(g, 0.0, 0.0, 0.0, False)


cdef void segment_point_at(const Segment *g, double s, double *out) noexcept nogil:
    """The point (axes [0, n_axes)) at path length s from the start, s clamped to
    [0, length]: the start and the end exactly at the two ends."""
    cdef double u
    cdef double plane[2]
    cdef int k
    if s <= 0.0 or g.length <= 0.0:
        memcpy(out, g.start, g.n_axes * sizeof(double))
        return
    if s >= g.length:
        memcpy(out, g.end, g.n_axes * sizeof(double))
        return
    u = s / g.length
    for k in range(g.n_axes):
        out[k] = g.start[k] + (g.end[k] - g.start[k]) * u
    if g.arc:
        arc_point_at(g.centre, g.radius, g.start[g.first], g.start[g.second], u * g.sweep, plane)
        out[g.first] = plane[0]
        out[g.second] = plane[1]


cdef inline bint _zero_still_axes(const Segment *g, double *per_axis) noexcept nogil:
    """Zeros per_axis (ten axes) where g does not move: beyond n_axes, or all of them
    when g has no length (True then)."""
    cdef int k
    if g.length <= 0.0:
        for k in range(10):
            per_axis[k] = 0.0
        return True
    for k in range(g.n_axes, 10):
        per_axis[k] = 0.0
    return False


cdef void segment_tangent(const Segment *g, double u, double *t) noexcept nogil:
    """Unit tangent (ten axes) at the fraction u (0 start, 1 end) of the part;
    zeros for a part without length."""
    cdef double theta, sgn, norm, turn, radial_a, radial_b, rho, inv
    cdef int k
    if _zero_still_axes(g, t):
        return
    if not g.arc:
        inv = 1.0 / g.length
        for k in range(g.n_axes):
            t[k] = (g.end[k] - g.start[k]) * inv
        return
    sgn = 1.0 if g.sweep > 0 else -1.0
    turn = fabs(g.sweep)
    norm = sqrt(g.radius * g.radius + g.lead * g.lead)
    inv = 1.0 / (turn * norm)
    for k in range(g.n_axes):
        t[k] = (g.end[k] - g.start[k]) * inv
    if u == 0.0 or u == 1.0:        # the radius to the end point gives cos and sin
        radial_a = (g.start[g.first] if u == 0.0 else g.end[g.first]) - g.centre[0]
        radial_b = (g.start[g.second] if u == 0.0 else g.end[g.second]) - g.centre[1]
        rho = sqrt(radial_a * radial_a + radial_b * radial_b)
        if rho > 0.0:
            t[g.first] = -sgn * g.radius * (radial_b / rho) / norm
            t[g.second] = sgn * g.radius * (radial_a / rho) / norm
            return
    theta = atan2(g.start[g.second] - g.centre[1], g.start[g.first] - g.centre[0]) + u * g.sweep
    t[g.first] = -sgn * g.radius * sin(theta) / norm
    t[g.second] = sgn * g.radius * cos(theta) / norm


cdef inline bint _covers(double lo, double hi, double phase) noexcept nogil:
    """Some angle phase + k*pi lies in [lo, hi]."""
    return phase + ceil((lo - phase) / M_PI) * M_PI <= hi


cdef void segment_axis_reach(const Segment *g, double *reach) noexcept nogil:
    """reach[k] = the largest |t_k| over the whole part (t the unit tangent): the
    share of the path speed (and tangential acceleration) axis k takes at most."""
    cdef double lo, hi, norm, turn, angle0
    cdef int k
    if _zero_still_axes(g, reach):
        return
    if not g.arc:
        for k in range(g.n_axes):
            reach[k] = fabs(g.end[k] - g.start[k]) / g.length
        return
    turn = fabs(g.sweep)
    norm = sqrt(g.radius * g.radius + g.lead * g.lead)
    for k in range(g.n_axes):
        reach[k] = fabs(g.end[k] - g.start[k]) / turn / norm
    angle0 = atan2(g.start[g.second] - g.centre[1], g.start[g.first] - g.centre[0])
    lo = angle0 if g.sweep > 0 else angle0 + g.sweep
    hi = lo + turn
    # first axis goes with |sin|, second with |cos| of the polar angle
    reach[g.first] = g.radius / norm * (1.0 if _covers(lo, hi, 0.5 * M_PI)
                                        else max(fabs(sin(lo)), fabs(sin(hi))))
    reach[g.second] = g.radius / norm * (1.0 if _covers(lo, hi, 0.0)
                                         else max(fabs(cos(lo)), fabs(cos(hi))))


cdef double segment_feed_length(const Segment *g, uint32_t ignored) noexcept nogil:
    """Length over the axes not in `ignored` (bit k = axis k), the length a programmed
    feed is measured on. An arc whose plane axis is ignored counts whole."""
    cdef double rest = 0.0, d
    cdef int k
    if ignored == 0:
        return g.length
    if g.arc and ((ignored >> g.first) & 1 or (ignored >> g.second) & 1):
        return g.length
    for k in range(g.n_axes):
        if (ignored >> k) & 1:
            continue
        if g.arc and (k == g.first or k == g.second):
            continue
        d = g.end[k] - g.start[k]
        rest += d * d
    if g.arc:
        d = fabs(g.sweep) * g.radius
        return sqrt(d * d + rest)
    return sqrt(rest)
