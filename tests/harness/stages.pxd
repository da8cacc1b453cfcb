# The library's faces, for the stages stages.pyx includes.
include "libSF_TCh.pxd"
