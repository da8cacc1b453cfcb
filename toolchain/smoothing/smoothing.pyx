# Smoothing of the machine's output (docs/smoothing.md, which derives both filters):
# the positions of ten axes, one sample per machine step, pass the spline, then the
# IIR filter.
#
# The spline delays every axis by the buffer's `span` samples. Each new sample is
# written into the buffer; the sample half a buffer back is checked: where an axis's
# third difference (its jerk times period^3) exceeds the limit, the buffer from the
# last sample given out to two samples before the newest is replaced, on every axis
# together, by the quintic that continues the output given so far and joins the
# input there with the same position, velocity and acceleration (all three taken
# from three samples on each side). Elsewhere the output is the input, span samples
# later, bit for bit.
#
# The IIR filter is H(s) = q / ((s/w)^2 + p (s/w) + q), w = 2 pi / f, on the axes of
# its mask, discretised exactly for an input held over each period: the state
# (position - input, velocity) advances by the 2x2 matrix exponential of one period.
from libc.stdlib cimport free
from libc.string cimport memcpy
from libc.math cimport exp, expm1, cos, sin, sqrt, fabs, floor, M_PI, INFINITY

cdef extern from *:
    """
    #define TC_SMOOTHING_MAX 1e12     /* the largest register value: jerk mm/s^3, p q f x 1e6 */
    #define TC_SETTLED_MM 1e-6        /* the filtered output has settled within this of its input, mm */
    #define TC_IIR_TAU_MAX 1.0        /* the IIR filter's slowest time constant, s: a stopped machine
                                         rests within ~30 tau of a step across the 1e6 mm range */
    #define TC_IIR_PER_REGISTER 1e-6  /* p, q and f per unit of their registers (which hold them x 1e6) */
    #define TC_IIR_SERIES_BELOW 1e-6  /* |d| T^2 below which the transition's three-term series is
                                         exact to the last bit (the next term, x^3 / 720, < 2e-21) */
    """
    double TC_SMOOTHING_MAX
    double TC_SETTLED_MM
    double TC_IIR_TAU_MAX
    double TC_IIR_PER_REGISTER
    double TC_IIR_SERIES_BELOW


cdef bint _parameter_error(ErrorInfo *err, int32_t command, int index, double value, const char *why) noexcept nogil:
    """Error 740 naming Command_Parameter[index]; False (the setting is refused)."""
    err_smoothing(err, -1, 0, command, index, value, why)
    return False


cdef bint smoothing_check_parameter(int32_t command, int index, double value, ErrorInfo *err) noexcept nogil:
    """One register value on its own (command -2 or -1, index 0..3): False with err
    (ERR_SMOOTHING) saying why not. The values that must go together:
    smoothing_check."""
    if not isfinite(value) or value < 0.0 or value > TC_SMOOTHING_MAX:
        return _parameter_error(err, command, index, value, "not a number in <0, 1e12>")
    if command == SMOOTHING_COMMAND_SPLINE and index == 0 and (
            value != floor(value) or (value != 0.0 and not (SPLINE_POINTS_MIN <= value <= SPLINE_POINTS_MAX))):
        return _parameter_error(err, command, index, value, "the spline's buffer: 0 (off) or 50..500 steps")
    if command == SMOOTHING_COMMAND_IIR and index == 3 and (value != floor(value) or value > 4294967295.0):
        return _parameter_error(err, command, index, value, "the IIR filter's axes: a bit mask, a whole number below 2^32")
    return True


cdef bint smoothing_check(const SmoothingConfig *config, int32_t command, ErrorInfo *err) noexcept nogil:
    """The values of one command together: a spline that is on needs its jerk limit,
    an IIR filter on some axis needs p, q and f. False with err naming the first
    value missing."""
    cdef int k
    cdef double tau
    cdef char why[160]
    if command == SMOOTHING_COMMAND_SPLINE and config.spline[0] != 0.0 and config.spline[1] == 0.0:
        return _parameter_error(err, command, 1, 0.0, "a spline that is on needs a jerk limit above 0 mm/s^3")
    if command == SMOOTHING_COMMAND_IIR and (<uint32_t>config.iir[3] & 0x3FF) != 0:
        for k in range(3):
            if config.iir[k] == 0.0:
                return _parameter_error(err, command, k, 0.0, "an IIR filter on some axis needs p, q and f above 0")
        tau = _iir_slowest_time(config.iir[0] * TC_IIR_PER_REGISTER, config.iir[1] * TC_IIR_PER_REGISTER,
                                config.iir[2] * TC_IIR_PER_REGISTER)
        if not (tau <= TC_IIR_TAU_MAX):
            c_snprintf(why, sizeof(why), "with p, q and f the filter's slowest time constant is %g s, "
                       "above 1 s: a stopped machine would not come to rest", tau)
            return _parameter_error(err, command, 0, config.iir[0], why)
    return True


cdef double _iir_slowest_time(double p, double q, double f) noexcept nogil:
    """1 / the decay rate of H(s)'s slower pole (s); inf when p, q and f overflow the
    filter's coefficients (w = 2 pi / f, a1 = p w, a0 = q w^2). Overdamped, the slow
    pole's rate is a1/2 - sqrt(a1^2/4 - a0), written a0 / (a1/2 + sqrt(..)) so that it
    does not cancel; otherwise it is a1/2."""
    cdef double w = 2.0 * M_PI / f
    cdef double a1 = p * w, a0 = q * w * w
    cdef double d = 0.25 * a1 * a1 - a0
    if not (isfinite(a1) and isfinite(a0) and isfinite(d) and a1 > 0.0 and a0 > 0.0):
        return INFINITY
    if d > 0.0:
        return (0.5 * a1 + sqrt(d)) / a0
    return 2.0 / a1


cdef bint smoothing_set(SmoothingConfig *config, int32_t command, const double *params, ErrorInfo *err) noexcept nogil:
    """The Interpolator's command -2 (spline: params[0..1]) or -1 (IIR filter:
    params[0..3]) with the vendor's units into *config, which changes only when every
    value is good; False with err (ERR_SMOOTHING) otherwise."""
    cdef SmoothingConfig candidate = config[0]
    cdef int k
    cdef int n = 2 if command == SMOOTHING_COMMAND_SPLINE else 4
    for k in range(n):
        if not smoothing_check_parameter(command, k, params[k], err):
            return False
        if command == SMOOTHING_COMMAND_SPLINE:
            candidate.spline[k] = params[k]
        else:
            candidate.iir[k] = params[k]
    if not smoothing_check(&candidate, command, err):
        return False
    config[0] = candidate
    return True


# ------------------------------------------------------------------ the filters

cdef void _iir_transition(Smoother *s, double p, double q, double f) noexcept nogil:
    """phi = exp(A T) of x' = A x, x = (position - input, velocity), A = [[0, 1],
    [-a0, -a1]], a1 = p w, a0 = q w^2. With sigma = -a1/2 and d = sigma^2 - a0,
    M = A - sigma I squares to d I, so exp(A T) = e^(sigma T) (C I + S M) where
    C, S = cosh, sinh(rT)/r (r^2 = d > 0), cos, sin(rT)/r (r^2 = -d), or their series
    when d T^2 is small. e^(sigma T) cosh and sinh are written with e^((sigma + r) T)
    and e^(-2 r T), both at most 1: nothing overflows however fast the filter."""
    cdef double T = s.period
    cdef double w = 2.0 * M_PI / f
    cdef double a1 = p * w, a0 = q * w * w
    cdef double sigma = -0.5 * a1, d = sigma * sigma - a0
    cdef double ec, es, r, e_high, shrink, x
    if fabs(d) * T * T < TC_IIR_SERIES_BELOW:
        x = d * T * T
        ec = exp(sigma * T) * (1.0 + x / 2.0 + x * x / 24.0)
        es = exp(sigma * T) * T * (1.0 + x / 6.0 + x * x / 120.0)
    elif d > 0.0:
        r = sqrt(d)
        e_high = exp((sigma + r) * T)       # the slower pole's decay: sigma + r < 0, at most 1
        shrink = -expm1(-2.0 * r * T)       # 1 - e^(-2rT), in (0, 1]
        ec = e_high * (1.0 - 0.5 * shrink)
        es = e_high * shrink / (2.0 * r)
    else:
        r = sqrt(-d)
        ec = exp(sigma * T) * cos(r * T)
        es = exp(sigma * T) * sin(r * T) / r
    s.phi[0][0] = ec - sigma * es
    s.phi[0][1] = es
    s.phi[1][0] = -a0 * es
    s.phi[1][1] = ec + sigma * es
    s.omega = sqrt(a0)


cdef bint smoother_init(Smoother *s, const SmoothingConfig *config, double period, const double *start) noexcept nogil:
    """The filters of `config` for samples `period` seconds apart, standing at
    `start` (ten axes) since ever; False when out of memory (nothing to free)."""
    cdef uint64_t row, rows
    cdef int k
    s.period = period
    s.span = <int32_t>config.spline[0]
    s.jerk_step = config.spline[1] * period * period * period
    s.ring = NULL
    s.pushed = 2 * <uint64_t>s.span + 8         # a standing past, longer than the buffer and its history
    s.spliced_to = 0
    s.unchanged = s.pushed
    for k in range(3):
        memcpy(s.history[k], start, sizeof(s.history[k]))
    if s.span > 0:
        rows = <uint64_t>s.span + 1
        s.ring = <double *>tc_malloc(rows * SMOOTHING_AXES * sizeof(double))
        if s.ring == NULL:
            return False
        for row in range(rows):
            memcpy(s.ring + row * SMOOTHING_AXES, start, SMOOTHING_AXES * sizeof(double))
    s.iir_axes = <uint32_t>config.iir[3] & 0x3FF
    if s.iir_axes != 0:
        _iir_transition(s, config.iir[0] * TC_IIR_PER_REGISTER, config.iir[1] * TC_IIR_PER_REGISTER,
                        config.iir[2] * TC_IIR_PER_REGISTER)
    memcpy(s.held, start, sizeof(s.held))
    memcpy(s.position, start, sizeof(s.position))
    for k in range(SMOOTHING_AXES):
        s.velocity[k] = 0.0
    return True


cdef bint smoothing_sample_good(const double *sample) noexcept nogil:
    """A sample (ten axes) the filters take: every axis within the address words'
    bound (+-1e30 mm), so that no difference or spliced polynomial overflows."""
    cdef int a
    for a in range(SMOOTHING_AXES):
        if not (-TC_MAX_WORD_VALUE <= sample[a] <= TC_MAX_WORD_VALUE):
            return False
    return True


cdef void smoother_free(Smoother *s) noexcept nogil:
    """Frees the spline's buffer."""
    free(s.ring)
    s.ring = NULL


cdef inline double *_row(Smoother *s, uint64_t sample) noexcept nogil:
    """The row of the ring buffer that holds `sample` (ten axes)."""
    return s.ring + (sample % (<uint64_t>s.span + 1)) * SMOOTHING_AXES


cdef void _splice(Smoother *s, uint64_t k) noexcept nogil:
    """Replaces samples k - span .. k - 3 by the quintic from the last sample given
    out (k - span - 1) to sample k - 2, matching position, velocity and acceleration
    at both ends (one-sided three-point differences). In samples as the unit of time:
    the period cancels."""
    cdef double m = s.span - 1                  # the quintic's length in samples
    cdef double *e0 = _row(s, k - 2)
    cdef double *e1 = _row(s, k - 1)
    cdef double *e2 = _row(s, k)
    cdef double *h0 = s.history[0]
    cdef double *h1 = s.history[1]
    cdef double *h2 = s.history[2]
    cdef double c1[10]
    cdef double c2[10]
    cdef double c3[10]
    cdef double c4[10]
    cdef double c5[10]
    cdef double v0, a0, v1, a1, P, V, A, tau
    cdef double *row
    cdef uint64_t j
    cdef int a
    for a in range(SMOOTHING_AXES):
        v0 = 0.5 * (3.0 * h0[a] - 4.0 * h1[a] + h2[a]) * m      # velocity x length
        a0 = (h0[a] - 2.0 * h1[a] + h2[a]) * m * m               # acceleration x length^2
        v1 = 0.5 * (-3.0 * e0[a] + 4.0 * e1[a] - e2[a]) * m
        a1 = (e0[a] - 2.0 * e1[a] + e2[a]) * m * m
        P = e0[a] - h0[a] - v0 - 0.5 * a0
        V = v1 - v0 - a0
        A = a1 - a0
        c1[a] = v0
        c2[a] = 0.5 * a0
        c3[a] = 10.0 * P - 4.0 * V + 0.5 * A
        c4[a] = -15.0 * P + 7.0 * V - A
        c5[a] = 6.0 * P - 3.0 * V + 0.5 * A
    for j in range(k - s.span, k - 2):
        tau = (j - (k - s.span - 1)) / m
        row = _row(s, j)
        for a in range(SMOOTHING_AXES):
            row[a] = h0[a] + tau * (c1[a] + tau * (c2[a] + tau * (c3[a] + tau * (c4[a] + tau * c5[a]))))
    s.spliced_to = k - 3


cdef void _spline_push(Smoother *s, const double *sample, double *out) noexcept nogil:
    """The spline's step: the sample into the buffer; where the third difference at the buffer's
    middle exceeds the jerk limit the buffer is spliced (_splice); out: the sample `span` steps
    back, the output's delay."""
    cdef uint64_t k = s.pushed
    cdef uint64_t c = k - <uint64_t>(s.span / 2) - 2     # the sample checked: the quintic's middle
    cdef double *newest = _row(s, k)
    cdef double *before = _row(s, k - 1)
    cdef double *r0
    cdef double *r1
    cdef double *r2
    cdef double *r3
    cdef bint same = True
    cdef int a
    for a in range(SMOOTHING_AXES):
        same = same and sample[a] == before[a]
    s.unchanged = s.unchanged + 1 if same else 0
    memcpy(newest, sample, SMOOTHING_AXES * sizeof(double))
    s.pushed += 1
    if c > s.spliced_to:
        r0 = _row(s, c - 2)
        r1 = _row(s, c - 1)
        r2 = _row(s, c)
        r3 = _row(s, c + 1)
        for a in range(SMOOTHING_AXES):
            if fabs(r3[a] - 3.0 * r2[a] + 3.0 * r1[a] - r0[a]) > s.jerk_step:
                _splice(s, k)
                break
    memcpy(s.history[2], s.history[1], sizeof(s.history[2]))
    memcpy(s.history[1], s.history[0], sizeof(s.history[1]))
    memcpy(s.history[0], _row(s, k - s.span), sizeof(s.history[0]))
    memcpy(out, s.history[0], SMOOTHING_AXES * sizeof(double))


cdef void smoother_push(Smoother *s, const double *sample, double *out) noexcept nogil:
    """The next sample of ten axes in; the smoothed one out (out may be sample)."""
    cdef double x[10]
    cdef double e, v
    cdef int a
    if s.span > 0:
        _spline_push(s, sample, x)
    else:
        memcpy(x, sample, sizeof(x))
    for a in range(SMOOTHING_AXES):
        if s.iir_axes & (1u << a):
            # the input x[a] held over the period from here: one exact step
            s.held[a] = x[a]
            e = s.position[a] - x[a]
            v = s.velocity[a]
            s.position[a] = x[a] + s.phi[0][0] * e + s.phi[0][1] * v
            s.velocity[a] = s.phi[1][0] * e + s.phi[1][1] * v
            x[a] = s.position[a]
    memcpy(out, x, sizeof(x))


cdef bint smoother_settled(const Smoother *s) noexcept nogil:
    """The output has settled on the input: the sample given out last, and every one
    after it while the input stands still, is the last input's within TC_SETTLED_MM
    (the spline: exactly). The spline has settled when its buffer and the three
    samples it gave out last are the last input's, and none of them was spliced;
    the IIR filter when each filtered axis is within TC_SETTLED_MM of its input and
    moves slower than TC_SETTLED_MM x its natural angular frequency."""
    cdef int a
    if s.span > 0 and not (s.unchanged >= <uint64_t>s.span + 3
                           and s.spliced_to + <uint64_t>s.span + 3 < s.pushed - 1):
        return False
    for a in range(SMOOTHING_AXES):
        if s.iir_axes & (1u << a):
            if fabs(s.position[a] - s.held[a]) > TC_SETTLED_MM or fabs(s.velocity[a]) > TC_SETTLED_MM * s.omega:
                return False
    return True
