"""A conformance suite: the vendor's documented behaviour, checked from a host.

``python -m sf_tch.conformance --library PATH`` loads any library that exports the
vendor's ABI (this one, or the vendor's own ``libSF_TCh.so`` / ``SF_TCh.dll``) with
plain ``ctypes`` and runs checks, one per documented statement, each naming the
document and section of this project's docs that states it. Only the vendor's
exports and callbacks decide a verdict; the offline machine is waited for as a panel
waits (polling ``StatusCNC`` / ``GetPos`` with a time bound), in real time.

Modules: :mod:`.checks` (the registry and the verdicts), :mod:`.host` (the library
seen through ctypes, the platform's text types), :mod:`.worker` (runs one area's
checks in a child process), :mod:`.runner` (the child processes, time bounds,
crashes, the report), and one module per area. The list of every check:
docs/conformance.md.
"""
from .checks import AREAS, all_checks

__all__ = ["AREAS", "all_checks"]
