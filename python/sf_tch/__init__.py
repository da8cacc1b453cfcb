"""sf_tch: the open drop-in replacement of the TG Motion CNC module library.

The product is the shared library ``libSF_TCh.so`` (its C ABI is ``include/tgm_cnc.h``);
this package ships it and adds a Pythonic layer over ``ctypes``:

- :func:`compile` -- G-code (a file or text) to a :class:`Program`: errors and
  warnings, the toolpath as numpy records, extents, run time, :meth:`Program.plot`;
- :class:`Core` -- a handle of one CNC core (compile, simulate, callbacks);
- :mod:`sf_tch.enums` -- statuses, regimes, callbacks, error numbers, part kinds;
- :func:`library_path` -- where the library is, for ``ctypes.CDLL``;
- :mod:`sf_tch.abi` -- the ctypes mirror of every structure of the header;
- :mod:`sf_tch.library` -- the library loaded once, with typed prototypes;
- :func:`forward_library_log` -- the library's log lines to a :mod:`logging` logger.
"""
import os
import sys
from pathlib import Path
from typing import Iterator

LIBRARY_NAME = "SF_TCh.dll" if sys.platform == "win32" else "libSF_TCh.so"   # docs/hosts.md, "Windows"
LIBRARY_ENV = "SF_TCH_LIBRARY"

_PACKAGE_DIR = Path(__file__).resolve().parent


def _candidates() -> Iterator[Path]:
    """Where the library may be, in order: the package directory (a wheel or
    ``pip install .``), where the installed distribution put it (``pip install -e
    .``: site-packages, beside the redirected sources), then the build directories of
    a source tree (scikit-build-core's ``build-dir``, a CMake build in ``build/``).
    Lazily: importlib.metadata costs a host 30 ms and 4 MB, and an installed package
    never needs it."""
    yield _PACKAGE_DIR / LIBRARY_NAME
    from importlib import metadata
    try:
        installed = metadata.distribution("sf-tch")
        yield from (Path(str(installed.locate_file(f))) for f in installed.files or ()
                    if f.name == LIBRARY_NAME)
    except metadata.PackageNotFoundError:
        pass
    root = _PACKAGE_DIR.parents[1]
    for build in (root / "build", *sorted(root.glob("build/*"))):
        yield build / LIBRARY_NAME


def library_path() -> str:
    """Absolute path of ``libSF_TCh.so``: ``$SF_TCH_LIBRARY`` when set (e.g. a
    sanitizer build), else the installed one, else one built in the source tree.
    Raises :class:`LibraryNotFoundError` saying where it looked."""
    from .errors import LibraryNotFoundError
    override = os.environ.get(LIBRARY_ENV)
    if override:
        path = Path(override).expanduser()
        if not path.is_file():
            raise LibraryNotFoundError(f"{LIBRARY_ENV}={override}: no such file")
        return str(path.resolve())
    candidates = []
    for path in _candidates():
        if path.is_file():
            return str(path)
        candidates.append(path)
    looked = ", ".join(str(p) for p in candidates[:2])
    raise LibraryNotFoundError(f"{LIBRARY_NAME} not found (looked in {looked}, ...): build and install it "
                               f"with 'pip install .' (needs a C compiler), or set {LIBRARY_ENV}")


def header_path() -> str:
    """Absolute path of the C header ``tgm_cnc.h``: the installed copy, else the
    source tree's."""
    installed = _PACKAGE_DIR / "include" / "tgm_cnc.h"
    if installed.is_file():
        return str(installed)
    return str(_PACKAGE_DIR.parents[1] / "include" / "tgm_cnc.h")


from .enums import (Callback, Compensation, ErrorNumber, GFunction, MFunction, PartKind, Plane,  # noqa: E402
                    Regime, ReturnCode, Status, ToolpathFlag)
from .errors import (Cancelled, CncError, Diagnostic, GougeWarning, LibraryNotFoundError,  # noqa: E402
                     NoFreeCoreError, SfTchError)
from .logs import LibraryLog, LogSource, forward_library_log  # noqa: E402

# The numpy side (Core, Program, Toolpath) is imported on first use: a host that only
# needs the ctypes layer (sf_tch.abi, sf_tch.library) does not load numpy, whose
# OpenBLAS threads spin for a while after the import and take a core from the
# library's compile threads on a two-core panel (docs/benchmarks.md, 2026-11-25).
_LAZY = {
    "Core": "core", "RunResult": "core", "default_ini": "core", "sample_program": "core",
    "CompileJob": "program", "Program": "program", "compile": "program", "start_compile": "program",
    "TOOLPATH_DTYPE": "toolpath", "Run": "toolpath", "Toolpath": "toolpath",
}


def _version() -> str:
    """pyproject.toml's [project] version, the one place, as installed; read on first
    use (importlib.metadata alone takes longer to import than the rest of the package)."""
    from importlib import metadata
    try:
        return metadata.version("sf-tch")
    except metadata.PackageNotFoundError:           # imported from a source tree that is not installed
        return "0+unknown"


def __getattr__(name: str):
    if name == "__version__":
        globals()[name] = _version()
        return globals()[name]
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module 'sf_tch' has no attribute {name!r}")
    import importlib
    value = getattr(importlib.import_module(f".{module}", __name__), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_LAZY) | {"__version__"})


__all__ = [
    "__version__", "library_path", "header_path", "compile", "start_compile", "CompileJob", "Program",
    "Core", "RunResult", "Toolpath", "Run", "TOOLPATH_DTYPE", "Diagnostic", "GougeWarning", "SfTchError", "CncError",
    "Cancelled", "LibraryNotFoundError", "NoFreeCoreError", "Callback", "Compensation", "ErrorNumber",
    "GFunction", "MFunction", "PartKind", "Plane", "Regime", "ReturnCode", "Status", "ToolpathFlag",
    "default_ini", "sample_program", "forward_library_log", "LibraryLog", "LogSource",
]
