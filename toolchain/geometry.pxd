# Face of geometry.pyx: the geometry every stage shares, each algorithm once. Planes
# name their two arc axes in order (first, second) and the normal: 17 XY, 18 XZ,
# 19 YZ, -18 ZX; counter-clockwise is the positive turn from first to second. Owns the
# named tolerances and limits, the 2-D primitives of the plane (angles, sweeps, the
# axis points an arc passes, crossings of lines and circles), rotations, Segment (a part as the
# tool runs it: lines, arcs and helices in any plane, the other axes along) with its
# length, point, tangent, curvature, box and nearest point, and where a run's
# placement moves a part. Called by the compiler, the compensation, the extent, the
# planner, placement, the toolpath, the simulator, the machine and its connection
# search (docs/geometry.md).

from libc.math cimport atan2, sqrt, fabs, cos, sin, M_PI


# ---- tolerances and limits: every stage compares with these, none with a literal
cdef extern from *:
    """
    #define TC_ANGLE_EPS 1e-12
    #define TC_TURN_EPS 1e-9
    #define TC_LENGTH_EPS 1e-9
    #define TC_ROUNDING_EPS 1e-12
    #define TC_CLOSED_EPS 1e-6
    #define TC_MEET_EPS 1e-7
    #define TC_ROOT_REL_EPS 1e-15
    #define TC_SPEED2_REL_EPS 1e-9
    #define TC_UNDERFLOW_EPS 1e-300
    #define TC_COS2_REL_EPS 1e-9
    #define TC_NO_LIMIT 1e12
    """
    # radians, or the sine of an angle: directions closer than this are one (the ends
    # of an arc that meet within it make a full turn; lines this near parallel do not
    # cross; three points this near a line have no circle); a unit vector's component
    # this small is none
    const double ANGLE_EPS "TC_ANGLE_EPS"
    # radians: an arc of the tool path that sweeps no more is no arc; a corner that
    # turns no more is tangent (G167 inserts no arc there)
    const double TURN_EPS "TC_TURN_EPS"
    # mm: points this close are one point; a move this short does not move (the
    # planner gives it no speed, the compensation no element)
    const double LENGTH_EPS "TC_LENGTH_EPS"
    # mm: what rounding leaves of a zero length or radius: no direction to divide by
    # (a line of no length, concentric circles, an offset arc of radius zero)
    const double ROUNDING_EPS "TC_ROUNDING_EPS"
    # mm: a contour whose last point comes this close to its first is closed
    const double CLOSED_EPS "TC_CLOSED_EPS"
    # mm: two pieces of a compensated contour's regions that meet this close to an end
    # of each touch there, they do not cross; the least slack of a joint (rounding
    # moves tangent pieces' meets farther on large coordinates: regions.pyx)
    const double MEET_EPS "TC_MEET_EPS"
    # relative to 1 + |x| (radians): a Newton step or bracket of the nearest point on an
    # arc this small has found the root to the last bits of a double
    const double ROOT_REL_EPS "TC_ROOT_REL_EPS"
    # relative to the squared entry speed: a squared exit speed less than this below the
    # lowest that braking allows is rounding (the plan keeps floats), not a plan that
    # brakes harder than the part can
    const double SPEED2_REL_EPS "TC_SPEED2_REL_EPS"
    # mm^4: a squared cross product this small is zero even where ANGLE_EPS^2 times the
    # squared lengths underflows (lines of no length have no direction: no crossing)
    const double UNDERFLOW_EPS "TC_UNDERFLOW_EPS"
    # relative to a squared cosine: a turn whose squared cosine is this much below the
    # bound's is beyond it whatever the rounding of the unit vectors (a few 1e-16;
    # join_lines tells turns from squares, the unit vectors only near the bound)
    const double COS2_REL_EPS "TC_COS2_REL_EPS"
    # mm/s^2: an acceleration of a motion class that is 0, or not below this, is no
    # limit, and stands for it (ramps instant in practice, the closed forms finite)
    const double NO_LIMIT "TC_NO_LIMIT"


cdef inline double limit_or_none(double acc) noexcept nogil:
    """A motion class's acceleration (acc or dec) as the planner and the machine use
    it: NO_LIMIT when the table gives none."""
    return acc if 0.0 < acc < NO_LIMIT else NO_LIMIT


# ---- Segment: a motion part as the tool runs it (the compensated path). A line
# moves every axis in proportion; an arc turns its two plane axes round the centre
# (radius: the tool path's, which the ends may miss by the compiler's tolerance) and
# moves the other axes in proportion to the turn (a helix). Every point inside lies
# on the circle of `radius`; the ends are start and end exactly.
ctypedef struct Segment:
    double length
    int n_axes              # 3: only x y z may move (the other seven as the part before), else AXES
    double start[AXES]      # axes [0, n_axes)
    double end[AXES]
    bint arc                # a circular (or helical) part with a plane and a radius
    int first, second, normal   # plane axes of an arc
    double radius           # of the tool path (compensated)
    double centre[2]        # in the plane (first, second)
    double sweep            # signed, + = counter-clockwise, in (0, 2pi] in the arc's direction
    double lead             # off-plane travel per radian of turn (helix), >= 0

# The squared distance to an arc (helix) as a function of its turn (segment_nearest).
ctypedef struct ArcDistanceFn:
    int plane_axes              # 0, 1 or 2 of the plane's axes in the mask
    double r, rho, u            # radius; |q - centre| in the plane (2); q - centre (1)
    double chi0, sigma          # chi at theta = 0, direction
    double L2, b


# ---- the plane's 2-D primitives (vectors and arcs by their radius vectors from the
# centre; small and hot, so inline here)
cdef inline double distance2d(double dx, double dy) noexcept nogil:
    """Length of (dx, dy). libm's hypot guards against overflow at several times the
    cost; machine coordinates never come near it."""
    return sqrt(dx * dx + dy * dy)


cdef inline double cross2d(double ax, double ay, double bx, double by) noexcept nogil:
    """a x b: > 0 when b lies counter-clockwise of a."""
    return ax * by - ay * bx


cdef inline double vector_turn(double ax, double ay, double bx, double by) noexcept nogil:
    """Signed angle from vector a to vector b, in (-pi, pi]."""
    return atan2(ax * by - ay * bx, ax * bx + ay * by)


cdef inline double vector_turn_near(double ax, double ay, double bx, double by) noexcept nogil:
    """vector_turn for the usual case of b on (or next to) the ray of a (an arc's end
    the corners did not trim lies on its radius): the angle is rounding noise and
    atan(t) = t - t^3/3 is t to far below 1e-24 for |t| <= 1e-8."""
    cdef double y = ax * by - ay * bx
    cdef double x = ax * bx + ay * by
    if x > 0 and fabs(y) <= 1e-8 * x:
        return y / x
    return atan2(y, x)


cdef inline double arc_sweep(double sx, double sy, double ex, double ey, bint ccw) noexcept nogil:
    """Signed sweep (radians, + = counter-clockwise) of an arc from the radius vector
    (sx, sy) to (ex, ey), in (0, 2pi] in its direction; a full turn when they meet
    within ANGLE_EPS."""
    cdef double d = vector_turn(sx, sy, ex, ey)
    if ccw:
        if d <= ANGLE_EPS:
            d += 2.0 * M_PI
    elif d >= -ANGLE_EPS:
        d -= 2.0 * M_PI
    return d


cdef inline double turn_from(double ax, double ay, double bx, double by, int direction) noexcept nogil:
    """Angle from vector a to vector b turning in `direction` (+1 counter-clockwise,
    -1 clockwise), in [0, 2pi)."""
    cdef double t = direction * vector_turn(ax, ay, bx, by)
    if t < 0:
        t += 2.0 * M_PI
    return t


cdef inline double pseudo_angle(double x, double y) noexcept nogil:
    """A monotone stand-in for the angle of (x, y) in [0, 4): k at the k-th axis
    direction (+x, +y, -x, -y), no trigonometry."""
    if y >= 0:
        if x >= 0:
            return y / (x + y) if x + y > 0 else 0.0
        return 1.0 - x / (y - x)
    if x < 0:
        return 2.0 - y / (-x - y)
    return 3.0 + x / (x - y)


cdef inline double pseudo_sweep(double sx, double sy, double ex, double ey, int direction) noexcept nogil:
    """A stand-in for the sweep of an arc from radius vector s to e turning in
    `direction`, in (0, 2pi]: monotone in the true one and equal to it at every
    quarter turn (so it compares with pi and 2pi as the sweep does), without
    trigonometry; a full turn when s = e."""
    cdef double d = pseudo_angle(ex, direction * ey) - pseudo_angle(sx, direction * sy)
    if d <= 0:
        d += 4.0
    return d * (0.5 * M_PI)


cdef inline int _quadrant(double x, double y) noexcept nogil:
    # quadrant q of a direction whose angle lies in [q * 90, (q + 1) * 90) degrees
    if y >= 0:
        return 0 if x > 0 else (1 if y > 0 else 2)
    return 2 if x < 0 else 3


cdef inline unsigned arc_axis_points(double sx, double sy, double ex, double ey, bint ccw,
                                     double turn) noexcept nogil:
    """The axis points an arc passes, where its extent reaches centre +- radius: bit q
    set for the direction q * 90 degrees from the centre (bit 0 +first, 1 +second,
    2 -first, 3 -second), its ends included; (sx, sy), (ex, ey) its ends from the
    centre. Found from the quadrants of the ends, no angles. turn: |sweep| when the
    caller knows it (it decides where the ends alone cannot: ends that nearly meet
    after nearly a full turn, or an end a hair behind the start of a short arc),
    else < 0: ends that meet within ANGLE_EPS are a full turn."""
    cdef double cross, dot
    cdef int qs, qe, n, k, k0
    cdef unsigned mask = 0
    if not ccw:
        # a clockwise arc covers the same points as the counter-clockwise one from e to s
        sx, sy, ex, ey = ex, ey, sx, sy
    qs = _quadrant(sx, sy)
    qe = _quadrant(ex, ey)
    n = (qe - qs) & 3
    cross = sx * ey - sy * ex
    if turn < 0:
        if n == 0 and cross <= ANGLE_EPS * sqrt((sx * sx + sy * sy) * (ex * ex + ey * ey)):
            n = 4           # the end is not ahead of the start: all the way round
    else:
        dot = sx * ex + sy * ey
        if dot > 0 and cross >= 0 and turn > 1.5 * M_PI:
            n = 4           # the ends nearly meet after nearly a full turn
        elif dot > 0 and cross < 0 and turn < 0.5 * M_PI:
            n = 0           # the end a hair behind the start of a short arc
        elif n == 0 and cross < 0:
            n = 4
    # a start exactly on an axis counts too (the ends already widen an extent, but
    # the axis point, centre + radius, may differ from them in the last bits)
    k0 = 0 if n < 4 and (sy == 0 if qs % 2 == 0 else sx == 0) else 1
    for k in range(k0, n + 1):
        mask |= 1u << ((qs + k) & 3)
    return mask


cdef inline void arc_point_at(const double *centre, double radius, double start_a, double start_b,
                              double turn, double *out) noexcept nogil:
    """The point of the circle (centre, radius) `turn` radians (+ = counter-clockwise)
    on from the point (start_a, start_b) of it, in the plane."""
    cdef double theta = atan2(start_b - centre[1], start_a - centre[0]) + turn
    out[0] = centre[0] + radius * cos(theta)
    out[1] = centre[1] + radius * sin(theta)


cdef inline bint line_circle(const double *p, const double *u, const double *c, double r, double slack,
                             double *pts) noexcept nogil:
    """Where the line p + t u (u a unit vector) meets the circle (c, r): pts = the two
    points, t = -b + q first (a tangent gives one twice); a miss by less than `slack`
    counts as tangent. False when they do not meet."""
    cdef double wx = p[0] - c[0], wy = p[1] - c[1]
    cdef double b = wx * u[0] + wy * u[1]
    cdef double disc = b * b - (wx * wx + wy * wy - r * r)
    cdef double q
    if disc < 0:
        if disc < -2.0 * slack * r:
            return False
        disc = 0.0
    q = sqrt(disc)
    pts[0] = p[0] + (-b + q) * u[0]; pts[1] = p[1] + (-b + q) * u[1]
    pts[2] = p[0] + (-b - q) * u[0]; pts[3] = p[1] + (-b - q) * u[1]
    return True


cdef inline bint circle_circle(const double *c1, double r1, const double *c2, double r2, double slack,
                               double *pts) noexcept nogil:
    """Where two circles meet: pts = the two points (left of the line c1 -> c2 first;
    circles that touch give one twice); a miss by less than `slack` counts as a touch.
    False when they do not meet or are concentric."""
    cdef double dx = c2[0] - c1[0], dy = c2[1] - c1[1]
    cdef double dist = distance2d(dx, dy)
    cdef double a, h2, h, mx, my
    if dist < ROUNDING_EPS:
        return False
    a = (r1 * r1 - r2 * r2 + dist * dist) / (2.0 * dist)
    h2 = r1 * r1 - a * a
    if h2 < 0:
        if h2 < -2.0 * slack * (r1 if r1 > r2 else r2):
            return False
        h2 = 0.0
    h = sqrt(h2)
    mx = c1[0] + a * dx / dist
    my = c1[1] + a * dy / dist
    pts[0] = mx - h * dy / dist; pts[1] = my + h * dx / dist
    pts[2] = mx + h * dy / dist; pts[3] = my - h * dx / dist
    return True


cdef inline void rotate_about(const double *centre, const double *matrix, bint back, double *point) noexcept nogil:
    """point (x y z) turned by `matrix` (3 x 3, by rows) about `centre`; back: by its
    transpose, the turn undone (a G168 rotation)."""
    cdef double q[3]
    cdef int a
    for a in range(3):
        q[a] = point[a] - centre[a]
    for a in range(3):
        if back:
            point[a] = centre[a] + matrix[a] * q[0] + matrix[3 + a] * q[1] + matrix[6 + a] * q[2]
        else:
            point[a] = centre[a] + matrix[3 * a] * q[0] + matrix[3 * a + 1] * q[1] + matrix[3 * a + 2] * q[2]


# ---- what other stages call
# an axis index's letter (x y z c b u v w a o); a plane's axes (False: no plane)
cdef const char *axis_name(int k) noexcept nogil
cdef bint plane_axes(int plane, int *first, int *second, int *normal) noexcept nogil

# a Segment whose start, end and n_axes are set, completed: an arc (plane 17 18 19
# -18, radius > 0, centre x y z of which the plane's two are read) or else a line
cdef void segment_shape(Segment *g, int plane, double radius, const double *centre, bint ccw) noexcept nogil
# a compiled part as a Segment: as compiled, as a run from pl places it (all ten
# axes), as the API's record gives it; its tool path length (0 for no motion), as
# compiled and as placed
cdef void segment_of_part(const Program *prog, size_t i, Segment *g) noexcept nogil
cdef void segment_of_placed_part(const Program *prog, size_t i, const Placement *pl, Segment *g) noexcept nogil
cdef void segment_of_gm(const SIMPLE_GM_PARAMS *gm, Segment *g) noexcept nogil
cdef double part_length(const Program *prog, size_t i) noexcept nogil
cdef double placed_part_length(const Program *prog, size_t i, const Placement *pl) noexcept nogil
# how far a run from pl moves part i's start and its end, each axis (the axes that
# follow the run's start); True when they move apart (the part is reshaped)
cdef bint placement_shift(const Program *prog, size_t i, const Placement *pl, double *start_shift,
                          double *end_shift) noexcept nogil

# along a Segment: the point (axes [0, n_axes)) and the unit tangent (all axes) at
# path length s; the curvature (1/mm, 0 for a line); the length over the axes not
# in `ignored` (bit k = axis k); each axis's largest share of the path speed
cdef void segment_point_at(const Segment *g, double s, double *out) noexcept nogil
cdef void segment_tangent(const Segment *g, double s, double *t) noexcept nogil
cdef double segment_curvature(const Segment *g) noexcept nogil
cdef double segment_feed_length(const Segment *g, uint32_t ignored) noexcept nogil
cdef void segment_axis_reach(const Segment *g, double *reach) noexcept nogil
# its box (axes [0, n_axes)): low and high corner, the arc's true extremes
cdef void segment_box(const Segment *g, double *lo, double *hi) noexcept nogil
# the path length of its point nearest q in the axes of `axes` (bit k = axis k), and
# the squared distance in those axes from q to the point at s (written to `point`)
cdef double segment_nearest(const Segment *g, uint32_t axes, const double *q) noexcept nogil
cdef double segment_distance2_at(const Segment *g, double s, uint32_t axes, const double *q,
                                 double *point) noexcept nogil
