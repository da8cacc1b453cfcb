# Face of the G-code compiler (compiler/): the text of a program, with its prefix and
# postfix, interpreted once line by line (loops and calls included) into one Part
# per G or M function. Its files, in the order they build on each other:
#   lexer.pyx        character classes, words, comments, numbers of one line
#   state.pyx        the compiler's state (CState): modal settings, frames, errors, coordinates
#   expressions.pyx  expressions and parameters, evaluated at once
#   labels.pyx       jump targets (labels, G29 comments, N numbers), found on the first jump
#   flow.pyx         IF / WHILE / FOR / BREAK / CONTINUE, calls and jumps
#   emit.pyx         the parts of a line's words, in machine coordinates
#   ngc_params.pyx   ISO mode: LinuxCNC's numbered and named parameters, [ ] expressions
#   words.pyx        the words of one line (LineWords), evaluated at once
#   dialects.pyx     the TG hints for ISO G functions; how the ISO mode reads a line
#   ngc_flow.pyx     ISO mode: O-word subroutines, branches and loops
#   ngc_motion.pyx   ISO mode: work offsets, G28 / G30, G53, canned cycles
#   ngc_spline.pyx   ISO mode: G5 / G5.1 / G5.2-G5.3 splines as arcs and lines within 1 um
#   tools.pyx        the tool table in programs: D, &, G92 D (ISO: G43 H, G49)
#   block.pyx        one line's G and M functions by modal group (Block), run in one order
#   compiler.pyx     the line loop: units, lines, the run to the end
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
    bint has_polar_r, has_polar_a   # ISO mode: LinuxCNC's polar words @ (distance) and ^ (angle)
    double polar_r, polar_a
    int polar_col
    bint has_amp                # & n: the length corrections of tool table entry n
    double amp
    int amp_col
    uint32_t tool_values        # G92 D's R0= .. R4=: bit k for Rk (TG)
    double tool_value[TOOL_VALUES]
    int tool_values_col         # the first one's column

# ---- ngc_params.pyx, ngc_flow.pyx, ngc_motion.pyx: the ISO compatibility mode's state
# LinuxCNC's RS274/NGC as the ISO mode reads it: numbered and named parameters, O-word
# flow, work offsets, home positions and canned cycles. Allocated once per compilation
# in the ISO mode (CState.ngc), so the TG dialect pays nothing for it.
cdef enum:
    NGC_PARAMS = 5602           # numbered parameters #1 .. #5601 (LinuxCNC's table)
    NGC_ARGS = 30               # #1 .. #30: a call's arguments, local to the call
    NGC_CALL_LEVELS = 10        # LinuxCNC's nesting limit of O-word calls (level 0 = the program)
    NGC_FRAMES = 256            # open O-word loops and calls
    NGC_LINE_SETTINGS = 50      # parameter settings on one line
    NGC_NAME_CHARS = 64         # longest parameter or subroutine name
    NGC_SCANS = 64              # remembered O-word scans (direct-mapped by position)

# O-word frames
cdef enum:
    OF_CALL = 1
    OF_WHILE = 2
    OF_DO = 3
    OF_REPEAT = 4

ctypedef struct NgcLabel:       # the number (o100) or name (o<name>) of an O word
    int64_t number              # -1 for a name
    int len
    char name[NGC_NAME_CHARS]   # lower case, without blanks

ctypedef struct NgcName:        # a named parameter
    int level                   # call level that owns a local one; -1: global (#<_name>)
    int len
    char name[NGC_NAME_CHARS]
    double value

ctypedef struct NgcSub:         # a subroutine whose definition was read
    NgcLabel label
    const char *text            # the source (unit) holding it
    size_t pos                  # the line after `sub`
    uint32_t line

ctypedef struct NgcFrame:       # an open O-word call or loop
    int kind                    # OF_*
    NgcLabel label
    size_t pos                  # call: the line to return to; while: its own line; do, repeat: the line after it
    uint32_t line
    int64_t count               # repeat: passes left

ctypedef struct NgcSetting:     # a parameter setting read on the line, done after the line is read
    int number                  # #number, or 0 for a named one
    int len
    char name[NGC_NAME_CHARS]
    double value

ctypedef struct NgcScan:        # a remembered ow_scan: the text is read-only, so is its answer
    const char *text            # the unit's text; NULL: an empty slot
    size_t pos                  # where the scan started
    uint32_t kinds
    NgcLabel label
    int found                   # the keyword found; 0: none
    size_t skip_pos, jpos       # as ow_scan sets st.skip_pos / st.jpos
    uint32_t lines              # lines from pos to the found one

ctypedef struct NgcState:
    double params[NGC_PARAMS]
    NgcName *names
    size_t n_names, cap_names
    uint32_t *name_slots        # open addressing over names[]: index + 1, 0 empty
    size_t n_slots              # a power of two, at least twice n_names; 0: no index yet
    size_t n_locals             # names of call levels >= 1 (a return drops them)
    NgcScan scans[NGC_SCANS]    # loops over skipped branches scan each branch once
    NgcSub *subs
    size_t n_subs, cap_subs
    # splines (ngc_spline.pyx)
    double spline_pq[2]         # the last G5's P Q: a G5 right after it may leave out I J
    size_t spline_part          # the part count after that G5 (a part made since: no G5 goes on from it)
    bint spline_pq_set
    bint nurbs_open             # between G5.2 and G5.3
    int nurbs_order
    double *nurbs               # the open NURBS's control points: x y w, in program coordinates
    size_t n_nurbs, cap_nurbs   # (cap in doubles)
    uint64_t *if_keys           # the labels of the `if` statements executed (ow_if_key; 0: empty slot)
    size_t n_if_keys, cap_if_keys   # cap: 0 or a power of two, at least twice n_if_keys
    NgcFrame frames[NGC_FRAMES]
    int n_frames
    int level                   # call level: 0 in the program
    double saved[NGC_CALL_LEVELS][NGC_ARGS]     # the callers' #1 .. #30
    NgcSetting settings[NGC_LINE_SETTINGS]
    int n_settings
    double value                # #<_value>: what the last return / endsub returned
    bint value_returned
    int coord                   # 1 .. 9: G54 .. G59.3
    int retract                 # 98 / 99
    bint ijk_absolute           # G90.1
    bint inverse_time           # G93: F is 1 / minutes per move
    int col                     # column of the O word of the statement being executed
    int spindle                 # 3 clockwise, 4 counter-clockwise, 0 stopped
    bint mist, flood
    # canned cycles (LinuxCNC keeps R, Z, Q, P from one line of a cycle to the next)
    double cycle_r, cycle_cc, cycle_q, cycle_p
    double cycle_il             # the level before the series of cycles (G98 returns there)
    bint cycle_il_set

ctypedef struct CState:
    const CompileInput *inp
    ProgramBuilder *build   # grows the program's arrays
    Program *prog           # &build.prog
    ErrorInfo *err
    GCODE_PARAMETERS params                 # working copy (G900 changes it)
    GCODE_PARAMETERS pstack[PARAM_STACK_DEPTH]
    int n_pstack
    double P[100]
    # positions: machine = rotate(mirror(ppos)) + zero + shift + length (&)
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
    int motion                              # modal 0 1 2 3 33; ISO mode: also 73 81..89, -1 none (G80)
    bint per_min
    bint lathe_radius                       # G24
    bint css                                # G96
    double feed, def_feed, ff, fp
    bint ff_set
    float spindle
    int tool
    int comp, comp_slot                     # the side (40 41 42 after the radius's sign), correction[] slot
    int comp_g                              # G40 .. G48 in force, as written
    int radius_idx                          # Program.radii of the D radius parts carry (0: correction[])
    double comp_radius                      # the signed radius in force
    ToolTable tools                         # the compilation's tool table (the core's at the start; G92 D writes it)
    int tool_d                              # D in force: -1 none (correction[] of the slot), 0 radius 0, 1..99
    int tool_len                            # & in force: 0 none, 1..99
    double length[AXES]                     # the lengths of & (axes 1..4: x y z c), added like an offset
    bint g167_on
    double g167[4]                          # E A U Q
    uint32_t limits_off                     # M-5: axes whose limits are disabled
    uint32_t g900_ignore_angle, g900_ignore_feed
    int32_t g900_stop_mode, g900_arc_table
    int32_t gindex
    bint gindex_set         # M-6 S set gindex: the next part starts the count again (FLAG_INDEX_SET)
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
    bint warned_feed, warned_bare_axes      # warnings 614 / 615 are given once
    bint motion_given                       # a G0 .. G3 (or ISO cycle) was written
    uint32_t g80_line                       # ISO mode: the line whose G80 cancelled the motion mode (0: none)
    size_t percent_open                     # ISO mode: start of the unit's opening '%' line (SIZE_MAX: none)
    NgcState *ngc                           # ISO mode: parameters, O-words, offsets, cycles (else NULL)
    int n_warnings
    ErrorInfo warning               # the compile warning being reported (warning_wanted, cwarn)
    char word[64]                           # text of an offending word for messages
    LineWords lw                            # words of the current line

# ---- expressions.pyx
cdef enum:
    EXPR_DEPTH = 64     # nesting of brackets/functions (stack safety on garbage input)

# ---- flow.pyx: the forward scan of skipped lines (fl_scan), shared with ngc_flow.pyx
# a line's answer to a scan: 0 read on, else the scan stops at that line with it
ctypedef int (*line_test_fn)(void *ctx, const char *p, const char *eol) noexcept nogil

ctypedef struct BlockSkip:      # fl_skip's scan: the blocks still open
    int depth                   # an END closes one, a FOR / WHILE / IF ... THEN opens one
    bint stop_at_else           # an ELSE at depth 1 ends the scan too

# ---- emit.pyx
cdef enum:
    # X Y Z C B U V W A O as letter bits
    AXIS_LETTERS = (1 << 23) | (1 << 24) | (1 << 25) | (1 << 2) | (1 << 1) | (1 << 20) | (1 << 21) | (1 << 22) | (1 << 0) | (1 << 14)

# ---- ngc_params.pyx
cdef enum:
    NGC_DEPTH = 64              # nesting of [ ] and functions (stack safety on garbage input)

# binary operators by precedence (LinuxCNC's): ** ; * / MOD ; + - ; EQ NE GT GE LT LE ; AND OR XOR
cdef enum:
    OP_NONE = 0
    OP_POWER = 1
    OP_TIMES = 2
    OP_DIVIDE = 3
    OP_MOD = 4
    OP_PLUS = 5
    OP_MINUS = 6
    OP_EQ = 7
    OP_NE = 8
    OP_GT = 9
    OP_GE = 10
    OP_LT = 11
    OP_LE = 12
    OP_AND = 13
    OP_OR = 14
    OP_XOR = 15

# ---- words.pyx: what reading one word leaves
cdef enum:
    WORDS_MORE = 0          # a word was read; more may follow
    WORDS_DONE = 1          # the rest of the line holds no words (REM, G29's comment, M29's text)

# ---- ngc_flow.pyx
cdef enum:
    R_NOT_O = 3                 # ow_statement: the line is no O-word statement

cdef enum:
    OW_SUB = 1
    OW_ENDSUB = 2
    OW_CALL = 3
    OW_RETURN = 4
    OW_IF = 5
    OW_ELSEIF = 6
    OW_ELSE = 7
    OW_ENDIF = 8
    OW_WHILE = 9
    OW_ENDWHILE = 10
    OW_DO = 11
    OW_REPEAT = 12
    OW_ENDREPEAT = 13
    OW_BREAK = 14
    OW_CONTINUE = 15

ctypedef struct LabelScan:      # ow_scan's: the statements of one O label it looks for
    const NgcLabel *label
    uint32_t kinds              # the keywords' bits (kw_bit)

# ---- ngc_spline.pyx
cdef enum:
    SPLINE_MIN_PIECES = 4       # a Bezier's range, a NURBS's knot span: split in this many pieces first
    SPLINE_MAX_DEPTH = 16       # a piece is halved at most this often (then its arc stands)
    SPLINE_MAX_ORDER = 16       # the highest NURBS order (L) read
    SPLINE_CHECKS = 7           # points of a piece checked against its arc (each eighth)

# ---- block.pyx
# What one line says, by modal group: cp_read_block fills it from the G functions in
# the order written (a later G of the same group replaces an earlier one); cp_block
# executes the groups in the order block.pyx documents. 0 / -1: not on the line.
ctypedef struct Block:
    int motion              # 0 1 2 3 33; ISO mode: also 73 74 81 .. 86 89 (cycles), 80 (cancel),
                            # 5 51 52 53 (G5 G5.1 G5.2 G5.3); -1 none
    int motion_col          # its column
    int plane               # 17 18 19 -18
    int units               # 21 (TG: an ISO header)
    int comp                # 40 .. 48
    int zero                # 53 .. 57, 59 (TG's zero offsets)
    int zero_col            # its column
    int rotation            # 168 on, 169 off
    int distance            # 90 / 91
    int feed_mode           # 94 / 95
    int css                 # 96 / 97
    int shift               # 92 / 98
    int length              # ISO mode: 43 (G43 H, a tool length offset) / 49 (cancel)
    int strategy            # 172 / 173
    int jump                # 25 26 27
    int jump_col            # its column
    int g900_col            # G900's column
    bint dwell              # G4
    bint lathe_radius       # G24
    bint g167               # automatic arcs
    bint settings           # a G function of groups 1, 2, 4 .. 10 (ISO mode: any): cp_block runs them
    uint32_t consumed       # letters the line's functions use: no axis moves
    # the ISO compatibility mode (ngc_*.pyx): LinuxCNC's G functions of the line
    int home                # 28 30 (go home), 281 282 (G28.1 / G30.1: store)
    int coord               # 1 .. 9: G54 .. G59.3
    int retract             # 98 / 99
    int ijk                 # 901 (G90.1 absolute centres) / 911 (G91.1 relative)
    int shift_reset         # 1 2 3: G92.1, G92.2, G92.3
    bint machine            # G53: this line moves in machine coordinates
    bint g10                # G10 L2 / L20 (L and P words)
    bint ngc_p              # a G function of the line takes its P word (dwell, cycle, G10, G64)

# which M functions of a line a pass of block.pyx runs
cdef enum:
    M_ALL = 0
    M_BEFORE = 1
    M_STOPS = 2


# ---- what other stages call
# the program of inp into build.prog: COMPILE_OK, COMPILE_ERROR (err filled) or
# COMPILE_CANCELLED; the compensation runs beside it when the core wires it (pipeline)
cdef int compile_program(const CompileInput *inp, ProgramBuilder *build, ErrorInfo *err) noexcept nogil
