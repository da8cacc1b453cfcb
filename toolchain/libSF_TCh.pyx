# cython: language_level=3, boundscheck=False, wraparound=False, cdivision=True
# cython: initializedcheck=False, nonecheck=False, overflowcheck=False
#
# libSF_TCh: the CNC module library. One C library built from the stages below,
# in pipeline order. Every function is C-level and runs without the GIL; no code
# here needs the Python module to be initialised, so a host may load the library
# with ctypes alone. Module-level variables are therefore only zero-initialised C
# statics (constants live in functions or C literals).
from libc.stdint cimport int8_t, int16_t, int32_t, int64_t, uint8_t, uint16_t, uint32_t, uint64_t, intptr_t, INT32_MAX
from includes.tgm_cnc cimport *
from includes.system cimport *
from program cimport *
from errors cimport *
from core cimport *

include "numbers.pyx"
include "errors.pyx"
include "geometry.pyx"
include "program.pyx"
include "extent.pyx"              # early: pipeline.pyx measures it beside the merge
include "pipeline.pyx"
include "compiler/compiler.pxd"      # the Block of block.pyx, the ISO mode's state
include "compiler/lexer.pyx"
include "compiler/state.pyx"
include "compiler/expressions.pyx"
include "compiler/labels.pyx"
include "compiler/flow.pyx"
include "compiler/emit.pyx"
include "compiler/ngc_params.pyx"
include "compiler/words.pyx"
include "compiler/dialects.pyx"
include "compiler/ngc_flow.pyx"
include "compiler/ngc_motion.pyx"
include "compiler/block.pyx"
include "compiler/compiler.pyx"
include "compensation/offsets.pyx"
include "compensation/corners.pyx"
include "compensation/strategy.pyx"
include "compensation/crossings.pyx"
include "compensation/compensation.pyx"
include "compensation/insert_arcs.pyx"
include "placement.pyx"
include "planner/segment.pyx"
include "planner/ramps.pyx"
include "planner/limits.pyx"
include "planner/junctions.pyx"
include "planner/mfunc_insert.pyx"
include "planner/passes.pyx"
include "machine/connect_search.pyx"
include "logging.pyx"
include "files.pyx"
include "ini.pyx"
include "parameters.pyx"
include "runtime/transitions.pyx"
include "runtime/snapshot.pyx"
include "runtime/programs.pyx"
include "runtime/callbacks.pyx"
include "runtime/file_names.pyx"
include "core.pyx"
include "simulator.pyx"
include "machine/motion.pyx"
include "machine/machine.pyx"
include "machine/connect.pyx"
include "toolpath.pyx"
include "exports.pyx"
