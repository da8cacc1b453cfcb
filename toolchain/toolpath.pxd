# Face of toolpath.pyx: the compiled program as TC_TOOLPATH_RECORDs in one copy
# (GetToolpath). Called by the exports.

# ToolChainCore_GetToolpath after its argument checks
cdef int32_t toolpath_copy(Core *core, TC_TOOLPATH_RECORD *out, uint64_t capacity, uint64_t first,
                           uint64_t *total) noexcept nogil
