# cython: language_level=3, boundscheck=False, wraparound=False, cdivision=True
# cython: initializedcheck=False, nonecheck=False, overflowcheck=False
from libc.stdint cimport int8_t, int16_t, int32_t, int64_t, uint8_t, uint16_t, uint32_t, uint64_t, intptr_t, INT32_MAX
from includes.tgm_cnc cimport *
from includes.system cimport *

include "arrays.pxd"
include "numbers.pxd"
include "errors.pxd"
include "geometry.pxd"
include "program.pxd"
include "compiler/compiler.pxd"
include "compensation/compensation.pxd"
include "extent.pxd"
include "planner/planner.pxd"
include "pipeline.pxd"
include "placement.pxd"
include "logging.pxd"
include "files.pxd"
include "ini.pxd"
include "parameters.pxd"
include "core.pxd"
include "runtime/runtime.pxd"
include "machine/machine.pxd"
include "simulator.pxd"
include "toolpath.pxd"
include "exports.pxd"
