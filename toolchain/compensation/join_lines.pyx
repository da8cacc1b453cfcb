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


cdef inline void _unit(const double *d, double n, double *u) noexcept nogil:
    """d / n (n > 0: d's length), as _direction divides."""
    u[0] = d[0] / n
    u[1] = d[1] / n
    u[2] = d[2] / n


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


cdef inline int _longer_than_eps(double n2) noexcept nogil:
    """Whether sqrt(n2) > LENGTH_EPS: 1, 0, or -1 when n2 is too close to tell
    without the square root (the exact test then takes it)."""
    if n2 > 4.0 * LENGTH_EPS * LENGTH_EPS:
        return 1
    if n2 < 0.25 * LENGTH_EPS * LENGTH_EPS:
        return 0
    return -1


cdef void _settle_all(Program *prog, const uint8_t *settle) noexcept nogil:
    """The followers' positions (compensate_end) in a pass of their own."""
    cdef size_t r
    for r in range(prog.n_parts):
        if settle[r] == ROLE_FOLLOW:
            settle_follower(&prog.parts[r], &prog.parts[r - 1].ce[0] if r > 0 else &prog.start[0])


cdef inline bint _narrows(const GCODE_SIZE *size, const double *a, const double *b,
                          const double *v) noexcept nogil:
    """Whether leaving point v (x y z) out of a path that keeps the line a-b can narrow
    the extent `size`: only where v lies beyond both a and b in some axis, on that
    side's bound."""
    cdef const double *lo = <const double *>&size.m_minimalPos
    cdef const double *hi = <const double *>&size.m_maximalPos
    cdef int k
    for k in range(3):
        if (v[k] < a[k] and v[k] < b[k] and v[k] <= lo[k]) or (v[k] > a[k] and v[k] > b[k] and v[k] >= hi[k]):
            return True
    return False


cdef bint _run_narrows(const GCODE_INFO *extent, const double *start_e, const double *start_c, const Part *p,
                       const double *left_e, const double *left_c, size_t count) noexcept nogil:
    """Whether the `count` end points a run leaves out (programmed, tool path) can narrow
    the extents as run of a path that keeps the line from the run's start to p's end."""
    cdef size_t k
    for k in range(count):
        if (_narrows(&extent.m_size[2], start_e, p.e, &left_e[3 * k])
                or _narrows(&extent.m_size[3], start_c, p.ce, &left_c[3 * k])):
            return True
    return False


cdef int join_lines(ProgramBuilder *build, const GCODE_PARAMETERS *params, bint number,
                    uint8_t *settle, const PartsWatch *watch, const GCODE_INFO *extent,
                    bint *extent_holds) noexcept nogil:
    """tolerance[4] on uncompensated arcs, tolerance[2] and [3] on consecutive G1 parts
    (above); the planning regions follow the parts. With `number` (nothing is inserted
    after it) the parts it keeps get the driver's G-code indexes on the way, as
    program_number_parts gives them (build.renumber cleared); with `settle` (the
    compensation's roles, freed here) the parts without motion in the plane first take
    the compensated position they sit at, as the merge would have. `watch` hears, with
    the joins, how far the parts kept are final (all but the last one kept: a join may
    still replace it). `extent` (may be NULL): the extent measured before (beside the
    merge); *extent_holds tells whether it is still the program's (no arc became a
    line, no end point left out lay beyond its joined line on one of its bounds, no
    rotation to undo).
    COMPILE_OK, or COMPILE_ERROR when out of memory.

    Most G1 parts join nothing: the test of their turn compares squares first and
    takes the unit vectors (a square root, three divisions) only where the turn may
    be within tolerance[2] -- the same quotients as always, so the same joins."""
    cdef Program *prog = &build.prog
    cdef size_t n = prog.n_parts, r, w = 0, run = 0, k, region = 0
    cdef size_t tell_at = PARTS_WATCH_STEP if watch != NULL else <size_t>-1     # kept parts to tell the watch at
    cdef size_t programmed = 0, kept_programmed = 0
    cdef double min_arc = params.tolerance[4]
    cdef double tol_angle = params.tolerance[2], tol_dev = params.tolerance[3]
    cdef double cos_tol = 0.0, cos2_tol = 0.0, dev2 = 0.0, len_new, n2, dot
    cdef double run_start_e[3]          # where the run began (programmed, tool path)
    cdef double run_start_c[3]
    cdef double d_last[3]               # the last part's direction (tool path), its squared length
    cdef double n2_last = 0.0
    cdef double u_last[3]               # ... as a unit vector, once u_last_known
    cdef double d_new[3]
    cdef double u_new[3]
    cdef double *left_e = NULL          # the end points the run leaves out
    cdef double *left_c = NULL
    cdef bint join, last_ok = False, do_join, u_last_known = False, candidate
    cdef int longer
    cdef PartNumbering numbering
    cdef Part *p
    cdef Part *q
    cdef const double *before_e
    cdef const double *before_c
    extent_holds[0] = extent != NULL and settle == NULL     # (followers settled here move)
    do_join = tol_angle > 0.0 and tol_angle < 90.0
    # the joins (when they run) visit every part: they number them whether they join
    # any or not; else only a program whose indexes need it is numbered
    number = number and (build.renumber or do_join)
    if not (min_arc > 0.0) and not do_join:
        if settle != NULL:
            _settle_all(prog, settle)
            free(settle)
        if number:
            program_number_parts(prog)
            build.renumber = False
        return COMPILE_OK
    if do_join:
        cos_tol = cos(tol_angle * (M_PI / 180.0))
        cos2_tol = cos_tol * cos_tol * (1.0 - COS2_REL_EPS)
        dev2 = tol_dev * tol_dev if tol_dev > 0.0 else 0.0
        left_e = <double *>tc_malloc(6 * JOIN_RUN_MAX * sizeof(double))
        if left_e == NULL:
            free(settle)
            return COMPILE_ERROR
        left_c = left_e + 3 * JOIN_RUN_MAX
    if number:
        numbering_begin(&numbering, prog)
    for r in range(n):
        p = &prog.parts[r]
        if settle != NULL and settle[r] == ROLE_FOLLOW:
            # the part before it, as the merge would have read it: where the joins put it
            if do_join:
                settle_follower(p, &prog.parts[w - 1].ce[0] if w > 0 else &prog.start[0])
            else:
                settle_follower(p, &prog.parts[r - 1].ce[0] if r > 0 else &prog.start[0])
        if min_arc > 0.0 and p.kind == PART_MOTION and (p.func == 2 or p.func == 3) and p.comp == 40 \
                and part_extra(prog, p).radius < min_arc:
            p.func = 1                  # a line to its end point
            p.flags = p.flags & ~FLAG_HELIX
            extent_holds[0] = False     # (its extreme points are gone)
            if not (p.flags & FLAG_CSS):
                p.extra = 0             # no centre, no radius
        if not do_join:
            if number:
                numbering_part(&numbering, prog, p)
            continue
        if not (p.flags & FLAG_INSERTED):
            while region < prog.n_plan_regions and prog.plan_regions[region].first <= programmed:
                if prog.plan_regions[region].first == programmed:
                    last_ok = False     # the settings change here: no join into the part before
                prog.plan_regions[region].first = kept_programmed
                region += 1
        join = False
        candidate = False               # d_new holds q -> p (the tool path)
        if last_ok and _joinable_kind(prog, p) and run < JOIN_RUN_MAX:
            q = &prog.parts[w - 1]
            if _same_cut(prog, q, p):
                d_new[0] = p.ce[0] - q.ce[0]
                d_new[1] = p.ce[1] - q.ce[1]
                d_new[2] = p.ce[2] - q.ce[2]
                candidate = True
                n2 = d_new[0] * d_new[0] + d_new[1] * d_new[1] + d_new[2] * d_new[2]
                dot = d_last[0] * d_new[0] + d_last[1] * d_new[1] + d_last[2] * d_new[2]
                longer = _longer_than_eps(n2)
                # the turn from d_last to d_new is within tolerance[2] only if
                # dot > cos_tol |d_last| |d_new|; the exact test decides near it
                if longer != 0 and dot > 0.0 and dot * dot >= cos2_tol * n2_last * n2:
                    len_new = sqrt(n2)
                    if len_new > 0.0:
                        _unit(d_new, len_new, u_new)
                    else:
                        u_new[0] = d_new[0]; u_new[1] = d_new[1]; u_new[2] = d_new[2]
                    if not u_last_known:
                        _unit(d_last, sqrt(n2_last), u_last)
                        u_last_known = True
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
            # the run's end points left out leave the path: the extent narrows only where
            # one lay beyond the joined line, on a bound (as written, under a rotation,
            # the bounds are others: measured again)
            if extent_holds[0] and (prog.n_rotations > 1 or _run_narrows(extent, run_start_e, run_start_c, p,
                                                                         left_e, left_c, run + 1)):
                extent_holds[0] = False
            prog.parts[w - 1] = p[0]    # the later part, from where the run began
            run += 1
            d_last[0] = d_new[0]; d_last[1] = d_new[1]; d_last[2] = d_new[2]
            n2_last = n2
            memcpy(u_last, u_new, sizeof(u_last))
        else:
            if number and w > 0:
                numbering_part(&numbering, prog, &prog.parts[w - 1])    # no part joins it any more
            if w != r:
                prog.parts[w] = p[0]
            w += 1
            if w > tell_at:
                tell_at = w + PARTS_WATCH_STEP
                watch.final(watch.ctx, w - 1)   # numbered above, the kept parts before it too
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
                    # the run's direction, as _direction(run_start_c, p.ce) gives it: when
                    # p was a candidate, d_new is that difference already
                    if not candidate:
                        d_new[0] = p.ce[0] - before_c[0]
                        d_new[1] = p.ce[1] - before_c[1]
                        d_new[2] = p.ce[2] - before_c[2]
                        n2 = d_new[0] * d_new[0] + d_new[1] * d_new[1] + d_new[2] * d_new[2]
                    d_last[0] = d_new[0]; d_last[1] = d_new[1]; d_last[2] = d_new[2]
                    n2_last = n2
                    longer = _longer_than_eps(n2)
                    last_ok = longer == 1 or (longer == -1 and sqrt(n2) > LENGTH_EPS)
                    u_last_known = False
            if not (p.flags & FLAG_INSERTED):
                kept_programmed += 1
        if not (p.flags & FLAG_INSERTED):
            programmed += 1
    if do_join:
        while region < prog.n_plan_regions:     # regions from past the last part
            prog.plan_regions[region].first = kept_programmed
            region += 1
        if w != n:
            build.renumber = True
        prog.n_parts = w
        free(left_e)
        if number and w > 0:
            numbering_part(&numbering, prog, &prog.parts[w - 1])
    if number:
        numbering_end(&numbering, prog)
        build.renumber = False
    free(settle)
    return COMPILE_OK
