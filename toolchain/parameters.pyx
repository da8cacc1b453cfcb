# The parameters a host gives a core: G-code parameters (GCODE_PARAMETERS) and
# machine parameters (MACHINE_PARAMETERS). Their documented defaults, the bounds
# every value must keep (SetGCodeParameters, SetMachineParameters and the INI refuse
# anything else, so no NaN, infinity or absurd size ever reaches the compiler, the
# compensation or a callback), and the keys of the INI file: [GCodeParameters], [Offline],
# and the files of [Corrections] and the values of [Smoothing] (tables/, smoothing/).
from libc.string cimport memset, memcpy, strncpy, strcasecmp, strlen, strcpy
from libc.stdlib cimport free

cdef extern from *:
    """
    #define TC_MAX_LENGTH 1e6       /* mm: radii, distances, tolerances, limits */
    #define TC_MAX_RATE 1e9         /* mm/min, mm/s^2: feeds, accelerations */
    #define TC_MAX_ANGLE 360.0      /* degrees */
    """
    double TC_MAX_RATE
    double TC_MAX_ANGLE


cdef void default_gcode_parameters(GCODE_PARAMETERS *p) noexcept nogil:
    """The documented defaults (docs/structures.md)."""
    cdef int i
    memset(p, 0, sizeof(GCODE_PARAMETERS))
    p.absMode = 1
    p.correctionStrategy = 0x600
    for i in range(8):
        p.motion[i].feed = 1000.0
        p.motion[i].acc = 500.0
        p.motion[i].dec = 500.0
        p.motion[i].rampType = 1
    p.motion[0].feed = 10000.0          # rapid
    p.motion[6].dec = 1000.0            # normal stop
    p.motion[7].dec = 5000.0            # emergency stop
    for i in range(8):
        p.correction[i].gCode = 41 + i
    p.maxConnectionDistance = 10.0
    p.startAngle = 360.0
    p.endAngle = 360.0
    p.overrideInc = 0.001
    p.M02_programEnd1 = 2
    p.M30_programEnd2 = 30
    p.M03_startSpindleCW = 3
    p.M04_startSpindleCCW = 4
    p.M05_stopSpindle = 5
    p.M06_changeTool = 6
    p.M07_coolOn = 7
    p.M08_oilOn = 8
    p.M09_coolOilOff = 9
    p.M17_return = 17
    p.M29_print = 29
    p.M80_mirrorOff = 80
    p.M81_mirrorX = 81
    p.M82_mirrorY = 82
    p.M83_mirrorZ = 83
    p.M84_mirrorXY = 84
    p.M85_mirrorXZ = 85
    p.M86_mirrorYZ = 86
    p.M87_mirrorXYZ = 87
    p.M99_defFeed = 99
    p.insertArcToleranceRMax = 0.03
    p.insertArcToleranceRMin = 0.03
    p.insertArcMaxAngle = 90.0
    p.tolerance[0] = 0.005
    p.tolerance[1] = 0.001
    p.tolerance[2] = 0.03
    p.tolerance[3] = 0.005
    p.tolerance[5] = 3.0
    p.tolerance[6] = 0.01


# ------------------------------------------------------------------ bounds

cdef bint _in_bounds(ErrorInfo *err, const char *name, double value, double lo, double hi,
                     bint lo_open) noexcept nogil:
    """True when value is finite and in [lo, hi] (lo excluded when lo_open); else
    err names the field (ERR_NOT_FINITE, ERR_OUT_OF_RANGE)."""
    if not isfinite(value):
        err_not_finite(err, -1, 0, name, value)
        return False
    if value > hi or value < lo or (lo_open and value == lo):
        err_out_of_range(err, -1, 0, name, value, lo, hi)
        return False
    return True


cdef bint _indexed_in_bounds(ErrorInfo *err, const char *name_format, int index, double value,
                             double lo, double hi, bint lo_open) noexcept nogil:
    """_in_bounds for an array element; name_format holds one %d for the index."""
    cdef char name[96]
    c_snprintf(name, sizeof(name), name_format, index)
    return _in_bounds(err, name, value, lo, hi, lo_open)


cdef bint check_gcode_parameters(const GCODE_PARAMETERS *p, ErrorInfo *err) noexcept nogil:
    """Every double of p finite and within its bounds (include/tgm_cnc.h, comment of
    ToolChainCore_SetGCodeParameters); False with err naming the first bad field.
    The reserved field is not used and not checked; integers are taken as they come."""
    cdef int i
    for i in range(8):
        if not _indexed_in_bounds(err, "GCODE_PARAMETERS.motion[%d].feed", i, p.motion[i].feed,
                                  0.0, TC_MAX_RATE, True):
            return False
        if not _indexed_in_bounds(err, "GCODE_PARAMETERS.motion[%d].acc", i, p.motion[i].acc,
                                  0.0, TC_MAX_RATE, True):
            return False
        if not _indexed_in_bounds(err, "GCODE_PARAMETERS.motion[%d].dec", i, p.motion[i].dec,
                                  0.0, TC_MAX_RATE, True):
            return False
    for i in range(8):
        if not _indexed_in_bounds(err, "GCODE_PARAMETERS.correction[%d].size", i, p.correction[i].size,
                                  -TC_MAX_LENGTH, TC_MAX_LENGTH, False):
            return False
    if not (_in_bounds(err, "GCODE_PARAMETERS.maxConnectionDistance", p.maxConnectionDistance,
                       0.0, TC_MAX_LENGTH, False)
            and _in_bounds(err, "GCODE_PARAMETERS.startAngle", p.startAngle, 0.0, TC_MAX_ANGLE, False)
            and _in_bounds(err, "GCODE_PARAMETERS.endAngle", p.endAngle, 0.0, TC_MAX_ANGLE, False)
            and _in_bounds(err, "GCODE_PARAMETERS.minAngleFeed", p.minAngleFeed, 0.0, TC_MAX_RATE, False)
            and _in_bounds(err, "GCODE_PARAMETERS.overrideInc", p.overrideInc, -TC_MAX_RATE, TC_MAX_RATE, False)
            and _in_bounds(err, "GCODE_PARAMETERS.centripetalAcc", p.centripetalAcc, 0.0, TC_MAX_RATE, False)):
        return False
    for i in range(5):
        if not (_indexed_in_bounds(err, "GCODE_PARAMETERS.arcFeedTable[%d].m_r", i, p.arcFeedTable[i].m_r,
                                   0.0, TC_MAX_LENGTH, False)
                and _indexed_in_bounds(err, "GCODE_PARAMETERS.arcFeedTable[%d].m_relFeed", i,
                                       p.arcFeedTable[i].m_relFeed, 0.0, 100.0, False)):
            return False
    for i in range(3):
        if not (_indexed_in_bounds(err, "GCODE_PARAMETERS.mFuncInsertTable[%d].relFeed", i,
                                   p.mFuncInsertTable[i].relFeed, 0.0, 1.0, False)
                and _indexed_in_bounds(err, "GCODE_PARAMETERS.mFuncInsertTable[%d].distance", i,
                                       p.mFuncInsertTable[i].distance, 0.0, TC_MAX_LENGTH, False)):
            return False
    if not (_in_bounds(err, "GCODE_PARAMETERS.insertArcToleranceRMax", p.insertArcToleranceRMax,
                       0.0, TC_MAX_LENGTH, False)
            and _in_bounds(err, "GCODE_PARAMETERS.insertArcToleranceRMin", p.insertArcToleranceRMin,
                           0.0, TC_MAX_LENGTH, False)
            and _in_bounds(err, "GCODE_PARAMETERS.insertArcMaxAngle", p.insertArcMaxAngle, 0.0, TC_MAX_ANGLE, False)
            and _in_bounds(err, "GCODE_PARAMETERS.insertArcMinAngle", p.insertArcMinAngle, 0.0, TC_MAX_ANGLE, False)
            and _in_bounds(err, "GCODE_PARAMETERS.dynamicG41Correction_mm", p.dynamicG41Correction_mm,
                           -TC_MAX_LENGTH, TC_MAX_LENGTH, False)
            and _in_bounds(err, "GCODE_PARAMETERS.dynamicG42Correction_mm", p.dynamicG42Correction_mm,
                           -TC_MAX_LENGTH, TC_MAX_LENGTH, False)
            and _in_bounds(err, "GCODE_PARAMETERS.dynamicG41Correction_percent", p.dynamicG41Correction_percent,
                           -1000.0, 1000.0, False)
            and _in_bounds(err, "GCODE_PARAMETERS.dynamicG42Correction_percent", p.dynamicG42Correction_percent,
                           -1000.0, 1000.0, False)):
        return False
    for i in range(AXES):
        if not (_indexed_in_bounds(err, "GCODE_PARAMETERS.axisLimits[%d].maxFeed", i, p.axisLimits[i].maxFeed,
                                   0.0, TC_MAX_RATE, False)
                and _indexed_in_bounds(err, "GCODE_PARAMETERS.axisLimits[%d].maxAcc", i, p.axisLimits[i].maxAcc,
                                       0.0, TC_MAX_RATE, False)
                and _indexed_in_bounds(err, "GCODE_PARAMETERS.axisLimits[%d].maxDec", i, p.axisLimits[i].maxDec,
                                       0.0, TC_MAX_RATE, False)):
            return False
    for i in range(10):
        if not _indexed_in_bounds(err, "GCODE_PARAMETERS.tolerance[%d]", i, p.tolerance[i],
                                  0.0, TC_MAX_LENGTH, False):
            return False
    return True


cdef bint _axes_in_bounds(ErrorInfo *err, const char *field, const P10DOUBLE *values,
                          double lo, double hi) noexcept nogil:
    """Whether every axis of a MACHINE_PARAMETERS field lies in [lo, hi]; else the error naming
    MACHINE_PARAMETERS.field.axis and its value."""
    cdef const double *v = <const double *>values
    cdef const char *axes = "xyzcbuvwao"
    cdef char name[96]
    cdef int i
    for i in range(AXES):
        c_snprintf(name, sizeof(name), "MACHINE_PARAMETERS.%s.%c", field, axes[i])
        if not _in_bounds(err, name, v[i], lo, hi, False):
            return False
    return True


cdef bint check_machine_parameters(const MACHINE_PARAMETERS *m, ErrorInfo *err) noexcept nogil:
    """Limits and reference point within |x| <= 1e6 mm, backlash in [0, 1e6];
    False with err naming the first bad field."""
    return (_axes_in_bounds(err, "minCoords", &m.minCoords, -TC_MAX_LENGTH, TC_MAX_LENGTH)
            and _axes_in_bounds(err, "maxCoords", &m.maxCoords, -TC_MAX_LENGTH, TC_MAX_LENGTH)
            and _axes_in_bounds(err, "refCoords", &m.refCoords, -TC_MAX_LENGTH, TC_MAX_LENGTH)
            and _axes_in_bounds(err, "backlash", &m.backlash, 0.0, TC_MAX_LENGTH)
            and _axes_in_bounds(err, "backlashInc", &m.backlashInc, 0.0, TC_MAX_LENGTH))


cdef void normalise_gcode_parameters(GCODE_PARAMETERS *p) noexcept nogil:
    """The documented clamp of overrideInc: 0 or less gives 0.001, at most 0.1."""
    if p.overrideInc <= 0.0:
        p.overrideInc = 0.001
    elif p.overrideInc > 0.1:
        p.overrideInc = 0.1


cdef bint user_params_finite(const double *values) noexcept nogil:
    """SetUserParams: the 100 presets P00..P99 are finite numbers."""
    return coordinates_finite(values, 100)


cdef bint coordinates_finite(const double *values, uint32_t n) noexcept nogil:
    """The first n values (ResetCNC's coordinates, presets, every part's end) are finite
    numbers. Without a branch a value: x * 0 is a zero for every finite x and NaN for an
    infinity or NaN, and so is their sum (the compiler checks ten values a part)."""
    cdef uint32_t i
    cdef double zeros = 0.0
    for i in range(n):
        zeros += values[i] * 0.0
    return zeros == zeros


# ------------------------------------------------------------------ INI


cdef bint strncasecmp_prefix(const char *s, const char *prefix) noexcept nogil:
    """Whether s starts with prefix, ASCII case ignored."""
    cdef size_t i = 0
    while prefix[i] != 0:
        if s[i] == 0 or (s[i] | 0x20) != (prefix[i] | 0x20):
            return False
        i += 1
    return True


cdef int _rezerva1_switch(GCODE_PARAMETERS *p, const char *value, uint32_t bit) noexcept nogil:
    """An INI switch (0 or 1) of a GCODE_REZERVA1_* bit: 1 set, -1 not 0 or 1."""
    cdef long long on
    if not c_parse_long(value, 0, 1, &on):
        return -1
    p.rezerva1 = (p.rezerva1 | <int32_t>bit) if on else (p.rezerva1 & ~<int32_t>bit)
    return 1


cdef int gcode_parameter_from_ini(GCODE_PARAMETERS *p, const char *key, const char *value) noexcept nogil:
    """[GCodeParameters] key = value for the scalar fields of GCODE_PARAMETERS and
    the radii correction0..correction7: 1 set, 0 unknown key (ignored), -1 a value
    that is not a number of the field's kind (nothing set)."""
    cdef double d = 0.0
    cdef long long i = 0
    cdef bint is_double = c_parse_double(value, &d)
    cdef bint is_int = c_parse_long(value, -2147483647 - 1, 2147483647, &i)
    if strcasecmp(key, "correctionStrategy") == 0:
        if not c_parse_long(value, 0, 4294967295, &i):
            return -1
        p.correctionStrategy = <uint32_t>i
        return 1
    if strcasecmp(key, "isoCompat") == 0:        # docs/compiler.md: the ISO compatibility mode
        return _rezerva1_switch(p, value, GCODE_REZERVA1_ISO_COMPAT)
    if strcasecmp(key, "isoStrict") == 0:        # docs/compiler.md: what LinuxCNC refuses is an error
        return _rezerva1_switch(p, value, GCODE_REZERVA1_ISO_STRICT)
    if strcasecmp(key, "strictCompensation") == 0:      # docs/compensation.md: crossing equidistants refused
        return _rezerva1_switch(p, value, GCODE_REZERVA1_COMP_STRICT)
    if strcasecmp(key, "applyUnimplemented") == 0:      # docs/behaviour.md: centripetalAcc, insertArcMinAngle
        return _rezerva1_switch(p, value, GCODE_REZERVA1_APPLY_UNIMPLEMENTED)
    if strcasecmp(key, "absMode") == 0 or strcasecmp(key, "swapG2G3") == 0 or strcasecmp(key, "forceMode") == 0 \
            or strcasecmp(key, "calcTime") == 0 or strcasecmp(key, "insertArcMode") == 0:
        if not is_int:
            return -1
        if strcasecmp(key, "absMode") == 0: p.absMode = <int32_t>i
        elif strcasecmp(key, "swapG2G3") == 0: p.swapG2G3 = <int32_t>i
        elif strcasecmp(key, "forceMode") == 0: p.forceMode = <int32_t>i
        elif strcasecmp(key, "calcTime") == 0: p.calcTime = <int32_t>i
        else: p.insertArcMode = <int32_t>i
        return 1
    if strcasecmp(key, "maxConnectionDistance") == 0: p.maxConnectionDistance = d
    elif strcasecmp(key, "startAngle") == 0: p.startAngle = d
    elif strcasecmp(key, "endAngle") == 0: p.endAngle = d
    elif strcasecmp(key, "minAngleFeed") == 0: p.minAngleFeed = d
    elif strcasecmp(key, "overrideInc") == 0: p.overrideInc = d
    elif strcasecmp(key, "rapidFeed") == 0: p.motion[0].feed = d
    elif strcasecmp(key, "forwardFeed") == 0: p.motion[1].feed = d
    elif strncasecmp_prefix(key, "correction") and key[10] >= b'0' and key[10] <= b'7' and key[11] == 0:
        p.correction[<int>key[10] - 48].size = d
    elif strncasecmp_prefix(key, "tolerance") and key[9] >= b'0' and key[9] <= b'9' and key[10] == 0:
        p.tolerance[<int>key[9] - 48] = d
    else:
        return 0
    return 1 if is_double else -1


cdef int32_t _ini_fail(IniSettings *s, int32_t line, const char *what) noexcept nogil:
    """Error 16 on the INI file's line; its number (ini_read's visitor ends the reading)."""
    err_ini_value(s.err, -1, line, s.path, line, what)
    return ERR_INI_VALUE


cdef char *_ini_file_path(const char *ini, const char *name) noexcept nogil:
    """A file an INI key names (malloc'ed; NULL out of memory): an absolute name as it
    is, a relative one in the INI file's folder."""
    cdef size_t folder = strlen(ini)
    cdef char *path
    if name[0] == b'/' or name[0] == b'\\' or (b'a' <= (name[0] | 0x20) <= b'z' and name[1] == b':'):
        return tc_strdup(name)
    while folder > 0 and ini[folder - 1] != b'/' and ini[folder - 1] != b'\\':
        folder -= 1
    path = <char *>tc_malloc(folder + strlen(name) + 1)
    if path != NULL:
        memcpy(path, ini, folder)
        strcpy(path + folder, name)
    return path


cdef void ini_settings_free(IniSettings *s) noexcept nogil:
    """Frees the file names LoadFromIni's reading kept."""
    cdef int k
    free(s.tool_table_file)
    s.tool_table_file = NULL
    for k in range(AXIS_TABLES_MAX):
        free(s.axis_table_files[k])
        s.axis_table_files[k] = NULL


cdef int32_t _ini_file_key(IniSettings *s, int32_t line, const char *key, const char *value,
                           char **slot) noexcept nogil:
    """[Corrections] key = a file name into *slot."""
    cdef char text[400]
    if value[0] == 0:
        c_snprintf(text, sizeof(text), "[Corrections] %s names no file", key)
        return _ini_fail(s, line, text)
    free(slot[0])
    slot[0] = _ini_file_path(s.path, value)
    if slot[0] == NULL:
        err_out_of_memory(s.err, -1, line)
        return ERR_OUT_OF_MEMORY
    return 0


cdef int32_t _ini_smoothing_key(IniSettings *s, int32_t line, const char *key, const char *value) noexcept nogil:
    """[Smoothing] key = a register value of the Interpolator's command -2 or -1
    (docs/smoothing.md); 0 also for an unknown key (ignored)."""
    cdef ErrorInfo why
    cdef char text[400]
    cdef int32_t command = SMOOTHING_COMMAND_SPLINE
    cdef int index
    cdef long long whole
    cdef double number
    if strcasecmp(key, "SplinePoints") == 0: index = 0
    elif strcasecmp(key, "SplineJerk") == 0: index = 1
    else:
        command = SMOOTHING_COMMAND_IIR
        if strcasecmp(key, "IirP") == 0: index = 0
        elif strcasecmp(key, "IirQ") == 0: index = 1
        elif strcasecmp(key, "IirF") == 0: index = 2
        elif strcasecmp(key, "IirAxes") == 0: index = 3
        else:
            return 0
    if index == 3 and c_parse_long(value, 0, 4294967295, &whole):   # a mask may be written 0x...
        number = <double>whole
    elif not c_parse_double(value, &number):
        c_snprintf(text, sizeof(text), "[Smoothing] %s = '%.200s' is not a number", key, value)
        return _ini_fail(s, line, text)
    if not smoothing_check_parameter(command, index, number, &why):
        c_snprintf(text, sizeof(text), "[Smoothing] %s: %s", key, why.text)
        return _ini_fail(s, line, text)
    if command == SMOOTHING_COMMAND_SPLINE:
        s.smoothing.spline[index] = number
    else:
        s.smoothing.iir[index] = number
    return 0


cdef int32_t ini_apply_setting(void *ctx, const char *section, const char *key, const char *value,
                               int32_t line) noexcept nogil:
    """ini_visitor of LoadFromIni: [CNC] Driver, [GCodeParameters], [Offline],
    [Corrections], [Smoothing] and [Texts] keys into the IniSettings; ERR_INI_VALUE (s.err naming
    the key and the line) for a bad value."""
    cdef IniSettings *s = <IniSettings *>ctx
    cdef GCODE_PARAMETERS candidate
    cdef ErrorInfo why
    cdef char text[400]
    cdef int known
    cdef long long window
    cdef double scale
    if strcasecmp(section, "Corrections") == 0 and strcasecmp(key, "ToolTable") == 0:
        return _ini_file_key(s, line, key, value, &s.tool_table_file)
    if strcasecmp(section, "Corrections") == 0 and strncasecmp_prefix(key, "AxisTable") \
            and b'1' <= key[9] <= b'8' and key[10] == 0:
        return _ini_file_key(s, line, key, value, &s.axis_table_files[<int>key[9] - 49])
    if strcasecmp(section, "Smoothing") == 0:
        return _ini_smoothing_key(s, line, key, value)
    if strcasecmp(section, "Texts") == 0 and strcasecmp(key, "Narrow") == 0:
        # the host's narrow texts (TGM_LPCSTR) on Windows: the ANSI code page or UTF-8
        if strcasecmp(value, "ansi") == 0:
            s.narrow_utf8 = 0
        elif strcasecmp(value, "utf8") == 0 or strcasecmp(value, "utf-8") == 0:
            s.narrow_utf8 = 1
        else:
            return _ini_fail(s, line, "[Texts] Narrow: the panel's narrow texts, ansi (the process's code page) or utf8")
        return 0
    if strcasecmp(section, "Offline") == 0 and strcasecmp(key, "TimeScale") == 0:
        if not c_parse_double(value, &scale) or not (0.0 < scale <= 1e6):
            return _ini_fail(s, line, "[Offline] TimeScale: the offline machine's speed against real time, in (0, 1e6]")
        s.time_scale = scale
    elif strcasecmp(section, "CNC") == 0 and strcasecmp(key, "Driver") == 0:
        strncpy(s.driver, value, sizeof(s.driver) - 1)
        s.driver[sizeof(s.driver) - 1] = 0
    elif strcasecmp(section, "GCodeParameters") == 0 and strcasecmp(key, "lookAheadParts") == 0:
        if not c_parse_long(value, -1, 1000000000, &window):
            return _ini_fail(s, line, "[GCodeParameters] lookAheadParts: parts of the planner's look-ahead, 0 (the vendor's 8), -1 (unlimited) or more")
        s.plan_window = window
    elif strcasecmp(section, "GCodeParameters") == 0:
        candidate = s.params
        known = gcode_parameter_from_ini(&candidate, key, value)
        if known < 0:
            c_snprintf(text, sizeof(text), "[GCodeParameters] %s = '%.200s' is not a number", key, value)
            return _ini_fail(s, line, text)
        if known > 0:
            # the parameters were good before this key: a failure is this key's value
            if not check_gcode_parameters(&candidate, &why):
                c_snprintf(text, sizeof(text), "[GCodeParameters] %s: %s", key, why.text)
                return _ini_fail(s, line, text)
            s.params = candidate
    return 0
