# Face of extent.pyx: the extent of a compiled program (GetGCodeSizeInfo), measured
# over every motion part with arcs' true extreme points, in one pass or range by
# range. Called by the pipeline (beside the merge and the plan) and by placement
# (the extent of a program run from elsewhere).

cdef enum:
    NO_MOTION = -1          # extent_range: no motion part in the range


# both extents (programmed, tool path) at the program's start, widened by a range of
# parts, finished into GetGCodeSizeInfo's four; the whole program in one go
cdef size_t extent_range(const Program *prog, size_t first, size_t end, GCODE_SIZE *programmed,
                         GCODE_SIZE *tool, bint rotated) noexcept nogil
cdef void extent_begin(const Program *prog, GCODE_SIZE *programmed, GCODE_SIZE *tool) noexcept nogil
cdef void extent_finish(const Program *prog, size_t last, GCODE_SIZE *programmed, GCODE_SIZE *tool,
                        GCODE_INFO *info) noexcept nogil
cdef void program_extent(const Program *prog, GCODE_INFO *info) noexcept nogil
