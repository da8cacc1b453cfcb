"""The status machine (toolchain/runtime/transitions.pyx) checked as a table against
the vendor's text (docs/api.md): every status a core can reach today (the offline machine's too), every command, the status that follows
or the refusal. The expected table is written from that text, not read from the
library; each cell is driven through the exported functions. A running status is
held by a callback that waits on a gate; an ending command opens the gate from a
timer (it returns only once the worker is joined)."""
import ctypes
import threading
import time

import pytest

from sf_tch import abi, default_ini

CORE = 2
GOOD = b"G1 X10 Y0 F1000\nG1 X10 Y10\nG1 X0 Y10\n"
BAD = b"G2 X10 Y0\n"                  # an arc without a centre: the compilation fails
PAUSED = b"G1 X10 Y0 F1000\nM0\nG1 X10 Y10\n"   # the offline machine pauses at M0 (-33)
FAST, REAL = 1000.0, 1.0               # time scales of the offline machine
INI = default_ini().encode()         # the bundled INI, wherever SF_TCH_LIBRARY points
REFUSED = "refused"


def wait_status(lib, predicate, timeout=10.0):
    deadline = time.monotonic() + timeout
    while not predicate(lib.ToolChainCore_StatusCNC(CORE)):
        assert time.monotonic() < deadline, f"status stuck at {lib.ToolChainCore_StatusCNC(CORE)}"
        time.sleep(0.001)
    return lib.ToolChainCore_StatusCNC(CORE)


class Gate:
    """Callbacks that hold the core's worker until the gate opens; an M function
    answered "later" holds the machine's start (70) or stop (80) until it opens."""

    def __init__(self, lib):
        self.lib = lib
        self.event = threading.Event()
        self.progress = abi.SetStatusBarProgress(lambda user, percent: self.event.wait(10) and 0)
        self.driver = abi.DriverGFunc(lambda user, part: self.event.wait(10) and 0)
        self.later = abi.DriverMFunc(lambda user, part: abi.TC_MFUNC_LATER)

    def hold(self, what):
        self.event.clear()
        number, fn = {"compile": (abi.CB_SET_STATUS_BAR_PROGRESS, self.progress),
                      "run": (abi.CB_DRIVER_G_FUNC, self.driver),
                      "m": (abi.CB_DRIVER_M_FUNC, self.later)}[what]
        assert self.lib.ToolChainCore_SetCallBack(CORE, number, 0, ctypes.cast(fn, ctypes.c_void_p)) == 0

    def open(self):
        self.event.set()
        for number in (abi.CB_SET_STATUS_BAR_PROGRESS, abi.CB_DRIVER_G_FUNC, abi.CB_DRIVER_M_FUNC):
            self.lib.ToolChainCore_SetCallBack(CORE, number, 0, None)
        self.lib.ToolChainCore_ConfirmMFunc(CORE)


def compile_(lib, code=GOOD):
    assert lib.ToolChainCore_CompileFromMemory(CORE, b"t.nc", code) == 0
    return wait_status(lib, lambda s: s != 1)


def reach(lib, gate, status):
    """Drives the core to `status` (a running status is held by the gate)."""
    lib.ToolChainCore_DestroyCNC(CORE)
    assert lib.ToolChainCore_SetTimeScale(CORE, FAST) == 0
    if status == 0:
        return
    if status == 1:
        gate.hold("compile")
        assert lib.ToolChainCore_CompileFromMemory(CORE, b"t.nc", GOOD) == 0
        return
    compile_(lib, BAD if status == "-1 failed" else PAUSED if status == -33 else GOOD)
    if status in (-1, "-1 failed"):
        return
    if status in (70, 80):
        # the offline machine sending the start's (70) or the stop's (80) M functions,
        # held there by an M7 answered "later"
        gate.hold("m")
        assert lib.ToolChainCore_SetTimeScale(CORE, REAL) == 0
        assert lib.ToolChainCore_StartCNCEx(CORE, 30, b"M7" if status == 70 else None) == 0
        if status == 80:
            assert lib.ToolChainCore_StopCNCEx(CORE, b"M7") == 0
        wait_status(lib, lambda s: s == status)
        assert lib.ToolChainCore_SetTimeScale(CORE, FAST) == 0
        return
    if status in (30, -31, -32, -33):
        # the offline machine: 30 held by the gate (its notifier waits in DriverGFunc
        # while the machine moves on in real time), -31 stopped at once in real time
        if status in (30, -31):
            assert lib.ToolChainCore_SetTimeScale(CORE, REAL) == 0
        if status == 30:
            gate.hold("run")
        assert lib.ToolChainCore_StartCNCEx(CORE, 30, None) == 0
        if status == -31:
            assert lib.ToolChainCore_StopCNCEx(CORE, None) == 0
        if status != 30:
            wait_status(lib, lambda s: s <= 0)
            assert lib.ToolChainCore_SetTimeScale(CORE, FAST) == 0
    elif status == -30:
        assert lib.ToolChainCore_ResetCNC(CORE, 1, 0, None) == 0
    elif status == -50:
        assert lib.ToolChainCore_ResetStatusCNC(CORE, 1) == 0
    else:
        regime = 10 if status in (10, -10, -11) else 20
        if status in (10, 20, -11, -21):
            gate.hold("run")
        assert lib.ToolChainCore_StartCNCEx(CORE, regime, None) == 0
        if status in (-11, -21):
            assert lib.ToolChainCore_StopCNCEx(CORE, None) == 0
            gate.open()
        if status not in (10, 20):
            wait_status(lib, lambda s: s <= 0)
    assert lib.ToolChainCore_StatusCNC(CORE) == (-1 if status == "-1 failed" else status)


def params(lib):
    p = abi.GCODE_PARAMETERS()
    assert lib.ToolChainCore_GetGCodeParameters(CORE, ctypes.byref(p)) == 0
    return ctypes.byref(p)


# command -> call; "ends" marks the calls that end the activity (they wait for the join)
COMMANDS = {
    "compile": (lambda lib: lib.ToolChainCore_CompileFromMemory(CORE, b"u.nc", GOOD), False),
    "simulate": (lambda lib: lib.ToolChainCore_StartCNCEx(CORE, 10, None), False),
    "test": (lambda lib: lib.ToolChainCore_StartCNCEx(CORE, 20, None), False),
    "stop": (lambda lib: lib.ToolChainCore_StopCNCEx(CORE, None), False),
    "reset": (lambda lib: lib.ToolChainCore_ResetCNC(CORE, 1, 0, None), True),
    "destroy": (lambda lib: lib.ToolChainCore_DestroyCNC(CORE), True),
    "drop": (lambda lib: lib.ToolChainCore_ResetStatusCNC(CORE, 0), True),
    "out": (lambda lib: lib.ToolChainCore_ResetStatusCNC(CORE, 1), True),
    "params": (lambda lib: lib.ToolChainCore_SetGCodeParameters(CORE, params(lib)), False),
    "ini": (lambda lib: lib.ToolChainCore_LoadFromIni(CORE, INI, None), False),
    "prefix": (lambda lib: lib.ToolChainCore_GCodePrefixPostfix(CORE, None, None), False),
    "fwd": (lambda lib: lib.ToolChainCore_StartCNCEx(CORE, 30, None), False),
    "no_m": (lambda lib: lib.ToolChainCore_StartCNCEx(CORE, 31, None), False),
    "back": (lambda lib: lib.ToolChainCore_StartCNCEx(CORE, 32, None), False),
    "skip_m": (lambda lib: lib.ToolChainCore_StartCNCEx(CORE, 33, None), False),
}

# The vendor's text: what follows each command in each status (1 / 10 / 20 / 30 are held
# running; "stop" in a run: the run ends stopped once the gate opens; a started
# compilation or run is awaited). The machine's regimes (StartCNCEx 30-33): forward
# from a compiled program or a stop (-1, -10, -11, -20, -21, -30, -31, -33) to the
# program's end (-32); backward only along a path run before (-31, -32, -33), back to
# the program's start (-30); nothing without a program, out of the trajectory (-50)
# or at the end (-32, forward). Sending the start's or the stop's M functions (70, 80,
# held by one the driver confirms later): a stop ends it standing on the trajectory.
R = REFUSED
EXPECTED = {
    #            compile sim  test stop reset destroy drop out  params ini prefix fwd  no_m back skip_m
    0:          (-1,     R,   R,   R,   0,    0,      R,   R,   0,     0,  0,     R,   R,   R,   R),
    1:          (R,      R,   R,   R,   -1,   0,      R,   R,   R,     R,  R,     R,   R,   R,   R),
    -1:         (-1,     -10, -20, R,   -30,  0,      0,   -50, -1,    -1, -1,    -32, -32, R,   -32),
    "-1 failed": (-1,    R,   R,   R,   -1,   0,      0,   -50, -1,    -1, -1,    R,   R,   R,   R),
    10:         (R,      R,   R,   -11, -30,  0,      R,   R,   R,     R,  10,    R,   R,   R,   R),
    -10:        (-1,     -10, -20, R,   -30,  0,      0,   -50, -10,   -10, -10,  -32, -32, R,   -32),
    -11:        (-1,     -10, -20, R,   -30,  0,      0,   -50, -11,   -11, -11,  -32, -32, R,   -32),
    20:         (R,      R,   R,   -21, -30,  0,      R,   R,   R,     R,  20,    R,   R,   R,   R),
    -20:        (-1,     -10, -20, R,   -30,  0,      0,   -50, -20,   -20, -20,  -32, -32, R,   -32),
    -21:        (-1,     -10, -20, R,   -30,  0,      0,   -50, -21,   -21, -21,  -32, -32, R,   -32),
    -30:        (-1,     -10, -20, R,   -30,  0,      0,   -50, -30,   -30, -30,  -32, -32, R,   -32),
    -50:        (-1,     -10, -20, R,   -30,  0,      0,   -50, -50,   -50, -50,  R,   R,   R,   R),
    30:         (R,      R,   R,   -31, -30,  0,      R,   R,   R,     R,  30,    R,   R,   R,   R),
    70:         (R,      R,   R,   -31, -30,  0,      R,   R,   R,     R,  70,    R,   R,   R,   R),
    80:         (R,      R,   R,   -31, -30,  0,      R,   R,   R,     R,  80,    R,   R,   R,   R),
    -31:        (-1,     -10, -20, R,   -30,  0,      0,   -50, -31,   -31, -31,  -32, -32, -30, -32),
    -32:        (-1,     -10, -20, R,   -30,  0,      0,   -50, -32,   -32, -32,  R,   R,   -30, R),
    -33:        (-1,     -10, -20, R,   -30,  0,      0,   -50, -33,   -33, -33,  -32, -32, -30, -32),
}


@pytest.mark.parametrize("status", list(EXPECTED), ids=str)
def test_status_table(fresh_core, status):
    lib = fresh_core
    gate = Gate(lib)
    assert lib.ToolChainCore_LoadFromIni(CORE, INI, None) == 0
    try:
        for (name, (call, ends)), expected in zip(COMMANDS.items(), EXPECTED[status]):
            reach(lib, gate, status)
            timer = threading.Timer(0.1, gate.event.set) if ends else None
            if timer:
                timer.start()
            rc = call(lib)
            if timer:
                timer.join()
            cell = f"status {status}, {name}"
            if expected == REFUSED:
                assert rc == -1, cell
                info = abi.CALLBACK_INFO()
                assert lib.ToolChainCore_GetLastCallError(CORE, ctypes.byref(info)) == 1, cell
                assert b"?" not in info.m_fullError, cell
            else:
                assert rc == 0, cell
                if name == "stop":
                    gate.open()
                if lib.ToolChainCore_StatusCNC(CORE) > 0 and not (name == "prefix" and status in (10, 20, 30, 70, 80)):
                    gate.open()
                    wait_status(lib, lambda s: s <= 0)
                if status in (10, 20, 30, 70, 80) and name == "prefix":
                    assert lib.ToolChainCore_StatusCNC(CORE) == expected, cell
                    continue
                assert lib.ToolChainCore_StatusCNC(CORE) == expected, cell
            gate.open()
            wait_status(lib, lambda s: s <= 0)
    finally:
        gate.open()
        lib.ToolChainCore_DestroyCNC(CORE)
        lib.ToolChainCore_SetTimeScale(CORE, REAL)
        lib.ToolChainCore_ResetCNC(CORE, 0, 10, (ctypes.c_double * 10)())   # the machine's runs moved it


def test_a_refused_call_keeps_the_compile_error_and_names_the_status(fresh_core):
    """GetLastError reports the activity's error; a refused call goes to
    GetLastCallError with the status' number and name."""
    lib = fresh_core
    assert compile_(lib) == -1
    assert lib.ToolChainCore_StopCNCEx(CORE, None) == -1
    info = abi.CALLBACK_INFO()
    assert lib.ToolChainCore_GetLastError(CORE, ctypes.byref(info)) == 0
    assert lib.ToolChainCore_GetLastCallError(CORE, ctypes.byref(info)) == 1
    assert info.m_fullError == b"StopCNCEx not allowed in status -1 (compilation finished)"
    assert compile_(lib, BAD) == -1
    assert lib.ToolChainCore_StopCNCEx(CORE, None) == -1
    assert lib.ToolChainCore_GetLastError(CORE, ctypes.byref(info)) == 1
    assert info.stringId == 402 and info.actLine == 1
