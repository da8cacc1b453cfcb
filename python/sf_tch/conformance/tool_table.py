"""The tool correction table TAB0.KOR (docs/tool-table.md).
The vendor sets it through TG Motion; a library reaches it through this project's extension
exports, so each check is not applicable where they are missing."""
from ctypes import c_double

from .checks import check, expect, near_point

T = "tool-table.md"

# The tool compensation manual's example file (docs/tool-table.md, "The file").
MANUAL_TABLE = """$KOR
01: R=10.0 X=20.0 Y=30.0 Z=40.0
02: R=0.8 X=0.0 2=0.0
03: R=0.8 X=0.0 Y=120.0 Z=0.0 4=0.0
25:  X=85.0 Y=45.5 Z=0.0
95: R=0.0 1=12.55 2=0.0 3=0.0 4=0.0

$KOR
01: R=0.0 X=0.0 Y=0.0 Z=0.0 4=0.0
"""


def _entry(host, n):
    values = (c_double * 5)()
    expect(0, host.need("ToolChainCore_GetToolCorrection")(0, n, values), f"GetToolCorrection({n})")
    return tuple(values)


def _load_table(host, text, name="TAB0.KOR"):
    path = host.file(name, text)
    return host.need("ToolChainCore_LoadToolTable")(0, host.texts.arg(path))


@check("tool_table", "tool_table_manual_example", T, "The file",
       "the manual's example TAB0.KOR: entries 2, 3, 25 and 95 as written (R, then axes 1–4), a value not given 0")
def _(host):
    expect(0, _load_table(host, MANUAL_TABLE), "LoadToolTable")
    expect((0.8, 0, 0, 0, 0), _entry(host, 2), "entry 2")
    expect((0.8, 0, 120, 0, 0), _entry(host, 3), "entry 3")
    expect((0, 85, 45.5, 0, 0), _entry(host, 25), "entry 25")
    expect((0, 12.55, 0, 0, 0), _entry(host, 95), "entry 95")
    expect((0, 0, 0, 0, 0), _entry(host, 40), "entry 40 (not in the file)")


@check("tool_table", "tool_table_refused_keeps", T, "The file",
       "a file not in the format is refused and the table in memory stays as it was")
def _(host):
    expect(0, _load_table(host, MANUAL_TABLE), "LoadToolTable")
    rc = _load_table(host, "$KOR\n02: R=zero\n", "BAD.KOR")
    expect(-1, rc, "LoadToolTable of a bad file")
    expect((0.8, 0, 0, 0, 0), _entry(host, 2), "entry 2 afterwards")


@check("tool_table", "tool_table_g92_write", T, "Loading and writing",
       "G92 D12 R0=10.0 R2=25.5 R3=-5.0 (SetToolCorrection with programmed 0b01101) writes those values only")
def _(host):
    set_ = host.need("ToolChainCore_SetToolCorrection")
    expect(0, _load_table(host, MANUAL_TABLE.replace("25:", "12: R=1 X=2 Y=3 Z=4 4=5\n25:")), "LoadToolTable")
    expect(0, set_(0, 12, 0b01101, (c_double * 5)(10.0, 0, 25.5, -5.0, 0)), "SetToolCorrection")
    expect((10.0, 2.0, 25.5, -5.0, 5.0), _entry(host, 12), "entry 12")


@check("tool_table", "tool_table_d_radius", T, "In programs",
       "G41 D n compensates with entry n's radius")
def _(host):
    expect(0, _load_table(host, MANUAL_TABLE), "LoadToolTable")
    code = ("G41 D3 G1 X0 Y-10 F1000\nG1 X10 Y-10\nG1 X10 Y10\nG1 X-10 Y10\nG1 X-10 Y-10\nG1 X0 Y-10\n"
            "G40 G1 X0 Y-20\n")
    parts = host.simulate(code, coords=(0.0, -20.0, 0.0)).of("G")
    near_point((9.2, -9.2), parts[1]["ce"][:2], 1e-6, "inner corner with radius 0.8")


