# Face of parameters.pyx: the parameters a host gives a core (GCODE_PARAMETERS,
# MACHINE_PARAMETERS): their defaults, the bounds every value keeps, and the INI
# keys. Owns IniSettings (what LoadFromIni reads into). Called by the exports (Set*,
# LoadFromIni), the core (defaults) and the correction tables (the bound of a length).

cdef extern from *:                 # C in parameters.pyx
    # mm: the largest radius, distance, tolerance or limit (a correction's too)
    double TC_MAX_LENGTH

ctypedef struct IniSettings:
    # what LoadFromIni reads into, a copy of the core's configuration: the file is
    # read and parsed without the core's lock, and stored only when all of it is good
    GCODE_PARAMETERS params
    char driver[256]
    int64_t plan_window     # [GCodeParameters] lookAheadParts (the core's, see SetLookAhead)
    double time_scale       # [Offline] TimeScale (the core's, see SetTimeScale)
    SmoothingConfig smoothing   # [Smoothing] keys (the core's, see SetSmoothing)
    int32_t narrow_utf8     # [Texts] Narrow: 1 utf8, 0 ansi, -1 not named (process-wide; Windows only)
    # [Corrections] ToolTable, AxisTable1..8: the files named (malloc'ed; NULL none), read
    # once the whole INI file is good (ini_settings_free frees them)
    char *tool_table_file
    char *axis_table_files[8]
    const char *path
    ErrorInfo *err


# the documented defaults; the bounds of Set*Parameters (err filled when refused),
# the clamp of overrideInc; finite presets and coordinates; LoadFromIni's visitor and
# the file names it leaves to free
cdef void default_gcode_parameters(GCODE_PARAMETERS *p) noexcept nogil
cdef bint check_gcode_parameters(const GCODE_PARAMETERS *p, ErrorInfo *err) noexcept nogil
cdef bint check_machine_parameters(const MACHINE_PARAMETERS *m, ErrorInfo *err) noexcept nogil
cdef void normalise_gcode_parameters(GCODE_PARAMETERS *p) noexcept nogil
cdef bint user_params_finite(const double *values) noexcept nogil
cdef bint coordinates_finite(const double *values, uint32_t n) noexcept nogil
cdef int32_t ini_apply_setting(void *ctx, const char *section, const char *key, const char *value,
                               int32_t line) noexcept nogil
cdef void ini_settings_free(IniSettings *s) noexcept nogil
