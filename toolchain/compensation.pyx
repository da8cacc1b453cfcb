# Tool radius compensation G41-G48 / G40 (placeholder until the compensation lands).

cdef int compensate_program(Program *prog, const GCODE_PARAMETERS *params, ErrorInfo *err,
                            output_fn output, void *ctx) noexcept nogil:
    """Computes the compensated path (Part.ce, Part.radius, inserted parts) of every
    part with comp 41/42; COMPILE_OK or COMPILE_ERROR with err filled."""
    set_error_text(err, ERR_NOT_IMPLEMENTED, prog.main_file_idx, 0, "tool radius compensation")
    return COMPILE_ERROR
