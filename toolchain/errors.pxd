# Face of errors.pyx: the error catalogue and the one way an error is recorded.
# Numbers are stable, part of the documented behaviour (docs/errors.md lists them).
# The enum ErrorNumber, the English formats and the names of the statuses are
# generated from toolchain/errors.toml and the header's enum cnc_status by
# tools/gen_catalogue.py (catalogue.pxi); set_error (errors.pyx) formats them.
# Owns ErrorInfo (one error with its location and texts). Every stage that fails
# calls set_error; the core and the exports read the errors out.
include "catalogue.pxi"


# One error: number of the catalogue (errors.pyx), location and the formatted texts.
cdef enum:
    ERROR_TEXT_BYTES = 1024
    ERROR_ARGS_BYTES = 512

ctypedef struct ErrorInfo:
    int32_t number          # 0 = no error
    int32_t file_idx
    int32_t line            # 1-based, 0 unknown
    int32_t n_lines
    char text[ERROR_TEXT_BYTES] # full English text
    char args[ERROR_ARGS_BYTES] # arguments separated by '\n'

# One argument of an error format: a number, or a string when text is not NULL.
ctypedef struct ErrArg:
    double num
    const char *text


# ---- what other stages call
# an error of the catalogue with its arguments formatted into err (file index, line:
# where), shorthands for one text or one number; "<what> not allowed in status ..."
# and a status's name; no error
cdef void set_error(ErrorInfo *err, int32_t number, int32_t file_idx, int32_t line,
                    const ErrArg *args, int n_args) noexcept nogil
cdef void set_error_text(ErrorInfo *err, int32_t number, int32_t file_idx, int32_t line,
                         const char *text) noexcept nogil
cdef void set_error_num(ErrorInfo *err, int32_t number, int32_t file_idx, int32_t line,
                        double value) noexcept nogil
cdef void set_error_status(ErrorInfo *err, const char *what, int32_t status) noexcept nogil
cdef void clear_error(ErrorInfo *err) noexcept nogil
