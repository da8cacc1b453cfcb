"""sf_tch: the open drop-in replacement of the TG Motion CNC module library.

The product is the shared library ``libSF_TCh.so`` (its C ABI is ``include/tgm_cnc.h``);
this package ships it and adds a thin Pythonic layer over ``ctypes``:

- :func:`library_path` -- where the installed library is, for ``ctypes.CDLL``;
- :mod:`sf_tch.abi` -- the ctypes mirror of every structure of the header;
- :mod:`sf_tch.library` -- the library loaded once, with typed prototypes;
- :mod:`sf_tch.core` -- :class:`Core`, a Pythonic handle of one CNC core.
"""
import os
from pathlib import Path

__version__ = "0.1.0"

LIBRARY_NAME = "libSF_TCh.so"


def library_path() -> str:
    """Absolute path of the installed ``libSF_TCh.so``, or the library that the
    environment variable ``SF_TCH_LIBRARY`` names (e.g. a sanitized build)."""
    if os.environ.get("SF_TCH_LIBRARY"):
        return os.environ["SF_TCH_LIBRARY"]
    path = Path(__file__).resolve().parent / LIBRARY_NAME
    if not path.exists():
        raise FileNotFoundError(f"{LIBRARY_NAME} is not installed next to {__file__}; run 'pip install .'")
    return str(path)


def header_path() -> str:
    """Absolute path of the installed C header ``tgm_cnc.h``."""
    return str(Path(__file__).resolve().parent / "include" / "tgm_cnc.h")
