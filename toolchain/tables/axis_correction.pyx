# The axis correction tables (docs/axis-correction.md): each corrects one axis by a
# value interpolated from a regular grid over up to three basis axes, e.g. Z over X
# and Y for a machine bed that is not flat. A table is a binary ACHS3D??.KOR file,
# little-endian, read byte for byte:
#
#   bytes 0..127   the header: the axis letters, NUL-terminated, the corrected axis
#                  first, then the basis axes; the table's number in byte 127
#   12 per basis   the definition: FLOAT min, FLOAT max (mm), ULONG grid points
#   4 per point    FLOAT corrections (mm); the first at the minimum of every basis
#                  axis, the last at the maximum; the last basis axis varies fastest
#
# A file whose size, letters, ranges or values do not fit is refused with an error
# naming the file and the field; a set of tables is published whole or not at all.
# axis_correction_apply is pure: multilinear interpolation, the edge value outside.
from libc.stdlib cimport free
from libc.string cimport memcpy, memset
from libc.math cimport floor


cdef int _axis_of_letter(unsigned char c) noexcept nogil:
    """0..9 for the letters of x y z c b u v w a o (any case), else -1."""
    cdef const char *letters = "xyzcbuvwao"
    cdef int k
    c = c | 0x20 if b'A' <= c <= b'Z' else c
    for k in range(AXES):
        if letters[k] == c:
            return k
    return -1


cdef char _axis_letter(int axis) noexcept nogil:
    """The letter (upper case) of axis 0..9 in the library's order X Y Z C B U V W A O."""
    cdef const char *letters = "XYZCBUVWAO"
    return letters[axis]


cdef uint32_t _le_u32(const unsigned char *p) noexcept nogil:
    """A little-endian ULONG of the file at p (byte for byte: any host, any alignment)."""
    return <uint32_t>p[0] | (<uint32_t>p[1] << 8) | (<uint32_t>p[2] << 16) | (<uint32_t>p[3] << 24)


cdef double _le_float(const unsigned char *p) noexcept nogil:
    """A little-endian FLOAT of the file at p, as a double."""
    cdef uint32_t bits = _le_u32(p)
    cdef float value
    memcpy(&value, &bits, 4)
    return value


cdef bint _value_text(char *why, size_t size, const char *what, double value) noexcept nogil:
    """why: what is wrong with a number that must be finite and within +-1e6 mm;
    False when it is good."""
    if not isfinite(value):
        c_snprintf(why, size, "%s = %g is not a finite number", what, value)
        return True
    if not (-TC_MAX_LENGTH <= value <= TC_MAX_LENGTH):
        c_snprintf(why, size, "%s = %g is outside <-1e6, 1e6> mm", what, value)
        return True
    return False


cdef bint _axis_table_parse(const unsigned char *data, size_t length, const char *name, AxisTable *out,
                           ErrorInfo *err) noexcept nogil:
    """The table of the file bytes [data, data + length) into *out (its values
    malloc'ed, the caller frees them); False with err naming the file and the field
    (ERR_AXIS_TABLE_HEADER, _DEFINITION, _SIZE, _VALUE) and nothing allocated."""
    cdef AxisTable t
    cdef char why[256]
    cdef char field[64]
    cdef const unsigned char *p
    cdef int n_letters = 0, axis, b, k
    cdef uint64_t total = 1, i
    cdef double value, asked = 1.0
    memset(&t, 0, sizeof(AxisTable))
    if length < AXIS_TABLE_HEADER:
        c_snprintf(why, sizeof(why), "the file has %llu bytes, the header alone 128",
                   <unsigned long long>length)
        err_axis_table_header(err, -1, 0, name, why)
        return False
    while data[n_letters] != 0:             # ended by a NUL byte or an error by byte 4
        axis = _axis_of_letter(data[n_letters])
        if axis < 0:
            c_snprintf(why, sizeof(why), "byte %d (0x%02x) is no axis letter (X Y Z C B U V W A O)",
                       n_letters, data[n_letters])
            err_axis_table_header(err, -1, 0, name, why)
            return False
        if n_letters > AXIS_TABLE_BASES_MAX:
            err_axis_table_header(err, -1, 0, name, "more than four axis letters: one corrected axis and at most three basis axes")
            return False
        if n_letters == 0:
            t.axis = axis
        else:
            for b in range(n_letters - 1):
                if t.bases[b] == axis:
                    c_snprintf(why, sizeof(why), "basis axis %c is named twice", _axis_letter(axis))
                    err_axis_table_header(err, -1, 0, name, why)
                    return False
            t.bases[n_letters - 1] = axis
        n_letters += 1
    if n_letters < 2:
        err_axis_table_header(err, -1, 0, name, "no basis axis: the letters name the corrected axis, then one to three basis axes")
        return False
    t.n_bases = n_letters - 1
    t.number = data[AXIS_TABLE_HEADER - 1]
    if length < <size_t>(AXIS_TABLE_HEADER + 12 * t.n_bases):
        err_axis_table_size(err, -1, 0, name, <double>length, AXIS_TABLE_HEADER + 12 * t.n_bases)
        return False
    for b in range(t.n_bases):
        p = data + AXIS_TABLE_HEADER + 12 * b
        c_snprintf(field, sizeof(field), "%c", _axis_letter(t.bases[b]))
        t.lo[b] = _le_float(p)
        t.hi[b] = _le_float(p + 4)
        t.points[b] = _le_u32(p + 8)
        if _value_text(why, sizeof(why), "min", t.lo[b]) or _value_text(why, sizeof(why), "max", t.hi[b]):
            err_axis_table_definition(err, -1, 0, name, field, why)
            return False
        if not (t.lo[b] < t.hi[b]):
            c_snprintf(why, sizeof(why), "min = %g is not below max = %g", t.lo[b], t.hi[b])
            err_axis_table_definition(err, -1, 0, name, field, why)
            return False
        if t.points[b] < 2:
            c_snprintf(why, sizeof(why), "%u grid points: at least 2 (min and max)", t.points[b])
            err_axis_table_definition(err, -1, 0, name, field, why)
            return False
        # the grid points asked for, exact in double for the message; in integers only
        # while below the table cap (two factors below 2^32 could wrap the third's product)
        asked *= t.points[b]
        if total <= MAX_TABLE_BYTES:
            total *= t.points[b]
    if total > MAX_TABLE_BYTES or <uint64_t>length != AXIS_TABLE_HEADER + 12 * <uint64_t>t.n_bases + 4 * total:
        err_axis_table_size(err, -1, 0, name, <double>length, AXIS_TABLE_HEADER + 12.0 * t.n_bases + 4.0 * asked)
        return False
    p = data + AXIS_TABLE_HEADER + 12 * t.n_bases
    for i in range(total):
        value = _le_float(p + 4 * i)
        if _value_text(why, sizeof(why), "the correction", value):
            err_axis_table_value(err, -1, 0, name, <double>i, why)
            return False
    t.values = <float *>tc_malloc(4 * total)
    if t.values == NULL:
        err_out_of_memory(err, -1, 0)
        return False
    for i in range(total):
        t.values[i] = <float>_le_float(p + 4 * i)
    out[0] = t
    return True


cdef void axis_corrections_release(AxisCorrections *tables) noexcept nogil:
    """Drops a reference (tables may be NULL); the last one frees the tables."""
    cdef int k
    if tables != NULL and TC_REF_SUB(&tables.refs) == 0:
        for k in range(tables.n):
            free(tables.table[k].values)
        free(tables)


cdef AxisCorrections *axis_corrections_ref(AxisCorrections *tables) noexcept nogil:
    """One more reference (tables may be NULL). The caller owns one already, or holds
    the lock of the core that does."""
    if tables != NULL:
        TC_REF_ADD(&tables.refs)
    return tables


cdef bint axis_corrections_read(const char *const *paths, uint32_t n, AxisCorrections **out,
                                ErrorInfo *err) noexcept nogil:
    """The tables of the files `paths[0..n)` with one reference in *out (NULL for
    n = 0: no correction); False with err naming the file and the field, *out
    untouched and nothing kept, when a file cannot be read or is not a table, when
    two tables have the same number, or for more than AXIS_TABLES_MAX files
    (ERR_AXIS_TABLES)."""
    cdef AxisCorrections *tables
    cdef char *data
    cdef char why[256]
    cdef size_t length
    cdef int32_t error = 0
    cdef uint32_t k
    cdef int j
    cdef bint good
    if n > AXIS_TABLES_MAX:
        c_snprintf(why, sizeof(why), "%u tables: at most 8 per core", n)
        err_axis_tables(err, -1, 0, paths[AXIS_TABLES_MAX], why)
        return False
    if n == 0:
        out[0] = NULL
        return True
    tables = <AxisCorrections *>tc_calloc(1, sizeof(AxisCorrections))
    if tables == NULL:
        err_out_of_memory(err, -1, 0)
        return False
    tables.refs = 1
    for k in range(n):
        data = read_whole_file(paths[k], MAX_TABLE_BYTES, &length, &error)
        if data == NULL:
            if error == ERR_FILE_TOO_LARGE:
                err_table_too_large(err, -1, 0, paths[k])
            else:
                file_error(err, error, -1, paths[k])
            axis_corrections_release(tables)
            return False
        good = _axis_table_parse(<const unsigned char *>data, length, paths[k], &tables.table[k], err)
        free(data)
        if not good:
            axis_corrections_release(tables)
            return False
        tables.n += 1
        for j in range(tables.n - 1):
            if tables.table[j].number == tables.table[k].number:
                c_snprintf(why, sizeof(why), "its number %u is the number of '%.200s' too",
                           tables.table[k].number, paths[j])
                axis_corrections_release(tables)
                err_axis_tables(err, -1, 0, paths[k], why)
                return False
    out[0] = tables
    return True


cdef double _table_value(const AxisTable *t, const double *position) noexcept nogil:
    """The correction of table t at `position` (ten axes): multilinear in the basis
    axes between the grid points around it, each basis axis held at its range's edge
    outside the range."""
    cdef uint32_t index[3]
    cdef double fraction[3]
    cdef uint64_t stride[3]
    cdef uint64_t offset
    cdef double u, weight, total = 0.0
    cdef int b, corner, n = t.n_bases
    for b in range(n):
        u = (position[t.bases[b]] - t.lo[b]) / (t.hi[b] - t.lo[b]) * (t.points[b] - 1)
        if not (u > 0.0):               # below the range (or not a number): its first point
            index[b] = 0
            fraction[b] = 0.0
        elif u >= t.points[b] - 1:      # above: its last point, as the last cell's end
            index[b] = t.points[b] - 2
            fraction[b] = 1.0
        else:
            index[b] = <uint32_t>floor(u)
            fraction[b] = u - index[b]
    stride[n - 1] = 1
    for b in range(n - 2, -1, -1):
        stride[b] = stride[b + 1] * t.points[b + 1]
    for corner in range(1 << n):
        weight = 1.0
        offset = 0
        for b in range(n):
            if corner & (1 << b):
                weight *= fraction[b]
                offset += (index[b] + 1) * stride[b]
            else:
                weight *= 1.0 - fraction[b]
                offset += index[b] * stride[b]
        if weight != 0.0:
            total += weight * t.values[offset]
    return total


cdef void axis_correction_apply(const AxisCorrections *tables, const double *pos_in, double *pos_out) noexcept nogil:
    """pos_out (ten axes) = pos_in with each table's correction added to its axis,
    every table reading the basis axes of pos_in (corrections do not feed each
    other; two tables of one axis add). pos_out may be pos_in. tables NULL: a copy."""
    cdef double position[10]
    cdef int k
    memcpy(position, pos_in, sizeof(position))
    memcpy(pos_out, pos_in, sizeof(position))
    if tables == NULL:
        return
    for k in range(tables.n):
        pos_out[tables.table[k].axis] += _table_value(&tables.table[k], position)
