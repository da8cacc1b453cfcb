"""Statements of the vendor's documents that a panel relies on, each checked from a host
(docs/behaviour.md, "The vendor's statements"): the absent-address marker, the GetPos cells
of the G92 offsets, the cells set at every callback, the tool table's fourth axis, arcs
dropped from the cutting plan, the settings the vendor documents as not implemented, the
feed override's range, the limit test and the parameters of M functions, and what
SetGCodeParameters takes while the program stands on its trajectory. Core 1."""
import ctypes
import math
import struct

import numpy as np
import pytest

import sf_tch
from sf_tch import abi
from compiler_host import Host, ok
from runtime_host import simulate

CORE = 1
LETTERS = "ABCDEFGHIJKLMNOPQRSTUVWXYZ"


@pytest.fixture(scope="module")
def host(tmp_path_factory):
    h = Host(CORE, tmp_path_factory.mktemp("core1vendor"))
    yield h
    h.lib.ToolChainCore_SetGCodeParameters(h.core, ctypes.byref(h.defaults))
    h.lib.ToolChainCore_SetMachineParameters(h.core, ctypes.byref(abi.MACHINE_PARAMETERS()))
    h.close()


def raw_cells(gm):
    return {letter: getattr(gm.m_pars, letter) for letter in LETTERS}


def test_an_absent_address_holds_more_than_1e38_in_float_and_in_double():
    """The structures description: a cell of an address the block does not write holds a
    value > 1e38. 1e38f itself is 9.99999968e37, below it."""
    as_float = struct.unpack("<f", struct.pack("<f", abi.INVALID_VALUE))[0]
    assert abi.INVALID_VALUE > 1e38 and as_float > 1e38 and np.float32(abi.INVALID_VALUE) > np.float32(1e38)
    assert as_float == abi.INVALID_VALUE       # the same number as a float and as a double


def test_every_driver_callback_carries_the_marker_and_the_documented_cells(host):
    """Absent letters > 1e38 in every callback (compiler_host reads cells with that test);
    F (feed), N (the part's length) and S (spindle) at every callback, G at moves and
    dwells, also in a dwell and in M functions (the structures description's list)."""
    seen = []
    on_g = abi.DriverGFunc(lambda user, gm: seen.append(("G", raw_cells(gm.contents))) or 0)
    on_m = abi.DriverMFunc(lambda user, gm: seen.append(("M", raw_cells(gm.contents))) or 0)
    lib = host.lib
    r = host.compile("G1 X10 F1200 S500\nG4 H0.5\nM7\nM51 Q3\nG1 Y10\n", run=False, start=[0] * 10)
    assert r.error is None
    assert lib.ToolChainCore_SetCallBack(CORE, abi.CB_DRIVER_G_FUNC, 0, ctypes.cast(on_g, ctypes.c_void_p)) == 0
    assert lib.ToolChainCore_SetCallBack(CORE, abi.CB_DRIVER_M_FUNC, 0, ctypes.cast(on_m, ctypes.c_void_p)) == 0
    try:
        assert lib.ToolChainCore_StartCNCEx(CORE, abi.RUN_SIMULATION, None) == 0
        while lib.ToolChainCore_StatusCNC(CORE) == 10:
            pass
    finally:
        for n in (abi.CB_DRIVER_G_FUNC, abi.CB_DRIVER_M_FUNC):
            lib.ToolChainCore_SetCallBack(CORE, n, 0, None)
    kinds = [(kind, cells["G"] if kind == "G" else cells["M"]) for kind, cells in seen]
    assert kinds == [("G", 1), ("G", 4), ("M", 7), ("M", 51), ("G", 1)]
    for kind, cells in seen:
        assert cells["F"] == 1200 and cells["S"] == 500, (kind, cells)
        assert cells["N"] == (10.0 if kind == "G" and cells["G"] == 1 else 0.0), (kind, cells)
        absent = [v for letter, v in cells.items() if letter not in "FGHMNSXYZQ"]
        assert absent and all(v > 1e38 for v in absent), (kind, cells)
    assert seen[3][1]["Q"] == 3.0


def test_getpos_shows_the_g92_offsets_in_i_to_h(host):
    """The structures description: at GetPos the cells I J K L Q R D E S H hold the offsets
    G92 set, for the axes X Y Z C B U V W A O."""
    lib = host.lib
    r = host.compile("G1 X1 F1000\nG92 X5 Y-3 C2\nG1 X7\n", run=False, start=[0] * 10)
    assert r.error is None
    status, _ = simulate(lib, CORE)
    assert status == -10
    pos = abi.SIMPLE_GM_PARAMS()
    assert lib.ToolChainCore_GetPos(CORE, 0, ctypes.byref(pos), None) == 0
    cells = raw_cells(pos)
    # G92 X5 at X1: the program's X5 is the machine's X1, an offset of -4; Y -3 at 0: +3
    shift = dict(zip("IJKLQRDESH", (-4.0, 3.0, 0.0, -2.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)))
    assert {letter: cells[letter] for letter in "IJKLQRDESH"} == shift
    assert pos.m_calcS.x == pytest.approx(1.0 + 2.0)        # X7 in the shifted frame: machine 3


def test_arcs_whose_offset_has_no_radius_leave_the_cutting_plan(host):
    """The structures description (correctionStrategy 0x00200000): arcs whose equidistant
    comes out negative for the correction are dropped from the cutting plan and their
    neighbours joined. An arc of radius 2 on the inside of a 2 mm tool's path has an
    offset of no radius: no driver callback gets it, with or without the bit."""
    code = "G0 X0 Y0\nG41 G1 X10 Y0 F1000\nG3 X12 Y2 I0 J2\nG1 X12 Y10\nG40 G1 X20 Y20\n"
    for strategy in (0, 0x200000):
        p = host.params(correctionStrategy=strategy)
        p.correction[0].size = 2.0
        r = host.compile(code, params=p, start=[0] * 10)
        assert r.error is None
        assert [q.func for q in r.g] == [0, 1, 1, 1], strategy
        assert [q.line for q in r.g] == [1, 2, 4, 5]
        assert r.g[1].ce[:2] == pytest.approx((10.0, 2.0)) and r.g[2].ce[:2] == pytest.approx((10.0, 10.0))


def test_settings_documented_as_not_implemented_are_ignored_unless_asked(host):
    """The structures description: centripetalAcc "not implemented yet", insertArcMinAngle
    "not implemented, always 0". The vendor's library does not slow a circle for the first;
    rezerva1 bit 0x10 (GCODE_REZERVA1_APPLY_UNIMPLEMENTED) applies both."""
    code = "G0 X10 Y0\nG3 X10 Y0 I-10 J0 F6000\n"

    def run_time(**params):
        with sf_tch.compile(code, params=params, start=[0] * 10, core=CORE) as program:
            assert program.ok, program.errors
            return program.run_time

    plain = run_time()
    assert run_time(centripetalAcc=10.0) == plain                   # as if it were 0
    v = math.sqrt(10.0 * 10.0)                                      # sqrt(a r) = 10 mm/s on R10
    slowed = run_time(centripetalAcc=10.0, rezerva1=abi.GCODE_REZERVA1_APPLY_UNIMPLEMENTED)
    assert slowed > 2 * math.pi * 10 / v > 5 * plain


def test_the_limit_test_is_the_test_run_s(host):
    """The structures description calls enableMask the mask "enabling the limit test": the
    test run (StartCNCEx 20) reports a part beyond maxCoords (error 406); the forward run of
    the offline machine (30) moves as the program says, as the vendor's library hands the
    parts to TG Motion, whose drives keep their own limits (docs/behaviour.md)."""
    lib = host.lib
    machine = abi.MACHINE_PARAMETERS()
    machine.minCoords.x, machine.maxCoords.x = 0.0, 50.0
    machine.enableMask.x = 1
    assert lib.ToolChainCore_SetMachineParameters(CORE, ctypes.byref(machine)) == 0
    try:
        assert host.compile("G1 X10 F60000\nG1 X60\n", run=False, start=[0] * 10).error is None
        status, _ = simulate(lib, CORE, regime=20)
        assert status == -20
        info = abi.CALLBACK_INFO()
        assert lib.ToolChainCore_GetLastError(CORE, ctypes.byref(info)) == 1 and info.stringId == 406
        assert info.actLine == 2
        assert lib.ToolChainCore_SetTimeScale(CORE, 1000.0) == 0
        status, _ = simulate(lib, CORE, regime=30)
        assert status == -32
        pos = abi.SIMPLE_GM_PARAMS()
        assert lib.ToolChainCore_GetPos(CORE, 0, ctypes.byref(pos), None) == 0
        assert pos.m_calcS.x == pytest.approx(60.0)
    finally:
        lib.ToolChainCore_SetTimeScale(CORE, 1.0)
        lib.ToolChainCore_SetMachineParameters(CORE, ctypes.byref(abi.MACHINE_PARAMETERS()))


def test_an_m_function_gets_the_letters_of_its_line_and_the_axes_move(host):
    """The interpolator manual: an M function's parameters are the 26 letters of its line,
    G, M, N and P reserved. TG's axis words move wherever they stand (docs/dialect.md), so
    `M51 A1 B2` passes A and B to M51 and moves the axes A and B, M51 first."""
    r = ok(host, "G1 X1 F1000\nM51 A1 B2 Q7\n", start=[0] * 10)
    m51 = [p for p in r.parts if p.kind == "M" and p.func == 51][0]
    assert (m51.pars["A"], m51.pars["B"], m51.pars["Q"]) == (1.0, 2.0, 7.0)
    last = r.g[-1]
    assert (last.e[8], last.e[4]) == (1.0, 2.0)          # A is axis 8, B axis 4


def test_set_gcode_parameters_while_stopped_takes_the_feeds_or_refuses(host):
    """The function reference: while the program is stopped, only the fields the feeds
    depend on may change. A structure that changes another field is refused whole (-1 and
    error 27), so a panel can tell; the feeds alone are taken."""
    lib = host.lib
    assert host.compile("G1 X10 F1000\nM0\nG1 X20\n", run=False, start=[0] * 10).error is None
    assert lib.ToolChainCore_SetTimeScale(CORE, 1000.0) == 0
    try:
        assert lib.ToolChainCore_StartCNCEx(CORE, 30, None) == 0
        while lib.ToolChainCore_StatusCNC(CORE) > 0:
            pass
        assert lib.ToolChainCore_StatusCNC(CORE) == -33
        p = abi.GCODE_PARAMETERS()
        assert lib.ToolChainCore_GetGCodeParameters(CORE, ctypes.byref(p)) == 0
        p.motion[1].feed = 1234.0
        assert lib.ToolChainCore_SetGCodeParameters(CORE, ctypes.byref(p)) == 0
        p.absMode = 1 - p.absMode
        p.motion[1].feed = 4321.0
        assert lib.ToolChainCore_SetGCodeParameters(CORE, ctypes.byref(p)) == -1
        info = abi.CALLBACK_INFO()
        assert lib.ToolChainCore_GetLastCallError(CORE, ctypes.byref(info)) == 1 and info.stringId == 27
        assert "only the feeds may change" in info.m_fullError.decode()
        q = abi.GCODE_PARAMETERS()
        assert lib.ToolChainCore_GetGCodeParameters(CORE, ctypes.byref(q)) == 0
        assert q.motion[1].feed == 1234.0 and q.absMode != p.absMode
    finally:
        lib.ToolChainCore_SetTimeScale(CORE, 1.0)
        lib.ToolChainCore_DestroyCNC(CORE)
        lib.ToolChainCore_SetGCodeParameters(CORE, ctypes.byref(host.defaults))


def test_the_gcode_index_rises_by_1_or_2_over_every_part_a_driver_gets(host):
    """The structures description: m_gCodeIndex is an always increasing, unique value that
    rises by 1 or by 2. Inserted M functions next to each other (mFuncInsertTable: M1101
    and M1100 at one corner), compensation corners, a PRINT line (no driver callback) and
    an arc dropped from the cutting plan."""
    p = host.params(startAngle=30.0, endAngle=90.0, minAngleFeed=600.0, MfuncInsertType=1)
    for k, (m, rel) in enumerate(((1100, 0.5), (1101, 0.9), (1102, 1.0))):
        p.mFuncInsertTable[k].mFunc, p.mFuncInsertTable[k].relFeed = m, rel
    p.correction[0].size = 2.0
    code = ("G1 X10 F6000\nG1 X50\nG1 X100\nPRINT \"half\"\nG1 X100 Y100\nG1 X100 Y200\n"
            "G0 X0 Y0\nG41 G1 X10 Y0\nG3 X12 Y2 I0 J2\nG1 X12 Y10\nG1 X0 Y10\nG40 G1 X-5 Y-5\nM2\n")
    r = host.compile(code, params=p, start=[0] * 10)
    assert r.error is None and r.printed == ["half"]
    indexes = [q.gindex for q in r.parts]
    steps = [b - a for a, b in zip(indexes, indexes[1:])]
    assert set(steps) <= {1, 2}, list(zip([(q.kind, q.func, q.line) for q in r.parts], indexes))
    assert [q.func for q in r.parts if q.kind == "M"][:3] == [1100, 1101, 1100]
    plain = ok(host, "G1 X10 F1000\nG1 X20\nM7\nG1 X30\n", start=[0] * 10)
    assert [q.gindex for q in plain.parts] == [0, 2, 4, 6]          # as compiled: programmed parts by 2
