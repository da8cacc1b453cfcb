"""Runs the checks of one area in this (child) process and writes one JSON line per
event to the protocol stream: ``{"start": i}`` before check i, then its result.

``python -m sf_tch.conformance.worker LIBRARY AREA FIRST WORKDIR``: the checks from
index FIRST on (the runner starts a new child after a crash or a hang). The
library's own writes to stdout go to stderr, so they never mix with the protocol.
"""
from __future__ import annotations

import json
import os
import sys
import time
import traceback

from .checks import DIFFERS, HOLDS, NOT_APPLICABLE, Differs, NotApplicable, area_checks
from .host import Host


def _short(value):
    """A value as JSON can hold it, short."""
    if isinstance(value, (int, float, str, bool)) or value is None:
        return value
    text = repr(value)
    return text if len(text) <= 300 else text[:297] + "..."


def run(library: str, area: str, first: int, workdir: str, out) -> None:
    """Runs the area's checks from index first on, writing the protocol to out."""
    checks = area_checks(area)
    os.chdir(workdir)
    host = Host(library, workdir)
    for index in range(first, len(checks)):
        c = checks[index]
        out.write(json.dumps({"start": index}) + "\n")
        out.flush()
        begun = time.monotonic()
        result = {"index": index, "id": c.id}
        try:
            host.reset()
            c.run(host)
            result["verdict"] = HOLDS
        except Differs as d:
            result.update(verdict=DIFFERS, expected=_short(d.expected), got=_short(d.got), detail=d.what)
        except NotApplicable as n:
            result.update(verdict=NOT_APPLICABLE, detail=str(n))
        except Exception as e:  # a function missing, a wrong type: the library does not answer as documented
            tb = traceback.extract_tb(e.__traceback__)[-1]
            result.update(verdict=DIFFERS, expected="the documented answer", got=f"{type(e).__name__}: {e}",
                          detail=f"at {os.path.basename(tb.filename)}:{tb.lineno}")
        result["seconds"] = round(time.monotonic() - begun, 3)
        out.write(json.dumps(result) + "\n")
        out.flush()
    host.reset()


def main(argv=None) -> int:
    """The child's entry point: LIBRARY AREA FIRST WORKDIR."""
    library, area, first, workdir = (argv or sys.argv[1:])[:4]
    out = os.fdopen(os.dup(1), "w")
    os.dup2(2, 1)             # the library's printf to stderr
    run(library, area, int(first), workdir, out)
    out.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())
