# Cross build of SF_TCh.dll for Windows x64 on Linux, with Debian's mingw-w64
# (apt: gcc-mingw-w64-x86-64). tools/build_windows.sh uses it:
#
#   cmake -S . -B build-windows -G Ninja -DCMAKE_BUILD_TYPE=Release \
#         -DCMAKE_TOOLCHAIN_FILE=cmake/mingw-w64-x86_64.cmake -DPython_EXECUTABLE=$(which python3)
#
# The compiler of the "win32" thread model: its thread-local storage and libgcc use
# Windows threads, so nothing pulls in winpthread (libwinpthread-1.dll). The
# "posix" variant would.
set(CMAKE_SYSTEM_NAME Windows)
set(CMAKE_SYSTEM_PROCESSOR x86_64)
set(MINGW_TRIPLET x86_64-w64-mingw32)
find_program(CMAKE_C_COMPILER NAMES ${MINGW_TRIPLET}-gcc-win32 ${MINGW_TRIPLET}-gcc REQUIRED)
find_program(CMAKE_RC_COMPILER NAMES ${MINGW_TRIPLET}-windres)
set(CMAKE_FIND_ROOT_PATH /usr/${MINGW_TRIPLET})
# programs (Python, Cython) from the build machine; libraries and headers of the target
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
