"""Shared fixtures of the test suite.

- ``lib``: the installed libSF_TCh.so loaded once with the typed prototypes of
  ``sf_tch.abi.FUNCTIONS`` (``sf_tch.library.load()``);
- ``lib_path``: its path, for ``ctypes.CDLL`` in a subprocess;
- ``fresh_core``: every core destroyed and reset to the state of a fresh process
  (default G-code and machine parameters, no user parameters, prefix/postfix or
  callbacks, override 1.0, the tool table all zero, no axis correction tables,
  smoothing off) before and after the test; yields ``lib``;
- ``run_python``: runs a Python snippet in a fresh interpreter (fresh library state)
  and returns its stdout; the snippet finds ``LIB_PATH`` predefined.
"""
import ctypes
import os
import subprocess
import sys
import textwrap

import pytest

from sf_tch import abi, library, library_path


def _run_python(code: str, env: dict | None = None, timeout: float = 60, check: bool = True,
                cwd: str | None = None) -> subprocess.CompletedProcess:
    prelude = f"LIB_PATH = {library_path()!r}\n"
    full_env = dict(os.environ)
    full_env.update(env or {})
    proc = subprocess.run([sys.executable, "-c", prelude + textwrap.dedent(code)], capture_output=True,
                          text=True, timeout=timeout, env=full_env, cwd=cwd)
    if check and proc.returncode != 0:
        raise AssertionError(f"subprocess failed ({proc.returncode}):\n{proc.stdout}\n{proc.stderr}")
    return proc


@pytest.fixture(scope="session")
def run_python():
    """run_python(code, env=None, timeout=60, check=True, cwd=None) -> CompletedProcess
    (check: fail the test on a non-zero exit, showing stdout/stderr)."""
    return _run_python


@pytest.fixture(scope="session")
def lib_path() -> str:
    return library_path()


@pytest.fixture(scope="session")
def lib() -> ctypes.CDLL:
    return library.load()


@pytest.fixture(scope="session")
def fresh_defaults():
    """(GCODE_PARAMETERS, MACHINE_PARAMETERS) of a fresh process, read in a subprocess
    so that nothing done in this process can leak into them."""
    out = _run_python("""
        import ctypes
        from sf_tch import abi, library
        lib = library.load(LIB_PATH)
        p, m = abi.GCODE_PARAMETERS(), abi.MACHINE_PARAMETERS()
        assert lib.ToolChainCore_GetGCodeParameters(0, ctypes.byref(p)) == 0
        assert lib.ToolChainCore_GetMachineParameters(0, ctypes.byref(m)) == 0
        print(bytes(p).hex()); print(bytes(m).hex())
    """).stdout.split()
    return (abi.GCODE_PARAMETERS.from_buffer_copy(bytes.fromhex(out[0])),
            abi.MACHINE_PARAMETERS.from_buffer_copy(bytes.fromhex(out[1])))


def reset_core(lib, idx: int, defaults) -> None:
    params, machine = defaults
    assert lib.ToolChainCore_DestroyCNC(idx) == 0
    assert lib.ToolChainCore_SetGCodeParameters(idx, ctypes.byref(abi.GCODE_PARAMETERS.from_buffer_copy(params))) == 0
    assert lib.ToolChainCore_SetMachineParameters(idx, ctypes.byref(abi.MACHINE_PARAMETERS.from_buffer_copy(machine))) == 0
    assert lib.ToolChainCore_SetUserParams(idx, None, 0) == 0
    assert lib.ToolChainCore_GCodePrefixPostfix(idx, None, None) == 0
    assert lib.ToolChainCore_SetRelFeed(idx, 1.0) == 0
    assert lib.ToolChainCore_SetLookAhead(idx, 0) == 0
    assert lib.ToolChainCore_SetTimeScale(idx, 1.0) == 0
    assert lib.ToolChainCore_SetBreakpoint(idx, 0, -1) == 0
    # the machine position survives DestroyCNC: a test that moved it leaves it at the origin
    assert lib.ToolChainCore_ResetCNC(idx, 0, 10, (ctypes.c_double * 10)()) == 0
    for number in abi.CALLBACK_NUMBERS:
        assert lib.ToolChainCore_SetCallBack(idx, number, 0, None) == 0
    # the correction tables and the smoothing: none, all zero, off
    assert lib.ToolChainCore_LoadAxisCorrections(idx, 0, None) == 0
    for command in (abi.TC_SMOOTHING_SPLINE, abi.TC_SMOOTHING_IIR):
        assert lib.ToolChainCore_SetSmoothing(idx, command, (ctypes.c_double * 4)()) == 0
    zeros = (ctypes.c_double * abi.TC_TOOL_VALUES)()
    for entry in range(1, abi.TC_TOOL_ENTRIES + 1):
        assert lib.ToolChainCore_SetToolCorrection(idx, entry, 0x1F, zeros) == 0


@pytest.fixture
def fresh_core(lib, fresh_defaults):
    for idx in range(abi.TOOL_CHAIN_MAX_CORES):
        reset_core(lib, idx, fresh_defaults)
    yield lib
    for idx in range(abi.TOOL_CHAIN_MAX_CORES):
        reset_core(lib, idx, fresh_defaults)
