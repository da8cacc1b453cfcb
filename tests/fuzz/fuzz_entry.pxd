# The library's faces, for the stages fuzz_entry.pyx includes.
include "libSF_TCh.pxd"
