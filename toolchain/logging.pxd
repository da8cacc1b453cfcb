# Face of logging.pyx: the library's log (SetLogValue's mask of sources and
# outputs, the file SF_TCh.log, stderr, the host's hook). Callable from any thread.
# Owns the mask and the hook; called by the exports (the log calls of the API), the
# core and the callbacks (what they log).

ctypedef void (*LogHook)(intptr_t, uint32_t, const char *) noexcept nogil


cdef uint32_t g_log_mask          # zero: nothing is logged until SetLogValue (written by log_set_mask)


# ToolChainCore_Init's directory, SetLogValue, one line of a source, the host's hook,
# the file flushed
cdef void log_set_dir(const char *directory) noexcept nogil
cdef void log_set_mask(uint32_t mask) noexcept nogil
cdef void log_line(uint32_t source, const char *text) noexcept nogil
cdef int32_t log_set_hook(intptr_t user, void *fn) noexcept nogil
cdef void log_flush() noexcept nogil
