# The geometry the stages share (the face, geometry.pxd, holds the tolerances and the
# small 2-D primitives): planes, a part as a Segment (compiled, placed by a run, or
# from the API's record) and what is measured along it -- length, point, tangent,
# curvature, the axes' share of the speed, its box and its nearest point.
from libc.math cimport atan2, sqrt, fabs, sin, cos, acos, fmod, hypot, M_PI
from libc.string cimport memcpy


cdef const char *axis_name(int k) noexcept nogil:
    """Letter of axis index k (x y z c b u v w a o order)."""
    if k == 0: return "X"
    if k == 1: return "Y"
    if k == 2: return "Z"
    if k == 3: return "C"
    if k == 4: return "B"
    if k == 5: return "U"
    if k == 6: return "V"
    if k == 7: return "W"
    if k == 8: return "A"
    return "O"


cdef bint plane_axes(int plane, int *first, int *second, int *normal) noexcept nogil:
    """Axis indexes of a plane; False for a plane that is not 17/18/19/-18."""
    if plane == 17:
        first[0] = 0; second[0] = 1; normal[0] = 2
    elif plane == 18:
        first[0] = 0; second[0] = 2; normal[0] = 1
    elif plane == 19:
        first[0] = 1; second[0] = 2; normal[0] = 0
    elif plane == -18:
        first[0] = 2; second[0] = 0; normal[0] = 1
    else:
        return False
    return True


# ---- a part as a Segment ---------------------------------------------------------------

cdef void segment_shape(Segment *g, int plane, double radius, const double *centre, bint ccw) noexcept nogil:
    """Length of g from its start and end over n_axes; for an arc also its plane
    axes, radius, centre (in the plane), sweep and lead."""
    cdef double rest = 0.0, d
    cdef int k
    g.arc = radius > 0 and plane_axes(plane, &g.first, &g.second, &g.normal)
    if not g.arc:
        for k in range(g.n_axes):
            d = g.end[k] - g.start[k]
            rest += d * d
        g.length = sqrt(rest)
        return
    g.radius = radius
    g.centre[0] = centre[g.first]
    g.centre[1] = centre[g.second]
    g.sweep = arc_sweep(g.start[g.first] - g.centre[0], g.start[g.second] - g.centre[1],
                        g.end[g.first] - g.centre[0], g.end[g.second] - g.centre[1], ccw)
    for k in range(g.n_axes):
        if k != g.first and k != g.second:
            d = g.end[k] - g.start[k]
            rest += d * d
    g.lead = sqrt(rest) / fabs(g.sweep)
    g.length = fabs(g.sweep) * sqrt(radius * radius + g.lead * g.lead)


cdef inline void _shape_part(const Part *p, double radius, Segment *g, const double *centre) noexcept nogil:
    """segment_shape with the part's arc (G2 / G3 in its plane round centre) or line."""
    segment_shape(g, p.plane, radius if p.func == 2 or p.func == 3 else 0.0, centre, p.func == 3)


cdef void segment_of_part(const Program *prog, size_t i, Segment *g) noexcept nogil:
    """The geometry of motion part i as compiled (the planner's): the compensated
    start and end, over x y z alone when the seven other axes stand."""
    cdef const Part *p = &prog.parts[i]
    cdef const PartExtra *x = part_extra(prog, p)
    cdef const Part *prev
    if i > 0 and prog.parts[i - 1].axes_idx == p.axes_idx:
        prev = &prog.parts[i - 1]       # the seven other axes stand: x y z alone
        g.n_axes = 3
        g.start[0] = prev.ce[0]; g.start[1] = prev.ce[1]; g.start[2] = prev.ce[2]
    else:
        g.n_axes = AXES
        part_calc_start(prog, i, g.start)
        part_end(prog, p, g.end)
    g.end[0] = p.ce[0]; g.end[1] = p.ce[1]; g.end[2] = p.ce[2]
    _shape_part(p, x.radius, g, x.cc)


cdef bint placement_shift(const Program *prog, size_t i, const Placement *pl, double *start_shift,
                          double *end_shift) noexcept nogil:
    """How far a run from pl moves part i's start (and an arc's centre, which is
    relative to the start) and its end, each axis: by pl.delta where that end
    follows the run's start (placement.pxd follows_start), else not. True when an
    axis moves one end and not the other (the part is reshaped)."""
    cdef const Part *p = &prog.parts[i]
    cdef const Part *prev = &prog.parts[i - 1] if i > 0 else NULL
    cdef bint reshaped = False, s_moves, e_moves
    cdef int k
    for k in range(AXES):
        start_shift[k] = 0.0
        end_shift[k] = 0.0
        if pl.delta[k] == 0.0:
            continue
        s_moves = prev == NULL or follows_start(prog, prev, k)
        e_moves = follows_start(prog, p, k)
        if s_moves:
            start_shift[k] = pl.delta[k]
        if e_moves:
            end_shift[k] = pl.delta[k]
        reshaped = reshaped or s_moves != e_moves
    return reshaped


cdef void segment_of_placed_part(const Program *prog, size_t i, const Placement *pl, Segment *g) noexcept nogil:
    """The geometry of motion part i as a run from pl places it, all ten axes: the
    ends and the centre moved first (placement_shift), then shaped -- the same
    numbers as segment_of_gm of the run's record (placement.pyx placed_part_to_gm)."""
    cdef const Part *p = &prog.parts[i]
    cdef const PartExtra *x = part_extra(prog, p)
    cdef double start_shift[AXES]
    cdef double end_shift[AXES]
    cdef double centre[3]
    cdef int k
    g.n_axes = AXES
    part_calc_start(prog, i, g.start)
    part_end(prog, p, g.end)
    g.end[0] = p.ce[0]; g.end[1] = p.ce[1]; g.end[2] = p.ce[2]
    centre[0] = x.cc[0]; centre[1] = x.cc[1]; centre[2] = x.cc[2]
    if pl.moved:
        placement_shift(prog, i, pl, start_shift, end_shift)
        for k in range(AXES):
            g.start[k] += start_shift[k]
            g.end[k] += end_shift[k]
        for k in range(3):
            centre[k] += start_shift[k]
    _shape_part(p, x.radius, g, centre)


cdef void segment_of_gm(const SIMPLE_GM_PARAMS *gm, Segment *g) noexcept nogil:
    """The geometry of a motion part the API's record gives (a run's, or a GoTo's
    destination): ten axes from m_calcS to m_calcE; an arc round m_cc with the tool
    path's radius in m_cc.c."""
    g.n_axes = AXES
    memcpy(g.start, <const double *>&gm.m_calcS, sizeof(g.start))
    memcpy(g.end, <const double *>&gm.m_calcE, sizeof(g.end))
    segment_shape(g, <int16_t>(gm.m_planeTool & 0xFFFF), gm.m_cc.c if gm.m_func == 2 or gm.m_func == 3 else 0.0,
                  <const double *>&gm.m_cc, gm.m_func == 3)


cdef double part_length(const Program *prog, size_t i) noexcept nogil:
    """Path length of the tool (compensated) for part i; 0 for M functions."""
    cdef Segment g
    if prog.parts[i].kind != PART_MOTION:
        return 0.0
    segment_of_part(prog, i, &g)
    return g.length


cdef double placed_part_length(const Program *prog, size_t i, const Placement *pl) noexcept nogil:
    """part_length for a run from pl: a line whose ends it moves apart is measured
    between its moved ends; an arc keeps its length (its centre moves with its start:
    the record keeps the compiled arc's length and the run moves along that turn)."""
    cdef const Part *p = &prog.parts[i]
    cdef Segment g
    cdef double start_shift[AXES]
    cdef double end_shift[AXES]
    if p.kind != PART_MOTION:
        return 0.0
    if pl.moved and p.func != 2 and p.func != 3 and placement_shift(prog, i, pl, start_shift, end_shift):
        segment_of_placed_part(prog, i, pl, &g)
        return g.length
    return part_length(prog, i)


# ---- along a Segment ---------------------------------------------------------------------

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
    """Zeros per_axis (all axes) where g does not move: beyond n_axes, or all of them
    when g has no length (True then)."""
    cdef int k
    if g.length <= 0.0:
        for k in range(AXES):
            per_axis[k] = 0.0
        return True
    for k in range(g.n_axes, AXES):
        per_axis[k] = 0.0
    return False


cdef void segment_tangent(const Segment *g, double s, double *t) noexcept nogil:
    """Unit tangent (all axes) at path length s (0 the start, length the end);
    zeros for a part without length."""
    cdef double u, theta, sgn, norm, turn, radial_a, radial_b, rho, inv
    cdef int k
    if _zero_still_axes(g, t):
        return
    if not g.arc:
        inv = 1.0 / g.length
        for k in range(g.n_axes):
            t[k] = (g.end[k] - g.start[k]) * inv
        return
    u = s / g.length
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


cdef double segment_curvature(const Segment *g) noexcept nogil:
    """1 / the radius of curvature: r / (r^2 + lead^2) along a helix (r alone on a
    plane arc), 0 on a line."""
    if not g.arc:
        return 0.0
    return g.radius / (g.radius * g.radius + g.lead * g.lead)


cdef inline unsigned _segment_axis_points(const Segment *g) noexcept nogil:
    """arc_axis_points of an arc Segment (its sweep decides where its ends meet)."""
    return arc_axis_points(g.start[g.first] - g.centre[0], g.start[g.second] - g.centre[1],
                           g.end[g.first] - g.centre[0], g.end[g.second] - g.centre[1],
                           g.sweep > 0, fabs(g.sweep))


cdef void segment_axis_reach(const Segment *g, double *reach) noexcept nogil:
    """reach[k] = the largest |t_k| over the whole part (t the unit tangent): the
    share of the path speed (and tangential acceleration) axis k takes at most."""
    cdef double lo, hi, norm, turn, angle0
    cdef unsigned passes
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
    # the first axis goes with |sin| of the polar angle (whole at the second axis's
    # points, bits 1 and 3), the second with |cos| (at the first axis's, bits 0 and 2)
    passes = _segment_axis_points(g)
    reach[g.first] = g.radius / norm * (1.0 if passes & 0xA else max(fabs(sin(lo)), fabs(sin(hi))))
    reach[g.second] = g.radius / norm * (1.0 if passes & 0x5 else max(fabs(cos(lo)), fabs(cos(hi))))


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


cdef void segment_box(const Segment *g, double *lo, double *hi) noexcept nogil:
    """The box of g, axes [0, n_axes): its ends, and for an arc's plane axes the
    circle of the tool path's radius (where its inner points lie) at the ends' angles
    and at the axis points it passes (arc_axis_points)."""
    cdef double p[2]
    cdef double c, v
    cdef unsigned passes
    cdef int k, q, a
    for k in range(g.n_axes):
        lo[k] = min(g.start[k], g.end[k])
        hi[k] = max(g.start[k], g.end[k])
    if not g.arc:
        return
    for q in range(2):
        arc_point_at(g.centre, g.radius, g.start[g.first], g.start[g.second], g.sweep if q else 0.0, p)
        for a in range(2):
            k = g.second if a else g.first
            lo[k] = min(lo[k], p[a])
            hi[k] = max(hi[k], p[a])
    passes = _segment_axis_points(g)
    for q in range(4):
        if not (passes >> q) & 1:
            continue
        for a in range(2):
            k = g.second if a else g.first
            c = g.centre[a]
            # the axis point at q * 90 degrees: bit 0 (1) sets the first (second) axis to c + r, 2 (3) to c - r
            v = c + (g.radius if q == a else (-g.radius if q == a + 2 else 0.0))
            lo[k] = min(lo[k], v)
            hi[k] = max(hi[k], v)


# ---- the nearest point -----------------------------------------------------------------

cdef double segment_distance2_at(const Segment *g, double s, uint32_t axes, const double *q,
                                 double *point) noexcept nogil:
    """Squared distance in the axes of `axes` from q to the point at path length s
    (written to `point`, axes [0, n_axes))."""
    cdef double d2 = 0.0, d
    cdef int k
    segment_point_at(g, s, point)
    for k in range(g.n_axes):
        if (axes >> k) & 1:
            d = point[k] - q[k]
            d2 += d * d
    return d2


cdef double _line_nearest(const Segment *g, uint32_t axes, const double *q) noexcept nogil:
    """Path length of the point of a line nearest q in the axes: the projection onto
    the line, clamped to its ends."""
    cdef double dd = 0.0, dw = 0.0, d
    cdef int k
    for k in range(g.n_axes):
        if (axes >> k) & 1:
            d = g.end[k] - g.start[k]
            dd += d * d
            dw += d * (q[k] - g.start[k])
    if dd <= 0.0 or dw <= 0.0:
        return 0.0
    if dw >= dd:
        return g.length
    return g.length * (dw / dd)


# The squared distance from q to an arc (helix) at turn theta in [0, T], T = |sweep|:
#   f(theta) = P(chi) + L2 theta^2 - 2 b theta + const,   chi = chi0 + sigma theta,
# where the axes of the mask off the plane move linearly (L2 = sum of their squared
# rates per radian, b = sum rate * (q - start)) and P is the plane's share:
#   both plane axes in the mask: P = rho^2 + r^2 - 2 r rho cos(chi)   (rho, angle of q)
#   one plane axis:              P = (u - r cos(chi))^2               (u = q - centre)
#   none:                        P = 0
# f'' is a polynomial of degree <= 2 in cos(chi), so its zeros split [0, T] into
# pieces where f' is monotonic: each holds at most one minimum, where f' turns from
# negative to positive; with the two ends they are every candidate.
cdef inline double _arc_df(const ArcDistanceFn *f, double theta) noexcept nogil:
    """f'(theta), the derivative of the squared distance to the arc at turn theta (the formula
    above)."""
    cdef double chi = f.chi0 + f.sigma * theta
    cdef double d = 2.0 * (f.L2 * theta - f.b)
    if f.plane_axes == 2:
        d += 2.0 * f.r * f.rho * f.sigma * sin(chi)
    elif f.plane_axes == 1:
        d += 2.0 * f.sigma * f.r * sin(chi) * (f.u - f.r * cos(chi))
    return d


cdef inline double _arc_ddf(const ArcDistanceFn *f, double theta) noexcept nogil:
    """f''(theta), whose zeros split the arc into pieces where f' is monotonic."""
    cdef double t = cos(f.chi0 + f.sigma * theta)
    if f.plane_axes == 2:
        return 2.0 * (f.r * f.rho * t + f.L2)
    if f.plane_axes == 1:
        return 2.0 * (f.r * f.r - 2.0 * f.r * f.r * t * t + f.u * f.r * t + f.L2)
    return 2.0 * f.L2


cdef int _add_turns(const ArcDistanceFn *f, double t, double T, double *at, int n) noexcept nogil:
    """Appends the theta in (0, T) where cos(chi) = t."""
    cdef double base, theta
    cdef int sign
    if not (t > -1.0 and t < 1.0):
        return n
    for sign in range(2):
        base = acos(t) if sign == 0 else -acos(t)
        theta = fmod(f.sigma * (base - f.chi0), 2.0 * M_PI)
        if theta < 0.0:
            theta += 2.0 * M_PI
        while theta < T and n < 12:
            if theta > 0.0:
                at[n] = theta
                n += 1
            theta += 2.0 * M_PI
    return n


cdef double _root(const ArcDistanceFn *f, double lo, double hi) noexcept nogil:
    """The zero of f' in [lo, hi], where f' rises from < 0 to >= 0: Newton steps kept
    inside the bracket, bisection otherwise, to the last bits of theta."""
    cdef double x = 0.5 * (lo + hi), fx, ddf, step
    cdef int it
    for it in range(100):
        fx = _arc_df(f, x)
        if fx == 0.0:
            return x
        if fx < 0.0:
            lo = x
        else:
            hi = x
        ddf = _arc_ddf(f, x)
        step = x - fx / ddf if ddf > 0.0 else lo - 1.0
        if not (step > lo and step < hi):
            step = 0.5 * (lo + hi)
        if fabs(step - x) <= ROOT_REL_EPS * (1.0 + fabs(x)) or hi - lo <= ROOT_REL_EPS * (1.0 + fabs(x)):
            return step
        x = step
    return x


cdef double _arc_nearest(const Segment *g, uint32_t axes, const double *q) noexcept nogil:
    """Path length of the point of an arc (helix) nearest q in the axes (see ArcDistanceFn)."""
    cdef ArcDistanceFn f
    cdef double T = fabs(g.sweep)
    cdef double at[14]
    cdef double point[AXES]
    cdef double rate, beta = 0.0, best_d2, d2, best_theta, x, lo, hi, disc
    cdef bint in_first = (axes >> g.first) & 1, in_second = (axes >> g.second) & 1
    cdef int n = 0, k, j
    f.r = g.radius
    f.sigma = 1.0 if g.sweep > 0.0 else -1.0
    f.L2 = 0.0
    f.b = 0.0
    f.rho = 0.0
    f.u = 0.0
    for k in range(g.n_axes):
        if k == g.first or k == g.second or not (axes >> k) & 1:
            continue
        rate = (g.end[k] - g.start[k]) / T
        f.L2 += rate * rate
        f.b += rate * (q[k] - g.start[k])
    if in_first and in_second:
        f.plane_axes = 2
        f.rho = hypot(q[g.first] - g.centre[0], q[g.second] - g.centre[1])
        beta = atan2(q[g.second] - g.centre[1], q[g.first] - g.centre[0])
    elif in_first or in_second:
        f.plane_axes = 1
        if in_first:
            f.u = q[g.first] - g.centre[0]
        else:
            f.u = q[g.second] - g.centre[1]
            beta = 0.5 * M_PI          # sin(psi) = cos(psi - pi/2)
    else:
        f.plane_axes = 0
    f.chi0 = atan2(g.start[g.second] - g.centre[1], g.start[g.first] - g.centre[0]) - beta
    # the pieces where f' is monotonic
    if f.plane_axes == 2 and f.r * f.rho > 0.0:
        n = _add_turns(&f, -f.L2 / (f.r * f.rho), T, at, n)
    elif f.plane_axes == 1 and f.r > 0.0:
        disc = sqrt(f.u * f.u + 8.0 * (f.r * f.r + f.L2))
        n = _add_turns(&f, (f.u + disc) / (4.0 * f.r), T, at, n)
        n = _add_turns(&f, (f.u - disc) / (4.0 * f.r), T, at, n)
    at[n] = 0.0
    at[n + 1] = T
    n += 2
    for k in range(1, n):               # insertion sort of at most 14
        x = at[k]
        j = k - 1
        while j >= 0 and at[j] > x:
            at[j + 1] = at[j]
            j -= 1
        at[j + 1] = x
    best_theta = 0.0
    best_d2 = segment_distance2_at(g, 0.0, axes, q, point)
    for k in range(n - 1):
        lo = at[k]
        hi = at[k + 1]
        if hi <= lo or not (_arc_df(&f, lo) < 0.0 and _arc_df(&f, hi) >= 0.0):
            continue
        x = _root(&f, lo, hi)
        d2 = segment_distance2_at(g, g.length * (x / T), axes, q, point)
        if d2 < best_d2:
            best_d2 = d2
            best_theta = x
    if segment_distance2_at(g, g.length, axes, q, point) < best_d2:
        return g.length
    return g.length * (best_theta / T)


cdef double segment_nearest(const Segment *g, uint32_t axes, const double *q) noexcept nogil:
    """Path length of the point of g nearest q in the axes of `axes` (bit k = axis k;
    axes [0, n_axes) count): exact for lines (a projection), arcs and helices (every
    minimum of the distance along the turn, ArcDistanceFn); the start for no length."""
    if g.length <= 0.0:
        return 0.0
    if g.arc:
        return _arc_nearest(g, axes, q)
    return _line_nearest(g, axes, q)
