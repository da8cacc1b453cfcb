"""The library, loaded once per process with typed prototypes.

``load()`` opens ``libSF_TCh.so`` (:func:`sf_tch.library_path`) with ``ctypes.CDLL``
(which releases the GIL during every call, so the library's threads may call back
into Python) and applies the argument and result types of
:data:`sf_tch.abi.FUNCTIONS`. A host that opens the same path with its own
``ctypes.CDLL`` shares the same library state.
"""
from __future__ import annotations

import ctypes
import functools

from . import abi, library_path


@functools.lru_cache(maxsize=None)
def load(path: str | None = None) -> ctypes.CDLL:
    """The library at `path` (default :func:`sf_tch.library_path`), prototypes applied."""
    lib = ctypes.CDLL(path or library_path())
    for name, restype, argtypes in abi.FUNCTIONS:
        fn = getattr(lib, name)
        fn.restype = restype
        fn.argtypes = argtypes
    return lib


def plc_memory(lib: ctypes.CDLL | None = None):
    """The offline PLC memory TGM_Data (524288 bytes) shared with ReadPLC*/WritePLC*."""
    return (ctypes.c_ubyte * abi.PLC_MEMORY_BYTES).in_dll(lib or load(), "TGM_Data")
