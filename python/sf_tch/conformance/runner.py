"""Runs areas in child processes and gathers their verdicts.

Each area runs in its own interpreter (:mod:`.worker`), in a temporary directory
that is removed afterwards: a library that crashes, or a check that outlives its
time bound, ends that child only. The check it was running gets the verdict
``crashed`` or ``timed out``, and a new child goes on with the next check.
"""
from __future__ import annotations

import json
import os
import queue
import signal
import subprocess
import sys
import tempfile
import threading
import time

from .checks import CRASHED, TIMED_OUT, area_checks

# The folder that holds this sf_tch package: the children import the same code.
_PACKAGE_ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def _reader(stream, lines: queue.Queue) -> None:
    for line in stream:
        lines.put(line)
    lines.put(None)


def _how(returncode: int) -> str:
    if returncode < 0:
        try:
            return f"killed by {signal.Signals(-returncode).name}"
        except ValueError:
            return f"killed by signal {-returncode}"
    if returncode > 0xFFFF:            # a Windows exception code, e.g. 0xC0000005
        return f"exit status {returncode:#010x}"
    return f"exit status {returncode}"


def _tail(path: str) -> str:
    try:
        with open(path, "rb") as f:
            f.seek(0, os.SEEK_END)
            f.seek(max(0, f.tell() - 600))
            lines = f.read().decode(errors="replace").strip().splitlines()
        return lines[-1][:200] if lines else ""
    except OSError:
        return ""


def run_area(library: str, area: str, timeout: float, workdir: str, progress=None) -> list[dict]:
    """Every check of area against library: one result dict per check, in order."""
    checks = area_checks(area)
    results: dict[int, dict] = {}
    first = 0
    while first < len(checks):
        err_path = os.path.join(workdir, f"{area}-{first}.stderr")
        env = dict(os.environ, SF_TCH_LOG_DIR=workdir, PYTHONDONTWRITEBYTECODE="1",
                   PYTHONPATH=os.pathsep.join(filter(None, (_PACKAGE_ROOT, os.environ.get("PYTHONPATH")))))
        with open(err_path, "wb") as err:
            proc = subprocess.Popen([sys.executable, "-m", f"{__package__}.worker", library, area, str(first), workdir],
                                    stdout=subprocess.PIPE, stderr=err, stdin=subprocess.DEVNULL, cwd=workdir,
                                    env=env, text=True)
        lines: queue.Queue = queue.Queue()
        threading.Thread(target=_reader, args=(proc.stdout, lines), daemon=True).start()
        current, deadline = None, time.monotonic() + timeout + 30   # +30: the child's start
        while True:
            try:
                line = lines.get(timeout=max(0.0, deadline - time.monotonic()))
            except queue.Empty:
                proc.kill()
                proc.wait()
                results[first if current is None else current] = {
                    "verdict": TIMED_OUT, "detail": f"no verdict within {timeout:g} s"}
                current = None
                break
            if line is None:
                proc.wait()
                break
            try:
                message = json.loads(line)
            except ValueError:          # not the worker's (it writes nothing else there)
                continue
            if "start" in message:
                current, deadline = message["start"], time.monotonic() + timeout
            else:
                results[message["index"]] = message
                current = None
                if progress:
                    progress(checks[message["index"]], message)
        crash = {"verdict": CRASHED, "detail": f"{_how(proc.returncode)}: {_tail(err_path)}".rstrip(": ")}
        if current is not None:       # the child ended in the middle of a check
            results[current] = crash
        elif first not in results:    # ... before its first one: it cannot run any
            for i in range(first, len(checks)):
                results[i] = dict(crash)
        while first in results:
            first += 1
    out = []
    for i, c in enumerate(checks):
        r = dict(results.get(i, {"verdict": CRASHED, "detail": "not run"}))
        r.pop("index", None)
        r.update(id=c.id, area=c.area, name=c.name, document=c.document, section=c.section,
                 statement=c.statement)
        out.append(r)
    return out


def run(library: str, areas, timeout: float = 30.0, progress=None) -> list[dict]:
    """Every check of the areas, each area in its own child process(es)."""
    with tempfile.TemporaryDirectory(prefix="sf_tch_conformance_") as tmp:
        results = []
        for area in areas:
            workdir = os.path.join(tmp, area)
            os.mkdir(workdir)
            results += run_area(library, area, timeout, workdir, progress)
        return results
