# Face of simulator.pyx: runs of a compiled program in the core's worker,
# simulation (regime 10) and test (regime 20). Called by the lifecycle (its worker)
# and the machine (a run's addCode).

# StartCNCEx's addCode: its M words sent before the program; the worker of a
# simulation or test (a RunJob)
cdef void send_add_code(Core *core, const char *code, const double *position) noexcept nogil
cdef void *simulation_body(void *arg) noexcept nogil
