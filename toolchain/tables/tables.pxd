# Face of the tables stage: the correction tables a machine builder configures once
# per core and every part then relies on. Each is read from its file into memory
# (a read that fails leaves what was in memory) and applied by pure functions.
#   tool_table.pyx       the tool correction table TAB0.KOR: the entries D (radius)
#                        and & (lengths of axes 1..4) select, G92 D's writes
#   axis_correction.pyx  the axis correction tables ACHS3D??.KOR: one axis corrected
#                        from a grid over up to three basis axes
# Owns ToolTable and AxisCorrections (the core holds one of each: core.pxd). Called
# by the exports and LoadFromIni (loading, G92 D's write, correcting a position) and
# the compiler (D, &, G92 D on its copy of the table, compiler/tools.pyx) and the offline
# machine (the corrections of its output: machine/output.pyx). Its face comes before
# program.pxd: a CompileInput carries the core's ToolTable.

# ------------------------------------------------------------------ tool_table.pyx

cdef enum:
    TOOL_ENTRIES = 99           # D1..D99
    TOOL_VALUES = 5             # per entry: [0] radius, [1..4] length of axes 1..4 (G92 D's R0..R4)

# One entry of the table: value[0] the radius G41/G42 use (a negative one swaps the
# side), value[1..4] the length corrections of axes 1..4 (x y z c), mm.
ctypedef struct ToolCorrection:
    double value[5]

# The table in memory: entry[d] for D d (1..99); entry[0] stays zero (no correction).
ctypedef struct ToolTable:
    ToolCorrection entry[100]

# ------------------------------------------------------------------ axis_correction.pyx

cdef enum:
    AXIS_TABLES_MAX = 8         # tables per core
    AXIS_TABLE_BASES_MAX = 3    # basis axes per table
    AXIS_TABLE_HEADER = 128     # bytes of a file's header

# One table: the corrected axis gets the correction interpolated from a regular grid
# over its basis axes at their current positions (uncorrected: the machine's filtered output).
ctypedef struct AxisTable:
    int32_t axis                # the corrected axis, 0..9 (x y z c b u v w a o)
    int32_t n_bases             # 1..3
    int32_t bases[3]            # the basis axes, in the file's order
    double lo[3]                # grid range of each basis axis, mm (lo < hi)
    double hi[3]
    uint32_t points[3]          # grid points of each basis axis (>= 2)
    uint32_t number             # the table's number (the header's last byte)
    float *values               # the corrections (mm), the first basis axis slowest, the last fastest

# The tables of a core: immutable once published; the core holds one reference and
# whoever applies them outside the core's lock holds its own (axis_corrections_ref).
ctypedef struct AxisCorrections:
    int32_t refs                # atomic
    int32_t n
    AxisTable table[8]


# ---- what other stages call

# the tool table of a file (any name, only a regular file) into *out, written only
# when the whole file is good (else err names the file and the line); G92 D's write
# of the values `programmed` (bit k: value k) into one entry, nothing written when
# one is refused
cdef bint tool_table_read(const char *path, ToolTable *out, ErrorInfo *err) noexcept nogil
cdef bint tool_table_set(ToolTable *table, int64_t entry, uint32_t programmed, const double *values,
                         ErrorInfo *err) noexcept nogil

# the axis tables of n files with one reference (NULL for none), all or nothing (err
# names the file and the field); one more reference, and one less (the last frees);
# ten axes' positions with every table's correction added (pure)
cdef bint axis_corrections_read(const char *const *paths, uint32_t n, AxisCorrections **out,
                                ErrorInfo *err) noexcept nogil
cdef AxisCorrections *axis_corrections_ref(AxisCorrections *tables) noexcept nogil
cdef void axis_corrections_release(AxisCorrections *tables) noexcept nogil
cdef void axis_correction_apply(const AxisCorrections *tables, const double *pos_in, double *pos_out) noexcept nogil
