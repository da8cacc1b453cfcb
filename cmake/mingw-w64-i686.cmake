# Cross build of SF_TCh.dll for Windows x86 (32-bit panels) on Linux, with Debian's
# mingw-w64 (apt: gcc-mingw-w64-i686). tools/build_windows.sh --x86 uses it:
#
#   cmake -S . -B build-windows-x86 -G Ninja -DCMAKE_BUILD_TYPE=Release \
#         -DCMAKE_TOOLCHAIN_FILE=cmake/mingw-w64-i686.cmake -DPython_EXECUTABLE=$(which python3)
#
# As for x64 (cmake/mingw-w64-x86_64.cmake), the compiler of the "win32" thread model, so
# that nothing pulls in winpthread. cmake/windows.cmake adds SSE2 floating point
# (-msse2 -mfpmath=sse): x87's 80-bit intermediates would round differently from x64.
set(CMAKE_SYSTEM_NAME Windows)
set(CMAKE_SYSTEM_PROCESSOR x86)
set(MINGW_TRIPLET i686-w64-mingw32)
find_program(CMAKE_C_COMPILER NAMES ${MINGW_TRIPLET}-gcc-win32 ${MINGW_TRIPLET}-gcc REQUIRED)
find_program(CMAKE_RC_COMPILER NAMES ${MINGW_TRIPLET}-windres)
set(CMAKE_FIND_ROOT_PATH /usr/${MINGW_TRIPLET})
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
