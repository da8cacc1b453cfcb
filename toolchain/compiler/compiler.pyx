# G-code compiler (placeholder until the compiler lands): refuses every program.

cdef int compile_program(const CompileInput *inp, Program *prog, ErrorInfo *err) noexcept nogil:
    """Compiles inp.text (prefix, main, postfix) into prog; COMPILE_OK, or COMPILE_ERROR
    with err filled, or COMPILE_CANCELLED when inp.cancel was set."""
    set_error_text(err, ERR_NOT_IMPLEMENTED, inp.file_idx, 0, "the G-code compiler")
    return COMPILE_ERROR
