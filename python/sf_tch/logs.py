"""The library's log lines forwarded to Python's :mod:`logging`.

The library writes its log (``ToolChain_LogANSI`` and its own lines of the sources
enabled by ``ToolChainCore_SetLogValue``) to ``SF_TCh.log`` and stderr as the mask
says; ``ToolChain_SetLogHook`` (an extension of the header) also hands each line to one
C function. :func:`forward_library_log` installs a ctypes function there that passes
every line on to a :class:`logging.Logger`, beside the file.
"""
from __future__ import annotations

import atexit
import ctypes
import enum
import logging
import threading

from . import abi, library


class LogSource(enum.IntFlag):
    """Sources of the log mask (``LOG_*`` of ``tgm_cnc.h``); a line's source, or
    ``LOG_ANSI`` (0) for a line of ``ToolChain_LogANSI``."""
    LOG_ANSI = 0
    DEBUG = 0x01
    VERBOSE = 0x02
    WORKER = 0x04
    TOOLCHAIN = 0x08
    DRIVER = 0x10
    COMPILER = 0x20
    EXECUTOR = 0x40
    MATH = 0x80


# the lines the library writes by itself today: compilations, errors, PRINT texts
DEFAULT_SOURCES = LogSource.TOOLCHAIN | LogSource.COMPILER
DEFAULT_LOGGER = "sf_tch.library"
_DEBUG_SOURCES = LogSource.DEBUG | LogSource.VERBOSE

_lock = threading.Lock()
_active: "LibraryLog | None" = None       # the library has one hook: one forwarding at a time


class LibraryLog:
    """A running forwarding (from :func:`forward_library_log`); :meth:`close` (or the
    end of a ``with`` block, or the interpreter's exit) removes the hook and disables
    the sources it enabled."""

    def __init__(self, logger: logging.Logger, sources: LogSource, lib: ctypes.CDLL):
        self.logger = logger
        self.sources = sources
        self._lib = lib
        self._hook = abi.LogHook(self._forward)    # kept alive while the library may call it
        self._enabled = LogSource(0)

    def _forward(self, _user: int, source: int, text: bytes) -> None:
        source = LogSource(source & 0xFF)
        level = logging.DEBUG if source & _DEBUG_SOURCES else logging.INFO
        self.logger.log(level, "%s", text.decode("utf-8", errors="replace"),
                        extra={"sf_tch_source": source.name or "LOG_ANSI"})

    def _start(self) -> None:
        mask = self._lib.ToolChainCore_GetLogValue()
        self._enabled = LogSource(self.sources & ~mask & 0xFF)
        self._lib.ToolChainCore_SetLogValue(mask | self._enabled)
        if self._lib.ToolChain_SetLogHook(0, ctypes.cast(self._hook, ctypes.c_void_p)) != 0:
            raise RuntimeError("forward_library_log called from inside the library's log hook")

    def close(self) -> None:
        """Stops forwarding; returns once no line is being forwarded. Idempotent."""
        global _active
        with _lock:
            if _active is not self:
                return
            if self._lib.ToolChain_SetLogHook(0, None) != 0:
                raise RuntimeError("the library's log forwarding cannot be closed from inside its own hook")
            self._lib.ToolChainCore_SetLogValue(self._lib.ToolChainCore_GetLogValue() & ~self._enabled)
            _active = None

    def __enter__(self) -> "LibraryLog":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def __repr__(self) -> str:
        state = "active" if _active is self else "closed"
        return f"<LibraryLog {state} to {self.logger.name!r}, sources {self.sources!r}>"


def forward_library_log(logger: logging.Logger | str = DEFAULT_LOGGER,
                        sources: LogSource | int = DEFAULT_SOURCES) -> LibraryLog:
    """Forwards every line of the library's log to `logger` (a :class:`logging.Logger`
    or its name): ``ToolChain_LogANSI`` lines always, the library's own lines of
    `sources` (enabled in the log mask now, disabled again by :meth:`LibraryLog.close`
    unless they were on before). Lines of ``DEBUG``/``VERBOSE`` sources are logged at
    ``logging.DEBUG``, others at ``logging.INFO``; each record carries the source's name
    as ``record.sf_tch_source``. The log file and stderr outputs of the mask go on as
    before. A new forwarding replaces the previous one. The records are emitted on the
    thread that logs (possibly a library thread): a handler must not wait for the
    library's threads (``DestroyCNC``, ``ResetCNC``)."""
    global _active
    if isinstance(logger, str):
        logger = logging.getLogger(logger)
    forwarding = LibraryLog(logger, LogSource(int(sources) & 0xFF), library.load())
    previous = _active
    if previous is not None:
        previous.close()
    with _lock:
        forwarding._start()
        _active = forwarding
    return forwarding


@atexit.register
def _stop_at_exit() -> None:
    # a library thread must not call into Python once the interpreter is finalising
    if _active is not None:
        _active.close()
