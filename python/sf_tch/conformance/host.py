"""The library under test as a panel sees it: ctypes, the vendor's prototypes, the
platform's text type, and the waits and records a panel needs.

The only platform choice is :func:`is_windows`: on Windows the header's
``TGM_LPCTSTR`` (file names, directories, texts the library returns or hands to a
callback) is UTF-16 ``wchar_t`` (ctypes ``c_wchar_p``, Python ``str``), elsewhere
``char`` (``c_char_p``, bytes). G-code and error texts are ``char`` on both.
"""
from __future__ import annotations

import ctypes
import os
import sys
import threading
import time
from ctypes import POINTER, c_double, c_int32, c_ssize_t, c_uint32, c_void_p

from .. import abi
from .checks import Differs, NotApplicable

CORES = 3
POLL = 0.001          # s between two polls of StatusCNC, as a panel polls


def is_windows(platform: str | None = None) -> bool:
    """Whether the library's TGM_LPCTSTR is UTF-16 (Windows) rather than narrow text."""
    return (platform or sys.platform) == "win32"


def library_file_name(windows: bool) -> str:
    """The vendor's file name of the library on that system."""
    return "SF_TCh.dll" if windows else "libSF_TCh.so"


def default_library() -> str:
    """The library this package ships (or SF_TCH_LIBRARY)."""
    from .. import library_path
    return library_path()


def load(path: str, windows: bool | None = None):
    """(ctypes.CDLL, windows): the library at path with the vendor's prototypes (cdecl,
    ``CDLL`` on both systems) applied to every function it exports."""
    windows = is_windows() if windows is None else windows
    lib = ctypes.CDLL(path)
    _, functions = abi.mirror(windows)
    for name, restype, argtypes in functions:
        try:
            fn = getattr(lib, name)
        except AttributeError:
            continue
        fn.restype, fn.argtypes = restype, argtypes
    return lib


class Texts:
    """Conversions between Python str and the platform's TGM_LPCTSTR."""

    def __init__(self, windows: bool):
        self.windows = windows
        self.type = abi.text_type(windows)

    def arg(self, text: str):
        """A str as a TGM_LPCTSTR argument."""
        return text if self.windows else text.encode()

    def back(self, value) -> str:
        """A TGM_LPCTSTR result (or callback argument) as str; None as ''."""
        return abi.library_text(value)

    def callback_types(self) -> dict:
        """The text-carrying callback prototypes with this platform's text type."""
        info = POINTER(abi.CALLBACK_INFO)
        return {
            abi.CB_ADD_OUTPUT_LOG: ctypes.CFUNCTYPE(c_int32, c_ssize_t, c_uint32, self.type, info),
            abi.CB_SET_STATUS_BAR_TEXT: ctypes.CFUNCTYPE(c_int32, c_ssize_t, c_uint32, self.type, info),
            abi.CB_DISP_AND_LOCATE_ERROR: ctypes.CFUNCTYPE(c_int32, c_ssize_t, c_uint32, c_int32, self.type, info),
        }


def part_dict(part: abi.SIMPLE_GM_PARAMS) -> dict:
    """What the checks compare of a part a callback or GetPos gives."""
    xyz = lambda p: (p.x, p.y, p.z)  # noqa: E731
    return {"func": part.m_func, "s": xyz(part.m_s), "e": xyz(part.m_e), "cs": xyz(part.m_calcS),
            "ce": xyz(part.m_calcE), "cc": (part.m_cc.x, part.m_cc.y, part.m_cc.z), "radius": part.m_cc.c,
            "line": part.m_editorLine, "file": part.m_fileIdx, "index": part.m_gCodeIndex,
            "F": part.m_pars.F, "G": part.m_pars.G, "M": part.m_pars.M, "N": part.m_pars.N,
            "Q": part.m_pars.Q, "H": part.m_pars.H,
            "comp": part.m_bFeedIsMin >> 16, "plane": part.m_planeTool & 0xFFFF}


class Recorder:
    """Every callback of a core, recorded in the order the library calls them:
    ``events`` holds (kind, value) with kind one of init, G, M, end, error, log,
    progress, warning, text, breakpoint. ``m_answer`` is what DriverMFunc answers;
    ``breakpoint`` a function (line, file) -> 0/1 for IsBreakpoint."""

    def __init__(self, host: "Host", core: int = 0, driver: bool = True, m_answer: int = 0, breakpoint=None):
        self.host, self.core = host, core
        self.events: list = []
        self.lock = threading.Lock()
        self.m_answer = m_answer
        self.threads = set()
        types = host.texts.callback_types()
        fns = {
            abi.CB_ADD_OUTPUT_LOG: types[abi.CB_ADD_OUTPUT_LOG](
                lambda u, tab, text, info: self._add("log", (tab & 0xFF, host.texts.back(text))) or 0),
            abi.CB_SET_STATUS_BAR_TEXT: types[abi.CB_SET_STATUS_BAR_TEXT](
                lambda u, pane, text, info: self._add("text", host.texts.back(text)) or 0),
            abi.CB_DISP_AND_LOCATE_ERROR: types[abi.CB_DISP_AND_LOCATE_ERROR](
                lambda u, line, fidx, text, info: self._add("error", (line, fidx, info.contents.stringId
                                                                      if info else None)) or 0),
            abi.CB_SET_STATUS_BAR_PROGRESS: abi.SetStatusBarProgress(lambda u, pct: self._add("progress", pct) or 0),
        }
        if breakpoint is not None:
            fns[abi.CB_IS_BREAKPOINT] = ctypes.CFUNCTYPE(c_int32, c_ssize_t, c_uint32, c_int32)(
                lambda u, line, fidx: int(breakpoint(line, fidx)))
        if driver:
            fns.update({
                abi.CB_DRIVER_INITIALIZE: abi.DriverInitialize(
                    lambda u, p, n, mode: self._add("init", ([p[i] for i in range(n)] if p else [], mode)) or 0),
                abi.CB_DRIVER_G_FUNC: abi.DriverGFunc(lambda u, part: self._add("G", part_dict(part.contents)) or 0),
                abi.CB_DRIVER_M_FUNC: abi.DriverMFunc(self._m),
                abi.CB_DRIVER_END: abi.DriverEnd(lambda u: self._add("end", None) or 0),
                abi.CB_MATH_WARNING: abi.MathWarning(
                    lambda u, info: self._add("warning", (info.contents.stringId, info.contents.actLine)) or 0),
            })
            host.load_ini(core)
        self.fns = fns
        host.installed.append(self)     # the library may call these until the next reset: kept alive
        for number, fn in fns.items():
            rc = host.lib.ToolChainCore_SetCallBack(core, number, 0, ctypes.cast(fn, c_void_p))
            if rc != 0:
                raise Differs(0, rc, f"SetCallBack({number})")

    def _add(self, kind, value):
        self.threads.add(threading.get_ident())
        with self.lock:
            self.events.append((kind, value))

    def _m(self, user, part):
        self._add("M", part_dict(part.contents))
        return self.m_answer

    def of(self, kind) -> list:
        """The values of every event of one kind, in order."""
        with self.lock:
            return [v for k, v in self.events if k == kind]

    def kinds(self) -> list:
        """The kind of every event, in order."""
        with self.lock:
            return [k for k, _ in self.events]


class Host:
    """The library and the state every check starts from (core parameters and
    machine position as in a fresh process, no callbacks)."""

    def __init__(self, path: str, workdir: str, windows: bool | None = None):
        self.windows = is_windows() if windows is None else windows
        self.texts = Texts(self.windows)
        self.path = path
        self.lib = load(path, self.windows)
        self.workdir = workdir
        self.ini_loaded = set()
        self.installed = []             # Recorders whose callbacks a core may still hold
        self.defaults = []
        self.as_written = []
        for core in range(CORES):
            p = abi.GCODE_PARAMETERS()
            self.lib.ToolChainCore_GetGCodeParameters(core, ctypes.byref(p))
            self.defaults.append(p)
            q = abi.GCODE_PARAMETERS.from_buffer_copy(bytes(p))
            q.tolerance[2] = 0.0
            self.as_written.append(q)

    # -- what the library has
    def has(self, name: str) -> bool:
        """Whether the library exports name."""
        return hasattr(self.lib, name)

    def need(self, name: str):
        """The export `name`, or NotApplicable (an extension this library lacks)."""
        if not self.has(name):
            raise NotApplicable(f"the library does not export {name}")
        return getattr(self.lib, name)

    # -- state between checks
    def reset(self) -> None:
        """Every core as in a fresh process: destroyed, no callbacks, its first parameters
        but tolerance[2] 0 (collinear lines are joined by the vendor's default; the checks
        compile their programs as written, the join has checks of its own), override 1,
        no user parameters, prefix, postfix or breakpoint, the machine at the origin."""
        lib = self.lib
        for core in range(CORES):
            lib.ToolChainCore_DestroyCNC(core)
            for number in abi.CALLBACK_NUMBERS:
                lib.ToolChainCore_SetCallBack(core, number, 0, None)
            lib.ToolChainCore_SetGCodeParameters(core, ctypes.byref(self.as_written[core]))
            lib.ToolChainCore_SetRelFeed(core, 1.0)
            lib.ToolChainCore_SetUserParams(core, None, 0)
            lib.ToolChainCore_GCodePrefixPostfix(core, None, None)
            lib.ToolChainCore_SetBreakpoint(core, 0, -1)        # no part has line 0: no breakpoint
            lib.ToolChainCore_ResetCNC(core, 0, 10, (c_double * 10)())
            lib.ToolChainCore_DestroyCNC(core)
        self.installed.clear()          # every callback removed above: nothing calls them any more

    def file(self, name: str, data) -> str:
        """Writes a file into the work directory; its absolute path."""
        path = os.path.join(self.workdir, name)
        with open(path, "wb") as f:
            f.write(data.encode() if isinstance(data, str) else data)
        return path

    def load_ini(self, core: int = 0, extra: str = "") -> None:
        """LoadFromIni with the vendor's module names (driver callbacks need it)."""
        if core in self.ini_loaded and not extra:
            return
        path = self.file(f"core{core}.ini", "[Modules]\nCompiler0=SF_DComp\nExecutor0=SF_Exec\n"
                                            "[CNC]\nDriver=SF_RTDrv\n" + extra)
        cores = c_uint32(0)
        kept = self.params(core)              # what the check set so far stays
        rc = self.lib.ToolChainCore_LoadFromIni(core, self.texts.arg(path), ctypes.byref(cores))
        if rc != 0:
            raise Differs(0, rc, "LoadFromIni of a vendor INI")
        self.ini_loaded.add(core)
        self.lib.ToolChainCore_SetGCodeParameters(core, ctypes.byref(kept))

    # -- parameters
    def params(self, core: int = 0) -> abi.GCODE_PARAMETERS:
        """GetGCodeParameters of the core."""
        p = abi.GCODE_PARAMETERS()
        rc = self.lib.ToolChainCore_GetGCodeParameters(core, ctypes.byref(p))
        if rc != 0:
            raise Differs(0, rc, "GetGCodeParameters")
        return p

    def set_params(self, core: int = 0, edit=None, **fields) -> None:
        """GetGCodeParameters, the fields (and edit(p)), SetGCodeParameters."""
        p = self.params(core)
        for name, value in fields.items():
            setattr(p, name, value)
        if edit:
            edit(p)
        rc = self.lib.ToolChainCore_SetGCodeParameters(core, ctypes.byref(p))
        if rc != 0:
            raise Differs(0, rc, f"SetGCodeParameters({fields})")

    # -- waiting like a panel
    def status(self, core: int = 0) -> int:
        """StatusCNC of the core."""
        return self.lib.ToolChainCore_StatusCNC(core)

    def wait(self, core: int, accept, timeout: float = 5.0, what: str = "") -> int:
        """Polls StatusCNC until accept(status) (a predicate or a collection); Differs
        when the time bound passes first."""
        test = accept if callable(accept) else (lambda s: s in accept)
        deadline = time.monotonic() + timeout
        while True:
            s = self.status(core)
            if test(s):
                return s
            if time.monotonic() > deadline:
                raise Differs(what or "the status to change", s, f"status after {timeout:g} s")
            time.sleep(POLL)

    def pos(self, core: int = 0):
        """(SIMPLE_GM_PARAMS, GM_PARAMS_ENHANCED) of GetPos."""
        part, enh = abi.SIMPLE_GM_PARAMS(), abi.GM_PARAMS_ENHANCED()
        rc = self.lib.ToolChainCore_GetPos(core, 0, ctypes.byref(part), ctypes.byref(enh))
        if rc != 0:
            raise Differs(0, rc, "GetPos")
        return part, enh

    # -- compiling
    def compile(self, code: str, core: int = 0, name: str = "prog.nc", timeout: float = 10.0):
        """Compiles text, waits for -1; the error (number, line, file index, text,
        arguments) or None."""
        rc = self.lib.ToolChainCore_CompileFromMemory(core, self.texts.arg(name), code.encode())
        if rc != 0:
            raise Differs(0, rc, "CompileFromMemory")
        s = self.wait(core, lambda s: s != 1, timeout, "the compilation to end")
        if s != -1:
            raise Differs(-1, s, "status after a compilation")
        return self.last_error(core)

    def compiled(self, code: str, core: int = 0, **kw) -> None:
        """Compiles text that must compile."""
        err = self.compile(code, core, **kw)
        if err is not None:
            raise Differs("no error", err[:2], "compiling")

    def last_error(self, core: int = 0):
        """GetLastError: (number, line, file index, text, arguments) or None."""
        info = abi.CALLBACK_INFO()
        rc = self.lib.ToolChainCore_GetLastError(core, ctypes.byref(info))
        if rc == 0:
            return None
        if rc != 1:
            raise Differs("0 or 1", rc, "GetLastError")
        return (info.stringId, info.actLine, info.fileIdx, (info.m_fullError or b"").decode(errors="replace"),
                (info.m_errorArguments or b"").decode(errors="replace"))

    # -- running
    def reset_cnc(self, core: int = 0, coords=None) -> None:
        """ResetCNC: coordinates (x, y, z, ...) or only the program start mark."""
        if coords is None:
            rc = self.lib.ToolChainCore_ResetCNC(core, 1, 0, None)
        else:
            arr = (c_double * 10)(*coords)
            rc = self.lib.ToolChainCore_ResetCNC(core, 0, len(coords), arr)
        if rc != 0:
            raise Differs(0, rc, "ResetCNC")

    def start(self, core: int, regime: int, add: bytes | None = None) -> None:
        """StartCNCEx, which must accept."""
        rc = self.lib.ToolChainCore_StartCNCEx(core, regime, add)
        if rc != 0:
            raise Differs(0, rc, f"StartCNCEx({regime}) in status {self.status(core)}")

    def simulate(self, code: str, core: int = 0, regime: int = 10, coords=(0.0, 0.0, 0.0), rec=None,
                 **params) -> "Recorder":
        """Compiles code with params from coords, runs a simulation with a Recorder,
        waits for its end (-10 / -20); the Recorder."""
        if params:
            self.set_params(core, **params)
        self.reset_cnc(core, coords)
        self.compiled(code, core)
        rec = rec or Recorder(self, core)
        self.reset_cnc(core)
        self.start(core, regime)
        self.wait(core, lambda s: s not in (regime,), 10.0, "the simulation to end")
        return rec

    def machine(self, code: str, core: int = 0, coords=(0.0, 0.0, 0.0), rec=None, **params):
        """Compiles code from coords and puts the machine at the program start (-30)."""
        if params:
            self.set_params(core, **params)
        self.reset_cnc(core, coords)
        self.compiled(code, core)
        self.reset_cnc(core, coords)
        s = self.status(core)
        if s != -30:
            raise Differs(-30, s, "status after ResetCNC with a program")
        return rec

