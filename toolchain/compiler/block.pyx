# One block (line) of address words, executed the way rs274ngc executes a block:
# cp_read_block first reads the G and M functions of the line, in the order written,
# into modal groups (a Block: what the line says; a later G of the same group
# replaces an earlier one), then cp_block runs the groups in one fixed order,
# whatever the order they were written in (the ISO mode's additions in brackets):
#
#    1. parameters      G900 (the working copy of GCODE_PARAMETERS)
#    2. feed mode       G94 / G95, G96 / G97, G24
#    3. F S T           modal values, FF, FP
#    4. plane           G17 G18 G19 G-18
#    5. units           G21 (TG: nothing; an ISO header) [G20 / G21: iso_units]
#    6. compensation    D, G40 .. G48, & (tools.pyx) [G43 H / G49: tool length offsets]
#    7. coordinates     G53 .. G57, G59 (zero offsets), G168 / G169 (rotation)
#                       [G54 .. G59.3: the work offsets]
#    8. path            G167 (automatic arcs), G172 / G173 (compensation strategy)
#    9. distance mode   G90 / G91 [G90.1 / G91.1; G98 / G99 the cycles' retract]
#   10. shift           G92 / G98 (new coordinates of the current point)
#                       [G92.1 G92.2 G92.3, G10 L2 / L20, G28.1 / G30.1]
#   11. parts           continuous M functions (>= 1001) [and every M function but the
#                       stops M0 M1 M2 M30 M60], then the dwell (G4) or the motion
#                       (G0 G1 G2 G3 G33, modal) [the dwell, then G28 / G30, a canned
#                       cycle, G53's move or the motion]
#   12. M functions     the others, in the order written (M2 / M30 end the program),
#                       then G92 D's write of the tool table (in force from the next line)
#   13. flow            G25 / G26 / G27 jumps and calls, M17 return
#
# Settings (1-10) come before every part of the line, so each part carries them.

from libc.string cimport memcpy, memset


# ------------------------------------------------------------ G functions

cdef int cp_zero(CState *st, const LineWords *lw, int g) noexcept nogil:
    """G53 off, G54..G57 set (absent axes 0), G59 set (absent axes kept)."""
    cdef int a, bit
    for a in range(AXES):
        bit = <int>letter_of_axis(a) - 65
        if g == 53:
            st.zero[a] = 0.0
        elif (lw.mask >> bit) & 1:
            st.zero[a] = lw.v[bit]
        elif g != 59:
            st.zero[a] = 0.0
    cp_reframe(st)
    if not update_zero(st):
        return R_ERR
    return 0


cdef int cp_g92(CState *st, const LineWords *lw) noexcept nogil:
    """G92 / G98: the current point gets the given program coordinates (shift)."""
    cdef int a, bit
    cdef double t[AXES]
    for a in range(AXES):
        bit = <int>letter_of_axis(a) - 65
        if (lw.mask >> bit) & 1:
            st.ppos[a] = lw.v[bit]
            # a shift taken where the machine follows the start follows it too
            st.shift_follows[a] = not st.fixed[a]
    to_machine(st, st.ppos, t)
    for a in range(AXES):
        st.shift[a] += st.mpos[a] - t[a]
    if not update_zero(st):
        return R_ERR
    return 0


cdef int cp_g168(CState *st, const LineWords *lw) noexcept nogil:
    """Rotation by R degrees about (X Y Z), axis IJK or the normal of plane Q."""
    cdef double ax = 0.0, ay = 0.0, az = 1.0
    cdef int plane = st.plane
    if has(lw, b'I') or has(lw, b'J') or has(lw, b'K'):
        ax = val(lw, b'I') if has(lw, b'I') else 0.0
        ay = val(lw, b'J') if has(lw, b'J') else 0.0
        az = val(lw, b'K') if has(lw, b'K') else 0.0
    else:
        if has(lw, b'Q'):
            plane = to_int(val(lw, b'Q'))
        if plane == 17:
            ax = 0.0; ay = 0.0; az = 1.0
        elif plane == 18:
            ax = 0.0; ay = -1.0; az = 0.0
        elif plane == 19:
            ax = 1.0; ay = 0.0; az = 0.0
        elif plane == -18:
            ax = 0.0; ay = 1.0; az = 0.0
        else:
            return err_bad_plane(st.err, st.unit.file_idx, st.line, plane)
    if not set_rotation(st, val(lw, b'X') if has(lw, b'X') else 0.0, val(lw, b'Y') if has(lw, b'Y') else 0.0,
                        val(lw, b'Z') if has(lw, b'Z') else 0.0, ax, ay, az,
                        val(lw, b'R') if has(lw, b'R') else 0.0):
        return R_ERR
    cp_reframe(st)
    return 0


cdef void _feed_set(CState *st, const LineWords *lw, int k) noexcept nogil:
    """G900 S20/30/31/32/41/50: motion class k's feed (F), acceleration (C), deceleration (D)
    and ramp type (R), those the line gives."""
    if has(lw, b'F'): st.params.motion[k].feed = val(lw, b'F')
    if has(lw, b'C'): st.params.motion[k].acc = val(lw, b'C')
    if has(lw, b'D'): st.params.motion[k].dec = val(lw, b'D')
    if has(lw, b'R'): st.params.motion[k].rampType = to_int(val(lw, b'R'))


cdef uint32_t _axis_flags(const LineWords *lw) noexcept nogil:
    """The mask of the axes whose address on the line is not 0 (G900 S10 / S11: the axes the
    angle and feed rules ignore)."""
    cdef uint32_t m = 0
    cdef int a, bit
    for a in range(AXES):
        bit = <int>letter_of_axis(a) - 65
        if (lw.mask >> bit) & 1 and lw.v[bit] != 0.0:
            m |= 1u << a
    return m


cdef int cp_g900(CState *st, const LineWords *lw, int col) noexcept nogil:
    """G900 S..: changes the working copy of GCODE_PARAMETERS (col: the G900's column)."""
    cdef int s, a
    cdef double sv
    if not has(lw, b'S'):
        return err_missing_value(st.err, st.unit.file_idx, st.line, "S", col)
    sv = val(lw, b'S')
    s = to_int(sv)
    if s == 1:
        if st.n_pstack >= PARAM_STACK_DEPTH:
            return err_param_stack(st.err, st.unit.file_idx, st.line, "overflow")
        st.pstack[st.n_pstack] = st.params
        st.n_pstack += 1
    elif s == 2:
        if st.n_pstack == 0:
            return err_param_stack(st.err, st.unit.file_idx, st.line, "empty")
        st.n_pstack -= 1
        st.params = st.pstack[st.n_pstack]
    elif s == 7:
        a = to_int(val(lw, b'A')) if has(lw, b'A') else -1
        if a < 0 or a > 9:
            return err_bad_value(st.err, st.unit.file_idx, st.line, val(lw, b'A') if has(lw, b'A') else -1.0, "A")
        if has(lw, b'F'): st.params.axisLimits[a].maxFeed = val(lw, b'F')
        if has(lw, b'C'): st.params.axisLimits[a].maxAcc = val(lw, b'C')
        if has(lw, b'D'): st.params.axisLimits[a].maxDec = val(lw, b'D')
    elif s == 9:
        if has(lw, b'A'): st.params.startAngle = val(lw, b'A')
        if has(lw, b'B'): st.params.endAngle = val(lw, b'B')
        if has(lw, b'F'): st.params.minAngleFeed = val(lw, b'F')
    elif s == 10:
        st.g900_ignore_angle = _axis_flags(lw)
    elif s == 11:
        st.g900_ignore_feed = _axis_flags(lw)
    elif s == 12:
        st.g900_stop_mode = to_int(val(lw, b'A')) if has(lw, b'A') else 0
    elif s == 13:
        st.g900_arc_table = to_int(val(lw, b'A')) if has(lw, b'A') else 0
    elif s == 20: _feed_set(st, lw, 0)
    elif s == 30: _feed_set(st, lw, 1)
    elif s == 31: _feed_set(st, lw, 4)
    elif s == 32: _feed_set(st, lw, 2)
    elif s == 41: _feed_set(st, lw, 3)
    elif s == 50: _feed_set(st, lw, 5)
    elif s == 60:
        if has(lw, b'D'): st.params.motion[6].dec = val(lw, b'D')
    elif s == 70:
        if has(lw, b'D'): st.params.motion[7].dec = val(lw, b'D')
    else:
        return err_bad_value(st.err, st.unit.file_idx, st.line, sv, "S")
    return 0


cdef bint cp_plan_region(CState *st) noexcept nogil:
    """The planning settings from the next part on (G900, M-5), for the planner."""
    return program_add_plan_region(st.build, st.prog.n_parts, &st.params, st.g900_ignore_angle,
                                   st.g900_ignore_feed, st.limits_off, st.g900_stop_mode, st.g900_arc_table)


cdef bint _is_m(const GCODE_PARAMETERS *pr, int m, int32_t number) noexcept nogil:
    """Whether M function m is the one a parameter assigns a role (number 0: none assigned)."""
    return number != 0 and m == number


cdef int cp_g167(CState *st, const LineWords *lw) noexcept nogil:
    """G167 [E] [A] [U] [Q]: automatic arcs on with these values (E/A default to the
    host's tolerances, U to 90 degrees, Q to insertArcPlane); bare G167: off. Recorded
    in Program.arc_regions from the next part on (compensation/insert_arcs.pyx)."""
    cdef int ga, gb, gc
    cdef uint32_t letters = bit_of(b'E') | bit_of(b'A') | bit_of(b'U') | bit_of(b'Q')
    st.g167_on = (lw.mask & letters) != 0
    st.g167[0] = val(lw, b'E') if has(lw, b'E') else st.params.insertArcToleranceRMax
    st.g167[1] = val(lw, b'A') if has(lw, b'A') else st.params.insertArcToleranceRMin
    st.g167[2] = val(lw, b'U') if has(lw, b'U') else 90.0
    st.g167[3] = val(lw, b'Q') if has(lw, b'Q') else <double>st.params.insertArcPlane
    if has(lw, b'Q') and not (to_int(st.g167[3]) == 0 or plane_axes(to_int(st.g167[3]), &ga, &gb, &gc)):
        return err_bad_plane(st.err, st.unit.file_idx, st.line, st.g167[3])
    if not program_add_arc_region(st.build, st.prog.n_parts, st.g167_on, to_int(st.g167[3]),
                                  st.g167[0], st.g167[1], st.g167[2]):
        return err_out_of_memory(st.err, st.unit.file_idx, st.line)
    return 0


# ------------------------------------------------------------ reading the block

cdef int cp_read_g(CState *st, const LineWords *lw, int i, Block *b) noexcept nogil:
    """G function i of the line into its group of the block."""
    cdef double gv = lw.g[i]
    cdef int g = to_int(gv), r
    cdef uint32_t axes = axes_mask()
    if st.iso:
        b.settings = True           # (the ISO mode's groups are not told apart: all run)
        r = iso_read_g(st, lw, i, b)
        if r != 0:
            return r if r < 0 else 0
    if gv != <double>g:
        return cp_unknown_g(st, gv, lw.gcol[i])
    if g == 0 or g == 1 or g == 2 or g == 3 or g == 33:
        if cp_set_motion(st, b, g, lw.gcol[i]) != 0:
            return R_ERR
        if g == 33:
            b.consumed |= bit_of(b'K') | bit_of(b'F')
        return 0
    if g == 4:
        b.dwell = True
        b.consumed |= bit_of(b'W') | bit_of(b'H') | bit_of(b'X') | bit_of(b'T')
        return 0
    if g == 29:
        return 0            # a comment
    if g == 25 or g == 26 or g == 27:
        b.jump = g
        b.jump_col = lw.gcol[i]
        b.consumed |= bit_of(b'L') | bit_of(b'H')
        return 0
    b.settings = True       # the others set groups 1, 2, 4 .. 10
    if g == 17 or g == 18 or g == 19 or g == -18:
        b.plane = g
    elif g == 21:
        b.units = g
    elif g == 24:
        b.lathe_radius = True
    elif g >= 40 and g <= 48:
        if g == 43 and has(lw, b'H'):     # (the ISO mode took G43 above)
            if warning_wanted(st):
                warn_g43_h(&st.warning, st.unit.file_idx, st.line, lw.gcol[i])
                cwarn(st)
        b.comp = g
    elif g == 53 or (g >= 54 and g <= 57) or g == 59:
        b.consumed |= axes
        b.zero = g
        b.zero_col = lw.gcol[i]
    elif g == 90 or g == 91:
        b.distance = g
    elif g == 92 or g == 98:
        b.consumed |= axes
        if g == 92:
            b.consumed |= bit_of(b'D')      # G92 D: the entry its R0= .. R4= write
        b.shift = g
    elif g == 94 or g == 95:
        b.feed_mode = g
    elif g == 96 or g == 97:
        b.css = g
    elif g == 167:
        b.consumed |= bit_of(b'E') | bit_of(b'A') | bit_of(b'U') | bit_of(b'Q')
        b.g167 = True
    elif g == 168:
        b.consumed |= (bit_of(b'X') | bit_of(b'Y') | bit_of(b'Z') | bit_of(b'I') | bit_of(b'J')
                       | bit_of(b'K') | bit_of(b'R') | bit_of(b'Q'))
        b.rotation = g
    elif g == 169:
        b.rotation = g
    elif g == 172 or g == 173:
        b.consumed |= bit_of(b'R') | bit_of(b'C') | bit_of(b'D')
        b.strategy = g
    elif g == 900:
        b.consumed = ~(<uint32_t>0)
        b.g900_col = lw.gcol[i]
    else:
        return cp_unknown_g(st, gv, lw.gcol[i])
    return 0


cdef bint _ngc_m_known(int m) noexcept nogil:
    """An M code LinuxCNC 2.9 runs without a user program (M100 .. M199 need one)."""
    return (m >= 0 and m <= 9) or m == 19 or m == 30 or (m >= 48 and m <= 53) or m == 60 \
        or (m >= 61 and m <= 68) or (m >= 70 and m <= 73) or m == 98 or m == 99


cdef int cp_read_m(CState *st, const LineWords *lw, int i, Block *b) noexcept nogil:
    """M function i of the line: a valid number; the letters it uses."""
    cdef const GCODE_PARAMETERS *pr = &st.params
    cdef int m = to_int(lw.m[i])
    if lw.m[i] != <double>m or m == 1000 or m < -6 or m > 1000000000 or (m < 0 and m != -5 and m != -6):
        return err_bad_m(st.err, st.unit.file_idx, st.line, lw.m[i], lw.mcol[i])
    if st.iso and m == 98:
        return err_ngc_unsupported(st.err, st.unit.file_idx, st.line, word_at_column(st, lw.mcol[i]), lw.mcol[i], "Fanuc-style subprograms (M98 / M99); an o-word call is read")
    if st.iso and not _ngc_m_known(m):
        if m >= 100 and m <= 199:
            if ngc_refused(st, word_at_column(st, lw.mcol[i]), lw.mcol[i],
                           "a user M code (LinuxCNC runs its program file, and stops without one)",
                           "keeps the M function's part (no file is read)") != 0:
                return R_ERR
        elif ngc_refused(st, word_at_column(st, lw.mcol[i]), lw.mcol[i], "no LinuxCNC M code (a Marlin / "
                         "GRBL post's?)", "compiles it with the TG meaning of its number (GCODE_PARAMETERS)") != 0:
            return R_ERR
    if m == -5:
        b.consumed |= axes_mask()
    elif _is_m(pr, m, pr.M06_changeTool):
        b.consumed |= axes_mask() | bit_of(b'D')    # D: the tool's diameter
    elif m == -6:
        b.consumed |= bit_of(b'A') | bit_of(b'S')
    elif _is_m(pr, m, pr.M99_defFeed):
        b.consumed |= bit_of(b'F')
    return 0


cdef inline int cp_read_block(CState *st, LineWords *lw, Block *b) noexcept nogil:
    """The G and M functions of the line into the block, in the order written; the
    P word judged after the G functions (so an unknown G of the line comes first)."""
    cdef int i
    memset(b, 0, sizeof(Block))
    b.motion = -1
    if st.iso:
        iso_units(st, lw)
        if lw.first_is_o:
            lw.mask &= ~bit_of(b'O')        # a program number
    for i in range(lw.ng):
        if cp_read_g(st, lw, i, b) != 0:
            return R_ERR
    if lw.has_pword and cp_pword(st, lw, b) != 0:
        return R_ERR
    for i in range(lw.nm):
        if cp_read_m(st, lw, i, b) != 0:
            return R_ERR
    if lw.tool_values != 0 and b.shift != 92:
        return err_tool_word(st.err, st.unit.file_idx, st.line, word_at_column(st, lw.tool_values_col), lw.tool_values_col, "R0= .. R4= write the tool table on a line with G92 D")
    return 0


# ------------------------------------------------------ executing the groups

cdef int _x_parameters(CState *st, const LineWords *lw, const Block *b) noexcept nogil:
    """1. G900."""
    if b.g900_col == 0:
        return 0
    if cp_g900(st, lw, b.g900_col) != 0:
        return R_ERR
    if not cp_plan_region(st):
        return err_out_of_memory(st.err, st.unit.file_idx, st.line)
    return 0


cdef inline void _x_feed_mode(CState *st, const Block *b) noexcept nogil:
    """2. G94 / G95 feed per minute / revolution, G96 / G97 constant cutting speed, G24;
    ISO: G93 inverse time (LinuxCNC wants a new F after it ends)."""
    if b.feed_mode != 0 and st.ngc != NULL:
        if b.feed_mode != 93 and st.ngc.inverse_time:
            st.feed = 0.0
        st.ngc.inverse_time = b.feed_mode == 93
    if b.feed_mode == 94 or b.feed_mode == 95:
        st.per_min = b.feed_mode == 94
    if b.css != 0:
        st.css = b.css == 96
    if b.lathe_radius:
        st.lathe_radius = True


cdef inline void _x_values(CState *st, const LineWords *lw, const Block *b) noexcept nogil:
    """3. F S T (unless a function of the line uses the letter), FF, FP."""
    cdef uint32_t given = lw.mask & ~b.consumed & (bit_of(b'F') | bit_of(b'S') | bit_of(b'T'))
    if given == 0 and not (lw.has_fp or lw.has_ff):
        return              # (most lines)
    if given & bit_of(b'F'):
        st.feed = val(lw, b'F')
    if given & bit_of(b'S'):
        st.spindle = <float>val(lw, b'S')
    if given & bit_of(b'T'):
        st.tool = to_int(val(lw, b'T'))
    if lw.has_fp and st.params.forceMode != 1:
        st.fp = lw.fp
    if lw.has_ff:
        st.ff = lw.ff
        st.ff_set = True


cdef int _x_coordinates(CState *st, const LineWords *lw, const Block *b) noexcept nogil:
    """7. Zero offsets, rotation; ISO: the work offsets of G54 .. G59.3."""
    if b.zero != 0 and cp_zero(st, lw, b.zero) != 0:
        return R_ERR
    if b.coord != 0 and ngc_select(st, b.coord, g_column(lw, 53.0 + b.coord if b.coord <= 6
                                                         else 59.0 + (b.coord - 6) / 10.0)) != 0:
        return R_ERR
    if b.rotation == 168:
        return cp_g168(st, lw)
    if b.rotation == 169:
        st.rot_on = False
        st.rot_idx = 0
        cp_reframe(st)
    return 0


cdef int _x_path(CState *st, const LineWords *lw, const Block *b) noexcept nogil:
    """8. Automatic arcs, the compensation strategy."""
    if b.g167 and cp_g167(st, lw) != 0:
        return R_ERR
    if b.strategy != 0:
        if not program_add_strategy_region(st.build, st.prog.n_parts, b.strategy == 172,
                                           val(lw, b'R') if has(lw, b'R') else 0.0,
                                           val(lw, b'C') if has(lw, b'C') else 0.0,
                                           has(lw, b'D') and val(lw, b'D') != 0.0):
            return err_out_of_memory(st.err, st.unit.file_idx, st.line)
    return 0


cdef int _x_shift(CState *st, const LineWords *lw, const Block *b) noexcept nogil:
    """10. G92 / G98: the current point gets new coordinates; ISO: G92.1 / G92.2 / G92.3,
    G10 L2 / L20, G28.1 / G30.1 (storing the position)."""
    if b.shift != 0:
        if cp_g92(st, lw) != 0:
            return R_ERR
        if st.ngc != NULL:
            ngc_store_shift(st)
    if b.shift_reset != 0 and ngc_shift_reset(st, b.shift_reset) != 0:
        return R_ERR
    if b.g10 and ngc_g10(st, lw, g_column(lw, 10.0)) != 0:
        return R_ERR
    if b.home == 281 or b.home == 282:
        ngc_home(st, lw, b.home, 1)
    return 0


cdef bint _is_cycle(int motion) noexcept nogil:
    """Whether a motion is a canned cycle (G73, G74, G81..G89)."""
    return motion == 73 or motion == 74 or (motion >= 81 and motion <= 89)


cdef int _ngc_ijk_unused(CState *st, const LineWords *lw, const Block *b, int motion) noexcept nogil:
    """ISO mode: I J K that no function of the line uses, which LinuxCNC refuses: on a
    line without an arc (`G0 X1 I2`), or the plane's normal on an arc (K in G17, I in G19,
    J in G18). Warning 621 (they are ignored), error 414 in the strict ISO mode."""
    cdef uint32_t unused = 0
    cdef int bit
    cdef char why[120]
    if b.rotation == 168 or b.g10:
        return 0
    if motion == 2 or motion == 3:
        unused = bit_of(b'K') if st.plane == 17 else (bit_of(b'I') if st.plane == 19 else bit_of(b'J'))
    elif motion == 5 or motion == 51:
        unused = bit_of(b'K')
    elif motion == 33:
        unused = bit_of(b'I') | bit_of(b'J')
    else:
        unused = bit_of(b'I') | bit_of(b'J') | bit_of(b'K')
    unused &= lw.mask & ~b.consumed
    if unused == 0:
        return 0
    bit = SF_CTZ(unused)
    if motion == 2 or motion == 3:
        c_snprintf(why, sizeof(why), "%c on an arc in the %s plane", <char>(65 + bit),
                   "XY" if st.plane == 17 else ("YZ" if st.plane == 19 else "ZX"))
    else:
        c_snprintf(why, sizeof(why), "%c on a line without an arc (G%d)", <char>(65 + bit),
                   motion if motion >= 0 else 80)
    return ngc_refused(st, word_at_column(st, lw.col[bit]), lw.col[bit], why, "ignores it")


cdef int _x_parts(CState *st, LineWords *lw, const Block *b) noexcept nogil:
    """11. Continuous M functions, then the dwell or the motion of the line."""
    cdef int i, m, motion = b.motion, r
    cdef uint32_t axes = axes_mask(), saved, moving
    for i in range(lw.nm):
        m = to_int(lw.m[i])
        if m >= 1001 and em_mfunc(st, lw, m, True) != 0:
            return R_ERR
    if motion >= 0 and not _is_cycle(motion):
        st.motion_given = True
        if st.ngc != NULL:
            st.ngc.cycle_il_set = False     # a series of cycles ends (G98's level is taken anew)
        if st.ngc != NULL and st.ngc.nurbs_open and motion != 52 and motion != 53:
            return err_ngc_g(st.err, st.unit.file_idx, st.line, 5.1 if motion == 51 else <double>motion, b.motion_col, "a NURBS block (G5.2) is open: G5.3 ends it")
        st.motion = -1 if (motion == 80 or motion == 53) else motion
        if motion == 80:
            st.g80_line = st.line
    if b.dwell:
        if em_dwell(st, lw) != 0:
            return R_ERR
        if not st.iso:
            return 0                        # TG: the line dwells and does not move
        lw.mask &= ~bit_of(b'H')            # (G4's seconds are no address of the motion)
    if b.g900_col != 0:
        return 0
    moving = lw.mask & axes & ~b.consumed
    if st.iso:
        if b.home == 28 or b.home == 30:
            return ngc_home(st, lw, b.home, g_column(lw, b.home))
        if motion < 0:
            motion = st.motion              # modal, whatever G90 / G91 the line has
        if (lw.has_polar_r or lw.has_polar_a) and not (_is_cycle(motion) and not st.absolute):
            if ngc_polar(st, lw) != 0:      # (a G91 cycle turns by ^ and grows by @ each repeat)
                return R_ERR
            moving = lw.mask & axes & ~b.consumed
        if _is_cycle(motion):
            if b.motion < 0 and moving == 0 and not (lw.has_polar_r or lw.has_polar_a):
                return 0                    # a line of the cycle without a position
            if moving == 0 and not (lw.has_polar_r or lw.has_polar_a):
                return err_ngc_g(st.err, st.unit.file_idx, st.line, motion, g_column(lw, motion), "the cycle has no axis words")
            return ngc_cycle(st, lw, motion, g_column(lw, motion))
        if motion < 0:
            if moving == 0:
                return 0
            return cp_no_motion_mode(st, lw, moving)
        if motion == 5 or motion == 51 or motion == 52 or motion == 53:
            if lw.mask & (bit_of(b'I') | bit_of(b'J') | bit_of(b'K')) and _ngc_ijk_unused(st, lw, b, motion) != 0:
                return R_ERR
            return ngc_spline(st, lw, b, motion, b.motion_col if b.motion >= 0 else axis_column(lw, moving))
        if lw.mask & (bit_of(b'I') | bit_of(b'J') | bit_of(b'K')) and _ngc_ijk_unused(st, lw, b, motion) != 0:
            return R_ERR
        if b.machine and moving:
            return ngc_machine_move(st, lw, motion)
        if motion == 38:
            return ngc_probe(st, lw)
    elif motion < 0:
        # TG: G90 / G91 with axis words move like G1
        motion = 1 if (b.distance != 0 and moving) else st.motion
    saved = lw.mask
    # words a G/M function of this line used are not axis moves (G168 also takes I J K R)
    lw.mask &= ~(b.consumed & axes)
    if b.rotation == 168:
        lw.mask &= ~(bit_of(b'I') | bit_of(b'J') | bit_of(b'K') | bit_of(b'R'))
    r = em_motion(st, lw, motion, 0)
    lw.mask = saved
    return r


cdef void _limits_off(CState *st, const LineWords *lw) noexcept nogil:
    """M-5: per written axis, 0 switches its limits off, anything else on again."""
    cdef int k
    for k in range(AXES):
        if has(lw, letter_of_axis(k)):
            if val(lw, letter_of_axis(k)) == 0.0:
                st.limits_off |= 1u << k
            else:
                st.limits_off &= ~(1u << k)


cdef int _g_index(CState *st, const LineWords *lw) noexcept nogil:
    """M-6: A stores the index the next part gets in the PLC memory, S restarts it."""
    cdef int addr
    cdef int32_t iv
    if has(lw, b'A'):
        addr = ex_plc_addr(st, val(lw, b'A'), 4)
        if addr < 0:
            return R_ERR
        iv = st.gindex
        memcpy(st.inp.plc + addr, &iv, 4)
    if has(lw, b'S'):
        st.gindex = to_int(val(lw, b'S'))
        if st.gindex > 0x40000000:          # leave room: the index is an int32
            st.gindex = 0x40000000
        elif st.gindex < -0x40000000:
            st.gindex = -0x40000000
        st.gindex += st.gindex & 1
        st.gindex_set = True                # the next part starts the count again
    return 0


cdef int _mirror_of(const GCODE_PARAMETERS *pr, int m) noexcept nogil:
    """The mirrored axes (bit 0 X, 1 Y, 2 Z) M m sets, -1: m mirrors nothing."""
    if _is_m(pr, m, pr.M80_mirrorOff): return 0
    if _is_m(pr, m, pr.M81_mirrorX): return 1
    if _is_m(pr, m, pr.M82_mirrorY): return 2
    if _is_m(pr, m, pr.M83_mirrorZ): return 4
    if _is_m(pr, m, pr.M84_mirrorXY): return 3
    if _is_m(pr, m, pr.M85_mirrorXZ): return 5
    if _is_m(pr, m, pr.M86_mirrorYZ): return 6
    if _is_m(pr, m, pr.M87_mirrorXYZ): return 7
    return -1


cdef bint _is_stop(const GCODE_PARAMETERS *pr, int m) noexcept nogil:
    """M0 M1 M60 and the program ends: LinuxCNC runs them after the motion of their line."""
    return m == 0 or m == 1 or m == 60 or _is_m(pr, m, pr.M02_programEnd1) or _is_m(pr, m, pr.M30_programEnd2)


cdef void _ngc_m_state(CState *st, int m) noexcept nogil:
    """ISO mode: the spindle and coolant state LinuxCNC's cycles and parameters read."""
    cdef const GCODE_PARAMETERS *pr = &st.params
    if _is_m(pr, m, pr.M03_startSpindleCW): st.ngc.spindle = 3
    elif _is_m(pr, m, pr.M04_startSpindleCCW): st.ngc.spindle = 4
    elif _is_m(pr, m, pr.M05_stopSpindle): st.ngc.spindle = 0
    elif _is_m(pr, m, pr.M07_coolOn): st.ngc.mist = True
    elif _is_m(pr, m, pr.M08_oilOn): st.ngc.flood = True
    elif _is_m(pr, m, pr.M09_coolOilOff):
        st.ngc.mist = False
        st.ngc.flood = False


cdef int _x_m_functions(CState *st, const LineWords *lw, int which, bint *ret, bint *end) noexcept nogil:
    """12. The M functions below 1001, in the order written; which: M_ALL, or in the ISO
    mode M_BEFORE (all but the stops, before the motion) / M_STOPS (after it). ret: M17
    was among them, end: M2 / M30."""
    cdef const GCODE_PARAMETERS *pr = &st.params
    cdef int i, m, mirror
    for i in range(lw.nm):
        m = to_int(lw.m[i])
        if m >= 1001 or (which == M_BEFORE and _is_stop(pr, m)) or (which == M_STOPS and not _is_stop(pr, m)):
            continue
        if st.ngc != NULL:
            _ngc_m_state(st, m)
        mirror = _mirror_of(pr, m)
        if m == -5:
            _limits_off(st, lw)
            if not cp_plan_region(st):
                return err_out_of_memory(st.err, st.unit.file_idx, st.line)
        elif m == -6:
            if _g_index(st, lw) != 0:
                return R_ERR
        elif _is_m(pr, m, pr.M29_print):
            if em_print(st, lw, m, lw.text, lw.text_len) != 0:
                return R_ERR
        elif _is_m(pr, m, pr.M17_return):
            ret[0] = True
        elif mirror >= 0:
            st.mirror = mirror
            cp_reframe(st)
        elif _is_m(pr, m, pr.M99_defFeed):
            if has(lw, b'F'):
                st.def_feed = val(lw, b'F')
        else:
            if em_mfunc(st, lw, m, False) != 0:
                return R_ERR
            if _is_m(pr, m, pr.M02_programEnd1) or _is_m(pr, m, pr.M30_programEnd2):
                end[0] = True
    return 0


cdef int _x_flow(CState *st, const LineWords *lw, const Block *b, bint ret) noexcept nogil:
    """13. G25 / G26 (H times) / G27 to an N number or a label; M17 return."""
    cdef int64_t times = 1
    if b.jump != 0:
        if b.jump == 26 and has(lw, b'H'):
            times = to_int(val(lw, b'H'))
        if lw.label != NULL:
            return fl_call(st, lw.label, lw.label_len, 0, False, b.jump != 27, times)
        if has(lw, b'L'):
            return fl_call(st, NULL, 0, val(lw, b'L'), True, b.jump != 27, times)
        return err_missing_value(st.err, st.unit.file_idx, st.line, "L", b.jump_col)
    if ret:
        return fl_return(st)
    return R_NEXT


cdef int _x_settings(CState *st, const LineWords *lw, const Block *b) noexcept nogil:
    """4. .. 10. Plane, units, compensation, coordinates, path, distance mode, shift."""
    if b.plane != 0:
        st.plane = b.plane
    if b.units == 21:
        st.iso_header = True
    if (b.comp != 0 or b.length != 0 or lw.has_amp or has(lw, b'D')) and tl_select(st, lw, b) != 0:
        return R_ERR
    if (b.zero != 0 or b.rotation != 0 or b.coord != 0) and _x_coordinates(st, lw, b) != 0:
        return R_ERR
    if (b.g167 or b.strategy != 0) and _x_path(st, lw, b) != 0:
        return R_ERR
    if b.distance != 0:
        st.absolute = b.distance == 90
        st.iso_header = st.iso_header or (b.distance == 90 and st.prog.n_parts == 0)
    if b.ijk != 0:
        st.ngc.ijk_absolute = b.ijk == 901
    if b.retract != 0:
        st.ngc.retract = b.retract
    if (b.shift != 0 or b.shift_reset != 0 or b.g10 or b.home > 100) and _x_shift(st, lw, b) != 0:
        return R_ERR
    return 0


cdef int cp_block(CState *st, LineWords *lw) noexcept nogil:
    """Executes the words of one line: read into groups, the groups in the order above
    (a group not on the line costs a test: most lines are a move and its words, and
    set none of the groups 1, 2, 4 .. 10)."""
    cdef Block b
    cdef bint ret = False, end = False
    if cp_read_block(st, lw, &b) != 0:
        return R_ERR
    if b.settings:
        if b.g900_col != 0 and _x_parameters(st, lw, &b) != 0:
            return R_ERR
        _x_feed_mode(st, &b)
    _x_values(st, lw, &b)
    if (b.settings or lw.has_amp or has(lw, b'D')) and _x_settings(st, lw, &b) != 0:
        return R_ERR
    if not st.iso:
        if lw.first_is_o or b.zero != 0 or st.plane == 18 or b.dwell or b.motion < 0:
            cp_dialect_warnings(st, lw, &b)
    elif lw.nm > 0 and _x_m_functions(st, lw, M_BEFORE, &ret, &end) != 0:
        return R_ERR
    if _x_parts(st, lw, &b) != 0:
        return R_ERR
    if lw.nm > 0 and _x_m_functions(st, lw, M_STOPS if st.iso else M_ALL, &ret, &end) != 0:
        return R_ERR
    if b.shift == 92 and (lw.tool_values != 0 or has(lw, b'D')) and tl_write(st, lw) != 0:
        return R_ERR
    if end:
        return R_END
    if b.jump == 0 and not ret:
        return R_NEXT
    return _x_flow(st, lw, &b, ret)
