"""The dynamic G41/G42 corrections of the offline machine (docs/machine.md): the tool
moves further out by dynamicG4xCorrection_mm + _percent of the tool radius, times
(1 - v / the part's full speed) -- all of it at rest, none at full speed. Checked at
the two ends of that rule: standing at M0, and cruising. The machine runs on its
stepped clock (ToolChainCore_TestClock, test-only)."""
import ctypes
import time

import pytest

from sf_tch import abi

CORE = 1
KEY = abi.TC_TEST_CLOCK_KEY
# along +X under G41 (the tool left of its way: +Y), an M0 at (50, 0), then on
PROGRAM = b"G0 X-5 Y-5\nG41 G1 X0 Y0 F3000\nG1 X50\nM0\nG1 X100\nG40 G1 X110 Y-10\n"


def run_to_m0(lib, mm=0.0, percent=0.0, side=41):
    p = abi.GCODE_PARAMETERS()
    assert lib.ToolChainCore_GetGCodeParameters(CORE, ctypes.byref(p)) == 0
    p.correction[0].size = 1.0
    p.correction[1].size = 1.0
    setattr(p, f"dynamicG{side}Correction_mm", mm)
    setattr(p, f"dynamicG{side}Correction_percent", percent)
    assert lib.ToolChainCore_SetGCodeParameters(CORE, ctypes.byref(p)) == 0
    code = PROGRAM if side == 41 else PROGRAM.replace(b"G41", b"G42")
    assert lib.ToolChainCore_CompileFromMemory(CORE, b"dyn.nc", code) == 0
    while lib.ToolChainCore_StatusCNC(CORE) == 1:
        time.sleep(0.001)
    assert lib.ToolChainCore_ResetCNC(CORE, 1, 0, None) == 0
    assert lib.ToolChainCore_TestClock(CORE, KEY, 0.0) == 0           # the stepped clock
    assert lib.ToolChainCore_StartCNCEx(CORE, 30, None) == 0
    while lib.ToolChainCore_StatusCNC(CORE) > 0:
        assert lib.ToolChainCore_TestClock(CORE, KEY, 0.1) == 0
    assert lib.ToolChainCore_StatusCNC(CORE) == -33
    pos = abi.SIMPLE_GM_PARAMS()
    assert lib.ToolChainCore_GetPos(CORE, 0, ctypes.byref(pos), None) == 0
    return pos.m_calcS.x, pos.m_calcS.y


@pytest.fixture
def fresh_core_stepped(fresh_core):
    yield fresh_core
    assert fresh_core.ToolChainCore_TestClock(CORE, KEY, -1.0) == 0     # the wall clock again


@pytest.mark.parametrize("mm, percent, expected", [(0.0, 0.0, 1.0), (0.5, 0.0, 1.5), (0.0, 30.0, 1.3),
                                                   (0.2, 10.0, 1.3)])
def test_at_rest_the_whole_correction_moves_the_tool_out(fresh_core_stepped, mm, percent, expected):
    x, y = run_to_m0(fresh_core_stepped, mm, percent)
    assert x == pytest.approx(50.0, abs=1e-9)
    assert y == pytest.approx(expected, abs=1e-9)


def test_g42_moves_to_the_other_side(fresh_core_stepped):
    x, y = run_to_m0(fresh_core_stepped, 0.5, 0.0, side=42)
    assert (x, y) == pytest.approx((50.0, -1.5), abs=1e-9)


def test_at_full_speed_nothing_is_added(fresh_core_stepped):
    lib = fresh_core_stepped
    run_to_m0(lib, 0.5, 0.0)
    # on from M0: sample the cruise along X (3000 mm/min = the part's full speed)
    assert lib.ToolChainCore_StartCNCEx(CORE, 30, None) == 0
    pos, enh = abi.SIMPLE_GM_PARAMS(), abi.GM_PARAMS_ENHANCED()
    cruising = []
    while lib.ToolChainCore_StatusCNC(CORE) > 0:
        assert lib.ToolChainCore_TestClock(CORE, KEY, 0.01) == 0
        lib.ToolChainCore_GetPos(CORE, 0, ctypes.byref(pos), ctypes.byref(enh))
        if pos.m_editorLine == 5 and abs(enh.m_actFeed - 3000.0) < 1e-6:
            cruising.append(pos.m_calcS.y)
    assert len(cruising) > 50, "never sampled at full speed"
    assert cruising == pytest.approx([1.0] * len(cruising), abs=1e-9)
