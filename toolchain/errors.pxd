# The error catalogue: numbers are stable, part of the documented behaviour
# (docs/errors.md lists them); the English formats live in errors.pyx.
cdef enum ErrorNumber:
    # configuration and host input (1..99)
    ERR_FILE_OPEN = 1               # Cannot open file '%s'
    ERR_FILE_READ = 2               # Cannot read file '%s'
    ERR_INI_OPEN = 3                # Cannot open INI file '%s'
    ERR_OUT_OF_MEMORY = 4           # Out of memory
    ERR_CANCELLED = 5               # Compilation interrupted
    ERR_NOTHING_COMPILED = 6        # No compiled program
    ERR_DRIVER_REFUSED = 7          # Driver callback %s returned %d
    ERR_BUSY = 8                    # Core busy: %s
    ERR_BAD_STATUS = 9              # %s not allowed in status %d (%s)
    ERR_NOT_IMPLEMENTED = 10        # %s is not implemented yet
    ERR_INI_FIRST = 11              # Callback %d needs LoadFromIni first
    ERR_FILE_TOO_LARGE = 12         # File '%s' is larger than 1 GiB
    ERR_NOT_REGULAR_FILE = 13       # '%s' is not a regular file
    ERR_NOT_FINITE = 14             # %s = %g is not a finite number
    ERR_OUT_OF_RANGE = 15           # %s = %g is outside <%g, %g>
    ERR_INI_VALUE = 16              # INI file '%s' line %d: %s
    ERR_REENTRANT = 20              # %s is not allowed inside a callback of the core's running activity
    ERR_BAD_REGIME = 21             # StartCNCEx: unknown regime
    ERR_NO_M_PENDING = 22           # No M function waits for a confirmation
    ERR_M_PENDING = 23              # An M function still waits for its confirmation (ToolChainCore_ConfirmMFunc)
    # lexical (100..199)
    ERR_UNKNOWN_WORD = 100          # Unknown word '%s' at column %d
    ERR_BAD_NUMBER = 101            # Bad number '%s' at column %d
    ERR_MISSING_VALUE = 102         # Address %s at column %d without a value
    ERR_UNBALANCED_BRACKETS = 103   # Unbalanced brackets: '(' at column %d not closed
    ERR_UNTERMINATED_COMMENT = 104  # Comment '(' at column %d not closed on this line
    ERR_LINE_TOO_LONG = 105         # Line longer than %d characters
    ERR_BAD_VALUE = 106             # Bad value %g of address %s
    ERR_TOO_MANY_WORDS = 107        # More than %d %s words on one line
    ERR_NUMBER_OVERFLOW = 108       # Number '%s' at column %d is too large
    ERR_P_WORD = 110                # Word '%s' at column %d: P is reserved for parameters P00..P99 (Pnn = value); %s
    ERR_NOT_TG = 111                # '%s' at column %d is not TG G-code: %s
    ERR_NGC_UNSUPPORTED = 112       # '%s' at column %d is not supported in the ISO compatibility mode: %s
    # expressions and parameters (200..299)
    ERR_DIVISION_BY_ZERO = 200      # Division by zero
    ERR_BAD_PARAMETER = 201         # Parameter P%g at column %d does not exist (P00..P99)
    ERR_BAD_EXPRESSION = 202        # Syntax error in expression '%s' at column %d
    ERR_UNKNOWN_FUNCTION = 203      # Unknown function '%s' at column %d
    ERR_MATH_DOMAIN = 204           # Argument out of domain in %s(%g)
    ERR_BAD_PLC_ADDRESS = 205       # PLC address %g out of range (1..%d)
    ERR_PARAM_STACK = 206           # G900 parameter stack %s
    ERR_NOT_FINITE_RESULT = 207     # Expression '%s' does not give a finite number
    ERR_NGC_UNDEFINED = 208         # Named parameter '%s' at column %d is not defined
    ERR_NGC_UNREADABLE = 209        # Parameter '%s' at column %d cannot be read: %s
    ERR_NGC_PARAMETER = 210         # Parameter #%g at column %d does not exist (#1..#5601)
    ERR_NGC_READ_ONLY = 211         # Parameter '%s' at column %d is read-only
    # program flow (300..399)
    ERR_UNDEFINED_LABEL = 300       # Undefined label '%s'
    ERR_DUPLICATE_LABEL = 301       # Label '%s' defined twice (first on line %d)
    ERR_UNBALANCED_END = 302        # END without FOR, WHILE or IF
    ERR_MISSING_END = 303           # %s without END
    ERR_CALL_STACK_OVERFLOW = 304   # Subroutine calls nested deeper than %d
    ERR_RETURN_WITHOUT_CALL = 305   # RETURN outside a subroutine
    ERR_BLOCK_LIMIT = 306           # More than %d blocks executed: endless loop?
    ERR_BREAK_OUTSIDE_LOOP = 307    # %s outside a loop
    ERR_BAD_CONDITION = 308         # Bad condition '%s' at column %d
    ERR_PART_LIMIT = 309            # More than %d parts: program too large
    ERR_O_WORD = 310                # O-word '%s' at column %d: %s
    ERR_O_UNDEFINED = 311           # Subroutine '%s' at column %d is not defined before its call
    # geometry (400..499)
    ERR_ARC_CENTRE = 400            # Wrongly entered centre of circular interpolation %s at column %d: ... Delta > 2*R
    ERR_ARC_RADIUS = 401            # Arc radius %g too small for chord %g
    ERR_ARC_NO_CENTRE = 402         # Arc without centre (I J K or R)
    ERR_BAD_PLANE = 403             # Bad plane G%d
    ERR_BAD_G = 404                 # Unknown G function G%g at column %d
    ERR_BAD_M = 405                 # Bad M function M%g at column %d
    ERR_ARC_RADII = 407             # Wrongly entered centre of circular interpolation %s at column %d: ... radius at start <> radius at end
    ERR_MACHINE_LIMIT = 406         # Axis %s position %g outside the machine limits <%g, %g>
    ERR_ISO_G = 408                 # G%g at column %d is not TG G-code: %s
    ERR_NO_FEED = 410               # G%g at column %d with feed 0: no F word was given (LinuxCNC refuses it)
    ERR_NO_MOTION_MODE = 411        # Axis word '%s' at column %d without a motion mode (G0 G1 G2 G3 or a canned cycle)
    ERR_NGC_G = 412                 # G%g at column %d: %s
    ERR_NGC_WORD = 413              # '%s' at column %d: %s
    # tool radius compensation (500..599)
    ERR_COMP_NOT_FOUND = 500        # Intersection of equidistants not found
    ERR_COMP_ON_ARC = 501           # Compensation switched on or off on an arc
    ERR_COMP_PLANE_CHANGE = 502     # Plane changed while tool radius compensation is active
    ERR_COMP_NEGATIVE_ARC = 503     # Arc radius %g smaller than the tool radius %g
    ERR_COMP_CROSSING = 504         # Equidistants cross: the tool (radius %g) does not fit the contour
    ERR_COMP_LOOKAHEAD = 505        # More than %d blocks without motion in the compensation plane
    # warnings (600..699): MathWarning callback, not errors
    WARN_COMP = 600                 # Tool radius compensation: %s
    # compile warnings: the program looks written for ISO G-code (docs/compiler.md)
    WARN_G43_H = 610                # G43 with H at column %d: ...
    WARN_O_AT_START = 611           # O%g at column %d at the start of the program moves the O axis ...
    WARN_G18_ARC = 612              # G18 arc at column %d after an ISO header: ...
    WARN_ZERO_WITH_MOVE = 613       # G%g at column %d with axis words sets the zero offset ...
    WARN_NO_FEED = 614              # G%g at column %d at feed 0 (no F word yet, or F0) moves at GCODE_PARAMETERS motion[1].feed ...
    WARN_BARE_AXES = 615            # Axis words at column %d before any G0..G3 move as G1 ...
    WARN_DWELL_WITH_MOTION = 616    # G4 at column %d with G%g: the line dwells and does not move ...
    WARN_G90_MOVES_G1 = 617         # G%g at column %d with axis words moves as G1 ...
    WARN_ISO_IGNORED = 620          # '%s' at column %d ignored (ISO compatibility mode)
    # the connection search of ConnectCNCEx_Plane (700..719; machine/connect_search.pyx)
    ERR_CONNECT_BAD_ARGUMENT = 700      # ConnectCNCEx_Plane: %s = %g: %s
    ERR_CONNECT_NO_LINE = 701       # ConnectCNCEx_Plane: no part at line %d of file %d
    ERR_CONNECT_NO_GINDEX = 702     # ConnectCNCEx_Plane: no part with G-code index %d
    ERR_CONNECT_NO_MFUNC = 703      # ConnectCNCEx_Plane: occurrence n = %d of M%d not found ...
    ERR_CONNECT_OFF_PART = 704      # ConnectCNCEx_Plane: the point lies %g mm from the part ...
    ERR_CONNECT_NO_MOTION = 705     # ConnectCNCEx_Plane: no motion to connect to in parts ...
