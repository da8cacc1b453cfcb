# Parts: turns the executed words of a line into compact Part records (motion,
# dwell, M function, print). Geometry is computed in program coordinates and then
# transformed to machine coordinates (zero offset, G92, mirroring, rotation).
from libc.math cimport fabs, sqrt, M_PI


cdef void _non_finite_error(CState *st, const double *end) noexcept nogil:
    """Error 106 naming the first axis of `end` that is not finite. The words, parameters
    and offsets that make a position pass number_gate; em_part's check of every end is
    the last guard that no part carries a non-finite position."""
    cdef char letter[2]
    cdef int a
    for a in range(AXES):
        if not isfinite(end[a]):
            letter[0] = letter_of_axis(a)
            letter[1] = 0
            err_bad_value(st.err, st.unit.file_idx, st.line, end[a], letter)
            return


cdef Part *em_part(CState *st, int kind, int func, const double *end) noexcept nogil:
    """A new part ending at `end` (machine coordinates, ten axes) with the modal fields
    filled in (a motion's feed too: em_feed); NULL on error (recorded)."""
    cdef Part *p
    cdef Program *prog = st.prog
    cdef PartSettings s
    if prog.n_parts >= MAX_PARTS:
        err_part_limit(st.err, st.unit.file_idx, st.line, MAX_PARTS)
        return NULL
    if (prog.n_parts & 1023) == 0 and st.inp.cancel != NULL and TC_ATOMIC_LOAD(st.inp.cancel) != 0:
        err_cancelled(st.err, st.unit.file_idx, st.line)         # an ending call: checked per part, one line may make millions
        return NULL
    if not coordinates_finite(end, AXES):
        _non_finite_error(st, end)
        return NULL
    p = program_add_part(st.build)
    if p == NULL:
        err_out_of_memory(st.err, st.unit.file_idx, st.line)
        return NULL
    p.kind = kind
    p.func = func
    if not program_set_end(st.build, p, end):
        err_out_of_memory(st.err, st.unit.file_idx, st.line)
        return NULL
    p.ce[0] = end[0]; p.ce[1] = end[1]; p.ce[2] = end[2]
    p.line = st.line
    p.gcode_index = st.gindex
    st.gindex += 2
    p.plane = <int16_t>st.plane
    p.comp = <uint8_t>st.comp
    p.comp_slot = <uint8_t>st.comp_slot
    p.radius_idx = <uint16_t>st.radius_idx
    if st.comp != 40:
        prog.compensated = True
    if st.per_min:
        p.flags = FLAG_FEED_PER_MIN
    if st.gindex_set:
        p.flags |= FLAG_INDEX_SET
        st.gindex_set = False
    s.feed = 0.0
    s.fp = <float>st.fp
    s.spindle = st.spindle
    s.tool = <uint16_t>(0 if st.tool < 0 else (65535 if st.tool > 65535 else st.tool))    # 16 bits in m_planeTool
    s.zero_idx = <uint16_t>st.zero_idx
    s.rot_idx = <uint16_t>st.rot_idx
    s.file_idx = <int16_t>st.unit.file_idx
    # a dwell or an M function carries the feed a G1 there would get: the vendor sets the F
    # cell at every callback (docs/structures.md)
    em_feed(st, p, func if kind == PART_MOTION else 1, &s)
    if em_settings(st, p, &s) != 0:
        return NULL
    return p


cdef int em_settings(CState *st, Part *p, const PartSettings *s) noexcept nogil:
    """The part's settings become s (a record shared with the parts that agree)."""
    cdef int64_t idx = program_settings_index(st.build, s)
    if idx < 0:
        return err_out_of_memory(st.err, st.unit.file_idx, st.line)
    p.settings = <uint32_t>idx
    return 0


cdef extern from *:
    """
    #define SF_CTZ(x) __builtin_ctz(x)
    /* the bits of x counted in registers: without -mpopcnt __builtin_popcount is a
       call into libgcc, once per part */
    static inline int SF_POPCOUNT(uint32_t x) {
        x = x - ((x >> 1) & 0x55555555u);
        x = (x & 0x33333333u) + ((x >> 2) & 0x33333333u);
        return (int)((((x + (x >> 4)) & 0x0F0F0F0Fu) * 0x01010101u) >> 24);
    }
    """
    int SF_CTZ(uint32_t x) nogil
    int SF_POPCOUNT(uint32_t x) nogil


cdef int em_pars(CState *st, const LineWords *lw, int g, int m) noexcept nogil:
    """Addresses of the line for the last part, packed in letter order into
    Program.pars; g / m (if > -1000) fill the G / M cell: the part's own function,
    its bit set but its value not stored (program.pxd part_own_cell). Walks only the
    set bits: this runs once per part."""
    cdef uint32_t mask = lw.mask
    cdef uint32_t bits
    cdef int letter
    cdef Program *prog = st.prog
    cdef Part *p = &prog.parts[prog.n_parts - 1]
    cdef float *out
    cdef uint32_t own = 0
    if g > -1000:
        own = 1u << 6
    elif m > -1000:
        own = 1u << 12
    mask |= own
    p.pars_mask = mask
    p.pars_off = <uint32_t>prog.n_pars
    bits = mask & ~own
    if bits == 0:
        return 0
    if not grow(<void **>&prog.pars, &st.build.cap_pars, prog.n_pars + <size_t>SF_POPCOUNT(bits), sizeof(float)):
        return err_out_of_memory(st.err, st.unit.file_idx, st.line)
    ready_ahead(prog.pars, (prog.n_pars + <size_t>SF_POPCOUNT(bits)) * sizeof(float), &st.build.ready_pars,
                st.build.cap_pars * sizeof(float))
    out = prog.pars + prog.n_pars
    while bits:
        letter = SF_CTZ(bits)
        bits &= bits - 1
        out[0] = <float>lw.v[letter]
        out += 1
    prog.n_pars = <size_t>(out - prog.pars)
    return 0


cdef void em_feed(CState *st, Part *p, int func, PartSettings *s) noexcept nogil:
    """Feed of a motion part after forceMode, FF and the M99 default feed."""
    cdef int fm = st.params.forceMode
    if func == 0:
        s.feed = st.ff if (fm == 0 and st.ff_set) else st.params.motion[0].feed
        p.flags |= FLAG_FEED_PER_MIN
    elif fm == 1 or fm == 2:
        s.feed = st.params.motion[1].feed
        p.flags |= FLAG_FEED_PER_MIN
    else:
        s.feed = st.feed
        if s.feed == 0.0:
            s.feed = st.def_feed if st.def_feed > 0.0 else st.params.motion[1].feed
    if fm == 1:
        s.fp = 1.0


cdef int em_css(CState *st, Part *p, double x_start, double x_end) noexcept nogil:
    """G96 with a feed per revolution: S is the cutting speed (m/min), the spindle
    turns at 1000 S / (2 pi r) rev/min, r the tool's distance from the spindle axis
    (|X| in the workpiece, the smaller of the part's two ends: the fastest the spindle
    turns on it; at least 1 mm, so that a cut through the axis stays finite). The
    dialect names no maximum spindle speed (docs/planner.md)."""
    cdef double r = min(fabs(x_start), fabs(x_end))
    cdef PartExtra *x = program_part_extra(st.build, p)
    if x == NULL:
        return err_out_of_memory(st.err, st.unit.file_idx, st.line)
    if r < 1.0:
        r = 1.0
    x.value = 1000.0 * part_settings(st.prog, p).spindle / (2.0 * M_PI * r)
    p.flags |= FLAG_CSS
    return 0


cdef inline bint has(const LineWords *lw, char letter) noexcept nogil:
    """Whether the line has the address `letter`."""
    return (lw.mask >> (<int>letter - 65)) & 1


cdef inline double val(const LineWords *lw, char letter) noexcept nogil:
    """The value of address `letter` on the line (meaningful only where `has` says it is
    there)."""
    return lw.v[<int>letter - 65]


cdef int em_arc_error(CState *st, int fa, int sa, const double *s, const double *e, double rs,
                      double re, int col) noexcept nogil:
    """The vendor's error 400 (the chord longer than the diameter) or 407 (the radii
    differ), or their kin of the other planes (415..420): the start and end on the
    plane's two axes (program coordinates), the chord and twice the start radius or
    the two radii; the column of the first centre word beside the text."""
    cdef double chord = distance2d(e[fa] - s[fa], e[sa] - s[sa])
    cdef int32_t fi = st.unit.file_idx
    cdef int32_t line = st.line
    if chord > 2.0 * rs:
        if st.plane == 17:
            return err_arc_centre(st.err, fi, line, col, s[fa], s[sa], e[fa], e[sa], chord, 2.0 * rs)
        if st.plane == 18:
            return err_arc_centre_xz(st.err, fi, line, col, s[fa], s[sa], e[fa], e[sa], chord, 2.0 * rs)
        if st.plane == 19:
            return err_arc_centre_yz(st.err, fi, line, col, s[fa], s[sa], e[fa], e[sa], chord, 2.0 * rs)
        return err_arc_centre_zx(st.err, fi, line, col, s[fa], s[sa], e[fa], e[sa], chord, 2.0 * rs)
    if st.plane == 17:
        return err_arc_radii(st.err, fi, line, col, s[fa], s[sa], e[fa], e[sa], rs, re)
    if st.plane == 18:
        return err_arc_radii_xz(st.err, fi, line, col, s[fa], s[sa], e[fa], e[sa], rs, re)
    if st.plane == 19:
        return err_arc_radii_yz(st.err, fi, line, col, s[fa], s[sa], e[fa], e[sa], rs, re)
    return err_arc_radii_zx(st.err, fi, line, col, s[fa], s[sa], e[fa], e[sa], rs, re)


cdef bint ngc_arc_off(const CState *st, double rs, double re) noexcept nogil:
    """ISO mode: LinuxCNC's test of an arc's end against its centre: the radii differ by
    more than 0.5 mm (0.05 inch in an inch program), or by more than 0.005 mm (0.0005
    inch) and 0.1 % of the radius."""
    cdef double err = fabs(rs - re)
    cdef double small = 0.005 if st.unit_scale == 1.0 else 0.0005 * 25.4
    return err > 100.0 * small or (err > small and err > 0.001 * rs)


cdef int em_arc(CState *st, const LineWords *lw, Part *p, int *func, const double *s,
                const double *e) noexcept nogil:
    """Centre, radius and direction of G2/G3 from s to e (program coordinates)."""
    cdef int fa, sa, na, a, dir = func[0]
    cdef double sx, sy, ex, ey, cx, cy, r, d, h, sgn, rs, re, tol
    cdef char li, lj
    cdef bint absolute
    cdef int col = 1
    cdef double c[AXES]
    cdef double cm[AXES]
    cdef PartExtra *x
    if not plane_axes(st.plane, &fa, &sa, &na):
        return err_bad_plane(st.err, st.unit.file_idx, st.line, st.plane)
    if st.params.swapG2G3:
        dir = 5 - dir
    sx = s[fa]; sy = s[sa]; ex = e[fa]; ey = e[sa]
    li = <char>(73 + fa)     # I J K belong to X Y Z
    lj = <char>(73 + sa)
    tol = st.params.tolerance[0]
    if not (tol > 0.0):
        tol = 0.005
    if has(lw, b'R'):
        r = val(lw, b'R')
        d = distance2d(ex - sx, ey - sy)
        if d == 0.0 or r == 0.0:
            return err_arc_no_centre(st.err, st.unit.file_idx, st.line)
        if d > 2.0 * fabs(r) + tol:
            return err_arc_radius(st.err, st.unit.file_idx, st.line, r, d)
        h = r * r - d * d * 0.25
        h = sqrt(h) if h > 0.0 else 0.0
        sgn = 1.0 if dir == 3 else -1.0
        if r < 0.0:         # negative R: the arc over 180 degrees
            sgn = -sgn
        cx = (sx + ex) * 0.5 - sgn * h * (ey - sy) / d
        cy = (sy + ey) * 0.5 + sgn * h * (ex - sx) / d
    elif has(lw, li) or has(lw, lj):
        col = lw.col[<int>li - 65] if has(lw, li) else lw.col[<int>lj - 65]
        if has(lw, li) and has(lw, lj) and lw.col[<int>lj - 65] < col:
            col = lw.col[<int>lj - 65]
        # Q70 (TG) or G90.1 (ISO mode): the centre is absolute
        absolute = (has(lw, b'Q') and val(lw, b'Q') == 70.0) or (st.ngc != NULL and st.ngc.ijk_absolute)
        if absolute and st.ngc != NULL and st.ngc.ijk_absolute and not (has(lw, li) and has(lw, lj)):
            return err_arc_no_centre(st.err, st.unit.file_idx, st.line)      # LinuxCNC: G90.1 needs both
        if absolute:
            cx = val(lw, li) if has(lw, li) else sx
            cy = val(lw, lj) if has(lw, lj) else sy
        else:
            cx = sx + (val(lw, li) if has(lw, li) else 0.0)
            cy = sy + (val(lw, lj) if has(lw, lj) else 0.0)
    else:
        return err_arc_no_centre(st.err, st.unit.file_idx, st.line)
    rs = distance2d(sx - cx, sy - cy)
    re = distance2d(ex - cx, ey - cy)
    if rs == 0.0:
        return err_arc_no_centre(st.err, st.unit.file_idx, st.line)
    if (fabs(rs - re) > tol and not st.iso) or (st.iso and ngc_arc_off(st, rs, re)):
        return em_arc_error(st, fa, sa, s, e, rs, re, col)
    for a in range(AXES):
        c[a] = s[a]
        if a != fa and a != sa and e[a] != s[a]:
            p.flags |= FLAG_HELIX
    c[fa] = cx
    c[sa] = cy
    to_machine(st, c, cm)
    x = program_part_extra(st.build, p)
    if x == NULL:
        return err_out_of_memory(st.err, st.unit.file_idx, st.line)
    x.cc[0] = cm[0]; x.cc[1] = cm[1]; x.cc[2] = cm[2]
    # ISO mode: an end off the start's circle (within the tolerance) is run as LinuxCNC
    # runs it, a spiral from the one radius to the other: the mean radius, its length
    x.radius = 0.5 * (rs + re) if st.iso else rs
    # mirroring one axis of the plane reverses the direction on the machine
    if fa < 3 and sa < 3 and (((st.mirror >> fa) ^ (st.mirror >> sa)) & 1):
        dir = 5 - dir
    func[0] = dir
    return 0


cdef int motion_column(const LineWords *lw, int func) noexcept nogil:
    """The column a message about a motion names: its G word, else its first axis word."""
    cdef int i
    for i in range(lw.ng):
        if lw.g[i] == func:
            return lw.gcol[i]
    return axis_column(lw, AXIS_LETTERS)


cdef void em_fix_axis(CState *st, int a) noexcept nogil:
    """Axis a is named absolutely from the next part on: it no longer follows the start."""
    if not st.fixed[a] and not st.shift_follows[a]:
        st.fixed[a] = True
        st.prog.start_gindex[a] = st.gindex


cdef inline int em_motion(CState *st, const LineWords *lw, int func, int col) noexcept nogil:
    """G0 G1 G2 G3 G33 to the axis words of the line (modal, absolute or relative); col:
    the column messages name (0: found when needed)."""
    cdef double newp[AXES]
    cdef int a, bit
    cdef uint32_t words = lw.mask & AXIS_LETTERS
    memcpy(newp, st.ppos, sizeof(newp))
    if words == 0:
        if func != 2 and func != 3:
            return R_NEXT
        if not (has(lw, b'I') or has(lw, b'J') or has(lw, b'K')):
            return R_NEXT       # bare G2/G3: only the modal change
    while words:                # only the axis letters written on the line
        bit = SF_CTZ(words)
        words &= words - 1
        a = axis_of_letter(<char>(65 + bit))
        if st.absolute:
            newp[a] = lw.v[bit]
            em_fix_axis(st, a)
        else:
            newp[a] += lw.v[bit]
    return em_move(st, lw, func, newp, col)


cdef inline int em_feed_check(CState *st, const LineWords *lw, int func, int col) noexcept nogil:
    """A feed move (G1 G2 G3) at feed 0: an error in the ISO mode (LinuxCNC refuses it),
    once a warning in the TG dialect, whose moves then run at motion[1].feed. ISO G93:
    every feed move has its F. col: the column to name, 0: the motion's G word, else
    its first axis word."""
    cdef bint inverse_time = st.ngc != NULL and st.ngc.inverse_time
    if not (func == 1 or func == 2 or func == 3):
        return 0
    if inverse_time:
        if has(lw, b'F') and val(lw, b'F') > 0.0:
            return 0
    elif st.feed != 0.0:
        return 0
    if col == 0:
        col = motion_column(lw, func)       # only a message needs it
    if inverse_time:
        return err_ngc_g(st.err, st.unit.file_idx, st.line, func, col,
                         "inverse time (G93) wants an F above 0 on every feed move")
    if st.iso:
        return err_no_feed(st.err, st.unit.file_idx, st.line, func, col)
    if st.def_feed <= 0.0 and st.params.forceMode == 0 and not st.warned_feed:
        st.warned_feed = True
        if warning_wanted(st):
            warn_no_feed(&st.warning, st.unit.file_idx, st.line, func, col)
            cwarn(st)
    return 0


cdef int em_move(CState *st, const LineWords *lw, int func, const double *newp, int col) noexcept nogil:
    """A motion part from the current point to newp (program coordinates, ten axes); lw
    holds the arc's centre words and the addresses the part carries."""
    cdef double e[AXES]
    cdef int f = func
    cdef Part *p
    cdef PartExtra *x
    cdef PartSettings s
    if em_feed_check(st, lw, func, col) != 0:
        return R_ERR
    to_machine(st, newp, e)
    p = em_part(st, PART_MOTION, func, e)
    if p == NULL:
        return R_ERR
    if st.css and (func == 1 or func == 2 or func == 3) and not (p.flags & FLAG_FEED_PER_MIN):
        if em_css(st, p, st.ppos[0], newp[0]) != 0:
            return R_ERR
    if func == 2 or func == 3:
        if em_arc(st, lw, p, &f, st.ppos, newp) != 0:
            return R_ERR
        p.func = f
    elif func == 33 and (has(lw, b'K') or has(lw, b'F')):
        x = program_part_extra(st.build, p)
        if x == NULL:
            return err_out_of_memory(st.err, st.unit.file_idx, st.line)
        x.value = val(lw, b'K') if has(lw, b'K') else val(lw, b'F')
    memcpy(st.ppos, newp, AXES * sizeof(double))
    memcpy(st.mpos, e, sizeof(e))
    if st.ngc != NULL and st.ngc.inverse_time and (func == 1 or func == 2 or func == 3):
        # G93: the move takes 1 / F minutes (F in 1/min, never converted from inches)
        s = part_settings(st.prog, p)[0]
        s.feed = val(lw, b'F') / st.unit_scale * part_length(st.prog, st.prog.n_parts - 1)
        if em_settings(st, p, &s) != 0:
            return R_ERR
    return em_pars(st, lw, p.func, -10000)


cdef int em_dwell(CState *st, const LineWords *lw) noexcept nogil:
    """G4: W milliseconds, or H / X / T seconds."""
    cdef Part *p = em_part(st, PART_DWELL, 4, st.mpos)
    cdef PartExtra *x
    if p == NULL:
        return R_ERR
    x = program_part_extra(st.build, p)
    if x == NULL:
        return err_out_of_memory(st.err, st.unit.file_idx, st.line)
    if has(lw, b'W'):
        x.value = val(lw, b'W') / 1000.0
    elif has(lw, b'H'):
        x.value = val(lw, b'H')
    elif has(lw, b'X'):
        x.value = val(lw, b'X')
    elif has(lw, b'T'):
        x.value = val(lw, b'T')
    return em_pars(st, lw, 4, -10000)


cdef int em_dwell_seconds(CState *st, double seconds) noexcept nogil:
    """A dwell of its own (a canned cycle's): the part G4 H seconds."""
    cdef LineWords words
    words.mask = 1u << 7
    words.v[7] = seconds
    return em_dwell(st, &words)


cdef int em_mfunc(CState *st, const LineWords *lw, int m, bint continuous) noexcept nogil:
    """An M function part (continuous: FLAG_CONTINUOUS_M, it does not stop the motion) with the
    line's addresses."""
    cdef Part *p = em_part(st, PART_MFUNC, m, st.mpos)
    if p == NULL:
        return R_ERR
    if continuous:
        p.flags |= FLAG_CONTINUOUS_M
    return em_pars(st, lw, -10000, m)


cdef int em_print(CState *st, const LineWords *lw, int m, const char *text, int n) noexcept nogil:
    """A PRINT part: its text kept in the program's texts, with the line's addresses."""
    cdef int64_t off = program_add_text(st.build, text, <size_t>n)
    cdef Part *p
    if off < 0:
        return err_out_of_memory(st.err, st.unit.file_idx, st.line)
    p = em_part(st, PART_PRINT, m, st.mpos)
    if p == NULL:
        return R_ERR
    p.extra = <uint32_t>off
    st.build.renumber = True        # no driver gets it: the next part's index moves (program_number_parts)
    return em_pars(st, lw, -10000, m)
