# Programs written for other dialects (docs/compiler.md, "Programs written for other
# dialects"): what TG expects instead of an ISO G function, the warnings where a line
# looks written for ISO G-code, and how the ISO compatibility mode reads a line.
from libc.math cimport floor


cdef const char *iso_g_hint(double gv) noexcept nogil:
    """What TG expects instead of an ISO G function it does not have (and what the ISO
    mode reads it as); NULL: no ISO meaning."""
    if gv == 20.0:
        return "TG works in millimetres (the ISO mode reads G20 as inches)"
    if gv == 28.0 or gv == 30.0:
        return "returns to a home position do not exist in TG (G98 is TG's reference run; the ISO mode reads G28 / G30)"
    if gv == 49.0 or gv == 43.1:
        return "TG's tool length corrections are & n of the tool table, & 0 cancels them (the ISO mode reads G43 H n and G49)"
    if gv == 61.0 or gv == 61.1 or gv == 64.0:
        return "path blending is set by GCODE_PARAMETERS (the ISO mode ignores G61 and G64)"
    if gv == 80.0:
        return "TG has no canned cycles (the ISO mode reads G80 and the cycles)"
    if gv == 73.0 or (gv >= 81.0 and gv <= 89.0 and gv == <double>(<int>gv) and gv != 87.0 and gv != 88.0):
        return "TG has no canned drilling cycles: write the moves (G0 / G1), or the ISO mode expands them"
    if gv == 90.1:
        return "TG's arc centres are relative; Q70 on the arc's line makes I J K absolute (the ISO mode reads G90.1)"
    if gv == 91.1:
        return "TG's arc centres are relative already (the ISO mode reads G91.1)"
    if gv == 92.1 or gv == 92.2:
        return "TG resets a G92 shift with G92 and the axes (the ISO mode reads G92.1 / G92.2)"
    if gv == 10.0:
        return "TG sets zero offsets with G54..G59 and the axes (the ISO mode reads G10 L2 / L20)"
    if gv >= 38.2 and gv <= 38.5:
        return "TG has no probing moves (the ISO mode moves to the point)"
    if gv == 5.0 or gv == 5.1 or gv == 5.2 or gv == 5.3:
        return "TG has no splines: write arcs and lines (the ISO mode reads G5, G5.1 and G5.2 / G5.3)"
    if gv == 93.0:
        return "TG has no inverse time feed: G94 mm/min, G95 mm/rev (the ISO mode reads G93)"
    return NULL


cdef int cp_unknown_g(CState *st, double gv, int col) noexcept nogil:
    """A G function TG does not have: where ISO has it, the error says what TG expects instead;
    else the plain unknown-G error."""
    cdef const char *hint = iso_g_hint(gv)
    if hint == NULL:
        return err_bad_g(st.err, st.unit.file_idx, st.line, gv, col)
    return err_iso_g(st.err, st.unit.file_idx, st.line, gv, col, hint)


cdef const char *word_at_column(CState *st, int col) noexcept nogil:
    """The source word at column col of the current line, for messages."""
    return cword_at(st, st.unit.text + st.cur_pos + col - 1, st.unit.text + st.next_pos - 1)


cdef void iso_units(CState *st, LineWords *lw) noexcept nogil:
    """ISO mode: G20 / G21 of the line switch inches / millimetres; in inches the
    lengths of the line (X Y Z U V W, I J K, R, F, FF) are converted to mm. Not on G4
    lines without P (times), G900 (parameters), nor G168's R (degrees); a cycle's Q
    is converted by the cycle."""
    cdef int i, bit
    cdef bint rotation = False
    cdef uint32_t letters, bits
    for i in range(lw.ng):
        if lw.g[i] == 20.0:
            st.unit_scale = 25.4
        elif lw.g[i] == 21.0:
            st.unit_scale = 1.0
    if st.unit_scale == 1.0:
        return
    for i in range(lw.ng):
        if (lw.g[i] == 4.0 and not lw.has_pword) or lw.g[i] == 900.0:
            return              # times (G4 W H X T) and parameters; with P, X of G4 lines is an axis
        if lw.g[i] == 168.0:
            rotation = True
    letters = (bit_of(b'X') | bit_of(b'Y') | bit_of(b'Z') | bit_of(b'U') | bit_of(b'V') | bit_of(b'W')
               | bit_of(b'I') | bit_of(b'J') | bit_of(b'K') | bit_of(b'F'))
    if not rotation:
        letters |= bit_of(b'R')
    bits = lw.mask & letters
    while bits:
        bit = SF_CTZ(bits)
        bits &= bits - 1
        lw.v[bit] *= st.unit_scale
    if lw.has_ff:
        lw.ff *= st.unit_scale
    if lw.has_polar_r:
        lw.polar_r *= st.unit_scale


cdef const char *ngc_unsupported(double gv) noexcept nogil:
    """LinuxCNC G functions the ISO mode does not read: why; NULL for the others."""
    if gv == 33.1 or gv == 76.0: return "spindle-synchronised tapping and threading cycles"
    if gv == 87.0 or gv == 88.0: return "LinuxCNC leaves the cycles G87 and G88 undefined"
    if gv == 7.0 or gv == 8.0: return "lathe diameter and radius modes"
    if gv == 41.1 or gv == 42.1: return "cutter compensation with a diameter from the program"
    if gv == 43.1 or gv == 43.2: return "tool length offsets from the program"
    if gv == 52.0: return "local coordinate systems (G52)"
    if gv == 70.0 or gv == 71.0 or gv == 72.0 or gv == 71.1 or gv == 71.2 or gv == 72.1 or gv == 72.2:
        return "lathe cycles"
    if gv == 17.1 or gv == 18.1 or gv == 19.1: return "the U V W planes"
    return NULL


cdef int _iso_second_motion(CState *st, Block *b, int g, int col) noexcept nogil:
    """cp_set_motion's ISO rule for a second motion word g of the line: 1 when G80 leaves
    the first one, 0 when g replaces it (with warning 621 unless the first was G80),
    R_ERR (error 414, strict)."""
    cdef char why[160]
    if g == 80:
        return 1
    if b.motion != 80:
        c_snprintf(why, sizeof(why), "a second motion word on the line after G%d "
                   "(two G words of one modal group)", b.motion)
        if ngc_refused(st, word_at_column(st, col), col, why, "runs the later one") != 0:
            return R_ERR
    return 0


cdef inline int cp_set_motion(CState *st, Block *b, int g, int col) noexcept nogil:
    """A motion word (group 1) of the line into the block. TG: the later one counts. ISO
    mode, LinuxCNC's rule: G80 never replaces another motion word of the line, and
    another replaces a G80 (`G0 G90 G80` and `G80 G0` both leave G0); two motion words
    other than G80 LinuxCNC refuses: warning 621 (the later counts), error 414 strict."""
    cdef int r
    if st.iso and b.motion >= 0:
        r = _iso_second_motion(st, b, g, col)
        if r != 0:
            return R_ERR if r < 0 else 0
    b.motion = g
    b.motion_col = col
    return 0


cdef int cp_no_motion_mode(CState *st, const LineWords *lw, uint32_t moving) noexcept nogil:
    """ISO mode: error 411 for axis words without a motion mode, naming the line whose
    G80 cancelled it, or that none was set."""
    cdef char why[96]
    cdef int col = axis_column(lw, moving)
    if st.g80_line > 0:
        c_snprintf(why, sizeof(why), "G80 on line %u cancelled it", st.g80_line)
    else:
        c_snprintf(why, sizeof(why), "none was set since the program start")
    return err_no_motion_mode(st.err, st.unit.file_idx, st.line, word_at_column(st, col), col, why)


cdef int iso_read_g(CState *st, const LineWords *lw, int i, Block *b) noexcept nogil:
    """ISO mode: G function i of the line read as LinuxCNC reads it into the block. 1
    done, 0 TG's meaning, R_ERR (error recorded)."""
    cdef double gv = lw.g[i]
    cdef int col = lw.gcol[i], g = to_int(gv)
    cdef const char *why = ngc_unsupported(gv)
    if why != NULL:
        return err_ngc_unsupported(st.err, st.unit.file_idx, st.line, word_at_column(st, col), col, why)
    if gv == 20.0 or gv == 21.0:
        return 1                    # iso_units
    if gv == 90.1 or gv == 91.1:
        b.ijk = 901 if gv == 90.1 else 911
    elif gv == 18.0:
        b.plane = -18               # ISO's G18 is the ZX plane
    elif gv == 4.0:
        b.dwell = True              # P seconds: the axis words of the line still move
        b.ngc_p = True
        if not lw.has_pword:
            b.consumed |= bit_of(b'W') | bit_of(b'H') | bit_of(b'X') | bit_of(b'T')
    elif gv == 43.0 or gv == 49.0:
        b.length = g                # tools.pyx: G43 H n is & n, G49 is & 0
        b.consumed |= bit_of(b'H')
    elif gv == 44.0 or gv == 61.0 or gv == 61.1 or gv == 64.0:
        if warning_wanted(st):
            warn_iso_ignored(&st.warning, st.unit.file_idx, st.line, word_at_column(st, col), col)
            cwarn(st)
        b.ngc_p = b.ngc_p or gv == 64.0
    elif gv == 80.0 or gv == 73.0 or gv == 74.0 or (gv >= 81.0 and gv <= 86.0 and gv == <double>g) or gv == 89.0:
        if cp_set_motion(st, b, g, col) != 0:
            return R_ERR
        b.ngc_p = True
    elif gv == 92.1 or gv == 92.2 or gv == 92.3:
        b.shift_reset = 1 if gv == 92.1 else (2 if gv == 92.2 else 3)
    elif gv == 53.0:
        b.machine = True
    elif (gv >= 54.0 and gv <= 59.0 and gv == <double>g) or gv == 59.1 or gv == 59.2 or gv == 59.3:
        b.coord = g - 53 if gv == <double>g else 6 + to_int(floor(gv * 10.0 + 0.5)) - 590
    elif gv == 28.0 or gv == 30.0:
        b.home = g
        b.consumed |= axes_mask()   # (the axes of the line go home, not the modal motion)
    elif gv == 28.1 or gv == 30.1:
        b.home = 281 if gv == 28.1 else 282
    elif gv == 10.0:
        b.g10 = True
        b.ngc_p = True
        b.consumed |= axes_mask() | bit_of(b'L') | bit_of(b'R')
    elif gv == 98.0 or gv == 99.0:
        b.retract = g
    elif gv == 93.0:
        b.feed_mode = 93
    elif gv == 5.0 or gv == 5.1 or gv == 5.2 or gv == 5.3:
        if cp_set_motion(st, b, 5 if gv == 5.0 else to_int(floor(gv * 10.0 + 0.5)), col) != 0:
            return R_ERR                # ngc_spline.pyx: 5 51 52 53
        b.ngc_p = True                  # P: G5's second control point, G5.2's weight
        b.consumed |= bit_of(b'I') | bit_of(b'J') | bit_of(b'Q') | bit_of(b'L')
    elif gv == 38.2 or gv == 38.3 or gv == 38.4 or gv == 38.5:
        if cp_set_motion(st, b, 38, col) != 0:  # a probing move: to the programmed point (nothing to touch)
            return R_ERR
    else:
        return 0
    return 1


cdef bint _cycle_runs(CState *st, const LineWords *lw, const Block *b) noexcept nogil:
    """ISO mode: a canned cycle runs on this line (written, or modal with axis words)."""
    cdef int m = b.motion if b.motion >= 0 else st.motion
    return (m == 73 or m == 74 or (m >= 81 and m <= 89)) and (b.motion >= 0 or (lw.mask & axes_mask()))


cdef int cp_pword(CState *st, LineWords *lw, const Block *b) noexcept nogil:
    """A P word without '=': in ISO mode dwell seconds (given to the part as H), a cycle's
    dwell, G10's coordinate system, G64's tolerance (ignored), an M function's argument
    (ignored with a warning); else an error that says what TG expects."""
    cdef const char *hint
    cdef const char *word
    cdef int arc
    if st.iso:
        if b.dwell:
            # (X is an axis on a G4 P line: it may move after the dwell)
            if not (lw.mask & (bit_of(b'W') | bit_of(b'H') | bit_of(b'T'))):
                lw.v[7] = lw.pword          # TG's H seconds: the driver sees a G4 it knows
                lw.mask |= bit_of(b'H')
                lw.col[7] = lw.col[15]
            return 0
        if b.ngc_p or _cycle_runs(st, lw, b) or (b.motion < 0 and st.motion == 52):
            return 0                        # (a line of a NURBS block: P is its weight)
        arc = b.motion if b.motion >= 0 else st.motion
        if (arc == 2 or arc == 3) and lw.pword != 1.0:
            word = cword(st, lw.pword_at, lw.pword_at + lw.pword_len, lw.pword_len)
            return err_ngc_unsupported(st.err, st.unit.file_idx, st.line, word, lw.col[15], "arcs of more than one turn")
        if (arc == 2 or arc == 3) or lw.nm > 0:
            if lw.nm > 0:
                word = cword(st, lw.pword_at, lw.pword_at + lw.pword_len, lw.pword_len)
                if warning_wanted(st):
                    warn_iso_ignored(&st.warning, st.unit.file_idx, st.line, word, lw.col[15])
                    cwarn(st)
            return 0
    if b.dwell:
        hint = ("G4 takes W (milliseconds), H, X or T (seconds); the ISO mode reads G4 P as seconds: "
                "sf-tch compile --iso, sf_tch.compile(..., iso=True), "
                "GCODE_PARAMETERS.rezerva1 bit 0")
    elif lw.nm > 0:
        hint = ("M functions take no P word (the ISO mode ignores it: sf-tch compile --iso, "
                "sf_tch.compile(..., iso=True), GCODE_PARAMETERS.rezerva1 bit 0)")
    else:
        hint = ("a P word without '=' is ISO G-code (the ISO mode reads G4 P and G64 P: sf-tch compile "
                "--iso, sf_tch.compile(..., iso=True), GCODE_PARAMETERS.rezerva1 bit 0)")
    word = cword(st, lw.pword_at, lw.pword_at + lw.pword_len, lw.pword_len)
    return err_p_word(st.err, st.unit.file_idx, st.line, word, lw.col[15], hint)


cdef void cp_dialect_warnings(CState *st, const LineWords *lw, const Block *b) noexcept nogil:
    """Default mode: warnings where the line looks written for ISO G-code and TG reads
    it otherwise (docs/compiler.md). cp_block calls it for the lines that may need one:
    an O first, a zero offset, plane G18, a dwell, or no motion G."""
    cdef int arc = b.motion if b.motion >= 0 else st.motion
    cdef int col
    cdef uint32_t moving = lw.mask & axes_mask() & ~b.consumed
    if lw.first_is_o and st.prog.n_parts == 0:
        moving &= ~bit_of(b'O')         # warning 611 below says it
        if warning_wanted(st):
            warn_o_at_start(&st.warning, st.unit.file_idx, st.line, val(lw, b'O'), lw.col[14])
            cwarn(st)
    if b.zero != 0 and b.zero != 53 and b.motion >= 0 and (lw.mask & axes_mask()) and warning_wanted(st):
        warn_zero_with_move(&st.warning, st.unit.file_idx, st.line, b.zero, b.zero_col)
        cwarn(st)
    if st.plane == 18 and (arc == 2 or arc == 3) and (has(lw, b'I') or has(lw, b'K')) \
            and st.iso_header and not st.warned_g18:
        st.warned_g18 = True
        col = lw.col[8] if has(lw, b'I') else lw.col[10]
        if warning_wanted(st):
            warn_g18_arc(&st.warning, st.unit.file_idx, st.line, col)
            cwarn(st)
    if b.dwell and b.motion >= 0 and b.motion <= 3 and warning_wanted(st):
        warn_dwell_with_motion(&st.warning, st.unit.file_idx, st.line, g_column(lw, 4.0), b.motion)
        cwarn(st)
    if b.distance != 0 and b.motion < 0 and moving and st.motion != 1 and not b.dwell and warning_wanted(st):
        warn_g90_moves_g1(&st.warning, st.unit.file_idx, st.line, b.distance, g_column(lw, b.distance), st.motion)
        cwarn(st)
    if b.motion < 0 and b.distance == 0 and moving and not b.dwell and b.g900_col == 0 \
            and not st.motion_given and not st.warned_bare_axes:
        st.warned_bare_axes = True
        if warning_wanted(st):
            warn_bare_axes(&st.warning, st.unit.file_idx, st.line, axis_column(lw, moving))
            cwarn(st)
