# Types of the compiler stage that are new with the modal-group reading of a block
# (block.pyx). Included by libSF_TCh.pyx before the compiler's .pyx files.
from libc.stdint cimport uint32_t


# What one line says, by modal group: cp_read_block fills it from the G functions in
# the order written (a later G of the same group replaces an earlier one); cp_block
# executes the groups in the order block.pyx documents. 0 / -1: not on the line.
ctypedef struct Block:
    int motion              # 0 1 2 3 33; -1 none
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
    bint clear_shift        # ISO G92.1
    uint32_t consumed       # letters the line's functions use: no axis moves
