# Face of the tool radius compensation (compensation/), G41-G48 / G40: the tool
# centre path of every compensated part (Part.ce, PartExtra.radius) and the parts
# inserted at its corners, in one pass beside the compiler; then the automatic arcs
# of G167 (insert_arcs.pyx). Its files, in the order they build on each other:
#   offsets.pyx       offset elements (equidistants) of lines and arcs, and their meets
#   corners.pyx       the corner between two elements: where the path turns, what is inserted
#   strategy.pyx      the strategy of a run: the host's correctionStrategy, G172 / G173
#   pass_state.pyx    what every step does with the pass's state (warn, fail, queue, discard)
#   crossings.pyx     the path crossing itself between parts that are not neighbours
#   clearance.pyx     the path keeping the tool radius from the contour (the gouge check)
#   regions.pyx       a closed chain rebuilt from the regions the tool fits in
#   compensation.pyx  the pass: runs, chains, the stack of open elements, the merge
#   insert_arcs.pyx   G167 arcs between G1 lines
#   join_lines.pyx    tolerance[4] on programmed arcs, nearly collinear G1 parts joined (tolerance[2], [3])
# Owns CompState (one pass) and its records. Called by the core's compile worker
# (begin, feed beside the compiler through the pipeline, end, free; insert_arcs) and
# by the compiler (the G167 and G172 regions it records).

# ---- offsets.pyx: an offset element of a part
cdef enum:
    EL_LINE = 0
    EL_ARC = 1

# Insertion after an element (the corner to the next one).
cdef enum:
    INS_NONE = 0
    INS_G1 = 1
    INS_G2 = 2
    INS_G3 = 3

ctypedef struct CompEl:
    size_t part             # index in Program.parts
    int kind                # EL_LINE / EL_ARC
    int dir                 # arcs: +1 CCW (G3), -1 CW (G2)
    double d                # signed offset distance (left > 0)
    double s[2]             # programmed start, end, centre (plane coordinates)
    double e[2]
    double c[2]
    double R                # programmed arc radius
    double ro               # offset arc radius R - d*dir
    double sweep            # arcs: |programmed sweep| in (0, 2pi]
    double u[2]             # lines: unit direction
    double os[2]            # offset points on the perpendiculars at s and e
    double oe[2]
    double ps[2]            # tool path start / end once the corners are known
    double pe[2]
    int ins                 # INS_* after this element
    double ins_end[2]       # end of the inserted part
    bint first              # first element of its chain (entry ramp aims at ps)
    bint fixed_start        # starts at an uncompensated point (ramp, strategy 1 / G0)

# ---- corners.pyx, strategy.pyx: the strategy in force, the corner's result
ctypedef struct CompCfg:
    uint32_t strategy
    int mode                # low byte of the strategy: 0 or 1
    double tol_angle        # radians: below it two parts join tangentially
    double sin_tol          # its sine (the test on the tangents' cross product)
    double slack            # length accuracy (crossing, near-tangent intersections)
    double factor           # CORR_CORNER_INTERSECTION: limit distance in radii
    double corner_distance  # ... or in mm (G172 R), when > 0
    size_t depth            # how many parts back a crossing may be removed
    double min_arc          # tolerance[4]: tool path arcs of a smaller radius are removed (0 = none)

cdef enum CornerResult:
    CORNER_OK = 0
    CORNER_NOT_FOUND = 1

# ---- crossings.pyx: the final pieces of a chain, searched by their boxes
cdef enum:
    X_WRITE = 1             # cross_write: let _write_el write the element
    X_DONE = 2              # ... the element is already written (removed)
    X_FAIL = 0

ctypedef struct XPiece:
    double s[2]
    double e[2]
    double c[2]
    double r                # arc radius
    double sweep            # arc sweep in dir, (0, 2pi]; < 0: not computed yet (_x_sweep)
    double box[4]           # xmin ymin xmax ymax
    double gs[2]            # bodies: the programmed start, end, radius and |sweep|
    double ge[2]
    double gR, gsweep
    size_t part             # part whose path this is (window of the search depth)
    size_t after            # inserted pieces: the part the InsRec follows
    size_t rec              # inserted pieces: index of the InsRec in CompState.ins
    signed char kind        # EL_LINE / EL_ARC
    signed char dir         # arcs: +1 CCW, -1 CW
    unsigned char ins       # an inserted corner piece
    unsigned char first     # the body of the chain's first element
    unsigned char prov      # a G1 join that has to end up inside a removed loop
    unsigned char gprog     # bodies: the programmed element (gs .. gsweep) follows

ctypedef struct XState:
    XPiece *pc              # the pieces, at the positions of their boxes in ix (room for cap)
    size_t cap
    BoxIndex ix             # their boxes: pieces [ix.base, ix.n) are searched
    size_t last_part        # part of the chain's last element (set when the chain ends)
    double start[2]         # programmed start of the chain's first element
    size_t *prov            # parts whose corner cross_join joined by a G1 (FIFO)
    size_t n_prov, head_prov, cap_prov
    int32_t err_number      # error found while writing (reported by compensate_feed)
    size_t err_part
    double err_arg

# ---- clearance.pyx: the contour window the path is measured against
cdef enum:
    CL_BLOCK = 16384        # parts of the chain whose contour window is held at a time
    CL_BATCH = 16           # pieces of the path that share one search of the boxes
    CL_GROUP = 256          # at most so many parts of the chain per group of the far check's boxes

ctypedef struct ClPiece:
    XPiece t                # a piece of the tool path waiting for its batch's search
    const XPiece *own       # arguments of cl_gap
    size_t skip_a, skip_b
    double r, stop

ctypedef struct Clearance:
    XPiece *el              # the programmed elements of the window, in part order
    double *off             # ... how far each one's end lies off its circle (arcs; lines 0)
    size_t n, cap
    BoxIndex ix             # the boxes of the window's elements
    double max_off          # the largest `off` of the window
    size_t lo, hi           # parts the window holds
    size_t el0, el_end      # the elements of the parts being walked (_cl_seam holds two ranges)
    size_t depth            # the window: parts at most this far apart are measured
    size_t span             # parts of the chain
    bint closed             # distances in parts wrap round the closed chain (_cl_seam)
    size_t *cand            # elements whose boxes meet the batch's box
    double *cbox            # ... their boxes, side by side (the inner loop reads only these)
    size_t n_cand, cap_cand
    ClPiece batch[CL_BATCH] # pieces queued by _cl_queue
    size_t n_batch
    size_t n_measured       # pieces of the batch _cl_flush measures (_cl_scan goes on after a gouge)
    bint loose              # an element was not measured because the piece's own crosses it
    bint only_far           # _cl_far_check: only parts farther apart than the depth count
    # per `group` parts of the chain from `first` on: the box of its measured pieces
    # grown by their radius (0..3) and the box of its contour elements (4..7); kept
    # only while `grouping` (a chain long enough for the far check)
    double *gbox
    size_t n_gbox, cap_gbox
    BoxIndex far_groups     # _cl_far_check: the groups' element boxes (not `far`: a macro of windef.h)
    int group_shift         # a group holds 1 << group_shift parts
    bint grouping
    # the chain being checked (cl_chain_open): parts before `next` are done, the tool
    # stands at `cur`, insertion `rec` is the next one; the block of parts [blo, bhi]
    size_t first, next, ins0, rec, blo, bhi, ei
    double cur[2]
    double allow
    bint started, in_block, first_piece

# ---- regions.pyx: the band's border split at its meets, the loop kept
ctypedef struct RSplit:
    size_t piece
    double pos              # distance along the piece from its start
    double x, y
    size_t node

ctypedef struct RSub:
    size_t piece
    double t0, t1
    double p0[2]
    double p1[2]
    size_t n0, n1           # nodes at its ends
    int64_t next            # the sub-piece the kept loop goes on with, -1 none
    uint8_t valid
    uint8_t on_part         # the kept loop: a tool side piece written to its element's part (else inserted)
    uint32_t seen           # the walk that reached it (_r_best_loop), 0 none

ctypedef struct Regions:
    CompEl *els             # the chain's elements, in order
    size_t n_els, cap_els
    XPiece *pc              # the pieces of the band's border
    size_t *pel             # element of each piece (a vertex circle: the element before it)
    uint8_t *pconn          # PIECE_*
    size_t *pn0             # nodes at the start and end of each piece
    size_t *pn1
    size_t n_pc, cap_pc
    size_t *alias           # nodes of touching ends: the node that stands for them
    size_t cap_alias
    size_t *out_start       # sub-pieces leaving each node: out_list[out_start[v] .. out_start[v + 1])
    size_t *out_list
    size_t cap_out_start, cap_out_list
    RSplit *sp
    size_t n_sp, cap_sp
    RSub *sub
    size_t n_sub, cap_sub
    size_t *loop            # sub-pieces of the loop kept, in order
    size_t cap_loop
    BoxIndex ix             # the boxes of the pieces (where they cross: _r_crossings)
    double end_slack        # a meet this close to a node two pieces share is their touch (_r_end_slack)

cdef enum:
    PIECE_TOOL = 0          # an element's offset on the tool side
    PIECE_FAR = 1           # ... on the other side, against the contour's direction
    PIECE_VERTEX = 2        # an arc of a vertex circle

cdef enum:
    REGIONS_NOT_APPLICABLE = 1  # not closed, several radii, no region, an arc not in program order
    KEPT_ON_PART = 1            # regions_rebuild: an element's piece written to its own part
    KEPT_INSERTED = 2           # ... inserted after a later part only

# ---- compensation.pyx: the pass
cdef enum:
    ROLE_NONE = 0           # not compensated: ce = e
    ROLE_SET = 1            # ce computed here
    ROLE_FOLLOW = 2         # no motion in the plane: ce = position of the previous part
    LOOKAHEAD_PARTS = 200   # blocks without motion in the plane a corner may span
    MAX_WARNINGS = 50

# 32 bytes: on a contour with many outer corners the queue holds about one record
# per two parts, so what the merge can read from the parts themselves is not stored:
# the arc centre is the programmed end of part `after` (the corner) and the radius
# that part's tool radius.
ctypedef struct InsRec:
    size_t after            # inserted right after this part
    double end[2]           # plane coordinates of its end
    double cc[2]            # arcs: plane coordinates of the centre (the programmed corner)
    int32_t func            # 1, 2, 3
    uint8_t src_next        # takes its attributes (line, feed, comp) from part after + 1, else after
    uint8_t no_centre       # centre 0, 0 in the plane (lines switching on or off)

# A warning, kept until the pass is over: compensate_end gives them from the thread
# that ends the compilation (a callback may then call back into the library, even
# DestroyCNC, as it may from the compiler's callbacks).
ctypedef struct CompWarning:
    const char *what        # WARN_COMP: a literal of this stage
    double depth            # WARN_COMP_GOUGE: how far the tool cuts into the contour, mm
    uint32_t line
    int32_t file_idx
    int32_t number          # WARN_COMP, WARN_COMP_GOUGE; 0: "further warnings suppressed"

ctypedef struct CompState:
    ProgramBuilder *build   # the merge grows its parts
    Program *prog           # &view while compensate_feed runs, else &build.prog
    # compensate_feed's copy of what it reads of the program's header (the arrays'
    # addresses, the strategy regions, the start), taken at each batch (the arrays move
    # only between batches; compensation.pyx _view_take): the compiler writes n_parts,
    # n_extras and n_pars with every part, on the cache line that also holds the
    # addresses, and a thread beside it reading them there would pull that line away
    # from it at every access
    Program view
    const GCODE_PARAMETERS *params
    ErrorInfo *err
    output_fn output
    warn_fn warn
    void *ctx
    CompCfg cfg
    bint strict             # GCODE_REZERVA1_COMP_STRICT: what cannot be removed is error 504
    # the chain being read keeps what crosses as the offsets give it (no error 504, no
    # rebuild): warning 601 where the tool cuts into the contour. Without 0x80000 and
    # the strict switch; with 0x80000, the second reading of a chain (_chain_retry)
    bint lenient
    bint retrying           # _chain_retry reads the chain again
    int first, second, normal
    uint8_t *role
    CompEl *st              # stack of open elements of the current chain
    size_t n_st, cap_st
    InsRec *ins
    size_t n_ins, cap_ins
    size_t ready_ins        # bytes of ins faulted in ahead (arrays.pxd ready_ahead)
    int64_t entry_part      # ramp whose end is the start of the chain's first element
    bint next_fixed         # the next chain starts at an uncompensated point
    int n_warnings
    CompWarning warnings[MAX_WARNINGS]
    bint has_followers      # some compensated part has no motion in the plane
    bint dropped            # some arc left the cutting plan (FLAG_DROPPED): the parts are numbered again
    XState xs               # crossings of parts that are not neighbours (crossings.pyx)
    Clearance cl            # the contour the tool path keeps away from (clearance.pyx)
    Regions rg              # a chain rebuilt from its regions (regions.pyx)
    # the chain being read: parts chain_first .. chain_last (its elements), what was
    # queued before it, and how it started; chain_global: the chain is rebuilt from its
    # regions at its end (0x80000 after a crossing or gouge the corners could not cut)
    bint chain_open
    bint chain_global
    bint chain_rebuilt      # the chain that just ended was rebuilt
    size_t chain_first, chain_last
    double chain_radius     # the largest tool radius of its elements (0: its path is its contour, not measured)
    int64_t chain_entry     # its entry ramp (a part ending where the chain starts), -1 none
    bint chain_fixed        # it starts at an uncompensated point (strategy 1)
    bint chain_entry_arc    # ... on an arc right after the G41/G42 block (S.entry_arc)
    bint chain_exit_fixed   # it ends at an uncompensated point (strategy 1 before G40)
    size_t chain_ins0       # insertions queued before it
    int chain_warn0         # warnings kept before it
    ErrorInfo chain_err     # the error that made it global (reported if the rebuild fails)
    CompCfg host            # the host's strategy (run_config changes it per run)
    size_t region           # next strategy region (run_config)
    size_t next             # first part compensate_feed has not taken yet
    size_t cap_role
    int result              # COMPILE_OK, or the first failure (err filled)
    # the run being read (parts with comp 41/42)
    bint in_run
    int plane
    size_t idle             # parts without motion in the plane since the last one with
    bint first_motion       # the G41/G42 block is still to come
    bint entry_arc          # ... it was an arc: the chain starts on it
    bint g0_never
    # after a run: the first move in the plane must be linear (G40 on an arc is an error)
    bint exit_check
    size_t exit_from

# ---- insert_arcs.pyx: one G167 arc to insert
ctypedef struct ArcIns:
    size_t after            # inserted right after this part (the shortened first line)
    double end[2]           # tangent point on the second line (plane coordinates)
    double cc[2]            # centre
    double radius
    int32_t func            # 2 CW, 3 CCW
    int16_t plane

ctypedef struct ArcInsertions:     # program_merge's context: the arcs, and where their records go
    ArcIns *items
    ProgramBuilder *build


# ---- what other stages call
# the compiler: the G172 / G173 strategy and the G167 settings from programmed part
# `first` on (False: out of memory)
cdef bint program_add_strategy_region(ProgramBuilder *build, size_t first, bint on, double corner_distance,
                                      double depth, bint drop_arcs) noexcept nogil
cdef bint program_add_arc_region(ProgramBuilder *build, size_t first, bint on, int32_t plane,
                                 double tol_max, double tol_min, double max_angle) noexcept nogil
# the core's compile worker: the pass over build.prog, fed beside the compiler
# (compensate_feed is a pipeline consume_fn), ended by the merge of its insertions
# (watch: a stage reading the merged parts, may be NULL); COMPILE_OK or err filled.
# `settle`: when the merge would insert nothing and only move the parts without motion
# in the plane to the position they sit at, that is left to join_lines' pass (which
# visits every part anyway) and *settle gets the parts' roles for it; NULL: the merge
# does it
cdef void compensate_begin(CompState *S, ProgramBuilder *build, const GCODE_PARAMETERS *params, ErrorInfo *err,
                           output_fn output, warn_fn warn, void *ctx) noexcept nogil
cdef int compensate_feed(void *ctx, size_t upto, bint last, size_t *more) noexcept nogil
cdef int compensate_end(CompState *S, const MergeWatch *watch, uint8_t **settle) noexcept nogil
cdef void compensate_free(CompState *S) noexcept nogil
# ... then the G167 arcs between G1 lines of the compensated program (idle: it inserts
# none, whatever the parts)
cdef int insert_arcs(ProgramBuilder *build, const GCODE_PARAMETERS *params, ErrorInfo *err) noexcept nogil
cdef bint insert_arcs_idle(const Program *prog, const GCODE_PARAMETERS *params) noexcept nogil
# ... then tolerance[4] on the uncompensated arcs and the nearly collinear G1 parts
# joined (tolerance[2], [3]; join_lines.pyx), before the extent and the plan; `number`:
# nothing is inserted after it, so it numbers the parts it keeps (program_number_parts);
# `settle`: compensate_end's roles (freed here), or NULL; `watch` (may be NULL) hears
# how far the parts are final (the plan made beside it, pipeline.pyx); `extent` (may be
# NULL): the extent measured beside the merge, *extent_holds: it is still the program's
cdef int join_lines(ProgramBuilder *build, const GCODE_PARAMETERS *params, bint number,
                    uint8_t *settle, const PartsWatch *watch, const GCODE_INFO *extent,
                    bint *extent_holds) noexcept nogil
# a part without motion in the plane takes the compensated position it sits at (`cur`:
# the previous part's compensated end, or the program's start)
cdef void settle_follower(Part *p, const double *cur) noexcept nogil
