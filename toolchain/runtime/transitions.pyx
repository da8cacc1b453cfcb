# The status machine of a core in one table: for every status of the header and every
# command (a host call, or the end of the worker's activity) the status that follows,
# or a refusal. The core asks the table before it acts; tests read it as a table
# (tests/test_transitions.py).

cdef extern from *:
    """
    /* Entries: a status, or one of these. */
    #define TC_REFUSED   (-1234)  /* the command is refused in this status (-1) */
    #define TC_KEEP      (-9999)  /* accepted, the status stays */
    #define TC_AT_START  (-9998)  /* -30 with a compiled program, else -1 (0 from 0) */
    #define R TC_REFUSED
    #define K TC_KEEP
    #define S TC_AT_START
    /* One row per status, in the order of the header's enum cnc_status (status_row of
       catalogue.pxi, generated from the header). -1234 is StatusCNC's answer for a bad
       core, never a core's status: its row refuses every command. */
    /*                     COMPILE SIM TEST STOP RESET DESTROY DROP  OUT  PARAMS INI PREFIX DONE STOPPED FWD FWD_NO_M BACK FWD_SKIP_M GOTO CONNECT M0 */
    static const int32_t tc_transitions[][20] = {
    /*    0 */            {    1,   10,   20,    R,    S,    0,    R,    R,    K,    K,    K,    R,    R,    R,    R,    R,    R,   50,    R,    R },
    /*   -2 */            {    1,   10,   20,    R,    S,    0,    0,  -50,    K,    K,    K,    R,    R,    R,    R,    R,    R,    R,    R,    R },
    /*    1 */            {    R,    R,    R,    R,    S,    0,    R,    R,    R,    R,    R,   -1,    R,    R,    R,    R,    R,    R,    R,    R },
    /*   -1 */            {    1,   10,   20,    R,    S,    0,    0,  -50,    K,    K,    K,    R,    R,   30,   31,    R,   33,   50,    R,    R },
    /*   10 */            {    R,    R,    R,    K,    S,    0,    R,    R,    R,    R,    K,  -10,  -11,    R,    R,    R,    R,    R,    R,    R },
    /*  -10 */            {    1,   10,   20,    R,    S,    0,    0,  -50,    K,    K,    K,    R,    R,   30,   31,    R,   33,   50,    R,    R },
    /*  -11 */            {    1,   10,   20,    R,    S,    0,    0,  -50,    K,    K,    K,    R,    R,   30,   31,    R,   33,   50,    R,    R },
    /*   20 */            {    R,    R,    R,    K,    S,    0,    R,    R,    R,    R,    K,  -20,  -21,    R,    R,    R,    R,    R,    R,    R },
    /*  -20 */            {    1,   10,   20,    R,    S,    0,    0,  -50,    K,    K,    K,    R,    R,   30,   31,    R,   33,   50,    R,    R },
    /*  -21 */            {    1,   10,   20,    R,    S,    0,    0,  -50,    K,    K,    K,    R,    R,   30,   31,    R,   33,   50,    R,    R },
    /*  -30 */            {    1,   10,   20,    R,    S,    0,    0,  -50,    K,    K,    K,    R,    R,   30,   31,    R,   33,   50,   40,    R },
    /*  -31 */            {    1,   10,   20,    R,    S,    0,    0,  -50,    K,    K,    K,    R,    R,   30,   31,   32,   33,   50,   40,    R },
    /*  -32 */            {    1,   10,   20,    R,    S,    0,    0,  -50,    K,    K,    K,    R,    R,    R,    R,   32,    R,   50,   40,    R },
    /*  -33 */            {    1,   10,   20,    R,    S,    0,    0,  -50,    K,    K,    K,    R,    R,   30,   31,   32,   33,   50,   40,    R },
    /*   30 */            {    R,    R,    R,    K,    S,    0,    R,    R,    R,    R,    K,  -32,  -31,    R,    R,    R,    R,    R,    R,  -33 },
    /*   31 */            {    R,    R,    R,    K,    S,    0,    R,    R,    R,    R,    K,  -32,  -31,    R,    R,    R,    R,    R,    R,    R },
    /*   32 */            {    R,    R,    R,    K,    S,    0,    R,    R,    R,    R,    K,  -30,  -31,    R,    R,    R,    R,    R,    R,    R },
    /*   33 */            {    R,    R,    R,    K,    S,    0,    R,    R,    R,    R,    K,  -32,  -31,    R,    R,    R,    R,    R,    R,  -33 },
    /*   40 */            {    R,    R,    R,    K,    S,    0,    R,    R,    R,    R,    K,  -31,  -50,    R,    R,    R,    R,    R,    R,    R },
    /*   41 */            {    R,    R,    R,    K,    S,    0,    R,    R,    R,    R,    K,  -31,  -50,    R,    R,    R,    R,    R,    R,    R },
    /*   50 */            {    R,    R,    R,    K,    S,    0,    R,    R,    R,    R,    K,  -50,  -50,    R,    R,    R,    R,    R,    R,    R },
    /*  -50 */            {    1,   10,   20,    R,    S,    0,    0,  -50,    K,    K,    K,    R,    R,    R,    R,    R,    R,   50,   40,    R },
    /*   60 */            {    R,    R,    R,    R,    S,    0,    R,    R,    R,    R,    K,    R,    R,    R,    R,    R,    R,    R,    R,    R },
    /*   70 */            {    R,    R,    R,    K,    S,    0,    R,    R,    R,    R,    K,    R,  -31,    R,    R,    R,    R,    R,    R,    R },
    /*   80 */            {    R,    R,    R,    K,    S,    0,    R,    R,    R,    R,    K,    R,  -31,    R,    R,    R,    R,    R,    R,    R },
    /*   90 */            {    R,    R,    R,    K,    S,    0,    R,    R,    R,    R,    K,  -31,  -31,    R,    R,    R,    R,    R,    R,    R },
    /* -1234 */           {    R,    R,    R,    R,    R,    R,    R,    R,    R,    R,    R,    R,    R,    R,    R,    R,    R,    R,    R,    R }};
    _Static_assert(sizeof(tc_transitions) / sizeof(tc_transitions[0]) == TC_N_STATUSES,
                   "tc_transitions: one row for every status of enum cnc_status");
    #undef R
    #undef K
    #undef S
    """
    const int32_t tc_transitions[][20]


cdef int32_t status_after(int32_t status, int32_t command, bint has_program) noexcept nogil:
    """The status that `command` leads to from `status`: a status, TC_KEEP, or
    TC_REFUSED (also for a value that is not a status)."""
    cdef int32_t row = status_row(status)
    cdef int32_t after
    if row < 0 or command < 0 or command >= N_COMMANDS:
        return TC_REFUSED
    after = tc_transitions[row][command]
    if after == TC_AT_START:
        if has_program:
            return CNC_STATUS_AT_START
        return CNC_STATUS_NOTHING_LOADED if status == CNC_STATUS_NOTHING_LOADED else CNC_STATUS_COMPILED
    return after

