/*
 * pyconfig.h for compiling Cython's C output with mingw-w64 for Windows x64 and x86.
 *
 * Why it exists: Cython's C file includes Python.h, so even the Windows build of the
 * library needs CPython's headers. Their platform-independent part (Include/ of the
 * Python that runs Cython) is the same on every system; only pyconfig.h describes the
 * target: Linux's says long is 8 bytes, wchar_t 4, and pulls in POSIX threads, which
 * would be wrong for Windows x64 (LLP64) and x86 (ILP32). This file replaces it in the cross build
 * (CMakeLists.txt copies Include/ without its pyconfig.h and puts this one beside it).
 *
 * The library itself never runs Python code: the module code that uses these headers
 * is unreachable from the exports and dropped at link time (docs/hosts.md), so the DLL
 * does not import python3x.dll. The values below must only make the declarations
 * compile with the right types; Py_ENABLE_SHARED stays undefined so that no CPython
 * symbol is declared __declspec(dllimport) and PyInit_* is not __declspec(dllexport).
 */
#ifndef Py_CONFIG_H
#define Py_CONFIG_H

#if !defined(__MINGW32__) || !(defined(_WIN64) ? defined(__x86_64__) : defined(__i386__))
#  error "this pyconfig.h is for mingw-w64 targeting Windows x64 or x86 only"
#endif

#if defined(_WIN64)
#define MS_WIN64
#endif
#define MS_WIN32
#define MS_WINDOWS
#define NT_THREADS
#define WITH_THREAD
#define Py_WINVER 0x0601
#define Py_NTDDI 0x06010000

/* x64, LLP64: long is 4 bytes, pointers and size_t 8; x86, ILP32: pointers and size_t
   4, long double 12 (mingw-w64's x87 type); time_t is 8 on both (mingw-w64's default);
   wchar_t is UTF-16 */
#define SIZEOF_SHORT 2
#define SIZEOF_INT 4
#define SIZEOF_LONG 4
#define SIZEOF_LONG_LONG 8
#if defined(_WIN64)
#define SIZEOF_VOID_P 8
#define SIZEOF_SIZE_T 8
#define SIZEOF_UINTPTR_T 8
#define SIZEOF_LONG_DOUBLE 16
#define ALIGNOF_SIZE_T 8
#else
#define SIZEOF_VOID_P 4
#define SIZEOF_SIZE_T 4
#define SIZEOF_UINTPTR_T 4
#define SIZEOF_LONG_DOUBLE 12
#define ALIGNOF_SIZE_T 4
#endif
#define SIZEOF_TIME_T 8
#define SIZEOF_OFF_T 4
#define SIZEOF_FPOS_T 8
#define SIZEOF_WCHAR_T 2
#define SIZEOF_FLOAT 4
#define SIZEOF_DOUBLE 8
#define SIZEOF__BOOL 1
#define SIZEOF_PID_T 4
#define ALIGNOF_LONG 4
#define HAVE_SSIZE_T 1
#define HAVE_WCHAR_H 1
#define HAVE_USABLE_WCHAR_T 1
#define PY_LONG_LONG long long
#define PY_FORMAT_SIZE_T "z"
#define DOUBLE_IS_LITTLE_ENDIAN_IEEE754 1
#define HAVE_STDARG_PROTOTYPES 1
#define STDC_HEADERS 1
#define HAVE_IO_H 1
#define HAVE_STDDEF_H 1
#define HAVE_SYS_TYPES_H 1
#define HAVE_SYS_STAT_H 1
#define HAVE_ERRNO_H 1
#define HAVE_FCNTL_H 1
#define HAVE_SIGNAL_H 1
#define HAVE_HYPOT 1
#define HAVE_COPYSIGN 1
#define HAVE_ROUND 1
#define HAVE_ERF 1
#define HAVE_ERFC 1
#define HAVE_LGAMMA 1
#define HAVE_TGAMMA 1
#define HAVE_ACOSH 1
#define HAVE_ASINH 1
#define HAVE_ATANH 1
#define HAVE_EXPM1 1
#define HAVE_LOG1P 1
#define HAVE_LOG2 1
#define Py_USING_UNICODE
#define WITH_DOC_STRINGS 1
#define WITH_PYMALLOC 1

#endif /* Py_CONFIG_H */
