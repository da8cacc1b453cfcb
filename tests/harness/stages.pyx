# cython: language_level=3, boundscheck=False, wraparound=False, cdivision=True
# cython: initializedcheck=False, nonecheck=False, overflowcheck=False
#
# Test-only Python module: the library's stages (toolchain/libSF_TCh.pyx, its faces
# through stages.pxd) and Python entry points into them, so that a stage can be
# tested alone, without ctypes and the core's threads. It reaches into the stages'
# own (underscored) functions where a test needs them. Built once per source state
# (tests/harness/__init__.py). The entry points of each stage:
include "libSF_TCh.pyx"

from libc.stdlib cimport malloc, calloc
from libc.string cimport strncat
from libc.math cimport fabs
from posix.time cimport clock_gettime, timespec

cdef extern from "<time.h>" nogil:
    enum: CLOCK_MONOTONIC
    enum: CLOCK_THREAD_CPUTIME_ID

import time as _time


def default_params():
    """bytes of GCODE_PARAMETERS with the documented defaults."""
    cdef GCODE_PARAMETERS p
    default_gcode_parameters(&p)
    return (<char *>&p)[:sizeof(GCODE_PARAMETERS)]


cdef void _fill(double *out, values, int n) except *:
    """out[0..n) = values, padded with zeros."""
    cdef int k
    for k in range(n):
        out[k] = float(values[k]) if k < len(values) else 0.0


include "geometry.pxi"
include "box_index.pxi"
include "compensation.pxi"
include "planner.pxi"
include "connect.pxi"
include "machine.pxi"
