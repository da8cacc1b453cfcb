"""Structures: the sizes GetStructuresSize reports, the offsets the library reads
and writes, the defaults of GetGCodeParameters (docs/structures.md, docs/api.md)."""
import ctypes

from .. import abi
from .checks import Differs, check, expect, near

S, A = "structures.md", "api.md"


def _sizes(host):
    n = 1 + len(abi.STRUCTURES_SIZE_ORDER)
    arr = (ctypes.c_uint32 * n)()
    rc = host.lib.ToolChainCore_GetStructuresSize(0, n, arr)
    expect(0, rc, "GetStructuresSize")
    return list(arr)


@check("structures", "sizes_count", A, "Lifecycle",
       "GetStructuresSize's first number says how many sizes follow: 8")
def _(host):
    expect(len(abi.STRUCTURES_SIZE_ORDER), _sizes(host)[0], "sizes[0]")


def _size_check(i, name):
    @check("structures", f"size_{name}", A, "Lifecycle",
           f"GetStructuresSize's entry {i + 1} is the size of {name} in the vendor's field order")
    def _(host):
        structures, _ = abi.mirror(host.windows)
        expect(ctypes.sizeof(structures[name]), _sizes(host)[i + 1], f"sizeof {name}")


for _i, _name in enumerate(abi.STRUCTURES_SIZE_ORDER):
    _size_check(_i, _name)


@check("structures", "sizes_short_buffer", A, "Lifecycle",
       "GetStructuresSize fills up to nItems numbers and no more")
def _(host):
    arr = (ctypes.c_uint32 * 4)(0, 0, 0, 0xDEADBEEF)
    rc = host.lib.ToolChainCore_GetStructuresSize(0, 3, arr)
    expect(0, rc, "GetStructuresSize(nItems 3)")
    expect(0xDEADBEEF, arr[3], "the number after nItems")


def _default(name, field, expected, tol=None, section="GCODE_PARAMETERS — a core's G-code properties"):
    @check("structures", f"default_{name}", S, section,
           f"GetGCodeParameters of a fresh core gives the vendor's default {field} = {expected}")
    def _(host):
        value = eval("p." + field, {}, {"p": host.defaults[0]})  # the core as it started
        if tol is None:
            expect(expected, value, field)
        else:
            near(expected, value, tol, field)


_default("absMode", "absMode", 1)
_default("swapG2G3", "swapG2G3", 0)
_default("correctionStrategy", "correctionStrategy", 0x600)
_default("forceMode", "forceMode", 0)
_default("overrideInc", "overrideInc", 0.001, 1e-12)
_default("insertArcToleranceRMax", "insertArcToleranceRMax", 0.03, 1e-12)
_default("insertArcToleranceRMin", "insertArcToleranceRMin", 0.03, 1e-12)
_default("tolerance0", "tolerance[0]", 0.005, 1e-12)
_default("tolerance1", "tolerance[1]", 0.001, 1e-12)
_default("tolerance2", "tolerance[2]", 0.03, 1e-12)
_default("tolerance3", "tolerance[3]", 0.005, 1e-12)
_default("calcTime", "calcTime", 0)


@check("structures", "default_m_numbers", S, "GCODE_PARAMETERS — a core's G-code properties",
       "the built-in M functions default to their own numbers (M02_programEnd1 = 2 … M99_defFeed = 99)")
def _(host):
    p = host.defaults[0]
    for field in abi.M_FUNCTION_FIELDS:
        expect(int(field[1:3]), getattr(p, field), field)


@check("structures", "default_arc_feed_table_off", S, "GCODE_PARAMETERS — a core's G-code properties",
       "the arc feed table is off by default (all zero)")
def _(host):
    for i, e in enumerate(host.defaults[0].arcFeedTable):
        expect((0.0, 0.0), (e.m_r, e.m_relFeed), f"arcFeedTable[{i}]")


@check("structures", "defaults_every_core", A, "Conventions",
       "each of the three cores has its own parameters, and all start alike")
def _(host):
    first = bytes(host.defaults[0])
    for core in (1, 2):
        if bytes(host.defaults[core]) != first:
            raise Differs("the same defaults on core 0 and core %d" % core, "different bytes")


@check("structures", "offsets_round_trip", S, "GCODE_PARAMETERS — a core's G-code properties",
       "SetGCodeParameters takes the whole structure and GetGCodeParameters gives it back: "
       "fields at the header's offsets, first to last")
def _(host):
    def edit(p):
        p.absMode, p.swapG2G3, p.forceMode = 0, 1, 2
        p.motion[6].dec = 1234.5
        p.correction[7].size = 0.75
        p.maxConnectionDistance = 7.25
        p.overrideInc = 0.002
        p.centripetalAcc = 321.0
        p.M99_defFeed = 98
        p.insertArcMaxAngle = 45.0
        p.calcTime = 1
        p.axisLimits[9].maxDec = 4321.0
        p.dynamicG42Correction_percent = 3.5
        p.tolerance[0] = 0.004
        p.tolerance[3] = 0.006
    host.set_params(0, edit=edit)
    want = abi.GCODE_PARAMETERS()
    ctypes.memmove(ctypes.byref(want), ctypes.byref(host.defaults[0]), ctypes.sizeof(want))
    edit(want)
    got = bytes(host.params(0))
    for name, *_ in abi.GCODE_PARAMETERS._fields_:
        f = getattr(abi.GCODE_PARAMETERS, name)
        if bytes(want)[f.offset:f.offset + f.size] != got[f.offset:f.offset + f.size]:
            back = abi.GCODE_PARAMETERS.from_buffer_copy(got)
            raise Differs(abi._value(getattr(want, name)), abi._value(getattr(back, name)), name)


@check("structures", "offsets_getpos_status", S, "GM_PARAMS_ENHANCED — GetPos",
       "GM_PARAMS_ENHANCED.m_statusCNC holds the same value as StatusCNC")
def _(host):
    host.compiled("G1 X1 F1000\n")
    _, enh = host.pos(0)
    expect(host.status(0), enh.m_statusCNC, "m_statusCNC")


@check("structures", "offsets_callback_info", S, "CALLBACK_INFO — errors and progress",
       "GetLastError fills CALLBACK_INFO: the number, the 1-based line, the file index, the full text")
def _(host):
    err = host.compile("G1 X1 F1000\n\nG1 X1/0\n", name="offsets.nc")
    if err is None:
        raise Differs("an error", None, "GetLastError")
    number, line, fidx, text, _ = err
    expect(3, line, "actLine")
    idx = host.lib.ToolChainCore_FileToIdx(0, host.texts.arg("offsets.nc"))
    expect(idx, fidx, "fileIdx")
    if not text:
        raise Differs("a text", text, "m_fullError")
    if number <= 0:
        raise Differs("an error number > 0", number, "stringId")


@check("structures", "offsets_simple_gm_params", S, "SIMPLE_GM_PARAMS — one part",
       "a part handed to DriverGFunc has its G number in m_func, its end in m_e, its line in m_editorLine, "
       "the feed in cell F")
def _(host):
    rec = host.simulate("G1 X3 Y4 F1500\n")
    parts = rec.of("G")
    expect(1, len(parts), "G parts")
    p = parts[0]
    expect((1, 1, 1500.0), (p["func"], p["line"], p["F"]), "m_func, m_editorLine, F")
    near(3.0, p["e"][0], 1e-9, "m_e.x")
    near(4.0, p["e"][1], 1e-9, "m_e.y")


@check("structures", "absent_letter_marker", S, "Building blocks",
       "a P26FLOAT cell of a letter the line did not write holds the marker (1e38 as a float)")
def _(host):
    p = host.simulate("G1 X3 Y4 F1500\n").of("G")[0]
    for letter in ("Q", "H"):
        if not p[letter] >= 1e37:
            raise Differs(">= 1e37 (the marker)", p[letter], f"cell {letter}")
