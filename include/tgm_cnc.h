/*
 * tgm_cnc.h -- the C ABI of the SF_TCh CNC module library (libSF_TCh.so on Linux,
 * SF_TCh.dll on Windows x64).
 *
 * This header is the single source of truth for the library's binary interface:
 * the Cython sources declare their structures from it, the C compiler checks every
 * exported definition against the prototypes below, and abi_check compares the
 * Python ctypes mirror (sf_tch.abi) with it field by field.
 *
 * Layouts follow the vendor's data-structure description (natural C alignment, no
 * packing pragma), the same on Linux and Windows x64; the sizes are asserted at the end
 * of this file.
 *
 * Threading (docs/threading.md): every function may be called from any thread at
 * any moment, also from inside a callback the library is running. Long work
 * (compilation, simulation, motion) runs in one worker thread per core; the calls
 * that start it return at once. Callbacks are called from the worker (and the
 * error callbacks of a refused call from the caller's thread). StatusCNC and GetPos
 * never wait for a lock. A call that ends the core's activity (DestroyCNC, ResetCNC,
 * ResetStatusCNC) returns once the worker has been joined; made inside a callback of
 * a running activity it returns at once and the worker applies it when the callback
 * has returned. A call that starts an activity (Compile*, StartCNCEx) is refused
 * inside a callback of that core's running activity (-1, error 20).
 *
 * Valid C99 and C++.
 */
#ifndef TGM_CNC_H
#define TGM_CNC_H

#include <stdint.h>
#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* On Windows a panel that includes this header imports the functions
 * (__declspec(dllimport), for linking SF_TCh.lib); the library's own build defines
 * SF_TCH_BUILDING_DLL and exports them. */
#if defined(_WIN32)
#  define TOOLCHAIN_CALLTYPE __cdecl
#  if defined(SF_TCH_BUILDING_DLL)
#    define TOOLCHAIN_API __declspec(dllexport)
#  else
#    define TOOLCHAIN_API __declspec(dllimport)
#  endif
#else
#  define TOOLCHAIN_CALLTYPE
#  define TOOLCHAIN_API __attribute__((visibility("default")))
#endif

/* File names, directories, the texts of the callbacks and the texts the library returns:
 * UTF-16 (wchar_t) on Windows, UTF-8 (char) on Linux. */
#if defined(_WIN32)
typedef const wchar_t *TGM_LPCTSTR;
typedef wchar_t *TGM_LPTSTR;
#else
typedef const char *TGM_LPCTSTR;
typedef char *TGM_LPTSTR;
#endif
/* G-code text, add codes, log lines and CALLBACK_INFO's error texts: narrow. UTF-8 on
 * Linux; on Windows the process's ANSI code page (CP_ACP, the vendor's "ANSI"; a
 * character it cannot hold arrives as '?'), or UTF-8 after an INI file's [Texts]
 * Narrow=utf8 (docs/hosts.md). */
typedef const char *TGM_LPCSTR;

/* ------------------------------------------------------------------ constants */

/* Return codes. */
#define TOOL_CHAIN_BAD_INTR_INDEX (-2) /* intIdx is not a core of this library */
#define TOOL_CHAIN_ERROR          (-1) /* bad argument, NULL pointer, wrong status */
#define TOOL_CHAIN_SUCCESS          0
#define TOOL_CHAIN_XEXEC            1  /* runtime failure (e.g. LoadFromIni) */
#define TOOL_CHAIN_XBREAK           2

/* Number of CNC cores (independent interpolator channels) of this build. */
#define TOOL_CHAIN_MAX_CORES 3

/* "Address not present" marker of P10DOUBLE / P26FLOAT cells: the smallest float above
 * 1e38 (1e38f itself is 9.99999968e37), the same number as a double, so that a host tests
 * a cell with "> 1e38" as the vendor documents, in float or in double. */
#define INVALID_VALUE   1.0000000694406173e38
#define INVALID_VALUE_F 1.00000007e38f

/* Special file indexes of FileToIdx / IdxToFile. */
#define TOOL_CHAIN_FILE_UNKNOWN (-1) /* "__unknown__" */
#define TOOL_CHAIN_FILE_END     (-2) /* "__end__"     */
#define TOOL_CHAIN_FILE_STOP    (-3) /* "__stop__"    */
#define TOOL_CHAIN_FILE_EXEC    (-4) /* "__exec__"    */
/* File names of this many bytes or more (of UTF-8; on Windows after the conversion from
 * UTF-16) are refused. */
#define TOOL_CHAIN_MAX_FILE_NAME 252

/* Status of a core (ToolChainCore_StatusCNC, GM_PARAMS_ENHANCED.m_statusCNC); positive:
 * something runs. The comment of each value is its name in error texts. */
enum cnc_status {
    CNC_STATUS_NOTHING_LOADED      = 0,   /* nothing loaded */
    CNC_STATUS_NOT_CONNECTED       = -2,  /* remote device not connected */
    CNC_STATUS_COMPILING           = 1,   /* compiling */
    CNC_STATUS_COMPILED            = -1,  /* compilation finished */
    CNC_STATUS_SIMULATING          = 10,  /* simulating */
    CNC_STATUS_SIMULATION_DONE     = -10, /* simulation finished */
    CNC_STATUS_SIMULATION_STOPPED  = -11, /* simulation stopped */
    CNC_STATUS_TESTING             = 20,  /* test running */
    CNC_STATUS_TEST_DONE           = -20, /* test finished */
    CNC_STATUS_TEST_STOPPED        = -21, /* test stopped */
    CNC_STATUS_AT_START            = -30, /* at the start of the trajectory */
    CNC_STATUS_STOPPED             = -31, /* stopped on the trajectory */
    CNC_STATUS_AT_END              = -32, /* end of the trajectory */
    CNC_STATUS_STOPPED_BY_M0       = -33, /* stopped by M0 */
    CNC_STATUS_FORWARD             = 30,  /* running forward */
    CNC_STATUS_FORWARD_NO_M        = 31,  /* running forward without M functions */
    CNC_STATUS_BACKWARD            = 32,  /* running backward */
    CNC_STATUS_FORWARD_SKIP_FIRST_M = 33, /* running forward skipping the first M functions */
    CNC_STATUS_CONNECT_CALCULATING = 40,  /* calculating the connection */
    CNC_STATUS_CONNECT_MOVING      = 41,  /* moving to the connection point */
    CNC_STATUS_MANUAL_MOVE         = 50,  /* manual move */
    CNC_STATUS_OUT_OF_TRAJECTORY   = -50, /* out of the trajectory */
    CNC_STATUS_INTERNAL_CALC       = 60,  /* internal calculation */
    CNC_STATUS_SENDING_START_M     = 70,  /* sending start M functions */
    CNC_STATUS_SENDING_STOP_M      = 80,  /* sending stop M functions */
    CNC_STATUS_SENDING_CONNECT_M   = 90,  /* sending connect M functions */
    CNC_STATUS_INVALID             = -1234 /* invalid */
};

/* Regimes of ToolChainCore_StartCNCEx. */
enum run_regime {
    RUN_SIMULATION        = 10,
    RUN_TEST              = 20,
    RUN_FORWARD           = 30,
    RUN_FORWARD_NO_M      = 31,
    RUN_BACKWARD          = 32,
    RUN_FORWARD_SKIP_FIRST_M = 33
};

/* Regime of ToolChainCore_ResetCNC: only mark the program start. */
#define RESET_MARK_START_ONLY 1

/* nType of ToolChainCore_ConnectCNCEx_Plane. */
enum connect_type {
    CONNECT_NEAREST_AND_STOP       = 0,
    CONNECT_LINE_START             = 1,
    CONNECT_LINE_END               = 2,
    CONNECT_NEAREST_CONTINUE       = 10,
    CONNECT_LINE_START_CONTINUE    = 11,
    CONNECT_LINE_END_CONTINUE      = 12,
    CONNECT_MFUNC_ABSOLUTE         = 20,
    CONNECT_MFUNC_RELATIVE         = 21,
    CONNECT_INDEX_START            = 30,
    CONNECT_INDEX_NEAREST          = 31,
    CONNECT_INDEX_END              = 32,
    CONNECT_NEAREST_NO_PAUSE       = 40,
    CONNECT_LINE_START_NO_PAUSE    = 41,
    CONNECT_LINE_END_NO_PAUSE      = 42,
    CONNECT_INDEX_NEAREST_NO_PAUSE = 44,
    CONNECT_EXACT_POINT            = 46
};

/* Axis bits (axesForCalc / axesForConnect), in P10DOUBLE order. */
#define AXIS_BIT_X 0x001
#define AXIS_BIT_Y 0x002
#define AXIS_BIT_Z 0x004
#define AXIS_BIT_C 0x008
#define AXIS_BIT_B 0x010
#define AXIS_BIT_U 0x020
#define AXIS_BIT_V 0x040
#define AXIS_BIT_W 0x080
#define AXIS_BIT_A 0x100
#define AXIS_BIT_O 0x200
#define AXIS_BITS_ALL 0x3FF

/* Log mask of ToolChainCore_SetLogValue: sources ... */
#define LOG_DEBUG      0x00000001u
#define LOG_VERBOSE    0x00000002u
#define LOG_WORKER     0x00000004u
#define LOG_TOOLCHAIN  0x00000008u
#define LOG_DRIVER     0x00000010u
#define LOG_COMPILER   0x00000020u
#define LOG_EXECUTOR   0x00000040u
#define LOG_MATH       0x00000080u
/* ... and outputs. */
#define LOG_TO_CONSOLE 0x10000000u /* debug view / console (stderr) */
#define LOG_TO_FILE    0x20000000u /* file SF_TCh.log in the log directory */
#define LOG_TO_TGM     0x40000000u /* TG Motion console (offline: stderr) */

/* GCODE_PARAMETERS.correctionStrategy bits. */
#define CORR_START_MODE_MASK        0x000000FFu /* 0: already compensated; 1: compensate from next move */
#define CORR_SEARCH_DEPTH_MASK      0x00000700u /* 0x100 10 ... 0x600 2000, 0x700 whole buffer */
#define CORR_ALLOW_FIRST_LAST_CROSS 0x00010000u
#define CORR_JOIN_BY_G1             0x00020000u
#define CORR_JOIN_BY_MOVING_START   0x00040000u
#define CORR_REMOVE_CROSSING        0x00080000u
#define CORR_ALLOW_REVERSE_SEARCH   0x00100000u
#define CORR_DROP_NEGATIVE_ARCS     0x00200000u
#define CORR_CORNER_FACTOR_2        0x00400000u
#define CORR_CORNER_INTERSECTION    0x00800000u
#define CORR_G0_NEVER_COMPENSATED   0x40000000u
#define CORR_OLD_COMPATIBILITY      0x80000000u

/* GCODE_PARAMETERS.rezerva1 bits (beyond the vendor's list; 0 = the vendor's behaviour).
   ISO_COMPAT: the compiler reads ISO/LinuxCNC constructs of CAM programs (G20/G21 units,
   G4 P seconds, G18 as ZX, G43 H / G49 tool lengths from the tool table, G64/G61 ignored,
   P words of M functions ignored, O program numbers), with a warning where it ignores
   something. */
#define GCODE_REZERVA1_ISO_COMPAT 0x00000001u
/* COMP_STRICT: tool radius compensation refuses (error 504) a tool path that crosses
   itself or cuts into the contour where it cannot remove that part (strategy 0x80000);
   0, the vendor's behaviour: warning 601 with the line and the depth, and the program
   compiles (docs/compensation.md, "Crossing equidistants: warning, removal, refusal"). */
#define GCODE_REZERVA1_COMP_STRICT 0x00000002u
/* ISO_STRICT: with ISO_COMPAT, what LinuxCNC refuses and the ISO mode reads on with a
   warning (621: unknown M codes, K on an XY-plane arc, a nested comment, ...) is an
   error (414) instead (docs/compiler.md, "ISO compatibility mode"). */
#define GCODE_REZERVA1_ISO_STRICT 0x00000004u
/* APPLY_UNIMPLEMENTED: apply centripetalAcc (arcs slowed to keep v^2/r under it) and
   insertArcMinAngle (no tangent arc below it), which the vendor documents as "not
   implemented yet" and "not implemented, always 0"; 0, the vendor's behaviour: both are
   kept in the structure and ignored (docs/behaviour.md). */
#define GCODE_REZERVA1_APPLY_UNIMPLEMENTED 0x00000010u

/* AddOutputLog tabs and flags. */
#define OUTPUT_TAB_ERRORS 0
#define OUTPUT_TAB_CNC    1
#define OUTPUT_TAB_PRINT  2
#define OUTPUT_TAB_STATUS 3
#define OUTPUT_FLAG_ACTIVATE    0x100
#define OUTPUT_FLAG_PREFIX_TIME 0x200
#define OUTPUT_FLAG_HIDE_VIEW   0x400

/* ------------------------------------------------------------------ structures */

/* Ten axis values in the fixed axis order x y z c b u v w a o. */
typedef struct P10DOUBLE {
    double x, y, z, c, b, u, v, w, a, o;
} P10DOUBLE;

/* Ten int32 flags in the same axis order. */
typedef struct P10BOOL {
    int32_t x, y, z, c, b, u, v, w, a, o;
} P10BOOL;

/* All 26 address letters of a G-code line; a letter not present holds > 1e38. */
typedef struct P26FLOAT {
    float A, B, C, D, E, F, G, H, I, J, K, L, M,
          N, O, P, Q, R, S, T, U, V, W, X, Y, Z;
} P26FLOAT;

/* Argument of ToolChainCore_Init. */
typedef struct DLL_INIT_STRUCT {
    TGM_LPCTSTR CNC_Dll_Dir;     /* directory of the CNC libraries */
    TGM_LPCTSTR Macros_Dir;      /* directory of macros (external G functions as G-code) */
    TGM_LPCTSTR Comm_Int2_Dir;   /* directory of the communication libraries */
    int32_t     Local_Core_Mode; /* 0 TG Motion, 1 calculations in the library, 2 offline (demo) */
} DLL_INIT_STRUCT;

/* One G-code part (a G or an M function). */
typedef struct SIMPLE_GM_PARAMS {
    P10DOUBLE m_s;        /* start position as programmed */
    P10DOUBLE m_e;        /* end position as programmed */
    P10DOUBLE m_calcS;    /* compensated start (GetPos: current position) */
    P10DOUBLE m_calcE;    /* compensated end */
    P10DOUBLE m_zero;     /* active zero offset */
    P10DOUBLE m_cc;       /* arc centre x y z, radius in c (GoToPositionEx: feed in a) */
    P26FLOAT  m_pars;     /* the line's addresses, > 1e38 = absent */
    int32_t   m_func;     /* G number; in GetPos an M function is + 10000 */
    int32_t   m_planeTool;   /* low 16 bits plane 17/18/19/-18, high 16 bits tool */
    uint32_t  m_reserved;
    uint32_t  m_editorLine;  /* 1-based line in the file */
    int32_t   m_fileIdx;     /* file index (FileToIdx), -1 unknown */
    int32_t   m_gCodeIndex;  /* unique increasing index; odd for inserted parts */
    int32_t   m_bFeedIsMin;  /* low 16 bits mm/min (1) or mm/rev (0); high 16 bits 40/41/42 */
    float     m_fp;          /* FP relative feed, usually 1.0 */
} SIMPLE_GM_PARAMS;

/* Extended position information of ToolChainCore_GetPos. */
typedef struct GM_PARAMS_ENHANCED {
    double   m_setFeed;          /* programmed feed, mm/min */
    double   m_calcFeed;         /* planned feed, mm/min */
    double   m_actFeed;          /* current feed */
    double   m_relFeed;          /* current override, 1 = 100 % */
    double   m_actPartLen;       /* length of the current part */
    double   m_actPartRemain;    /* remaining length of the current part */
    double   m_actWorkPartsLen;  /* cutting (G1/G2/G3) length so far */
    double   m_actG00PartsLen;   /* rapid (G0) length so far */
    double   m_actPartsLen;      /* all motion so far */
    int32_t  m_nWorkCounter;
    int32_t  m_nG00Counter;
    int32_t  m_nG00ToWorkChanges;
    int32_t  m_nWorkToG00Changes;
    int32_t  m_nMCounter;
    uint32_t m_MasterEditorLine; /* current line in the main file */
    uint32_t m_MasterFileIdx;    /* main file index */
    int32_t  m_statusCNC;        /* same as ToolChainCore_StatusCNC */
    double   m_cncRunTime;       /* estimated run time, valid after a simulation with calcTime */
} GM_PARAMS_ENHANCED;

/* Error / progress information of callbacks and GetLastError. */
typedef struct CALLBACK_INFO {
    int32_t    stringId;         /* error number; -1: only nLines/actLine valid */
    int32_t    nLines;           /* lines of the G-code, 0 unknown */
    int32_t    actLine;          /* 1-based line, 0 unused */
    int32_t    fileIdx;          /* file index, -1: only nLines/actLine valid */
    TGM_LPCSTR m_fullError;      /* complete text (GetLastError only) */
    TGM_LPCSTR m_errorArguments; /* arguments separated by '\n' (GetLastError only) */
} CALLBACK_INFO;

/* Extent of a program. */
typedef struct GCODE_SIZE {
    P10DOUBLE m_startPos;
    P10DOUBLE m_endPos;
    P10DOUBLE m_minimalPos;
    P10DOUBLE m_maximalPos;
} GCODE_SIZE;

/* [0] original, [1] compensated, [2] original rotated, [3] compensated rotated. */
typedef struct GCODE_INFO {
    GCODE_SIZE m_size[4];
} GCODE_INFO;

typedef struct MACHINE_PARAMETERS {
    P10DOUBLE minCoords;   /* minimum allowed coordinates, relative to refCoords */
    P10DOUBLE maxCoords;   /* maximum allowed coordinates, relative to refCoords */
    P10DOUBLE refCoords;   /* reference point */
    P10BOOL   enableMask;  /* limit test per axis */
    P10DOUBLE backlash;    /* mm */
    P10DOUBLE backlashInc; /* mm per 100 us */
    int32_t   backlashValuesSource;           /* 0 from the INI, 1 from these fields */
    int32_t   enhancedInterpolatorParameters; /* bit field: docs/structures.md */
} MACHINE_PARAMETERS;

typedef struct MACHINE_STATUS {
    uint32_t m_axesStatus;
    uint32_t m_refDone;
    uint32_t m_endSwitches;
    uint32_t m_reserved1, m_reserved2, m_reserved3, m_reserved4, m_reserved5,
             m_reserved6, m_reserved7, m_reserved8, m_reserved9, m_reserved10;
} MACHINE_STATUS;

typedef struct GCODE_FEED {
    double  feed;
    double  acc;
    double  dec;
    int32_t rampType; /* 1 trapezoid, 2 sine */
    int32_t padding1;
} GCODE_FEED;

typedef struct GCODE_CORRECTION {
    double  size;  /* tool radius; negative swaps left and right */
    int32_t gCode; /* 41, 42 (unused) */
    int32_t padding1;
} GCODE_CORRECTION;

typedef struct ARC_FEED_TABLE {
    double m_r;
    double m_relFeed;
} ARC_FEED_TABLE;

typedef struct INTERNAL_MFUNC_INSERT_TABLE {
    int32_t mFunc; /* 0 = unused */
    int32_t padding1;
    double  relFeed;  /* 0.01 .. 1.0 */
    double  distance;
} INTERNAL_MFUNC_INSERT_TABLE;

typedef struct AXIS_LIMITS {
    double maxFeed;
    double maxAcc;
    double maxDec;
} AXIS_LIMITS;

/* G-code properties of a core; meanings and defaults: docs/structures.md. */
typedef struct GCODE_PARAMETERS {
    int32_t  absMode;            /* 1 absolute (default), 0 relative */
    int32_t  swapG2G3;
    uint32_t correctionStrategy; /* CORR_* bits */
    int32_t  forceMode;          /* 0 feeds from G-code, 1 all from motion[], 2 F/FF from motion[] */
    GCODE_FEED motion[8];        /* rapid, forward, backward, connect, no-M, goto, stop, e-stop */
    GCODE_CORRECTION correction[8]; /* radii of G41 .. G48 */
    double   maxConnectionDistance;
    double   startAngle;
    double   endAngle;
    double   minAngleFeed;
    int32_t  disableG0FeedOverride;
    int32_t  interpolatorConfig0;
    double   overrideInc;
    ARC_FEED_TABLE arcFeedTable[5];
    double   centripetalAcc;
    INTERNAL_MFUNC_INSERT_TABLE mFuncInsertTable[3];
    int32_t  MfuncInsertType;
    int32_t  paddingTo8Bytes_2;
    double   reserved;
    int32_t  M02_programEnd1;
    int32_t  M30_programEnd2;
    int32_t  M03_startSpindleCW;
    int32_t  M04_startSpindleCCW;
    int32_t  M05_stopSpindle;
    int32_t  M06_changeTool;
    int32_t  M07_coolOn;
    int32_t  M08_oilOn;
    int32_t  M09_coolOilOff;
    int32_t  M17_return;
    int32_t  M29_print;
    int32_t  M80_mirrorOff;
    int32_t  M81_mirrorX;
    int32_t  M82_mirrorY;
    int32_t  M83_mirrorZ;
    int32_t  M84_mirrorXY;
    int32_t  M85_mirrorXZ;
    int32_t  M86_mirrorYZ;
    int32_t  M87_mirrorXYZ;
    int32_t  M99_defFeed;
    int32_t  insertArcMode;
    int32_t  paddingTo8Bytes_3;
    double   insertArcToleranceRMax;
    double   insertArcToleranceRMin;
    double   insertArcMaxAngle;
    double   insertArcMinAngle;
    int32_t  insertArcPlane;
    int32_t  rezerva1;           /* reserved by the vendor; this library: GCODE_REZERVA1_* bits */
    int32_t  calcTime;
    int32_t  rezerva2;
    double   dynamicG41Correction_mm;
    double   dynamicG42Correction_mm;
    AXIS_LIMITS axisLimits[10];
    double   dynamicG41Correction_percent;
    double   dynamicG42Correction_percent;
    double   tolerance[10];
} GCODE_PARAMETERS;

/* ------------------------------------------------------------------ toolpath (extension) */

/* Beyond the vendor's list: the compiled program as an array of fixed-size records,
 * copied by ToolChainCore_GetToolpath in one call (a host allocates the array, e.g. a
 * numpy structured array, and the library fills it). One record per part, in the
 * order the simulation hands the parts to the driver callbacks. Positions are machine
 * coordinates in mm (the programmed value plus the active zero offset, G54..G59/G92),
 * axes x y z only (the other seven axes: SIMPLE_GM_PARAMS of the simulation). */

/* TC_TOOLPATH_RECORD.kind */
#define TC_TOOLPATH_MOTION     1 /* G0 G1 G2 G3 G33: a move from start to end */
#define TC_TOOLPATH_M_FUNCTION 2 /* an M function (M0, M1, waiting < 1000, continuous >= 1001) */
#define TC_TOOLPATH_DWELL      3 /* G4: dwell seconds in value */
#define TC_TOOLPATH_PRINT      4 /* M29 / PRINT: a text for the output log */

/* TC_TOOLPATH_RECORD.flags */
#define TC_TOOLPATH_FEED_PER_MINUTE 0x01u /* feed is mm/min (G94); else mm per spindle revolution (G95) */
#define TC_TOOLPATH_INSERTED        0x02u /* inserted by the library (compensation corner, G167 arc) */
#define TC_TOOLPATH_CONTINUOUS_M    0x04u /* M >= 1001: signalled at the start of the next move, no wait */
#define TC_TOOLPATH_HELIX           0x08u /* arc with motion off its plane */

/* One part of the compiled program (168 bytes, no padding). A part starts where the
 * previous one ends: the start of the tool centre's path is the previous record's
 * tool_end (the first record's: its start). */
typedef struct TC_TOOLPATH_RECORD {
    double   start[3];      /* programmed start x y z, mm: the previous part's end (the first: the program start) */
    double   end[3];        /* programmed end x y z, mm; M functions, dwells, prints: the current position */
    double   tool_end[3];   /* end of the tool centre's path (after radius compensation), mm; = end without */
    double   centre[3];     /* arc centre x y z, mm (G2/G3; the same for both paths); 0 0 0 otherwise */
    double   radius;        /* radius of the tool centre's arc, mm (G2/G3); 0 otherwise */
    double   length;        /* length of the tool centre's path, mm (helix: with its rise); 0 unless motion */
    double   feed;          /* motion: feed after forceMode/M99, mm/min or mm/rev (flags), rapids motion[0].feed; else 0 */
    double   value;         /* G4: dwell seconds; G33: thread pitch mm; 0 otherwise */
    int32_t  kind;          /* TC_TOOLPATH_MOTION .. TC_TOOLPATH_PRINT */
    int32_t  number;        /* G number of a motion or dwell (0 1 2 3 4 33), M number of an M function, 29 for a print */
    uint32_t line;          /* 1-based line in its file */
    int32_t  file_index;    /* file of the line (ToolChainCore_IdxToFile); -1 unknown */
    int32_t  plane;         /* 17 XY, 18 XZ, 19 YZ, -18 ZX (first axis, second axis): G3 turns from the first to the second */
    int32_t  compensation;  /* 40 none, 41 tool left of the path, 42 right (G41..G48 after the radius's sign) */
    uint32_t flags;         /* TC_TOOLPATH_* bits */
    int32_t  tool;          /* T number, 0 none */
    float    spindle;       /* S, rev/min */
    float    feed_factor;   /* FP relative feed, 1.0 = the programmed feed */
} TC_TOOLPATH_RECORD;

/* ------------------------------------------------------------------ callbacks */

/* Numbers of ToolChainCore_SetCallBack. */
enum callback_number {
    CB_ADD_OUTPUT_LOG              = 1,
    CB_SET_STATUS_BAR_TEXT         = 2,
    CB_IS_DEBUG_MODE               = 3,
    CB_IS_VERBOSE_MODE             = 4,
    CB_GET_LIB_PATH                = 5,
    CB_GET_TOOL_PATH               = 6,
    CB_GET_SYSTEM_PATH             = 7,
    CB_GET_FILE_TIME_STAMP         = 10,
    CB_DO_YIELD                    = 11,
    CB_READ_INI_STRING             = 12,
    CB_READ_INI_DOUBLE             = 13,
    CB_READ_INI_INT                = 14,
    CB_IS_BREAKPOINT               = 17,
    CB_DISP_AND_LOCATE_ERROR       = 18,
    CB_ADD_OUTPUT_LOG_WITH_MSG_BOX = 31,
    CB_SET_STATUS_BAR_PROGRESS     = 32,
    CB_DRIVER_INITIALIZE           = 1001,
    CB_DRIVER_G_FUNC               = 1002,
    CB_DRIVER_M_FUNC               = 1003,
    CB_CONNECT_POINT_CALC_START    = 1004,
    CB_CONNECT_POINT_CALC          = 1005,
    CB_CONNECT_POINT_CALC_END      = 1006,
    CB_DRIVER_END                  = 1007,
    CB_MATH_WARNING                = 2001
};

/* Every callback receives the userData given to SetCallBack first. */
typedef int32_t (*TC_AddOutputLog)(intptr_t userData, uint32_t tab, TGM_LPCTSTR text, CALLBACK_INFO *info);
typedef int32_t (*TC_SetStatusBarText)(intptr_t userData, uint32_t pane, TGM_LPCTSTR text, CALLBACK_INFO *info);
typedef int32_t (*TC_IsDebugMode)(intptr_t userData);
typedef int32_t (*TC_IsVerboseMode)(intptr_t userData);
typedef TGM_LPCTSTR (*TC_GetPath)(intptr_t userData); /* 5, 6, 7 */
typedef int64_t (*TC_GetFileTimeStamp)(intptr_t userData, int32_t fileIdx);
typedef int32_t (*TC_DoYield)(intptr_t userData, int32_t messageOnly);
typedef void    (*TC_ReadIniString)(intptr_t userData, TGM_LPCTSTR section, TGM_LPCTSTR key, TGM_LPCTSTR def, TGM_LPTSTR buf, uint32_t bufChars);
typedef double  (*TC_ReadIniDouble)(intptr_t userData, TGM_LPCTSTR section, TGM_LPCTSTR key, double def);
typedef int32_t (*TC_ReadIniInt)(intptr_t userData, TGM_LPCTSTR section, TGM_LPCTSTR key, int32_t def);
typedef int32_t (*TC_IsBreakpoint)(intptr_t userData, uint32_t editorLine, int32_t fileIdx);
typedef int32_t (*TC_DispAndLocateError)(intptr_t userData, uint32_t editorLine, int32_t fileIdx, TGM_LPCTSTR text, CALLBACK_INFO *info);
typedef int32_t (*TC_AddOutputLogWithMsgBox)(intptr_t userData, uint32_t tab, uint32_t buttons, TGM_LPCTSTR text, CALLBACK_INFO *info);
typedef int32_t (*TC_SetStatusBarProgress)(intptr_t userData, uint32_t percent);
typedef int32_t (*TC_DriverInitialize)(intptr_t userData, double *params, uint32_t nParams, int32_t runMode);
typedef int32_t (*TC_DriverGFunc)(intptr_t userData, const SIMPLE_GM_PARAMS *part);
typedef int32_t (*TC_DriverMFunc)(intptr_t userData, const SIMPLE_GM_PARAMS *part);
typedef int32_t (*TC_ConnectPointCalcStart)(intptr_t userData, uint32_t nType, uint32_t nCoords, const double *coords, uint32_t axesForCalc);
typedef int32_t (*TC_ConnectPointCalc)(intptr_t userData, const SIMPLE_GM_PARAMS *part, double *sqDistance, P10DOUBLE *point);
typedef int32_t (*TC_ConnectPointCalcEnd)(intptr_t userData, SIMPLE_GM_PARAMS *part, P10DOUBLE *point);
typedef int32_t (*TC_DriverEnd)(intptr_t userData);
typedef int32_t (*TC_MathWarning)(intptr_t userData, CALLBACK_INFO *info);

/* ------------------------------------------------------------------ functions */

/*
 * Lifecycle
 */

/* First call of a session: stores the directories and Local_Core_Mode.
 * Returns 0; -1 if p or any of its strings is NULL or the mode is not 0..2.
 * Without it the current directory and the offline mode apply. */
TOOLCHAIN_API int32_t TOOLCHAIN_CALLTYPE ToolChainCore_Init(const DLL_INIT_STRUCT *p);

/* Loads the core's configuration from a Windows-syntax INI file ([Modules], [CNC],
 * [GCodeParameters], [Offline], [Corrections], [Smoothing]) and writes the number of
 * cores to *pnMaxCores (may be NULL). Only a regular file is read (a FIFO or device
 * never blocks the call), without the core's lock; numbers have a '.' decimal point
 * whatever the locale. [Corrections] ToolTable and AxisTable1..8 name table files
 * (relative names from the INI file's folder), read as LoadToolTable and
 * LoadAxisCorrections read them. Returns 0, or 1 (TOOL_CHAIN_XEXEC) when the file is
 * missing, not a regular file, unreadable, larger than 1 GiB, a [GCodeParameters] or
 * [Smoothing] value is not a number or outside its bounds (error 16 naming the key and
 * the line), or a table file it names is refused (that file's error) -- nothing of
 * the file is applied then, the reason via GetLastCallError and DispAndLocateError;
 * -2 bad core; -1 while the core is busy. The file is read into a copy of the core's G-code
 * parameters: a SetGCodeParameters from another thread during the call is replaced. */
TOOLCHAIN_API int32_t TOOLCHAIN_CALLTYPE ToolChainCore_LoadFromIni(uint32_t intIdx, TGM_LPCTSTR iniFile, uint32_t *pnMaxCores);

/* Stops everything on the core (interrupts a compilation, ends a simulation or motion,
 * joins the core's worker) and releases its program; status 0. Safe to call twice and
 * at any time; no callback of the ended activity is called after it returns (inside a
 * callback: the activity ends once that callback returns). The machine position
 * (ResetCNC) is kept. Returns 0, -2 bad core. */
TOOLCHAIN_API int32_t TOOLCHAIN_CALLTYPE ToolChainCore_DestroyCNC(uint32_t intIdx);

/* Version and build date/time; valid until the library is unloaded. Never NULL
 * (an empty string for a bad core). */
TOOLCHAIN_API TGM_LPCTSTR TOOLCHAIN_CALLTYPE ToolChainCore_GetVersionString(uint32_t intIdx);

/* Fills up to nItems entries of items: [0] number of sizes known (8), then the sizes of
 * GCODE_PARAMETERS, SIMPLE_GM_PARAMS, GM_PARAMS_ENHANCED, CALLBACK_INFO, GCODE_INFO,
 * MACHINE_STATUS, MACHINE_PARAMETERS, DLL_INIT_STRUCT. Always 0 (items NULL: nothing written). */
TOOLCHAIN_API int32_t TOOLCHAIN_CALLTYPE ToolChainCore_GetStructuresSize(uint32_t intIdx, uint32_t nItems, uint32_t *items);

/*
 * G-code, machine and user parameters
 */

/* Sets the core's G-code properties. -1 for NULL, while compiling or moving; while
 * stopped on the trajectory only the feed-related fields (motion, startAngle, endAngle,
 * minAngleFeed, overrideInc, arcFeedTable, axisLimits) are taken.
 * -1 too, nothing changed and an error naming the field (14 not finite, 15 out of
 * range), when a double taken is NaN, infinite or outside its bounds:
 *   motion[i].feed/acc/dec in (0, 1e9]; correction[i].size, dynamicG4xCorrection_mm
 *   in [-1e6, 1e6] mm; maxConnectionDistance, tolerance[i], arcFeedTable[i].m_r,
 *   mFuncInsertTable[i].distance, insertArcToleranceRMax/RMin in [0, 1e6];
 *   minAngleFeed, centripetalAcc, axisLimits[i].* in [0, 1e9] (0 = no limit);
 *   startAngle, endAngle, insertArcMaxAngle/MinAngle in [0, 360] degrees;
 *   arcFeedTable[i].m_relFeed in [0, 100]; mFuncInsertTable[i].relFeed in [0, 1];
 *   dynamicG4xCorrection_percent in [-1000, 1000]; overrideInc finite (then clamped:
 *   0 or less -> 0.001, at most 0.1). `reserved` and the integers are not checked. */
TOOLCHAIN_API int32_t TOOLCHAIN_CALLTYPE ToolChainCore_SetGCodeParameters(uint32_t intIdx, const GCODE_PARAMETERS *p);

/* Copies the current G-code properties (defaults, INI or the last Set). -1 NULL. */
TOOLCHAIN_API int32_t TOOLCHAIN_CALLTYPE ToolChainCore_GetGCodeParameters(uint32_t intIdx, GCODE_PARAMETERS *p);

/* Soft limits and backlash; any status. -1 NULL. SetMachineParameters: -1 too, nothing
 * changed and an error naming the field, when minCoords, maxCoords or refCoords is not
 * finite or beyond +-1e6 mm, or backlash / backlashInc is outside [0, 1e6]. */
TOOLCHAIN_API int32_t TOOLCHAIN_CALLTYPE ToolChainCore_GetMachineParameters(uint32_t intIdx, MACHINE_PARAMETERS *p);
TOOLCHAIN_API int32_t TOOLCHAIN_CALLTYPE ToolChainCore_SetMachineParameters(uint32_t intIdx, MACHINE_PARAMETERS *p);

/* Presets P00..P99 for the next compilations: n = 100 (p not NULL) sets them, n = 0
 * clears the preset (parameters start at 0). Other n, or a value that is NaN or
 * infinite: -1. */
TOOLCHAIN_API int32_t TOOLCHAIN_CALLTYPE ToolChainCore_SetUserParams(uint32_t intIdx, const double *p, uint32_t n);

/* G-code compiled before / after every main program; NULL = none. -1 while compiling. */
TOOLCHAIN_API int32_t TOOLCHAIN_CALLTYPE ToolChainCore_GCodePrefixPostfix(uint32_t intIdx, TGM_LPCSTR prefix, TGM_LPCSTR postfix);

/*
 * Compilation
 */

/* Starts compiling a file in the core's background thread and returns at once:
 * 0 (status already reads 1 or -1), -1 bad name / unreadable file / not a regular file
 * (a FIFO or device: refused, never opened blocking) / larger than 1 GiB / already
 * busy, -2.
 * The result: StatusCNC -1, then GetLastError. */
TOOLCHAIN_API int32_t TOOLCHAIN_CALLTYPE ToolChainCore_CompileFromFile(uint32_t intIdx, TGM_LPCTSTR fileName);

/* Same for G-code text in memory; fileName names it for errors and file indexes. */
TOOLCHAIN_API int32_t TOOLCHAIN_CALLTYPE ToolChainCore_CompileFromMemory(uint32_t intIdx, TGM_LPCTSTR fileName, TGM_LPCSTR code);

/* 0 idle, 1 busy (compiling, simulating, moving), -2 bad core. */
TOOLCHAIN_API int32_t TOOLCHAIN_CALLTYPE ToolChainCore_IsBusy(uint32_t intIdx);

/* 0 no error (info untouched); 1 the last compilation or run failed and info is filled;
 * -1 NULL. The strings are never rewritten: they stay valid until the calling thread
 * calls GetLastError for this core again (or ends), whatever other threads do.
 * A refused call never changes it: see GetLastCallError. */
TOOLCHAIN_API int32_t TOOLCHAIN_CALLTYPE ToolChainCore_GetLastError(uint32_t intIdx, CALLBACK_INFO *info);

/* Beyond the vendor's list. The error of the last call on the core that was refused
 * with an error text (busy, wrong status, unreadable file, not implemented, ...):
 * 1 and info filled (the strings never rewritten, valid until the calling thread calls
 * GetLastCallError for this core again or ends), 0 none yet; -1 NULL, -2 bad core. The same error also went to DispAndLocateError and AddOutputLog. */
TOOLCHAIN_API int32_t TOOLCHAIN_CALLTYPE ToolChainCore_GetLastCallError(uint32_t intIdx, CALLBACK_INFO *info);

/* Beyond the vendor's list. The 1-based column of the word in error of the error that
 * GetLastError (ofCalls 0) or GetLastCallError (ofCalls 1) gives now, for the errors
 * whose format has no place for it (the vendor's arc-centre error 400 and its kin 407,
 * 415-420; docs/errors.md) and for every error whose format names a column: 1 and
 * *column (0: unknown), 0 no such error; -1 column NULL or ofCalls not 0/1, -2 bad core.
 * Read it right after GetLastError: a later error replaces both. */
TOOLCHAIN_API int32_t TOOLCHAIN_CALLTYPE ToolChainCore_GetLastErrorColumn(uint32_t intIdx, int32_t ofCalls, int32_t *column);

/* Index of a file name (new names get the next index, 64 per core; when the table is
 * full the least recently used name that no loaded program references is replaced,
 * its run time forgotten). Special names give -1..-4; NULL, empty or names of 252
 * characters or more: -1. */
TOOLCHAIN_API int32_t TOOLCHAIN_CALLTYPE ToolChainCore_FileToIdx(uint32_t intIdx, TGM_LPCTSTR fileName);

/* Inverse of FileToIdx; special and unknown indexes give the special names. Never NULL;
 * the text is never rewritten (also when the entry is recycled) and stays valid until
 * the library is unloaded. */
TOOLCHAIN_API TGM_LPCTSTR TOOLCHAIN_CALLTYPE ToolChainCore_IdxToFile(uint32_t intIdx, int32_t fileIdx);

/* Start/end/min/max of the compiled program (arcs with their true extremes). -1 NULL or
 * nothing compiled, or no memory to measure it from a start ResetCNC moved (error 4 in
 * GetLastCallError; ResetCNC itself never fails for memory). */
TOOLCHAIN_API int32_t TOOLCHAIN_CALLTYPE ToolChainCore_GetGCodeSizeInfo(uint32_t intIdx, GCODE_INFO *p);

/* Run time in seconds of the file (its index) from the last simulation with calcTime = 1
 * or SetGCodeRunTime; negative if unknown. */
TOOLCHAIN_API double TOOLCHAIN_CALLTYPE ToolChainCore_GetGCodeRunTime(uint32_t intIdx, int32_t fileIdx);

/* Stores a known run time for a file index. -1 for a negative index, a negative,
 * infinite or NaN time. */
TOOLCHAIN_API int32_t TOOLCHAIN_CALLTYPE ToolChainCore_SetGCodeRunTime(uint32_t intIdx, int32_t fileIdx, double seconds);

/* Legacy single-core names: core 0. */
TOOLCHAIN_API int32_t TOOLCHAIN_CALLTYPE ToolChain_GetLastError(CALLBACK_INFO *info);
TOOLCHAIN_API TGM_LPCTSTR TOOLCHAIN_CALLTYPE ToolChain_IdxToFile(int32_t fileIdx);

/*
 * Running
 */

/* Ends any activity (interrupts a compilation, stops a run; waits until the worker is
 * joined) and sets the machine position, where the next run and compilation start:
 * regime 1 only marks the program start; otherwise the first nCoords machine
 * coordinates come from coords (axis order; nCoords 0 keeps all). A program written
 * relative to its start (G91 from the first block) moves with it; any other keeps its
 * positions and only its first move starts there. Status -30 when a program is
 * compiled. -1 when nCoords > 10, coords is NULL with nCoords > 0, or one of the first
 * nCoords coordinates is NaN or infinite (nothing done). */
TOOLCHAIN_API int32_t TOOLCHAIN_CALLTYPE ToolChainCore_ResetCNC(uint32_t intIdx, int32_t regime, uint32_t nCoords, const double *coords);

/* Starts a run in the core's worker (run_regime) from the machine position; a
 * simulation or test is a dry run and does not move the machine position. addCode:
 * M functions sent first (the offline machine: at status 70, one that DriverMFunc
 * answers TC_MFUNC_LATER holds the start until ToolChainCore_ConfirmMFunc). -1 when
 * compiling, nothing compiled, the regime cannot start in this status, or inside a
 * callback of the core's running activity. */
TOOLCHAIN_API int32_t TOOLCHAIN_CALLTYPE ToolChainCore_StartCNCEx(uint32_t intIdx, int32_t regime, TGM_LPCSTR addCode);

/* Controlled stop (simulation: -11, test: -21, motion: -31); returns at once, the
 * worker sets the status when it has stopped, after sending addCode's M functions (not
 * in regimes 31, 32; the offline machine: at status 80, held like the start's). It also
 * answers an M function that waits for its confirmation (it stays sent). -1 when
 * nothing runs. */
TOOLCHAIN_API int32_t TOOLCHAIN_CALLTYPE ToolChainCore_StopCNCEx(uint32_t intIdx, TGM_LPCSTR addCode);

/* Moves back onto the trajectory (connect_type): docs/api.md, docs/connect.md. */
TOOLCHAIN_API int32_t TOOLCHAIN_CALLTYPE ToolChainCore_ConnectCNCEx_Plane(uint32_t intIdx, uint32_t nType, uint32_t nCoords, const double *coords, TGM_LPCSTR addCode, uint32_t axesForCalc, uint32_t axesForConnect, int32_t stateAfter);

/* Manual linear move to absolute coordinates with motion[5]. -1 (error 24) when its
 * path is not finite from where the machine stands (a target that far away). */
TOOLCHAIN_API int32_t TOOLCHAIN_CALLTYPE ToolChainCore_GoToPosition(uint32_t intIdx, uint32_t nCoords, const double *coords);

/* Manual move by line or arc described by dest (m_func 1/2/3, m_calcE, m_cc). -1
 * (error 24) when its path is not finite (a target, an arc centre or a feed too large). */
TOOLCHAIN_API int32_t TOOLCHAIN_CALLTYPE ToolChainCore_GoToPositionEx(uint32_t intIdx, const SIMPLE_GM_PARAMS *dest);

/* Signals M function fun->m_func to the machine while stopped. */
TOOLCHAIN_API int32_t TOOLCHAIN_CALLTYPE ToolChainCore_MFunc(uint32_t intIdx, const SIMPLE_GM_PARAMS *fun, int32_t bDirectToPLC);

/* Feed override, a coefficient clamped to the interpolator's Rel_Speed range 0.01 .. 2.0
 * (1 % .. 200 %): 0, the "hold" of some panels, gives 1 %, as the vendor's library does.
 * NaN is -1. */
TOOLCHAIN_API int32_t TOOLCHAIN_CALLTYPE ToolChainCore_SetRelFeed(uint32_t intIdx, double relFeed);

/* One built-in breakpoint: the run stops just before the part on that line. */
TOOLCHAIN_API int32_t TOOLCHAIN_CALLTYPE ToolChainCore_SetBreakpoint(uint32_t intIdx, uint32_t editorLine, int32_t fileIdx);

/* In a negative status: mode 0 drops the program (status 0), mode 1 declares
 * "out of trajectory" (-50). -1 otherwise. */
TOOLCHAIN_API int32_t TOOLCHAIN_CALLTYPE ToolChainCore_ResetStatusCNC(uint32_t intIdx, uint32_t mode);

/* The core's cnc_status; cheap, never blocks. A bad core gives -1234. */
TOOLCHAIN_API int32_t TOOLCHAIN_CALLTYPE ToolChainCore_StatusCNC(uint32_t intIdx);

/* Current state for the HMI; either pointer may be NULL, not both. Never blocks on a
 * running compilation. */
TOOLCHAIN_API int32_t TOOLCHAIN_CALLTYPE ToolChainCore_GetPos(uint32_t intIdx, int32_t reserved, SIMPLE_GM_PARAMS *pos, GM_PARAMS_ENHANCED *enh);

/* Loads (or with an empty name unloads) a calculation plug-in. 1 success, -1 error. */
TOOLCHAIN_API int32_t TOOLCHAIN_CALLTYPE ToolChainCore_LoadCNCCalcPlugIn(TGM_LPCTSTR fileName, uint32_t flags, int64_t userValue);

/*
 * Callbacks
 */

/* Sets (fn non-NULL) or removes (fn NULL) callback fceNo (callback_number) of the core;
 * userData is passed back as the first argument. Returns once no call of the previous
 * function runs on another thread, and no later call reaches it: the host may free it
 * then. Called from inside any callback it returns at once (no later call reaches the
 * old function, but one may still run on another thread): waiting there could wait for
 * a callback that waits for this one. 0; -1 unknown number, or a driver number (> 1000) before LoadFromIni; -2 bad
 * core. */
TOOLCHAIN_API int32_t TOOLCHAIN_CALLTYPE ToolChainCore_SetCallBack(uint32_t intIdx, uint32_t fceNo, intptr_t userData, void *fn);

/*
 * Logging (any thread, any time)
 */

/* Sets the log mask (LOG_*); always 0. */
TOOLCHAIN_API int32_t TOOLCHAIN_CALLTYPE ToolChainCore_SetLogValue(uint32_t value);
TOOLCHAIN_API uint32_t TOOLCHAIN_CALLTYPE ToolChainCore_GetLogValue(void);
/* Appends a line to the log outputs selected by the mask (NULL ignored). */
TOOLCHAIN_API void TOOLCHAIN_CALLTYPE ToolChain_LogANSI(TGM_LPCSTR text);
/* Flushes the log file. */
TOOLCHAIN_API void TOOLCHAIN_CALLTYPE ToolChain_FlushLogFile(void);

/*
 * Toolpath (extension, not in the vendor's library)
 */

/* Copies records [first, first + capacity) of the compiled program's toolpath into out
 * (TC_TOOLPATH_RECORD) and, on success, writes the number of records of the whole
 * program to *total (may be NULL); the records written are min(capacity, total - first).
 * out may be NULL when capacity is 0 (asks for the total). A host copies the whole
 * program with one call (capacity = total) or in chunks; chunks stay consistent while
 * the host does not change the program meanwhile (a compilation replaces it, ResetCNC
 * with coordinates moves its start, ResetStatusCNC 0 and DestroyCNC drop it). The
 * positions are those of a run from the machine position (axes the program has not
 * named yet follow it). Takes its own reference to the program, so it holds no lock
 * while it copies; never fails for lack of memory and reports nothing through
 * GetLastError or the callbacks.
 * Returns 0; -1 while compiling, when nothing is compiled (or the compilation failed),
 * first > total, or out is NULL with capacity > 0; -2 bad core. */
TOOLCHAIN_API int32_t TOOLCHAIN_CALLTYPE ToolChainCore_GetToolpath(uint32_t intIdx, TC_TOOLPATH_RECORD *out, uint64_t capacity, uint64_t first, uint64_t *total);

/*
 * Feed planner (extension)
 */

/* Look-ahead of the feed planner in parts, for the core's next compilations: 0 the
 * vendor's window (the current part and 7 more: run times as on a TG Motion machine),
 * n >= 1 that many parts, -1 unlimited (faster on dense short segments; docs/planner.md).
 * Also the INI key [GCodeParameters] lookAheadParts. Any thread, any status.
 * Returns 0; -1 for parts < -1; -2 bad core. */
TOOLCHAIN_API int32_t TOOLCHAIN_CALLTYPE ToolChainCore_SetLookAhead(uint32_t intIdx, int32_t parts);

/*
 * Offline machine (extension)
 */

/* Speed of the offline machine (Local_Core_Mode 2) against real time: 1 real time, 10
 * ten times faster (for tests and fast dry runs), 0.5 half as fast; (0, 1e6]. Takes
 * effect at once, also during a run. Also the INI key [Offline] TimeScale.
 * Returns 0; -1 for a value outside (0, 1e6] or not finite; -2 bad core. */
TOOLCHAIN_API int32_t TOOLCHAIN_CALLTYPE ToolChainCore_SetTimeScale(uint32_t intIdx, double scale);

/* Confirms the waiting M function the offline machine stands at, when DriverMFunc
 * (1003) answered TC_MFUNC_LATER instead of 0 (the PLC confirms later), or the one
 * ToolChainCore_MFunc signalled. Any thread, also inside a callback.
 * Returns 0; -1 when no M function waits for a confirmation; -2 bad core. */
#define TC_MFUNC_LATER 2
TOOLCHAIN_API int32_t TOOLCHAIN_CALLTYPE ToolChainCore_ConfirmMFunc(uint32_t intIdx);

/* Test-only: never call it from a host. The offline machine's stepped clock, for tests
 * that step the machine instead of sleeping. With key TC_TEST_CLOCK_KEY:
 *   seconds > 0: the core's machine runs on a clock that only this function advances
 *     (from now on, also in later runs: the wall clock and the time scale no longer move
 *     it), and the run that moves -- or is starting -- runs `seconds` of machine time in
 *     100 us steps. Returns once they have run (or the machine halted, stands at an M
 *     function that waits for a confirmation, or nothing moves), GetPos shows them and
 *     every driver callback they caused has returned.
 *   seconds == 0: the stepped clock on, nothing run.   seconds < 0: the wall clock again.
 * Any other key: -1 and nothing changes, so no host switches it on by accident.
 * Returns 0; -1 for another key, NaN, or a call from a library thread (a callback of a
 * running activity: it would wait for its own thread); -2 bad core. */
#define TC_TEST_CLOCK_KEY 0x4B434F4C43545354ULL   /* "TSTCLOCK" */
TOOLCHAIN_API int32_t TOOLCHAIN_CALLTYPE ToolChainCore_TestClock(uint32_t intIdx, uint64_t key, double seconds);

/* Test-only: never call it from a host. Fails the library's allocations one at a time,
 * for tests that fail each allocation of an operation in turn and check that it reports
 * error 4 "Out of memory" and leaves nothing behind (docs/testing.md). With key
 * TC_TEST_ALLOC_KEY:
 *   nth > 0: the nth allocation of the library from now (on any of its threads, for any
 *     core) fails, once, as an exhausted memory would; the ones after it succeed.
 *   nth == 0: none fails.
 * Any other key: -1 and nothing changes.
 * Returns how many allocations the previous setting still had to go before its failure:
 * 0 once that failure happened (or when none was set), n > 0 when fewer allocations than
 * asked for were made meanwhile (nth - n of them); -1 for another key or nth < 0. */
#define TC_TEST_ALLOC_KEY 0x434F4C4C41545354ULL   /* "TSTALLOC" */
TOOLCHAIN_API int64_t TOOLCHAIN_CALLTYPE ToolChain_TestAllocFail(uint64_t key, int64_t nth);

/*
 * Log hook (extension)
 */

/* Receives each line the log writes (ToolChain_LogANSI and the library's own lines of
 * the sources enabled by ToolChainCore_SetLogValue), whatever the outputs of the mask:
 * source is the line's LOG_* source bit (0 for ToolChain_LogANSI), text the line
 * without time stamp or newline, valid during the call only. Called on the thread that
 * logs (the host's, or a worker's), one call at a time. */
typedef void (*TC_LogHook)(intptr_t userData, uint32_t source, TGM_LPCSTR text);

/* Sets (fn, a TC_LogHook, non-NULL) or removes (fn NULL) the log hook; userData is
 * passed back as its first argument. Returns once no call of the previous hook runs:
 * the host may free it then. Lines logged by the hook itself do not reach it again; the
 * hook must not wait for the library's threads (DestroyCNC, ResetCNC, a blocking stop).
 * Returns 0; -1 when called from inside the hook (nothing changed). */
TOOLCHAIN_API int32_t TOOLCHAIN_CALLTYPE ToolChain_SetLogHook(intptr_t userData, void *fn);

/*
 * Correction tables and smoothing (extension)
 *
 * What a machine builder configures once per core: the tool correction table
 * (docs/tool-table.md), the axis correction tables (docs/axis-correction.md) and the
 * smoothing of the machine's output (docs/smoothing.md). Each is also an INI key of
 * ToolChainCore_LoadFromIni ([Corrections], [Smoothing]). Any status, any thread (also
 * inside a callback): a file is read without the core's lock, and what was in memory
 * changes only when all of it is good. Programs use the tool table (D, &, G92 D: a
 * compilation works on a copy taken when it starts; docs/tool-table.md, "In programs");
 * the offline machine applies the smoothing and the axis corrections to its output, in
 * the order interpolator -> spline -> IIR filter -> axis corrections -> drives (GetPos:
 * m_calcS the filtered position, m_calcE the corrected one the drives are sent; the
 * spline delays the M functions with the output, and a run ends once the output
 * settled); ToolChainCore_CorrectPosition and ToolChainCore_SmoothSamples apply them to
 * a host's positions and samples. Those pages' "Integration status" says when the
 * machine takes a reloaded table or changed setting.
 */

/* Entries of the tool correction table: D1..D99. */
#define TC_TOOL_ENTRIES 99
/* Values of an entry (values[5] below; bit k of `programmed`): [0] the radius (D, what
 * G41/G42 use; a negative radius swaps the side), [1]..[4] the length corrections of
 * axes 1..4 (&), in mm: G92 D's R0..R4. */
#define TC_TOOL_RADIUS  0
#define TC_TOOL_VALUES  5

/* Reads the tool correction table file fileName (the vendor's TAB0.KOR format: an
 * optional comment, the keyword $KOR, lines "NN: R=.. X=.. Y=.. Z=.. 4=.."; any name;
 * only a regular file, never blocking) into the core's table, replacing all 99 entries
 * (an entry the file does not give is 0; a value its line does not give is 0).
 * Returns 0; -1, the table unchanged and the reason through GetLastCallError, when
 * fileName is NULL or empty, the file cannot be read (errors 1, 2, 12, 13), has no
 * $KOR line (720) or a line that is no entry (721: the file and the line); -2 bad
 * core. */
TOOLCHAIN_API int32_t TOOLCHAIN_CALLTYPE ToolChainCore_LoadToolTable(uint32_t intIdx, TGM_LPCTSTR fileName);

/* Copies entry `entry` (1..99) of the core's tool correction table into values[0..4]
 * (TC_TOOL_VALUES doubles: radius, lengths of axes 1..4, mm).
 * Returns 0; -1 for values NULL or an entry outside 1..99; -2 bad core. */
TOOLCHAIN_API int32_t TOOLCHAIN_CALLTYPE ToolChainCore_GetToolCorrection(uint32_t intIdx, uint32_t entry, double *values);

/* G92 D's write into the table in memory (never into the file): for every bit k set in
 * `programmed` (bit 0 R0 the radius, bits 1..4 R1..R4 the lengths of axes 1..4),
 * values[k] becomes value k of entry `entry`; the values of the other bits stay.
 * G92 D12 R0=10 R2=25.5 R3=-5 is entry 12, programmed 0x0D, values {10, -, 25.5, -5, -}.
 * values may be NULL when programmed is 0 (nothing is written).
 * Returns 0; -1 for bits above bit 4 in programmed or values NULL with a bit set, and,
 * nothing written and the error through GetLastCallError, for an entry outside 1..99
 * (722) or a value written that is NaN, infinite (14) or beyond +-1e6 mm (15, naming
 * it as "D12 R2"); -2 bad core. */
TOOLCHAIN_API int32_t TOOLCHAIN_CALLTYPE ToolChainCore_SetToolCorrection(uint32_t intIdx, uint32_t entry, uint32_t programmed, const double *values);

/* Replaces the core's axis correction tables by the nFiles files fileNames[0..nFiles)
 * (the vendor's binary ACHS3D??.KOR format, little-endian: a 128-byte header with the
 * corrected axis and one to three basis axes, a definition block, the grid of FLOAT
 * corrections; any names); nFiles 0 removes them all. At most 8 tables, each with its
 * own number (the header's last byte); two tables of one axis add their corrections.
 * Returns 0; -1, the tables unchanged and the reason through GetLastCallError, for
 * fileNames NULL with nFiles > 0, a NULL or empty name, a file that cannot be read
 * (1, 2, 12, 13), a header (730), definition block (731), size (732) or correction
 * (733) that does not fit, more than 8 files or two tables with the same number (734):
 * the error names the file and the field; -2 bad core. */
TOOLCHAIN_API int32_t TOOLCHAIN_CALLTYPE ToolChainCore_LoadAxisCorrections(uint32_t intIdx, uint32_t nFiles, const TGM_LPCTSTR *fileNames);

/* corrected[0..9] = position[0..9] (machine coordinates, mm, axis order x y z c b u v w
 * a o) with the core's axis correction tables applied: each table adds to its axis the
 * correction interpolated linearly in each basis axis between the grid points around
 * the basis axes' positions in `position` (outside a table's range a basis axis counts
 * at the range's edge). Without tables a copy. corrected may be position.
 * Returns 0; -1 for NULL or a coordinate that is NaN or infinite; -2 bad core. */
TOOLCHAIN_API int32_t TOOLCHAIN_CALLTYPE ToolChainCore_CorrectPosition(uint32_t intIdx, const double *position, double *corrected);

/* The Interpolator's Command register values of the vendor's smoothing. */
#define TC_SMOOTHING_IIR    (-1)
#define TC_SMOOTHING_SPLINE (-2)

/* Sets the smoothing of the core's output as the vendor's Command register and
 * Command_Parameter[0..3] do, in their units (params: 4 doubles):
 *   command -2 (spline): params[0] the buffer in steps of the machine (100 us), 0 off or
 *     50..500 (the output's delay); params[1] the jerk limit in mm/s^3 (1,000,000 is the
 *     vendor's advice), above 0 when the spline is on; params[2..3] unused;
 *   command -1 (IIR filter H(s) = q / (s^2 + p s + q), s in units of 2 pi / f):
 *     params[0] p x 1e6, params[1] q x 1e6, params[2] f x 1e6 (f in seconds),
 *     params[3] the axes filtered, bit k axis k (bits above 9 ignored), 0 off; p, q and
 *     f above 0 when an axis is filtered.
 * Every value must be a number in [0, 1e12]. Returns 0; -1 for params NULL or another
 * command, and, nothing changed and the error (740) through GetLastCallError, for a
 * value that does not fit; -2 bad core. */
TOOLCHAIN_API int32_t TOOLCHAIN_CALLTYPE ToolChainCore_SetSmoothing(uint32_t intIdx, int32_t command, const double *params);

/* Copies the core's values of command -2 or -1 into params[0..3] (as set; the spline's
 * params[2..3] 0). Returns 0; -1 for params NULL or another command; -2 bad core. */
TOOLCHAIN_API int32_t TOOLCHAIN_CALLTYPE ToolChainCore_GetSmoothing(uint32_t intIdx, int32_t command, double *params);

/* Runs the core's smoothing (spline, then IIR filter) over nSamples positions of ten
 * axes, samples[10 * i + axis], one per machine step of 100 us, as the machine's output
 * would pass it: standing at samples[0..9] before the first. Writes the smoothed
 * positions to out (the same layout; out may be samples) and to *settledFrom (may be
 * NULL) the first sample from which on the output had settled after every sample, i.e.
 * equals the input within 1e-6 mm and will while the input stands (nSamples: not settled
 * at the end). Does not change the core; holds no lock while it runs.
 * Returns 0; -1 for samples or out NULL with nSamples > 0, a sample that is NaN or
 * infinite, or no memory for the spline's buffer; -2 bad core. */
TOOLCHAIN_API int32_t TOOLCHAIN_CALLTYPE ToolChainCore_SmoothSamples(uint32_t intIdx, const double *samples, uint64_t nSamples, double *out, uint64_t *settledFrom);

/* ------------------------------------------------------------------ layout checks */
/* The vendor's layouts: x86_64 (Linux and Windows x64) and 32-bit x86 (Windows x86, and
 * Linux i686, whose 4-byte alignment of double inside structures changes no offset
 * here: every double already falls on 8). On 32 bits only the structures holding
 * pointers shrink: DLL_INIT_STRUCT (three texts) and CALLBACK_INFO (two). */
#if defined(__x86_64__) || defined(_M_X64) || defined(__i386__) || defined(_M_IX86)
#  if defined(__cplusplus)
#    define TGM_STATIC_ASSERT(c, m) static_assert(c, m)
#  else
#    define TGM_STATIC_ASSERT(c, m) _Static_assert(c, m)
#  endif
#  if defined(__x86_64__) || defined(_M_X64)
TGM_STATIC_ASSERT(sizeof(DLL_INIT_STRUCT) == 32, "DLL_INIT_STRUCT");
TGM_STATIC_ASSERT(sizeof(CALLBACK_INFO) == 32, "CALLBACK_INFO");
TGM_STATIC_ASSERT(offsetof(CALLBACK_INFO, m_errorArguments) == 24, "m_errorArguments");
TGM_STATIC_ASSERT(offsetof(DLL_INIT_STRUCT, Local_Core_Mode) == 24, "Local_Core_Mode");
#  else
TGM_STATIC_ASSERT(sizeof(DLL_INIT_STRUCT) == 16, "DLL_INIT_STRUCT (32-bit)");
TGM_STATIC_ASSERT(sizeof(CALLBACK_INFO) == 24, "CALLBACK_INFO (32-bit)");
TGM_STATIC_ASSERT(offsetof(CALLBACK_INFO, m_errorArguments) == 20, "m_errorArguments (32-bit)");
TGM_STATIC_ASSERT(offsetof(DLL_INIT_STRUCT, Local_Core_Mode) == 12, "Local_Core_Mode (32-bit)");
#  endif
TGM_STATIC_ASSERT(sizeof(P10DOUBLE) == 80, "P10DOUBLE");
TGM_STATIC_ASSERT(sizeof(P10BOOL) == 40, "P10BOOL");
TGM_STATIC_ASSERT(sizeof(P26FLOAT) == 104, "P26FLOAT");
TGM_STATIC_ASSERT(sizeof(SIMPLE_GM_PARAMS) == 616, "SIMPLE_GM_PARAMS");
TGM_STATIC_ASSERT(sizeof(GM_PARAMS_ENHANCED) == 112, "GM_PARAMS_ENHANCED");
TGM_STATIC_ASSERT(offsetof(GM_PARAMS_ENHANCED, m_cncRunTime) == 104, "m_cncRunTime");
TGM_STATIC_ASSERT(sizeof(MACHINE_STATUS) == 52, "MACHINE_STATUS");
TGM_STATIC_ASSERT(sizeof(GCODE_PARAMETERS) == 1112, "GCODE_PARAMETERS");
TGM_STATIC_ASSERT(sizeof(GCODE_SIZE) == 320, "GCODE_SIZE");
TGM_STATIC_ASSERT(sizeof(GCODE_INFO) == 1280, "GCODE_INFO");
TGM_STATIC_ASSERT(sizeof(MACHINE_PARAMETERS) == 448, "MACHINE_PARAMETERS");
TGM_STATIC_ASSERT(offsetof(MACHINE_PARAMETERS, backlash) == 280, "backlash");
TGM_STATIC_ASSERT(offsetof(GCODE_PARAMETERS, M02_programEnd1) == 624, "M02_programEnd1");
TGM_STATIC_ASSERT(offsetof(GCODE_PARAMETERS, tolerance) == 1032, "tolerance");
TGM_STATIC_ASSERT(offsetof(SIMPLE_GM_PARAMS, m_fp) == 612, "m_fp");
TGM_STATIC_ASSERT(sizeof(TC_TOOLPATH_RECORD) == 168, "TC_TOOLPATH_RECORD");
#  undef TGM_STATIC_ASSERT
#endif

#ifdef __cplusplus
}
#endif
#endif /* TGM_CNC_H */
