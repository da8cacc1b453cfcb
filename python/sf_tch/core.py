"""A Pythonic handle of one CNC core, over the C ABI (the same library state an
HMI sees through ctypes).

    with Core(0) as core:
        core.compile_text("G1 X10 Y10 F1000\\nG2 X20 Y0 I10 J0\\n")
        parts = core.simulate()          # numpy structured array of SIMPLE_GM_PARAMS
        print(core.size_info()[0], core.run_time())
"""
import ctypes
import time
from dataclasses import dataclass
from importlib import resources

import numpy as np

from . import abi
from .library import load

PART_DTYPE = np.dtype(abi.SIMPLE_GM_PARAMS)


@dataclass(eq=False)
class CncError(Exception):
    """An error the library reported (GetLastError). Not frozen: Python sets the
    traceback of an exception as it propagates (a `with` block among others)."""

    number: int
    line: int
    file: str
    text: str
    arguments: tuple

    def __str__(self):
        return f"{self.file}:{self.line}: error {self.number}: {self.text}"


@dataclass
class RunResult:
    parts: np.ndarray          # motion parts (DriverGFunc), SIMPLE_GM_PARAMS records
    m_functions: np.ndarray    # M functions (DriverMFunc)
    printed: list              # PRINT / M29 texts (AddOutputLog tab 2)
    status: int


def default_ini() -> str:
    return str(resources.files("sf_tch") / "data" / "SF_TCh.ini")


def sample_program() -> str:
    return str(resources.files("sf_tch") / "data" / "demo.nc")


class Core:
    """One core of the library. Loads the default INI (so driver callbacks can be
    set) unless ``ini`` says otherwise."""

    def __init__(self, index: int = 0, ini: str | None = None, timeout: float = 600.0):
        self.lib = load()
        self.index = index
        self.timeout = timeout
        self._callbacks = {}            # keeps the ctypes thunks alive
        n = ctypes.c_uint32()
        rc = self.lib.ToolChainCore_LoadFromIni(index, (ini or default_ini()).encode(), ctypes.byref(n))
        if rc == abi.TOOL_CHAIN_BAD_INTR_INDEX:
            raise IndexError(f"core {index} does not exist")
        if rc != abi.TOOL_CHAIN_SUCCESS:
            raise self.last_error() or RuntimeError(f"LoadFromIni failed ({rc})")
        self.cores = n.value

    # -- context -------------------------------------------------------------
    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def close(self):
        self.lib.ToolChainCore_DestroyCNC(self.index)
        for number in list(self._callbacks):
            self.set_callback(number, None)

    # -- configuration -------------------------------------------------------
    @property
    def params(self) -> abi.GCODE_PARAMETERS:
        p = abi.GCODE_PARAMETERS()
        self._check(self.lib.ToolChainCore_GetGCodeParameters(self.index, ctypes.byref(p)))
        return p

    @params.setter
    def params(self, p: abi.GCODE_PARAMETERS):
        self._check(self.lib.ToolChainCore_SetGCodeParameters(self.index, ctypes.byref(p)))

    def update_params(self, **fields):
        """Changes named fields of GCODE_PARAMETERS, e.g. ``absMode=0``."""
        p = self.params
        for name, value in fields.items():
            setattr(p, name, value)
        self.params = p

    def set_callback(self, number: int, fn, user_data: int = 0):
        """Sets a callback: ``fn`` must be an instance of the abi prototype for
        that number (or None to remove it)."""
        self._check(self.lib.ToolChainCore_SetCallBack(self.index, number, user_data,
                                                       ctypes.cast(fn, ctypes.c_void_p) if fn else None))
        if fn is None:
            self._callbacks.pop(number, None)
        else:
            self._callbacks[number] = fn

    # -- compilation ---------------------------------------------------------
    @property
    def status(self) -> int:
        return self.lib.ToolChainCore_StatusCNC(self.index)

    def wait(self, timeout: float | None = None) -> int:
        """Polls the status until the core is idle; returns the status."""
        deadline = time.monotonic() + (timeout or self.timeout)
        while self.lib.ToolChainCore_IsBusy(self.index) > 0:
            if time.monotonic() > deadline:
                raise TimeoutError(f"core {self.index} still busy (status {self.status})")
            time.sleep(0.002)
        return self.status

    def compile_text(self, code: str, name: str = "program.nc"):
        self._check(self.lib.ToolChainCore_CompileFromMemory(self.index, name.encode(), code.encode()))
        self._finish()

    def compile_file(self, path: str):
        self._check(self.lib.ToolChainCore_CompileFromFile(self.index, str(path).encode()))
        self._finish()

    def _finish(self):
        self.wait()
        error = self.last_error()
        if error is not None:
            raise error

    def last_error(self, refused_call: bool = False) -> CncError | None:
        """The error of the last compilation or run (GetLastError), or with
        refused_call the error of the last call the library refused (GetLastCallError)."""
        info = abi.CALLBACK_INFO()
        read = self.lib.ToolChainCore_GetLastCallError if refused_call else self.lib.ToolChainCore_GetLastError
        if read(self.index, ctypes.byref(info)) != 1:
            return None
        args = (info.m_errorArguments or b"").decode(errors="replace")
        return CncError(info.stringId, info.actLine, self.file_name(info.fileIdx),
                        (info.m_fullError or b"").decode(errors="replace"),
                        tuple(args.split("\n")) if args else ())

    def file_name(self, index: int) -> str:
        return self.lib.ToolChainCore_IdxToFile(self.index, index).decode(errors="replace")

    def file_index(self, name: str) -> int:
        return self.lib.ToolChainCore_FileToIdx(self.index, name.encode())

    # -- running -------------------------------------------------------------
    def reset(self, coords=None):
        values = list(coords or [])
        array = (ctypes.c_double * max(1, len(values)))(*values)
        self._check(self.lib.ToolChainCore_ResetCNC(self.index, 0, len(values), array))

    def simulate(self, regime: int = abi.RUN_SIMULATION, add_code: str | None = None) -> RunResult:
        """ResetCNC keeping the position, StartCNCEx(regime), and every part handed
        to the driver callbacks, in order."""
        g_parts, m_parts, printed = bytearray(), bytearray(), []

        def on_g(user, part):
            g_parts.extend(ctypes.string_at(part, PART_DTYPE.itemsize))
            return 0

        def on_m(user, part):
            m_parts.extend(ctypes.string_at(part, PART_DTYPE.itemsize))
            return 0

        def on_output(user, tab, text, info):
            if tab == 2:
                printed.append((text or b"").decode(errors="replace"))
            return 0

        self.set_callback(abi.CB_DRIVER_G_FUNC, abi.DriverGFunc(on_g))
        self.set_callback(abi.CB_DRIVER_M_FUNC, abi.DriverMFunc(on_m))
        self.set_callback(abi.CB_ADD_OUTPUT_LOG, abi.AddOutputLog(on_output))
        try:
            self.lib.ToolChainCore_ResetCNC(self.index, 1, 0, None)
            self._check(self.lib.ToolChainCore_StartCNCEx(self.index, regime,
                                                          add_code.encode() if add_code else None))
            status = self.wait()
        finally:
            for number in (abi.CB_DRIVER_G_FUNC, abi.CB_DRIVER_M_FUNC, abi.CB_ADD_OUTPUT_LOG):
                self.set_callback(number, None)
        error = self.last_error()
        if error is not None:
            raise error
        return RunResult(np.frombuffer(bytes(g_parts), PART_DTYPE), np.frombuffer(bytes(m_parts), PART_DTYPE),
                         printed, status)

    def size_info(self) -> abi.GCODE_INFO:
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
        pos, enh = abi.SIMPLE_GM_PARAMS(), abi.GM_PARAMS_ENHANCED()
        self._check(self.lib.ToolChainCore_GetPos(self.index, 0, ctypes.byref(pos), ctypes.byref(enh)))
        return pos, enh

    # -- helpers -------------------------------------------------------------
    def _check(self, rc: int):
        if rc == abi.TOOL_CHAIN_SUCCESS:
            return
        error = self.last_error(refused_call=True)
        if rc == abi.TOOL_CHAIN_BAD_INTR_INDEX:
            raise IndexError(f"core {self.index} does not exist")
        raise error or RuntimeError(f"library call failed with {rc}")
