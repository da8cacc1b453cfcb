# Face of simulator.pyx: runs of a compiled program in the core's worker,
# simulation (regime 10) and test (regime 20); core_start_run starts any run, the
# offline machine's (machine/) included. Called by the exports (StartCNCEx) and the
# machine (a run's addCode).

# StartCNCEx's addCode: its M words sent before the program; StartCNCEx itself
cdef void send_add_code(Core *core, const char *code, const double *position) noexcept nogil
cdef int32_t core_start_run(Core *core, int32_t regime, const char *add_code) noexcept nogil
