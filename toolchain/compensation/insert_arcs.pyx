# Automatic arcs (G167 / GCODE_PARAMETERS.insertArcMode): a small tangent arc between
# two consecutive G1 lines that meet at an angle, so that the path deviates from the
# corner by at most the tolerance.
#
# Geometry of a corner with deflection angle t (0 = tangent, 180 = reversal): the arc
# of radius r tangent to both lines has its centre on the bisector at r / cos(t/2)
# from the corner, its tangent points at r * tan(t/2) from the corner along each line
# and its midpoint at d = r * (1 / cos(t/2) - 1) from the corner. The pass picks
# d = tolerance max (E), smaller when the tangent point would be further than half of
# the shorter line from the corner, and inserts nothing when even d = tolerance min (A)
# does not fit.
#
# Runs after the compensation on the path the tool follows (Part.ce; Part.e too when
# the part is not compensated). One pass, O(n); no pass at all when neither the host
# (insertArcMode 1) nor any G167 of the program switches insertion on.
from libc.stdlib cimport free
from libc.string cimport memcpy, memset
from libc.math cimport fabs, atan2, cos, tan, M_PI


cdef bint program_add_arc_region(ProgramBuilder *build, size_t first, bint on, int32_t plane,
                                 double tol_max, double tol_min, double max_angle) noexcept nogil:
    """Records a G167 (compiler): settings in force from programmed part `first` on."""
    cdef Program *prog = &build.prog
    cdef ArcRegion *r
    if prog.n_arc_regions > 0 and prog.arc_regions[prog.n_arc_regions - 1].first == first:
        prog.n_arc_regions -= 1          # several G167 before the same part: the last one counts
    if not grow(<void **>&prog.arc_regions, &build.cap_arc_regions, prog.n_arc_regions + 1, sizeof(ArcRegion)):
        return False
    r = &prog.arc_regions[prog.n_arc_regions]
    prog.n_arc_regions += 1
    r.first = first
    r.on = on
    r.plane = plane
    r.tol_max = tol_max
    r.tol_min = tol_min if tol_min < tol_max else tol_max
    r.max_angle = max_angle
    return True


cdef inline void _ia_point(const Part *p, int a, int b, double *out) noexcept nogil:
    """Where the tool is at the end of p, in the plane (a, b) (plane axes are x y z)."""
    out[0] = p.ce[a]
    out[1] = p.ce[b]


cdef bint _ia_in_plane_line(const Program *prog, size_t k, int a, int b) noexcept nogil:
    """Part k is a G1 that moves only in the plane (a, b), by more than nothing."""
    cdef const Part *p = &prog.parts[k]
    cdef Segment g
    cdef int i
    if p.kind != PART_MOTION or p.func != 1:
        return False
    segment_of_part(prog, k, &g)
    for i in range(g.n_axes):
        if i != a and i != b and fabs(g.end[i] - g.start[i]) > LENGTH_EPS:
            return False
    return distance2d(g.end[a] - g.start[a], g.end[b] - g.start[b]) > LENGTH_EPS


cdef bint insert_arcs_idle(const Program *prog, const GCODE_PARAMETERS *params) noexcept nogil:
    """Whether insert_arcs leaves the program as it is: neither the host's mode nor a
    G167 of the program switches the arcs on."""
    cdef size_t k
    if params.insertArcMode == 1:
        return False
    for k in range(prog.n_arc_regions):
        if prog.arc_regions[k].on:
            return False
    return True


cdef int insert_arcs(ProgramBuilder *build, const GCODE_PARAMETERS *params, ErrorInfo *err) noexcept nogil:
    """Inserts the automatic arcs; COMPILE_OK or COMPILE_ERROR (out of memory)."""
    cdef Program *prog = &build.prog
    cdef size_t k, n, region = 0, programmed = 0, n_ins = 0, cap_ins = 0
    cdef bint on, any_on, cur_ok, merged
    cdef int32_t plane
    cdef double tol_max, tol_min, max_angle, min_angle
    cdef int a, b, c, pa, pb, pc, sa, sb, sc
    cdef Part *p
    cdef Part *q
    cdef ArcIns *ins = NULL
    cdef ArcInsertions arcs
    cdef ArcIns *x
    cdef double s0[2]
    cdef double s1[2]
    cdef double e1[2]
    cdef double u0[2]
    cdef double u1[2]
    cdef double len0, len1, cross, dot, t, half, ct, tt, d, rad, tang, bl
    cdef double bis[2]
    # the line before the corner: its start before this pass shortened it
    cdef double prev_start[2]
    cdef bint prev_line = False
    cdef int prev_a = -1, prev_b = -1
    any_on = params.insertArcMode == 1
    for k in range(prog.n_arc_regions):
        if prog.arc_regions[k].on:
            any_on = True
    if not any_on or prog.n_parts < 2:
        return COMPILE_OK
    on = params.insertArcMode == 1
    plane = params.insertArcPlane
    tol_max = params.insertArcToleranceRMax
    tol_min = params.insertArcToleranceRMin
    max_angle = params.insertArcMaxAngle
    # the vendor: "not implemented, always 0"; applied only on the host's request
    min_angle = params.insertArcMinAngle if (<uint32_t>params.rezerva1 & GCODE_REZERVA1_APPLY_UNIMPLEMENTED) else 0.0
    n = prog.n_parts
    for k in range(n):
        p = &prog.parts[k]
        if not (p.flags & FLAG_INSERTED):
            while region < prog.n_arc_regions and prog.arc_regions[region].first <= programmed:
                on = prog.arc_regions[region].on
                plane = prog.arc_regions[region].plane
                tol_max = prog.arc_regions[region].tol_max
                tol_min = prog.arc_regions[region].tol_min
                max_angle = prog.arc_regions[region].max_angle
                region += 1
            programmed += 1
        # a line in the plane: the first of a corner even where insertion is still off
        cur_ok = False
        if plane_axes(plane if plane != 0 else p.plane, &a, &b, &c):
            cur_ok = _ia_in_plane_line(prog, k, a, b)
        if not cur_ok:
            prev_line = False
            continue
        s1[0] = 0; s1[1] = 0
        _ia_point(&prog.parts[k - 1] if k > 0 else p, a, b, s1)
        if k == 0:
            s1[0] = prog.start[a]; s1[1] = prog.start[b]
        _ia_point(p, a, b, e1)
        if on and tol_max > 0 and prev_line and prev_a == a and prev_b == b:
            # corner at s1 between the previous line (prev_start -> s1) and this one
            len0 = distance2d(s1[0] - prev_start[0], s1[1] - prev_start[1])
            len1 = distance2d(e1[0] - s1[0], e1[1] - s1[1])
            u0[0] = (s1[0] - prev_start[0]) / len0; u0[1] = (s1[1] - prev_start[1]) / len0
            u1[0] = (e1[0] - s1[0]) / len1; u1[1] = (e1[1] - s1[1]) / len1
            cross = u0[0] * u1[1] - u0[1] * u1[0]
            dot = u0[0] * u1[0] + u0[1] * u1[1]
            t = atan2(fabs(cross), dot)                 # deflection, 0..pi
            if t > TURN_EPS and t * 180.0 / M_PI > min_angle and t * 180.0 / M_PI <= max_angle + TURN_EPS \
                    and t < M_PI - TURN_EPS:
                ct = cos(t / 2.0)
                tt = tan(t / 2.0)
                d = tol_max
                rad = d * ct / (1.0 - ct)
                tang = rad * tt
                half = 0.5 * (len0 if len0 < len1 else len1)
                if tang > half:
                    tang = half
                    rad = tang / tt
                    d = rad * (1.0 - ct) / ct
                if d >= tol_min - ROUNDING_EPS and rad > LENGTH_EPS:
                    if not grow(<void **>&ins, &cap_ins, n_ins + 1, sizeof(ArcIns)):
                        free(ins)
                        err_out_of_memory(err, prog.main_file_idx, 0)
                        return COMPILE_ERROR
                    x = &ins[n_ins]
                    n_ins += 1
                    x.after = k - 1
                    x.end[0] = s1[0] + u1[0] * tang; x.end[1] = s1[1] + u1[1] * tang
                    # centre: from the corner along the bisector (towards the inside)
                    bis[0] = u1[0] - u0[0]; bis[1] = u1[1] - u0[1]
                    bl = distance2d(bis[0], bis[1])
                    x.cc[0] = s1[0] + bis[0] / bl * rad / ct
                    x.cc[1] = s1[1] + bis[1] / bl * rad / ct
                    x.radius = rad
                    x.func = 3 if cross > 0 else 2
                    x.plane = <int16_t>(plane if plane != 0 else p.plane)
                    # the first line ends at its tangent point
                    q = &prog.parts[k - 1]
                    _ia_set(q, a, b, s1[0] - u0[0] * tang, s1[1] - u0[1] * tang)
        prev_line = True
        prev_a = a; prev_b = b
        prev_start[0] = s1[0]; prev_start[1] = s1[1]
    if n_ins == 0:
        return COMPILE_OK
    arcs.items = ins
    arcs.build = build
    merged = program_merge(build, n_ins, &arcs, _ia_after, _ia_make, NULL, NULL)
    free(ins)
    if not merged:
        err_out_of_memory(err, prog.main_file_idx, 0)
        return COMPILE_ERROR
    return COMPILE_OK


cdef void _ia_set(Part *q, int a, int b, double va, double vb) noexcept nogil:
    """Moves the tool end of part q in the plane (x y z axes); a part without
    compensation moves its programmed end with it (ce = e)."""
    q.ce[a] = va
    q.ce[b] = vb
    if q.comp == 40:
        q.e[a] = va
        q.e[b] = vb


cdef size_t _ia_after(void *ctx, size_t rec) noexcept nogil:
    """program_merge's inserted_after_fn: the part insertion rec follows."""
    return (<ArcInsertions *>ctx).items[rec].after


cdef void _ia_make(void *ctx, size_t rec, Part *out, const Part *before, const Part *after) noexcept nogil:
    """program_merge's make_inserted_fn: G167's arc between the two lines of insertion rec."""
    cdef ArcInsertions *arcs = <ArcInsertions *>ctx
    _ia_part(arcs.build, out, before, after, &arcs.items[rec])


cdef void _ia_part(ProgramBuilder *build, Part *q, const Part *prev, const Part *src, const ArcIns *x) noexcept nogil:
    """The arc after prev (the shortened first line), with the attributes of src (the
    second line); its record from the room the merge reserved."""
    cdef int a, b, c
    cdef PartExtra *arc
    part_inserted(build, q, prev, src, x.func, x.plane)
    plane_axes(x.plane, &a, &b, &c)
    _ia_set(q, a, b, x.end[0], x.end[1])
    arc = program_part_extra(build, q)
    arc.cc[0] = q.ce[0]; arc.cc[1] = q.ce[1]; arc.cc[2] = q.ce[2]
    arc.cc[a] = x.cc[0]; arc.cc[b] = x.cc[1]
    arc.radius = x.radius
