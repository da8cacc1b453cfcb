# The English texts of the error catalogue (numbers in errors.pxd) and the one way
# an error is recorded: set_error formats the text and its '\n'-separated arguments
# (numbers with a '.' decimal point under any locale: numbers.pyx c_snprintf).
from libc.string cimport memset, strlen
from errors cimport *


cdef const char *error_format(int32_t number) noexcept nogil:
    if number == ERR_FILE_OPEN: return "Cannot open file '%s'"
    if number == ERR_FILE_READ: return "Cannot read file '%s'"
    if number == ERR_INI_OPEN: return "Cannot open INI file '%s'"
    if number == ERR_OUT_OF_MEMORY: return "Out of memory"
    if number == ERR_CANCELLED: return "Compilation interrupted"
    if number == ERR_NOTHING_COMPILED: return "No compiled program"
    if number == ERR_DRIVER_REFUSED: return "Driver callback %s returned %d"
    if number == ERR_BUSY: return "Core busy: %s"
    if number == ERR_BAD_STATUS: return "%s not allowed in status %d (%s)"
    if number == ERR_REENTRANT: return "%s is not allowed inside a callback of the core's running activity"
    if number == ERR_BAD_REGIME: return "StartCNCEx: unknown regime"
    if number == ERR_NO_M_PENDING: return "No M function waits for a confirmation"
    if number == ERR_M_PENDING: return "An M function still waits for its confirmation (ToolChainCore_ConfirmMFunc)"
    if number == ERR_NOT_IMPLEMENTED: return "%s is not implemented yet"
    if number == ERR_INI_FIRST: return "Callback %d needs LoadFromIni first"
    if number == ERR_FILE_TOO_LARGE: return "File '%s' is larger than 1 GiB"
    if number == ERR_NOT_REGULAR_FILE: return "'%s' is not a regular file"
    if number == ERR_NOT_FINITE: return "%s = %g is not a finite number"
    if number == ERR_OUT_OF_RANGE: return "%s = %g is outside <%g, %g>"
    if number == ERR_INI_VALUE: return "INI file '%s' line %d: %s"
    if number == ERR_UNKNOWN_WORD: return "Unknown word '%s' at column %d"
    if number == ERR_BAD_NUMBER: return "Bad number '%s' at column %d"
    if number == ERR_MISSING_VALUE: return "Address %s at column %d without a value"
    if number == ERR_UNBALANCED_BRACKETS: return "Unbalanced brackets: '(' at column %d not closed"
    if number == ERR_UNTERMINATED_COMMENT: return "Comment '(' at column %d not closed on this line"
    if number == ERR_LINE_TOO_LONG: return "Line longer than %d characters"
    if number == ERR_BAD_VALUE: return "Bad value %g of address %s"
    if number == ERR_TOO_MANY_WORDS: return "More than %d %s words on one line"
    if number == ERR_NUMBER_OVERFLOW: return "Number '%s' at column %d is too large"
    if number == ERR_P_WORD:
        return "Word '%s' at column %d: P is reserved for parameters P00..P99 (Pnn = value); %s"
    if number == ERR_NOT_TG: return "'%s' at column %d is not TG G-code: %s"
    if number == ERR_NGC_UNSUPPORTED: return "'%s' at column %d is not supported in the ISO compatibility mode: %s"
    if number == ERR_PARAM_STACK: return "G900 parameter stack %s"
    if number == ERR_NOT_FINITE_RESULT: return "Expression '%s' does not give a finite number"
    if number == ERR_NGC_UNDEFINED: return "Named parameter '%s' at column %d is not defined"
    if number == ERR_NGC_UNREADABLE: return "Parameter '%s' at column %d cannot be read: %s"
    if number == ERR_NGC_PARAMETER: return "Parameter #%g at column %d does not exist (#1..#5601)"
    if number == ERR_NGC_READ_ONLY: return "Parameter '%s' at column %d is read-only"
    if number == ERR_DIVISION_BY_ZERO: return "Division by zero"
    if number == ERR_BAD_PARAMETER: return "Parameter P%g at column %d does not exist (P00..P99)"
    if number == ERR_BAD_EXPRESSION: return "Syntax error in expression '%s' at column %d"
    if number == ERR_UNKNOWN_FUNCTION: return "Unknown function '%s' at column %d"
    if number == ERR_MATH_DOMAIN: return "Argument out of domain in %s(%g)"
    if number == ERR_BAD_PLC_ADDRESS: return "PLC address %g out of range (1..%d)"
    if number == ERR_UNDEFINED_LABEL: return "Undefined label '%s'"
    if number == ERR_DUPLICATE_LABEL: return "Label '%s' defined twice (first on line %d)"
    if number == ERR_UNBALANCED_END: return "END without FOR, WHILE or IF"
    if number == ERR_MISSING_END: return "%s without END"
    if number == ERR_CALL_STACK_OVERFLOW: return "Subroutine calls nested deeper than %d"
    if number == ERR_RETURN_WITHOUT_CALL: return "RETURN outside a subroutine"
    if number == ERR_BLOCK_LIMIT: return "More than %d blocks executed: endless loop?"
    if number == ERR_BREAK_OUTSIDE_LOOP: return "%s outside a loop"
    if number == ERR_BAD_CONDITION: return "Bad condition '%s' at column %d"
    if number == ERR_PART_LIMIT: return "More than %d parts: program too large"
    if number == ERR_O_WORD: return "O-word '%s' at column %d: %s"
    if number == ERR_O_UNDEFINED: return "Subroutine '%s' at column %d is not defined before its call"
    if number == ERR_ARC_CENTRE:
        return ("Wrongly entered centre of circular interpolation %s at column %d: "
                "start %s = %g %s = %g, end %s = %g %s = %g, delta (%.7f) > 2*R (%.7f)")
    if number == ERR_ARC_RADII:
        return ("Wrongly entered centre of circular interpolation %s at column %d: "
                "start %s = %g %s = %g, end %s = %g %s = %g, radius at start (%.7f) <> radius at end (%.7f)")
    if number == ERR_ARC_RADIUS: return "Arc radius %g too small for chord %g"
    if number == ERR_ARC_NO_CENTRE: return "Arc without centre (I J K or R)"
    if number == ERR_BAD_PLANE: return "Bad plane G%d"
    if number == ERR_BAD_G: return "Unknown G function G%g at column %d"
    if number == ERR_BAD_M: return "Bad M function M%g at column %d"
    if number == ERR_ISO_G: return "G%g at column %d is not TG G-code: %s"
    if number == ERR_NO_FEED: return "G%g at column %d with feed 0: no F word was given (LinuxCNC refuses it)"
    if number == ERR_NO_MOTION_MODE:
        return "Axis word '%s' at column %d without a motion mode (G0 G1 G2 G3 or a canned cycle)"
    if number == ERR_NGC_G: return "G%g at column %d: %s"
    if number == ERR_NGC_WORD: return "'%s' at column %d: %s"
    if number == ERR_MACHINE_LIMIT: return "Axis %s position %g outside the machine limits <%g, %g>"
    if number == ERR_COMP_NOT_FOUND: return "Intersection of equidistants not found"
    if number == ERR_COMP_ON_ARC: return "Compensation switched on or off on an arc"
    if number == ERR_COMP_PLANE_CHANGE: return "Plane changed while tool radius compensation is active"
    if number == ERR_COMP_NEGATIVE_ARC: return "Arc radius %g smaller than the tool radius %g"
    if number == ERR_COMP_CROSSING: return "Equidistants cross: the tool (radius %g) does not fit the contour"
    if number == ERR_COMP_LOOKAHEAD: return "More than %d blocks without motion in the compensation plane"
    if number == ERR_CONNECT_BAD_ARGUMENT: return "ConnectCNCEx_Plane: %s = %g: %s"
    if number == ERR_CONNECT_NO_LINE: return "ConnectCNCEx_Plane: no part at line %d of file %d"
    if number == ERR_CONNECT_NO_GINDEX: return "ConnectCNCEx_Plane: no part with G-code index %d"
    if number == ERR_CONNECT_NO_MFUNC:
        return "ConnectCNCEx_Plane: occurrence n = %d of M%d not found (%d in that direction)"
    if number == ERR_CONNECT_OFF_PART:
        return "ConnectCNCEx_Plane: the point lies %g mm from the part with G-code index %d (tolerance %g mm)"
    if number == ERR_CONNECT_NO_MOTION:
        return "ConnectCNCEx_Plane: no motion to connect to in parts %d to %d (the program has %d)"
    if number == WARN_COMP: return "Tool radius compensation: %s"
    if number == WARN_G43_H:
        return ("G43 with H at column %d: TG's G43 switches on tool radius compensation with "
                "correction[2], it is no tool length offset (isoCompat: ignored)")
    if number == WARN_O_AT_START:
        return ("O%g at column %d at the start of the program moves the O axis; a program "
                "number? (isoCompat: ignored)")
    if number == WARN_G18_ARC:
        return ("G18 arc at column %d after an ISO header (G21 / G90): TG's G18 is the XZ plane "
                "with arcs turning the other way than ISO's ZX plane, which is TG's G-18 "
                "(isoCompat: G18 is read as G-18)")
    if number == WARN_ZERO_WITH_MOVE:
        return ("G%g at column %d with axis words sets the zero offset to them; the axes do not "
                "move (isoCompat: G54..G59 keep the offset and the line moves)")
    if number == WARN_NO_FEED:
        return ("G%g at column %d at feed 0 (no F word yet, or F0) moves at GCODE_PARAMETERS motion[1].feed; "
                "LinuxCNC refuses a feed of 0 (isoCompat: error 410)")
    if number == WARN_BARE_AXES:
        return ("Axis words at column %d before any G0..G3 move as G1; LinuxCNC refuses axis words "
                "without a motion mode (isoCompat: error 411)")
    if number == WARN_DWELL_WITH_MOTION:
        return ("G4 at column %d with G%g: the line dwells and does not move (isoCompat: "
                "the dwell, then the move)")
    if number == WARN_G90_MOVES_G1:
        return ("G%g at column %d with axis words moves as G1; ISO moves with the modal G%g "
                "(isoCompat)")
    if number == WARN_ISO_IGNORED: return "'%s' at column %d ignored (ISO compatibility mode)"
    return NULL


cdef const char *status_name(int32_t status) noexcept nogil:
    """Every cnc_status of the API (include/tgm_cnc.h) by name, for error texts;
    "unknown" for a value that is not a status."""
    if status == CNC_STATUS_NOTHING_LOADED: return "nothing loaded"
    if status == CNC_STATUS_NOT_CONNECTED: return "remote device not connected"
    if status == CNC_STATUS_COMPILING: return "compiling"
    if status == CNC_STATUS_COMPILED: return "compilation finished"
    if status == CNC_STATUS_SIMULATING: return "simulating"
    if status == CNC_STATUS_SIMULATION_DONE: return "simulation finished"
    if status == CNC_STATUS_SIMULATION_STOPPED: return "simulation stopped"
    if status == CNC_STATUS_TESTING: return "test running"
    if status == CNC_STATUS_TEST_DONE: return "test finished"
    if status == CNC_STATUS_TEST_STOPPED: return "test stopped"
    if status == CNC_STATUS_AT_START: return "at the start of the trajectory"
    if status == CNC_STATUS_STOPPED: return "stopped on the trajectory"
    if status == CNC_STATUS_AT_END: return "end of the trajectory"
    if status == CNC_STATUS_STOPPED_BY_M0: return "stopped by M0"
    if status == CNC_STATUS_FORWARD: return "running forward"
    if status == CNC_STATUS_FORWARD_NO_M: return "running forward without M functions"
    if status == CNC_STATUS_BACKWARD: return "running backward"
    if status == CNC_STATUS_FORWARD_SKIP_FIRST_M: return "running forward skipping the first M functions"
    if status == CNC_STATUS_CONNECT_CALCULATING: return "calculating the connection"
    if status == CNC_STATUS_CONNECT_MOVING: return "moving to the connection point"
    if status == CNC_STATUS_MANUAL_MOVE: return "manual move"
    if status == CNC_STATUS_OUT_OF_TRAJECTORY: return "out of the trajectory"
    if status == CNC_STATUS_INTERNAL_CALC: return "internal calculation"
    if status == CNC_STATUS_SENDING_START_M: return "sending start M functions"
    if status == CNC_STATUS_SENDING_STOP_M: return "sending stop M functions"
    if status == CNC_STATUS_SENDING_CONNECT_M: return "sending connect M functions"
    if status == CNC_STATUS_INVALID: return "invalid"
    return "unknown"


cdef void set_error_status(ErrorInfo *err, const char *what, int32_t status) noexcept nogil:
    """ERR_BAD_STATUS: `what` is not allowed in `status` (number and name)."""
    cdef ErrArg a[3]
    a[0].num = 0
    a[0].text = what
    a[1].num = status
    a[1].text = NULL
    a[2].num = 0
    a[2].text = status_name(status)
    set_error(err, ERR_BAD_STATUS, -1, 0, a, 3)


cdef size_t _append(char *buf, size_t cap, size_t pos, const char *s, size_t n) noexcept nogil:
    # Copies n bytes of s at buf[pos], truncating at cap - 1; keeps buf terminated.
    cdef size_t i = 0
    while i < n and pos + 1 < cap:
        buf[pos] = s[i]
        pos += 1
        i += 1
    buf[pos] = 0
    return pos


cdef void set_error(ErrorInfo *err, int32_t number, int32_t file_idx, int32_t line,
                    const ErrArg *args, int n_args) noexcept nogil:
    """Records error `number` at file/line: the catalogue's format with `args`
    substituted in order (numbers for %g %f %d ..., texts for %s)."""
    cdef const char *fmt = error_format(number)
    cdef char spec[16]
    cdef char piece[256]
    cdef size_t tpos = 0, apos = 0, k
    cdef int used = 0, n
    cdef const char *p = fmt
    cdef char conv
    cdef const char *text_arg
    err.number = number
    err.file_idx = file_idx
    err.line = line
    err.text[0] = 0
    err.args[0] = 0
    if fmt == NULL:  # not in the catalogue: keep the number visible
        n = c_snprintf(piece, sizeof(piece), "Error %d", number)
        _append(err.text, ERROR_TEXT_BYTES, 0, piece, <size_t>n)
        return
    while p[0] != 0:
        if p[0] != b'%':
            tpos = _append(err.text, ERROR_TEXT_BYTES, tpos, p, 1)
            p += 1
            continue
        if p[1] == b'%':
            tpos = _append(err.text, ERROR_TEXT_BYTES, tpos, p, 1)
            p += 2
            continue
        # copy the conversion spec: flags, width, precision, then the conversion letter
        k = 0
        while p[k] != 0 and k < 15 and not (p[k] in b'gGfFeEdisx' and k > 0):
            spec[k] = p[k]
            k += 1
        if p[k] == 0 or k >= 15:
            break
        conv = p[k]
        spec[k] = conv
        spec[k + 1] = 0
        p += k + 1
        if used < n_args:
            if conv == b's':
                text_arg = args[used].text
                if text_arg == NULL:
                    text_arg = "(null)"
                n = c_snprintf(piece, sizeof(piece), spec, text_arg)
            elif conv == b'd' or conv == b'i' or conv == b'x':
                n = c_snprintf(piece, sizeof(piece), spec, <int>args[used].num)
            else:
                n = c_snprintf(piece, sizeof(piece), spec, args[used].num)
            used += 1
        else:
            n = c_snprintf(piece, sizeof(piece), "?")
        if n < 0:
            n = 0
        if n >= <int>sizeof(piece):
            n = sizeof(piece) - 1
        tpos = _append(err.text, ERROR_TEXT_BYTES, tpos, piece, <size_t>n)
        if apos > 0:
            apos = _append(err.args, ERROR_ARGS_BYTES, apos, "\n", 1)
        apos = _append(err.args, ERROR_ARGS_BYTES, apos, piece, <size_t>n)


cdef void set_error_text(ErrorInfo *err, int32_t number, int32_t file_idx, int32_t line,
                         const char *text) noexcept nogil:
    """set_error with a single text argument."""
    cdef ErrArg a
    a.num = 0
    a.text = text
    set_error(err, number, file_idx, line, &a, 1)


cdef void set_error_num(ErrorInfo *err, int32_t number, int32_t file_idx, int32_t line,
                        double value) noexcept nogil:
    """set_error with a single numeric argument."""
    cdef ErrArg a
    a.num = value
    a.text = NULL
    set_error(err, number, file_idx, line, &a, 1)


cdef void clear_error(ErrorInfo *err) noexcept nogil:
    memset(err, 0, sizeof(ErrorInfo))
