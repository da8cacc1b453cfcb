"""Shared fixtures of the test suite.

- ``lib``: the installed libSF_TCh.so loaded once with the typed prototypes of
  ``sf_tch.abi.FUNCTIONS`` (``sf_tch.library.load()``);
- ``lib_path``: its path, for ``ctypes.CDLL`` in a subprocess;
- ``fresh_core``: every core destroyed and reset to the state of a fresh process
  (default G-code and machine parameters, no user parameters, prefix/postfix or
  callbacks, override 1.0, the tool table all zero, no axis correction tables,
  smoothing off) before and after the test; yields ``lib``;
- ``run_python``: runs a Python snippet in a fresh interpreter (fresh library state)
  and returns its stdout; the snippet finds ``LIB_PATH`` predefined;
- ``comma_locale``: (name, environment) of a locale with a decimal comma;
- ``harness``: the test harness module (tests/harness: the library's stages with
  test-only entry points), built once per source state; test modules name it as
  they like (ph, mh, ch, geo) through a fixture of their own that uses this one.

How the suite runs (the hooks below):

- in parallel (pytest-xdist), one worker per core unless ``-n`` is given (``-n 0`` or
  ``-p no:xdist``: all in this process);
- the body of a test marked ``exclusive`` runs while no other test runs (its fixtures
  are set up beside them);
- every test has a time limit (pytest-timeout: ``timeout`` in pyproject.toml, more for
  slow tests and with ``@pytest.mark.timeout(seconds)``), stretched by
  ``SF_TCH_TIME_SCALE`` as the runtime tests' own hang limits are;
- the library's log file (``SF_TCh.log``) goes to a directory of each process's own;
- a test that uses ``harness`` (directly or through another fixture) but not ``lib``
  is marked ``harness``: it runs the stages compiled into the harness, never the
  built library (the sanitizer runs leave it out).
"""
import ctypes
import faulthandler
import fcntl
import os
import re
import shutil
import subprocess
import sys
import textwrap
from pathlib import Path
from typing import TextIO

import pytest

from runtime_host import TIME_SCALE
from sf_tch import abi, library, library_path

SLOW_TIME_LIMIT = 600.0  # s, a slow test's time limit unless it has its own
SLOW_SCALE = float(os.environ.get("SF_TCH_SLOW_SCALE", "1"))
HANG_GRACE = 30.0       # s after its time limit: a test stuck in C is ended by the watchdog
TIME_LIMIT = pytest.StashKey[float]()
STDERR = pytest.StashKey[TextIO]()


class RunLock:
    """A lock of the xdist workers of one run: every test holds it shared, an
    exclusive test's body alone. The turnstile, held by an exclusive test while it
    waits, keeps the other workers from starting new tests meanwhile (with tests
    always running somewhere, it would wait for ever)."""

    def __init__(self, directory: Path):
        self.turnstile = open(directory / "turnstile.lock", "a")
        self.tests = open(directory / "tests.lock", "a")

    def shared(self):
        fcntl.flock(self.turnstile, fcntl.LOCK_EX)
        fcntl.flock(self.turnstile, fcntl.LOCK_UN)
        fcntl.flock(self.tests, fcntl.LOCK_SH)

    def exclusive(self):
        fcntl.flock(self.turnstile, fcntl.LOCK_EX)
        fcntl.flock(self.tests, fcntl.LOCK_EX)
        fcntl.flock(self.turnstile, fcntl.LOCK_UN)

    def release(self):
        fcntl.flock(self.tests, fcntl.LOCK_UN)


RUN_LOCK = pytest.StashKey[RunLock]()


@pytest.hookimpl(tryfirst=True)
def pytest_cmdline_main(config):
    """Without -n, one xdist worker per core. Without --dist, each worker starts on its
    share of the tests in their order and takes over the end of a busier one's when it
    runs out (worksteal): the tests of a module, sharing its fixtures and the test
    harnesses, mostly stay on one worker."""
    if not config.pluginmanager.hasplugin("xdist") or hasattr(config, "workerinput"):
        return
    if config.option.numprocesses is None and not config.option.collectonly:
        config.option.numprocesses = "auto"
    if config.option.dist == "no" and config.option.numprocesses != 0:
        config.option.dist = "worksteal"


def pytest_configure(config):
    if hasattr(config, "workerinput"):
        # a worker's temporary directory lies in the run's (xdist sets --basetemp)
        config.stash[RUN_LOCK] = RunLock(Path(config.option.basetemp).parent)
    # the process's stderr, also while a test's output is captured (the watchdog's stacks)
    config.stash[STDERR] = os.fdopen(os.dup(sys.stderr.fileno()), "w")


@pytest.hookimpl(tryfirst=True)
def pytest_collection_modifyitems(config, items):
    """The `harness` mark, and each test's time limit: its timeout mark, else
    SLOW_TIME_LIMIT for a slow test (times SF_TCH_SLOW_SCALE, which sizes them), else
    pytest-timeout's default; all stretched by SF_TCH_TIME_SCALE (sanitized libraries
    run slower)."""
    for item in items:
        if "harness" in item.fixturenames and "lib" not in item.fixturenames:
            item.add_marker(pytest.mark.harness)
    if not config.pluginmanager.hasplugin("timeout"):
        return
    default = config.getoption("timeout")
    if default is None:
        default = config.getini("timeout")
    if not default:
        return                      # --timeout 0: no limits
    for item in items:
        marker = item.get_closest_marker("timeout")
        if marker and marker.args:
            seconds = float(marker.args[0])
        elif item.get_closest_marker("slow"):
            seconds = SLOW_TIME_LIMIT * SLOW_SCALE
        else:
            seconds = float(default)
        seconds *= TIME_SCALE
        item.add_marker(pytest.mark.timeout(seconds), append=False)
        item.stash[TIME_LIMIT] = seconds


@pytest.hookimpl(wrapper=True, tryfirst=True)
def pytest_runtest_protocol(item, nextitem):
    """A test that is not exclusive runs holding the run's lock shared; waiting for it
    is outside the test's time limit (pytest-timeout's timer starts inside this wrapper).

    pytest-timeout (signal method) fails a test at its time limit, unless the test is
    stuck in C, where the signal is never handled: the watchdog then prints every
    thread's stack to stderr and ends the process (under xdist: this worker, reported
    as crashed in that test; the run goes on with a new worker)."""
    lock = item.config.stash.get(RUN_LOCK, None)
    shared = lock is not None and not item.get_closest_marker("exclusive")
    if shared:
        lock.shared()
    limit = item.stash.get(TIME_LIMIT, None)
    if limit:
        faulthandler.dump_traceback_later(limit + HANG_GRACE, exit=True, file=item.config.stash[STDERR])
    try:
        return (yield)
    finally:
        if limit:
            faulthandler.cancel_dump_traceback_later()
        if shared:
            lock.release()


@pytest.hookimpl(wrapper=True, tryfirst=True)
def pytest_runtest_call(item):
    """An exclusive test's body holds the run's lock alone: it waits for the tests
    running on the other workers to end, and they wait for it."""
    lock = item.config.stash.get(RUN_LOCK, None)
    if lock is None or not item.get_closest_marker("exclusive"):
        return (yield)
    lock.exclusive()
    try:
        return (yield)
    finally:
        lock.release()


@pytest.fixture(scope="session", autouse=True)
def library_log_dir(tmp_path_factory):
    """SF_TCh.log of this process and its subprocesses in a directory of its own (the
    library's default, the current directory, is shared by parallel workers); a test
    that reads the log names its own directory."""
    before = os.environ.get("SF_TCH_LOG_DIR")
    os.environ["SF_TCH_LOG_DIR"] = str(tmp_path_factory.mktemp("library-log"))
    yield
    if before is None:
        del os.environ["SF_TCH_LOG_DIR"]
    else:
        os.environ["SF_TCH_LOG_DIR"] = before


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
def harness():
    import harness
    return harness.load()


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


@pytest.fixture(scope="session")
def comma_locale(tmp_path_factory) -> tuple[str, dict]:
    """(name, environment) of a locale with a decimal comma: one the machine has (no
    environment), else de_DE.UTF-8 generated with localedef (LOCPATH names it)."""
    listed = subprocess.run(["locale", "-a"], capture_output=True, text=True).stdout.split() \
        if shutil.which("locale") else []
    for name in listed:
        if re.match(r"(de_DE|fr_FR|cs_CZ|it_IT|es_ES)\.utf-?8$", name, re.I):
            return name, {}
    localedef = shutil.which("localedef")
    if localedef is None:
        pytest.skip("no decimal-comma locale installed and no localedef to generate one")
    root = tmp_path_factory.mktemp("locale")
    proc = subprocess.run([localedef, "-i", "de_DE", "-f", "UTF-8", str(root / "de_DE.UTF-8")],
                          capture_output=True, text=True, timeout=120)
    if not (root / "de_DE.UTF-8").exists():
        pytest.skip(f"no decimal-comma locale and localedef failed: {proc.stderr.strip()[:200]}")
    return "de_DE.UTF-8", {"LOCPATH": str(root)}


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
