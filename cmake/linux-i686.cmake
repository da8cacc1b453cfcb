# Build of libSF_TCh.so for Linux i686 (32-bit x86) on an x86_64 Linux with multilib
# (apt: gcc-multilib, which brings libc6-dev-i386). tools/build_x86.sh uses it to test
# the 32-bit code natively (the layouts of 4-byte pointers, the results with SSE2
# floating point) where Wine's 32-bit half cannot be installed:
#
#   cmake -S . -B build-linux-i686 -DCMAKE_BUILD_TYPE=Release \
#         -DCMAKE_TOOLCHAIN_FILE=cmake/linux-i686.cmake -DPython_EXECUTABLE=$(which python3)
#
# Python's headers come from the 64-bit Python that runs Cython, with a pyconfig.h that
# describes i686 (cmake/linux-i686/pyconfig.h.in; CMakeLists.txt). SSE2 floating point
# as for Windows x86 (cmake/windows.cmake): x87's 80-bit intermediates would round
# differently from x86_64.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR i686)
set(CMAKE_C_FLAGS_INIT "-m32 -msse2 -mfpmath=sse")
set(CMAKE_EXE_LINKER_FLAGS_INIT "-m32")
set(CMAKE_SHARED_LINKER_FLAGS_INIT "-m32")
set(CMAKE_MODULE_LINKER_FLAGS_INIT "-m32")
set(CMAKE_LIBRARY_ARCHITECTURE i386-linux-gnu)
