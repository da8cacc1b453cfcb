"""The axis correction tables ACHS3D??.KOR (docs/axis-correction.md).
The vendor sets it through TG Motion; a library reaches it through this project's extension
exports, so each check is not applicable where they are missing."""
import struct
from ctypes import c_double

from .checks import check, expect, near, near_point

X = "axis-correction.md"


def _axis_table(host, name="ACHS3D01.KOR", number=1, header=b"ZXY"):
    """Z over X and Y on a 3 × 3 grid over 0 … 100: z = 0.01 x + 0.02 y."""
    data = header + b"\0" * (127 - len(header)) + bytes([number])
    data += struct.pack("<ffI", 0.0, 100.0, 3) + struct.pack("<ffI", 0.0, 100.0, 3)
    for x in (0.0, 50.0, 100.0):
        for y in (0.0, 50.0, 100.0):          # the last basis axis fastest
            data += struct.pack("<f", 0.01 * x + 0.02 * y)
    return host.file(name, data)


def _load_axes(host, *paths):
    load = host.need("ToolChainCore_LoadAxisCorrections")
    names = (host.texts.type * len(paths))(*[host.texts.arg(p) for p in paths])
    return load(0, len(paths), names)


def _correct(host, x, y, z=0.0):
    fn = host.need("ToolChainCore_CorrectPosition")
    out = (c_double * 10)()
    expect(0, fn(0, (c_double * 10)(x, y, z), out), "CorrectPosition")
    return tuple(out)[:3]


@check("axis_tables", "axis_table_grid", X, "Interpolation",
       "an axis table adds exactly the correction at a grid point, bilinear between grid points")
def _(host):
    expect(0, _load_axes(host, _axis_table(host)), "LoadAxisCorrections")
    near(1.5, _correct(host, 50, 50)[2], 1e-6, "z at the grid point (50, 50)")
    near(0.25 + 0.5, _correct(host, 25, 25)[2] - 0.0, 1e-6, "z between grid points (25, 25)")
    near_point((25, 25), _correct(host, 25, 25)[:2], 1e-12, "x, y unchanged")


@check("axis_tables", "axis_table_edge", X, "Interpolation",
       "outside the grid an axis table keeps the edge value")
def _(host):
    expect(0, _load_axes(host, _axis_table(host)), "LoadAxisCorrections")
    near(1.0 + 0.0, _correct(host, 250, -40)[2], 1e-6, "z at (250, -40): the value at (100, 0)")


@check("axis_tables", "axis_table_refused_keeps", X, "The file, byte for byte",
       "a table whose header names no basis axis is refused and the core keeps the tables it had")
def _(host):
    expect(0, _load_axes(host, _axis_table(host)), "LoadAxisCorrections")
    bad = _axis_table(host, "ACHS3D02.KOR", 2, header=b"Z")
    expect(-1, _load_axes(host, bad), "LoadAxisCorrections of a bad table")
    near(1.5, _correct(host, 50, 50)[2], 1e-6, "z at (50, 50) afterwards")


