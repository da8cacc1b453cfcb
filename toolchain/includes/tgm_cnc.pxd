# The ABI structures and constants, declared from include/tgm_cnc.h (the C compiler
# uses the header's definitions; these lines only tell Cython the field names).
from libc.stdint cimport int32_t, uint32_t, int64_t, uint64_t, intptr_t

cdef extern from "tgm_cnc.h" nogil:
    int TOOL_CHAIN_BAD_INTR_INDEX
    int TOOL_CHAIN_ERROR
    int TOOL_CHAIN_SUCCESS
    int TOOL_CHAIN_XEXEC
    int TOOL_CHAIN_XBREAK
    int TOOL_CHAIN_MAX_CORES
    int TOOL_CHAIN_MAX_FILE_NAME
    int TOOL_CHAIN_FILE_UNKNOWN, TOOL_CHAIN_FILE_END, TOOL_CHAIN_FILE_STOP, TOOL_CHAIN_FILE_EXEC
    double INVALID_VALUE
    float INVALID_VALUE_F
    uint32_t GCODE_REZERVA1_ISO_COMPAT
    uint32_t GCODE_REZERVA1_COMP_STRICT
    uint32_t GCODE_REZERVA1_ISO_STRICT
    uint32_t GCODE_REZERVA1_APPLY_UNIMPLEMENTED
    int32_t TC_MFUNC_LATER
    uint64_t TC_TEST_CLOCK_KEY
    uint64_t TC_TEST_ALLOC_KEY
    # the log mask's sources and destinations (SetLogValue)
    uint32_t LOG_TO_CONSOLE, LOG_TO_FILE, LOG_TO_TGM
    uint32_t LOG_DEBUG, LOG_VERBOSE, LOG_WORKER, LOG_TOOLCHAIN, LOG_DRIVER, LOG_COMPILER
    uint32_t LOG_EXECUTOR, LOG_MATH
    # the bits of GCODE_PARAMETERS.correctionStrategy
    enum:
        CORR_START_MODE_MASK
        CORR_SEARCH_DEPTH_MASK
        CORR_ALLOW_FIRST_LAST_CROSS
        CORR_JOIN_BY_G1
        CORR_JOIN_BY_MOVING_START
        CORR_REMOVE_CROSSING
        CORR_ALLOW_REVERSE_SEARCH
        CORR_DROP_NEGATIVE_ARCS
        CORR_CORNER_FACTOR_2
        CORR_CORNER_INTERSECTION
        CORR_G0_NEVER_COMPENSATED
        CORR_OLD_COMPATIBILITY

    # char on Linux, wchar_t on Windows: opaque here, so that every text of the host
    # goes through platform.pxd's text_from_host / text_to_host
    ctypedef const void *TGM_LPCTSTR
    ctypedef void *TGM_LPTSTR
    ctypedef const char *TGM_LPCSTR

    ctypedef struct P10DOUBLE:
        double x, y, z, c, b, u, v, w, a, o
    ctypedef struct P10BOOL:
        int32_t x, y, z, c, b, u, v, w, a, o
    ctypedef struct P26FLOAT:
        float A, B, C, D, E, F, G, H, I, J, K, L, M
        float N, O, P, Q, R, S, T, U, V, W, X, Y, Z
    ctypedef struct DLL_INIT_STRUCT:
        TGM_LPCTSTR CNC_Dll_Dir
        TGM_LPCTSTR Macros_Dir
        TGM_LPCTSTR Comm_Int2_Dir
        int32_t Local_Core_Mode
    ctypedef struct SIMPLE_GM_PARAMS:
        P10DOUBLE m_s, m_e, m_calcS, m_calcE, m_zero, m_cc
        P26FLOAT m_pars
        int32_t m_func
        int32_t m_planeTool
        uint32_t m_reserved
        uint32_t m_editorLine
        int32_t m_fileIdx
        int32_t m_gCodeIndex
        int32_t m_bFeedIsMin
        float m_fp
    ctypedef struct GM_PARAMS_ENHANCED:
        double m_setFeed, m_calcFeed, m_actFeed, m_relFeed
        double m_actPartLen, m_actPartRemain, m_actWorkPartsLen, m_actG00PartsLen, m_actPartsLen
        int32_t m_nWorkCounter, m_nG00Counter, m_nG00ToWorkChanges, m_nWorkToG00Changes, m_nMCounter
        uint32_t m_MasterEditorLine, m_MasterFileIdx
        int32_t m_statusCNC
        double m_cncRunTime
    ctypedef struct CALLBACK_INFO:
        int32_t stringId, nLines, actLine, fileIdx
        TGM_LPCSTR m_fullError
        TGM_LPCSTR m_errorArguments
    ctypedef struct GCODE_SIZE:
        P10DOUBLE m_startPos, m_endPos, m_minimalPos, m_maximalPos
    ctypedef struct GCODE_INFO:
        GCODE_SIZE m_size[4]
    ctypedef struct MACHINE_PARAMETERS:
        P10DOUBLE minCoords, maxCoords, refCoords
        P10BOOL enableMask
        P10DOUBLE backlash, backlashInc
        int32_t backlashValuesSource
        int32_t enhancedInterpolatorParameters
    ctypedef struct MACHINE_STATUS:
        uint32_t m_axesStatus, m_refDone, m_endSwitches
        uint32_t m_reserved1, m_reserved2, m_reserved3, m_reserved4, m_reserved5
        uint32_t m_reserved6, m_reserved7, m_reserved8, m_reserved9, m_reserved10
    ctypedef struct GCODE_FEED:
        double feed, acc, dec
        int32_t rampType, padding1
    ctypedef struct GCODE_CORRECTION:
        double size
        int32_t gCode, padding1
    ctypedef struct ARC_FEED_TABLE:
        double m_r, m_relFeed
    ctypedef struct INTERNAL_MFUNC_INSERT_TABLE:
        int32_t mFunc, padding1
        double relFeed, distance
    ctypedef struct AXIS_LIMITS:
        double maxFeed, maxAcc, maxDec
    ctypedef struct GCODE_PARAMETERS:
        int32_t absMode, swapG2G3
        uint32_t correctionStrategy
        int32_t forceMode
        GCODE_FEED motion[8]
        GCODE_CORRECTION correction[8]
        double maxConnectionDistance, startAngle, endAngle, minAngleFeed
        int32_t disableG0FeedOverride, interpolatorConfig0
        double overrideInc
        ARC_FEED_TABLE arcFeedTable[5]
        double centripetalAcc
        INTERNAL_MFUNC_INSERT_TABLE mFuncInsertTable[3]
        int32_t MfuncInsertType, paddingTo8Bytes_2
        double reserved
        int32_t M02_programEnd1, M30_programEnd2, M03_startSpindleCW, M04_startSpindleCCW
        int32_t M05_stopSpindle, M06_changeTool, M07_coolOn, M08_oilOn, M09_coolOilOff
        int32_t M17_return, M29_print, M80_mirrorOff, M81_mirrorX, M82_mirrorY, M83_mirrorZ
        int32_t M84_mirrorXY, M85_mirrorXZ, M86_mirrorYZ, M87_mirrorXYZ, M99_defFeed
        int32_t insertArcMode, paddingTo8Bytes_3
        double insertArcToleranceRMax, insertArcToleranceRMin
        double insertArcMaxAngle, insertArcMinAngle
        int32_t insertArcPlane, rezerva1, calcTime, rezerva2
        double dynamicG41Correction_mm, dynamicG42Correction_mm
        AXIS_LIMITS axisLimits[10]
        double dynamicG41Correction_percent, dynamicG42Correction_percent
        double tolerance[10]

    # callback numbers
    enum:
        CB_ADD_OUTPUT_LOG, CB_SET_STATUS_BAR_TEXT, CB_IS_DEBUG_MODE, CB_IS_VERBOSE_MODE
        CB_GET_LIB_PATH, CB_GET_TOOL_PATH, CB_GET_SYSTEM_PATH, CB_GET_FILE_TIME_STAMP
        CB_DO_YIELD, CB_READ_INI_STRING, CB_READ_INI_DOUBLE, CB_READ_INI_INT
        CB_IS_BREAKPOINT, CB_DISP_AND_LOCATE_ERROR, CB_ADD_OUTPUT_LOG_WITH_MSG_BOX
        CB_SET_STATUS_BAR_PROGRESS, CB_DRIVER_INITIALIZE, CB_DRIVER_G_FUNC, CB_DRIVER_M_FUNC
        CB_CONNECT_POINT_CALC_START, CB_CONNECT_POINT_CALC, CB_CONNECT_POINT_CALC_END
        CB_DRIVER_END, CB_MATH_WARNING

    ctypedef int32_t (*TC_AddOutputLog)(intptr_t, uint32_t, TGM_LPCTSTR, CALLBACK_INFO *) noexcept nogil
    ctypedef int32_t (*TC_SetStatusBarText)(intptr_t, uint32_t, TGM_LPCTSTR, CALLBACK_INFO *) noexcept nogil
    ctypedef int32_t (*TC_SetStatusBarProgress)(intptr_t, uint32_t) noexcept nogil
    ctypedef int32_t (*TC_DispAndLocateError)(intptr_t, uint32_t, int32_t, TGM_LPCTSTR, CALLBACK_INFO *) noexcept nogil
    ctypedef int32_t (*TC_IsBreakpoint)(intptr_t, uint32_t, int32_t) noexcept nogil
    ctypedef int32_t (*TC_DriverInitialize)(intptr_t, double *, uint32_t, int32_t) noexcept nogil
    ctypedef int32_t (*TC_DriverGFunc)(intptr_t, const SIMPLE_GM_PARAMS *) noexcept nogil
    ctypedef int32_t (*TC_DriverMFunc)(intptr_t, const SIMPLE_GM_PARAMS *) noexcept nogil
    ctypedef int32_t (*TC_DriverEnd)(intptr_t) noexcept nogil
    ctypedef int32_t (*TC_ConnectPointCalcStart)(intptr_t, uint32_t, uint32_t, const double *, uint32_t) noexcept nogil
    ctypedef int32_t (*TC_ConnectPointCalc)(intptr_t, const SIMPLE_GM_PARAMS *, double *, P10DOUBLE *) noexcept nogil
    ctypedef int32_t (*TC_ConnectPointCalcEnd)(intptr_t, SIMPLE_GM_PARAMS *, P10DOUBLE *) noexcept nogil
    ctypedef int32_t (*TC_MathWarning)(intptr_t, CALLBACK_INFO *) noexcept nogil

    enum cnc_status:
        CNC_STATUS_NOTHING_LOADED, CNC_STATUS_NOT_CONNECTED, CNC_STATUS_COMPILING
        CNC_STATUS_COMPILED, CNC_STATUS_SIMULATING, CNC_STATUS_SIMULATION_DONE
        CNC_STATUS_SIMULATION_STOPPED, CNC_STATUS_TESTING, CNC_STATUS_TEST_DONE
        CNC_STATUS_TEST_STOPPED, CNC_STATUS_AT_START, CNC_STATUS_STOPPED, CNC_STATUS_AT_END
        CNC_STATUS_STOPPED_BY_M0, CNC_STATUS_FORWARD, CNC_STATUS_FORWARD_NO_M, CNC_STATUS_BACKWARD
        CNC_STATUS_FORWARD_SKIP_FIRST_M, CNC_STATUS_CONNECT_CALCULATING, CNC_STATUS_CONNECT_MOVING
        CNC_STATUS_MANUAL_MOVE, CNC_STATUS_OUT_OF_TRAJECTORY, CNC_STATUS_INTERNAL_CALC
        CNC_STATUS_SENDING_START_M, CNC_STATUS_SENDING_STOP_M, CNC_STATUS_SENDING_CONNECT_M
        CNC_STATUS_INVALID
    enum run_regime:
        RUN_SIMULATION, RUN_TEST, RUN_FORWARD, RUN_FORWARD_NO_M, RUN_BACKWARD, RUN_FORWARD_SKIP_FIRST_M
    int RESET_MARK_START_ONLY

    # toolpath (extension): ToolChainCore_GetToolpath
    int TC_TOOLPATH_MOTION, TC_TOOLPATH_M_FUNCTION, TC_TOOLPATH_DWELL, TC_TOOLPATH_PRINT
    unsigned int TC_TOOLPATH_FEED_PER_MINUTE, TC_TOOLPATH_INSERTED, TC_TOOLPATH_CONTINUOUS_M
    unsigned int TC_TOOLPATH_HELIX
    ctypedef struct TC_TOOLPATH_RECORD:
        double start[3]
        double end[3]
        double tool_end[3]
        double centre[3]
        double radius
        double length
        double feed
        double value
        int32_t kind
        int32_t number
        uint32_t line
        int32_t file_index
        int32_t plane
        int32_t compensation
        uint32_t flags
        int32_t tool
        float spindle
        float feed_factor
