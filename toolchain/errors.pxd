# Face of errors.pyx: the error catalogue and the one way an error is recorded.
# Numbers are stable, part of the documented behaviour (docs/errors.md lists them).
# The enum ErrorNumber, the English formats, the names of the statuses and one typed
# constructor per error (err_<name>(err, file_idx, at_line, arguments...)) are
# generated from toolchain/errors.toml and the header's enum cnc_status by
# tools/gen_catalogue.py (catalogue.pxi, included at the end). Owns ErrorInfo (one error
# with its location and texts). Every stage that fails calls its error's constructor;
# the core and the exports read the errors out.
from libc.stdint cimport int32_t


# One error: number of the catalogue, location and the formatted texts.
cdef enum:
    ERROR_TEXT_BYTES = 1024
    ERROR_ARGS_BYTES = 512

ctypedef struct ErrorInfo:
    int32_t number          # 0 = no error
    int32_t file_idx
    int32_t line            # 1-based, 0 unknown
    int32_t n_lines
    int32_t column          # 1-based column of the word in error, 0 unknown (beside the text)
    char text[ERROR_TEXT_BYTES] # full English text
    char args[ERROR_ARGS_BYTES] # the format's arguments in its order, separated by '\n'

# One argument of an error format: a number, or a string when text is not NULL.
ctypedef struct ErrArg:
    double num
    const char *text


# ---- what other stages call
# no error
cdef void clear_error(ErrorInfo *err) noexcept nogil

# ---- what only the generated constructors (catalogue.pxi) call: error `number` at
# file index and line (column beside the text, 0 none), its format filled with args
cdef void record_error(ErrorInfo *err, int32_t number, int32_t file_idx, int32_t line, int64_t column,
                       const ErrArg *args, int n_args) noexcept nogil

include "catalogue.pxi"
