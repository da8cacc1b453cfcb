# Compiler state: everything modal while a program is compiled (positions, zero
# offsets, mirroring, rotation, feeds, compensation, flow frames), the words of one
# line, error helpers, and the program -> machine coordinate transform.
from libc.math cimport sin, cos, sqrt, fabs, M_PI
from libc.string cimport memcpy
from libc.stdio cimport snprintf


cdef inline int to_int(double v) noexcept nogil:
    """A word's value as int, saturated (no undefined cast of huge values or NaN)."""
    if v != v:
        return 0
    if v >= 2147483647.0:
        return 2147483647
    if v <= -2147483648.0:
        return -2147483647 - 1
    return <int>v


cdef inline int axis_of_letter(char c) noexcept nogil:
    """Axis index (X Y Z C B U V W A O) of an upper-case letter, -1 if not an axis."""
    if c == b'X': return 0
    if c == b'Y': return 1
    if c == b'Z': return 2
    if c == b'C': return 3
    if c == b'B': return 4
    if c == b'U': return 5
    if c == b'V': return 6
    if c == b'W': return 7
    if c == b'A': return 8
    if c == b'O': return 9
    return -1


cdef inline char letter_of_axis(int a) noexcept nogil:
    """The address letter of axis 0..9 in the library's order X Y Z C B U V W A O."""
    cdef const char *names = "XYZCBUVWAO"
    return names[a]


cdef int g_column(const LineWords *lw, double g) noexcept nogil:
    """Column of G function g on the line (1 when it is modal, not written)."""
    cdef int i
    for i in range(lw.ng):
        if lw.g[i] == g:
            return lw.gcol[i]
    return 1


cdef int axis_column(const LineWords *lw, uint32_t letters) noexcept nogil:
    """Column of the first of the given address letters written on the line (1: none)."""
    cdef int col = 0, bit
    for bit in range(26):
        if (letters >> bit) & 1 and (lw.mask >> bit) & 1 and (col == 0 or lw.col[bit] < col):
            col = lw.col[bit]
    return col if col > 0 else 1


# --------------------------------------------------------------- errors

cdef const char *cword(CState *st, const char *p, const char *eol, int n) noexcept nogil:
    """Copies up to n (max 40) printable characters at p for an error message."""
    cdef int i = 0
    cdef unsigned char c
    if n > 40:
        n = 40
    while i < n and p + i < eol:
        c = <unsigned char>p[i]
        if c < 32 or c >= 127:
            st.word[i] = b'?'
        else:
            st.word[i] = p[i]
        i += 1
    st.word[i] = 0
    return st.word


cdef int column_of(const CState *st, const char *p) noexcept nogil:
    """1-based column of p in the line being executed."""
    return <int>(p - (st.unit.text + st.cur_pos)) + 1


cdef const char *cword_at(CState *st, const char *p, const char *eol) noexcept nogil:
    """The word at p for a message: up to a blank (CR included), a comment or 40 characters."""
    cdef int n = 0
    while p + n < eol and n < 40 and p[n] != b' ' and p[n] != b'\t' and p[n] != b'\r' \
            and p[n] != b'(' and p[n] != b';':
        n += 1
    return cword(st, p, eol, n if n > 0 else 1)


cdef const char *cword_rest(CState *st, const char *p, const char *eol) noexcept nogil:
    """The rest of the line from p for a message, without trailing blanks or CR."""
    while eol > p and ((eol - 1)[0] == b' ' or (eol - 1)[0] == b'\t' or (eol - 1)[0] == b'\r'):
        eol -= 1
    return cword(st, p, eol, <int>(eol - p))


cdef int number_gate(CState *st, double v, const char *address) noexcept nogil:
    """The one bound of every number that reaches a part (docs/dialect.md, "Numbers"):
    finite and within +-TC_MAX_WORD_VALUE; 0, or error 106 naming `address` (an
    address letter, a polar word, an ISO parameter such as #5221)."""
    if v >= -TC_MAX_WORD_VALUE and v <= TC_MAX_WORD_VALUE:
        return 0
    return err_bad_value(st.err, st.unit.file_idx, st.line, v, address)


cdef int cerr_open_comment(CState *st, const char *p, const char *eol) noexcept nogil:
    """Error 104 for the gap [p, eol) that holds a '(' without ')': comments do not
    nest, so it is the first '(' after the last ')'."""
    cdef const char *q = eol
    cdef const char *open_at = NULL
    while q > p and (q - 1)[0] != b')':
        q -= 1
        if q[0] == b'(':
            open_at = q
    return err_unterminated_comment(st.err, st.unit.file_idx, st.line, column_of(st, open_at if open_at != NULL else p))


# --------------------------------------------------------------- warnings

cdef bint warning_wanted(CState *st) noexcept nogil:
    """Whether a compile warning is still reported: False once MAX_COMPILE_WARNINGS were
    (the first one beyond says so in the output log). The caller then fills
    st.warning with its constructor and calls cwarn."""
    if st.n_warnings > MAX_COMPILE_WARNINGS:
        return False
    st.n_warnings += 1
    if st.n_warnings > MAX_COMPILE_WARNINGS:
        if st.inp.output != NULL:
            st.inp.output(st.inp.ctx, 0, "Warning: G-code: further warnings suppressed")
        return False
    return True


cdef void cwarn(CState *st) noexcept nogil:
    """The numbered compile warning (600..699) in st.warning, on the current line: to the
    host's MathWarning (CompileInput.warn) and to the output log, like the compensation's."""
    cdef char text[1100]
    st.warning.n_lines = <int32_t>st.prog.n_lines
    if st.inp.warn != NULL:
        st.inp.warn(st.inp.ctx, &st.warning)
    if st.inp.output != NULL:
        snprintf(text, sizeof(text), "Warning: G-code, line %u: %s", st.line, st.warning.text)
        st.inp.output(st.inp.ctx, 0, text)


cdef int ngc_refused(CState *st, const char *word, int column, const char *why,
                     const char *instead) noexcept nogil:
    """ISO mode: a construct LinuxCNC refuses (`why`). Warning 621 and 0 (the caller
    compiles on as `instead` says: "ignores it", ...), or in the strict ISO mode error
    414 and R_ERR."""
    if (<uint32_t>st.params.rezerva1 & GCODE_REZERVA1_ISO_STRICT) != 0:
        return err_ngc_refused(st.err, st.unit.file_idx, st.line, word, column, why)
    if warning_wanted(st):
        warn_ngc_refused(&st.warning, st.unit.file_idx, st.line, word, column, why, instead)
        cwarn(st)
    return 0


# ----------------------------------------------------- coordinate transform

cdef void to_machine(const CState *st, const double *pp, double *out) noexcept nogil:
    """Program coordinates -> machine: mirror (M81..M87), rotation (G168), then the
    zero offset, the G92 shift and the tool's lengths (&)."""
    cdef int a
    if st.identity:
        memcpy(out, pp, AXES * sizeof(double))
        return
    for a in range(AXES):
        out[a] = pp[a]
    if st.mirror & 1: out[0] = -out[0]
    if st.mirror & 2: out[1] = -out[1]
    if st.mirror & 4: out[2] = -out[2]
    if st.rot_on:
        rotate_about(st.rot_c, st.rot_m, False, out)
    for a in range(AXES):
        out[a] += st.zero[a] + st.shift[a] + st.length[a]


cdef void to_program(const CState *st, const double *mp, double *out) noexcept nogil:
    """Inverse of to_machine."""
    cdef int a
    for a in range(AXES):
        out[a] = mp[a] - st.zero[a] - st.shift[a] - st.length[a]
    if st.rot_on:
        rotate_about(st.rot_c, st.rot_m, True, out)
    if st.mirror & 1: out[0] = -out[0]
    if st.mirror & 2: out[1] = -out[1]
    if st.mirror & 4: out[2] = -out[2]


cdef void update_identity(CState *st) noexcept nogil:
    """to_machine is a plain copy while no offset, mirroring or rotation is active."""
    cdef int a
    st.identity = st.mirror == 0 and not st.rot_on
    for a in range(AXES):
        if st.zero[a] != 0.0 or st.shift[a] != 0.0 or st.length[a] != 0.0:
            st.identity = False


cdef void cp_reframe(CState *st) noexcept nogil:
    """After a change of zero offset, mirroring or rotation the machine stays where
    it is: its program coordinates are recomputed."""
    update_identity(st)
    to_program(st, st.mpos, st.ppos)


cdef bint registered(CState *st, int idx, const char *what) noexcept nogil:
    """idx of program_add_zero / _rotation / _radius is an entry; False with the error
    recorded when it is none (out of memory, or more than PROGRAM_TABLE_MAX `what`)."""
    if idx >= 0:
        return True
    if idx == -2:
        err_program_table_limit(st.err, st.unit.file_idx, st.line, PROGRAM_TABLE_MAX, what)
    else:
        err_out_of_memory(st.err, st.unit.file_idx, st.line)
    return False


cdef bint update_zero(CState *st) noexcept nogil:
    """Registers the active offset (zero + shift + the tool's lengths) with the program;
    False with the error recorded (registered)."""
    cdef double total[AXES]
    cdef int a, idx
    update_identity(st)
    for a in range(AXES):
        total[a] = st.zero[a] + st.shift[a] + st.length[a]
    idx = program_add_zero(st.build, total, st.shift)
    if not registered(st, idx, "zero offsets (G54.., G92, tool lengths)"):
        return False
    st.zero_idx = idx
    return True


cdef bint set_rotation(CState *st, double cx, double cy, double cz, double ax, double ay,
                       double az, double deg) noexcept nogil:
    """Rotation by deg about the axis (ax, ay, az) through the centre (Rodrigues),
    registered with the program for the unrotated size info; False with the error
    recorded (registered)."""
    cdef double n = sqrt(ax * ax + ay * ay + az * az)
    cdef double c, s, t
    if n == 0.0:
        ax = 0.0; ay = 0.0; az = 1.0
        n = 1.0
    ax /= n; ay /= n; az /= n
    c = cos(deg * M_PI / 180.0)
    s = sin(deg * M_PI / 180.0)
    t = 1.0 - c
    st.rot_m[0] = t * ax * ax + c
    st.rot_m[1] = t * ax * ay - s * az
    st.rot_m[2] = t * ax * az + s * ay
    st.rot_m[3] = t * ax * ay + s * az
    st.rot_m[4] = t * ay * ay + c
    st.rot_m[5] = t * ay * az - s * ax
    st.rot_m[6] = t * ax * az - s * ay
    st.rot_m[7] = t * ay * az + s * ax
    st.rot_m[8] = t * az * az + c
    st.rot_c[0] = cx; st.rot_c[1] = cy; st.rot_c[2] = cz
    st.rot_on = True
    st.rot_idx = program_add_rotation(st.build, st.rot_c, st.rot_m)
    if not registered(st, st.rot_idx, "rotations (G168)"):
        st.rot_idx = 0
        return False
    return True
