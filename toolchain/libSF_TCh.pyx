# cython: language_level=3, boundscheck=False, wraparound=False, cdivision=True
# cython: initializedcheck=False, nonecheck=False, overflowcheck=False
#
# libSF_TCh: the CNC module library. One C library built from the stages below,
# in pipeline order. Every function is C-level and runs without the GIL; no code
# here needs the Python module to be initialised, so a host may load the library
# with ctypes alone. Module-level variables are therefore only zero-initialised C
# statics (constants live in functions or C literals).

# The faces (libSF_TCh.pxd, read first) declare every stage's types and the functions
# other stages call; the stages follow in the order they depend on each other
# (docs/architecture.md).

# the data and its tools
include "arrays.pyx"
include "numbers.pyx"
include "errors.pyx"
include "geometry.pyx"
include "box_index.pyx"
include "program.pyx"

# compile: text -> parts -> tool path -> extent -> feed plan
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
include "compiler/ngc_spline.pyx"
include "compiler/tools.pyx"
include "compiler/block.pyx"
include "compiler/compiler.pyx"
include "compensation/offsets.pyx"
include "compensation/corners.pyx"
include "compensation/strategy.pyx"
include "compensation/pass_state.pyx"
include "compensation/crossings.pyx"
include "compensation/clearance.pyx"
include "compensation/regions.pyx"
include "compensation/compensation.pyx"
include "compensation/insert_arcs.pyx"
include "compensation/join_lines.pyx"
include "extent.pyx"
include "planner/limits.pyx"
include "planner/junctions.pyx"
include "planner/mfunc_insert.pyx"
include "planner/profile.pyx"
include "planner/passes.pyx"
include "pipeline.pyx"                  # the stages side by side
include "placement.pyx"                 # a program where a run starts

# the host's settings
include "logging.pyx"
include "files.pyx"
include "ini.pyx"
include "smoothing/smoothing.pyx"       # the output's filters: their values are INI keys too
include "parameters.pyx"
include "tables/tool_table.pyx"         # the correction tables: files an INI key may name
include "tables/axis_correction.pyx"

# run: the core, its activities, the offline machine
include "runtime/transitions.pyx"
include "runtime/snapshot.pyx"
include "runtime/programs.pyx"
include "runtime/callbacks.pyx"
include "runtime/last_errors.pyx"
include "runtime/file_names.pyx"
include "runtime/lifecycle.pyx"
include "runtime/session.pyx"
include "core.pyx"
include "configuration.pyx"             # what a host sets on a core
include "machine/motion.pyx"
include "machine/place.pyx"
include "machine/clock.pyx"
include "machine/output.pyx"
include "machine/machine.pyx"
include "machine/connect_search.pyx"
include "machine/connect.pyx"
include "simulator.pyx"
include "toolpath.pyx"
include "exports.pyx"
