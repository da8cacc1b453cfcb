"""The registry of checks and their verdicts.

A check is a function of a :class:`~sf_tch.conformance.host.Host` registered with
:func:`check` under an area, a short name and the documented statement it checks
(document, section, the statement in a sentence). It returns normally when the
statement holds, raises :class:`Differs` (what was expected, what came back) when it
does not, or :class:`NotApplicable` when the library lacks what the statement needs
(an extension beyond the vendor's list).
"""
from __future__ import annotations

import importlib
import math
from dataclasses import dataclass
from typing import Callable

# Areas in the order they run; each is a module of this package.
AREAS = ("structures", "returns", "errors", "dialect", "compensation", "planner", "simulation",
         "machine", "tool_table",
         "axis_tables", "smoothing")

HOLDS, DIFFERS, NOT_APPLICABLE, CRASHED, TIMED_OUT = "holds", "differs", "not applicable", "crashed", "timed out"
VERDICTS = (HOLDS, DIFFERS, NOT_APPLICABLE, CRASHED, TIMED_OUT)


@dataclass(frozen=True)
class Check:
    """One documented statement and the function that checks it."""
    area: str
    name: str
    document: str
    section: str
    statement: str
    run: Callable

    @property
    def id(self) -> str:
        """area.name, as the report and docs/conformance.md name the check."""
        return f"{self.area}.{self.name}"


class Differs(Exception):
    """The library's answer is not the documented one."""

    def __init__(self, expected, got, what: str = ""):
        super().__init__(f"{what}: expected {expected!r}, got {got!r}" if what else
                         f"expected {expected!r}, got {got!r}")
        self.expected, self.got, self.what = expected, got, what


class NotApplicable(Exception):
    """The statement cannot be checked on this library (the reason says why)."""


_REGISTRY: dict[str, list[Check]] = {}


def check(area: str, name: str, document: str, section: str, statement: str):
    """Registers the decorated function as the check `area.name` of a statement."""
    def register(fn):
        checks = _REGISTRY.setdefault(area, [])
        if any(c.name == name for c in checks):
            raise ValueError(f"check {area}.{name} registered twice")
        checks.append(Check(area, name, document, section, statement, fn))
        return fn
    return register


def area_checks(area: str) -> list[Check]:
    """The checks of one area, in the order they are written (imports its module)."""
    if area not in AREAS:
        raise ValueError(f"unknown area {area!r} (one of {', '.join(AREAS)})")
    importlib.import_module(f"{__package__}.{area}")
    return list(_REGISTRY.get(area, ()))


def all_checks() -> list[Check]:
    """Every check of every area."""
    return [c for area in AREAS for c in area_checks(area)]


def expect(expected, got, what: str = "") -> None:
    """Equal, or Differs."""
    if expected != got:
        raise Differs(expected, got, what)


def near(expected: float, got: float, tol: float, what: str = "") -> None:
    """Within tol (absolute), or Differs; NaN never holds."""
    if not (isinstance(got, (int, float)) and math.isfinite(got) and abs(got - expected) <= tol):
        raise Differs(f"{expected:.6g} ± {tol:g}", got if not isinstance(got, float) else float(f"{got:.9g}"), what)


def near_point(expected, got, tol: float, what: str = "") -> None:
    """Two points (sequences) equal within tol per coordinate, or Differs."""
    got = tuple(float(v) for v in got)
    if len(got) != len(expected) or any(abs(a - b) > tol for a, b in zip(expected, got)):
        raise Differs(tuple(round(v, 6) for v in expected), tuple(round(v, 6) for v in got), what)
