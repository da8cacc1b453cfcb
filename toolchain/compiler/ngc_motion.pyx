# ISO mode: LinuxCNC's G functions that place and move the tool beyond G0..G3:
# work offsets (G54..G59.3, set by G10 L2 / L20, kept in #5221.. as LinuxCNC keeps
# them), the G92 family, moves in machine coordinates (G53), the home positions
# (G28 / G30, stored by G28.1 / G30.1 in #5161.. / #5181..) and the canned cycles
# G73, G81..G86, G89 with G98 / G99, expanded into the rapid, feed and dwell parts
# LinuxCNC's interpreter makes of them. Work offsets are TG's zero offset, G92 TG's
# shift, so machine = program + offset + G92 as in LinuxCNC. Lengths are in mm
# (iso_units converted the words of an inch program).
from libc.math cimport floor, fabs, atan2, cos, sin, sqrt, M_PI

cdef extern from *:
    """
    /* LinuxCNC's G83_RAPID_DELTA: pecks go back down to 0.010 inch above the last depth */
    #define NGC_PECK_CLEARANCE 0.254
    """
    double NGC_PECK_CLEARANCE


cdef inline int ngc_axis(int k) noexcept nogil:
    """LinuxCNC's parameter axis k (X Y Z A B C U V W) as a TG axis index."""
    cdef const char *axes = "XYZABCUVW"
    return axis_of_letter(axes[k])



# ------------------------------------------------------------- work offsets

cdef int ngc_use_offsets(CState *st) noexcept nogil:
    """The active coordinate system's offsets (#5221.. of it) and the G92 offsets become
    the zero offset and shift; the machine stays where it is."""
    cdef NgcState *n = st.ngc
    cdef int k, base = 5201 + 20 * n.coord
    for k in range(9):
        st.zero[ngc_axis(k)] = n.params[base + k]
    cp_reframe(st)
    if not update_zero(st):
        return R_ERR
    return 0


cdef void ngc_store_shift(CState *st) noexcept nogil:
    """#5211.. hold the G92 offsets, #5210 whether they apply."""
    cdef int k
    for k in range(9):
        st.ngc.params[5211 + k] = st.shift[ngc_axis(k)]


cdef int ngc_select(CState *st, int coord, int col) noexcept nogil:
    """G54 .. G59.3."""
    if st.comp != 40:
        return err_ngc_g(st.err, st.unit.file_idx, st.line, 53.0 + coord if coord <= 6 else 59.0 + (coord - 6) / 10.0, col, "cutter compensation is on")
    st.ngc.coord = coord
    return ngc_use_offsets(st)


cdef int ngc_g10(CState *st, const LineWords *lw, int col) noexcept nogil:
    """G10 L2 P n (the offsets of system n, P0 the active one) or G10 L20 P n (offsets
    that make the current point have the given coordinates)."""
    cdef NgcState *n = st.ngc
    cdef int k, a, bit, coord, base
    cdef double l = val(lw, b'L') if has(lw, b'L') else -1.0
    if l != 2.0 and l != 20.0:
        if has(lw, b'L'):
            col = lw.col[11]
        return err_ngc_unsupported(st.err, st.unit.file_idx, st.line, word_at_column(st, col), col, "G10 sets work offsets with L2 or L20 (tool tables do not exist here)")
    if not lw.has_pword or lw.pword != floor(lw.pword) or lw.pword < 0.0 or lw.pword > 9.0:
        return err_ngc_g(st.err, st.unit.file_idx, st.line, 10.0, col, "P must name a coordinate system 0..9")
    if has(lw, b'R') and val(lw, b'R') != 0.0:
        return err_ngc_unsupported(st.err, st.unit.file_idx, st.line, word_at_column(st, lw.col[17]), lw.col[17], "rotated coordinate systems are not read")
    coord = <int>lw.pword if lw.pword > 0.0 else n.coord
    base = 5201 + 20 * coord
    for k in range(9):
        a = ngc_axis(k)
        bit = <int>letter_of_axis(a) - 65
        if (lw.mask >> bit) & 1:
            if l == 2.0:
                n.params[base + k] = lw.v[bit]
            else:
                n.params[base + k] = st.mpos[a] - st.shift[a] - st.length[a] - lw.v[bit]
    if coord == n.coord:
        return ngc_use_offsets(st)
    return 0


cdef int ngc_shift_reset(CState *st, int how) noexcept nogil:
    """G92.1 clears the G92 offsets and #5211..; G92.2 clears them, keeping #5211..;
    G92.3 takes them back from #5211.."""
    cdef int k
    for k in range(9):
        st.shift[ngc_axis(k)] = st.ngc.params[5211 + k] if how == 3 else 0.0
    if how == 1:
        ngc_store_shift(st)
    cp_reframe(st)
    if not update_zero(st):
        return R_ERR
    return 0


# ------------------------------------------------------------- moves

cdef int ngc_polar(CState *st, LineWords *lw) noexcept nogil:
    """@ (distance) and ^ (angle) as the X Y words they stand for: from the program zero;
    a missing one is the current point's; in G91 both add to the current point's."""
    cdef double r = sqrt(st.ppos[0] * st.ppos[0] + st.ppos[1] * st.ppos[1])
    cdef double a = atan2(st.ppos[1], st.ppos[0])
    cdef double x, y
    if has(lw, b'X') or has(lw, b'Y'):
        return err_ngc_word(st.err, st.unit.file_idx, st.line, word_at_column(st, lw.polar_col), lw.polar_col, "polar coordinates do not mix with X or Y")
    if st.absolute:
        if lw.has_polar_r: r = lw.polar_r
        if lw.has_polar_a: a = lw.polar_a * M_PI / 180.0
    else:
        if r == 0.0:
            return err_ngc_word(st.err, st.unit.file_idx, st.line, word_at_column(st, lw.polar_col), lw.polar_col, "an incremental polar move from the origin has no direction")
        if lw.has_polar_r: r += lw.polar_r
        if lw.has_polar_a: a += lw.polar_a * M_PI / 180.0
    x = r * cos(a)
    y = r * sin(a)
    lw.v[23] = x if st.absolute else x - st.ppos[0]
    lw.v[24] = y if st.absolute else y - st.ppos[1]
    lw.mask |= bit_of(b'X') | bit_of(b'Y')
    lw.col[23] = lw.polar_col
    lw.col[24] = lw.polar_col
    return 0


cdef int ngc_probe(CState *st, const LineWords *lw) noexcept nogil:
    """G38.2 .. G38.5: a feed move to the programmed point (a compiled program touches
    nothing); #5061.. hold that point, #5070 = 1, as after a probe that tripped there."""
    cdef int k
    if st.comp != 40:
        return err_ngc_g(st.err, st.unit.file_idx, st.line, 38.2, motion_column(lw, 38), "cutter compensation is on")
    if em_motion(st, lw, 1, motion_column(lw, 38)) != 0:
        return R_ERR
    for k in range(9):
        st.ngc.params[5061 + k] = st.ppos[ngc_axis(k)] / st.unit_scale
    st.ngc.params[5070] = 1.0
    return 0


cdef int ngc_rapid_to(CState *st, const double *newp) noexcept nogil:
    """A rapid part to newp (program coordinates) carrying its x y z as its addresses."""
    cdef LineWords words
    words.mask = (1u << 23) | (1u << 24) | (1u << 25)
    words.v[23] = newp[0]; words.v[24] = newp[1]; words.v[25] = newp[2]
    return em_move(st, &words, 0, newp, 1)


cdef int ngc_feed_to(CState *st, const double *newp, int col) noexcept nogil:
    """A G1 of a canned cycle to newp's X, Y and Z (the cycle's feed moves), its words as if
    written on the line at column col."""
    cdef LineWords words
    words.mask = (1u << 23) | (1u << 24) | (1u << 25)
    words.v[23] = newp[0]; words.v[24] = newp[1]; words.v[25] = newp[2]
    return em_move(st, &words, 1, newp, col)


cdef int ngc_machine_move(CState *st, const LineWords *lw, int motion) noexcept nogil:
    """G53 G0 / G1: the axis words are machine coordinates, for this line only."""
    cdef double target[AXES]
    cdef double newp[AXES]
    cdef uint32_t words = lw.mask & AXIS_LETTERS
    cdef int a, bit, col = g_column(lw, 53.0)
    if motion != 0 and motion != 1:
        return err_ngc_g(st.err, st.unit.file_idx, st.line, 53.0, col, "moves in machine coordinates with G0 or G1 only")
    if st.comp != 40:
        return err_ngc_g(st.err, st.unit.file_idx, st.line, 53.0, col, "cutter compensation is on")
    if not st.absolute:
        return err_ngc_g(st.err, st.unit.file_idx, st.line, 53.0, col, "machine coordinates are absolute (G90)")
    memcpy(target, st.mpos, sizeof(target))
    while words:
        bit = SF_CTZ(words)
        words &= words - 1
        a = axis_of_letter(<char>(65 + bit))
        target[a] = lw.v[bit]
        em_fix_axis(st, a)
    to_program(st, target, newp)
    return em_move(st, lw, motion, newp, 0)


cdef int ngc_home(CState *st, const LineWords *lw, int home, int col) noexcept nogil:
    """G28 / G30: a rapid to the axis words (an intermediate point, as a move of the line
    would go), then a rapid to the stored position (#5161.. / #5181.., machine
    coordinates) of those axes, or of all axes when the line names none. G28.1 / G30.1
    store the current position there."""
    cdef NgcState *n = st.ngc
    cdef int base = 5161 if (home == 28 or home == 281) else 5181
    cdef double newp[AXES]
    cdef double target[AXES]
    cdef uint32_t words = lw.mask & AXIS_LETTERS
    cdef int a, k, bit
    cdef bint moved = False
    if home == 281 or home == 282:
        for k in range(9):
            n.params[base + k] = st.mpos[ngc_axis(k)]
        return R_NEXT
    if st.comp != 40:
        return err_ngc_g(st.err, st.unit.file_idx, st.line, home, col, "cutter compensation is on")
    memcpy(newp, st.ppos, sizeof(newp))
    while words:
        bit = SF_CTZ(words)
        words &= words - 1
        a = axis_of_letter(<char>(65 + bit))
        newp[a] = lw.v[bit] if st.absolute else newp[a] + lw.v[bit]
        moved = moved or newp[a] != st.ppos[a]
        if st.absolute:
            em_fix_axis(st, a)
    if moved and ngc_rapid_to(st, newp) != 0:
        return R_ERR
    memcpy(target, st.mpos, sizeof(target))
    for k in range(9):
        a = ngc_axis(k)
        if (lw.mask & AXIS_LETTERS) == 0 or has(lw, letter_of_axis(a)):
            target[a] = n.params[base + k]
            em_fix_axis(st, a)
    to_program(st, target, newp)
    return ngc_rapid_to(st, newp)


# ------------------------------------------------------------- canned cycles

cdef int ngc_spindle_m(CState *st, int32_t m) noexcept nogil:
    """A spindle M function a cycle gives (the host's number for it; 0: none)."""
    cdef LineWords words
    if m == 0:
        return 0
    words.mask = 0
    return em_mfunc(st, &words, m, False)


cdef double _cycle_pecks(int g, double depth, double q) noexcept nogil:
    """The pecks of one hole of a G73 / G83 cycle `depth` deep (0 for the others)."""
    return floor(depth / q) + 1.0 if g == 73 or g == 83 else 0.0


cdef double _cycle_parts(int g, int repeat, double depth, double q) noexcept nogil:
    """At least the parts a cycle line makes (reckoned before one is made, so that a
    line asking for millions of holes or pecks is refused at once, not cut short by
    the part limit after seconds): per hole at most 9 parts besides three per peck."""
    return <double>repeat * (9.0 + 3.0 * _cycle_pecks(g, depth, q))


cdef int ngc_cycle(CState *st, const LineWords *lw, int g, int col) noexcept nogil:
    """A canned cycle at the positions of the line (L times), as LinuxCNC makes it: to
    the R level first when below it, then per repeat a rapid in the plane, a rapid to
    R, the cycle's own moves, the retract (G98: back to the level before the series
    of cycles, when above R; G99: R). R, Z (the plane's normal axis), Q and P are kept
    for the following lines of the same cycle."""
    cdef NgcState *n = st.ngc
    cdef int fa, sa, na, repeat, k
    cdef char la, lb, lc
    cdef double aa, bb, inc_a = 0.0, inc_b = 0.0, r, z, q, dwell, old_cc, current, clear, depth
    cdef double inc_r = 0.0, inc_t = 0.0, radius, theta
    cdef double target[AXES]
    cdef bint same = st.motion == g
    cdef bint reverse
    cdef char why[128]
    if st.feed == 0.0:
        return err_ngc_g(st.err, st.unit.file_idx, st.line, g, col, "feed 0: no F word was given (LinuxCNC refuses it)")
    if st.comp != 40:
        return err_ngc_g(st.err, st.unit.file_idx, st.line, g, col, "cutter compensation is on")
    if n.inverse_time:
        return err_ngc_g(st.err, st.unit.file_idx, st.line, g, col, "inverse time feed (G93) is on")
    if not plane_axes(st.plane, &fa, &sa, &na) or st.plane == 18:
        return err_ngc_g(st.err, st.unit.file_idx, st.line, g, col, "canned cycles run in G17, G18 or G19")
    la = letter_of_axis(fa); lb = letter_of_axis(sa); lc = letter_of_axis(na)
    if lw.mask & AXIS_LETTERS & ~(bit_of(la) | bit_of(lb) | bit_of(lc)):
        return err_ngc_g(st.err, st.unit.file_idx, st.line, g, col, "only the axes of the plane and its normal move in a cycle")
    if not has(lw, lc) and not same:
        return err_ngc_g(st.err, st.unit.file_idx, st.line, g, col, "the first line of a cycle names the hole bottom (the normal axis)")
    if not has(lw, b'R') and not same:
        return err_ngc_g(st.err, st.unit.file_idx, st.line, g, col, "the first line of a cycle names the R level")
    repeat = 1
    if has(lw, b'L'):
        if val(lw, b'L') != floor(val(lw, b'L')) or val(lw, b'L') < 1.0:
            return err_ngc_g(st.err, st.unit.file_idx, st.line, g, col, "L repeats a positive whole number of times")
        repeat = to_int(val(lw, b'L'))
    q = val(lw, b'Q') * st.unit_scale if has(lw, b'Q') else n.cycle_q
    if (g == 73 or g == 83) and ((not has(lw, b'Q') and not same) or not (q > 0.0)):
        return err_ngc_g(st.err, st.unit.file_idx, st.line, g, col, "Q (the peck depth) must be above 0")
    dwell = lw.pword if lw.has_pword else n.cycle_p
    if (g == 82 or g == 86 or g == 89) and not lw.has_pword and not same:
        return err_ngc_g(st.err, st.unit.file_idx, st.line, g, col, "P (the dwell in seconds) is missing")
    reverse = g == 84 or g == 74
    if (g == 84 and n.spindle != 3) or (g == 74 and n.spindle != 4) or (g == 86 and n.spindle == 0):
        return err_ngc_g(st.err, st.unit.file_idx, st.line, g, col, "the spindle does not turn the way the cycle needs (M3 / M4)")
    n.cycle_r = val(lw, b'R') if has(lw, b'R') else n.cycle_r
    n.cycle_cc = val(lw, lc) if has(lw, lc) else n.cycle_cc
    n.cycle_q = q
    n.cycle_p = dwell
    if not n.cycle_il_set:
        n.cycle_il = st.ppos[na]
        n.cycle_il_set = True
    old_cc = n.cycle_il
    if st.absolute:
        r = n.cycle_r
        z = n.cycle_cc
        aa = val(lw, la) if has(lw, la) else st.ppos[fa]
        bb = val(lw, lb) if has(lw, lb) else st.ppos[sa]
        if has(lw, la): em_fix_axis(st, fa)
        if has(lw, lb): em_fix_axis(st, sa)
        em_fix_axis(st, na)
    else:
        inc_a = val(lw, la) if has(lw, la) else 0.0
        inc_b = val(lw, lb) if has(lw, lb) else 0.0
        if lw.has_polar_r or lw.has_polar_a:
            if has(lw, b'X') or has(lw, b'Y') or st.plane != 17:
                return err_ngc_word(st.err, st.unit.file_idx, st.line, word_at_column(st, lw.polar_col), lw.polar_col, "polar coordinates are XY positions without X or Y")
            inc_r = lw.polar_r if lw.has_polar_r else 0.0
            inc_t = lw.polar_a * M_PI / 180.0 if lw.has_polar_a else 0.0
        r = n.cycle_r + old_cc
        z = r + n.cycle_cc
        aa = st.ppos[fa]
        bb = st.ppos[sa]
    if r < z:
        return err_ngc_g(st.err, st.unit.file_idx, st.line, g, col, "the R level is below the hole bottom")
    if _cycle_parts(g, repeat, r - z, q) > <double>(MAX_PARTS - st.prog.n_parts):
        c_snprintf(why, sizeof(why), "%d repeats of %g pecks make more parts than a program holds (%d)",
                   repeat, _cycle_pecks(g, r - z, q), <int>MAX_PARTS)
        return err_ngc_g(st.err, st.unit.file_idx, st.line, g, col, why)
    st.motion = g
    memcpy(target, st.ppos, sizeof(target))
    current = st.ppos[na]
    if old_cc < r:
        target[na] = r
        if ngc_rapid_to(st, target) != 0:
            return R_ERR
        old_cc = r
        current = r
    clear = r if n.retract == 99 else old_cc
    for k in range(repeat):
        aa += inc_a
        bb += inc_b
        if inc_r != 0.0 or inc_t != 0.0:
            if aa == 0.0 and bb == 0.0:
                return err_ngc_word(st.err, st.unit.file_idx, st.line, word_at_column(st, lw.polar_col), lw.polar_col, "an incremental polar move from the origin has no direction")
            radius = sqrt(aa * aa + bb * bb) + inc_r
            theta = atan2(bb, aa) + inc_t
            aa = radius * cos(theta)
            bb = radius * sin(theta)
        target[fa] = aa; target[sa] = bb; target[na] = current
        if ngc_rapid_to(st, target) != 0:
            return R_ERR
        if current != r:
            target[na] = r
            if ngc_rapid_to(st, target) != 0:
                return R_ERR
        if g == 73 or g == 83:
            depth = r - q
            while depth > z:
                target[na] = depth
                if ngc_feed_to(st, target, col) != 0:
                    return R_ERR
                if g == 83:
                    target[na] = r
                    if ngc_rapid_to(st, target) != 0:
                        return R_ERR
                target[na] = depth + NGC_PECK_CLEARANCE
                if ngc_rapid_to(st, target) != 0:
                    return R_ERR
                depth -= q
        target[na] = z
        if ngc_feed_to(st, target, col) != 0:
            return R_ERR
        if reverse:
            if ngc_spindle_m(st, st.params.M05_stopSpindle) != 0 or \
                    ngc_spindle_m(st, st.params.M04_startSpindleCCW if g == 84 else st.params.M03_startSpindleCW) != 0:
                return R_ERR
        if (g == 82 or g == 86 or g == 89 or reverse) and dwell > 0.0 and em_dwell_seconds(st, dwell) != 0:
            return R_ERR
        if g == 86 and ngc_spindle_m(st, st.params.M05_stopSpindle) != 0:
            return R_ERR
        if g == 85:
            target[na] = r
            if ngc_feed_to(st, target, col) != 0:
                return R_ERR
        target[na] = clear
        if g == 85 or g == 86 or g == 81 or g == 82 or g == 73 or g == 83:
            if (g != 85 or clear != r) and ngc_rapid_to(st, target) != 0:
                return R_ERR
        elif ngc_feed_to(st, target, col) != 0:        # G89, G84, G74 feed out
            return R_ERR
        if reverse:
            if ngc_spindle_m(st, st.params.M05_stopSpindle) != 0 or \
                    ngc_spindle_m(st, st.params.M03_startSpindleCW if g == 84 else st.params.M04_startSpindleCCW) != 0:
                return R_ERR
        if g == 86 and ngc_spindle_m(st, st.params.M03_startSpindleCW if n.spindle == 3
                                     else st.params.M04_startSpindleCCW) != 0:
            return R_ERR
        current = clear
    return R_NEXT
