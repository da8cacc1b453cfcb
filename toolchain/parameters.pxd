# Face of parameters.pyx: the parameters a host gives a core (GCODE_PARAMETERS,
# MACHINE_PARAMETERS): their defaults, the bounds every value keeps, and the INI
# keys. Owns IniSettings (what LoadFromIni reads into). Called by the exports (Set*,
# LoadFromIni) and the core (defaults).

ctypedef struct IniSettings:
    # what LoadFromIni reads into, a copy of the core's configuration: the file is
    # read and parsed without the core's lock, and stored only when all of it is good
    GCODE_PARAMETERS params
    char driver[256]
    int64_t plan_window     # [GCodeParameters] lookAheadParts (the core's, see SetLookAhead)
    double time_scale       # [Offline] TimeScale (the core's, see SetTimeScale)
    const char *path
    ErrorInfo *err


# the documented defaults; the bounds of Set*Parameters (err filled when refused),
# the clamp of overrideInc; finite presets and coordinates; LoadFromIni's visitor
cdef void default_gcode_parameters(GCODE_PARAMETERS *p) noexcept nogil
cdef bint check_gcode_parameters(const GCODE_PARAMETERS *p, ErrorInfo *err) noexcept nogil
cdef bint check_machine_parameters(const MACHINE_PARAMETERS *m, ErrorInfo *err) noexcept nogil
cdef void normalise_gcode_parameters(GCODE_PARAMETERS *p) noexcept nogil
cdef bint user_params_finite(const double *values) noexcept nogil
cdef bint coordinates_finite(const double *values, uint32_t n) noexcept nogil
cdef int32_t ini_apply_setting(void *ctx, const char *section, const char *key, const char *value,
                               int32_t line) noexcept nogil
