# The exported C functions of include/tgm_cnc.h. Each one checks its arguments
# (core index, NULL pointers, status), then calls into the core. The C compiler
# checks every signature here against the header's prototype. The host's texts
# (TGM_LPCTSTR: UTF-16 on Windows) are converted here once, to UTF-8 on the way in
# (text_from_host) and back on the way out (text_to_host_kept); inside, every text
# is UTF-8 (platform.pxd).
from libc.string cimport memset, memcpy, memcmp, strlen
from libc.stdlib cimport free

cdef extern from *:
    """
    #define TC_VERSION_STRING "SF_TCh 0.1.0 (open drop-in CNC module library, built " __DATE__ " " __TIME__ ")"
    """
    const char *TC_VERSION_STRING


# ------------------------------------------------------------------ lifecycle

cdef public int32_t ToolChainCore_Init(const DLL_INIT_STRUCT *p) noexcept nogil:
    """Init: checks DLL_INIT_STRUCT (every directory given, Local_Core_Mode 0..2), then keeps
    the core mode, the log's directory and the macros' directory. -1 on a bad structure or when
    a text cannot be converted."""
    global g_core_mode
    cdef char *owned_dll_dir
    cdef char *owned_macros_dir
    cdef const char *dll_dir
    cdef const char *macros_dir
    core_get(0)
    if p == NULL or p.CNC_Dll_Dir == NULL or p.Macros_Dir == NULL or p.Comm_Int2_Dir == NULL:
        return TOOL_CHAIN_ERROR
    if p.Local_Core_Mode < 0 or p.Local_Core_Mode > 2:
        return TOOL_CHAIN_ERROR
    dll_dir = text_from_host(p.CNC_Dll_Dir, &owned_dll_dir)
    macros_dir = text_from_host(p.Macros_Dir, &owned_macros_dir)
    if dll_dir != NULL and macros_dir != NULL:      # else out of memory
        g_core_mode = p.Local_Core_Mode
        log_set_dir(dll_dir)
        strncpy(g_macros_dir, macros_dir, sizeof(g_macros_dir) - 1)
    free(owned_dll_dir)
    free(owned_macros_dir)
    return TOOL_CHAIN_SUCCESS if dll_dir != NULL and macros_dir != NULL else TOOL_CHAIN_ERROR


cdef int32_t _ini_read_tables(IniSettings *settings, ToolTable *tool_table, bint *has_tool_table,
                              AxisCorrections **axis_tables, bint *has_axis_tables, ErrorInfo *err) noexcept nogil:
    """LoadFromIni, once every key is good: the smoothing's values together, then the
    files of [Corrections]. 0, or an error number (err set) and nothing kept."""
    cdef ErrorInfo why
    cdef char text[400]
    cdef const char *names[8]
    cdef uint32_t n = 0
    cdef int k
    cdef bint good
    if not smoothing_check(&settings.smoothing, SMOOTHING_COMMAND_SPLINE, &why) \
            or not smoothing_check(&settings.smoothing, SMOOTHING_COMMAND_IIR, &why):
        c_snprintf(text, sizeof(text), "[Smoothing]: %s", why.text)
        err_ini_value(err, -1, 0, settings.path, 0, text)
        return ERR_INI_VALUE
    has_tool_table[0] = settings.tool_table_file != NULL
    if has_tool_table[0] and not tool_table_read(settings.tool_table_file, tool_table, err):
        return err.number
    for k in range(AXIS_TABLES_MAX):
        if settings.axis_table_files[k] != NULL:
            names[n] = settings.axis_table_files[k]
            n += 1
    has_axis_tables[0] = n > 0
    tc_set_stage("reading an axis table")
    good = not has_axis_tables[0] or axis_corrections_read(names, n, axis_tables, err)
    tc_set_stage(NULL)
    return 0 if good else err.number


cdef public int32_t ToolChainCore_LoadFromIni(uint32_t intIdx, TGM_LPCTSTR iniFile, uint32_t *pnMaxCores) noexcept nogil:
    """LoadFromIni: the INI file's name converted from the host's text, then _load_from_ini."""
    cdef char *owned
    cdef int32_t result = _load_from_ini(intIdx, text_from_host(iniFile, &owned), pnMaxCores)
    free(owned)
    return result


cdef int32_t _load_from_ini(uint32_t intIdx, const char *iniFile, uint32_t *pnMaxCores) noexcept nogil:
    """LoadFromIni on one core: every key read into a copy of the core's settings, the tables it
    names read, and only when all are good the copy taken (under the lock); the number of cores
    in *pnMaxCores. 1 (XEXEC) with the reason in GetLastCallError otherwise, nothing changed."""
    cdef Core *core = core_get(intIdx)
    cdef IniSettings settings
    cdef ErrorInfo err
    cdef int32_t result
    cdef ToolTable *tool_table
    cdef AxisCorrections *axis_tables = NULL
    cdef bint has_tool_table = False, has_axis_tables = False
    if core == NULL:
        return TOOL_CHAIN_BAD_INTR_INDEX
    if iniFile == NULL:
        err_ini_open(refusal(), -1, 0, "(null)")
        core_fail(core, refusal())
        return TOOL_CHAIN_XEXEC
    # read and parse into a copy without the lock (GetPos, GetLastError never wait
    # for the file); store only when every value is good
    result = config_ini_begin(core, &settings)
    if result != 0:
        return result
    settings.tool_table_file = NULL
    settings.narrow_utf8 = -1
    memset(settings.axis_table_files, 0, sizeof(settings.axis_table_files))
    settings.path = iniFile
    settings.err = &err
    clear_error(&err)
    tool_table = <ToolTable *>tc_malloc(sizeof(ToolTable))
    if tool_table == NULL:
        err_out_of_memory(refusal(), -1, 0)
        core_fail(core, refusal())
        return TOOL_CHAIN_XEXEC
    tc_set_stage("reading an INI file")
    result = ini_read(iniFile, ini_apply_setting, &settings)
    tc_set_stage(NULL)
    if result != 0 and err.number == 0:     # the file's reading failed, not one of its keys
        if result == ERR_FILE_OPEN:
            err_ini_open(&err, -1, 0, iniFile)
        else:
            file_error(&err, result, -1, iniFile)
    if result == 0:
        result = _ini_read_tables(&settings, tool_table, &has_tool_table, &axis_tables, &has_axis_tables, &err)
    ini_settings_free(&settings)
    if result != 0:
        free(tool_table)
        core_fail(core, &err)
        return TOOL_CHAIN_XEXEC
    normalise_gcode_parameters(&settings.params)
    config_ini_store(core, &settings, tool_table if has_tool_table else NULL, axis_tables, has_axis_tables)
    if settings.narrow_utf8 >= 0:
        set_narrow_utf8(settings.narrow_utf8)
    free(tool_table)
    if pnMaxCores != NULL:
        pnMaxCores[0] = TOOL_CHAIN_MAX_CORES
    return TOOL_CHAIN_SUCCESS


cdef public int32_t ToolChainCore_DestroyCNC(uint32_t intIdx) noexcept nogil:
    """DestroyCNC: ends whatever the core does and drops its program (status 0)."""
    cdef Core *core = core_get(intIdx)
    if core == NULL:
        return TOOL_CHAIN_BAD_INTR_INDEX
    return core_end(core, END_DESTROY, "DestroyCNC", 0, NULL)


cdef public TGM_LPCTSTR ToolChainCore_GetVersionString(uint32_t intIdx) noexcept nogil:
    """GetVersionString: the library's name, version and build time in the host's text; an empty
    text for a bad core."""
    if core_get(intIdx) == NULL:
        return text_to_host_kept("")
    return text_to_host_kept(TC_VERSION_STRING)


cdef public int32_t ToolChainCore_GetStructuresSize(uint32_t intIdx, uint32_t nItems, uint32_t *items) noexcept nogil:
    """GetStructuresSize: up to nItems numbers, [0] how many sizes follow (8), then the sizes of
    the ABI's structures, so a host can check it talks to a compatible library."""
    cdef uint32_t sizes[9]
    cdef uint32_t i
    sizes[0] = 8
    sizes[1] = sizeof(GCODE_PARAMETERS)
    sizes[2] = sizeof(SIMPLE_GM_PARAMS)
    sizes[3] = sizeof(GM_PARAMS_ENHANCED)
    sizes[4] = sizeof(CALLBACK_INFO)
    sizes[5] = sizeof(GCODE_INFO)
    sizes[6] = sizeof(MACHINE_STATUS)
    sizes[7] = sizeof(MACHINE_PARAMETERS)
    sizes[8] = sizeof(DLL_INIT_STRUCT)
    if items == NULL:
        return TOOL_CHAIN_SUCCESS
    for i in range(nItems if nItems < 9 else 9):
        items[i] = sizes[i]
    return TOOL_CHAIN_SUCCESS


# ------------------------------------------------------------------ parameters

cdef public int32_t ToolChainCore_SetGCodeParameters(uint32_t intIdx, const GCODE_PARAMETERS *p) noexcept nogil:
    """SetGCodeParameters: its arguments checked, then configuration's rule
    (config_set_gcode_parameters)."""
    cdef Core *core = core_get(intIdx)
    if core == NULL:
        return TOOL_CHAIN_BAD_INTR_INDEX
    if p == NULL:
        return TOOL_CHAIN_ERROR
    return config_set_gcode_parameters(core, p)


cdef public int32_t ToolChainCore_GetGCodeParameters(uint32_t intIdx, GCODE_PARAMETERS *p) noexcept nogil:
    """GetGCodeParameters: a copy of the core's GCODE_PARAMETERS taken under the lock."""
    cdef Core *core = core_get(intIdx)
    if core == NULL:
        return TOOL_CHAIN_BAD_INTR_INDEX
    if p == NULL:
        return TOOL_CHAIN_ERROR
    config_gcode_parameters(core, p)
    return TOOL_CHAIN_SUCCESS


cdef public int32_t ToolChainCore_GetMachineParameters(uint32_t intIdx, MACHINE_PARAMETERS *p) noexcept nogil:
    """GetMachineParameters: a copy of the core's MACHINE_PARAMETERS taken under the lock."""
    cdef Core *core = core_get(intIdx)
    if core == NULL:
        return TOOL_CHAIN_BAD_INTR_INDEX
    if p == NULL:
        return TOOL_CHAIN_ERROR
    config_machine_parameters(core, p)
    return TOOL_CHAIN_SUCCESS


cdef public int32_t ToolChainCore_SetMachineParameters(uint32_t intIdx, MACHINE_PARAMETERS *p) noexcept nogil:
    """SetMachineParameters: checked (the error through GetLastCallError), then the core's."""
    cdef Core *core = core_get(intIdx)
    cdef ErrorInfo err
    if core == NULL:
        return TOOL_CHAIN_BAD_INTR_INDEX
    if p == NULL:
        return TOOL_CHAIN_ERROR
    if not check_machine_parameters(p, &err):
        core_fail(core, &err)
        return TOOL_CHAIN_ERROR
    config_set_machine_parameters(core, p)
    return TOOL_CHAIN_SUCCESS


cdef public int32_t ToolChainCore_SetUserParams(uint32_t intIdx, const double *p, uint32_t n) noexcept nogil:
    """SetUserParams: n = 100 presets P00..P99 (finite) for the next compilations, n = 0 clears
    the preset; any other n is -1."""
    cdef Core *core = core_get(intIdx)
    if core == NULL:
        return TOOL_CHAIN_BAD_INTR_INDEX
    if n != 0 and n != 100:
        return TOOL_CHAIN_ERROR
    if n == 100 and p == NULL:
        return TOOL_CHAIN_ERROR
    if n == 100 and not user_params_finite(p):
        return TOOL_CHAIN_ERROR
    config_set_user_params(core, p if n == 100 else NULL)
    return TOOL_CHAIN_SUCCESS


cdef public int32_t ToolChainCore_GCodePrefixPostfix(uint32_t intIdx, TGM_LPCSTR prefix, TGM_LPCSTR postfix) noexcept nogil:
    """GCodePrefixPostfix: the G-code compiled before and after every main program (NULL or
    empty: none), copied in UTF-8; refused while the status does not allow it."""
    cdef Core *core = core_get(intIdx)
    cdef char *pre = NULL
    cdef char *post = NULL
    if core == NULL:
        return TOOL_CHAIN_BAD_INTR_INDEX
    if prefix != NULL and prefix[0] != 0:
        pre = narrow_from_host(prefix)          # UTF-8 inside (Windows: from the ANSI code page)
        if pre == NULL:
            pre = tc_strdup(prefix)
    if postfix != NULL and postfix[0] != 0:
        post = narrow_from_host(postfix)
        if post == NULL:
            post = tc_strdup(postfix)
    if (pre == NULL and prefix != NULL and prefix[0] != 0) or (post == NULL and postfix != NULL and postfix[0] != 0):
        free(pre)
        free(post)
        err_out_of_memory(refusal(), -1, 0)
        return core_fail(core, refusal())
    return config_set_prefix_postfix(core, pre, post)


# ------------------------------------------------------------------ compilation

cdef public int32_t ToolChainCore_CompileFromFile(uint32_t intIdx, TGM_LPCTSTR fileName) noexcept nogil:
    """CompileFromFile: the file's name converted from the host's text, then
    _compile_from_file."""
    cdef char *owned
    cdef int32_t result = _compile_from_file(intIdx, text_from_host(fileName, &owned))
    free(owned)
    return result


cdef int32_t _compile_from_file(uint32_t intIdx, const char *fileName) noexcept nogil:
    """CompileFromFile on one core: a name that is missing, too long or names no readable file
    is refused now (the status unchanged); otherwise the compile worker starts, reading the file
    in its thread."""
    cdef Core *core = core_get(intIdx)
    cdef int32_t unreadable
    if core == NULL:
        return TOOL_CHAIN_BAD_INTR_INDEX
    if fileName == NULL:
        err_file_open(refusal(), -1, 0, "(null)")
        core_fail(core, refusal())
        return TOOL_CHAIN_ERROR
    if fileName[0] == 0 or strlen(fileName) >= <size_t>TOOL_CHAIN_MAX_FILE_NAME:
        err_file_open(refusal(), -1, 0, fileName)
        core_fail(core, refusal())
        return TOOL_CHAIN_ERROR
    # refused now when it cannot be read (never blocks: files.pyx); read in the worker
    unreadable = file_check_readable(fileName)
    if unreadable != 0:
        file_error(refusal(), unreadable, -1, fileName)
        core_fail(core, refusal())
        return TOOL_CHAIN_ERROR
    return core_start_compile(core, fileName, NULL, 0)


cdef public int32_t ToolChainCore_CompileFromMemory(uint32_t intIdx, TGM_LPCTSTR fileName, TGM_LPCSTR code) noexcept nogil:
    """CompileFromMemory: the name from the host's text and the G-code in UTF-8, then
    _compile_from_memory."""
    cdef char *owned
    cdef char *utf8 = narrow_from_host(code)    # the G-code in UTF-8 (Windows: from the ANSI code page)
    cdef const char *source = code
    cdef int32_t result
    if utf8 != NULL:
        source = utf8
    result = _compile_from_memory(intIdx, text_from_host(fileName, &owned), source)
    free(owned)
    free(utf8)
    return result


cdef int32_t _compile_from_memory(uint32_t intIdx, const char *fileName, const char *code) noexcept nogil:
    """CompileFromMemory on one core: the text copied (the host may free its own at once) and
    the compile worker started; -1 for a missing or too long name."""
    cdef Core *core = core_get(intIdx)
    cdef char *source
    if core == NULL:
        return TOOL_CHAIN_BAD_INTR_INDEX
    if fileName == NULL or code == NULL or fileName[0] == 0 or strlen(fileName) >= <size_t>TOOL_CHAIN_MAX_FILE_NAME:
        return TOOL_CHAIN_ERROR
    source = tc_strdup(code)
    if source == NULL:
        err_out_of_memory(refusal(), -1, 0)
        core_fail(core, refusal())
        return TOOL_CHAIN_ERROR
    return core_start_compile(core, fileName, source, strlen(source))


cdef public int32_t ToolChainCore_IsBusy(uint32_t intIdx) noexcept nogil:
    """IsBusy: 1 while the core compiles, simulates or moves (a positive status), else 0."""
    cdef Core *core = core_get(intIdx)
    if core == NULL:
        return TOOL_CHAIN_BAD_INTR_INDEX
    return 1 if core_status(core) > 0 else 0


cdef public int32_t ToolChainCore_GetLastError(uint32_t intIdx, CALLBACK_INFO *info) noexcept nogil:
    """GetLastError: the error of the last compilation or run into info (1), or 0 when it
    succeeded."""
    cdef Core *core = core_get(intIdx)
    if core == NULL:
        return TOOL_CHAIN_BAD_INTR_INDEX
    if info == NULL:
        return TOOL_CHAIN_ERROR
    return core_read_error(core, False, info)


cdef public int32_t ToolChainCore_GetLastCallError(uint32_t intIdx, CALLBACK_INFO *info) noexcept nogil:
    """GetLastCallError: the error of the last call on the core that was refused with a reason
    (1), or 0."""
    cdef Core *core = core_get(intIdx)
    if core == NULL:
        return TOOL_CHAIN_BAD_INTR_INDEX
    if info == NULL:
        return TOOL_CHAIN_ERROR
    return core_read_error(core, True, info)


cdef public int32_t ToolChainCore_GetLastErrorColumn(uint32_t intIdx, int32_t ofCalls, int32_t *column) noexcept nogil:
    """GetLastErrorColumn: the column of the word in error of the error GetLastError (ofCalls 0)
    or GetLastCallError (1) gives."""
    cdef Core *core = core_get(intIdx)
    if core == NULL:
        return TOOL_CHAIN_BAD_INTR_INDEX
    if column == NULL or (ofCalls != 0 and ofCalls != 1):
        return TOOL_CHAIN_ERROR
    return core_read_error_column(core, ofCalls == 1, column)


cdef public int32_t ToolChain_GetLastError(CALLBACK_INFO *info) noexcept nogil:
    """The vendor's older single-core GetLastError: core 0's."""
    return ToolChainCore_GetLastError(0, info)


cdef public int32_t ToolChainCore_FileToIdx(uint32_t intIdx, TGM_LPCTSTR fileName) noexcept nogil:
    """FileToIdx: the index of a file name in the core's file table (the special names their
    negative indexes)."""
    cdef Core *core = core_get(intIdx)
    cdef char *owned
    cdef int32_t result
    if core == NULL:
        return TOOL_CHAIN_BAD_INTR_INDEX
    result = core_file_to_idx(core, text_from_host(fileName, &owned))
    free(owned)
    return result


cdef public TGM_LPCTSTR ToolChainCore_IdxToFile(uint32_t intIdx, int32_t fileIdx) noexcept nogil:
    """IdxToFile: the name of a file index in the host's text; __unknown__ for an unknown index
    or a bad core, never NULL."""
    cdef Core *core = core_get(intIdx)
    if core == NULL:
        return text_to_host_kept("__unknown__")
    return text_to_host_kept(core_idx_to_file(core, fileIdx))


cdef public TGM_LPCTSTR ToolChain_IdxToFile(int32_t fileIdx) noexcept nogil:
    """The vendor's older single-core IdxToFile: core 0's."""
    return ToolChainCore_IdxToFile(0, fileIdx)


cdef public int32_t ToolChainCore_GetGCodeSizeInfo(uint32_t intIdx, GCODE_INFO *p) noexcept nogil:
    """GetGCodeSizeInfo: the compiled program's extent (as written, compensated, both rotated by
    G168), measured again first when a reset moved the start; -1 while compiling or without a
    program."""
    cdef Core *core = core_get(intIdx)
    if core == NULL:
        return TOOL_CHAIN_BAD_INTR_INDEX
    if p == NULL or core_status(core) == CNC_STATUS_COMPILING:
        return TOOL_CHAIN_ERROR
    return core_size_info(core, p)


cdef public double ToolChainCore_GetGCodeRunTime(uint32_t intIdx, int32_t fileIdx) noexcept nogil:
    """GetGCodeRunTime: the run time in seconds of a file index (the last simulation's with
    calcTime, or the host's); negative when unknown."""
    cdef Core *core = core_get(intIdx)
    if core == NULL or fileIdx < 0 or fileIdx >= MAX_FILES:
        return -1.0
    return core_file_run_time(core, fileIdx)


cdef public int32_t ToolChainCore_SetGCodeRunTime(uint32_t intIdx, int32_t fileIdx, double seconds) noexcept nogil:
    """SetGCodeRunTime: the host's run time (finite, >= 0) of a known file index."""
    cdef Core *core = core_get(intIdx)
    if core == NULL:
        return TOOL_CHAIN_BAD_INTR_INDEX
    if fileIdx < 0 or fileIdx >= MAX_FILES or not (seconds >= 0.0) or not isfinite(seconds):
        return TOOL_CHAIN_ERROR
    return TOOL_CHAIN_SUCCESS if core_set_file_run_time(core, fileIdx, seconds) else TOOL_CHAIN_ERROR


# ------------------------------------------------------------------ running

cdef public int32_t ToolChainCore_ResetCNC(uint32_t intIdx, int32_t regime, uint32_t nCoords, const double *coords) noexcept nogil:
    """ResetCNC: ends any activity and sets where the next run and compilation start: regime 1
    only marks the program start, otherwise the first nCoords coordinates (finite) from
    coords."""
    cdef Core *core = core_get(intIdx)
    if core == NULL:
        return TOOL_CHAIN_BAD_INTR_INDEX
    if regime == RESET_MARK_START_ONLY:
        nCoords = 0
    elif nCoords > 10 or (nCoords > 0 and coords == NULL):
        return TOOL_CHAIN_ERROR
    if regime != RESET_MARK_START_ONLY and not coordinates_finite(coords, nCoords):
        return TOOL_CHAIN_ERROR
    return core_end(core, END_RESET, "ResetCNC", nCoords, coords)


cdef public int32_t ToolChainCore_StartCNCEx(uint32_t intIdx, int32_t regime, TGM_LPCSTR addCode) noexcept nogil:
    """StartCNCEx: a run in `regime` (10, 20 the simulator; 30-33 the offline machine),
    addCode's M functions in UTF-8 sent first."""
    cdef Core *core = core_get(intIdx)
    cdef char *utf8
    cdef int32_t result
    if core == NULL:
        return TOOL_CHAIN_BAD_INTR_INDEX
    utf8 = narrow_from_host(addCode)
    if utf8 != NULL:
        addCode = utf8
    result = core_start_run(core, regime, addCode)
    free(utf8)
    return result


cdef public int32_t ToolChainCore_StopCNCEx(uint32_t intIdx, TGM_LPCSTR addCode) noexcept nogil:
    """StopCNCEx: a controlled stop on the trajectory; addCode's M functions (UTF-8) sent once
    it stands."""
    cdef Core *core = core_get(intIdx)
    cdef char *utf8
    cdef int32_t result
    if core == NULL:
        return TOOL_CHAIN_BAD_INTR_INDEX
    utf8 = narrow_from_host(addCode)
    if utf8 != NULL:
        addCode = utf8
    result = core_stop(core, addCode)
    free(utf8)
    return result


cdef int32_t not_implemented(uint32_t intIdx, const char *what) noexcept nogil:
    """Functions of the offline machine that are not implemented yet: the documented
    error code -1, and an error saying so."""
    cdef Core *core = core_get(intIdx)
    if core == NULL:
        return TOOL_CHAIN_BAD_INTR_INDEX
    err_not_implemented(refusal(), -1, 0, what)
    core_fail(core, refusal())
    return TOOL_CHAIN_ERROR


cdef public int32_t ToolChainCore_ConnectCNCEx_Plane(uint32_t intIdx, uint32_t nType, uint32_t nCoords, const double *coords, TGM_LPCSTR addCode, uint32_t axesForCalc, uint32_t axesForConnect, int32_t stateAfter) noexcept nogil:
    """ConnectCNCEx_Plane: checks the arguments (at most 11 finite coordinates, stateAfter 0 or
    2), then the connection back onto the trajectory in the machine's worker (core_connect)."""
    cdef char *utf8
    cdef int32_t result
    if core_get(intIdx) == NULL:
        return TOOL_CHAIN_BAD_INTR_INDEX
    if nCoords > 11 or (nCoords > 0 and coords == NULL) or (stateAfter != 0 and stateAfter != 2):
        return TOOL_CHAIN_ERROR
    if not coordinates_finite(coords, nCoords):
        return TOOL_CHAIN_ERROR
    utf8 = narrow_from_host(addCode)
    if utf8 != NULL:
        addCode = utf8
    result = core_connect(core_get(intIdx), nType, nCoords, coords, addCode, axesForCalc, axesForConnect, stateAfter)
    free(utf8)
    return result


cdef public int32_t ToolChainCore_GoToPosition(uint32_t intIdx, uint32_t nCoords, const double *coords) noexcept nogil:
    """GoToPosition: a manual straight move to the first nCoords (finite) absolute
    coordinates."""
    cdef Core *core = core_get(intIdx)
    cdef SIMPLE_GM_PARAMS dest
    if core == NULL:
        return TOOL_CHAIN_BAD_INTR_INDEX
    if nCoords > 10 or (nCoords > 0 and coords == NULL) or not coordinates_finite(coords, nCoords):
        return TOOL_CHAIN_ERROR
    memset(&dest, 0, sizeof(dest))
    dest.m_func = 1
    return core_goto(core, &dest, nCoords, coords)


cdef public int32_t ToolChainCore_GoToPositionEx(uint32_t intIdx, const SIMPLE_GM_PARAMS *dest) noexcept nogil:
    """GoToPositionEx: a manual line (m_func 1) or arc (2 CW, 3 CCW) to dest's end, with finite
    coordinates."""
    cdef Core *core = core_get(intIdx)
    if core == NULL:
        return TOOL_CHAIN_BAD_INTR_INDEX
    if dest == NULL or dest.m_func < 1 or dest.m_func > 3:
        return TOOL_CHAIN_ERROR
    if not coordinates_finite(<const double *>&dest.m_calcE, AXES) or not coordinates_finite(<const double *>&dest.m_cc, AXES):
        return TOOL_CHAIN_ERROR
    return core_goto(core, dest, 10, <const double *>&dest.m_calcE)


cdef public int32_t ToolChainCore_MFunc(uint32_t intIdx, const SIMPLE_GM_PARAMS *fun, int32_t bDirectToPLC) noexcept nogil:
    """MFunc: the M function `fun` to DriverMFunc on the caller's thread while the machine
    stands (bDirectToPLC unused: the offline machine has no PLC)."""
    cdef Core *core = core_get(intIdx)
    if core == NULL:
        return TOOL_CHAIN_BAD_INTR_INDEX
    if fun == NULL:
        return TOOL_CHAIN_ERROR
    return session_standing_m(core, fun)


cdef public int32_t ToolChainCore_SetRelFeed(uint32_t intIdx, double relFeed) noexcept nogil:
    """SetRelFeed: the feed override, clamped to the interpolator's 0.01..2; the machine reaches
    it gradually. NaN is -1."""
    cdef Core *core = core_get(intIdx)
    if core == NULL:
        return TOOL_CHAIN_BAD_INTR_INDEX
    if not (relFeed == relFeed):        # NaN
        return TOOL_CHAIN_ERROR
    if relFeed < REL_FEED_MIN:          # the interpolator's Rel_Speed: 0.01 .. 2 (1 % .. 200 %)
        relFeed = REL_FEED_MIN
    elif relFeed > REL_FEED_MAX:
        relFeed = REL_FEED_MAX
    config_set_rel_feed(core, relFeed)
    return TOOL_CHAIN_SUCCESS


cdef public int32_t ToolChainCore_SetBreakpoint(uint32_t intIdx, uint32_t editorLine, int32_t fileIdx) noexcept nogil:
    """SetBreakpoint: the one built-in breakpoint (line and file index) a run stops before."""
    cdef Core *core = core_get(intIdx)
    if core == NULL:
        return TOOL_CHAIN_BAD_INTR_INDEX
    config_set_breakpoint(core, editorLine, fileIdx)
    return TOOL_CHAIN_SUCCESS


cdef public int32_t ToolChainCore_ResetStatusCNC(uint32_t intIdx, uint32_t mode) noexcept nogil:
    """ResetStatusCNC: in a negative status, mode 0 drops the compiled program (status 0), mode
    1 declares the machine out of the trajectory (-50)."""
    cdef Core *core = core_get(intIdx)
    if core == NULL:
        return TOOL_CHAIN_BAD_INTR_INDEX
    if mode > 1:
        return TOOL_CHAIN_ERROR
    return core_end(core, END_DROP_PROGRAM if mode == 0 else END_OUT_OF_TRAJECTORY, "ResetStatusCNC", 0, NULL)


cdef public int32_t ToolChainCore_StatusCNC(uint32_t intIdx) noexcept nogil:
    """StatusCNC: the core's cnc_status, lock-free (a panel polls it); CNC_STATUS_INVALID for a
    bad core."""
    cdef Core *core = core_get(intIdx)
    if core == NULL:
        return CNC_STATUS_INVALID
    return core_status(core)


cdef public int32_t ToolChainCore_GetPos(uint32_t intIdx, int32_t reserved, SIMPLE_GM_PARAMS *pos, GM_PARAMS_ENHANCED *enh) noexcept nogil:
    """GetPos: the last published snapshot of the run (either pointer may be NULL, not both)
    with the status of now, and the override of now while the machine does not move; never waits
    for a lock."""
    cdef Core *core = core_get(intIdx)
    if core == NULL:
        return TOOL_CHAIN_BAD_INTR_INDEX
    if pos == NULL and enh == NULL:
        return TOOL_CHAIN_ERROR
    core_read_position(core, pos, enh)
    return TOOL_CHAIN_SUCCESS


cdef public int32_t ToolChainCore_LoadCNCCalcPlugIn(TGM_LPCTSTR fileName, uint32_t flags, int64_t userValue) noexcept nogil:
    """LoadCNCCalcPlugIn: plug-ins (kinematics) are not supported yet: an empty name unloads (1:
    nothing is loaded), any other is the documented -1 with an error saying so; -1 while a core
    is busy."""
    cdef int i
    cdef char *owned
    cdef const char *name
    cdef bint unloading
    if fileName == NULL:
        return TOOL_CHAIN_ERROR
    for i in range(TOOL_CHAIN_MAX_CORES):
        if core_status(core_get(i)) > 0:
            return TOOL_CHAIN_ERROR
    name = text_from_host(fileName, &owned)
    unloading = name != NULL and name[0] == 0
    free(owned)
    if unloading:
        return 1                          # unloading: nothing is loaded
    return not_implemented(0, "LoadCNCCalcPlugIn")     # no core argument: reported on core 0


# ------------------------------------------------------------------ callbacks

cdef public int32_t ToolChainCore_SetCallBack(uint32_t intIdx, uint32_t fceNo, intptr_t userData, void *fn) noexcept nogil:
    """SetCallBack: callback fceNo of the core (NULL clears it); the driver's callbacks (above
    1000) only after LoadFromIni. Returns once no call of the old function runs on another
    thread."""
    cdef Core *core = core_get(intIdx)
    cdef int32_t slot
    if core == NULL:
        return TOOL_CHAIN_BAD_INTR_INDEX
    slot = callback_slot(fceNo)
    if slot < 0:
        return TOOL_CHAIN_ERROR
    if fceNo > 1000 and fn != NULL and not config_ini_loaded(core):
        _fail_ini_first(core, fceNo)
        return TOOL_CHAIN_ERROR
    callback_set(core, slot, fn, userData)
    return TOOL_CHAIN_SUCCESS


cdef void _fail_ini_first(Core *core, uint32_t number) noexcept nogil:
    """SetCallBack of a driver callback before LoadFromIni: the error that says the INI comes
    first."""
    err_ini_first(refusal(), -1, 0, number)
    core_fail(core, refusal())


# ------------------------------------------------------------------ logging

cdef public int32_t ToolChainCore_SetLogValue(uint32_t value) noexcept nogil:
    """SetLogValue: the mask of what is logged."""
    log_set_mask(value)
    return TOOL_CHAIN_SUCCESS


cdef public uint32_t ToolChainCore_GetLogValue() noexcept nogil:
    """GetLogValue: the mask of what is logged."""
    return g_log_mask


cdef public void ToolChain_LogANSI(TGM_LPCSTR text) noexcept nogil:
    """LogANSI: one line of the host's text appended to the log (UTF-8 in the file)."""
    cdef char *utf8 = narrow_from_host(text)    # the log file is UTF-8 (Windows: from the ANSI code page)
    if utf8 != NULL:
        text = utf8
    log_line(0, text)
    free(utf8)


cdef public void ToolChain_FlushLogFile() noexcept nogil:
    """FlushLogFile: the log written out to its file."""
    log_flush()


cdef public int32_t ToolChain_SetLogHook(intptr_t userData, void *fn) noexcept nogil:
    """SetLogHook: every log line (source, text) also to one C function, on the thread that
    logs."""
    return log_set_hook(userData, fn)


cdef public int32_t ToolChainCore_SetLookAhead(uint32_t intIdx, int32_t parts) noexcept nogil:
    """SetLookAhead: the feed planner's window for the next compilations: 0 the vendor's 8
    parts, n parts, or -1 unlimited."""
    cdef Core *core = core_get(intIdx)
    if core == NULL:
        return TOOL_CHAIN_BAD_INTR_INDEX
    if parts < -1:
        return TOOL_CHAIN_ERROR
    config_set_plan_window(core, parts)
    return TOOL_CHAIN_SUCCESS


# ------------------------------------------------------------------ offline machine (extension)

cdef public int32_t ToolChainCore_SetTimeScale(uint32_t intIdx, double scale) noexcept nogil:
    """SetTimeScale: the offline machine's speed against real time, in (0, 1e6]."""
    cdef Core *core = core_get(intIdx)
    if core == NULL:
        return TOOL_CHAIN_BAD_INTR_INDEX
    if not (0.0 < scale <= 1e6):
        return TOOL_CHAIN_ERROR
    config_set_time_scale(core, scale)
    return TOOL_CHAIN_SUCCESS


cdef public int32_t ToolChainCore_ConfirmMFunc(uint32_t intIdx) noexcept nogil:
    """ConfirmMFunc: confirms the M function the machine waits at after DriverMFunc answered
    TC_MFUNC_LATER."""
    cdef Core *core = core_get(intIdx)
    if core == NULL:
        return TOOL_CHAIN_BAD_INTR_INDEX
    return session_confirm(core)


cdef public int32_t ToolChainCore_TestClock(uint32_t intIdx, uint64_t key, double seconds) noexcept nogil:
    """Test-only TestClock: the offline machine's stepped clock (with TC_TEST_CLOCK_KEY), so
    tests step the machine instead of sleeping."""
    cdef Core *core = core_get(intIdx)
    if core == NULL:
        return TOOL_CHAIN_BAD_INTR_INDEX
    return machine_test_clock(core, key, seconds)


cdef public int64_t ToolChain_TestAllocFail(uint64_t key, int64_t nth) noexcept nogil:
    """Test-only TestAllocFail: with TC_TEST_ALLOC_KEY the nth allocation from now fails, once,
    so tests can fail each allocation of an operation in turn."""
    if key != TC_TEST_ALLOC_KEY or nth < 0:
        return -1
    return tc_alloc_fail_nth(nth)


# ------------------------------------------------------------------ toolpath (extension)

cdef public int32_t ToolChainCore_GetToolpath(uint32_t intIdx, TC_TOOLPATH_RECORD *out, uint64_t capacity,
                                              uint64_t first, uint64_t *total) noexcept nogil:
    """GetToolpath: the compiled program as TC_TOOLPATH_RECORDs from `first` into the host's
    memory (at most capacity), the number of records in *total; -1 while compiling."""
    cdef Core *core = core_get(intIdx)
    if core == NULL:
        return TOOL_CHAIN_BAD_INTR_INDEX
    if (out == NULL and capacity > 0) or core_status(core) == CNC_STATUS_COMPILING:
        return TOOL_CHAIN_ERROR
    return toolpath_copy(core, out, capacity, first, total)


# ------------------------------------------------------------------ correction tables and smoothing (extension)

cdef public int32_t ToolChainCore_LoadToolTable(uint32_t intIdx, TGM_LPCTSTR fileName) noexcept nogil:
    """LoadToolTable: the file's name converted from the host's text, then _load_tool_table."""
    cdef char *owned
    cdef int32_t result = _load_tool_table(intIdx, text_from_host(fileName, &owned))
    free(owned)
    return result


cdef int32_t _load_tool_table(uint32_t intIdx, const char *fileName) noexcept nogil:
    """LoadToolTable on one core: the TAB0.KOR file read without the lock, then the core's tool
    table; the core's unchanged when it cannot be read."""
    cdef Core *core = core_get(intIdx)
    cdef ToolTable *table
    cdef ErrorInfo err
    if core == NULL:
        return TOOL_CHAIN_BAD_INTR_INDEX
    if fileName == NULL:
        err_file_open(refusal(), -1, 0, "(null)")
        return core_fail(core, refusal())
    if fileName[0] == 0:
        err_file_open(refusal(), -1, 0, fileName)
        return core_fail(core, refusal())
    table = <ToolTable *>tc_malloc(sizeof(ToolTable))
    if table == NULL:
        err_out_of_memory(refusal(), -1, 0)
        return core_fail(core, refusal())
    if not tool_table_read(fileName, table, &err):      # read without the lock
        free(table)
        core_fail(core, &err)
        return TOOL_CHAIN_ERROR
    config_set_tool_table(core, table)
    free(table)
    return TOOL_CHAIN_SUCCESS


cdef public int32_t ToolChainCore_GetToolCorrection(uint32_t intIdx, uint32_t entry, double *values) noexcept nogil:
    """GetToolCorrection: the values of tool table entry 1..TOOL_ENTRIES."""
    cdef Core *core = core_get(intIdx)
    if core == NULL:
        return TOOL_CHAIN_BAD_INTR_INDEX
    if values == NULL or entry < 1 or entry > TOOL_ENTRIES:
        return TOOL_CHAIN_ERROR
    config_tool_correction(core, entry, values)
    return TOOL_CHAIN_SUCCESS


cdef public int32_t ToolChainCore_SetToolCorrection(uint32_t intIdx, uint32_t entry, uint32_t programmed,
                                                    const double *values) noexcept nogil:
    """SetToolCorrection: the values of one entry of the core's tool table, `programmed` the
    mask of those given; checked, the reason through GetLastCallError."""
    cdef Core *core = core_get(intIdx)
    cdef ErrorInfo err
    if core == NULL:
        return TOOL_CHAIN_BAD_INTR_INDEX
    if programmed >> TOOL_VALUES or (values == NULL and programmed != 0):
        return TOOL_CHAIN_ERROR
    if not config_set_tool_correction(core, entry, programmed, values, &err):
        return core_fail(core, &err)
    return TOOL_CHAIN_SUCCESS


cdef public int32_t ToolChainCore_LoadAxisCorrections(uint32_t intIdx, uint32_t nFiles,
                                                      const TGM_LPCTSTR *fileNames) noexcept nogil:
    """LoadAxisCorrections: the names converted from the host's text (one more than the tables
    allowed, for the error of too many), then _load_axis_corrections."""
    cdef const char *names[AXIS_TABLES_MAX + 1]
    cdef char *owned[AXIS_TABLES_MAX + 1]
    cdef uint32_t n = nFiles if nFiles <= AXIS_TABLES_MAX + 1 else AXIS_TABLES_MAX + 1
    cdef uint32_t k
    cdef int32_t result
    if nFiles > 0 and fileNames == NULL:
        return TOOL_CHAIN_BAD_INTR_INDEX if core_get(intIdx) == NULL else TOOL_CHAIN_ERROR
    for k in range(n):
        names[k] = text_from_host(fileNames[k], &owned[k])
    result = _load_axis_corrections(intIdx, nFiles, names)
    for k in range(n):
        free(owned[k])
    return result


cdef int32_t _load_axis_corrections(uint32_t intIdx, uint32_t nFiles, const char *const *fileNames) noexcept nogil:
    """LoadAxisCorrections on one core: the ACHS3D??.KOR files read without the lock, then they
    replace the core's tables (a run keeps the ones it took, by their owner count)."""
    cdef Core *core = core_get(intIdx)
    cdef AxisCorrections *tables = NULL
    cdef ErrorInfo err
    cdef uint32_t k
    cdef bint good
    if core == NULL:
        return TOOL_CHAIN_BAD_INTR_INDEX
    for k in range(nFiles if nFiles <= AXIS_TABLES_MAX + 1 else AXIS_TABLES_MAX + 1):
        if fileNames[k] == NULL:
            err_file_open(refusal(), -1, 0, "(null)")
            return core_fail(core, refusal())
        if fileNames[k][0] == 0:
            err_file_open(refusal(), -1, 0, fileNames[k])
            return core_fail(core, refusal())
    tc_set_stage("reading an axis table")
    good = axis_corrections_read(fileNames, nFiles, &tables, &err)      # read without the lock
    tc_set_stage(NULL)
    if not good:
        core_fail(core, &err)
        return TOOL_CHAIN_ERROR
    config_set_axis_corrections(core, tables)
    return TOOL_CHAIN_SUCCESS


cdef public int32_t ToolChainCore_CorrectPosition(uint32_t intIdx, const double *position, double *corrected) noexcept nogil:
    """CorrectPosition: a position (ten finite coordinates) with the core's axis correction
    tables applied."""
    cdef Core *core = core_get(intIdx)
    cdef AxisCorrections *tables
    if core == NULL:
        return TOOL_CHAIN_BAD_INTR_INDEX
    if position == NULL or corrected == NULL or not coordinates_finite(position, 10):
        return TOOL_CHAIN_ERROR
    tables = config_axis_corrections_ref(core)
    axis_correction_apply(tables, position, corrected)
    axis_corrections_release(tables)
    return TOOL_CHAIN_SUCCESS


cdef public int32_t ToolChainCore_SetSmoothing(uint32_t intIdx, int32_t command, const double *params) noexcept nogil:
    """SetSmoothing: the spline (Command -2) or IIR filter (-1) of the machine's output in the
    vendor's units, checked."""
    cdef Core *core = core_get(intIdx)
    cdef ErrorInfo err
    if core == NULL:
        return TOOL_CHAIN_BAD_INTR_INDEX
    if params == NULL or (command != SMOOTHING_COMMAND_SPLINE and command != SMOOTHING_COMMAND_IIR):
        return TOOL_CHAIN_ERROR
    if not config_set_smoothing(core, command, params, &err):
        return core_fail(core, &err)
    return TOOL_CHAIN_SUCCESS


cdef public int32_t ToolChainCore_GetSmoothing(uint32_t intIdx, int32_t command, double *params) noexcept nogil:
    """GetSmoothing: the spline's two values (the rest 0) or the IIR filter's four."""
    cdef Core *core = core_get(intIdx)
    if core == NULL:
        return TOOL_CHAIN_BAD_INTR_INDEX
    if params == NULL or (command != SMOOTHING_COMMAND_SPLINE and command != SMOOTHING_COMMAND_IIR):
        return TOOL_CHAIN_ERROR
    config_smoothing_parameters(core, command, params)
    return TOOL_CHAIN_SUCCESS


cdef public int32_t ToolChainCore_SmoothSamples(uint32_t intIdx, const double *samples, uint64_t nSamples,
                                                double *out, uint64_t *settledFrom) noexcept nogil:
    """SmoothSamples: the core's spline and IIR filter run over the host's samples (ten axes
    each, one per 100 us step) into out (which may be samples); *settledFrom: the first sample
    from which the output stays settled. -1 if a sample or an output is not finite."""
    cdef Core *core = core_get(intIdx)
    cdef SmoothingConfig config
    cdef Smoother smoother
    cdef double sample[10]
    cdef uint64_t i, settled_from = 0
    if core == NULL:
        return TOOL_CHAIN_BAD_INTR_INDEX
    if nSamples > 0 and (samples == NULL or out == NULL):
        return TOOL_CHAIN_ERROR
    for i in range(nSamples):
        if not smoothing_sample_good(samples + 10 * i):
            return TOOL_CHAIN_ERROR
    if nSamples > 0:
        config_smoothing(core, &config)
        if not smoother_init(&smoother, &config, STEP_US * SECONDS_PER_US, samples):
            tc_set_stage("the smoothing")
            err_out_of_memory(refusal(), -1, 0)
            core_fail(core, refusal())
            tc_set_stage(NULL)
            return TOOL_CHAIN_ERROR
        for i in range(nSamples):
            memcpy(sample, samples + 10 * i, sizeof(sample))     # out may be samples
            smoother_push(&smoother, sample, out + 10 * i)
            if not smoother_settled(&smoother):
                settled_from = i + 1
        smoother_free(&smoother)
        for i in range(nSamples):       # the filters' guard: never success with a non-finite output
            if not coordinates_finite(out + 10 * i, 10):
                return TOOL_CHAIN_ERROR
    if settledFrom != NULL:
        settledFrom[0] = settled_from
    return TOOL_CHAIN_SUCCESS
