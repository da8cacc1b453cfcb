# The error catalogue: numbers are stable, part of the documented behaviour
# (docs/errors.md lists them). The enum ErrorNumber, the English formats and the
# names of the statuses are generated from toolchain/errors.toml and the header's
# enum cnc_status by tools/gen_catalogue.py; set_error (errors.pyx) formats them.
include "catalogue.pxi"
