"""The numbers of the C ABI as :class:`enum.IntEnum` (they compare equal to the plain
ints the library returns): statuses, run regimes, callbacks, return codes, error
numbers, part kinds, G and M functions, planes, compensation sides. Status is built
from abi's STATUS_ ints, ErrorNumber generated from the error catalogue
(toolchain/errors.toml); both by tools/gen_catalogue.py, the statuses from the header's
enum cnc_status."""
import enum

from . import abi
from ._catalogue import ErrorNumber  # noqa: F401 (re-exported)


class _StatusBase(enum.IntEnum):
    """What every status has besides its value (Status's base: an IntEnum without members)."""

    @property
    def busy(self) -> bool:
        """True while the core works (compiles, runs, moves)."""
        return self > 0


# the one list of the statuses in Python is abi.py's block of STATUS_<name> ints (abi
# needs nothing but ctypes, so it cannot import this): Status names them without STATUS_
Status = _StatusBase("Status", [(name[len("STATUS_"):], value) for name, value in vars(abi).items()
                                if name.startswith("STATUS_") and isinstance(value, int)],
                     module=__name__, qualname="Status")
Status.__doc__ = "cnc_status of a core (ToolChainCore_StatusCNC); positive: something runs."


class ReturnCode(enum.IntEnum):
    """Return codes of the exported functions."""
    BAD_CORE = -2  # intIdx is not a core of this library
    ERROR = -1  # bad argument, NULL pointer, wrong status
    SUCCESS = 0
    EXEC_FAILED = 1  # runtime failure (e.g. LoadFromIni: file missing)
    BREAK = 2


class Regime(enum.IntEnum):
    """Run regimes of ToolChainCore_StartCNCEx."""
    SIMULATION = 10
    TEST = 20
    FORWARD = 30
    FORWARD_NO_M = 31
    BACKWARD = 32
    FORWARD_SKIP_FIRST_M = 33


class Callback(enum.IntEnum):
    """Callback numbers of ToolChainCore_SetCallBack."""
    ADD_OUTPUT_LOG = 1
    SET_STATUS_BAR_TEXT = 2
    IS_DEBUG_MODE = 3
    IS_VERBOSE_MODE = 4
    GET_LIB_PATH = 5
    GET_TOOL_PATH = 6
    GET_SYSTEM_PATH = 7
    GET_FILE_TIME_STAMP = 10
    DO_YIELD = 11
    READ_INI_STRING = 12
    READ_INI_DOUBLE = 13
    READ_INI_INT = 14
    IS_BREAKPOINT = 17
    DISP_AND_LOCATE_ERROR = 18
    ADD_OUTPUT_LOG_WITH_MSG_BOX = 31
    SET_STATUS_BAR_PROGRESS = 32
    DRIVER_INITIALIZE = 1001
    DRIVER_G_FUNC = 1002
    DRIVER_M_FUNC = 1003
    CONNECT_POINT_CALC_START = 1004
    CONNECT_POINT_CALC = 1005
    CONNECT_POINT_CALC_END = 1006
    DRIVER_END = 1007
    MATH_WARNING = 2001


class OutputTab(enum.IntEnum):
    """Tabs of the AddOutputLog callback."""
    ERRORS = 0
    CNC = 1
    PRINT = 2
    STATUS = 3


class PartKind(enum.IntEnum):
    """TC_TOOLPATH_RECORD.kind: what a part of the toolpath is."""
    MOTION = 1  # G0 G1 G2 G3 G33
    M_FUNCTION = 2  # M0, M1, waiting (< 1000) and continuous (>= 1001) M functions
    DWELL = 3  # G4
    PRINT = 4  # M29 / PRINT text


class ToolpathFlag(enum.IntFlag):
    """TC_TOOLPATH_RECORD.flags."""
    FEED_PER_MINUTE = 0x01  # feed in mm/min (G94), else mm/rev (G95)
    INSERTED = 0x02  # inserted by the library: compensation corner, G167 arc
    CONTINUOUS_M = 0x04  # M >= 1001, signalled at the start of the next move
    HELIX = 0x08  # arc with motion off its plane


class GFunction(enum.IntEnum):
    """G numbers of motion and dwell parts (TC_TOOLPATH_RECORD.number)."""
    RAPID = 0
    LINE = 1
    ARC_CW = 2
    ARC_CCW = 3
    DWELL = 4
    THREAD = 33


class MFunction(enum.IntEnum):
    """The default numbers of the M functions the library interprets (GCODE_PARAMETERS
    may renumber them); any other M number is passed to the machine."""
    PROGRAM_STOP = 0
    OPTIONAL_STOP = 1
    PROGRAM_END = 2
    SPINDLE_CW = 3
    SPINDLE_CCW = 4
    SPINDLE_STOP = 5
    TOOL_CHANGE = 6
    COOLANT_ON = 7
    OIL_ON = 8
    COOLANT_OIL_OFF = 9
    RETURN = 17
    PRINT = 29
    PROGRAM_END_RESET = 30
    MIRROR_OFF = 80
    MIRROR_X = 81
    MIRROR_Y = 82
    MIRROR_Z = 83
    MIRROR_XY = 84
    MIRROR_XZ = 85
    MIRROR_YZ = 86
    MIRROR_XYZ = 87
    DEFAULT_FEED = 99


class Plane(enum.IntEnum):
    """Arc planes (first axis, second axis): G3 turns from the first to the second."""
    XY = 17
    XZ = 18
    YZ = 19
    ZX = -18


class Compensation(enum.IntEnum):
    """Side of the tool radius compensation of a part."""
    OFF = 40
    LEFT = 41
    RIGHT = 42
