# cython: language_level=3, boundscheck=False, wraparound=False, cdivision=True
# cython: initializedcheck=False, nonecheck=False, overflowcheck=False
#
# Test-only: the library (every stage, toolchain/libSF_TCh.pyx) with a synchronous
# compilation for the coverage-guided fuzzer (fuzz_main.c, tests/test_fuzz.py), so that
# one input is one call on the fuzzer's thread. The readers of the tool table, the axis
# tables and the INI file are synchronous exports already; fuzz_main.c calls those.
include "libSF_TCh.pyx"

from libc.stdlib cimport malloc


cdef public int32_t sf_tch_fuzz_compile(const char *data, size_t size, int32_t iso) noexcept nogil:
    """Compiles `size` bytes as the text of a program file (the ISO mode for iso != 0,
    else TG's dialect) as core 0's compile worker does -- the compiler with the
    compensation beside it, G167's arcs, the extent, the plan -- on this thread, and
    frees the program: 0 when it compiled, else the error's number."""
    cdef Core *core = core_get(0)
    cdef CompileJob job
    cdef ProgramBuilder build
    cdef GCODE_INFO extent
    cdef ErrorInfo err
    cdef int result
    cdef int k
    memset(&job, 0, sizeof(job))
    memset(&err, 0, sizeof(err))
    job.text = <char *>malloc(size + 1)
    if job.text == NULL:
        return ERR_OUT_OF_MEMORY
    memcpy(job.text, data, size)
    job.text[size] = 0
    job.length = size
    strncpy(job.name, "fuzz.nc", sizeof(job.name) - 1)
    job.files[0] = core_file_to_idx(core, "fuzz.nc")
    job.files[1] = job.files[2] = -1
    if iso:
        core.params.rezerva1 |= GCODE_REZERVA1_ISO_COMPAT
    else:
        core.params.rezerva1 &= ~GCODE_REZERVA1_ISO_COMPAT
    for k in range(8):
        core.params.correction[k].size = 0.5       # G41..G48 compensate: the compensation runs
    TC_ATOMIC_STORE(&core.cancel, 0)
    program_builder_init(&build)
    result = _compile_job(core, &job, &build, &extent, &err)
    program_builder_free(&build)
    free(job.text)
    return 0 if result == COMPILE_OK else err.number


cdef public void sf_tch_fuzz_cancel() noexcept nogil:
    """Cancels the compilation running (as ResetCNC does): the fuzzer's watchdog ends an
    input that runs too long (an endless loop runs to the part limit otherwise)."""
    TC_ATOMIC_STORE(&core_get(0).cancel, 1)
