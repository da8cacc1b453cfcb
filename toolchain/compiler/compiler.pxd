# Face of the G-code compiler (compiler/): the text of a program, with its prefix and
# postfix, interpreted once line by line (loops and calls included) into one Part
# per G or M function. Its files, in the order they build on each other:
#   lexer.pyx        character classes, words, comments, numbers of one line
#   state.pyx        the compiler's state (CState): modal settings, frames, errors, coordinates
#   expressions.pyx  expressions and parameters, evaluated at once
#   labels.pyx       jump targets (labels, G29 comments, N numbers), found on the first jump
#   flow.pyx         IF / WHILE / FOR / BREAK / CONTINUE, calls and jumps
#   emit.pyx         the parts of a line's words, in machine coordinates
#   compiler.pyx     the line loop: words, modal G and M functions, the parts
# Owns CState and its records; reads CompileInput and writes the Program through its
# builder (program.pxd). Called by the core's compile worker (compile_program).

# ---- lexer.pyx
cdef enum:
    NUMBER_MAX_CHARS = 400      # longer digit strings are a "bad number"

# ---- state.pyx: the compiler's state
cdef enum:
    CALL_DEPTH = 64             # nested CALL / G25 / G26 (documented in docs/errors.md)
    FRAME_DEPTH = 256           # calls + open FOR / WHILE / IF blocks
    PARAM_STACK_DEPTH = 16      # G900 S1 pushes
    MAX_LINE_CHARS = 65536      # longer lines are refused (ERR_LINE_TOO_LONG)
    MAX_PARTS = 20000000        # ERR_PART_LIMIT
    MAX_WORD_LIST = 16          # G or M words on one line
    MAX_COMPILE_WARNINGS = 50   # per compilation; then one "further warnings suppressed"
    DEFAULT_MAX_BLOCKS = 10000000

# what exec_line asks the run loop to do next
cdef enum:
    R_NEXT = 0
    R_JUMP = 1
    R_END = 2
    R_ERR = -1

# flow frames
cdef enum:
    FR_CALL = 1
    FR_FOR = 2
    FR_WHILE = 3
    FR_IF = 4

ctypedef struct Label:
    const char *name        # NULL for an N number
    int32_t len
    int64_t nval            # N number
    size_t pos              # start of the line holding the label
    uint32_t line
    bint used

ctypedef struct Unit:
    const char *text
    size_t len
    int32_t file_idx
    Label *labels           # open-addressing hash table, built on the first jump
    size_t cap_labels, n_labels
    bint labels_built

ctypedef struct Frame:
    int kind
    size_t pos              # FOR: body start; WHILE: its own line; CALL: return line
    uint32_t line
    int param               # FOR: loop parameter
    double end, step        # FOR
    int64_t repeat          # CALL (G26 H): calls still to do
    size_t target_pos       # CALL: subroutine start, for repeats
    uint32_t target_line

ctypedef struct LineWords:
    double v[26]            # values of the address letters (after evaluation)
    uint32_t mask           # letters present
    int ng, nm
    double g[MAX_WORD_LIST]
    double m[MAX_WORD_LIST]
    int gcol[MAX_WORD_LIST]     # 1-based columns of the G / M words, for messages
    int mcol[MAX_WORD_LIST]
    int col[26]                 # column of each address letter (valid where mask is set)
    bint has_pword              # a P word that is no assignment (P0.1): ISO dwell, G64 or M argument
    double pword
    const char *pword_at        # its text, for messages
    int pword_len
    bint first_is_o             # the line starts with an O word (a program number in ISO)
    bint has_ff, has_fp
    double ff, fp
    const char *label       # G25/G26/G27 L target given as a name
    int label_len
    const char *text        # M29 / PRINT text
    int text_len
    bint has_text

ctypedef struct CState:
    const CompileInput *inp
    ProgramBuilder *build   # grows the program's arrays
    Program *prog           # &build.prog
    ErrorInfo *err
    GCODE_PARAMETERS params                 # working copy (G900 changes it)
    GCODE_PARAMETERS pstack[PARAM_STACK_DEPTH]
    int n_pstack
    double P[100]
    # positions: machine = rotate(mirror(ppos)) + zero + shift
    double ppos[AXES]
    double mpos[AXES]
    double zero[AXES]
    double shift[AXES]
    int zero_idx
    int mirror                              # bit 0 X, 1 Y, 2 Z
    bint rot_on
    int rot_idx                             # Program.rotations entry of the active rotation, 0 = none
    bint identity                           # no offset, mirror or rotation: machine = program
    double rot_c[3]
    double rot_m[9]
    bint absolute
    int plane
    int motion                              # modal 0 1 2 3 33
    bint per_min
    bint lathe_radius                       # G24
    bint css                                # G96
    double feed, def_feed, ff, fp
    bint ff_set
    float spindle
    int tool
    int comp, comp_slot
    bint g167_on
    double g167[4]                          # E A U Q
    uint32_t limits_off                     # M-5: axes whose limits are disabled
    uint32_t g900_ignore_angle, g900_ignore_feed
    int32_t g900_stop_mode, g900_arc_table
    int32_t gindex
    bint fixed[AXES]                        # the axis no longer follows the start (named absolutely)
    bint shift_follows[AXES]                # a G92 on the axis while it followed the start
    bint program_end
    int64_t blocks, block_limit
    Frame frames[FRAME_DEPTH]
    int n_frames, n_calls
    Unit *unit
    uint32_t line
    size_t cur_pos                          # start of the line being executed
    size_t skip_pos                         # fl_skip: the END/ELSE line found
    uint32_t skip_line
    size_t next_pos
    uint32_t next_line
    size_t jpos
    uint32_t jline
    int last_percent
    bint iso                                # ISO compatibility mode (GCODE_REZERVA1_ISO_COMPAT)
    double unit_scale                       # 1, or 25.4 after an ISO G20 (inches)
    bint iso_header                         # G21, or G90 before the first part: written for ISO?
    bint warned_g18                         # the G18 arc warning is given once
    int n_warnings
    char word[64]                           # text of an offending word for messages
    LineWords lw                            # words of the current line

# ---- expressions.pyx
cdef enum:
    EXPR_DEPTH = 64     # nesting of brackets/functions (stack safety on garbage input)

# ---- emit.pyx
cdef enum:
    # X Y Z C B U V W A O as letter bits
    AXIS_LETTERS = (1 << 23) | (1 << 24) | (1 << 25) | (1 << 2) | (1 << 1) | (1 << 20) | (1 << 21) | (1 << 22) | (1 << 0) | (1 << 14)


# ---- what other stages call
# the program of inp into build.prog: COMPILE_OK, COMPILE_ERROR (err filled) or
# COMPILE_CANCELLED; the compensation runs beside it when the core wires it (pipeline)
cdef int compile_program(const CompileInput *inp, ProgramBuilder *build, ErrorInfo *err) noexcept nogil
