# The tool correction table in programs (docs/tool-table.md): D selects the entry
# whose radius G41 / G42 use, & the entry whose lengths of axes 1..4 (x y z c) are
# added to the positions, G92 D writes an entry. The compilation works on its own
# copy of the core's table (CState.tools, taken when it starts); its G92 D writes are
# kept in Program.tool_writes for the core's table. ISO mode: G43 H n is & n, G49 &0.
from libc.math cimport floor


cdef int tl_entry(CState *st, double v, int col, bint writable) noexcept nogil:
    """The entry a D, & or H word names: 0..99 (0: none), 1..99 when it is written;
    -1 with the error recorded."""
    if v == floor(v) and v >= (1.0 if writable else 0.0) and v <= <double>TOOL_ENTRIES:
        return <int>v
    return err_tool_word(st.err, st.unit.file_idx, st.line, word_at_column(st, col), col, "G92 D writes the entries 1..99" if writable
                     else "the table has the entries 1..99 (0: none)")


cdef int tl_comp(CState *st) noexcept nogil:
    """The compensation parts carry from G40 .. G48 in force (comp_g) and the D in
    force: the side (41 / 42 after the sign of the radius), the correction[] slot, the
    radius. D selects the radius of G41 / G42 only (G43 .. G48 name their slot)."""
    cdef int slot, side, idx
    cdef double radius
    st.radius_idx = 0
    if st.comp_g == 40:
        st.comp = 40
        st.comp_slot = 0
        st.comp_radius = 0.0
        return 0
    slot = st.comp_g - 41
    side = 41 if (slot & 1) == 0 else 42
    radius = st.params.correction[slot].size
    if slot < 2 and st.tool_d >= 0:
        radius = st.tools.entry[st.tool_d].value[0]     # (entry 0 is all zero)
        idx = program_add_radius(st.build, radius)
        if not registered(st, idx, "tool radii (D words under G41 / G42)"):
            return R_ERR
        st.radius_idx = idx
    if radius < 0.0:
        side = 83 - side
    st.comp = side
    st.comp_slot = slot
    st.comp_radius = radius
    if st.iso and radius == 0.0:
        st.comp = 40                # ISO: a radius of 0 compensates nothing (LinuxCNC's tool 0)
    return 0


cdef int tl_lengths(CState *st, int entry) noexcept nogil:
    """& entry: its lengths of axes 1..4 are added to every machine position from now
    on, like an offset: the machine stays where it is, its program coordinates change,
    and the next move to a programmed position goes to it plus the lengths."""
    cdef int k
    st.tool_len = entry
    for k in range(4):
        st.length[k] = st.tools.entry[entry].value[k + 1]
    cp_reframe(st)
    if not update_zero(st):
        return R_ERR
    return 0


cdef int tl_select(CState *st, const LineWords *lw, const Block *b) noexcept nogil:
    """The line's D (unless a function of the line takes it), &, G40 .. G48 and the
    ISO mode's G43 H / G49, before the parts of the line."""
    cdef int entry
    if has(lw, b'D') and not (b.consumed & bit_of(b'D')):
        entry = tl_entry(st, val(lw, b'D'), lw.col[3], False)
        if entry < 0:
            return R_ERR
        st.tool_d = entry
    if b.comp != 0:
        st.comp_g = b.comp
    if (b.comp != 0 or (has(lw, b'D') and not (b.consumed & bit_of(b'D')))) and tl_comp(st) != 0:
        return R_ERR
    if lw.has_amp:
        entry = tl_entry(st, lw.amp, lw.amp_col, False)
        if entry < 0 or tl_lengths(st, entry) != 0:
            return R_ERR
    if b.length == 49:
        return tl_lengths(st, 0)
    if b.length == 43:
        # LinuxCNC: G43 without H takes the tool in the spindle (T)
        entry = tl_entry(st, val(lw, b'H') if has(lw, b'H') else <double>st.tool,
                         lw.col[7] if has(lw, b'H') else g_column(lw, 43.0), False)
        if entry < 0 or tl_lengths(st, entry) != 0:
            return R_ERR
    return 0


cdef int tl_write(CState *st, const LineWords *lw) noexcept nogil:
    """G92 D n R0= .. R4=: the values written into entry n of the compilation's table
    (and kept for the core's), after the parts of the line: the radius and lengths in
    force follow from the next line on."""
    cdef ToolWrite w
    cdef int entry, k
    if not has(lw, b'D'):
        return err_tool_word(st.err, st.unit.file_idx, st.line, word_at_column(st, lw.tool_values_col), lw.tool_values_col, "G92 D n names the entry that R0 .. R4 write")
    entry = tl_entry(st, val(lw, b'D'), lw.col[3], True)
    if entry < 0:
        return R_ERR
    if lw.tool_values == 0:
        return 0
    w.entry = entry
    w.programmed = lw.tool_values
    for k in range(TOOL_VALUES):
        w.values[k] = lw.tool_value[k] if (lw.tool_values >> k) & 1 else 0.0
    if not tool_table_set(&st.tools, entry, w.programmed, w.values, st.err):
        st.err.file_idx = st.unit.file_idx      # (the table names no place)
        st.err.line = <int32_t>st.line
        return R_ERR
    if not program_add_tool_write(st.build, &w):
        return err_out_of_memory(st.err, st.unit.file_idx, st.line)
    if entry == st.tool_d and tl_comp(st) != 0:
        return R_ERR
    if entry == st.tool_len and tl_lengths(st, entry) != 0:
        return R_ERR
    return 0
