# Face of configuration.pyx: what a host sets on a core and reads back -- the G-code
# and machine parameters, the user parameters, the prefix and postfix texts, the
# tool and axis correction tables, the smoothing, the look-ahead, the breakpoint,
# the feed override and the time scale (Core's configuration fields, core.pxd).
# Owns those fields: every write takes core.lock (or is atomic, as core.pxd says);
# the exports validate their arguments and call these. The activities read the
# fields as they begin, under core.lock (core.pyx, runtime/, machine/, simulator).

# ---- what the exports call
# LoadFromIni: the settings to read the INI file over (a copy of the core's, made
# under the lock; the status refused: core_refuse's code, else 0), and the read
# settings stored (tool_table NULL: the core's kept; axis_tables stored when
# has_axis_tables: the old ones released)
cdef int32_t config_ini_begin(Core *core, IniSettings *settings) noexcept nogil
cdef void config_ini_store(Core *core, const IniSettings *settings, const ToolTable *tool_table,
                           AxisCorrections *axis_tables, bint has_axis_tables) noexcept nogil
cdef bint config_ini_loaded(Core *core) noexcept nogil
# SetGCodeParameters (a TOOL_CHAIN_ code; refused and failed calls reported) and Get
cdef int32_t config_set_gcode_parameters(Core *core, const GCODE_PARAMETERS *p) noexcept nogil
cdef void config_gcode_parameters(Core *core, GCODE_PARAMETERS *out) noexcept nogil
# MACHINE_PARAMETERS (checked by the caller), the user parameters (NULL: none)
cdef void config_set_machine_parameters(Core *core, const MACHINE_PARAMETERS *p) noexcept nogil
cdef void config_machine_parameters(Core *core, MACHINE_PARAMETERS *out) noexcept nogil
cdef void config_set_user_params(Core *core, const double *values) noexcept nogil
# GCodePrefixPostfix: takes both texts (owned, NULL none); a TOOL_CHAIN_ code
cdef int32_t config_set_prefix_postfix(Core *core, char *prefix, char *postfix) noexcept nogil
# the look-ahead, the breakpoint, the feed override and the time scale (atomic)
cdef void config_set_plan_window(Core *core, int64_t parts) noexcept nogil
cdef void config_set_breakpoint(Core *core, uint32_t line, int32_t file_idx) noexcept nogil
cdef void config_set_rel_feed(Core *core, double rel_feed) noexcept nogil
cdef double config_rel_feed(Core *core) noexcept nogil
cdef void config_set_time_scale(Core *core, double scale) noexcept nogil
# the tool table: a whole one, an entry read, an entry set (False: err filled)
cdef void config_set_tool_table(Core *core, const ToolTable *table) noexcept nogil
cdef void config_tool_correction(Core *core, uint32_t entry, double *values) noexcept nogil
cdef bint config_set_tool_correction(Core *core, uint32_t entry, uint32_t programmed, const double *values,
                                     ErrorInfo *err) noexcept nogil
# the axis correction tables: taken (the old ones released), a reference to read
cdef void config_set_axis_corrections(Core *core, AxisCorrections *tables) noexcept nogil
cdef AxisCorrections *config_axis_corrections_ref(Core *core) noexcept nogil
# the smoothing: one command's parameters set (False: err filled), read, all copied
cdef bint config_set_smoothing(Core *core, int32_t command, const double *params, ErrorInfo *err) noexcept nogil
cdef void config_smoothing_parameters(Core *core, int32_t command, double *params) noexcept nogil
cdef void config_smoothing(Core *core, SmoothingConfig *out) noexcept nogil
