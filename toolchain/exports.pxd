# Face of exports.pyx: the exported C functions of include/tgm_cnc.h (the header is
# their declaration; the C compiler checks every signature against it). The top of
# the house: each export checks its arguments and calls into the core, the runtime,
# the machine and the other stages' faces. No stage calls an export, so this face
# declares nothing.
