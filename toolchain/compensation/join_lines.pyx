# The tolerances of the finished tool path, after the compensation and the G167 arcs
# and before the extent and the plan (docs/behaviour.md, "tolerance[2], [3], [4]"):
#   tolerance[4]  an uncompensated arc whose radius is below it is removed: a G1 to
#                 its end point (the compensation removes its own arcs the same way,
#                 by their tool path radius);
#   tolerance[2]  two consecutive G1 parts whose directions differ by less than this
#   tolerance[3]  (degrees), where the joined line passes every end point it leaves
#                 out within this (mm), become one G1: the later part, from where the
#                 first one started. A run of such parts becomes one part.
# The part kept is the last of a run, whole (its line, G-code index, addresses, end),
# so a driver callback reports a real line and the part's G-code index is its own;
# the lines before it in the run are not reported. Only programmed G1 parts with the
# same settings, compensation and plane join, moving x y z alone, never across a
# change of the planning settings (G900, M-5). 0 in tolerance[2] joins nothing;
# 0 in tolerance[3] joins exactly collinear parts only.
from libc.math cimport sqrt, cos, M_PI
from libc.stdlib cimport free
from libc.string cimport memcpy, memcmp

cdef extern from *:
    """
    /* end points a joined run leaves out at most (the check of each new part is
       linear in them): a longer run starts a new part */
    #define TC_JOIN_RUN_MAX 256
    """
    const size_t JOIN_RUN_MAX "TC_JOIN_RUN_MAX"


cdef inline double _point_line_distance2(const double *a, const double *b, const double *p) noexcept nogil:
    """Squared distance from p to the segment a-b (x y z)."""
    cdef double d[3]
    cdef double w[3]
    cdef double dd = 0.0, t = 0.0, r = 0.0, c
    cdef int k
    for k in range(3):
        d[k] = b[k] - a[k]
        w[k] = p[k] - a[k]
        dd += d[k] * d[k]
        t += d[k] * w[k]
    if dd > 0.0:
        t = t / dd
        if t < 0.0:
            t = 0.0
        elif t > 1.0:
            t = 1.0
    else:
        t = 0.0
    for k in range(3):
        c = w[k] - t * d[k]
        r += c * c
    return r


cdef inline bint _start_axes_equal(const Program *prog, const Part *p) noexcept nogil:
    """The first part moves x y z alone (its other axes are the program's start's)."""
    return memcmp(&prog.axes[OTHER_AXES * p.axes_idx], prog.start + 3, OTHER_AXES * sizeof(double)) == 0


cdef inline bint _joinable_kind(const Program *prog, const Part *p) noexcept nogil:
    """A programmed G1 (no spindle speed of its own, G96)."""
    return (p.kind == PART_MOTION and p.func == 1
            and not (p.flags & (FLAG_INSERTED | FLAG_CSS | FLAG_HELIX)))


cdef inline bint _same_cut(const Program *prog, const Part *a, const Part *b) noexcept nogil:
    """Whether parts a and b cut alike (flags, compensation, radius, plane, axes and settings):
    only then may they join into one line."""
    return (a.flags == b.flags and a.comp == b.comp and a.comp_slot == b.comp_slot
            and a.radius_idx == b.radius_idx and a.plane == b.plane and a.axes_idx == b.axes_idx
            and (a.settings == b.settings or settings_equal(part_settings(prog, a), part_settings(prog, b))))


cdef inline double _direction(const double *a, const double *b, double *u) noexcept nogil:
    """Unit vector from a to b (x y z) in u; the length."""
    cdef double n
    u[0] = b[0] - a[0]
    u[1] = b[1] - a[1]
    u[2] = b[2] - a[2]
    n = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2])
    if n > 0.0:
        u[0] /= n
        u[1] /= n
        u[2] /= n
    return n


cdef int join_lines(ProgramBuilder *build, const GCODE_PARAMETERS *params) noexcept nogil:
    """tolerance[4] on uncompensated arcs, tolerance[2] and [3] on consecutive G1 parts
    (above); the planning regions follow the parts. COMPILE_OK, or COMPILE_ERROR when
    out of memory."""
    cdef Program *prog = &build.prog
    cdef size_t n = prog.n_parts, r, w = 0, run = 0, k, region = 0
    cdef size_t programmed = 0, kept_programmed = 0
    cdef double min_arc = params.tolerance[4]
    cdef double tol_angle = params.tolerance[2], tol_dev = params.tolerance[3]
    cdef double cos_tol, dev2, len_new
    cdef double run_start_e[3]          # where the run began (programmed, tool path)
    cdef double run_start_c[3]
    cdef double u_last[3]
    cdef double u_new[3]
    cdef double *left_e = NULL          # the end points the run leaves out
    cdef double *left_c = NULL
    cdef bint join, last_ok = False, do_join
    cdef Part *p
    cdef Part *q
    cdef const double *before_e
    cdef const double *before_c
    do_join = tol_angle > 0.0 and tol_angle < 90.0
    if not (min_arc > 0.0) and not do_join:
        return COMPILE_OK
    if do_join:
        cos_tol = cos(tol_angle * (M_PI / 180.0))
        dev2 = tol_dev * tol_dev if tol_dev > 0.0 else 0.0
        left_e = <double *>tc_malloc(6 * JOIN_RUN_MAX * sizeof(double))
        if left_e == NULL:
            return COMPILE_ERROR
        left_c = left_e + 3 * JOIN_RUN_MAX
    for r in range(n):
        p = &prog.parts[r]
        if min_arc > 0.0 and p.kind == PART_MOTION and (p.func == 2 or p.func == 3) and p.comp == 40 \
                and part_extra(prog, p).radius < min_arc:
            p.func = 1                  # a line to its end point
            p.flags = p.flags & ~FLAG_HELIX
            if not (p.flags & FLAG_CSS):
                p.extra = 0             # no centre, no radius
        if not do_join:
            continue
        if not (p.flags & FLAG_INSERTED):
            while region < prog.n_plan_regions and prog.plan_regions[region].first <= programmed:
                if prog.plan_regions[region].first == programmed:
                    last_ok = False     # the settings change here: no join into the part before
                prog.plan_regions[region].first = kept_programmed
                region += 1
        join = False
        if last_ok and _joinable_kind(prog, p) and run < JOIN_RUN_MAX:
            q = &prog.parts[w - 1]
            if _same_cut(prog, q, p):
                len_new = _direction(q.ce, p.ce, u_new)
                if (len_new > LENGTH_EPS and u_last[0] * u_new[0] + u_last[1] * u_new[1]
                        + u_last[2] * u_new[2] > cos_tol):
                    # the joined line from the run's start to p's end passes every end
                    # point it leaves out, q's end among them, within tolerance[3]
                    memcpy(&left_e[3 * run], q.e, 3 * sizeof(double))
                    memcpy(&left_c[3 * run], q.ce, 3 * sizeof(double))
                    join = True
                    for k in range(run + 1):
                        if (_point_line_distance2(run_start_c, p.ce, &left_c[3 * k]) > dev2
                                or _point_line_distance2(run_start_e, p.e, &left_e[3 * k]) > dev2):
                            join = False
                            break
        if join:
            prog.parts[w - 1] = p[0]    # the later part, from where the run began
            run += 1
            memcpy(u_last, u_new, sizeof(u_last))
        else:
            if w != r:
                prog.parts[w] = p[0]
            w += 1
            run = 0
            last_ok = False
            if _joinable_kind(prog, p):
                if w >= 2:
                    before_e = &prog.parts[w - 2].e[0]
                    before_c = &prog.parts[w - 2].ce[0]
                else:
                    before_e = &prog.start[0]
                    before_c = &prog.start[0]
                if (w >= 2 and prog.parts[w - 2].axes_idx == p.axes_idx) or (w < 2 and _start_axes_equal(prog, p)):
                    memcpy(run_start_e, before_e, sizeof(run_start_e))
                    memcpy(run_start_c, before_c, sizeof(run_start_c))
                    last_ok = _direction(run_start_c, p.ce, u_last) > LENGTH_EPS
            if not (p.flags & FLAG_INSERTED):
                kept_programmed += 1
        if not (p.flags & FLAG_INSERTED):
            programmed += 1
    if do_join:
        while region < prog.n_plan_regions:     # regions from past the last part
            prog.plan_regions[region].first = kept_programmed
            region += 1
        prog.n_parts = w
        free(left_e)
    return COMPILE_OK

