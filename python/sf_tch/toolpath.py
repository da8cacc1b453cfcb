"""The toolpath of a compiled program as a numpy structured array.

:data:`TOOLPATH_DTYPE` mirrors ``TC_TOOLPATH_RECORD`` of ``include/tgm_cnc.h`` (168
bytes, every field documented there): ``start``, ``end`` (programmed, mm, machine
coordinates, x y z), ``tool_end`` (the tool centre's path after radius compensation;
its start is the previous record's ``tool_end``), ``centre``, ``radius``, ``length``,
``feed``, ``value``, ``kind`` (:class:`~sf_tch.enums.PartKind`), ``number`` (G or M
number), ``line``, ``file_index``, ``plane``, ``compensation``, ``flags``, ``tool``,
``spindle``, ``feed_factor``. :func:`fetch` has the library fill such an array in one
call; :class:`Toolpath` adds the file names and samples arcs for drawing.
"""
from __future__ import annotations

import ctypes
from dataclasses import dataclass

import numpy as np

from . import abi
from .enums import GFunction, PartKind

TOOLPATH_DTYPE = np.dtype(abi.TC_TOOLPATH_RECORD)
assert TOOLPATH_DTYPE.itemsize == 168, "TC_TOOLPATH_RECORD is 168 bytes (include/tgm_cnc.h)"

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
        kinds = np.bincount(self.records["kind"], minlength=5)
        return (f"<Toolpath {len(self)} parts: {kinds[PartKind.MOTION]} moves, "
                f"{kinds[PartKind.M_FUNCTION]} M functions, {kinds[PartKind.DWELL]} dwells, "
                f"{kinds[PartKind.PRINT]} prints>")

    @property
    def motion(self) -> np.ndarray:
        """A copy of the records of the motion parts only (G0 G1 G2 G3 G33)."""
        return self.records[self.records["kind"] == PartKind.MOTION]

    def tool_start(self) -> np.ndarray:
        """(n, 3): where the tool centre's path of each part starts, the previous
        part's ``tool_end`` (the first part's: its ``start``)."""
        starts = np.empty((len(self.records), 3))
        starts[:1] = self.records["start"][:1]
        starts[1:] = self.records["tool_end"][:-1]
        return starts

    def file_of(self, record) -> str:
        """File name of a record (its file_index)."""
        return self.files.get(int(record["file_index"]), "__unknown__")

    def to_dict(self) -> dict:
        """Summary as plain types: counts and lengths (mm) of cuts and rapids."""
        kind, number, length = self.records["kind"], self.records["number"], self.records["length"]
        moves = kind == PartKind.MOTION
        rapid = moves & (number == GFunction.RAPID)
        cut = moves & ~rapid
        return {"parts": len(self), "moves": int(moves.sum()),
                "m_functions": int((kind == PartKind.M_FUNCTION).sum()),
                "cut_parts": int(cut.sum()), "rapid_parts": int(rapid.sum()),
                "cut_length": float(length[cut].sum()), "rapid_length": float(length[rapid].sum())}

    def _moves(self, tool: bool) -> _Moves:
        keep = self.records["kind"] == PartKind.MOTION
        starts = self.tool_start()[keep] if tool else self.records["start"][keep]
        return _Moves(starts, self.records["tool_end" if tool else "end"][keep], self.records["centre"][keep],
                      self.records["number"][keep], self.records["plane"][keep])

    def points(self, step: float = 0.5, tool: bool = False) -> np.ndarray:
        """Every move in order as one (n, 3) array of points (mm): the first move's
        start, then for each move its end, arcs sampled so that no chord spans more
        than `step` mm of arc. `tool`: the compensated path instead of the programmed."""
        moves = self._moves(tool)
        if len(moves.start) == 0:
            return np.empty((0, 3))
        samples, _ = _sample(moves, step)
        return np.concatenate([moves.start[:1], samples])

    def polyline(self, step: float = 0.5, tool: bool = False) -> list[Run]:
        """The moves as runs of rapids and of cuts (a new run where they change, or
        where a move does not start at the previous one's end), arcs sampled as in
        :meth:`points`; for drawing, e.g. rapids dashed."""
        moves = self._moves(tool)
        if len(moves.start) == 0:
            return []
        rapid = moves.number == GFunction.RAPID
        breaks = np.flatnonzero((rapid[1:] != rapid[:-1])
                                | np.any(np.abs(moves.start[1:] - moves.end[:-1]) > 1e-9, axis=1)) + 1
        samples, counts = _sample(moves, step)
        offsets = np.concatenate([[0], np.cumsum(counts)])
        runs = []
        for first, last in zip(np.concatenate([[0], breaks]), np.concatenate([breaks, [len(rapid)]])):
            pts = np.concatenate([moves.start[first:first + 1], samples[offsets[first]:offsets[last]]])
            runs.append(Run(bool(rapid[first]), pts))
        return runs


@dataclass(frozen=True)
class _Moves:
    """The fields of the motion parts that drawing needs, for one of the two paths."""

    start: np.ndarray
    end: np.ndarray
    centre: np.ndarray
    number: np.ndarray
    plane: np.ndarray


def _sample(moves: _Moves, step: float) -> tuple[np.ndarray, np.ndarray]:
    """The points after each move's start (its arc samples, its end last), all moves,
    and how many each move has: 1 for a line, enough for an arc that no chord spans
    more than `step` mm of arc (at most 720)."""
    if not step > 0:
        raise ValueError("step must be positive")
    n = len(moves.start)
    arc = ((moves.number == GFunction.ARC_CW) | (moves.number == GFunction.ARC_CCW)) \
        & np.isin(moves.plane, list(_PLANE_AXES))
    first, second = np.zeros(n, int), np.ones(n, int)
    for plane, (a, b) in _PLANE_AXES.items():
        on = moves.plane == plane
        first[on], second[on] = a, b
    rows = np.arange(n)
    s, e, c = moves.start, moves.end, moves.centre
    sa, sb = s[rows, first] - c[rows, first], s[rows, second] - c[rows, second]
    a0 = np.arctan2(sb, sa)
    sweep = np.arctan2(e[rows, second] - c[rows, second], e[rows, first] - c[rows, first]) - a0
    # in the arc's direction, in (0, 2 pi]: equal start and end make a full circle
    ccw = moves.number == GFunction.ARC_CCW
    sweep = np.where(ccw, np.mod(sweep - 1e-12, 2 * np.pi) + 1e-12, -(np.mod(-sweep - 1e-12, 2 * np.pi) + 1e-12))
    radius = np.hypot(sa, sb)
    counts = np.ones(n, np.int64)
    counts[arc] = np.clip(np.ceil(np.abs(sweep[arc]) * radius[arc] / step), 1, 720).astype(np.int64)

    owner = np.repeat(rows, counts)
    within = np.arange(len(owner)) - np.repeat(np.cumsum(counts) - counts, counts)
    t = (within + 1) / counts[owner]                        # (0, 1], 1 = the move's end
    points = s[owner] + (e[owner] - s[owner]) * t[:, None]  # lines; the normal axis of helices
    on_arc = np.flatnonzero(arc[owner])
    k = owner[on_arc]
    angle = a0[k] + sweep[k] * t[on_arc]
    points[on_arc, first[k]] = c[k, first[k]] + radius[k] * np.cos(angle)
    points[on_arc, second[k]] = c[k, second[k]] + radius[k] * np.sin(angle)
    points[np.cumsum(counts) - 1] = e                       # ends exactly as the library has them
    return points, counts
