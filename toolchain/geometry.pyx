# Plane and arc geometry shared by the stages (compiler, compensation, size info,
# planner). Planes name their two arc axes in order (first, second) and the normal:
# 17 XY, 18 XZ, 19 YZ, -18 ZX. Counter-clockwise = positive turn from first to second.
from libc.math cimport atan2, sqrt, fabs, M_PI, cos, sin


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


cdef double arc_sweep(double sa, double sb, double ea, double eb, double ca, double cb,
                      bint ccw) noexcept nogil:
    """Signed sweep (radians, + = CCW) from start to end about the centre, in (0, 2pi]
    in the arc's direction; a full circle when start and end coincide."""
    cdef double a0 = atan2(sb - cb, sa - ca)
    cdef double a1 = atan2(eb - cb, ea - ca)
    cdef double d = a1 - a0
    if ccw:
        while d <= 1e-12:
            d += 2.0 * M_PI
        while d > 2.0 * M_PI + 1e-12:
            d -= 2.0 * M_PI
    else:
        while d >= -1e-12:
            d -= 2.0 * M_PI
        while d < -2.0 * M_PI - 1e-12:
            d += 2.0 * M_PI
    return d


cdef double segment_length(const double *s, const double *e) noexcept nogil:
    """Straight distance over all ten axes."""
    cdef double acc = 0.0, d
    cdef int i
    for i in range(10):
        d = e[i] - s[i]
        acc += d * d
    return sqrt(acc)
