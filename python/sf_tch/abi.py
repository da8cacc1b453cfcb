"""ctypes mirror of ``include/tgm_cnc.h``: every structure by its C name, with the
same fields in the same order, plus the constants an HMI needs.

``abi_check`` and the tests compare every size and offset here with the C header
and with the library's ``ToolChainCore_GetStructuresSize``.

The header's TGM_LPCTSTR (file names, directories, callback texts, the texts the
library returns) is UTF-16 ``wchar_t`` on Windows and UTF-8 ``char`` on Linux: here
:data:`TSTR` (``c_wchar_p``, str, on Windows; ``c_char_p``, bytes, elsewhere), and
:func:`mirror` gives the structures and functions of either system.
"""
from __future__ import annotations

import ctypes
import sys
from ctypes import c_char_p, c_double, c_float, c_int32, c_int64, c_ssize_t, c_uint32, c_uint64, c_void_p, c_wchar_p

WINDOWS = sys.platform == "win32"


def text_type(windows: bool = WINDOWS):
    """The ctypes type of TGM_LPCTSTR on Windows (``c_wchar_p``) or Linux (``c_char_p``)."""
    return c_wchar_p if windows else c_char_p


TSTR = text_type()


def host_text(text: str):
    """A Python str as this system's TGM_LPCTSTR argument: itself on Windows, UTF-8 elsewhere."""
    return text if WINDOWS else text.encode()


def library_text(value: bytes | str | None) -> str:
    """A text the library returns as str: UTF-8 bytes, or already str (TGM_LPCTSTR on
    Windows); None as ''."""
    if isinstance(value, str):
        return value
    return (value or b"").decode(errors="replace")

# return codes
TOOL_CHAIN_BAD_INTR_INDEX = -2
TOOL_CHAIN_ERROR = -1
TOOL_CHAIN_SUCCESS = 0
TOOL_CHAIN_XEXEC = 1
TOOL_CHAIN_XBREAK = 2
TOOL_CHAIN_MAX_CORES = 3
TOOL_CHAIN_MAX_FILE_NAME = 252
INVALID_VALUE = 1.0000000694406173e38  # > 1e38 in float and in double (the header)
PLC_MEMORY_BYTES = 524288
GCODE_REZERVA1_ISO_COMPAT = 0x1   # GCODE_PARAMETERS.rezerva1: the ISO compatibility mode (docs/compiler.md)
GCODE_REZERVA1_COMP_STRICT = 0x2  # ... crossing equidistants refused (error 504; docs/compensation.md)
GCODE_REZERVA1_ISO_STRICT = 0x4   # ... with the ISO mode: what LinuxCNC refuses is error 414, not warning 621
GCODE_REZERVA1_APPLY_UNIMPLEMENTED = 0x10  # ... centripetalAcc and insertArcMinAngle applied (docs/behaviour.md)

AXES = ("x", "y", "z", "c", "b", "u", "v", "w", "a", "o")
LETTERS = tuple(chr(ord("A") + i) for i in range(26))


class P10DOUBLE(ctypes.Structure):
    _fields_ = [(name, c_double) for name in AXES]


class P10BOOL(ctypes.Structure):
    _fields_ = [(name, c_int32) for name in AXES]


class P26FLOAT(ctypes.Structure):
    _fields_ = [(name, c_float) for name in LETTERS]


def _dll_init_struct(tstr):
    return type("DLL_INIT_STRUCT", (ctypes.Structure,), {"_fields_": [
        ("CNC_Dll_Dir", tstr),
        ("Macros_Dir", tstr),
        ("Comm_Int2_Dir", tstr),
        ("Local_Core_Mode", c_int32),
    ], "__module__": __name__})


DLL_INIT_STRUCT = _dll_init_struct(TSTR)


class SIMPLE_GM_PARAMS(ctypes.Structure):
    _fields_ = [
        ("m_s", P10DOUBLE),
        ("m_e", P10DOUBLE),
        ("m_calcS", P10DOUBLE),
        ("m_calcE", P10DOUBLE),
        ("m_zero", P10DOUBLE),
        ("m_cc", P10DOUBLE),
        ("m_pars", P26FLOAT),
        ("m_func", c_int32),
        ("m_planeTool", c_int32),
        ("m_reserved", c_uint32),
        ("m_editorLine", c_uint32),
        ("m_fileIdx", c_int32),
        ("m_gCodeIndex", c_int32),
        ("m_bFeedIsMin", c_int32),
        ("m_fp", c_float),
    ]


class GM_PARAMS_ENHANCED(ctypes.Structure):
    _fields_ = [
        ("m_setFeed", c_double),
        ("m_calcFeed", c_double),
        ("m_actFeed", c_double),
        ("m_relFeed", c_double),
        ("m_actPartLen", c_double),
        ("m_actPartRemain", c_double),
        ("m_actWorkPartsLen", c_double),
        ("m_actG00PartsLen", c_double),
        ("m_actPartsLen", c_double),
        ("m_nWorkCounter", c_int32),
        ("m_nG00Counter", c_int32),
        ("m_nG00ToWorkChanges", c_int32),
        ("m_nWorkToG00Changes", c_int32),
        ("m_nMCounter", c_int32),
        ("m_MasterEditorLine", c_uint32),
        ("m_MasterFileIdx", c_uint32),
        ("m_statusCNC", c_int32),
        ("m_cncRunTime", c_double),
    ]


class CALLBACK_INFO(ctypes.Structure):
    _fields_ = [
        ("stringId", c_int32),
        ("nLines", c_int32),
        ("actLine", c_int32),
        ("fileIdx", c_int32),
        ("m_fullError", c_char_p),
        ("m_errorArguments", c_char_p),
    ]


class GCODE_SIZE(ctypes.Structure):
    _fields_ = [
        ("m_startPos", P10DOUBLE),
        ("m_endPos", P10DOUBLE),
        ("m_minimalPos", P10DOUBLE),
        ("m_maximalPos", P10DOUBLE),
    ]


class GCODE_INFO(ctypes.Structure):
    _fields_ = [("m_size", GCODE_SIZE * 4)]


class MACHINE_PARAMETERS(ctypes.Structure):
    _fields_ = [
        ("minCoords", P10DOUBLE),
        ("maxCoords", P10DOUBLE),
        ("refCoords", P10DOUBLE),
        ("enableMask", P10BOOL),
        ("backlash", P10DOUBLE),
        ("backlashInc", P10DOUBLE),
        ("backlashValuesSource", c_int32),
        ("enhancedInterpolatorParameters", c_int32),
    ]


class MACHINE_STATUS(ctypes.Structure):
    _fields_ = [("m_axesStatus", c_uint32), ("m_refDone", c_uint32), ("m_endSwitches", c_uint32)] + [
        (f"m_reserved{i}", c_uint32) for i in range(1, 11)
    ]


class GCODE_FEED(ctypes.Structure):
    _fields_ = [
        ("feed", c_double),
        ("acc", c_double),
        ("dec", c_double),
        ("rampType", c_int32),
        ("padding1", c_int32),
    ]


class GCODE_CORRECTION(ctypes.Structure):
    _fields_ = [("size", c_double), ("gCode", c_int32), ("padding1", c_int32)]


class ARC_FEED_TABLE(ctypes.Structure):
    _fields_ = [("m_r", c_double), ("m_relFeed", c_double)]


class INTERNAL_MFUNC_INSERT_TABLE(ctypes.Structure):
    _fields_ = [("mFunc", c_int32), ("padding1", c_int32), ("relFeed", c_double), ("distance", c_double)]


class AXIS_LIMITS(ctypes.Structure):
    _fields_ = [("maxFeed", c_double), ("maxAcc", c_double), ("maxDec", c_double)]


M_FUNCTION_FIELDS = (
    "M02_programEnd1", "M30_programEnd2", "M03_startSpindleCW", "M04_startSpindleCCW",
    "M05_stopSpindle", "M06_changeTool", "M07_coolOn", "M08_oilOn", "M09_coolOilOff",
    "M17_return", "M29_print", "M80_mirrorOff", "M81_mirrorX", "M82_mirrorY", "M83_mirrorZ",
    "M84_mirrorXY", "M85_mirrorXZ", "M86_mirrorYZ", "M87_mirrorXYZ", "M99_defFeed",
)


class GCODE_PARAMETERS(ctypes.Structure):
    _fields_ = [
        ("absMode", c_int32),
        ("swapG2G3", c_int32),
        ("correctionStrategy", c_uint32),
        ("forceMode", c_int32),
        ("motion", GCODE_FEED * 8),
        ("correction", GCODE_CORRECTION * 8),
        ("maxConnectionDistance", c_double),
        ("startAngle", c_double),
        ("endAngle", c_double),
        ("minAngleFeed", c_double),
        ("disableG0FeedOverride", c_int32),
        ("interpolatorConfig0", c_int32),
        ("overrideInc", c_double),
        ("arcFeedTable", ARC_FEED_TABLE * 5),
        ("centripetalAcc", c_double),
        ("mFuncInsertTable", INTERNAL_MFUNC_INSERT_TABLE * 3),
        ("MfuncInsertType", c_int32),
        ("paddingTo8Bytes_2", c_int32),
        ("reserved", c_double),
    ] + [(name, c_int32) for name in M_FUNCTION_FIELDS] + [
        ("insertArcMode", c_int32),
        ("paddingTo8Bytes_3", c_int32),
        ("insertArcToleranceRMax", c_double),
        ("insertArcToleranceRMin", c_double),
        ("insertArcMaxAngle", c_double),
        ("insertArcMinAngle", c_double),
        ("insertArcPlane", c_int32),
        ("rezerva1", c_int32),
        ("calcTime", c_int32),
        ("rezerva2", c_int32),
        ("dynamicG41Correction_mm", c_double),
        ("dynamicG42Correction_mm", c_double),
        ("axisLimits", AXIS_LIMITS * 10),
        ("dynamicG41Correction_percent", c_double),
        ("dynamicG42Correction_percent", c_double),
        ("tolerance", c_double * 10),
    ]


# Toolpath (extension beyond the vendor's list): ToolChainCore_GetToolpath fills an
# array of these; include/tgm_cnc.h documents every field and its unit.
TC_TOOLPATH_MOTION = 1
TC_TOOLPATH_M_FUNCTION = 2
TC_TOOLPATH_DWELL = 3
TC_TOOLPATH_PRINT = 4
TC_TOOLPATH_FEED_PER_MINUTE = 0x01
TC_TOOLPATH_INSERTED = 0x02
TC_TOOLPATH_CONTINUOUS_M = 0x04
TC_TOOLPATH_HELIX = 0x08


class TC_TOOLPATH_RECORD(ctypes.Structure):
    _fields_ = [
        ("start", c_double * 3),
        ("end", c_double * 3),
        ("tool_end", c_double * 3),
        ("centre", c_double * 3),
        ("radius", c_double),
        ("length", c_double),
        ("feed", c_double),
        ("value", c_double),
        ("kind", c_int32),
        ("number", c_int32),
        ("line", c_uint32),
        ("file_index", c_int32),
        ("plane", c_int32),
        ("compensation", c_int32),
        ("flags", c_uint32),
        ("tool", c_int32),
        ("spindle", c_float),
        ("feed_factor", c_float),
    ]


# Correction tables and smoothing (extension): include/tgm_cnc.h documents each.
TC_TOOL_ENTRIES = 99
TC_TOOL_RADIUS = 0
TC_TOOL_VALUES = 5
TC_SMOOTHING_IIR = -1
TC_SMOOTHING_SPLINE = -2


def _structures(dll_init_struct) -> dict:
    return {
        cls.__name__: cls
        for cls in (
            P10DOUBLE, P10BOOL, P26FLOAT, dll_init_struct, SIMPLE_GM_PARAMS, GM_PARAMS_ENHANCED,
            CALLBACK_INFO, GCODE_SIZE, GCODE_INFO, MACHINE_PARAMETERS, MACHINE_STATUS, GCODE_FEED,
            GCODE_CORRECTION, ARC_FEED_TABLE, INTERNAL_MFUNC_INSERT_TABLE, AXIS_LIMITS, GCODE_PARAMETERS,
            TC_TOOLPATH_RECORD,
        )
    }


# Every structure of the header, by name (abi_check walks this).
STRUCTURES = _structures(DLL_INIT_STRUCT)

# Order of ToolChainCore_GetStructuresSize entries [1..8].
STRUCTURES_SIZE_ORDER = (
    "GCODE_PARAMETERS", "SIMPLE_GM_PARAMS", "GM_PARAMS_ENHANCED", "CALLBACK_INFO", "GCODE_INFO",
    "MACHINE_STATUS", "MACHINE_PARAMETERS", "DLL_INIT_STRUCT",
)

# cnc_status: generated by tools/gen_catalogue.py from include/tgm_cnc.h, do not edit (to its end)
STATUS_NOTHING_LOADED = 0  # nothing loaded
STATUS_NOT_CONNECTED = -2  # remote device not connected
STATUS_COMPILING = 1  # compiling
STATUS_COMPILED = -1  # compilation finished
STATUS_SIMULATING = 10  # simulating
STATUS_SIMULATION_DONE = -10  # simulation finished
STATUS_SIMULATION_STOPPED = -11  # simulation stopped
STATUS_TESTING = 20  # test running
STATUS_TEST_DONE = -20  # test finished
STATUS_TEST_STOPPED = -21  # test stopped
STATUS_AT_START = -30  # at the start of the trajectory
STATUS_STOPPED = -31  # stopped on the trajectory
STATUS_AT_END = -32  # end of the trajectory
STATUS_STOPPED_BY_M0 = -33  # stopped by M0
STATUS_FORWARD = 30  # running forward
STATUS_FORWARD_NO_M = 31  # running forward without M functions
STATUS_BACKWARD = 32  # running backward
STATUS_FORWARD_SKIP_FIRST_M = 33  # running forward skipping the first M functions
STATUS_CONNECT_CALCULATING = 40  # calculating the connection
STATUS_CONNECT_MOVING = 41  # moving to the connection point
STATUS_MANUAL_MOVE = 50  # manual move
STATUS_OUT_OF_TRAJECTORY = -50  # out of the trajectory
STATUS_INTERNAL_CALC = 60  # internal calculation
STATUS_SENDING_START_M = 70  # sending start M functions
STATUS_SENDING_STOP_M = 80  # sending stop M functions
STATUS_SENDING_CONNECT_M = 90  # sending connect M functions
STATUS_INVALID = -1234  # invalid
# end of cnc_status

# run regimes of StartCNCEx
RUN_SIMULATION = 10
RUN_TEST = 20

# callback numbers and prototypes (userData first)
CB_ADD_OUTPUT_LOG = 1
CB_SET_STATUS_BAR_TEXT = 2
CB_IS_DEBUG_MODE = 3
CB_IS_VERBOSE_MODE = 4
CB_GET_LIB_PATH = 5
CB_GET_TOOL_PATH = 6
CB_GET_SYSTEM_PATH = 7
CB_GET_FILE_TIME_STAMP = 10
CB_DO_YIELD = 11
CB_READ_INI_STRING = 12
CB_READ_INI_DOUBLE = 13
CB_READ_INI_INT = 14
CB_IS_BREAKPOINT = 17
CB_DISP_AND_LOCATE_ERROR = 18
CB_ADD_OUTPUT_LOG_WITH_MSG_BOX = 31
CB_SET_STATUS_BAR_PROGRESS = 32
CB_DRIVER_INITIALIZE = 1001
CB_DRIVER_G_FUNC = 1002
CB_DRIVER_M_FUNC = 1003
CB_CONNECT_POINT_CALC_START = 1004
CB_CONNECT_POINT_CALC = 1005
CB_CONNECT_POINT_CALC_END = 1006
CB_DRIVER_END = 1007
CB_MATH_WARNING = 2001
CALLBACK_NUMBERS = (1, 2, 3, 4, 5, 6, 7, 10, 11, 12, 13, 14, 17, 18, 31, 32,
                    1001, 1002, 1003, 1004, 1005, 1006, 1007, 2001)

AddOutputLog = ctypes.CFUNCTYPE(c_int32, c_ssize_t, c_uint32, TSTR, ctypes.POINTER(CALLBACK_INFO))
SetStatusBarText = ctypes.CFUNCTYPE(c_int32, c_ssize_t, c_uint32, TSTR, ctypes.POINTER(CALLBACK_INFO))
SetStatusBarProgress = ctypes.CFUNCTYPE(c_int32, c_ssize_t, c_uint32)
DispAndLocateError = ctypes.CFUNCTYPE(c_int32, c_ssize_t, c_uint32, c_int32, TSTR, ctypes.POINTER(CALLBACK_INFO))
DriverInitialize = ctypes.CFUNCTYPE(c_int32, c_ssize_t, ctypes.POINTER(c_double), c_uint32, c_int32)
DriverGFunc = ctypes.CFUNCTYPE(c_int32, c_ssize_t, ctypes.POINTER(SIMPLE_GM_PARAMS))
DriverMFunc = ctypes.CFUNCTYPE(c_int32, c_ssize_t, ctypes.POINTER(SIMPLE_GM_PARAMS))
DriverEnd = ctypes.CFUNCTYPE(c_int32, c_ssize_t)
ConnectPointCalcStart = ctypes.CFUNCTYPE(c_int32, c_ssize_t, c_uint32, c_uint32, ctypes.POINTER(c_double), c_uint32)
ConnectPointCalc = ctypes.CFUNCTYPE(c_int32, c_ssize_t, ctypes.POINTER(SIMPLE_GM_PARAMS), ctypes.POINTER(c_double),
                                    ctypes.POINTER(P10DOUBLE))
ConnectPointCalcEnd = ctypes.CFUNCTYPE(c_int32, c_ssize_t, ctypes.POINTER(SIMPLE_GM_PARAMS), ctypes.POINTER(P10DOUBLE))
MathWarning = ctypes.CFUNCTYPE(c_int32, c_ssize_t, ctypes.POINTER(CALLBACK_INFO))
# ToolChain_SetLogHook's function (extension): (userData, LOG_* source, text).
LogHook = ctypes.CFUNCTYPE(None, c_ssize_t, c_uint32, c_char_p)

_P = ctypes.POINTER


def _functions(tstr, dll_init_struct) -> tuple:
    """Every exported function: (name, restype, argtypes), tstr the type of TGM_LPCTSTR."""
    return (
        ("ToolChainCore_Init", c_int32, (_P(dll_init_struct),)),
        ("ToolChainCore_LoadFromIni", c_int32, (c_uint32, tstr, _P(c_uint32))),
        ("ToolChainCore_DestroyCNC", c_int32, (c_uint32,)),
        ("ToolChainCore_GetVersionString", tstr, (c_uint32,)),
        ("ToolChainCore_GetStructuresSize", c_int32, (c_uint32, c_uint32, _P(c_uint32))),
        ("ToolChainCore_SetGCodeParameters", c_int32, (c_uint32, _P(GCODE_PARAMETERS))),
        ("ToolChainCore_GetGCodeParameters", c_int32, (c_uint32, _P(GCODE_PARAMETERS))),
        ("ToolChainCore_GetMachineParameters", c_int32, (c_uint32, _P(MACHINE_PARAMETERS))),
        ("ToolChainCore_SetMachineParameters", c_int32, (c_uint32, _P(MACHINE_PARAMETERS))),
        ("ToolChainCore_SetUserParams", c_int32, (c_uint32, _P(c_double), c_uint32)),
        ("ToolChainCore_GCodePrefixPostfix", c_int32, (c_uint32, c_char_p, c_char_p)),
        ("ToolChainCore_CompileFromFile", c_int32, (c_uint32, tstr)),
        ("ToolChainCore_CompileFromMemory", c_int32, (c_uint32, tstr, c_char_p)),
        ("ToolChainCore_IsBusy", c_int32, (c_uint32,)),
        ("ToolChainCore_GetLastError", c_int32, (c_uint32, _P(CALLBACK_INFO))),
        ("ToolChainCore_GetLastCallError", c_int32, (c_uint32, _P(CALLBACK_INFO))),
        ("ToolChainCore_GetLastErrorColumn", c_int32, (c_uint32, c_int32, _P(c_int32))),
        ("ToolChainCore_FileToIdx", c_int32, (c_uint32, tstr)),
        ("ToolChainCore_IdxToFile", tstr, (c_uint32, c_int32)),
        ("ToolChainCore_GetGCodeSizeInfo", c_int32, (c_uint32, _P(GCODE_INFO))),
        ("ToolChainCore_GetGCodeRunTime", c_double, (c_uint32, c_int32)),
        ("ToolChainCore_SetGCodeRunTime", c_int32, (c_uint32, c_int32, c_double)),
        ("ToolChain_GetLastError", c_int32, (_P(CALLBACK_INFO),)),
        ("ToolChain_IdxToFile", tstr, (c_int32,)),
        ("ToolChainCore_ResetCNC", c_int32, (c_uint32, c_int32, c_uint32, _P(c_double))),
        ("ToolChainCore_StartCNCEx", c_int32, (c_uint32, c_int32, c_char_p)),
        ("ToolChainCore_StopCNCEx", c_int32, (c_uint32, c_char_p)),
        ("ToolChainCore_ConnectCNCEx_Plane", c_int32,
         (c_uint32, c_uint32, c_uint32, _P(c_double), c_char_p, c_uint32, c_uint32, c_int32)),
        ("ToolChainCore_GoToPosition", c_int32, (c_uint32, c_uint32, _P(c_double))),
        ("ToolChainCore_GoToPositionEx", c_int32, (c_uint32, _P(SIMPLE_GM_PARAMS))),
        ("ToolChainCore_MFunc", c_int32, (c_uint32, _P(SIMPLE_GM_PARAMS), c_int32)),
        ("ToolChainCore_SetRelFeed", c_int32, (c_uint32, c_double)),
        ("ToolChainCore_SetBreakpoint", c_int32, (c_uint32, c_uint32, c_int32)),
        ("ToolChainCore_ResetStatusCNC", c_int32, (c_uint32, c_uint32)),
        ("ToolChainCore_StatusCNC", c_int32, (c_uint32,)),
        ("ToolChainCore_GetPos", c_int32, (c_uint32, c_int32, _P(SIMPLE_GM_PARAMS), _P(GM_PARAMS_ENHANCED))),
        ("ToolChainCore_LoadCNCCalcPlugIn", c_int32, (tstr, c_uint32, c_int64)),
        ("ToolChainCore_SetCallBack", c_int32, (c_uint32, c_uint32, c_ssize_t, c_void_p)),
        ("ToolChainCore_SetLogValue", c_int32, (c_uint32,)),
        ("ToolChainCore_GetLogValue", c_uint32, ()),
        ("ToolChain_LogANSI", None, (c_char_p,)),
        ("ToolChain_FlushLogFile", None, ()),
        ("ToolChainCore_GetToolpath", c_int32,
         (c_uint32, _P(TC_TOOLPATH_RECORD), c_uint64, c_uint64, _P(c_uint64))),
        ("ToolChainCore_SetLookAhead", c_int32, (c_uint32, c_int32)),
        ("ToolChain_SetLogHook", c_int32, (c_ssize_t, c_void_p)),
        ("ToolChainCore_SetTimeScale", c_int32, (c_uint32, c_double)),
        ("ToolChainCore_ConfirmMFunc", c_int32, (c_uint32,)),
        ("ToolChainCore_LoadToolTable", c_int32, (c_uint32, tstr)),
        ("ToolChainCore_GetToolCorrection", c_int32, (c_uint32, c_uint32, _P(c_double))),
        ("ToolChainCore_SetToolCorrection", c_int32, (c_uint32, c_uint32, c_uint32, _P(c_double))),
        ("ToolChainCore_LoadAxisCorrections", c_int32, (c_uint32, c_uint32, _P(tstr))),
        ("ToolChainCore_CorrectPosition", c_int32, (c_uint32, _P(c_double), _P(c_double))),
        ("ToolChainCore_SetSmoothing", c_int32, (c_uint32, c_int32, _P(c_double))),
        ("ToolChainCore_GetSmoothing", c_int32, (c_uint32, c_int32, _P(c_double))),
        ("ToolChainCore_SmoothSamples", c_int32, (c_uint32, _P(c_double), c_uint64, _P(c_double), _P(c_uint64))),
        ("ToolChainCore_TestClock", c_int32, (c_uint32, c_uint64, c_double)),
        ("ToolChain_TestAllocFail", c_int64, (c_uint64, c_int64)),
    )


FUNCTIONS = _functions(TSTR, DLL_INIT_STRUCT)


def mirror(windows: bool, pointer_bits: int = 64) -> tuple[dict, tuple]:
    """(STRUCTURES, FUNCTIONS) of Windows x64 or of Linux, whichever system this is.

    `pointer_bits` 32: the layouts of the 32-bit builds (Windows x86, Linux i686), for
    abi_check; FUNCTIONS is empty then (this process cannot call a 32-bit library).
    Every pointer field becomes a 4-byte stand-in of the same C name (``char*``,
    ``wchar_t*``), and on Linux i686 a double inside a structure is 4-aligned (the
    i386 System V ABI; Windows x86 aligns it to 8, as x64 does)."""
    if pointer_bits == 32:
        structures, _ = mirror(windows)
        return _layouts_32(structures, windows), ()
    if pointer_bits != 64:
        raise ValueError(f"pointer_bits is 32 or 64, not {pointer_bits}")
    if windows == WINDOWS:
        return STRUCTURES, FUNCTIONS
    dll_init_struct = _dll_init_struct(text_type(windows))
    return _structures(dll_init_struct), _functions(text_type(windows), dll_init_struct)


def _pointer_32(c_name: str):
    """A 4-byte stand-in for a pointer field of a 32-bit layout (abi_check reads
    `_c_name_` as its C type)."""
    return type(f"pointer32_{c_name.rstrip('*')}", (ctypes.c_uint32,), {"_c_name_": c_name, "__module__": __name__})


_POINTERS_32 = {c_char_p: _pointer_32("char*"), c_wchar_p: _pointer_32("wchar_t*"), c_void_p: _pointer_32("void*")}


def _layouts_32(structures: dict, windows: bool) -> dict:
    made: dict = {}

    def remade(t):
        if t in _POINTERS_32:
            return _POINTERS_32[t]
        if isinstance(t, type) and issubclass(t, ctypes.Array):
            return remade(t._type_) * t._length_
        if isinstance(t, type) and issubclass(t, ctypes.Structure):
            if t.__name__ not in made:
                attrs = {"_fields_": [(name, remade(ft)) for name, ft in t._fields_], "__module__": __name__}
                if not windows:
                    attrs["_pack_"] = 4          # i386: double and int64 4-aligned inside structures
                made[t.__name__] = type(t.__name__, (ctypes.Structure,), attrs)
            return made[t.__name__]
        return t

    return {name: remade(cls) for name, cls in structures.items()}


# Beyond the vendor's list (docs/api.md, "Extensions"): the structures and functions this library adds.
EXTENSION_STRUCTURES = ("TC_TOOLPATH_RECORD",)
EXTENSION_FUNCTIONS = ("ToolChainCore_GetLastCallError", "ToolChainCore_GetLastErrorColumn", "ToolChainCore_GetToolpath", "ToolChainCore_SetLookAhead",
                       "ToolChain_SetLogHook", "ToolChainCore_SetTimeScale", "ToolChainCore_ConfirmMFunc",
                       "ToolChainCore_LoadToolTable", "ToolChainCore_GetToolCorrection",
                       "ToolChainCore_SetToolCorrection", "ToolChainCore_LoadAxisCorrections",
                       "ToolChainCore_CorrectPosition", "ToolChainCore_SetSmoothing", "ToolChainCore_GetSmoothing",
                       "ToolChainCore_SmoothSamples", "ToolChainCore_TestClock",
                       "ToolChain_TestAllocFail")
# DriverMFunc's answer "the host confirms later" (ToolChainCore_ConfirmMFunc)
TC_MFUNC_LATER = 2
# ToolChainCore_TestClock's key: the test-only stepped clock of the offline machine
TC_TEST_CLOCK_KEY = 0x4B434F4C43545354
# ToolChain_TestAllocFail's key: the test-only allocation failure (docs/testing.md)
TC_TEST_ALLOC_KEY = 0x434F4C4C41545354


# Readable repr() and to_dict() of every structure (added to the classes above,
# whose definitions stay the header's).
def _value(value):
    if isinstance(value, ctypes.Structure):
        return _to_dict(value)
    if isinstance(value, ctypes.Array):
        return [_value(v) for v in value]
    if isinstance(value, bytes):
        return value.decode(errors="replace")
    return value


def _to_dict(self) -> dict:
    """Every field by name, nested structures and arrays as dicts and lists."""
    return {name: _value(getattr(self, name)) for name, *_ in self._fields_}


def _repr(self) -> str:
    fields = ", ".join(f"{name}={_value(getattr(self, name))!r}" for name, *_ in self._fields_
                       if not name.startswith(("padding", "rezerva", "m_reserved", "reserved")))
    return f"{type(self).__name__}({fields})"


for _cls in STRUCTURES.values():
    setattr(_cls, "to_dict", _to_dict)
    setattr(_cls, "__repr__", _repr)
del _cls
