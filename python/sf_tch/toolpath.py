"""The toolpath of a compiled program as a numpy structured array.

:data:`TOOLPATH_DTYPE` mirrors ``TC_TOOLPATH_RECORD`` of ``include/tgm_cnc.h`` (168
bytes, every field documented there): ``start``, ``end`` (programmed, mm, machine
coordinates, x y z), ``tool_end`` (the tool centre's path after radius compensation;
its start is the previous record's ``tool_end``), ``centre``, ``radius``, ``length``,
``feed``, ``value``, ``kind`` (:class:`~sf_tch.enums.PartKind`), ``number`` (G or M
number), ``line``, ``file_index``, ``plane``, ``compensation``, ``flags``, ``tool``,
``spindle``, ``feed_factor``. :func:`fetch` has the library fill such an array in one
call, :func:`read_chunks` reads it a bounded chunk at a time (a summary of a program
of any size, :func:`summarize`); :class:`Toolpath` adds the file names and samples
arcs for drawing, a bounded number of moves at a time.
"""
from __future__ import annotations

import ctypes
from dataclasses import dataclass
from typing import Iterable, Iterator

import numpy as np

from . import abi
from .enums import GFunction, PartKind

TOOLPATH_DTYPE = np.dtype(abi.TC_TOOLPATH_RECORD)
assert TOOLPATH_DTYPE.itemsize == 168, "TC_TOOLPATH_RECORD is 168 bytes (include/tgm_cnc.h)"

# first and second axis of each arc plane (geometry.pyx of the library)
_PLANE_AXES = {17: (0, 1), 18: (0, 2), 19: (1, 2), -18: (2, 0)}

# Records read or sampled per step: the temporaries of a step stay a few MB whatever
# the program's size (a 1,000,000-line program is 168 MB of records).
CHUNK_RECORDS = 16384
_SAMPLES_PER_STEP = 16384


def fetch(lib: ctypes.CDLL, core: int) -> np.ndarray:
    """The whole toolpath of the core's compiled program: asks the library for the
    number of records, allocates the array, and has the library fill it (one copy).
    Raises RuntimeError when the core has no compiled program."""
    total = _total(lib, core)
    records = np.empty(total, TOOLPATH_DTYPE)
    _read(lib, core, records, 0, total)
    return records


def read_chunks(lib: ctypes.CDLL, core: int, size: int = CHUNK_RECORDS) -> Iterator[np.ndarray]:
    """The toolpath of the core's compiled program in order, at most `size` records
    at a time, read into one buffer: each chunk is valid until the next is read
    (copy what you keep). Raises RuntimeError as :func:`fetch`."""
    total = _total(lib, core)
    buffer = np.empty(max(1, min(size, total)), TOOLPATH_DTYPE)
    for first in range(0, total, len(buffer)):
        count = min(len(buffer), total - first)
        _read(lib, core, buffer, first, total)
        yield buffer[:count]


def _total(lib: ctypes.CDLL, core: int) -> int:
    total = ctypes.c_uint64()
    if lib.ToolChainCore_GetToolpath(core, None, 0, 0, ctypes.byref(total)) != abi.TOOL_CHAIN_SUCCESS:
        raise RuntimeError(f"core {core} has no compiled program")
    return total.value


def _read(lib: ctypes.CDLL, core: int, out: np.ndarray, first: int, total: int) -> None:
    """Records [first, first + len(out)) into `out`; the program must still have `total`."""
    again = ctypes.c_uint64()
    pointer = out.ctypes.data_as(ctypes.POINTER(abi.TC_TOOLPATH_RECORD))
    if (lib.ToolChainCore_GetToolpath(core, pointer, len(out), first, ctypes.byref(again)) != abi.TOOL_CHAIN_SUCCESS
            or again.value != total):
        raise RuntimeError(f"the program of core {core} changed while it was read")


def summarize(chunks: Iterable[np.ndarray]) -> dict:
    """Counts and lengths (mm) of the parts, cuts and rapids of records given in one
    or more chunks (:func:`read_chunks`), as plain types."""
    summary = dict.fromkeys(("parts", "moves", "m_functions", "cut_parts", "rapid_parts"), 0)
    summary.update(cut_length=0.0, rapid_length=0.0)
    for records in chunks:
        kind, number, length = records["kind"], records["number"], records["length"]
        moves = kind == PartKind.MOTION
        rapid = moves & (number == GFunction.RAPID)
        cut = moves & ~rapid
        summary["parts"] += len(records)
        summary["moves"] += int(moves.sum())
        summary["m_functions"] += int((kind == PartKind.M_FUNCTION).sum())
        summary["cut_parts"] += int(cut.sum())
        summary["rapid_parts"] += int(rapid.sum())
        summary["cut_length"] += float(length[cut].sum())
        summary["rapid_length"] += float(length[rapid].sum())
    return summary


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
        return summarize(self.records[k:k + CHUNK_RECORDS] for k in range(0, len(self.records), CHUNK_RECORDS))

    def points(self, step: float = 0.5, tool: bool = False) -> np.ndarray:
        """Every move in order as one (n, 3) array of points (mm): the first move's
        start, then for each move its end, arcs sampled so that no chord spans more
        than `step` mm of arc. `tool`: the compensated path instead of the programmed.
        Sampled a bounded number of moves at a time: beside the array it returns,
        it needs a few bytes per move."""
        return self._sample(step, tool).points

    def polyline(self, step: float = 0.5, tool: bool = False) -> list[Run]:
        """The moves as runs of rapids and of cuts (a new run where they change, or
        where a move does not start at the previous one's end), arcs sampled as in
        :meth:`points`; for drawing, e.g. rapids dashed. A run's points are a view
        into one array of every point (a copy only for a run after a gap)."""
        sampled = self._sample(step, tool)
        rapid, gap = sampled.rapid, sampled.gap
        if len(rapid) == 0:
            return []
        breaks = np.flatnonzero((rapid[1:] != rapid[:-1]) | gap[1:]) + 1
        firsts = np.concatenate([[0], breaks])
        # points[ends[i]] is the end of move i (points[0] the first move's start): a run
        # from move `first` to move `last` spans points[ends[first - 1] .. ends[last]]
        ends = np.cumsum(sampled.counts, dtype=np.int64)
        begins = np.concatenate([[0], ends[breaks - 1]]).tolist()
        stops = (ends[np.concatenate([breaks, [len(rapid)]]) - 1] + 1).tolist()
        points, gap_starts = sampled.points, sampled.gap_starts
        runs = []
        for first, begin, stop, is_rapid in zip(firsts.tolist(), begins, stops, rapid[firsts].tolist()):
            if first in gap_starts:
                pts = np.concatenate([gap_starts[first][None, :], points[begin + 1:stop]])
            else:
                pts = points[begin:stop]
            runs.append(Run(is_rapid, pts))
        return runs

    def _sample(self, step: float, tool: bool) -> _Sampled:
        """The points of :meth:`points` and, per move, its number of points, whether
        it is a rapid and whether it starts away from the previous move's end. Two
        passes over the records a chunk at a time: the number of points of every
        move, then the points into the one array of them all."""
        if not step > 0:
            raise ValueError("step must be positive")
        chunks = range(0, len(self.records), CHUNK_RECORDS)
        counts, rapid, gap, gap_starts = [], [], [], {}
        previous_end, moves_before = None, 0
        for lo in chunks:
            moves = self._moves(lo, tool)
            shape = _ArcShape(moves, step)
            counts.append(shape.counts.astype(np.int32))
            rapid.append(moves.number == GFunction.RAPID)
            if len(moves.start):
                joined = np.concatenate([moves.end[:1] if previous_end is None else previous_end, moves.end[:-1]])
                away = np.any(np.abs(moves.start - joined) > 1e-9, axis=1)
                gap.append(away)
                for k in np.flatnonzero(away):
                    gap_starts[moves_before + int(k)] = moves.start[k].copy()
                previous_end = moves.end[-1:].copy()
                moves_before += len(moves.start)
        counts = np.concatenate(counts) if counts else np.empty(0, np.int32)
        rapid = np.concatenate(rapid) if rapid else np.empty(0, bool)
        gap = np.concatenate(gap) if gap else np.empty(0, bool)
        points = np.empty((int(counts.sum(dtype=np.int64)) + (1 if len(counts) else 0), 3))
        written = 1
        for lo in chunks:
            moves = self._moves(lo, tool)
            if len(moves.start) == 0:
                continue
            if written == 1:
                points[0] = moves.start[0]
            written += _ArcShape(moves, step).fill(points[written:])
        return _Sampled(points, counts, rapid, gap, gap_starts)

    def _moves(self, lo: int, tool: bool) -> _Moves:
        """The motion parts among records [lo, lo + CHUNK_RECORDS), on one of the two paths."""
        records = self.records[lo:lo + CHUNK_RECORDS]
        keep = records["kind"] == PartKind.MOTION
        if tool:
            starts = np.empty((len(records), 3))
            starts[:1] = self.records["tool_end"][lo - 1] if lo else records["start"][:1]
            starts[1:] = records["tool_end"][:-1]
            starts = starts[keep]
        else:
            starts = records["start"][keep]
        return _Moves(starts, records["tool_end" if tool else "end"][keep], records["centre"][keep],
                      records["number"][keep], records["plane"][keep])


@dataclass(frozen=True)
class _Moves:
    """The fields of the motion parts that drawing needs, for one of the two paths."""

    start: np.ndarray
    end: np.ndarray
    centre: np.ndarray
    number: np.ndarray
    plane: np.ndarray


@dataclass(frozen=True)
class _Sampled:
    """What :meth:`Toolpath._sample` gives: every point, and per move its number of
    points, rapid or not, away from the previous end or not (the start of each such
    move in ``gap_starts``, by move index)."""

    points: np.ndarray
    counts: np.ndarray
    rapid: np.ndarray
    gap: np.ndarray
    gap_starts: dict


class _ArcShape:
    """The arcs among some moves (G2/G3 in a known plane): the plane's two axes, the
    start angle, the sweep and the radius of each, and how many points each move
    gets: 1 for a line, enough for an arc that no chord spans more than `step` mm of
    arc (at most 720)."""

    def __init__(self, moves: _Moves, step: float):
        self.moves = moves
        n = len(moves.start)
        self.arc = ((moves.number == GFunction.ARC_CW) | (moves.number == GFunction.ARC_CCW)) \
            & np.isin(moves.plane, list(_PLANE_AXES))
        self.first, self.second = np.zeros(n, np.int8), np.ones(n, np.int8)
        for plane, (a, b) in _PLANE_AXES.items():
            on = moves.plane == plane
            self.first[on], self.second[on] = a, b
        rows = np.arange(n)
        s, e, c = moves.start, moves.end, moves.centre
        first, second = self.first, self.second
        sa, sb = s[rows, first] - c[rows, first], s[rows, second] - c[rows, second]
        self.a0 = np.arctan2(sb, sa)
        sweep = np.arctan2(e[rows, second] - c[rows, second], e[rows, first] - c[rows, first]) - self.a0
        # in the arc's direction, in (0, 2 pi]: equal start and end make a full circle
        ccw = moves.number == GFunction.ARC_CCW
        self.sweep = np.where(ccw, np.mod(sweep - 1e-12, 2 * np.pi) + 1e-12,
                              -(np.mod(-sweep - 1e-12, 2 * np.pi) + 1e-12))
        self.radius = np.hypot(sa, sb)
        self.counts = np.ones(n, np.int64)
        arc = self.arc
        self.counts[arc] = np.clip(np.ceil(np.abs(self.sweep[arc]) * self.radius[arc] / step), 1, 720)

    def fill(self, out: np.ndarray) -> int:
        """Writes the points after each move's start (its arc samples, its end last)
        to the front of `out`, a bounded number of points at a time; returns how many."""
        ends = np.cumsum(self.counts)
        written, lo = 0, 0
        while lo < len(self.counts):
            # the moves whose points fit in one step (at least one move)
            hi = max(lo + 1, int(np.searchsorted(ends, written + _SAMPLES_PER_STEP, side="right")))
            count = int(ends[hi - 1]) - written
            self._fill_moves(lo, hi, out[written:written + count])
            written += count
            lo = hi
        return written

    def _fill_moves(self, lo: int, hi: int, out: np.ndarray) -> None:
        m = self.moves
        counts = self.counts[lo:hi]
        s, e = m.start[lo:hi], m.end[lo:hi]
        owner = np.repeat(np.arange(hi - lo), counts)
        within = np.arange(len(owner)) - np.repeat(np.cumsum(counts) - counts, counts)
        t = (within + 1) / counts[owner]                        # (0, 1], 1 = the move's end
        np.multiply(e[owner] - s[owner], t[:, None], out=out)   # lines; the normal axis of helices
        out += s[owner]
        on_arc = np.flatnonzero(self.arc[lo:hi][owner])
        if len(on_arc):
            k = owner[on_arc] + lo
            first, second = self.first[k], self.second[k]
            angle = self.a0[k] + self.sweep[k] * t[on_arc]
            out[on_arc, first] = m.centre[k, first] + self.radius[k] * np.cos(angle)
            out[on_arc, second] = m.centre[k, second] + self.radius[k] * np.sin(angle)
        out[np.cumsum(counts) - 1] = e                          # ends exactly as the library has them
