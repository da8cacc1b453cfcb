"""The numbers of the C ABI as :class:`enum.IntEnum` (they compare equal to the plain
ints the library returns): statuses, run regimes, callbacks, return codes, error
numbers, part kinds, G and M functions, planes, compensation sides."""
import enum


class ReturnCode(enum.IntEnum):
    """Return codes of the exported functions."""
    BAD_CORE = -2  # intIdx is not a core of this library
    ERROR = -1  # bad argument, NULL pointer, wrong status
    SUCCESS = 0
    EXEC_FAILED = 1  # runtime failure (e.g. LoadFromIni: file missing)
    BREAK = 2


class Status(enum.IntEnum):
    """cnc_status of a core (ToolChainCore_StatusCNC); positive: something runs."""
    NOTHING_LOADED = 0
    NOT_CONNECTED = -2
    COMPILING = 1
    COMPILED = -1
    SIMULATING = 10
    SIMULATION_DONE = -10
    SIMULATION_STOPPED = -11
    TESTING = 20
    TEST_DONE = -20
    TEST_STOPPED = -21
    AT_START = -30
    STOPPED = -31
    AT_END = -32
    STOPPED_BY_M0 = -33
    FORWARD = 30
    FORWARD_NO_M = 31
    BACKWARD = 32
    FORWARD_SKIP_FIRST_M = 33
    CONNECT_CALCULATING = 40
    CONNECT_MOVING = 41
    MANUAL_MOVE = 50
    OUT_OF_TRAJECTORY = -50
    INTERNAL_CALC = 60
    SENDING_START_M = 70
    SENDING_STOP_M = 80
    SENDING_CONNECT_M = 90
    INVALID = -1234

    @property
    def busy(self) -> bool:
        """True while the core works (compiles, runs, moves)."""
        return self > 0


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


class ErrorNumber(enum.IntEnum):
    """The library's error catalogue (docs/errors.md, toolchain/errors.pxd); 600 and up are warnings."""
    FILE_OPEN = 1  # Cannot open file '%s'
    FILE_READ = 2  # Cannot read file '%s'
    INI_OPEN = 3  # Cannot open INI file '%s'
    OUT_OF_MEMORY = 4  # Out of memory
    CANCELLED = 5  # Compilation interrupted
    NOTHING_COMPILED = 6  # No compiled program
    DRIVER_REFUSED = 7  # Driver callback %s returned %d
    BUSY = 8  # Core busy: %s
    BAD_STATUS = 9  # %s not allowed in status %d (%s)
    NOT_IMPLEMENTED = 10  # %s is not implemented yet
    INI_FIRST = 11  # Callback %d needs LoadFromIni first
    FILE_TOO_LARGE = 12  # File '%s' is larger than 1 GiB
    NOT_REGULAR_FILE = 13  # '%s' is not a regular file
    NOT_FINITE = 14  # %s = %g is not a finite number
    OUT_OF_RANGE = 15  # %s = %g is outside <%g, %g>
    INI_VALUE = 16  # INI file '%s' line %d: %s
    REENTRANT = 20  # %s is not allowed inside a callback of the core's running activity
    BAD_REGIME = 21  # StartCNCEx: unknown regime
    NO_M_PENDING = 22  # No M function waits for a confirmation
    M_PENDING = 23  # An M function still waits for its confirmation (ToolChainCore_ConfirmMFunc)
    UNKNOWN_WORD = 100  # Unknown word '%s' at column %d
    BAD_NUMBER = 101  # Bad number '%s' at column %d
    MISSING_VALUE = 102  # Address %s at column %d without a value
    UNBALANCED_BRACKETS = 103  # Unbalanced brackets: '(' at column %d not closed
    UNTERMINATED_COMMENT = 104  # Comment '(' at column %d not closed on this line
    LINE_TOO_LONG = 105  # Line longer than %d characters
    BAD_VALUE = 106  # Bad value %g of address %s
    TOO_MANY_WORDS = 107  # More than %d %s words on one line
    NUMBER_OVERFLOW = 108  # Number '%s' at column %d is too large
    P_WORD = 110  # Word '%s' at column %d: P is reserved for parameters P00..P99 (Pnn = value); %s
    NOT_TG = 111  # '%s' at column %d is not TG G-code: %s
    NGC_UNSUPPORTED = 112  # '%s' at column %d is not supported in the ISO compatibility mode: %s
    DIVISION_BY_ZERO = 200  # Division by zero
    BAD_PARAMETER = 201  # Parameter P%g at column %d does not exist (P00..P99)
    BAD_EXPRESSION = 202  # Syntax error in expression '%s' at column %d
    UNKNOWN_FUNCTION = 203  # Unknown function '%s' at column %d
    MATH_DOMAIN = 204  # Argument out of domain in %s(%g)
    BAD_PLC_ADDRESS = 205  # PLC address %g out of range (1..%d)
    PARAM_STACK = 206  # G900 parameter stack %s
    NOT_FINITE_RESULT = 207  # Expression '%s' does not give a finite number
    NGC_UNDEFINED = 208  # Named parameter '%s' at column %d is not defined
    NGC_UNREADABLE = 209  # Parameter '%s' at column %d cannot be read: %s
    NGC_PARAMETER = 210  # Parameter #%g at column %d does not exist (#1..#5601)
    NGC_READ_ONLY = 211  # Parameter '%s' at column %d is read-only
    UNDEFINED_LABEL = 300  # Undefined label '%s'
    DUPLICATE_LABEL = 301  # Label '%s' defined twice (first on line %d)
    UNBALANCED_END = 302  # END without FOR, WHILE or IF
    MISSING_END = 303  # %s without END
    CALL_STACK_OVERFLOW = 304  # Subroutine calls nested deeper than %d
    RETURN_WITHOUT_CALL = 305  # RETURN outside a subroutine
    BLOCK_LIMIT = 306  # More than %d blocks executed: endless loop?
    BREAK_OUTSIDE_LOOP = 307  # %s outside a loop
    BAD_CONDITION = 308  # Bad condition '%s' at column %d
    PART_LIMIT = 309  # More than %d parts: program too large
    O_WORD = 310  # O-word '%s' at column %d: %s
    O_UNDEFINED = 311  # Subroutine '%s' at column %d is not defined before its call
    ARC_CENTRE = 400  # Wrongly entered centre of circular interpolation %s at column %d: ... Delta > 2*R
    ARC_RADIUS = 401  # Arc radius %g too small for chord %g
    ARC_NO_CENTRE = 402  # Arc without centre (I J K or R)
    BAD_PLANE = 403  # Bad plane G%d
    BAD_G = 404  # Unknown G function G%g at column %d
    BAD_M = 405  # Bad M function M%g at column %d
    ARC_RADII = 407  # Wrongly entered centre of circular interpolation %s at column %d: ... radius at start <> radius at end
    MACHINE_LIMIT = 406  # Axis %s position %g outside the machine limits <%g, %g>
    ISO_G = 408  # G%g at column %d is not TG G-code: %s
    NO_FEED = 410  # G%g at column %d with feed 0: no F word was given (LinuxCNC refuses it)
    NO_MOTION_MODE = 411  # Axis word '%s' at column %d without a motion mode (G0 G1 G2 G3 or a canned cycle)
    NGC_G = 412  # G%g at column %d: %s
    NGC_WORD = 413  # '%s' at column %d: %s
    COMP_NOT_FOUND = 500  # Intersection of equidistants not found
    COMP_ON_ARC = 501  # Compensation switched on or off on an arc
    COMP_PLANE_CHANGE = 502  # Plane changed while tool radius compensation is active
    COMP_NEGATIVE_ARC = 503  # Arc radius %g smaller than the tool radius %g
    COMP_CROSSING = 504  # Equidistants cross: the tool (radius %g) does not fit the contour
    COMP_LOOKAHEAD = 505  # More than %d blocks without motion in the compensation plane
    COMPENSATION_WARNING = 600  # Tool radius compensation: %s
    WARN_G43_H = 610  # G43 with H at column %d: ...
    WARN_O_AT_START = 611  # O%g at column %d at the start of the program moves the O axis ...
    WARN_G18_ARC = 612  # G18 arc at column %d after an ISO header: ...
    WARN_ZERO_WITH_MOVE = 613  # G%g at column %d with axis words sets the zero offset ...
    WARN_NO_FEED = 614  # G%g at column %d at feed 0 (no F word yet, or F0) moves at GCODE_PARAMETERS motion[1].feed ...
    WARN_BARE_AXES = 615  # Axis words at column %d before any G0..G3 move as G1 ...
    WARN_DWELL_WITH_MOTION = 616  # G4 at column %d with G%g: the line dwells and does not move ...
    WARN_G90_MOVES_G1 = 617  # G%g at column %d with axis words moves as G1 ...
    WARN_ISO_IGNORED = 620  # '%s' at column %d ignored (ISO compatibility mode)
    CONNECT_BAD_ARGUMENT = 700  # ConnectCNCEx_Plane: %s = %g: %s
    CONNECT_NO_LINE = 701  # ConnectCNCEx_Plane: no part at line %d of file %d
    CONNECT_NO_GINDEX = 702  # ConnectCNCEx_Plane: no part with G-code index %d
    CONNECT_NO_MFUNC = 703  # ConnectCNCEx_Plane: occurrence n = %d of M%d not found ...
    CONNECT_OFF_PART = 704  # ConnectCNCEx_Plane: the point lies %g mm from the part ...
    CONNECT_NO_MOTION = 705  # ConnectCNCEx_Plane: no motion to connect to in parts ...


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
