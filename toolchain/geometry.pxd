# Face of geometry.pyx: plane and arc geometry shared by the stages. Planes name
# their two arc axes in order (first, second) and the normal: 17 XY, 18 XZ, 19 YZ,
# -18 ZX; counter-clockwise is the positive turn from first to second. Owns nothing;
# called by the compiler, the compensation, the extent, the planner and the machine.

from libc.math cimport sqrt


cdef inline double distance2d(double dx, double dy) noexcept nogil:
    """Length of (dx, dy). libm's hypot guards against overflow at several times the
    cost; machine coordinates never come near it."""
    return sqrt(dx * dx + dy * dy)


# an axis index's letter (x y z c b u v w a o); a plane's axes (False: no plane);
# an arc's signed sweep in (0, 2pi] in its direction; the distance over ten axes
cdef const char *axis_name(int k) noexcept nogil
cdef bint plane_axes(int plane, int *first, int *second, int *normal) noexcept nogil
cdef double arc_sweep(double sa, double sb, double ea, double eb, double ca, double cb,
                      bint ccw) noexcept nogil
cdef double segment_length(const double *s, const double *e) noexcept nogil
