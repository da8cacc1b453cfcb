"""A Pythonic handle of one CNC core, over the C ABI (the same library state an
HMI sees through ctypes).

    with Core() as core:                       # the first core this process does not use
        core.compile_text("G1 X10 Y10 F1000\\nG2 X20 Y0 I10 J0\\n")
        path = core.toolpath()                 # numpy records, one copy by the library
        run = core.simulate()                  # the parts the driver callbacks receive
        print(len(run), core.size_info(), core.run_time())

A core is the library's, not the object's: :meth:`Core.close` (or leaving the ``with``
block, or the object's end) destroys its program and removes every callback set
through the object, so the next user starts clean.
"""
from __future__ import annotations

import ctypes
import logging
import threading
import time
from dataclasses import dataclass, field
from importlib import resources
from typing import Callable

import numpy as np

from . import abi
from .enums import Callback, OutputTab, Regime, Status
from .errors import CncError, Diagnostic, NoFreeCoreError, _number, locate_column
from .library import load
from .toolpath import Toolpath, fetch

PART_DTYPE = np.dtype(abi.SIMPLE_GM_PARAMS)
LOG = logging.getLogger("sf_tch")
LOG.addHandler(logging.NullHandler())      # the application decides where library output goes

_claimed: set[int] = set()          # cores a Core of this process holds
_claim_lock = threading.Lock()

__all__ = ["Core", "CncError", "RunResult", "PART_DTYPE", "default_ini", "sample_program"]


@dataclass
class RunResult:
    """What a simulation handed to the driver callbacks, in order: motion parts
    (DriverGFunc) and M functions (DriverMFunc) as SIMPLE_GM_PARAMS records, the PRINT
    texts, and the status it ended in. ``len()`` counts the motion parts."""

    parts: np.ndarray
    m_functions: np.ndarray
    printed: list = field(default_factory=list)
    status: int = Status.SIMULATION_DONE

    def __len__(self) -> int:
        return len(self.parts)

    def __repr__(self) -> str:
        return (f"<RunResult {len(self.parts)} motion parts, {len(self.m_functions)} M functions, "
                f"{len(self.printed)} printed, status {Status(self.status).name}>")

    def to_dict(self) -> dict:
        """Counts, printed texts and status as plain types."""
        return {"parts": len(self.parts), "m_functions": len(self.m_functions), "printed": list(self.printed),
                "status": int(self.status)}


class _KeepThreadState:
    """DriverInitialize / DriverEnd handlers that keep a Python thread state on the
    core's worker for the whole run. ctypes gives a foreign thread a new thread
    state for every callback and drops it after (about 25 us each here); holding one
    from the run's first callback to its last makes a part's callback 60 times
    cheaper. The library calls DriverEnd after every run, interrupted ones too."""

    _ensure = ctypes.pythonapi.PyGILState_Ensure
    _ensure.restype = ctypes.c_int
    _release = ctypes.pythonapi.PyGILState_Release
    _release.argtypes = (ctypes.c_int,)

    def __init__(self):
        self._held: list[int] = []
        self.initialize = abi.DriverInitialize(self._on_initialize)
        self.end = abi.DriverEnd(self._on_end)

    def _on_initialize(self, user, params, n_params, run_mode) -> int:
        self._held.append(self._ensure())
        return 0

    def _on_end(self, user) -> int:
        if self._held:
            self._release(self._held.pop())
        return 0


# DriverGFunc / DriverMFunc with the part as a plain address: ctypes then builds no
# pointer object per call
_RAW_PART_CALLBACK = ctypes.CFUNCTYPE(ctypes.c_int32, ctypes.c_ssize_t, ctypes.c_void_p)


class _PartSink:
    """SIMPLE_GM_PARAMS records handed to a driver callback, copied once each into a
    numpy array sized for the whole program (pages never written cost nothing)."""

    SIZE = PART_DTYPE.itemsize

    def __init__(self, capacity: int):
        self._array = np.empty(capacity + 16, PART_DTYPE)     # + addCode's M functions
        self._next = self._base = self._array.ctypes.data
        self._end = self._base + self._array.nbytes

    def add(self, user, part) -> int:
        if self._next == self._end:
            count = len(self._array)
            grown = np.empty(2 * count, PART_DTYPE)
            grown[:count] = self._array
            self._array = grown
            self._base = grown.ctypes.data
            self._next, self._end = self._base + count * self.SIZE, self._base + grown.nbytes
        ctypes.memmove(self._next, part, self.SIZE)
        self._next += self.SIZE
        return 0

    def parts(self) -> np.ndarray:
        return self._array[:(self._next - self._base) // self.SIZE]


def default_ini() -> str:
    """The bundled INI of an offline core (driver callbacks allowed, calcTime on)."""
    return str(resources.files("sf_tch") / "data" / "SF_TCh.ini")


def sample_program() -> str:
    """The bundled sample cutting program (a plate, a slot, four helical holes)."""
    return str(resources.files("sf_tch") / "data" / "demo.nc")


class _Events:
    """The four callbacks every Core sets (output log, progress, warnings, errors)
    and the Python listeners behind them. The ctypes thunks reference this object,
    never the Core: a Core nothing else references is freed at once (its core
    released), not when the garbage collector finds a cycle."""

    def __init__(self, lib: ctypes.CDLL, index: int):
        self.lib = lib
        self.index = index
        self.listeners: dict[int, list[Callable]] = {number: [] for number in (
            Callback.ADD_OUTPUT_LOG, Callback.SET_STATUS_BAR_PROGRESS, Callback.MATH_WARNING,
            Callback.DISP_AND_LOCATE_ERROR)}

    def thunks(self) -> dict[int, object]:
        return {Callback.ADD_OUTPUT_LOG: abi.AddOutputLog(self._on_output),
                Callback.SET_STATUS_BAR_PROGRESS: abi.SetStatusBarProgress(self._on_progress),
                Callback.MATH_WARNING: abi.MathWarning(self._on_warning),
                Callback.DISP_AND_LOCATE_ERROR: abi.DispAndLocateError(self._on_error)}

    def _emit(self, number: int, *args) -> int:
        for fn in list(self.listeners.get(number, ())):
            try:
                fn(*args)
            except Exception:       # a listener's bug must not unwind through the library
                LOG.exception("listener of callback %d failed", number)
        return 0

    def diagnostic(self, severity: str, info, column: int | None = None) -> Diagnostic:
        args = abi.library_text(info.m_errorArguments)
        file = abi.library_text(self.lib.ToolChainCore_IdxToFile(self.index, info.fileIdx))
        return Diagnostic(severity, _number(info.stringId), file, info.actLine, abi.library_text(info.m_fullError),
                          tuple(args.split("\n")) if args else (), column)

    def _on_output(self, user, tab, text, info) -> int:
        line = abi.library_text(text)
        level = logging.ERROR if tab == OutputTab.ERRORS else logging.INFO if tab == OutputTab.PRINT else logging.DEBUG
        LOG.log(level, "core %d: %s", self.index, line)
        return self._emit(Callback.ADD_OUTPUT_LOG, int(tab), line)

    def _on_progress(self, user, percent) -> int:
        return self._emit(Callback.SET_STATUS_BAR_PROGRESS, int(percent))

    def _on_warning(self, user, info) -> int:
        return self._emit(Callback.MATH_WARNING, self.diagnostic("warning", info.contents))

    def _on_error(self, user, line, file_idx, text, info) -> int:
        return self._emit(Callback.DISP_AND_LOCATE_ERROR, self.diagnostic("error", info.contents))


class Core:
    """One core of the library. ``index`` None takes the first core no other
    :class:`Core` of this process holds. Loads the bundled INI (so driver callbacks
    can be set) unless ``ini`` names another. Library output lines (AddOutputLog) go
    to the ``sf_tch`` logger: errors as ERROR, PRINT texts as INFO, the rest DEBUG."""

    closed = False      # True once close() released the core

    def __init__(self, index: int | None = None, ini: str | None = None, timeout: float = 600.0):
        self.lib = load()
        self.timeout = timeout
        self._callbacks: dict[int, object] = {}         # keeps the ctypes thunks alive
        self.index = self._claim(index)
        self._events = _Events(self.lib, self.index)
        try:
            n = ctypes.c_uint32()
            rc = self.lib.ToolChainCore_LoadFromIni(self.index, abi.host_text(str(ini or default_ini())),
                                                   ctypes.byref(n))
            if rc != abi.TOOL_CHAIN_SUCCESS:
                raise self.last_error() or RuntimeError(f"LoadFromIni failed ({rc})")
            self.cores = n.value
            for number, thunk in self._events.thunks().items():
                self.set_callback(number, thunk)
        except BaseException:
            self.close()
            raise

    @staticmethod
    def _claim(index: int | None) -> int:
        with _claim_lock:
            if index is None:
                free = [k for k in range(abi.TOOL_CHAIN_MAX_CORES) if k not in _claimed]
                if not free:
                    raise NoFreeCoreError(f"all {abi.TOOL_CHAIN_MAX_CORES} cores are in use; close a Core or a "
                                          f"Program compiled with keep_core=True")
                index = free[0]
            elif not isinstance(index, int) or not 0 <= index < abi.TOOL_CHAIN_MAX_CORES:
                raise IndexError(f"core {index} does not exist (cores 0..{abi.TOOL_CHAIN_MAX_CORES - 1})")
            elif index in _claimed:
                raise NoFreeCoreError(f"core {index} is in use by another Core or Program (keep_core=True) "
                                      f"of this process")
            _claimed.add(index)
            return index

    def __repr__(self) -> str:
        status = self.status
        state = "closed" if self.closed else getattr(status, "name", str(status))
        return f"<Core {self.index} {state}>"

    # -- context -------------------------------------------------------------
    def __enter__(self) -> Core:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def __del__(self):
        self.close()

    def close(self) -> None:
        """Destroys the core's program and activity and removes every callback set
        through this object; safe twice."""
        if self.closed or not hasattr(self, "index"):
            return
        self.lib.ToolChainCore_DestroyCNC(self.index)
        for number in list(self._callbacks):
            self.lib.ToolChainCore_SetCallBack(self.index, number, 0, None)
        self._callbacks.clear()
        self._events.listeners.clear()
        self.closed = True
        with _claim_lock:
            _claimed.discard(self.index)

    # -- configuration -------------------------------------------------------
    @property
    def params(self) -> abi.GCODE_PARAMETERS:
        """A copy of the core's GCODE_PARAMETERS; assign one to set them."""
        p = abi.GCODE_PARAMETERS()
        self._check(self.lib.ToolChainCore_GetGCodeParameters(self.index, ctypes.byref(p)))
        return p

    @params.setter
    def params(self, p: abi.GCODE_PARAMETERS) -> None:
        self._check(self.lib.ToolChainCore_SetGCodeParameters(self.index, ctypes.byref(p)))

    def update_params(self, **fields) -> None:
        """Changes named fields of GCODE_PARAMETERS, e.g. ``absMode=0``."""
        p = self.params
        for name, value in fields.items():
            if not hasattr(p, name):
                raise AttributeError(f"GCODE_PARAMETERS has no field {name!r}")
            setattr(p, name, value)
        self.params = p

    def set_tool_radius(self, radius: float) -> None:
        """The radius (mm) of every compensation slot G41..G48."""
        p = self.params
        for k in range(8):
            p.correction[k].size = radius
        self.params = p

    def set_look_ahead(self, parts: int) -> None:
        """Parts the feed planner looks ahead from the next compilation on: 0 the
        vendor's 8, n >= 1, or -1 unlimited (ToolChainCore_SetLookAhead)."""
        if parts < -1:
            raise ValueError(f"look-ahead must be -1 (unlimited), 0 (the vendor's 8) or more parts, not {parts}")
        self._check(self.lib.ToolChainCore_SetLookAhead(self.index, parts))

    def set_callback(self, number: int, fn, user_data: int = 0) -> None:
        """Sets a raw callback: ``fn`` must be an instance of the abi prototype for
        that number (None removes it). Replaces the object's own handler of that number."""
        self._check(self.lib.ToolChainCore_SetCallBack(self.index, number, user_data,
                                                       ctypes.cast(fn, ctypes.c_void_p) if fn else None))
        if fn is None:
            self._callbacks.pop(number, None)
        else:
            self._callbacks[number] = fn

    def listen(self, number: Callback, fn: Callable) -> Callable[[], None]:
        """Adds a Python listener of ADD_OUTPUT_LOG ``fn(tab, text)``,
        SET_STATUS_BAR_PROGRESS ``fn(percent)``, MATH_WARNING or DISP_AND_LOCATE_ERROR
        ``fn(Diagnostic)``; called from the library's thread. Returns the remover."""
        listeners = self._events.listeners[Callback(number)]
        listeners.append(fn)
        return lambda: listeners.remove(fn) if fn in listeners else None

    # -- compilation ---------------------------------------------------------
    @property
    def status(self) -> Status:
        """The core's status (StatusCNC)."""
        value = self.lib.ToolChainCore_StatusCNC(self.index)
        try:
            return Status(value)
        except ValueError:
            return value

    def wait(self, timeout: float | None = None, cancel=None) -> Status:
        """Polls until the core is idle and returns the status. ``cancel`` (an object
        with ``is_set()``, e.g. threading.Event) interrupts the work when set; Ctrl-C
        interrupts it too (and is raised once the core is idle)."""
        deadline = time.monotonic() + (timeout or self.timeout)
        try:
            while self.lib.ToolChainCore_IsBusy(self.index) > 0:
                if cancel is not None and cancel.is_set():
                    self.cancel()
                if time.monotonic() > deadline:
                    raise TimeoutError(f"core {self.index} still busy (status {self.status})")
                time.sleep(0.002)
        except KeyboardInterrupt:
            self.cancel()
            while self.lib.ToolChainCore_IsBusy(self.index) > 0:
                time.sleep(0.002)
            raise
        return self.status

    def cancel(self) -> None:
        """Interrupts a compilation or run (ResetCNC marking the start only)."""
        self.lib.ToolChainCore_ResetCNC(self.index, 1, 0, None)

    def start_compile_text(self, code: str | bytes, name: str = "program.nc") -> None:
        """Starts compiling G-code text (a str is sent as UTF-8, bytes as they are) in
        the core's thread and returns at once."""
        data = code if isinstance(code, bytes) else code.encode()
        self._check(self.lib.ToolChainCore_CompileFromMemory(self.index, abi.host_text(name), data))

    def start_compile_file(self, path) -> None:
        """Starts compiling a file in the core's thread and returns at once."""
        self._check(self.lib.ToolChainCore_CompileFromFile(self.index, abi.host_text(str(path))))

    def compile_text(self, code: str | bytes, name: str = "program.nc") -> None:
        """Compiles G-code text; raises :class:`CncError` on the first error."""
        self.start_compile_text(code, name)
        self._finish()

    def compile_file(self, path) -> None:
        """Compiles a file; raises :class:`CncError` on the first error."""
        self.start_compile_file(path)
        self._finish()

    def _finish(self) -> None:
        self.wait()
        error = self.last_error()
        if error is not None:
            raise error

    def last_error(self, refused_call: bool = False) -> CncError | None:
        """The error of the core's last compilation or run (GetLastError), or with
        refused_call the error of the last call the library refused
        (GetLastCallError); None when there is none."""
        info = abi.CALLBACK_INFO()
        read = self.lib.ToolChainCore_GetLastCallError if refused_call else self.lib.ToolChainCore_GetLastError
        if read(self.index, ctypes.byref(info)) != 1:
            return None
        column = ctypes.c_int32(0)      # kept beside the text (ToolChainCore_GetLastErrorColumn)
        self.lib.ToolChainCore_GetLastErrorColumn(self.index, int(refused_call), ctypes.byref(column))
        return CncError.from_diagnostic(self._events.diagnostic("error", info, column.value or None))

    def file_name(self, index: int) -> str:
        """IdxToFile: the name of a file index (special names for -1..-4)."""
        return abi.library_text(self.lib.ToolChainCore_IdxToFile(self.index, index))

    def file_index(self, name: str) -> int:
        """FileToIdx: the index of a file name (a new name gets the next index)."""
        return self.lib.ToolChainCore_FileToIdx(self.index, abi.host_text(name))

    # -- results -------------------------------------------------------------
    def toolpath(self) -> Toolpath:
        """The compiled program's parts as numpy records (one copy by the library,
        ToolChainCore_GetToolpath), with the names of their files."""
        records = fetch(self.lib, self.index)
        indexes = np.unique(records["file_index"]) if len(records) else ()
        return Toolpath(records, {int(k): self.file_name(int(k)) for k in indexes})

    def size_info(self) -> abi.GCODE_INFO:
        """GetGCodeSizeInfo: [0] programmed, [1] compensated, [2]/[3] rotated extents."""
        info = abi.GCODE_INFO()
        self._check(self.lib.ToolChainCore_GetGCodeSizeInfo(self.index, ctypes.byref(info)))
        return info

    def run_time(self, file_index: int | None = None) -> float:
        """Seconds estimated by the last simulation with calcTime (negative: unknown)."""
        if file_index is None:
            pos = abi.GM_PARAMS_ENHANCED()
            self.lib.ToolChainCore_GetPos(self.index, 0, None, ctypes.byref(pos))
            return pos.m_cncRunTime
        return self.lib.ToolChainCore_GetGCodeRunTime(self.index, file_index)

    def position(self) -> tuple:
        """GetPos: (SIMPLE_GM_PARAMS, GM_PARAMS_ENHANCED)."""
        pos, enh = abi.SIMPLE_GM_PARAMS(), abi.GM_PARAMS_ENHANCED()
        self._check(self.lib.ToolChainCore_GetPos(self.index, 0, ctypes.byref(pos), ctypes.byref(enh)))
        return pos, enh

    # -- running -------------------------------------------------------------
    def reset(self, coords=None) -> None:
        """ResetCNC with the first len(coords) machine coordinates (none: keep them)."""
        values = list(coords or [])
        array = (ctypes.c_double * max(1, len(values)))(*values)
        self._check(self.lib.ToolChainCore_ResetCNC(self.index, 0, len(values), array))

    def run(self, regime: Regime = Regime.SIMULATION, add_code: str | None = None, cancel=None) -> Status:
        """ResetCNC keeping the position, StartCNCEx(regime) and wait; raises the
        run's error (e.g. a machine limit of the test regime)."""
        self.lib.ToolChainCore_ResetCNC(self.index, 1, 0, None)
        self._check(self.lib.ToolChainCore_StartCNCEx(self.index, regime, add_code.encode() if add_code else None))
        status = self.wait(cancel=cancel)
        error = self.last_error()
        if error is not None:
            raise error
        return status

    # -- the offline machine (regimes 30-33) ----------------------------------
    def start(self, regime: Regime = Regime.FORWARD, add_code: str | None = None) -> None:
        """StartCNCEx without waiting: the offline machine runs (30 forward, 31 without
        M functions, 32 backward, 33 skipping the first M functions) from where it
        stands -- the program's start after :meth:`reset`, the stop point after
        :meth:`stop`. Poll :attr:`status` and :meth:`position`, or :meth:`wait`."""
        self._check(self.lib.ToolChainCore_StartCNCEx(self.index, regime, add_code.encode() if add_code else None))

    def stop(self, add_code: str | None = None) -> None:
        """StopCNCEx: a controlled stop on the path (motion[6].dec); the status reads
        -31 once the machine stands (:meth:`wait`)."""
        self._check(self.lib.ToolChainCore_StopCNCEx(self.index, add_code.encode() if add_code else None))

    def set_time_scale(self, scale: float) -> None:
        """How many times faster than real time the offline machine runs (0, 1e6]."""
        self._check(self.lib.ToolChainCore_SetTimeScale(self.index, float(scale)))

    def set_override(self, relative_feed: float) -> None:
        """SetRelFeed: the feed override 0.01..2.0 (1 % .. 200 %), approached by overrideInc per 100 us."""
        self._check(self.lib.ToolChainCore_SetRelFeed(self.index, float(relative_feed)))

    def set_breakpoint(self, line: int, file_index: int | None = None) -> None:
        """SetBreakpoint: the machine stops (-31) before the first part of that line
        (file: the main program's by default); line 0 clears it."""
        if file_index is None:
            _, enh = self.position()
            file_index = enh.m_MasterFileIdx
        self._check(self.lib.ToolChainCore_SetBreakpoint(self.index, line, file_index))

    def confirm_m(self) -> None:
        """ConfirmMFunc: ends the waiting M function DriverMFunc answered with
        TC_MFUNC_LATER (2)."""
        self._check(self.lib.ToolChainCore_ConfirmMFunc(self.index))

    def go_to(self, coords) -> None:
        """GoToPosition: a manual linear move (motion[5]) to the first len(coords)
        axes; status 50, then -50 (out of the trajectory)."""
        values = list(coords)
        array = (ctypes.c_double * max(1, len(values)))(*values)
        self._check(self.lib.ToolChainCore_GoToPosition(self.index, len(values), array))

    def simulate(self, regime: Regime = Regime.SIMULATION, add_code: str | None = None) -> RunResult:
        """:meth:`run`, collecting every part handed to the driver callbacks, in order,
        each copied once into a numpy array (one Python call per part: for large
        programs :meth:`toolpath` is the fast way)."""
        total = ctypes.c_uint64()
        self.lib.ToolChainCore_GetToolpath(self.index, None, 0, 0, ctypes.byref(total))
        g_parts, m_parts, printed = _PartSink(total.value), _PartSink(total.value), []

        def on_output(tab, text):
            if tab == OutputTab.PRINT:
                printed.append(text)

        keep = _KeepThreadState()
        self.set_callback(Callback.DRIVER_INITIALIZE, keep.initialize)
        self.set_callback(Callback.DRIVER_END, keep.end)
        self.set_callback(Callback.DRIVER_G_FUNC, _RAW_PART_CALLBACK(g_parts.add))
        self.set_callback(Callback.DRIVER_M_FUNC, _RAW_PART_CALLBACK(m_parts.add))
        remove = self.listen(Callback.ADD_OUTPUT_LOG, on_output)
        try:
            status = self.run(regime, add_code)
        finally:
            remove()
            for number in (Callback.DRIVER_INITIALIZE, Callback.DRIVER_END, Callback.DRIVER_G_FUNC,
                           Callback.DRIVER_M_FUNC):
                self.set_callback(number, None)
        return RunResult(g_parts.parts(), m_parts.parts(), printed, status)

    # -- helpers -------------------------------------------------------------
    def _check(self, rc: int) -> None:
        if rc == abi.TOOL_CHAIN_SUCCESS:
            return
        if rc == abi.TOOL_CHAIN_BAD_INTR_INDEX:
            raise IndexError(f"core {self.index} does not exist")
        raise self.last_error(refused_call=True) or RuntimeError(f"library call failed with {rc}")


def attach_column(diagnostic: Diagnostic, source_lines: list[str] | None) -> Diagnostic:
    """The diagnostic with a column: the library's, else that of its argument in its
    source line, when found."""
    if diagnostic.column:
        return diagnostic
    line = source_lines[diagnostic.line - 1] if source_lines and 1 <= diagnostic.line <= len(source_lines) else None
    column = locate_column(line, diagnostic.number, diagnostic.arguments, diagnostic.text)
    if column is None:
        return diagnostic
    return Diagnostic(diagnostic.severity, diagnostic.number, diagnostic.file, diagnostic.line,
                      diagnostic.text, diagnostic.arguments, column)
