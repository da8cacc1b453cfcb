// SfTch.cs -- a C# binding of SF_TCh (SF_TCh.dll on Windows, libSF_TCh.so on Linux) for
// .NET and Mono panels: the structures of include/tgm_cnc.h, the exports (cdecl), the
// callback delegates, and the helpers that keep a panel out of the traps below.
//
//   * Texts the library lends or returns (GetVersionString, IdxToFile, a callback's
//     text, CALLBACK_INFO's m_fullError / m_errorArguments) are IntPtr, read with
//     Texts.*. Declared `string`, the marshaller would free the library's memory
//     ("munmap_chunk(): invalid pointer", or a heap corruption on Windows).
//   * Host texts (TGM_LPCTSTR: file names, directories) are UTF-16 on Windows and UTF-8 on
//     Linux: HostText makes the right one. (CharSet.Unicode would hand the Linux library
//     UTF-16, which it reads as "S" for "SF_TCh.ini".)
//   * Narrow texts (TGM_LPCSTR: G-code, add codes, log lines, CALLBACK_INFO's texts) are
//     the process's ANSI code page on Windows (the vendor's "ANSI"; UTF-8 when the INI
//     opts in, Texts.NarrowIsUtf8) and UTF-8 on Linux: NarrowText / Texts.Narrow.
//   * Delegates handed to the library are kept in a static table (Callbacks.Set) until
//     the library no longer calls them: a collected delegate kills the process the next
//     time a library thread calls it.
//   * Every callback body runs guarded (Callbacks.Guard): an exception escaping into the
//     library's thread ends the process. Callbacks.Faults counts what was caught.
//   * P10BOOL is ten 4-byte ints, not bool.
//   * Layout.Check() compares every Marshal.SizeOf with ToolChainCore_GetStructuresSize at
//     start-up: a structure declared too small is written past its end.
//
// Compile with the panel (mcs SfTch.cs Panel.cs, or add both to a .NET project; works on
// .NET Framework 4.x, Mono and .NET 6+). The library is looked up as "SF_TCh": SF_TCh.dll
// on Windows, libSF_TCh.so on Linux (beside the program or on LD_LIBRARY_PATH).
using System;
using System.Runtime.InteropServices;
using System.Text;
using System.Threading;

namespace SfTch
{
    // ------------------------------------------------------------------ constants
    public static class Tc
    {
        public const int SUCCESS = 0, ERROR = -1, BAD_INTR_INDEX = -2, XEXEC = 1, XBREAK = 2;
        public const int MAX_CORES = 3;
        public const int FILE_UNKNOWN = -1;
        public const int RUN_SIMULATION = 10, RUN_TEST = 20, RUN_FORWARD = 30;
        public const int RESET_MARK_START_ONLY = 1;
        public const int STATUS_COMPILED = -1, STATUS_SIMULATION_DONE = -10, STATUS_AT_START = -30,
                         STATUS_STOPPED = -31, STATUS_AT_END = -32, STATUS_INVALID = -1234;
        public const int MFUNC_LATER = 2;
        public const uint CB_ADD_OUTPUT_LOG = 1, CB_SET_STATUS_BAR_TEXT = 2, CB_IS_DEBUG_MODE = 3,
            CB_IS_VERBOSE_MODE = 4, CB_GET_LIB_PATH = 5, CB_GET_TOOL_PATH = 6, CB_GET_SYSTEM_PATH = 7,
            CB_GET_FILE_TIME_STAMP = 10, CB_DO_YIELD = 11, CB_READ_INI_STRING = 12, CB_READ_INI_DOUBLE = 13,
            CB_READ_INI_INT = 14, CB_IS_BREAKPOINT = 17, CB_DISP_AND_LOCATE_ERROR = 18,
            CB_ADD_OUTPUT_LOG_WITH_MSG_BOX = 31, CB_SET_STATUS_BAR_PROGRESS = 32, CB_DRIVER_INITIALIZE = 1001,
            CB_DRIVER_G_FUNC = 1002, CB_DRIVER_M_FUNC = 1003, CB_CONNECT_POINT_CALC_START = 1004,
            CB_CONNECT_POINT_CALC = 1005, CB_CONNECT_POINT_CALC_END = 1006, CB_DRIVER_END = 1007,
            CB_MATH_WARNING = 2001;
    }

    // ------------------------------------------------------------------ structures
    [StructLayout(LayoutKind.Sequential)]
    public struct P10DOUBLE { public double x, y, z, c, b, u, v, w, a, o; }

    /// <summary>Ten int32 flags (4 bytes each: not C# bool).</summary>
    [StructLayout(LayoutKind.Sequential)]
    public struct P10BOOL { public int x, y, z, c, b, u, v, w, a, o; }

    [StructLayout(LayoutKind.Sequential)]
    public struct P26FLOAT
    {
        public float A, B, C, D, E, F, G, H, I, J, K, L, M, N, O, P, Q, R, S, T, U, V, W, X, Y, Z;
    }

    /// <summary>Init's argument: three host texts (HostText.Pointer; kept alive during Init) and the mode.</summary>
    [StructLayout(LayoutKind.Sequential)]
    public struct DLL_INIT_STRUCT
    {
        public IntPtr CNC_Dll_Dir, Macros_Dir, Comm_Int2_Dir;
        public int Local_Core_Mode;
    }

    [StructLayout(LayoutKind.Sequential)]
    public struct SIMPLE_GM_PARAMS
    {
        public P10DOUBLE m_s, m_e, m_calcS, m_calcE, m_zero, m_cc;
        public P26FLOAT m_pars;
        public int m_func, m_planeTool;
        public uint m_reserved, m_editorLine;
        public int m_fileIdx, m_gCodeIndex, m_bFeedIsMin;
        public float m_fp;
    }

    [StructLayout(LayoutKind.Sequential)]
    public struct GM_PARAMS_ENHANCED
    {
        public double m_setFeed, m_calcFeed, m_actFeed, m_relFeed, m_actPartLen, m_actPartRemain,
                      m_actWorkPartsLen, m_actG00PartsLen, m_actPartsLen;
        public int m_nWorkCounter, m_nG00Counter, m_nG00ToWorkChanges, m_nWorkToG00Changes, m_nMCounter;
        public uint m_MasterEditorLine, m_MasterFileIdx;
        public int m_statusCNC;
        public double m_cncRunTime;
    }

    /// <summary>The texts are the library's: read them with Texts.Narrow, never keep the pointers.</summary>
    [StructLayout(LayoutKind.Sequential)]
    public struct CALLBACK_INFO
    {
        public int stringId, nLines, actLine, fileIdx;
        public IntPtr m_fullError, m_errorArguments;
        public string FullError { get { return Texts.Narrow(m_fullError); } }
        public string[] Arguments
        {
            get
            {
                string a = Texts.Narrow(m_errorArguments);
                return a.Length == 0 ? new string[0] : a.Split('\n');
            }
        }
    }

    [StructLayout(LayoutKind.Sequential)]
    public struct GCODE_SIZE { public P10DOUBLE m_startPos, m_endPos, m_minimalPos, m_maximalPos; }

    /// <summary>[0] original, [1] compensated, [2] original rotated, [3] compensated rotated.</summary>
    [StructLayout(LayoutKind.Sequential)]
    public struct GCODE_INFO
    {
        [MarshalAs(UnmanagedType.ByValArray, SizeConst = 4)] public GCODE_SIZE[] m_size;
    }

    [StructLayout(LayoutKind.Sequential)]
    public struct MACHINE_PARAMETERS
    {
        public P10DOUBLE minCoords, maxCoords, refCoords;
        public P10BOOL enableMask;
        public P10DOUBLE backlash, backlashInc;
        public int backlashValuesSource, enhancedInterpolatorParameters;
    }

    [StructLayout(LayoutKind.Sequential)]
    public struct MACHINE_STATUS
    {
        public uint m_axesStatus, m_refDone, m_endSwitches;
        public uint m_reserved1, m_reserved2, m_reserved3, m_reserved4, m_reserved5,
                    m_reserved6, m_reserved7, m_reserved8, m_reserved9, m_reserved10;
    }

    [StructLayout(LayoutKind.Sequential)]
    public struct GCODE_FEED { public double feed, acc, dec; public int rampType, padding1; }

    [StructLayout(LayoutKind.Sequential)]
    public struct GCODE_CORRECTION { public double size; public int gCode, padding1; }

    [StructLayout(LayoutKind.Sequential)]
    public struct ARC_FEED_TABLE { public double m_r, m_relFeed; }

    [StructLayout(LayoutKind.Sequential)]
    public struct INTERNAL_MFUNC_INSERT_TABLE { public int mFunc, padding1; public double relFeed, distance; }

    [StructLayout(LayoutKind.Sequential)]
    public struct AXIS_LIMITS { public double maxFeed, maxAcc, maxDec; }

    /// <summary>A core's G-code properties. Get them first (GetGCodeParameters fills the
    /// arrays), change fields, then set them.</summary>
    [StructLayout(LayoutKind.Sequential)]
    public struct GCODE_PARAMETERS
    {
        public int absMode, swapG2G3;
        public uint correctionStrategy;
        public int forceMode;
        [MarshalAs(UnmanagedType.ByValArray, SizeConst = 8)] public GCODE_FEED[] motion;
        [MarshalAs(UnmanagedType.ByValArray, SizeConst = 8)] public GCODE_CORRECTION[] correction;
        public double maxConnectionDistance, startAngle, endAngle, minAngleFeed;
        public int disableG0FeedOverride, interpolatorConfig0;
        public double overrideInc;
        [MarshalAs(UnmanagedType.ByValArray, SizeConst = 5)] public ARC_FEED_TABLE[] arcFeedTable;
        public double centripetalAcc;
        [MarshalAs(UnmanagedType.ByValArray, SizeConst = 3)] public INTERNAL_MFUNC_INSERT_TABLE[] mFuncInsertTable;
        public int MfuncInsertType, paddingTo8Bytes_2;
        public double reserved;
        public int M02_programEnd1, M30_programEnd2, M03_startSpindleCW, M04_startSpindleCCW, M05_stopSpindle,
                   M06_changeTool, M07_coolOn, M08_oilOn, M09_coolOilOff, M17_return, M29_print, M80_mirrorOff,
                   M81_mirrorX, M82_mirrorY, M83_mirrorZ, M84_mirrorXY, M85_mirrorXZ, M86_mirrorYZ,
                   M87_mirrorXYZ, M99_defFeed;
        public int insertArcMode, paddingTo8Bytes_3;
        public double insertArcToleranceRMax, insertArcToleranceRMin, insertArcMaxAngle, insertArcMinAngle;
        public int insertArcPlane, rezerva1, calcTime, rezerva2;
        public double dynamicG41Correction_mm, dynamicG42Correction_mm;
        [MarshalAs(UnmanagedType.ByValArray, SizeConst = 10)] public AXIS_LIMITS[] axisLimits;
        public double dynamicG41Correction_percent, dynamicG42Correction_percent;
        [MarshalAs(UnmanagedType.ByValArray, SizeConst = 10)] public double[] tolerance;
    }

    // ------------------------------------------------------------------ callbacks
    // userData (intptr_t) is IntPtr; every text is IntPtr (Texts.Host / Texts.Narrow).
    [UnmanagedFunctionPointer(CallingConvention.Cdecl)] public delegate int AddOutputLog(IntPtr user, uint tab, IntPtr text, IntPtr info);
    [UnmanagedFunctionPointer(CallingConvention.Cdecl)] public delegate int SetStatusBarText(IntPtr user, uint pane, IntPtr text, IntPtr info);
    [UnmanagedFunctionPointer(CallingConvention.Cdecl)] public delegate int Query(IntPtr user);                 // 3, 4, 1007
    [UnmanagedFunctionPointer(CallingConvention.Cdecl)] public delegate IntPtr GetPath(IntPtr user);            // 5, 6, 7
    [UnmanagedFunctionPointer(CallingConvention.Cdecl)] public delegate long GetFileTimeStamp(IntPtr user, int fileIdx);
    [UnmanagedFunctionPointer(CallingConvention.Cdecl)] public delegate int DoYield(IntPtr user, int messageOnly);
    [UnmanagedFunctionPointer(CallingConvention.Cdecl)] public delegate void ReadIniString(IntPtr user, IntPtr section, IntPtr key, IntPtr def, IntPtr buf, uint bufChars);
    [UnmanagedFunctionPointer(CallingConvention.Cdecl)] public delegate double ReadIniDouble(IntPtr user, IntPtr section, IntPtr key, double def);
    [UnmanagedFunctionPointer(CallingConvention.Cdecl)] public delegate int ReadIniInt(IntPtr user, IntPtr section, IntPtr key, int def);
    [UnmanagedFunctionPointer(CallingConvention.Cdecl)] public delegate int IsBreakpoint(IntPtr user, uint editorLine, int fileIdx);
    [UnmanagedFunctionPointer(CallingConvention.Cdecl)] public delegate int DispAndLocateError(IntPtr user, uint editorLine, int fileIdx, IntPtr text, IntPtr info);
    [UnmanagedFunctionPointer(CallingConvention.Cdecl)] public delegate int AddOutputLogWithMsgBox(IntPtr user, uint tab, uint buttons, IntPtr text, IntPtr info);
    [UnmanagedFunctionPointer(CallingConvention.Cdecl)] public delegate int SetStatusBarProgress(IntPtr user, uint percent);
    [UnmanagedFunctionPointer(CallingConvention.Cdecl)] public delegate int DriverInitialize(IntPtr user, IntPtr parameters, uint nParams, int runMode);
    [UnmanagedFunctionPointer(CallingConvention.Cdecl)] public delegate int DriverPart(IntPtr user, IntPtr part);   // 1002, 1003: const SIMPLE_GM_PARAMS *
    [UnmanagedFunctionPointer(CallingConvention.Cdecl)] public delegate int ConnectPointCalcStart(IntPtr user, uint nType, uint nCoords, IntPtr coords, uint axesForCalc);
    [UnmanagedFunctionPointer(CallingConvention.Cdecl)] public delegate int ConnectPointCalc(IntPtr user, IntPtr part, IntPtr sqDistance, IntPtr point);
    [UnmanagedFunctionPointer(CallingConvention.Cdecl)] public delegate int ConnectPointCalcEnd(IntPtr user, IntPtr part, IntPtr point);
    [UnmanagedFunctionPointer(CallingConvention.Cdecl)] public delegate int MathWarning(IntPtr user, IntPtr info);
    [UnmanagedFunctionPointer(CallingConvention.Cdecl)] public delegate void LogHook(IntPtr user, uint source, IntPtr text);

    /// <summary>Sets callbacks with their delegates kept, and runs callback bodies guarded.</summary>
    public static class Callbacks
    {
        // every delegate the library may call, by core and callback number; replaced or
        // dropped only after SetCallBack has returned (then no call reaches the old one)
        static readonly Delegate[,] kept = new Delegate[Tc.MAX_CORES, 2002 + 1];
        static readonly object keptLock = new object();
        static int faults;
        static Exception firstFault;

        /// <summary>Exceptions caught in callback bodies so far (each also in FirstFault).</summary>
        public static int Faults { get { return Volatile.Read(ref faults); } }
        public static Exception FirstFault { get { return Volatile.Read(ref firstFault); } }

        /// <summary>Sets callback `number` of `core` to `fn` (null removes it); keeps `fn`.</summary>
        public static int Set(uint core, uint number, Delegate fn, IntPtr user = default(IntPtr))
        {
            if (core >= Tc.MAX_CORES || number > 2002)
                return Tc.ERROR;
            lock (keptLock)
            {
                Delegate old = kept[core, number];
                if (fn != null)
                    kept[core, number] = fn;          // before the library can call it
                IntPtr p = fn == null ? IntPtr.Zero : Marshal.GetFunctionPointerForDelegate(fn);
                int rc = Native.ToolChainCore_SetCallBack(core, number, user, p);
                if (rc != Tc.SUCCESS)
                    kept[core, number] = old;
                else if (fn == null)
                    kept[core, number] = null;        // no call reaches the old one any more
                GC.KeepAlive(old);
                return rc;
            }
        }

        static LogHook keptHook;
        /// <summary>The log hook set, kept while it is.</summary>
        public static LogHook CurrentLogHook { get { return keptHook; } }

        /// <summary>Sets the log hook; keeps `fn` (null removes it).</summary>
        public static int SetLogHook(LogHook fn)
        {
            lock (keptLock)
            {
                if (fn != null) keptHook = fn;
                int rc = Native.ToolChain_SetLogHook(IntPtr.Zero, fn == null ? IntPtr.Zero : Marshal.GetFunctionPointerForDelegate(fn));
                if (rc == Tc.SUCCESS && fn == null) keptHook = null;
                return rc;
            }
        }

        static void Fault(Exception e)
        {
            Interlocked.CompareExchange(ref firstFault, e, null);
            Interlocked.Increment(ref faults);
        }

        /// <summary>Runs `body`; what it throws is counted and `fallback` returned instead.</summary>
        public static T Guard<T>(Func<T> body, T fallback)
        {
            try { return body(); }
            catch (Exception e) { Fault(e); return fallback; }
        }

        public static void Guard(Action body)
        {
            try { body(); }
            catch (Exception e) { Fault(e); }
        }

        // Guarded delegates from plain C# bodies: the texts and structures read for them.
        public static AddOutputLog OutputLog(Action<uint, string, CALLBACK_INFO> body)
        {
            return (user, tab, text, info) => Guard(() => { body(tab, Texts.Host(text), Info(info)); return 0; }, 0);
        }
        public static DispAndLocateError Error(Action<uint, int, string, CALLBACK_INFO> body)
        {
            return (user, line, file, text, info) => Guard(() => { body(line, file, Texts.Host(text), Info(info)); return 0; }, 0);
        }
        public static SetStatusBarProgress Progress(Action<uint> body)
        {
            return (user, percent) => Guard(() => { body(percent); return 0; }, 0);
        }
        public static DriverInitialize Initialize(Func<uint, int, int> body)
        {
            return (user, parameters, n, mode) => Guard(() => body(n, mode), 0);
        }
        /// <summary>1002 and 1003: the part copied; the body's answer (0, or Tc.MFUNC_LATER for 1003).</summary>
        public static DriverPart Part(Func<SIMPLE_GM_PARAMS, int> body)
        {
            return (user, part) => Guard(() => body((SIMPLE_GM_PARAMS)Marshal.PtrToStructure(part, typeof(SIMPLE_GM_PARAMS))), 0);
        }
        public static Query End(Action body)
        {
            return user => Guard(() => { body(); return 0; }, 0);
        }
        public static MathWarning Warning(Action<CALLBACK_INFO> body)
        {
            return (user, info) => Guard(() => { body(Info(info)); return 0; }, 0);
        }

        static CALLBACK_INFO Info(IntPtr p)
        {
            return p == IntPtr.Zero ? new CALLBACK_INFO { stringId = -1, fileIdx = -1 }
                                    : (CALLBACK_INFO)Marshal.PtrToStructure(p, typeof(CALLBACK_INFO));
        }
    }

    // ------------------------------------------------------------------ texts
    public static class Texts
    {
        /// <summary>True on Windows: host texts are UTF-16 there, UTF-8 elsewhere.</summary>
        public static readonly bool Windows = Environment.OSVersion.Platform == PlatformID.Win32NT;

        /// <summary>Narrow texts (TGM_LPCSTR) are UTF-8: always on Linux; on Windows only when
        /// the library's INI says TextsUtf8=1 ([Texts] section): set it to match.</summary>
        public static bool NarrowIsUtf8 = !Windows;

        /// <summary>A TGM_LPCTSTR the library lends or returns, copied (null pointer: "").</summary>
        public static string Host(IntPtr p)
        {
            if (p == IntPtr.Zero) return "";
            return Windows ? Marshal.PtrToStringUni(p) : Utf8(p);
        }

        /// <summary>A TGM_LPCSTR the library lends (CALLBACK_INFO's texts, log lines), copied.</summary>
        public static string Narrow(IntPtr p)
        {
            if (p == IntPtr.Zero) return "";
            return NarrowIsUtf8 ? Utf8(p) : Marshal.PtrToStringAnsi(p);
        }

        static string Utf8(IntPtr p)
        {
            int n = 0;
            while (Marshal.ReadByte(p, n) != 0) n++;
            byte[] bytes = new byte[n];
            Marshal.Copy(p, bytes, 0, n);
            return Encoding.UTF8.GetString(bytes);
        }
    }

    /// <summary>A text for the library, NUL-terminated in unmanaged memory until Dispose:
    /// `using (var name = HostText.Of("demo.nc")) Native.ToolChainCore_CompileFromFile(0, name.Pointer);`</summary>
    public sealed class HostText : IDisposable
    {
        public IntPtr Pointer { get; private set; }

        HostText(IntPtr p) { Pointer = p; }

        /// <summary>TGM_LPCTSTR: UTF-16 on Windows, UTF-8 on Linux.</summary>
        public static HostText Of(string text)
        {
            if (text == null) return new HostText(IntPtr.Zero);
            return Texts.Windows ? new HostText(Marshal.StringToHGlobalUni(text)) : Bytes(Encoding.UTF8.GetBytes(text));
        }

        /// <summary>TGM_LPCSTR: UTF-8 on Linux (and on Windows with NarrowIsUtf8), else the ANSI code page.</summary>
        public static HostText Narrow(string text)
        {
            if (text == null) return new HostText(IntPtr.Zero);
            return Texts.NarrowIsUtf8 ? Bytes(Encoding.UTF8.GetBytes(text)) : new HostText(Marshal.StringToHGlobalAnsi(text));
        }

        static HostText Bytes(byte[] bytes)
        {
            IntPtr p = Marshal.AllocHGlobal(bytes.Length + 1);
            Marshal.Copy(bytes, 0, p, bytes.Length);
            Marshal.WriteByte(p, bytes.Length, 0);
            return new HostText(p);
        }

        public void Dispose()
        {
            if (Pointer != IntPtr.Zero) Marshal.FreeHGlobal(Pointer);
            Pointer = IntPtr.Zero;
        }
    }

    // ------------------------------------------------------------------ the layout check
    public static class Layout
    {
        /// <summary>Marshal.SizeOf of every structure the library measures, in the order of
        /// ToolChainCore_GetStructuresSize; an exception naming the first that differs.</summary>
        public static uint[] Check()
        {
            Type[] order = { typeof(GCODE_PARAMETERS), typeof(SIMPLE_GM_PARAMS), typeof(GM_PARAMS_ENHANCED),
                             typeof(CALLBACK_INFO), typeof(GCODE_INFO), typeof(MACHINE_STATUS),
                             typeof(MACHINE_PARAMETERS), typeof(DLL_INIT_STRUCT) };
            uint[] items = new uint[order.Length + 1];
            Native.ToolChainCore_GetStructuresSize(0, (uint)items.Length, items);
            if (items[0] < order.Length)
                throw new InvalidOperationException("the library measures " + items[0] + " structures, the binding " + order.Length);
            for (int k = 0; k < order.Length; k++)
                if (Marshal.SizeOf(order[k]) != items[k + 1])
                    throw new InvalidOperationException(order[k].Name + ": Marshal.SizeOf " + Marshal.SizeOf(order[k]) +
                                                        ", the library's " + items[k + 1]);
            return items;
        }
    }

    // ------------------------------------------------------------------ the exports
    /// <summary>The exports as the header declares them (cdecl). Texts in: HostText.Pointer;
    /// texts out: IntPtr, read with Texts.Host.</summary>
    public static class Native
    {
        const string Lib = "SF_TCh";     // SF_TCh.dll on Windows, libSF_TCh.so on Linux
        const CallingConvention C = CallingConvention.Cdecl;

        [DllImport(Lib, CallingConvention = C)] public static extern int ToolChainCore_Init(ref DLL_INIT_STRUCT p);
        [DllImport(Lib, CallingConvention = C)] public static extern int ToolChainCore_LoadFromIni(uint core, IntPtr iniFile, out uint maxCores);
        [DllImport(Lib, CallingConvention = C)] public static extern int ToolChainCore_DestroyCNC(uint core);
        [DllImport(Lib, CallingConvention = C)] public static extern IntPtr ToolChainCore_GetVersionString(uint core);
        [DllImport(Lib, CallingConvention = C)] public static extern int ToolChainCore_GetStructuresSize(uint core, uint nItems, [Out] uint[] items);
        [DllImport(Lib, CallingConvention = C)] public static extern int ToolChainCore_SetGCodeParameters(uint core, ref GCODE_PARAMETERS p);
        [DllImport(Lib, CallingConvention = C)] public static extern int ToolChainCore_GetGCodeParameters(uint core, ref GCODE_PARAMETERS p);
        [DllImport(Lib, CallingConvention = C)] public static extern int ToolChainCore_GetMachineParameters(uint core, ref MACHINE_PARAMETERS p);
        [DllImport(Lib, CallingConvention = C)] public static extern int ToolChainCore_SetMachineParameters(uint core, ref MACHINE_PARAMETERS p);
        [DllImport(Lib, CallingConvention = C)] public static extern int ToolChainCore_CompileFromFile(uint core, IntPtr fileName);
        [DllImport(Lib, CallingConvention = C)] public static extern int ToolChainCore_CompileFromMemory(uint core, IntPtr fileName, IntPtr code);
        [DllImport(Lib, CallingConvention = C)] public static extern int ToolChainCore_IsBusy(uint core);
        [DllImport(Lib, CallingConvention = C)] public static extern int ToolChainCore_GetLastError(uint core, out CALLBACK_INFO info);
        [DllImport(Lib, CallingConvention = C)] public static extern int ToolChainCore_GetLastCallError(uint core, out CALLBACK_INFO info);
        [DllImport(Lib, CallingConvention = C)] public static extern int ToolChainCore_FileToIdx(uint core, IntPtr fileName);
        [DllImport(Lib, CallingConvention = C)] public static extern IntPtr ToolChainCore_IdxToFile(uint core, int fileIdx);
        [DllImport(Lib, CallingConvention = C)] public static extern int ToolChainCore_GetGCodeSizeInfo(uint core, ref GCODE_INFO p);
        [DllImport(Lib, CallingConvention = C)] public static extern double ToolChainCore_GetGCodeRunTime(uint core, int fileIdx);
        [DllImport(Lib, CallingConvention = C)] public static extern int ToolChainCore_ResetCNC(uint core, int regime, uint nCoords, double[] coords);
        [DllImport(Lib, CallingConvention = C)] public static extern int ToolChainCore_StartCNCEx(uint core, int regime, IntPtr addCode);
        [DllImport(Lib, CallingConvention = C)] public static extern int ToolChainCore_StopCNCEx(uint core, IntPtr addCode);
        [DllImport(Lib, CallingConvention = C)] public static extern int ToolChainCore_SetRelFeed(uint core, double relFeed);
        [DllImport(Lib, CallingConvention = C)] public static extern int ToolChainCore_StatusCNC(uint core);
        [DllImport(Lib, CallingConvention = C)] public static extern int ToolChainCore_GetPos(uint core, int reserved, out SIMPLE_GM_PARAMS pos, out GM_PARAMS_ENHANCED enh);
        [DllImport(Lib, CallingConvention = C)] public static extern int ToolChainCore_SetCallBack(uint core, uint fceNo, IntPtr userData, IntPtr fn);
        [DllImport(Lib, CallingConvention = C)] public static extern int ToolChainCore_SetLogValue(uint value);
        [DllImport(Lib, CallingConvention = C)] public static extern uint ToolChainCore_GetLogValue();
        [DllImport(Lib, CallingConvention = C)] public static extern void ToolChain_LogANSI(IntPtr text);
        [DllImport(Lib, CallingConvention = C)] public static extern void ToolChain_FlushLogFile();
        [DllImport(Lib, CallingConvention = C)] public static extern int ToolChain_SetLogHook(IntPtr userData, IntPtr fn);
        [DllImport(Lib, CallingConvention = C)] public static extern int ToolChainCore_SetTimeScale(uint core, double scale);
        [DllImport(Lib, CallingConvention = C)] public static extern int ToolChainCore_ConfirmMFunc(uint core);
    }
}
