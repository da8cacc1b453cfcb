# The geometry module (toolchain/geometry.pyx) alone: a Segment made from numbers
# given from Python and what is measured along it; the plane's 2-D primitives.

cdef class Seg:
    """segment_shape of start -> end (n_axes values each; padded to n_axes): a line,
    or with plane (17 18 19 -18) and radius > 0 an arc round centre (x y z) in the
    direction ccw, a helix when the other axes move."""
    cdef Segment g

    def __init__(self, start, end, int plane=0, centre=(0.0, 0.0, 0.0), double radius=0.0,
                 bint ccw=False, int n_axes=AXES):
        cdef double c[3]
        if not (1 <= n_axes <= AXES):
            raise ValueError("n_axes")
        self.g.n_axes = n_axes
        _fill(self.g.start, start, n_axes)
        _fill(self.g.end, end, n_axes)
        _fill(c, centre, 3)
        segment_shape(&self.g, plane, radius, c, ccw)

    @property
    def length(self):
        return self.g.length

    @property
    def arc(self):
        return bool(self.g.arc)

    @property
    def sweep(self):
        return self.g.sweep if self.g.arc else 0.0

    @property
    def lead(self):
        return self.g.lead if self.g.arc else 0.0

    @property
    def plane_axes(self):
        return (self.g.first, self.g.second) if self.g.arc else None

    def point(self, double s):
        """segment_point_at: axes [0, n_axes)."""
        cdef double out[AXES]
        segment_point_at(&self.g, s, out)
        return [out[k] for k in range(self.g.n_axes)]

    def tangent(self, double s):
        """segment_tangent: all axes."""
        cdef double t[AXES]
        segment_tangent(&self.g, s, t)
        return [t[k] for k in range(AXES)]

    def curvature(self):
        return segment_curvature(&self.g)

    def reach(self):
        """segment_axis_reach: all axes."""
        cdef double r[AXES]
        segment_axis_reach(&self.g, r)
        return [r[k] for k in range(AXES)]

    def feed_length(self, unsigned int ignored):
        return segment_feed_length(&self.g, ignored)

    def box(self):
        """segment_box: (low corner, high corner), axes [0, n_axes)."""
        cdef double lo[AXES]
        cdef double hi[AXES]
        segment_box(&self.g, lo, hi)
        return [lo[k] for k in range(self.g.n_axes)], [hi[k] for k in range(self.g.n_axes)]

    def nearest(self, q, unsigned int axes):
        """segment_nearest: (s, squared distance in the axes, the point at s)."""
        cdef double qq[AXES]
        cdef double point[AXES]
        cdef double s, d2
        _fill(qq, q, AXES)
        s = segment_nearest(&self.g, axes, qq)
        d2 = segment_distance2_at(&self.g, s, axes, qq, point)
        return s, d2, [point[k] for k in range(self.g.n_axes)]


def arc_sweep_of(double sx, double sy, double ex, double ey, bint ccw):
    return arc_sweep(sx, sy, ex, ey, ccw)


def turn_from_of(double ax, double ay, double bx, double by, int direction):
    return turn_from(ax, ay, bx, by, direction)


def vector_turn_near_of(double ax, double ay, double bx, double by):
    return vector_turn_near(ax, ay, bx, by)


def pseudo_sweep_of(double sx, double sy, double ex, double ey, int direction):
    return pseudo_sweep(sx, sy, ex, ey, direction)


def arc_axis_points_of(double sx, double sy, double ex, double ey, bint ccw, double turn=-1.0):
    return arc_axis_points(sx, sy, ex, ey, ccw, turn)


def line_circle_of(p, u, c, double r, double slack=0.0):
    """The two points, or None."""
    cdef double pp[2]
    cdef double uu[2]
    cdef double cc[2]
    cdef double pts[4]
    _fill(pp, p, 2)
    _fill(uu, u, 2)
    _fill(cc, c, 2)
    if not line_circle(pp, uu, cc, r, slack, pts):
        return None
    return [(pts[0], pts[1]), (pts[2], pts[3])]


def circle_circle_of(c1, double r1, c2, double r2, double slack=0.0):
    """The two points, or None."""
    cdef double a[2]
    cdef double b[2]
    cdef double pts[4]
    _fill(a, c1, 2)
    _fill(b, c2, 2)
    if not circle_circle(a, r1, b, r2, slack, pts):
        return None
    return [(pts[0], pts[1]), (pts[2], pts[3])]


def tolerances():
    """The named tolerances and limits."""
    return dict(ANGLE_EPS=ANGLE_EPS, TURN_EPS=TURN_EPS, LENGTH_EPS=LENGTH_EPS, ROUNDING_EPS=ROUNDING_EPS,
                CLOSED_EPS=CLOSED_EPS, NO_LIMIT=NO_LIMIT)
