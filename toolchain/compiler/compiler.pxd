# Types of the compiler stage that are new with the modal-group reading of a block
# (block.pyx). Included by libSF_TCh.pyx before the compiler's .pyx files.
from libc.stdint cimport uint32_t


# What one line says, by modal group: cp_read_block fills it from the G functions in
# the order written (a later G of the same group replaces an earlier one); cp_block
# executes the groups in the order block.pyx documents. 0 / -1: not on the line.
ctypedef struct Block:
    int motion              # 0 1 2 3 33; ISO mode: also 73 74 81 .. 86 89 (cycles), 80 (cancel); -1 none
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
    int strategy            # 172 / 173
    int jump                # 25 26 27
    int jump_col            # its column
    int g900_col            # G900's column
    bint dwell              # G4
    bint lathe_radius       # G24
    bint g167               # automatic arcs
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


# ------------------------------------------------------------------------------
# The ISO compatibility mode's reading of LinuxCNC's RS274/NGC (ngc_params.pyx,
# ngc_flow.pyx, ngc_motion.pyx): numbered and named parameters, O-word flow, work
# offsets, home positions and canned cycles. Allocated once per compilation in the
# ISO mode (CState.ngc), so the TG dialect pays nothing for it.
from libc.stdint cimport int64_t

cdef enum:
    NGC_PARAMS = 5602           # numbered parameters #1 .. #5601 (LinuxCNC's table)
    NGC_ARGS = 30               # #1 .. #30: a call's arguments, local to the call
    NGC_CALL_LEVELS = 10        # LinuxCNC's nesting limit of O-word calls (level 0 = the program)
    NGC_FRAMES = 256            # open O-word loops and calls
    NGC_LINE_SETTINGS = 50      # parameter settings on one line
    NGC_NAME_CHARS = 64         # longest parameter or subroutine name

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

ctypedef struct NgcState:
    double params[NGC_PARAMS]
    NgcName *names
    int n_names, cap_names
    NgcSub *subs
    int n_subs, cap_subs
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
