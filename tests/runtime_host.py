"""A host of the core runtime for the runtime and stress tests: what an HMI does
through bare ctypes (load the INI, compile, simulate with driver callbacks, poll),
written to be imported by the subprocess that each of those tests runs in, since a
defect of the runtime may crash or hang the process.

``script(body)`` builds such a subprocess's source: ``faulthandler`` dumps every
thread's stack and exits if the body hangs, ``lib``, ``abi`` and this module's names
are predefined, and every core is destroyed at exit as a host ends (its threads
joined: ThreadSanitizer reports a thread that nobody joined)."""
import ctypes
import os
import signal
import tempfile
import textwrap
import threading
import time
from pathlib import Path

import pytest

from sf_tch import abi, library

TESTS_DIR = str(Path(__file__).resolve().parent)

# A square of four parts: the program every "core usable afterwards" check runs.
SQUARE = b"G1 X10 F1000\nG1 Y10\nG1 X0\nG1 Y0\nM30\n"
SQUARE_END = (0.0, 0.0)

# Sanitized libraries run several times slower (tests/test_sanitizers.py sets it).
TIME_SCALE = float(os.environ.get("SF_TCH_TIME_SCALE", "1"))


def run_script(run_python, body: str, seconds: float, what: str = "subprocess") -> str:
    """Runs body (see script) in a fresh interpreter; its stdout, or the test fails
    with how the process ended (signal, exit status, hang) and its output."""
    hang_after = seconds * TIME_SCALE
    proc = run_python(script(body, hang_after), timeout=hang_after + 30, check=False)
    if proc.returncode != 0:
        how = (f"killed by {signal.Signals(-proc.returncode).name}" if proc.returncode < 0
               else f"exit status {proc.returncode}")
        pytest.fail(f"{what} {how}\n--- stdout\n{proc.stdout[-4000:]}\n--- stderr\n{proc.stderr[-8000:]}",
                    pytrace=False)
    return proc.stdout


def script(body: str, hang_after: float) -> str:
    """Source of a subprocess running body; after hang_after seconds every thread's
    Python stack is printed and the process exits with status 1 (a hang reported as
    a failure, not a pytest timeout)."""
    return (f"import sys\nsys.path.insert(0, {TESTS_DIR!r})\n"
            "import atexit, faulthandler\nfaulthandler.enable()\n"
            f"faulthandler.dump_traceback_later({hang_after!r}, exit=True)\n"
            "from runtime_host import *\n"
            "lib = load(LIB_PATH)\n"
            "atexit.register(destroy_all, lib)\n" + textwrap.dedent(body))


def load(path):
    return library.load(path)


def destroy_all(lib) -> None:
    for core in range(abi.TOOL_CHAIN_MAX_CORES):
        lib.ToolChainCore_DestroyCNC(core)


def thread_count() -> int:
    return len(os.listdir("/proc/self/task"))


def assert_threads_back(base: int, what: str = "before") -> None:
    """The process has base threads again. A thread that was just joined may still be
    leaving the kernel (its /proc entry outlives the join by microseconds): polled
    for up to a second before failing."""
    deadline = time.monotonic() + 1.0
    while thread_count() != base and time.monotonic() < deadline:
        time.sleep(0.005)
    assert thread_count() == base, f"{thread_count()} threads, {base} {what}"


def vm_size_kb() -> int:
    with open("/proc/self/status") as status:
        for line in status:
            if line.startswith("VmSize:"):
                return int(line.split()[1])
    raise RuntimeError("no VmSize in /proc/self/status")


def load_ini(lib, core: int) -> None:
    """LoadFromIni with a driver: the driver callbacks (> 1000) need it."""
    ini = Path(tempfile.mkdtemp()) / f"core{core}.ini"
    ini.write_text("[Modules]\nCompiler0=SF_DComp\n[CNC]\nDriver=SF_RTDrv\n")
    assert lib.ToolChainCore_LoadFromIni(core, str(ini).encode(), None) == 0


def set_params(lib, core: int, **fields) -> None:
    params = abi.GCODE_PARAMETERS()
    assert lib.ToolChainCore_GetGCodeParameters(core, ctypes.byref(params)) == 0
    for name, value in fields.items():
        setattr(params, name, value)
    assert lib.ToolChainCore_SetGCodeParameters(core, ctypes.byref(params)) == 0


def wait_status(lib, core: int, accept, timeout: float = 10.0) -> int:
    """Polls StatusCNC until accept(status) (a predicate or a tuple of statuses)."""
    test = accept if callable(accept) else (lambda s: s in accept)
    deadline = time.monotonic() + timeout
    while True:
        status = lib.ToolChainCore_StatusCNC(core)
        if test(status):
            return status
        if time.monotonic() > deadline:
            raise AssertionError(f"core {core}: status stuck at {status}")
        time.sleep(0.0005)


def last_error(lib, core: int):
    """(stringId, line, text) of GetLastError, or None."""
    info = abi.CALLBACK_INFO()
    rc = lib.ToolChainCore_GetLastError(core, ctypes.byref(info))
    assert rc in (0, 1), rc
    return None if rc == 0 else (info.stringId, info.actLine, (info.m_fullError or b"").decode())


def last_call_error(lib, core: int):
    """(stringId, text) of ToolChainCore_GetLastCallError (the last refused call), or None."""
    fn = getattr(lib, "ToolChainCore_GetLastCallError", None)
    assert fn is not None, "the library does not export ToolChainCore_GetLastCallError"
    fn.restype, fn.argtypes = ctypes.c_int32, (ctypes.c_uint32, ctypes.POINTER(abi.CALLBACK_INFO))
    info = abi.CALLBACK_INFO()
    rc = fn(core, ctypes.byref(info))
    assert rc in (0, 1), rc
    return None if rc == 0 else (info.stringId, (info.m_fullError or b"").decode())


def compile_wait(lib, core: int, code: bytes, name: bytes = b"prog.nc", timeout: float = 20.0):
    """Compiles and waits for the end; the GetLastError triple or None."""
    rc = lib.ToolChainCore_CompileFromMemory(core, name, code)
    assert rc == 0, f"CompileFromMemory -> {rc} in status {lib.ToolChainCore_StatusCNC(core)}"
    status = wait_status(lib, core, lambda s: s != 1, timeout)
    assert status == -1, f"compilation ended in status {status}"
    return last_error(lib, core)


class Driver:
    """Driver callbacks (1002 G, 1003 M) recording every part; hook(kind, part) runs
    inside the callback (a test's re-entrant call). Keeps its ctypes thunks alive."""

    def __init__(self, lib, core: int, hook=None):
        self.lib, self.core, self.hook = lib, core, hook
        self.parts = []           # (kind, editor line, file index, start xyz, end xyz)
        self.threads = set()
        self.g = abi.DriverGFunc(lambda user, part: self._on("G", part))
        self.m = abi.DriverMFunc(lambda user, part: self._on("M", part))

    def _on(self, kind, part_ptr):
        part = part_ptr.contents
        self.threads.add(threading.get_native_id())
        self.parts.append((kind, part.m_editorLine, part.m_fileIdx,
                           (part.m_s.x, part.m_s.y, part.m_s.z), (part.m_e.x, part.m_e.y, part.m_e.z)))
        if self.hook is not None:
            self.hook(kind, part)
        return 0

    def install(self):
        set_callback(self.lib, self.core, abi.CB_DRIVER_G_FUNC, self.g)
        set_callback(self.lib, self.core, abi.CB_DRIVER_M_FUNC, self.m)
        return self

    def remove(self):
        set_callback(self.lib, self.core, abi.CB_DRIVER_G_FUNC, None)
        set_callback(self.lib, self.core, abi.CB_DRIVER_M_FUNC, None)

    @property
    def g_parts(self):
        return [p for p in self.parts if p[0] == "G"]


def set_callback(lib, core: int, number: int, fn, user: int = 0) -> None:
    pointer = None if fn is None else ctypes.cast(fn, ctypes.c_void_p)
    assert lib.ToolChainCore_SetCallBack(core, number, user, pointer) == 0


def start(lib, core: int, regime: int = abi.RUN_SIMULATION) -> None:
    """Marks the program start (the machine position unchanged) and starts a run."""
    assert lib.ToolChainCore_ResetCNC(core, 1, 0, None) == 0
    rc = lib.ToolChainCore_StartCNCEx(core, regime, None)
    assert rc == 0, f"StartCNCEx({regime}) -> {rc} in status {lib.ToolChainCore_StatusCNC(core)}"


def simulate(lib, core: int, regime: int = abi.RUN_SIMULATION, timeout: float = 20.0):
    """Runs the compiled program with a recording driver; (final status, Driver)."""
    driver = Driver(lib, core).install()
    start(lib, core, regime)
    status = wait_status(lib, core, lambda s: s not in (regime, 1), timeout)
    driver.remove()
    return status, driver


def reset_to(lib, core: int, *xyz: float) -> None:
    """ResetCNC regime 0: the machine position (x, y, z, 0...)."""
    coords = (ctypes.c_double * 10)(*xyz, *([0.0] * (10 - len(xyz))))
    assert lib.ToolChainCore_ResetCNC(core, 0, 10, coords) == 0


def check_usable(lib, core: int) -> None:
    """The core compiles and simulates the square: four G parts from the origin
    back to it, one worker thread, status -10."""
    reset_to(lib, core, 0.0, 0.0, 0.0)
    assert compile_wait(lib, core, SQUARE, b"square.nc") is None
    status, driver = simulate(lib, core)
    assert status == -10, f"core {core}: simulation of the square ended in status {status}"
    g = driver.g_parts
    assert len(g) == 4, f"core {core}: {len(g)} G parts of the square, 4 expected: {driver.parts}"
    assert [p[4][:2] for p in g] == [(10.0, 0.0), (10.0, 10.0), (0.0, 10.0), SQUARE_END], g
    assert len(driver.threads) == 1, driver.threads


def lines_program(n: int, seed: int = 0) -> bytes:
    """n G1 lines (one part each) inside a 50 x 70 box."""
    return b"".join(b"G1 X%d Y%d F6000\n" % ((i * 7 + seed) % 50, (i * 13 + seed) % 70) for i in range(n))
