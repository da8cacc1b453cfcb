"""The library's log forwarded to Python's logging (sf_tch.forward_library_log over the
ToolChain_SetLogHook extension): ToolChain_LogANSI and the library's own lines of the
enabled sources, from the host's and from the library's threads, beside the log file;
the mask restored, nothing forwarded after close; the hook's own rules at the C level."""
import logging
import threading

import pytest

import sf_tch
from sf_tch import LogSource, forward_library_log


class Collect(logging.Handler):
    def __init__(self):
        super().__init__(logging.DEBUG)
        self.records: list[logging.LogRecord] = []

    def emit(self, record):
        self.records.append(record)


@pytest.fixture
def collected(fresh_core):
    logger = logging.getLogger("test_logs.library")
    logger.setLevel(logging.DEBUG)
    logger.propagate = False
    handler = Collect()
    logger.addHandler(handler)
    yield logger, handler.records
    logger.removeHandler(handler)


def test_log_ansi_lines_reach_the_logger_until_closed(collected):
    logger, records = collected
    lib = sf_tch.library.load()
    mask_before = lib.ToolChainCore_GetLogValue()
    with forward_library_log(logger) as forwarding:
        assert lib.ToolChainCore_GetLogValue() == mask_before | LogSource.TOOLCHAIN | LogSource.COMPILER
        lib.ToolChain_LogANSI("ünits: mm".encode())
        lib.ToolChain_LogANSI(None)                         # ignored by the library
    assert lib.ToolChainCore_GetLogValue() == mask_before
    lib.ToolChain_LogANSI(b"after close")
    assert [(r.getMessage(), r.levelno, r.sf_tch_source, r.name) for r in records] == [
        ("ünits: mm", logging.INFO, "LOG_ANSI", "test_logs.library")]
    assert "closed" in repr(forwarding)


def test_compiler_and_error_lines_from_the_worker_thread(collected):
    logger, records = collected
    with forward_library_log(logger):
        with sf_tch.compile("G1 X10 Y10 F1000\nG1 X20\nM5\n") as good:
            parts = len(good.toolpath)
        with sf_tch.compile("G1 X10 Y10 F1000\nG1 X20 Q\n") as bad:
            errors = bad.errors
    assert parts == 3 and len(errors) == 1
    compiled = [r for r in records if r.sf_tch_source == "COMPILER"]
    assert [r.getMessage() for r in compiled] == ["Compiled program.nc: 3 parts"]
    # the compile worker logs it, not the test's thread
    assert compiled[0].thread != threading.get_ident()
    (error,) = [r for r in records if r.sf_tch_source == "TOOLCHAIN"]
    diag = errors[0]
    assert f"error {int(diag.number)} " in error.getMessage() and f" line {diag.line}: {diag.text}" in error.getMessage()
    assert error.levelno == logging.INFO


def test_only_the_chosen_sources(collected):
    logger, records = collected
    with forward_library_log(logger, sources=LogSource.COMPILER):
        with sf_tch.compile("G1 X10 Y10 F1000\nG1 X20 Q\n"):   # an error: a TOOLCHAIN line
            pass
        with sf_tch.compile("G1 X10 Y10 F1000\n"):
            pass
    assert [r.sf_tch_source for r in records] == ["COMPILER"]


def test_a_new_forwarding_replaces_the_previous(collected):
    logger, records = collected
    other = logging.getLogger("test_logs.other")
    other.propagate = False
    other.setLevel(logging.DEBUG)
    other_handler = Collect()
    other.addHandler(other_handler)
    try:
        first = forward_library_log(logger)
        second = forward_library_log(other)
        sf_tch.library.load().ToolChain_LogANSI(b"to the second")
        second.close()
        first.close()                                     # already replaced: nothing to do
    finally:
        other.removeHandler(other_handler)
    assert records == [] and [r.getMessage() for r in other_handler.records] == ["to the second"]


def test_the_log_file_still_gets_the_lines(run_python, tmp_path):
    """Forwarding is beside the outputs of the mask: the file gets the same lines."""
    proc = run_python("""
        import logging, sf_tch
        logging.basicConfig(level=logging.INFO, format="%(sf_tch_source)s|%(message)s")
        lib = sf_tch.library.load()
        lib.ToolChainCore_SetLogValue(0x20000000 | 0x20)            # LOG_TO_FILE | LOG_COMPILER
        with sf_tch.forward_library_log():
            with sf_tch.compile("G1 X1 F100\\n"):
                pass
            lib.ToolChain_LogANSI(b"a host line")
        lib.ToolChain_FlushLogFile()
    """, env={"SF_TCH_LOG_DIR": str(tmp_path)})
    logged = (tmp_path / "SF_TCh.log").read_text().splitlines()
    forwarded = [line for line in proc.stderr.splitlines() if "|" in line]
    assert [line.split("|", 1)[1] for line in forwarded] == [line.split(" ", 2)[2] for line in logged]
    assert forwarded[0].startswith("COMPILER|Compiled ") and forwarded[1] == "LOG_ANSI|a host line"


def test_hook_rules_at_the_c_level(run_python):
    """With bare ctypes: the hook gets (userData, source, text); a line logged inside
    the hook does not reach it again; setting the hook from inside it is refused
    (-1), without deadlock; after removal nothing arrives."""
    proc = run_python("""
        import ctypes
        from sf_tch import abi
        lib = ctypes.CDLL(LIB_PATH)
        for name, restype, argtypes in abi.FUNCTIONS:
            getattr(lib, name).restype, getattr(lib, name).argtypes = restype, argtypes
        seen = []
        def hook(user, source, text):
            seen.append((user, source, text))
            lib.ToolChain_LogANSI(b"inside")
            seen.append(("set inside", lib.ToolChain_SetLogHook(0, None)))
        fn = abi.LogHook(hook)
        assert lib.ToolChain_SetLogHook(1234, ctypes.cast(fn, ctypes.c_void_p)) == 0
        lib.ToolChain_LogANSI(b"outside")
        assert lib.ToolChain_SetLogHook(0, None) == 0
        lib.ToolChain_LogANSI(b"removed")
        print(seen)
    """, timeout=30)
    assert proc.stdout.strip() == "[(1234, 0, b'outside'), ('set inside', -1)]"
