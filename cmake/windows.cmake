# SF_TCh.dll for Windows x64 or x86, cross-built with mingw-w64 (included by CMakeLists.txt
# when the toolchain file cmake/mingw-w64-x86_64.cmake or cmake/mingw-w64-i686.cmake
# targets Windows; docs/hosts.md).
#
# Python's headers: Cython's C file includes Python.h. Include/ of the Python that
# runs Cython is copied without its pyconfig.h (it describes Linux: 8-byte long,
# 4-byte wchar_t) and cmake/mingw/pyconfig.h, written for mingw-w64 x64, is put in
# its place (it describes x64 or x86 by the compiler's _WIN64). Nothing of Python is
# linked: see the exports below.
execute_process(COMMAND ${Python_EXECUTABLE} -c "import sysconfig; print(sysconfig.get_paths()['include'])"
                OUTPUT_VARIABLE PYTHON_HOST_INCLUDE OUTPUT_STRIP_TRAILING_WHITESPACE COMMAND_ERROR_IS_FATAL ANY)
set(PYTHON_WINDOWS_INCLUDE ${CMAKE_CURRENT_BINARY_DIR}/python-include)
file(COPY ${PYTHON_HOST_INCLUDE}/ DESTINATION ${PYTHON_WINDOWS_INCLUDE} PATTERN pyconfig.h EXCLUDE)
configure_file(${CMAKE_CURRENT_SOURCE_DIR}/cmake/mingw/pyconfig.h ${PYTHON_WINDOWS_INCLUDE}/pyconfig.h COPYONLY)

add_library(SF_TCh SHARED ${GENERATED_C})
# SF_TCh.dll as the vendor names it; the import library SF_TCh.lib for C/C++ hosts
# that link instead of LoadLibrary, and SF_TCh.def (the export list) for MSVC's lib.exe
set_target_properties(SF_TCh PROPERTIES PREFIX "" IMPORT_PREFIX "" IMPORT_SUFFIX ".lib")
target_include_directories(SF_TCh PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/include ${TOOLCHAIN_DIR}/includes
                           ${PYTHON_WINDOWS_INCLUDE})
# The exports: the header declares every function __declspec(dllexport) for the
# library's build (SF_TCH_BUILDING_DLL; dllimport for a panel); TGM_Data, a
# Cython "public" variable, gets it through Cython's DL_EXPORT; PyInit_libSF_TCh does
# not (CYTHON_NO_PYINIT_EXPORT). -fwhole-program makes everything else of the one C
# file static, so the compiler drops all it does not reach from an export: Cython's
# module code (PyInit_libSF_TCh and everything behind it) is never emitted and no
# CPython symbol is left to import. (--gc-sections alone, as on Linux, cannot do this
# for PE: every function's unwind data keeps it alive; here it only drops the unused
# pointers to CPython's data the compiler emitted.) The link fails on any undefined
# symbol left, as -z defs does on Linux.
target_compile_options(SF_TCh PRIVATE -DSF_TCH_BUILDING_DLL "-DDL_EXPORT(t)=__declspec(dllexport) t" -DCYTHON_NO_PYINIT_EXPORT
                       -fwhole-program -Wno-unused-function -Wno-unused-variable
                       # a text of the host (wchar_t here) handed on as char *, or back: an error
                       -Werror=incompatible-pointer-types)
# x86: SSE2 floating point, as on x64 (double rounding of x87's 80-bit registers would
# give other last bits); Windows x86 has had SSE2 on every processor it supports since 8
if(CMAKE_SIZEOF_VOID_P EQUAL 4)
  target_compile_options(SF_TCh PRIVATE -msse2 -mfpmath=sse)
endif()
# only Windows system DLLs at run time: libgcc (thread-local storage) is linked in
target_link_options(SF_TCh PRIVATE -static-libgcc -Wl,--no-undefined -Wl,--gc-sections
                    -Wl,--output-def,${CMAKE_CURRENT_BINARY_DIR}/SF_TCh.def)

install(TARGETS SF_TCh RUNTIME DESTINATION sf_tch ARCHIVE DESTINATION sf_tch)
install(FILES include/tgm_cnc.h DESTINATION sf_tch/include)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/SF_TCh.def DESTINATION sf_tch)
