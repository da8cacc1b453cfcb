# Programs written for other dialects (docs/compiler.md, "Programs written for other
# dialects"): what TG expects instead of an ISO G function, the warnings where a line
# looks written for ISO G-code, and how the ISO compatibility mode reads a line.


cdef const char *iso_g_hint(double gv) noexcept nogil:
    """What TG expects instead of an ISO G function it does not have; NULL: no ISO meaning."""
    if gv == 20.0:
        return "TG works in millimetres (isoCompat reads G20 as inches)"
    if gv == 28.0 or gv == 30.0:
        return "returns to a home position do not exist in TG (G98 is TG's reference run)"
    if gv == 49.0 or gv == 43.1:
        return "TG has no tool length offsets (isoCompat ignores G43 H and G49)"
    if gv == 61.0 or gv == 61.1 or gv == 64.0:
        return "path blending is set by GCODE_PARAMETERS (isoCompat ignores G61 and G64)"
    if gv == 80.0:
        return "TG has no canned cycles (isoCompat ignores G80)"
    if gv == 73.0 or gv == 76.0 or (gv >= 81.0 and gv <= 89.0 and gv == <double>(<int>gv)):
        return "TG has no canned drilling cycles: write the moves (G0 / G1)"
    if gv == 90.1:
        return "TG's arc centres are relative; Q70 on the arc's line makes I J K absolute"
    if gv == 91.1:
        return "TG's arc centres are relative already (isoCompat ignores G91.1)"
    if gv == 92.1 or gv == 92.2:
        return "TG resets a G92 shift with G92 and the axes (isoCompat: G92.1 clears the shift)"
    if gv == 10.0:
        return "TG sets zero offsets with G54..G59 and the axes"
    if gv >= 38.2 and gv <= 38.5:
        return "TG has no probing moves"
    if gv == 93.0:
        return "TG has no inverse time feed (G94 mm/min, G95 mm/rev)"
    return NULL


cdef int cp_unknown_g(CState *st, double gv, int col) noexcept nogil:
    cdef const char *hint = iso_g_hint(gv)
    cdef ErrArg a[3]
    if hint == NULL:
        return cerr_num_at(st, ERR_BAD_G, gv, col)
    a[0].num = gv; a[0].text = NULL
    a[1].num = col; a[1].text = NULL
    a[2].num = 0; a[2].text = hint
    set_error(st.err, ERR_ISO_G, st.unit.file_idx, st.line, a, 3)
    return R_ERR


cdef const char *word_at_column(CState *st, int col) noexcept nogil:
    """The source word at column col of the current line, for messages."""
    return cword_at(st, st.unit.text + st.cur_pos + col - 1, st.unit.text + st.next_pos - 1)


cdef void iso_units(CState *st, LineWords *lw) noexcept nogil:
    """ISO mode: G20 / G21 of the line switch inches / millimetres; in inches the
    lengths of the line (X Y Z U V W, I J K, R, F, FF) are converted to mm. Not on G4
    (times), G900 (parameters), nor G168's R (degrees)."""
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
        if lw.g[i] == 4.0 or lw.g[i] == 900.0:
            return
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


cdef int iso_read_g(CState *st, const LineWords *lw, int i, Block *b) noexcept nogil:
    """ISO mode: G function i of the line read as ISO G-code into the block. 1 done,
    0 TG's meaning, R_ERR (error recorded)."""
    cdef double gv = lw.g[i]
    cdef int col = lw.gcol[i]
    if gv == 20.0 or gv == 21.0 or gv == 91.1:
        return 1                    # units: iso_units; relative centres: TG's own
    if gv == 18.0:
        b.plane = -18               # ISO's G18 is the ZX plane
        return 1
    if gv == 43.0 or gv == 44.0 or gv == 49.0 or gv == 61.0 or gv == 61.1 or gv == 64.0 or gv == 80.0:
        cwarn_at(st, WARN_ISO_IGNORED, word_at_column(st, col), col)
        return 1
    if gv == 92.1:
        b.clear_shift = True
        return 1
    if gv == 53.0 or (gv >= 54.0 and gv <= 59.0 and gv == <double>(<int>gv)):
        return 1                    # no table of offsets: the offset stays and the axes move
    return 0


cdef int cp_pword(CState *st, LineWords *lw, bint dwell) noexcept nogil:
    """A P word without '=': in ISO mode dwell seconds (given to the part as H), G64's
    tolerance, or an M function's argument ignored with a warning; else an error that
    says what TG expects."""
    cdef int i
    cdef const char *hint
    cdef const char *word
    if st.iso:
        if dwell:
            if not (lw.mask & (bit_of(b'W') | bit_of(b'H') | bit_of(b'X') | bit_of(b'T'))):
                lw.v[7] = lw.pword          # TG's H seconds: the driver sees a G4 it knows
                lw.mask |= bit_of(b'H')
                lw.col[7] = lw.col[15]
            return 0
        for i in range(lw.ng):
            if lw.g[i] == 64.0:
                return 0            # ignored with its G64 (warned)
        if lw.nm > 0:
            word = cword(st, lw.pword_at, lw.pword_at + lw.pword_len, lw.pword_len)
            cwarn_at(st, WARN_ISO_IGNORED, word, lw.col[15])
            return 0
    if dwell:
        hint = "G4 takes W (milliseconds), H, X or T (seconds)"
    elif lw.nm > 0:
        hint = "M functions take no P word (isoCompat ignores it)"
    else:
        hint = "a P word without '=' is ISO G-code (isoCompat reads G4 P and G64 P)"
    word = cword(st, lw.pword_at, lw.pword_at + lw.pword_len, lw.pword_len)
    return cerr_hint(st, ERR_P_WORD, word, lw.col[15], hint)


cdef void cp_dialect_warnings(CState *st, const LineWords *lw, const Block *b) noexcept nogil:
    """Default mode: warnings where the line looks written for ISO G-code and TG reads
    it otherwise (docs/compiler.md)."""
    cdef int arc = b.motion if b.motion >= 0 else st.motion
    cdef int col
    cdef ErrArg a[2]
    if lw.first_is_o and st.prog.n_parts == 0:
        a[0].num = val(lw, b'O'); a[0].text = NULL
        a[1].num = lw.col[14]; a[1].text = NULL
        cwarn(st, WARN_O_AT_START, a, 2)
    if b.zero != 0 and b.zero != 53 and b.motion >= 0 and (lw.mask & axes_mask()):
        a[0].num = b.zero; a[0].text = NULL
        a[1].num = b.zero_col; a[1].text = NULL
        cwarn(st, WARN_ZERO_WITH_MOVE, a, 2)
    if st.plane == 18 and (arc == 2 or arc == 3) and (has(lw, b'I') or has(lw, b'K')) \
            and st.iso_header and not st.warned_g18:
        st.warned_g18 = True
        col = lw.col[8] if has(lw, b'I') else lw.col[10]
        a[0].num = col; a[0].text = NULL
        cwarn(st, WARN_G18_ARC, a, 1)
