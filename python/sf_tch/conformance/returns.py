"""Return codes and statuses of the exports and their transitions (docs/api.md)."""
import ctypes
from ctypes import c_double, c_uint32

from .. import abi
from .checks import Differs, check, expect

A = "api.md"
GOOD = "G1 X10 Y0 F1000\nG1 X10 Y10\nG1 X0 Y10\n"


@check("returns", "callback_driver_before_ini", A, "Callbacks",
       "SetCallBack refuses a number above 1000 before LoadFromIni (-1)")
def _(host):
    if 1 in host.ini_loaded:
        raise Differs("core 1 without LoadFromIni", "loaded", "the check's order")
    fn = abi.DriverEnd(lambda u: 0)
    expect(-1, host.lib.ToolChainCore_SetCallBack(1, abi.CB_DRIVER_END, 0, ctypes.cast(fn, ctypes.c_void_p)),
           "SetCallBack(1007) before LoadFromIni")


@check("returns", "callback_unknown_number", A, "Callbacks",
       "SetCallBack returns -1 for an unknown callback number, -2 for a bad core")
def _(host):
    fn = abi.DriverEnd(lambda u: 0)
    expect(-1, host.lib.ToolChainCore_SetCallBack(0, 999, 0, ctypes.cast(fn, ctypes.c_void_p)), "number 999")
    expect(-2, host.lib.ToolChainCore_SetCallBack(3, 1, 0, None), "core 3")


@check("returns", "load_ini", A, "Lifecycle",
       "LoadFromIni loads a vendor INI, returns 0 and writes the number of cores (3)")
def _(host):
    path = host.file("vendor.ini", "[Modules]\nCompiler0=SF_DComp\n[CNC]\nDriver=SF_RTDrv\n")
    n = c_uint32(0)
    expect(0, host.lib.ToolChainCore_LoadFromIni(2, host.texts.arg(path), ctypes.byref(n)), "LoadFromIni")
    expect(3, n.value, "*pnMaxCores")


@check("returns", "load_ini_missing", A, "Lifecycle",
       "LoadFromIni of a missing file returns 1 (XEXEC) and reports the reason (DispAndLocateError)")
def _(host):
    from .host import Recorder
    rec = Recorder(host, 2, driver=False)
    n = c_uint32(0)
    rc = host.lib.ToolChainCore_LoadFromIni(2, host.texts.arg(host.workdir + "/missing.ini"), ctypes.byref(n))
    expect(abi.TOOL_CHAIN_XEXEC, rc, "LoadFromIni")
    if not rec.of("error"):
        raise Differs("an error through DispAndLocateError", rec.kinds(), "callbacks")


@check("returns", "bad_core", A, "Conventions",
       "a core index outside 0 … 2 returns -2 (StatusCNC -1234, GetVersionString an empty text)")
def _(host):
    lib, p = host.lib, abi.GCODE_PARAMETERS()
    expect(-1234, lib.ToolChainCore_StatusCNC(3), "StatusCNC(3)")
    expect(-2, lib.ToolChainCore_DestroyCNC(3), "DestroyCNC(3)")
    expect(-2, lib.ToolChainCore_GetGCodeParameters(7, ctypes.byref(p)), "GetGCodeParameters(7)")
    expect(-2, lib.ToolChainCore_IsBusy(3), "IsBusy(3)")
    expect("", host.texts.back(lib.ToolChainCore_GetVersionString(3)), "GetVersionString(3)")


@check("returns", "null_pointer", A, "Conventions",
       "a NULL pointer where a structure is needed returns -1")
def _(host):
    lib = host.lib
    expect(-1, lib.ToolChainCore_GetGCodeParameters(0, None), "GetGCodeParameters(NULL)")
    expect(-1, lib.ToolChainCore_SetGCodeParameters(0, None), "SetGCodeParameters(NULL)")
    expect(-1, lib.ToolChainCore_GetMachineParameters(0, None), "GetMachineParameters(NULL)")
    expect(-1, lib.ToolChainCore_GetGCodeSizeInfo(0, None), "GetGCodeSizeInfo(NULL)")


@check("returns", "version", A, "Lifecycle", "GetVersionString gives the version and build date: a text")
def _(host):
    text = host.texts.back(host.lib.ToolChainCore_GetVersionString(0))
    if not text.strip():
        raise Differs("a version text", text, "GetVersionString(0)")


@check("returns", "fresh_status", A, "cnc_status", "a core with nothing loaded is at status 0 and not busy")
def _(host):
    expect((0, 0), (host.status(0), host.lib.ToolChainCore_IsBusy(0)), "(StatusCNC, IsBusy)")


@check("returns", "compile_status", A, "Compilation",
       "when CompileFromMemory returns 0 the status reads 1 or -1, then -1; GetLastError 0 after success")
def _(host):
    rc = host.lib.ToolChainCore_CompileFromMemory(0, host.texts.arg("a.nc"), GOOD.encode())
    s = host.status(0)
    expect(0, rc, "CompileFromMemory")
    if s not in (1, -1):
        raise Differs("1 or -1", s, "status right after CompileFromMemory")
    expect(-1, host.wait(0, lambda s: s != 1), "status at the end")
    expect(None, host.last_error(0), "GetLastError")
    expect(0, host.lib.ToolChainCore_IsBusy(0), "IsBusy")


@check("returns", "compile_failed_status", A, "cnc_status",
       "a failed compilation also ends at -1, and GetLastError returns 1")
def _(host):
    err = host.compile("G2 X10 Y0\n")
    expect(-1, host.status(0), "status")
    if err is None:
        raise Differs("an error", None, "GetLastError")


@check("returns", "compile_from_file", A, "Compilation",
       "CompileFromFile compiles a file; a missing file is an error")
def _(host):
    path = host.file("file.nc", GOOD)
    expect(0, host.lib.ToolChainCore_CompileFromFile(0, host.texts.arg(path)), "CompileFromFile")
    host.wait(0, lambda s: s != 1)
    expect(None, host.last_error(0), "GetLastError of a good file")
    rc = host.lib.ToolChainCore_CompileFromFile(0, host.texts.arg(host.workdir + "/missing.nc"))
    if rc == 0:
        host.wait(0, lambda s: s != 1)
    if rc == 0 and host.last_error(0) is None:
        raise Differs("an error", None, "GetLastError of a missing file")


@check("returns", "file_index_names", A, "Compilation",
       "FileToIdx / IdxToFile: __unknown__ -1, __end__ -2, __stop__ -3, __exec__ -4; an unknown index "
       "gives __unknown__")
def _(host):
    lib = host.lib
    for name, idx in (("__unknown__", -1), ("__end__", -2), ("__stop__", -3), ("__exec__", -4)):
        expect(idx, lib.ToolChainCore_FileToIdx(0, host.texts.arg(name)), f"FileToIdx({name})")
        expect(name, host.texts.back(lib.ToolChainCore_IdxToFile(0, idx)), f"IdxToFile({idx})")
    expect("__unknown__", host.texts.back(lib.ToolChainCore_IdxToFile(0, 12345)), "IdxToFile(12345)")


@check("returns", "file_index_round_trip", A, "Compilation",
       "the name given to CompileFromMemory gets a file index, IdxToFile names it; ToolChain_IdxToFile is core 0's")
def _(host):
    host.compiled(GOOD, name="named.nc")
    idx = host.lib.ToolChainCore_FileToIdx(0, host.texts.arg("named.nc"))
    if idx < 0:
        raise Differs("an index >= 0", idx, "FileToIdx(named.nc)")
    expect("named.nc", host.texts.back(host.lib.ToolChainCore_IdxToFile(0, idx)), "IdxToFile")
    expect("named.nc", host.texts.back(host.lib.ToolChain_IdxToFile(idx)), "ToolChain_IdxToFile")


@check("returns", "stop_when_idle", A, "How the status moves",
       "StopCNCEx is accepted only while something runs: -1 when nothing does")
def _(host):
    expect(-1, host.lib.ToolChainCore_StopCNCEx(0, None), "StopCNCEx at 0")
    host.compiled(GOOD)
    expect(-1, host.lib.ToolChainCore_StopCNCEx(0, None), "StopCNCEx at -1")


@check("returns", "reset_status", A, "Running",
       "ResetStatusCNC only in a negative status: mode 0 gives 0, mode 1 gives -50")
def _(host):
    expect(-1, host.lib.ToolChainCore_ResetStatusCNC(0, 0), "ResetStatusCNC at 0")
    host.compiled(GOOD)
    expect(0, host.lib.ToolChainCore_ResetStatusCNC(0, 1), "ResetStatusCNC(1) at -1")
    expect(-50, host.status(0), "status")
    expect(0, host.lib.ToolChainCore_ResetStatusCNC(0, 0), "ResetStatusCNC(0) at -50")
    expect(0, host.status(0), "status")


@check("returns", "reset_cnc_program", A, "Running", "ResetCNC gives -30 when a program is compiled")
def _(host):
    host.compiled(GOOD)
    host.reset_cnc(0, (0.0, 0.0, 0.0))
    expect(-30, host.status(0), "status after ResetCNC")


@check("returns", "destroy", A, "Lifecycle", "DestroyCNC gives 0 from any status and is safe twice")
def _(host):
    host.compiled(GOOD)
    host.reset_cnc(0)
    expect(0, host.lib.ToolChainCore_DestroyCNC(0), "DestroyCNC")
    expect(0, host.status(0), "status")
    expect(0, host.lib.ToolChainCore_DestroyCNC(0), "DestroyCNC again")


@check("returns", "start_without_program", A, "How the status moves",
       "StartCNCEx with nothing loaded is refused (-1) and the status stays 0")
def _(host):
    expect(-1, host.lib.ToolChainCore_StartCNCEx(0, 10, None), "StartCNCEx(10) at 0")
    expect(0, host.status(0), "status")


@check("returns", "simulation_path", A, "How the status moves",
       "-1 -StartCNCEx 10-> 10 -> -10; -1 -StartCNCEx 20-> 20 -> -20")
def _(host):
    for regime in (10, 20):
        host.compiled(GOOD)
        host.start(0, regime)
        expect(-regime, host.wait(0, lambda s: s != regime), f"status after regime {regime}")


@check("returns", "simulation_again", A, "How the status moves",
       "a finished simulation (-10) may be started again after ResetCNC")
def _(host):
    host.compiled(GOOD)
    host.start(0, 10)
    host.wait(0, lambda s: s != 10)
    host.reset_cnc(0)
    host.start(0, 10)
    expect(-10, host.wait(0, lambda s: s != 10), "status")


@check("returns", "user_params", A, "Parameters",
       "SetUserParams: n = 100 sets P00 … P99 for the next compilations, n = 0 clears, another n is -1")
def _(host):
    values = (c_double * 100)(*[float(i) for i in range(100)])
    expect(-1, host.lib.ToolChainCore_SetUserParams(0, values, 5), "n = 5")
    expect(0, host.lib.ToolChainCore_SetUserParams(0, values, 100), "n = 100")
    rec = host.simulate("G1 X P7 F1000\n")
    g = rec.of("G")
    expect(7.0, g[0]["e"][0] if g else None, "X P7 with P7 preset to 7")
    expect(0, host.lib.ToolChainCore_SetUserParams(0, None, 0), "n = 0")


@check("returns", "set_params_refused_while_running", A, "How the status moves",
       "SetGCodeParameters is refused while anything runs")
def _(host):
    host.machine("G1 X50 F600\n")
    host.start(0, 30)
    host.wait(0, (30,), 2.0, "running")
    p = host.params(0)
    p.absMode = 0
    rc = host.lib.ToolChainCore_SetGCodeParameters(0, ctypes.byref(p))
    host.lib.ToolChainCore_StopCNCEx(0, None)
    expect(-1, rc, "SetGCodeParameters while running (30)")


@check("returns", "run_time_store", A, "Compilation",
       "GetGCodeRunTime is negative when unknown; SetGCodeRunTime stores a time the host gives")
def _(host):
    host.compiled(GOOD, name="time.nc")
    idx = host.lib.ToolChainCore_FileToIdx(0, host.texts.arg("time.nc"))
    t = host.lib.ToolChainCore_GetGCodeRunTime(0, idx)
    if not t < 0:
        raise Differs("a negative time", t, "GetGCodeRunTime before a timed simulation")
    expect(0, host.lib.ToolChainCore_SetGCodeRunTime(0, idx, 12.5), "SetGCodeRunTime")
    expect(12.5, host.lib.ToolChainCore_GetGCodeRunTime(0, idx), "GetGCodeRunTime")


@check("returns", "log_value", A, "Logging", "SetLogValue returns 0 and GetLogValue reads the mask back")
def _(host):
    old = host.lib.ToolChainCore_GetLogValue()
    try:
        expect(0, host.lib.ToolChainCore_SetLogValue(0x2), "SetLogValue")
        expect(0x2, host.lib.ToolChainCore_GetLogValue(), "GetLogValue")
    finally:
        host.lib.ToolChainCore_SetLogValue(old)


@check("returns", "size_info", A, "Compilation",
       "GetGCodeSizeInfo gives the compiled program's start, end, minimum and maximum")
def _(host):
    host.reset_cnc(0, (0.0, 0.0, 0.0))
    host.compiled("G1 X10 Y-5 F1000\nG1 X-3 Y20\n")
    info = abi.GCODE_INFO()
    expect(0, host.lib.ToolChainCore_GetGCodeSizeInfo(0, ctypes.byref(info)), "GetGCodeSizeInfo")
    s = info.m_size[0]
    got = [(v.x, v.y) for v in (s.m_startPos, s.m_endPos, s.m_minimalPos, s.m_maximalPos)]
    expect([(0, 0), (-3, 20), (-3, -5), (10, 20)], [(round(x, 9), round(y, 9)) for x, y in got],
           "start, end, min, max of [0]")


@check("returns", "init", A, "Lifecycle",
       "Init stores the directories and Local_Core_Mode of a DLL_INIT_STRUCT: 0; NULL is -1")
def _(host):
    structures, _ = abi.mirror(host.windows)
    init = structures["DLL_INIT_STRUCT"]()
    for name in ("CNC_Dll_Dir", "Macros_Dir", "Comm_Int2_Dir"):
        setattr(init, name, host.texts.arg(host.workdir))
    init.Local_Core_Mode = 2
    expect(-1, host.lib.ToolChainCore_Init(None), "Init(NULL)")
    expect(0, host.lib.ToolChainCore_Init(ctypes.byref(init)), "Init(offline, the work directory)")


@check("returns", "machine_parameters", A, "Parameters",
       "SetMachineParameters / GetMachineParameters: the soft limits, reference point and backlash read back as set")
def _(host):
    m = abi.MACHINE_PARAMETERS()
    expect(0, host.lib.ToolChainCore_GetMachineParameters(0, ctypes.byref(m)), "GetMachineParameters")
    old = abi.MACHINE_PARAMETERS.from_buffer_copy(m)
    m.minCoords.x, m.maxCoords.y, m.refCoords.z, m.enableMask.c, m.backlash.x = -12.5, 250.0, 3.0, 1, 0.01
    try:
        expect(0, host.lib.ToolChainCore_SetMachineParameters(0, ctypes.byref(m)), "SetMachineParameters")
        got = abi.MACHINE_PARAMETERS()
        host.lib.ToolChainCore_GetMachineParameters(0, ctypes.byref(got))
        expect(bytes(m), bytes(got), "the structure read back")
    finally:
        host.lib.ToolChainCore_SetMachineParameters(0, ctypes.byref(old))


@check("returns", "getpos_pointers", A, "Positions and status",
       "GetPos takes either pointer NULL, not both (-1)")
def _(host):
    part, enh = abi.SIMPLE_GM_PARAMS(), abi.GM_PARAMS_ENHANCED()
    expect(-1, host.lib.ToolChainCore_GetPos(0, 0, None, None), "GetPos(NULL, NULL)")
    expect(0, host.lib.ToolChainCore_GetPos(0, 0, ctypes.byref(part), None), "GetPos(part, NULL)")
    expect(0, host.lib.ToolChainCore_GetPos(0, 0, None, ctypes.byref(enh)), "GetPos(NULL, enhanced)")


def _running(host):
    """A long move on the offline machine, running (30)."""
    host.machine("G1 X500 Y0 Z0 F600\n")
    host.start(0, 30)
    host.wait(0, (30,), 2.0, "running")


@check("returns", "busy_while_running", A, "Compilation", "IsBusy is 1 while the machine moves")
def _(host):
    _running(host)
    busy = host.lib.ToolChainCore_IsBusy(0)
    host.lib.ToolChainCore_StopCNCEx(0, None)
    expect(1, busy, "IsBusy during 30")


@check("returns", "refused_while_running", A, "How the status moves",
       "while the machine moves, StartCNCEx, Compile*, GoToPosition, MFunc and ResetStatusCNC are refused (-1) "
       "and the status stays 30")
def _(host):
    _running(host)
    lib = host.lib
    fun = abi.SIMPLE_GM_PARAMS()
    fun.m_func = 60
    got = {"StartCNCEx(30)": lib.ToolChainCore_StartCNCEx(0, 30, None),
           "CompileFromMemory": lib.ToolChainCore_CompileFromMemory(0, host.texts.arg("x.nc"), b"G1 X1\n"),
           "GoToPosition": lib.ToolChainCore_GoToPosition(0, 1, (c_double * 1)(5.0)),
           "MFunc": lib.ToolChainCore_MFunc(0, ctypes.byref(fun), 0),
           "ResetStatusCNC(0)": lib.ToolChainCore_ResetStatusCNC(0, 0)}
    status = host.status(0)
    lib.ToolChainCore_StopCNCEx(0, None)
    expect({k: -1 for k in got}, got, "return codes")
    expect(30, status, "status afterwards")


@check("returns", "start_bad_regime", A, "Regimes of StartCNCEx",
       "StartCNCEx with a regime that is not 10, 20 or 30–33 is refused (-1)")
def _(host):
    host.compiled(GOOD)
    expect(-1, host.lib.ToolChainCore_StartCNCEx(0, 99, None), "StartCNCEx(99)")
    expect(-1, host.status(0), "status")


@check("returns", "connect_bad_state_after", A, "Connect types of ConnectCNCEx_Plane",
       "ConnectCNCEx_Plane: a stateAfter other than 0 or 2 is -1")
def _(host):
    host.machine(GOOD)
    coords = (c_double * 2)(1.0, 1.0)
    expect(-1, host.lib.ToolChainCore_ConnectCNCEx_Plane(0, 0, 2, coords, None, 0, 0, 5), "stateAfter 5")


@check("returns", "prefix_postfix", A, "Parameters",
       "GCodePrefixPostfix: G-code compiled before and after every main program")
def _(host):
    expect(0, host.lib.ToolChainCore_GCodePrefixPostfix(0, b"G1 X1 Y0 F1000\n", b"G1 X3 Y0\n"),
           "GCodePrefixPostfix")
    rec = host.simulate("G1 X2 Y0 F1000\n")
    kinds = sorted(set(rec.kinds()))        # said when it differs: what the run did instead
    expect([1.0, 2.0, 3.0], [round(p["e"][0], 9) for p in rec.of("G")],
           f"X of the parts (the run's events: {', '.join(kinds) or 'none'}; status {host.status(0)})")
