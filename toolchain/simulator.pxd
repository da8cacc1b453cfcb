# Face of simulator.pyx: runs of a compiled program in the core's worker,
# simulation (regime 10) and test (regime 20). Called by the lifecycle.

# the worker of a simulation or test (a RunJob)
cdef void *simulation_body(void *arg) noexcept nogil
