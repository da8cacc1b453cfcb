# cython: language_level=3, boundscheck=False, wraparound=False, cdivision=True
# cython: initializedcheck=False, nonecheck=False, overflowcheck=False
#
# The library module's own .pxd: Cython reads it before libSF_TCh.pyx. It includes
# the faces, one per stage, in the order their types build on each other: each
# declares the stage's types and what other stages may call (docs/architecture.md).
# The faces are included, never cimported: a cimported .pxd that declares functions
# makes Cython import it as a Python module, and the library must run without
# Python. Cython checks every function a face declares against its definition. The
# directives above hold for the faces' inline functions (those of the .pyx do not
# reach here).
from libc.stdint cimport int8_t, int16_t, int32_t, int64_t, uint8_t, uint16_t, uint32_t, uint64_t, intptr_t, INT32_MAX, INT32_MIN
from includes.tgm_cnc cimport *
from includes.system cimport *
from includes.platform cimport *

include "arrays.pxd"
include "numbers.pxd"
include "errors.pxd"
include "tables/tables.pxd"
include "program.pxd"
include "placement.pxd"
include "geometry.pxd"
include "box_index.pxd"
include "compiler/compiler.pxd"
include "compensation/compensation.pxd"
include "extent.pxd"
include "planner/planner.pxd"
include "pipeline.pxd"
include "logging.pxd"
include "files.pxd"
include "ini.pxd"
include "smoothing/smoothing.pxd"
include "parameters.pxd"
include "core.pxd"
include "runtime/runtime.pxd"
include "configuration.pxd"
include "machine/machine.pxd"
include "simulator.pxd"
include "toolpath.pxd"
include "exports.pxd"
