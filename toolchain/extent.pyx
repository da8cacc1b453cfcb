# The extent of a compiled program (GetGCodeSizeInfo): start, end, minimum and
# maximum over every motion part, arcs with their true extreme points. A pass widens
# the extent by a range of parts (extent_range), so that it may also be measured range
# by range beside the stage that writes the parts (pipeline.pyx).
from libc.string cimport memcpy


cdef inline void _widen(GCODE_SIZE *size, const double *point, int axes) noexcept nogil:
    """Widens the first `axes` axes of the extent to the point."""
    cdef double *lo = <double *>&size.m_minimalPos
    cdef double *hi = <double *>&size.m_maximalPos
    cdef int k
    for k in range(axes):
        if point[k] < lo[k]:
            lo[k] = point[k]
        if point[k] > hi[k]:
            hi[k] = point[k]


cdef inline void _widen_axis(GCODE_SIZE *size, int k, double value) noexcept nogil:
    """The size's minimum and maximum on axis k grown to take in value."""
    cdef double *lo = <double *>&size.m_minimalPos
    cdef double *hi = <double *>&size.m_maximalPos
    if value < lo[k]:
        lo[k] = value
    if value > hi[k]:
        hi[k] = value


cdef void _widen_arc(GCODE_SIZE *size, const double *s, const double *e, const double *cc,
                     double radius, int first, int second, bint ccw) noexcept nogil:
    """Adds the axis points (0, 90, 180, 270 degrees) the arc passes through
    (geometry.pxd arc_axis_points: no angles; start = end, within ANGLE_EPS, is a full
    circle); its ends widen the extent already."""
    cdef unsigned passes
    cdef const double *lo = <const double *>&size.m_minimalPos
    cdef const double *hi = <const double *>&size.m_maximalPos
    cdef int q
    if radius <= 0:
        return
    # its whole circle inside the extent so far: the arc cannot widen it (most arcs
    # of a large program)
    if (cc[first] - radius >= lo[first] and cc[first] + radius <= hi[first]
            and cc[second] - radius >= lo[second] and cc[second] + radius <= hi[second]):
        return
    passes = arc_axis_points(s[first] - cc[first], s[second] - cc[second],
                             e[first] - cc[first], e[second] - cc[second], ccw, -1.0)
    # the axis points differ from the ends only in the plane axes
    for q in range(4):
        if (passes >> q) & 1:
            _widen_axis(size, first, cc[first] + (radius if q == 0 else (-radius if q == 2 else 0.0)))
            _widen_axis(size, second, cc[second] + (radius if q == 1 else (-radius if q == 3 else 0.0)))


cdef inline void _start_size(GCODE_SIZE *size, const double *start) noexcept nogil:
    """A size that holds only the start: start, end, minimum and maximum all at it."""
    memcpy(&size.m_startPos, start, sizeof(P10DOUBLE))
    memcpy(&size.m_minimalPos, start, sizeof(P10DOUBLE))
    memcpy(&size.m_maximalPos, start, sizeof(P10DOUBLE))
    memcpy(&size.m_endPos, start, sizeof(P10DOUBLE))


cdef inline void _unrotate(const Program *prog, uint16_t rot_idx, double *point) noexcept nogil:
    """The point as written in the program: the inverse (transpose) of its G168 rotation."""
    cdef const double *r
    if rot_idx == 0:
        return
    r = prog.rotations + 12 * rot_idx
    rotate_about(r, r + 3, True, point)


cdef size_t extent_range(const Program *prog, size_t first, size_t end, GCODE_SIZE *programmed,
                         GCODE_SIZE *tool, bint rotated) noexcept nogil:
    """Widens the programmed and the compensated extent (x y z; the programmed one all
    ten axes) by the motion parts of [first, end), as the machine runs them (rotated)
    or as the program is written (G168 undone); the last motion part among them, or
    NO_MOTION. Ranges may be measured in any order: a part reads only itself and the
    end of the part before it."""
    cdef size_t i, last = NO_MOTION
    cdef uint32_t axes_idx = <uint32_t>-1
    cdef const Part *p
    cdef const double *s
    cdef const double *e
    cdef const double *cc
    cdef const PartExtra *x
    cdef double s_buf[3]
    cdef double e_buf[3]
    cdef double cc_buf[3]
    cdef double cs[3]
    cdef double ce[3]
    cdef double other[AXES]
    cdef double dx, dy
    cdef int first_axis, second_axis, normal
    cdef bint arc
    cdef uint16_t prev_rot = 0, rot = 0
    for i in range(first, end):
        p = &prog.parts[i]
        if p.kind != PART_MOTION:
            continue
        last = i
        s = part_start_xyz(prog, i)
        e = p.e
        x = part_extra(prog, p)
        cc = x.cc
        if not rotated:
            prev_rot = part_settings(prog, &prog.parts[i - 1]).rot_idx if i > 0 else 0
            rot = part_settings(prog, p).rot_idx
        if not rotated and (prev_rot != 0 or rot != 0):
            memcpy(s_buf, s, sizeof(s_buf))
            memcpy(e_buf, e, sizeof(e_buf))
            memcpy(cc_buf, cc, sizeof(cc_buf))
            _unrotate(prog, prev_rot, s_buf)
            _unrotate(prog, rot, e_buf)
            _unrotate(prog, rot, cc_buf)
            s = s_buf
            e = e_buf
            cc = cc_buf
        if p.axes_idx != axes_idx:
            # the other seven axes: once per entry of Program.axes
            axes_idx = p.axes_idx
            part_end(prog, p, other)
            other[0] = e[0]; other[1] = e[1]; other[2] = e[2]
            _widen(programmed, other, AXES)
        _widen(programmed, e, 3)
        arc = (p.func == 2 or p.func == 3) and plane_axes(p.plane, &first_axis, &second_axis, &normal)
        if arc:
            dx = s[first_axis] - cc[first_axis]
            dy = s[second_axis] - cc[second_axis]
            _widen_arc(programmed, s, e, cc, distance2d(dx, dy), first_axis, second_axis, p.func == 3)
        if not prog.compensated:
            continue
        ce[0] = p.ce[0]; ce[1] = p.ce[1]; ce[2] = p.ce[2]
        if not rotated:
            _unrotate(prog, rot, ce)
        _widen(tool, ce, 3)
        if arc:
            # the previous part's compensated end
            if i > 0:
                cs[0] = prog.parts[i - 1].ce[0]; cs[1] = prog.parts[i - 1].ce[1]; cs[2] = prog.parts[i - 1].ce[2]
                if not rotated:
                    _unrotate(prog, prev_rot, cs)
            else:
                cs[0] = s[0]; cs[1] = s[1]; cs[2] = s[2]
            _widen_arc(tool, cs, ce, cc, x.radius, first_axis, second_axis, p.func == 3)
    return last


cdef void extent_begin(const Program *prog, GCODE_SIZE *programmed, GCODE_SIZE *tool) noexcept nogil:
    """Both extents at the program's start, before any range widens them."""
    _start_size(programmed, prog.start)
    _start_size(tool, prog.start)


cdef void _extent_end(const Program *prog, size_t last, GCODE_SIZE *programmed, GCODE_SIZE *tool,
                      bint rotated) noexcept nogil:
    """The end positions (of the last motion part, NO_MOTION: none) once every part
    was measured. The tool path differs from the programmed one only in x y z: its
    other axes are the programmed ones."""
    cdef double tool_end[3]
    cdef int k
    if last == NO_MOTION:
        tool[0] = programmed[0]
        return
    part_end(prog, &prog.parts[last], <double *>&programmed.m_endPos)
    if not rotated:
        _unrotate(prog, part_settings(prog, &prog.parts[last]).rot_idx, <double *>&programmed.m_endPos)
    if not prog.compensated:
        tool[0] = programmed[0]
        return
    tool_end[0] = prog.parts[last].ce[0]; tool_end[1] = prog.parts[last].ce[1]; tool_end[2] = prog.parts[last].ce[2]
    if not rotated:
        _unrotate(prog, part_settings(prog, &prog.parts[last]).rot_idx, tool_end)
    tool.m_endPos = programmed.m_endPos
    for k in range(3, AXES):
        (<double *>&tool.m_minimalPos)[k] = (<double *>&programmed.m_minimalPos)[k]
        (<double *>&tool.m_maximalPos)[k] = (<double *>&programmed.m_maximalPos)[k]
    memcpy(&tool.m_endPos, tool_end, sizeof(tool_end))


cdef void extent_finish(const Program *prog, size_t last, GCODE_SIZE *programmed, GCODE_SIZE *tool,
                        GCODE_INFO *info) noexcept nogil:
    """GetGCodeSizeInfo's four extents once every part widened programmed[0] / tool[0]
    (as the machine runs the program) and, with G168 rotations, programmed[1] / tool[1]
    (as it is written); `last`: the last motion part. [0] programmed and [1]
    compensated as written, [2] and [3] as run; without rotations [0] = [2]."""
    _extent_end(prog, last, &programmed[0], &tool[0], True)
    info.m_size[2] = programmed[0]
    info.m_size[3] = tool[0]
    if prog.n_rotations > 1:
        _extent_end(prog, last, &programmed[1], &tool[1], False)
        info.m_size[0] = programmed[1]
        info.m_size[1] = tool[1]
    else:
        info.m_size[0] = info.m_size[2]
        info.m_size[1] = info.m_size[3]


cdef void program_extent(const Program *prog, GCODE_INFO *info) noexcept nogil:
    """The extents of the whole program in one pass each (extent_finish)."""
    cdef GCODE_SIZE programmed[2]
    cdef GCODE_SIZE tool[2]
    cdef size_t last
    extent_begin(prog, &programmed[0], &tool[0])
    last = extent_range(prog, 0, prog.n_parts, &programmed[0], &tool[0], True)
    if prog.n_rotations > 1:
        extent_begin(prog, &programmed[1], &tool[1])
        extent_range(prog, 0, prog.n_parts, &programmed[1], &tool[1], False)
    extent_finish(prog, last, programmed, tool, info)
