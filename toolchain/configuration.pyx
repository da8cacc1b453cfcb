# A core's configuration: what a host sets and reads back (configuration.pxd). Every
# function takes core.lock for as long as it touches the fields, never while it
# reads a file or calls the host; the atomic fields (rel_feed, time_scale) are read
# and written without it.
from libc.string cimport memset, memcpy, memcmp
from libc.stdlib cimport free


cdef int32_t config_ini_begin(Core *core, IniSettings *settings) noexcept nogil:
    """LoadFromIni's start: refused in a status that takes no INI (the refusal's code),
    else 0 with the core's settings copied into `settings` for the file to change."""
    cdef int32_t status
    pthread_mutex_lock(&core.lock)
    status = core_status(core)
    if status_after(status, CMD_LOAD_INI, False) == TC_REFUSED:
        pthread_mutex_unlock(&core.lock)
        return core_refuse(core, "LoadFromIni", status)
    settings.params = core.params
    settings.plan_window = core.plan_window
    settings.time_scale = TC_ATOMIC_LOAD_D(&core.time_scale)
    settings.smoothing = core.smoothing
    memcpy(settings.driver, core.driver, sizeof(settings.driver))
    pthread_mutex_unlock(&core.lock)
    return 0


cdef void config_ini_store(Core *core, const IniSettings *settings, const ToolTable *tool_table,
                           AxisCorrections *axis_tables, bint has_axis_tables) noexcept nogil:
    """Every value of a good INI file at once (the file was read without the lock)."""
    cdef AxisCorrections *old = NULL
    pthread_mutex_lock(&core.lock)
    core.params = settings.params
    core.plan_window = settings.plan_window
    TC_ATOMIC_STORE_D(&core.time_scale, settings.time_scale)
    memcpy(core.driver, settings.driver, sizeof(core.driver))
    core.smoothing = settings.smoothing
    if tool_table != NULL:
        core.tool_table = tool_table[0]
    if has_axis_tables:
        old = core.axis_corrections
        core.axis_corrections = axis_tables
    core.ini_loaded = True
    pthread_mutex_unlock(&core.lock)
    axis_corrections_release(old)


cdef bint config_ini_loaded(Core *core) noexcept nogil:
    """Whether an INI file was loaded (the driver callbacks need one)."""
    cdef bint loaded
    pthread_mutex_lock(&core.lock)
    loaded = core.ini_loaded
    pthread_mutex_unlock(&core.lock)
    return loaded


cdef void _feeds_of(GCODE_PARAMETERS *params, const GCODE_PARAMETERS *source) noexcept nogil:
    """The fields the feeds depend on (the ones SetGCodeParameters may change while the
    program is stopped on its trajectory) copied from source into params."""
    memcpy(params.motion, source.motion, sizeof(source.motion))
    params.startAngle = source.startAngle
    params.endAngle = source.endAngle
    params.minAngleFeed = source.minAngleFeed
    params.overrideInc = source.overrideInc
    memcpy(params.arcFeedTable, source.arcFeedTable, sizeof(source.arcFeedTable))
    memcpy(params.axisLimits, source.axisLimits, sizeof(source.axisLimits))


cdef int32_t config_set_gcode_parameters(Core *core, const GCODE_PARAMETERS *p) noexcept nogil:
    """SetGCodeParameters: refused in a status that takes none; while the program stands
    on its trajectory only the feeds may change (a structure that changes anything else
    is refused whole, error 27, so a panel can tell); checked, normalised, stored."""
    cdef int32_t status
    cdef GCODE_PARAMETERS params
    cdef ErrorInfo err
    cdef bint good
    pthread_mutex_lock(&core.lock)
    status = core_status(core)
    if status_after(status, CMD_SET_PARAMETERS, False) == TC_REFUSED:
        pthread_mutex_unlock(&core.lock)
        return core_refuse(core, "SetGCodeParameters", status)
    if status == CNC_STATUS_STOPPED or status == CNC_STATUS_STOPPED_BY_M0:
        params = p[0]
        _feeds_of(&params, &core.params)
        if memcmp(&params, &core.params, sizeof(GCODE_PARAMETERS)) != 0:
            pthread_mutex_unlock(&core.lock)
            err_parameters_while_stopped(refusal(), -1, 0, status, status_name(status),
                                         "another field differs from GetGCodeParameters' (nothing was changed)")
            return core_fail(core, refusal())
        params = core.params
        _feeds_of(&params, p)
    else:
        params = p[0]
    good = check_gcode_parameters(&params, &err)
    if good:
        normalise_gcode_parameters(&params)
        core.params = params
    pthread_mutex_unlock(&core.lock)
    if not good:
        return core_fail(core, &err)
    return TOOL_CHAIN_SUCCESS


cdef void config_gcode_parameters(Core *core, GCODE_PARAMETERS *out) noexcept nogil:
    """GetGCodeParameters: the core's GCODE_PARAMETERS."""
    pthread_mutex_lock(&core.lock)
    out[0] = core.params
    pthread_mutex_unlock(&core.lock)


cdef void config_set_machine_parameters(Core *core, const MACHINE_PARAMETERS *p) noexcept nogil:
    """SetMachineParameters, after the caller's check."""
    pthread_mutex_lock(&core.lock)
    core.machine = p[0]
    pthread_mutex_unlock(&core.lock)


cdef void config_machine_parameters(Core *core, MACHINE_PARAMETERS *out) noexcept nogil:
    """GetMachineParameters: the core's MACHINE_PARAMETERS."""
    pthread_mutex_lock(&core.lock)
    out[0] = core.machine
    pthread_mutex_unlock(&core.lock)


cdef void config_set_user_params(Core *core, const double *values) noexcept nogil:
    """SetUserParams: the 100 values P00..P99 start with (NULL: none, all 0)."""
    pthread_mutex_lock(&core.lock)
    if values != NULL:
        memcpy(core.user_params, values, sizeof(core.user_params))
    else:
        memset(core.user_params, 0, sizeof(core.user_params))
    core.has_user_params = values != NULL
    pthread_mutex_unlock(&core.lock)


cdef int32_t config_set_prefix_postfix(Core *core, char *prefix, char *postfix) noexcept nogil:
    """GCodePrefixPostfix: the core takes both texts (freed when refused)."""
    cdef int32_t status
    pthread_mutex_lock(&core.lock)
    status = core_status(core)
    if status_after(status, CMD_SET_PREFIX, False) == TC_REFUSED:
        pthread_mutex_unlock(&core.lock)
        free(prefix)
        free(postfix)
        return core_refuse(core, "GCodePrefixPostfix", status)
    free(core.prefix)
    free(core.postfix)
    core.prefix = prefix
    core.postfix = postfix
    pthread_mutex_unlock(&core.lock)
    return TOOL_CHAIN_SUCCESS


cdef void config_set_plan_window(Core *core, int64_t parts) noexcept nogil:
    """SetLookAhead: the planner's window for the next compilations."""
    pthread_mutex_lock(&core.lock)
    core.plan_window = parts
    pthread_mutex_unlock(&core.lock)


cdef void config_set_breakpoint(Core *core, uint32_t line, int32_t file_idx) noexcept nogil:
    """SetBreakpoint: the editor line (0: none) and file the machine stops at."""
    pthread_mutex_lock(&core.lock)
    core.breakpoint_line = line
    core.breakpoint_file = file_idx
    pthread_mutex_unlock(&core.lock)


cdef void config_set_rel_feed(Core *core, double rel_feed) noexcept nogil:
    """SetRelFeed (clamped by the caller); the machine reads it every step."""
    TC_ATOMIC_STORE_D(&core.rel_feed, rel_feed)


cdef double config_rel_feed(Core *core) noexcept nogil:
    """The feed override the host set."""
    return TC_ATOMIC_LOAD_D(&core.rel_feed)


cdef void config_set_time_scale(Core *core, double scale) noexcept nogil:
    """SetTimeScale; the machine's clock reads it every step."""
    TC_ATOMIC_STORE_D(&core.time_scale, scale)


cdef void config_set_tool_table(Core *core, const ToolTable *table) noexcept nogil:
    """LoadToolTable: a whole table (read without the lock)."""
    pthread_mutex_lock(&core.lock)
    core.tool_table = table[0]
    pthread_mutex_unlock(&core.lock)


cdef void config_tool_correction(Core *core, uint32_t entry, double *values) noexcept nogil:
    """GetToolCorrection: the values of entry 1..TOOL_ENTRIES (checked by the caller)."""
    pthread_mutex_lock(&core.lock)
    memcpy(values, core.tool_table.entry[entry].value, sizeof(core.tool_table.entry[entry].value))
    pthread_mutex_unlock(&core.lock)


cdef bint config_set_tool_correction(Core *core, uint32_t entry, uint32_t programmed, const double *values,
                                     ErrorInfo *err) noexcept nogil:
    """SetToolCorrection: the programmed values of an entry; False with err filled."""
    cdef bint good
    pthread_mutex_lock(&core.lock)
    good = tool_table_set(&core.tool_table, entry, programmed, values, err)
    pthread_mutex_unlock(&core.lock)
    return good


cdef void config_set_axis_corrections(Core *core, AxisCorrections *tables) noexcept nogil:
    """LoadAxisCorrections: the core takes `tables` (NULL: none); the old ones are
    released after the lock (a run that holds a reference keeps them)."""
    cdef AxisCorrections *old
    pthread_mutex_lock(&core.lock)
    old = core.axis_corrections
    core.axis_corrections = tables
    pthread_mutex_unlock(&core.lock)
    axis_corrections_release(old)


cdef AxisCorrections *config_axis_corrections_ref(Core *core) noexcept nogil:
    """A reference to the core's axis tables (NULL: none), for the caller to release."""
    cdef AxisCorrections *tables
    pthread_mutex_lock(&core.lock)
    tables = axis_corrections_ref(core.axis_corrections)
    pthread_mutex_unlock(&core.lock)
    return tables


cdef bint config_set_smoothing(Core *core, int32_t command, const double *params, ErrorInfo *err) noexcept nogil:
    """SetSmoothing: one command's parameters; False with err filled."""
    cdef bint good
    pthread_mutex_lock(&core.lock)
    good = smoothing_set(&core.smoothing, command, params, err)
    pthread_mutex_unlock(&core.lock)
    return good


cdef void config_smoothing_parameters(Core *core, int32_t command, double *params) noexcept nogil:
    """GetSmoothing: the four parameters of the spline or the IIR filter."""
    pthread_mutex_lock(&core.lock)
    if command == SMOOTHING_COMMAND_SPLINE:
        params[0] = core.smoothing.spline[0]
        params[1] = core.smoothing.spline[1]
        params[2] = params[3] = 0.0
    else:
        memcpy(params, core.smoothing.iir, sizeof(core.smoothing.iir))
    pthread_mutex_unlock(&core.lock)


cdef void config_smoothing(Core *core, SmoothingConfig *out) noexcept nogil:
    """The core's whole smoothing setting (SmoothSamples runs on a copy)."""
    pthread_mutex_lock(&core.lock)
    out[0] = core.smoothing
    pthread_mutex_unlock(&core.lock)
