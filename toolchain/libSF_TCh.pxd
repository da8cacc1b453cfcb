from libc.stdint cimport int8_t, int16_t, int32_t, int64_t, uint8_t, uint16_t, uint32_t, uint64_t, intptr_t, INT32_MAX
from includes.tgm_cnc cimport *
from includes.system cimport *

include "errors.pxd"
include "program.pxd"
include "core.pxd"
