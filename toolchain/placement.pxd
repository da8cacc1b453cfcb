# Face of placement.pyx: where a compiled program runs. A run starts from the
# machine position of its own moment; the axes the program has not named absolutely
# follow it (Program.start_gindex). Owns Placement, the difference a reader applies
# (the program itself is never rewritten). Called by the core (GetGCodeSizeInfo), the
# planner (a placed run's plan), the simulator, the machine, the connection search and
# the toolpath; how far a run moves a part, and its geometry there: geometry.pxd
# (placement_shift, segment_of_placed_part).

ctypedef struct Placement:
    double start[AXES]      # where the run starts (machine position)
    double delta[AXES]      # start - the compile's start
    bint moved              # some delta is not 0


# axis k of part p follows the run's start (not yet named absolutely)
cdef inline bint follows_start(const Program *prog, const Part *p, int k) noexcept nogil:
    return p.gcode_index < prog.start_gindex[k]


# a run from `start`; the parts before placement_reshaped_end may change their shape
# in it (the others only move); a part as that run sees it; GetGCodeSizeInfo of that run
cdef void placement_init(Placement *pl, const Program *prog, const double *start) noexcept nogil
cdef size_t placement_reshaped_end(const Program *prog, const Placement *pl) noexcept nogil
cdef void placed_part_to_gm(const Program *prog, size_t i, const Placement *pl,
                            SIMPLE_GM_PARAMS *gm) noexcept nogil
cdef bint placed_extent(const Program *prog, const Placement *pl, GCODE_INFO *info) noexcept nogil
