# The extent of a compiled program (GetGCodeSizeInfo): start, end, minimum and
# maximum over every motion part, arcs with their true extreme points.
from libc.math cimport M_PI, floor, ceil, cos, sin
from libc.string cimport memcpy


cdef inline void _widen(GCODE_SIZE *size, const double *point) noexcept nogil:
    cdef double *lo = <double *>&size.m_minimalPos
    cdef double *hi = <double *>&size.m_maximalPos
    cdef int k
    for k in range(10):
        if point[k] < lo[k]:
            lo[k] = point[k]
        if point[k] > hi[k]:
            hi[k] = point[k]


cdef void _widen_arc(GCODE_SIZE *size, const double *s, const double *e, const double *cc,
                     double radius, int plane, bint ccw) noexcept nogil:
    """Adds the quadrant points (0, 90, 180, 270 degrees) the arc passes through."""
    cdef int first, second, normal, q, q0, q1
    cdef double a0, sweep, angle
    cdef double point[10]
    if radius <= 0 or not plane_axes(plane, &first, &second, &normal):
        return
    sweep = arc_sweep(s[first], s[second], e[first], e[second], cc[first], cc[second], ccw)
    a0 = atan2(s[second] - cc[second], s[first] - cc[first])
    memcpy(point, e, sizeof(point))
    if sweep > 0:
        q0 = <int>ceil(a0 / (M_PI / 2))
        q1 = <int>floor((a0 + sweep) / (M_PI / 2))
    else:
        q0 = <int>ceil((a0 + sweep) / (M_PI / 2))
        q1 = <int>floor(a0 / (M_PI / 2))
    for q in range(q0, q1 + 1):
        angle = q * (M_PI / 2)
        point[first] = cc[first] + radius * cos(angle)
        point[second] = cc[second] + radius * sin(angle)
        _widen(size, point)


cdef inline void _unrotate(const Program *prog, uint16_t rot_idx, double *point) noexcept nogil:
    """The point as written in the program: the inverse (transpose) of its G168 rotation."""
    cdef const double *r
    cdef double q[3]
    cdef int a
    if rot_idx == 0:
        return
    r = prog.rotations + 12 * rot_idx
    for a in range(3):
        q[a] = point[a] - r[a]
    for a in range(3):
        point[a] = r[a] + r[3 + a] * q[0] + r[6 + a] * q[1] + r[9 + a] * q[2]


cdef void _extent(const Program *prog, GCODE_SIZE *size, bint compensated, bint rotated) noexcept nogil:
    """Extent of the programmed (or compensated) path, as the machine runs it
    (rotated) or as the program is written (G168 undone)."""
    cdef size_t i
    cdef const Part *p
    cdef double s[10]
    cdef double e[10]
    cdef double cc[3]
    cdef double programmed_radius
    cdef int first, second, normal
    memcpy(&size.m_startPos, prog.start, sizeof(P10DOUBLE))
    memcpy(&size.m_minimalPos, prog.start, sizeof(P10DOUBLE))
    memcpy(&size.m_maximalPos, prog.start, sizeof(P10DOUBLE))
    memcpy(&size.m_endPos, prog.start, sizeof(P10DOUBLE))
    for i in range(prog.n_parts):
        p = &prog.parts[i]
        if p.kind != PART_MOTION:
            continue
        if compensated:
            part_calc_start(prog, i, s)
            memcpy(e, p.e, sizeof(e))
            e[0] = p.ce[0]; e[1] = p.ce[1]; e[2] = p.ce[2]
        else:
            memcpy(s, part_start(prog, i), sizeof(s))
            memcpy(e, p.e, sizeof(e))
        memcpy(cc, p.cc, sizeof(cc))
        if not rotated:
            if i > 0:
                _unrotate(prog, prog.parts[i - 1].rot_idx, s)
            _unrotate(prog, p.rot_idx, e)
            _unrotate(prog, p.rot_idx, cc)
        _widen(size, e)
        memcpy(&size.m_endPos, e, sizeof(P10DOUBLE))
        if p.func == 2 or p.func == 3:
            if compensated:
                _widen_arc(size, s, e, cc, p.radius, p.plane, p.func == 3)
            elif plane_axes(p.plane, &first, &second, &normal):
                programmed_radius = hypot(s[first] - cc[first], s[second] - cc[second])
                _widen_arc(size, s, e, cc, programmed_radius, p.plane, p.func == 3)


cdef void program_extent(const Program *prog, GCODE_INFO *info) noexcept nogil:
    """[0] programmed, [1] compensated (the same without compensation), both as the
    program is written; [2] and [3] the same as the machine runs them (G168 applied)."""
    _extent(prog, &info.m_size[2], False, True)
    if prog.compensated:
        _extent(prog, &info.m_size[3], True, True)
    else:
        info.m_size[3] = info.m_size[2]
    if prog.n_rotations > 1:
        _extent(prog, &info.m_size[0], False, False)
        if prog.compensated:
            _extent(prog, &info.m_size[1], True, False)
        else:
            info.m_size[1] = info.m_size[0]
    else:
        info.m_size[0] = info.m_size[2]
        info.m_size[1] = info.m_size[3]


cdef void program_move_start(Program *prog, const double *position) noexcept nogil:
    """ResetCNC with coordinates: a program written relative to its start (G91 from
    the first block) moves with it; any other keeps its positions and only its
    first move starts from the new position."""
    cdef double delta[10]
    cdef size_t i
    cdef int k
    cdef Part *p
    if prog.relative_only:
        for k in range(10):
            delta[k] = position[k] - prog.start[k]
        for i in range(prog.n_parts):
            p = &prog.parts[i]
            for k in range(10):
                p.e[k] += delta[k]
            for k in range(3):
                p.ce[k] += delta[k]
                p.cc[k] += delta[k]
        for i in range(1, prog.n_rotations):
            for k in range(3):
                prog.rotations[12 * i + k] += delta[k]
    memcpy(prog.start, position, sizeof(prog.start))
