"""The toolpath of a compiled program as a numpy structured array.

:data:`TOOLPATH_DTYPE` mirrors ``TC_TOOLPATH_RECORD`` of ``include/tgm_cnc.h`` (192
bytes, every field documented there): ``start``, ``end`` (programmed, mm, machine
coordinates, x y z), ``tool_start``, ``tool_end`` (the tool centre's path after radius
compensation), ``centre``, ``radius``, ``length``, ``feed``, ``value``, ``kind``
(:class:`~sf_tch.enums.PartKind`), ``number`` (G or M number), ``line``,
``file_index``, ``plane``, ``compensation``, ``flags``, ``tool``, ``spindle``,
``feed_factor``. :func:`fetch` has the library fill such an array in one call;
:class:`Toolpath` adds the file names and samples arcs for drawing.
"""
from __future__ import annotations

import ctypes
from dataclasses import dataclass

import numpy as np

from . import abi
from .enums import GFunction, PartKind

TOOLPATH_DTYPE = np.dtype(abi.TC_TOOLPATH_RECORD)
assert TOOLPATH_DTYPE.itemsize == 192, "TC_TOOLPATH_RECORD is 192 bytes (include/tgm_cnc.h)"

# first and second axis of each arc plane (geometry.pyx of the library)
_PLANE_AXES = {17: (0, 1), 18: (0, 2), 19: (1, 2), -18: (2, 0)}


def fetch(lib: ctypes.CDLL, core: int) -> np.ndarray:
    """The whole toolpath of the core's compiled program: asks the library for the
    number of records, allocates the array, and has the library fill it (one copy).
    Raises RuntimeError when the core has no compiled program."""
    total = ctypes.c_uint64()
    if lib.ToolChainCore_GetToolpath(core, None, 0, 0, ctypes.byref(total)) != abi.TOOL_CHAIN_SUCCESS:
        raise RuntimeError(f"core {core} has no compiled program")
    records = np.empty(total.value, TOOLPATH_DTYPE)
    out = records.ctypes.data_as(ctypes.POINTER(abi.TC_TOOLPATH_RECORD))
    again = ctypes.c_uint64()
    if (lib.ToolChainCore_GetToolpath(core, out, total.value, 0, ctypes.byref(again)) != abi.TOOL_CHAIN_SUCCESS
            or again.value != total.value):
        raise RuntimeError(f"the program of core {core} changed while it was read")
    return records


@dataclass(frozen=True)
class Run:
    """A stretch of consecutive moves of one sort, sampled for drawing: ``points`` is
    an (n, 3) array x y z (mm) from the first move's start to the last move's end."""

    rapid: bool
    points: np.ndarray


class Toolpath:
    """The parts of a compiled program in order (``records``: a structured array of
    :data:`TOOLPATH_DTYPE`), with the names of the files its ``file_index`` refers to."""

    def __init__(self, records: np.ndarray, files: dict[int, str] | None = None):
        self.records = records
        self.files = dict(files or {})

    def __len__(self) -> int:
        return len(self.records)

    def __getitem__(self, index):
        return self.records[index]

    def __iter__(self):
        return iter(self.records)

    def __repr__(self) -> str:
        kinds = np.bincount(self.records["kind"], minlength=5) if len(self) else np.zeros(5, int)
        return (f"<Toolpath {len(self)} parts: {kinds[PartKind.MOTION]} moves, "
                f"{kinds[PartKind.M_FUNCTION]} M functions, {kinds[PartKind.DWELL]} dwells, "
                f"{kinds[PartKind.PRINT]} prints>")

    @property
    def motion(self) -> np.ndarray:
        """The motion parts only (G0 G1 G2 G3 G33), a view-free copy of their records."""
        return self.records[self.records["kind"] == PartKind.MOTION]

    def file_of(self, record) -> str:
        """File name of a record (its file_index)."""
        return self.files.get(int(record["file_index"]), "__unknown__")

    def to_dict(self) -> dict:
        """Summary as plain types: counts and lengths (mm) of cuts and rapids."""
        motion = self.motion
        rapid = motion["number"] == GFunction.RAPID
        return {"parts": len(self), "moves": int(len(motion)),
                "m_functions": int((self.records["kind"] == PartKind.M_FUNCTION).sum()),
                "cut_parts": int((~rapid).sum()), "rapid_parts": int(rapid.sum()),
                "cut_length": float(motion["length"][~rapid].sum()),
                "rapid_length": float(motion["length"][rapid].sum())}

    def points(self, step: float = 0.5, tool: bool = False) -> np.ndarray:
        """Every move in order as one (n, 3) array of points (mm): the first move's
        start, then for each move its end, arcs sampled so that no chord spans more
        than `step` mm of arc. `tool`: the compensated path instead of the programmed."""
        motion = self.motion
        if len(motion) == 0:
            return np.empty((0, 3))
        return np.concatenate([motion[:1]["tool_start" if tool else "start"], _sample(motion, step, tool)])

    def polyline(self, step: float = 0.5, tool: bool = False) -> list[Run]:
        """The moves as runs of rapids and of cuts (a new run where they change, or
        where a move does not start at the previous one's end), arcs sampled as in
        :meth:`points`; for drawing, e.g. rapids dashed."""
        motion = self.motion
        if len(motion) == 0:
            return []
        starts = motion["tool_start" if tool else "start"]
        ends = motion["tool_end" if tool else "end"]
        rapid = motion["number"] == GFunction.RAPID
        breaks = np.flatnonzero((rapid[1:] != rapid[:-1])
                                | np.any(np.abs(starts[1:] - ends[:-1]) > 1e-9, axis=1)) + 1
        samples = _sample(motion, step, tool)
        counts = _sample_counts(motion, step, tool)
        offsets = np.concatenate([[0], np.cumsum(counts)])
        runs = []
        for first, last in zip(np.concatenate([[0], breaks]), np.concatenate([breaks, [len(motion)]])):
            pts = np.concatenate([starts[first:first + 1], samples[offsets[first]:offsets[last]]])
            runs.append(Run(bool(rapid[first]), pts))
        return runs


def _arc_geometry(motion: np.ndarray, tool: bool):
    """Per move: is it an arc, plane axes (a, b), start angle, signed sweep, radius
    about the centre, for the programmed or the tool path."""
    s = motion["tool_start" if tool else "start"]
    e = motion["tool_end" if tool else "end"]
    c = motion["centre"]
    arc = (motion["number"] == GFunction.ARC_CW) | (motion["number"] == GFunction.ARC_CCW)
    arc &= np.isin(motion["plane"], list(_PLANE_AXES))
    first = np.zeros(len(motion), int)
    second = np.ones(len(motion), int)
    for plane, (a, b) in _PLANE_AXES.items():
        on = motion["plane"] == plane
        first[on], second[on] = a, b
    rows = np.arange(len(motion))
    sa, sb = s[rows, first] - c[rows, first], s[rows, second] - c[rows, second]
    ea, eb = e[rows, first] - c[rows, first], e[rows, second] - c[rows, second]
    a0, a1 = np.arctan2(sb, sa), np.arctan2(eb, ea)
    ccw = motion["number"] == GFunction.ARC_CCW
    sweep = a1 - a0
    # in the arc's direction, in (0, 2 pi]: equal start and end make a full circle
    sweep = np.where(ccw, np.mod(sweep - 1e-12, 2 * np.pi) + 1e-12, -(np.mod(-sweep - 1e-12, 2 * np.pi) + 1e-12))
    radius = np.hypot(sa, sb)
    return arc, first, second, a0, sweep, radius


def _sample_counts(motion: np.ndarray, step: float, tool: bool) -> np.ndarray:
    """Points each move contributes: 1 for a line, enough for an arc that no chord
    spans more than `step` mm of arc (at most 720)."""
    if step <= 0:
        raise ValueError("step must be positive")
    arc, _, _, _, sweep, radius = _arc_geometry(motion, tool)
    counts = np.ones(len(motion), np.int64)
    counts[arc] = np.clip(np.ceil(np.abs(sweep[arc]) * radius[arc] / step), 1, 720).astype(np.int64)
    return counts


def _sample(motion: np.ndarray, step: float, tool: bool) -> np.ndarray:
    """The points after each move's start (its samples, its end last), all moves."""
    arc, first, second, a0, sweep, radius = _arc_geometry(motion, tool)
    counts = _sample_counts(motion, step, tool)
    s = motion["tool_start" if tool else "start"]
    e = motion["tool_end" if tool else "end"]
    owner = np.repeat(np.arange(len(motion)), counts)
    within = np.arange(len(owner)) - np.repeat(np.cumsum(counts) - counts, counts)
    t = (within + 1) / counts[owner]                        # (0, 1], 1 = the move's end
    points = s[owner] + (e[owner] - s[owner]) * t[:, None]  # lines; the normal axis of helices
    on_arc = arc[owner]
    k = owner[on_arc]
    angle = a0[k] + sweep[k] * t[on_arc]
    rows = np.flatnonzero(on_arc)
    centre = motion["centre"]
    points[rows, first[k]] = centre[k, first[k]] + radius[k] * np.cos(angle)
    points[rows, second[k]] = centre[k, second[k]] + radius[k] * np.sin(angle)
    last = np.cumsum(counts) - 1
    points[last] = e                                        # ends exactly as the library has them
    return points
