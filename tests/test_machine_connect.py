"""ConnectCNCEx_Plane through the exports (the search itself: test_connect_search):
statuses 40 -> 41 -> -31 (or on forward), where the machine ends up against the
geometry of a square (closed forms), the place a later StartCNCEx continues from,
a failed search keeping the status, stateAfter 2, a stop on the way, and the
ConnectPointCalc callbacks. The machine runs on its stepped clock (ToolChainCore_TestClock,
test-only): a test steps its time instead of sleeping."""
import ctypes
import time

import pytest

from sf_tch import abi, default_ini

CORE = 2
INI = default_ini().encode()         # the bundled INI, wherever SF_TCH_LIBRARY points
# a 100 mm square from the origin, counter-clockwise, with an M function on line 4
SQUARE = b"G0 X0 Y0\nG1 X100 F6000\nG1 Y100\nM8\nG1 X0\nG1 Y0\n"


def doubles(*values):
    return (ctypes.c_double * max(1, len(values)))(*values)


MOVING = (30, 31, 32, 33, 40, 41, 50)       # the machine's statuses: its clock is stepped


def follow(lib, limit=10.0):
    """The statuses the core passes through until it stands, the machine stepped 10 ms
    at a time (a compilation or a simulation polled); the last one."""
    seen = []
    deadline = time.monotonic() + limit
    while True:
        status = lib.ToolChainCore_StatusCNC(CORE)
        if not seen or seen[-1] != status:
            seen.append(status)
        if status <= 0:
            return seen
        assert time.monotonic() < deadline, seen
        if status in MOVING:
            assert lib.ToolChainCore_TestClock(CORE, abi.TC_TEST_CLOCK_KEY, 0.01) == 0
        else:
            time.sleep(0.0005)


def position(lib):
    pos = abi.SIMPLE_GM_PARAMS()
    assert lib.ToolChainCore_GetPos(CORE, 0, ctypes.byref(pos), None) == 0
    return pos.m_calcS.x, pos.m_calcS.y


@pytest.fixture
def square(fresh_core):
    lib = fresh_core
    assert lib.ToolChainCore_LoadFromIni(CORE, INI, None) == 0
    p = abi.GCODE_PARAMETERS()
    assert lib.ToolChainCore_GetGCodeParameters(CORE, ctypes.byref(p)) == 0
    p.maxConnectionDistance = 1000.0            # every part counts by its nearest point
    assert lib.ToolChainCore_SetGCodeParameters(CORE, ctypes.byref(p)) == 0
    assert lib.ToolChainCore_ResetCNC(CORE, 0, 10, doubles(*[0.0] * 10)) == 0
    assert lib.ToolChainCore_CompileFromMemory(CORE, b"square.nc", SQUARE) == 0
    assert follow(lib)[-1] == -1
    assert lib.ToolChainCore_ResetCNC(CORE, 1, 0, None) == 0
    assert lib.ToolChainCore_TestClock(CORE, abi.TC_TEST_CLOCK_KEY, 0.0) == 0     # the stepped clock
    # one run from the origin places the program there (a machine that never ran stands
    # at the start of its first rapid, wherever it is)
    assert lib.ToolChainCore_StartCNCEx(CORE, 30, None) == 0
    assert follow(lib)[-1] == -32
    yield lib
    lib.ToolChainCore_DestroyCNC(CORE)
    lib.ToolChainCore_ResetCNC(CORE, 0, 10, doubles(*[0.0] * 10))
    assert lib.ToolChainCore_TestClock(CORE, abi.TC_TEST_CLOCK_KEY, -1.0) == 0    # the wall clock


def gcode_index_of_line(lib, line):
    """The G-code index of the part on `line`, as DriverGFunc reports it in a simulation."""
    found = {}

    @abi.DriverGFunc
    def on_part(user, part):
        found.setdefault(part.contents.m_editorLine, part.contents.m_gCodeIndex)
        return 0

    assert lib.ToolChainCore_SetCallBack(CORE, abi.CB_DRIVER_G_FUNC, 0, ctypes.cast(on_part, ctypes.c_void_p)) == 0
    status = lib.ToolChainCore_StatusCNC(CORE)
    assert lib.ToolChainCore_StartCNCEx(CORE, 10, None) == 0
    assert follow(lib)[-1] == -10
    assert lib.ToolChainCore_SetCallBack(CORE, abi.CB_DRIVER_G_FUNC, 0, None) == 0
    if status == -50:
        assert lib.ToolChainCore_ResetStatusCNC(CORE, 1) == 0
    return found[line]


def go_off(lib, x, y):
    assert lib.ToolChainCore_GoToPosition(CORE, 2, doubles(x, y)) == 0
    assert follow(lib)[-1] == -50
    assert position(lib) == pytest.approx((x, y), abs=1e-9)


def test_nearest_point_then_on_to_the_end(square):
    lib = square
    go_off(lib, 60.0, 7.0)
    # the nearest point of the square to (60, 7) is (60, 0) on its first side
    assert lib.ToolChainCore_ConnectCNCEx_Plane(CORE, 0, 2, doubles(60.0, 7.0), None, 0x3, 0x3, 0) == 0
    assert follow(lib)[-1] == -31
    assert position(lib) == pytest.approx((60.0, 0.0), abs=1e-9)
    # a forward run continues from there: the rest of the square, 40 + 300 mm
    pos, enh = abi.SIMPLE_GM_PARAMS(), abi.GM_PARAMS_ENHANCED()
    assert lib.ToolChainCore_StartCNCEx(CORE, 30, None) == 0
    assert follow(lib)[-1] == -32
    assert lib.ToolChainCore_GetPos(CORE, 0, ctypes.byref(pos), ctypes.byref(enh)) == 0
    assert (pos.m_calcS.x, pos.m_calcS.y) == pytest.approx((0.0, 0.0), abs=1e-9)
    # the program's cuts so far: the first run's 400 mm and the 340 mm from (60, 0) on
    assert enh.m_actWorkPartsLen == pytest.approx(400.0 + 340.0, abs=1e-6)


def test_a_far_point_connects_to_a_vertex(square):
    lib = square
    p = abi.GCODE_PARAMETERS()
    assert lib.ToolChainCore_GetGCodeParameters(CORE, ctypes.byref(p)) == 0
    p.maxConnectionDistance = 20.0              # the sides are 30 mm away: only their ends count
    assert lib.ToolChainCore_SetGCodeParameters(CORE, ctypes.byref(p)) == 0
    go_off(lib, 130.0, 60.0)
    assert lib.ToolChainCore_ConnectCNCEx_Plane(CORE, 0, 2, doubles(130.0, 60.0), None, 0, 0, 0) == 0
    assert follow(lib)[-1] == -31
    assert position(lib) == pytest.approx((100.0, 100.0), abs=1e-9)


def test_the_statuses_of_a_connection(square):
    lib = square
    go_off(lib, 150.0, 50.0)
    assert lib.ToolChainCore_ConnectCNCEx_Plane(CORE, 0, 2, doubles(150.0, 50.0), None, 0, 0, 0) == 0
    seen = follow(lib)
    assert seen[-1] == -31 and set(seen[:-1]) <= {40, 41} and 41 in seen, seen
    assert position(lib) == pytest.approx((100.0, 50.0), abs=1e-9)


@pytest.mark.parametrize("n_type, expected", [(1, (100.0, 0.0)), (2, (100.0, 100.0)),
                                              (30, (100.0, 0.0)), (32, (100.0, 100.0))])
def test_start_and_end_of_a_line_and_of_a_part(square, n_type, expected):
    lib = square
    go_off(lib, 50.0, 50.0)
    if n_type in (1, 2):
        coords = doubles(3.0)                       # editor line 3: G1 Y100, from (100, 0)
        n = 1
    else:
        coords, n = doubles(float(gcode_index_of_line(lib, 3))), 1
    assert lib.ToolChainCore_ConnectCNCEx_Plane(CORE, n_type, n, coords, None, 0, 0x3FF, 0) == 0
    assert follow(lib)[-1] == -31
    assert position(lib) == pytest.approx(expected, abs=1e-9)


def test_connect_and_continue(square):
    lib = square
    go_off(lib, 50.0, 50.0)
    # 11: to the start of line 5 (G1 X0 from (100, 100)) and on to the program's end
    assert lib.ToolChainCore_ConnectCNCEx_Plane(CORE, 11, 1, doubles(5.0), None, 0, 0x3FF, 0) == 0
    seen = follow(lib)
    assert 30 in seen and seen[-1] == -32, seen
    assert position(lib) == pytest.approx((0.0, 0.0), abs=1e-9)


def test_a_search_that_finds_nothing_keeps_the_status(square):
    lib = square
    go_off(lib, 50.0, 50.0)
    assert lib.ToolChainCore_ConnectCNCEx_Plane(CORE, 1, 1, doubles(99.0), None, 0, 0x3FF, 0) == 0
    assert follow(lib)[-1] == -50
    info = abi.CALLBACK_INFO()
    assert lib.ToolChainCore_GetLastError(CORE, ctypes.byref(info)) == 1
    assert b"line 99" in info.m_fullError
    assert position(lib) == pytest.approx((50.0, 50.0), abs=1e-9)
    assert lib.ToolChainCore_ConnectCNCEx_Plane(CORE, 77, 1, doubles(1.0), None, 0, 0, 0) == 0
    assert follow(lib)[-1] == -50
    assert lib.ToolChainCore_GetLastError(CORE, ctypes.byref(info)) == 1
    assert b"nType" in info.m_fullError


def test_bad_arguments_are_refused_at_once(square):
    lib = square
    assert lib.ToolChainCore_ConnectCNCEx_Plane(CORE, 0, 12, doubles(*[0.0] * 12), None, 0, 0, 0) == -1
    assert lib.ToolChainCore_ConnectCNCEx_Plane(CORE, 0, 2, None, None, 0, 0, 0) == -1
    assert lib.ToolChainCore_ConnectCNCEx_Plane(CORE, 0, 2, doubles(0.0, 0.0), None, 0, 0, 1) == -1
    assert lib.ToolChainCore_ConnectCNCEx_Plane(CORE, 0, 2, doubles(float("nan"), 0.0), None, 0, 0, 0) == -1
    assert lib.ToolChainCore_ConnectCNCEx_Plane(9, 0, 0, None, None, 0, 0, 0) == -2
    # while the machine moves: refused (status 30)
    assert lib.ToolChainCore_ResetCNC(CORE, 1, 0, None) == 0
    assert lib.ToolChainCore_StartCNCEx(CORE, 30, None) == 0
    assert lib.ToolChainCore_ConnectCNCEx_Plane(CORE, 0, 2, doubles(0.0, 0.0), None, 0, 0, 0) == -1
    assert lib.ToolChainCore_ResetCNC(CORE, 1, 0, None) == 0


def test_state_after_2_reports_out_of_the_trajectory(square):
    lib = square
    go_off(lib, 60.0, 7.0)
    assert lib.ToolChainCore_ConnectCNCEx_Plane(CORE, 0, 2, doubles(60.0, 7.0), None, 0, 0, 2) == 0
    assert follow(lib)[-1] == -50
    assert position(lib) == pytest.approx((60.0, 0.0), abs=1e-9)


def test_a_stop_on_the_way_leaves_it_out_of_the_trajectory(square):
    lib = square
    go_off(lib, 50.0, 90.0)
    assert lib.ToolChainCore_ConnectCNCEx_Plane(CORE, 0, 2, doubles(50.0, 90.0), None, 0, 0, 0) == 0
    # on its way (10 mm at motion[5]) after 0.1 s: the search (40) takes no machine time
    assert lib.ToolChainCore_TestClock(CORE, abi.TC_TEST_CLOCK_KEY, 0.1) == 0
    assert lib.ToolChainCore_StatusCNC(CORE) == 41
    assert lib.ToolChainCore_StopCNCEx(CORE, None) == 0
    assert follow(lib)[-1] == -50
    x, y = position(lib)
    assert x == pytest.approx(50.0, abs=1e-9) and 90.0 < y < 100.0


def test_connect_point_callbacks(square):
    lib = square
    calls = []

    @abi.ConnectPointCalcStart
    def on_start(user, n_type, n_coords, coords, axes):
        calls.append(("start", n_type, n_coords, coords[0], coords[1], axes))
        return 0

    @abi.ConnectPointCalc
    def on_part(user, part, sq_distance, point):
        # the host makes the part on line 5 (the top side) win, at its middle
        calls.append(("part", part.contents.m_editorLine))
        if part.contents.m_editorLine == 5:
            sq_distance[0] = 0.0
            point.contents.x, point.contents.y = 50.0, 100.0
            return 1
        return 0

    @abi.ConnectPointCalcEnd
    def on_end(user, part, point):
        calls.append(("end", part.contents.m_editorLine, point.contents.x, point.contents.y))
        point.contents.x = 49.0
        return 1

    for number, fn in ((abi.CB_CONNECT_POINT_CALC_START, on_start), (abi.CB_CONNECT_POINT_CALC, on_part),
                       (abi.CB_CONNECT_POINT_CALC_END, on_end)):
        assert lib.ToolChainCore_SetCallBack(CORE, number, 0, ctypes.cast(fn, ctypes.c_void_p)) == 0
    go_off(lib, 60.0, 7.0)
    assert lib.ToolChainCore_ConnectCNCEx_Plane(CORE, 0, 2, doubles(60.0, 7.0), None, 0x3, 0x3, 0) == 0
    assert follow(lib)[-1] == -31
    assert calls[0] == ("start", 0, 2, 60.0, 7.0, 0x3)
    assert [c[1] for c in calls if c[0] == "part"] == [1, 2, 3, 5, 6]     # every motion part, in order
    assert calls[-1] == ("end", 5, 50.0, 100.0)
    assert position(lib) == pytest.approx((49.0, 100.0), abs=1e-9)


@pytest.mark.parametrize("where, value", [("end", float("inf")), ("end", float("nan")), ("part", float("nan")),
                                          ("part_distance", float("nan"))])
def test_a_point_that_is_not_finite_from_the_callbacks_fails_the_connection(square, where, value):
    """connect_callback_nonfinite.py: an infinite point from ConnectPointCalcEnd sent the
    machine towards infinity (status 41 for ever, x NaN); a NaN one gave -31 while the
    machine stood 5 mm from its place, and the next run jumped there. A point or
    distance that is not finite fails the connection: error 706 naming the callback,
    the status where it was (-50), the machine where it stood; no NaN in GetPos."""
    lib = square

    @abi.ConnectPointCalc
    def on_part(user, part, sq_distance, point):
        if where == "part":
            point.contents.x = value
        else:
            sq_distance[0] = value
        return 1

    @abi.ConnectPointCalcEnd
    def on_end(user, part, point):
        point.contents.x = value
        return 1

    number, fn = ((abi.CB_CONNECT_POINT_CALC_END, on_end) if where == "end" else (abi.CB_CONNECT_POINT_CALC, on_part))
    assert lib.ToolChainCore_SetCallBack(CORE, number, 0, ctypes.cast(fn, ctypes.c_void_p)) == 0
    go_off(lib, 50.0, 7.0)
    assert lib.ToolChainCore_ConnectCNCEx_Plane(CORE, 0, 2, doubles(50.0, 7.0), None, 0, 0, 0) == 0
    assert follow(lib)[-1] == -50
    info = abi.CALLBACK_INFO()
    assert lib.ToolChainCore_GetLastError(CORE, ctypes.byref(info)) == 1
    callback = b"ConnectPointCalcEnd" if where == "end" else b"ConnectPointCalc "
    assert info.stringId == 706 and callback in info.m_fullError, info.m_fullError
    assert position(lib) == pytest.approx((50.0, 7.0), abs=1e-9)
    assert lib.ToolChainCore_SetCallBack(CORE, number, 0, None) == 0
    # the next connection, without the callback, goes to the nearest point
    assert lib.ToolChainCore_ConnectCNCEx_Plane(CORE, 0, 2, doubles(50.0, 7.0), None, 0, 0, 0) == 0
    assert follow(lib)[-1] == -31
    assert position(lib) == pytest.approx((50.0, 0.0), abs=1e-9)
