# Compiled programs with an owner count. The compile worker publishes a program once
# it is complete; from then on nobody writes it. The core holds one reference, and
# every run that reads it holds its own, so replacing or dropping the core's program
# (a new compilation, DestroyCNC) never frees parts under a reader: the last
# release does.
from libc.stdlib cimport free


cdef LoadedProgram *loaded_program_new(Program *prog, const GCODE_INFO *extent,
                                       const int32_t *files) noexcept nogil:
    """Takes over `prog` (left empty) with one reference; NULL when out of memory
    (prog untouched)."""
    cdef LoadedProgram *lp = <LoadedProgram *>tc_calloc(1, sizeof(LoadedProgram))
    if lp == NULL:
        return NULL
    lp.refs = 1
    lp.prog = prog[0]
    lp.extent = extent[0]
    lp.files[0] = files[0]
    lp.files[1] = files[1]
    lp.files[2] = files[2]
    program_init(prog)
    return lp


cdef LoadedProgram *loaded_program_ref(LoadedProgram *lp) noexcept nogil:
    """One more reference (lp may be NULL). The caller must already own one, or hold
    the lock of the core that does."""
    if lp != NULL:
        TC_REF_ADD(&lp.refs)
    return lp


cdef void loaded_program_release(LoadedProgram *lp) noexcept nogil:
    """Drops a reference (lp may be NULL); the last one frees the program. Never
    called under a core's lock: freeing a large program takes time."""
    if lp != NULL and TC_REF_SUB(&lp.refs) == 0:
        program_free(&lp.prog)
        free(lp)
