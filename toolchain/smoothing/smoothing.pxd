# Face of the smoothing stage: the spline and the IIR filter over the offline
# machine's output positions, sampled at the machine's fixed step (the vendor's
# trajectory smoothing; docs/smoothing.md derives both). Pure: a Smoother is pushed
# one sample of ten axes at a time and gives the smoothed sample; it says when its
# output has settled on a standing input.
#   smoothing.pyx   the configuration in the vendor's units (Command -2 / -1 and
#                   Command_Parameter[0..3]), the spline, the IIR filter, the predicate
# Owns SmoothingConfig (the core's: core.pxd; LoadFromIni's: parameters.pxd) and
# Smoother. Called by the exports and LoadFromIni (configuration,
# ToolChainCore_SmoothSamples) and the offline machine, whose every step's position
# passes it (machine/output.pyx).

cdef enum:
    SMOOTHING_COMMAND_IIR = -1          # the Interpolator's Command register: IIR filter parameters
    SMOOTHING_COMMAND_SPLINE = -2       # ... spline parameters
    SPLINE_POINTS_MIN = 50              # Command_Parameter[0] of -2: 0 (off) or 50..500 steps
    SPLINE_POINTS_MAX = 500
    SMOOTHING_AXES = 10

# A core's smoothing, as the vendor's registers hold it (the values are kept as
# given, so reading them back gives what was set):
#   spline[0]  Command -2, Command_Parameter[0]: the spline's buffer in steps, 0 = off
#   spline[1]  Command -2, Command_Parameter[1]: the jerk limit, mm/s^3
#   iir[0]     Command -1, Command_Parameter[0]: p x 1e6
#   iir[1]     Command -1, Command_Parameter[1]: q x 1e6
#   iir[2]     Command -1, Command_Parameter[2]: f x 1e6, f in seconds
#   iir[3]     Command -1, Command_Parameter[3]: the axes filtered, bit k = axis k; 0 = off
ctypedef struct SmoothingConfig:
    double spline[2]
    double iir[4]

# The filters' state over one stream of samples.
ctypedef struct Smoother:
    double period               # s between two samples
    # the spline: a buffer of span + 1 samples, spliced in place where the jerk exceeds
    int32_t span                # the buffer in steps (the output's delay); 0: off
    double jerk_step            # the jerk limit times period^3: the largest third difference
    double *ring                # (span + 1) x 10 samples; sample i at row i % (span + 1)
    uint64_t pushed             # samples in the stream so far, the span standing samples before the first counted
    uint64_t spliced_to         # samples up to this one were spliced: not looked at again
    double history[3][10]       # the last three samples given out, newest first
    uint64_t unchanged          # pushes in a row equal to the one before
    # the IIR filter: position and velocity of each filtered axis, advanced exactly
    uint32_t iir_axes           # bit k: axis k is filtered
    double phi[2][2]            # the transition of (position - input, velocity) over one period
    double omega                # natural angular frequency sqrt(q) * 2 pi / f, 1/s
    double held[10]             # the filter's input over the last period
    double position[10]
    double velocity[10]


# ---- what other stages call

# the configuration: one register value of command -2 or -1 on its own (the INI's
# keys), the values of one command together, a command's values set all or nothing;
# each False with err (ERR_SMOOTHING) saying why
cdef bint smoothing_check_parameter(int32_t command, int index, double value, ErrorInfo *err) noexcept nogil
cdef bint smoothing_check(const SmoothingConfig *config, int32_t command, ErrorInfo *err) noexcept nogil
cdef bint smoothing_set(SmoothingConfig *config, int32_t command, const double *params, ErrorInfo *err) noexcept nogil

# a stream of samples: the filters standing at `start` (False: out of memory), one
# sample in and the smoothed one out, whether the output has settled, the buffer freed
cdef bint smoother_init(Smoother *s, const SmoothingConfig *config, double period, const double *start) noexcept nogil
cdef void smoother_push(Smoother *s, const double *sample, double *out) noexcept nogil
cdef bint smoother_settled(const Smoother *s) noexcept nogil
cdef void smoother_free(Smoother *s) noexcept nogil
# a sample the filters take (ToolChainCore_SmoothSamples refuses others)
cdef bint smoothing_sample_good(const double *sample) noexcept nogil
