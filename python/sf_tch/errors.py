"""Errors and warnings of the library as Python values: :class:`Diagnostic` (one
error or warning with its place) and the exceptions the package raises."""
from __future__ import annotations

import re
from dataclasses import dataclass

from .enums import ErrorNumber


def _number(value: int) -> int:
    """The catalogue's enum member when the number is known, else the int."""
    try:
        return ErrorNumber(value)
    except ValueError:
        return value


# IdxToFile's names of the special file indexes -1..-4: no file to point at
_NO_FILE = ("__unknown__", "__end__", "__stop__", "__exec__")


@dataclass(frozen=True)
class Diagnostic:
    """One error or warning: catalogue number, file, 1-based line (0 unknown), 1-based
    column (``None``: the library reports lines only, and the column could not be
    found from the error's argument), the English text and its arguments."""

    severity: str               # "error" or "warning"
    number: int                 # ErrorNumber when in the catalogue
    file: str
    line: int
    text: str
    arguments: tuple = ()
    column: int | None = None

    def __str__(self) -> str:
        """``file:line:col: error N: text`` on one line, the form compilers and editors
        read (a line break of the text, as in the vendor's three-line error 400, printed
        as ``; ``); ``error N: text`` for an error of no file (e.g. a file that cannot be
        opened)."""
        text = self.text.replace("\n", "; ")
        if self.line <= 0 and self.file in _NO_FILE:
            return f"{self.severity} {int(self.number)}: {text}"
        place = f"{self.file}:{self.line}:" + (f"{self.column}:" if self.column else "")
        return f"{place} {self.severity} {int(self.number)}: {text}"

    def to_dict(self) -> dict:
        """Plain types only (JSON-ready); ``fields``: the details of the longer messages
        by name (an arc's start and end, radii)."""
        return {"severity": self.severity, "number": int(self.number),
                "name": self.number.name if isinstance(self.number, ErrorNumber) else None,
                "file": self.file, "line": self.line, "column": self.column, "text": self.text,
                "arguments": list(self.arguments), "fields": _fields(self.number, self.arguments)}


# The arc-centre errors in the vendor's form: the plane and its two axes are in the text
_ARC_FORMAT = re.compile(r"interpolation (\w+)\nStart (\w) = %g (\w) = %g \| End")
_ARC_CENTRE = {400, 415, 416, 417}      # the chord longer than the diameter
_ARC_RADII = {407, 418, 419, 420}       # the radii at start and end differ


def _fields(number: int, arguments: tuple) -> dict:
    """The arguments of a message by name, where they are more than a word and its column."""
    a = arguments
    try:
        if number in _ARC_CENTRE | _ARC_RADII and len(a) == 6:
            plane, first, second = _ARC_FORMAT.search(ErrorNumber(number).format).groups()
            fields = {"plane": plane, "start": {first: float(a[0]), second: float(a[1])},
                      "end": {first: float(a[2]), second: float(a[3])}}
            if number in _ARC_CENTRE:
                fields.update(chord=float(a[4]), diameter=float(a[5]))
            else:
                fields.update(radius_start=float(a[4]), radius_end=float(a[5]))
            return fields
        if number == ErrorNumber.ARC_RADIUS and len(a) == 2:
            return {"radius": float(a[0]), "chord": float(a[1])}
        if number == ErrorNumber.COMP_NEGATIVE_ARC and len(a) == 2:
            return {"arc_radius": float(a[0]), "tool_radius": float(a[1])}
        if number == ErrorNumber.COMP_CROSSING and len(a) == 1:
            return {"tool_radius": float(a[0])}
    except ValueError:
        pass
    return {}


# Errors whose first argument is text of the line as written (a word, a number, an
# address letter, an expression, a label, a condition): it gives the column.
_SOURCE_TEXT_ARGUMENT = frozenset({
    ErrorNumber.UNKNOWN_WORD, ErrorNumber.BAD_NUMBER, ErrorNumber.MISSING_VALUE, ErrorNumber.BAD_EXPRESSION,
    ErrorNumber.UNKNOWN_FUNCTION, ErrorNumber.UNDEFINED_LABEL, ErrorNumber.DUPLICATE_LABEL,
    ErrorNumber.BAD_CONDITION,
})


_LIBRARY_COLUMN = re.compile(r" at column (\d+)")


def locate_column(source_line: str | None, number: int, arguments: tuple, text: str = "") -> int | None:
    """1-based column of a diagnostic in its source line: the one the library's text gives
    ("... at column N"), else where its text argument occurs in the line, when it occurs
    there exactly once, else the block's: the first word of the line (an error of the
    whole move, like the compensation's); None without the line."""
    given = _LIBRARY_COLUMN.search(text)
    if given:
        return int(given.group(1))
    if source_line is None:
        return None
    if number in _SOURCE_TEXT_ARGUMENT and arguments and arguments[0] and source_line.count(arguments[0]) == 1:
        return source_line.index(arguments[0]) + 1
    stripped = source_line.lstrip(" \t")
    return len(source_line) - len(stripped) + 1 if stripped.strip() else None


class SfTchError(Exception):
    """Base of the exceptions of this package."""


class GougeWarning(UserWarning):
    """Warning 601 of a compilation: the compensated tool path cuts into the contour
    (``warnings.simplefilter("error", GougeWarning)`` makes it an exception; or
    compile with ``strict=True``, which refuses such a program with error 504)."""


class LibraryNotFoundError(SfTchError, FileNotFoundError):
    """``libSF_TCh.so`` is neither where ``SF_TCH_LIBRARY`` says, nor installed."""


class NoFreeCoreError(SfTchError, RuntimeError):
    """Every core of the library is in use by this process."""


class CncError(SfTchError):
    """An error the library reported (GetLastError, DispAndLocateError): the number,
    file, line, column (may be None), text and arguments of its :class:`Diagnostic`."""

    def __init__(self, number: int, line: int, file: str, text: str, arguments: tuple = (),
                 column: int | None = None):
        self.diagnostic = Diagnostic("error", _number(number), file, line, text, tuple(arguments), column)
        super().__init__(str(self.diagnostic))

    @classmethod
    def from_diagnostic(cls, diagnostic: Diagnostic) -> CncError:
        """The exception of a diagnostic (the cancelled compilation: :class:`Cancelled`)."""
        kind = Cancelled if diagnostic.number == ErrorNumber.CANCELLED else cls
        return kind(diagnostic.number, diagnostic.line, diagnostic.file, diagnostic.text,
                    diagnostic.arguments, diagnostic.column)

    number = property(lambda self: self.diagnostic.number, doc="catalogue number (ErrorNumber)")
    line = property(lambda self: self.diagnostic.line, doc="1-based line, 0 unknown")
    file = property(lambda self: self.diagnostic.file, doc="file name as the library knows it")
    column = property(lambda self: self.diagnostic.column, doc="1-based column or None")
    text = property(lambda self: self.diagnostic.text, doc="the English text")
    arguments = property(lambda self: self.diagnostic.arguments, doc="the text's arguments")

    def __str__(self) -> str:
        return str(self.diagnostic)

    def __repr__(self) -> str:
        return f"{type(self).__name__}({self.diagnostic})"

    def to_dict(self) -> dict:
        """The diagnostic as plain types."""
        return self.diagnostic.to_dict()


class Cancelled(CncError):
    """The compilation was interrupted (cancel(), a cancel event, Ctrl-C)."""
