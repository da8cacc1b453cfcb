# The library's faces, for the library's stages this test module includes.
include "libSF_TCh.pxd"
