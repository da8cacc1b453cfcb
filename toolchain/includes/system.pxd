# C declarations of the compiler's builtins the library uses that Cython's own
# includes lack: atomics, streaming stores and bit counts. Gathered here, declared once (what
# comes from the operating system: platform.pxd).
from libc.stdint cimport int32_t, int64_t

# GCC/Clang atomic builtins on int32 flags shared between the host's threads and
# the core's worker thread (status, cancel requests).
cdef extern from *:
    """
    #define TC_ATOMIC_LOAD(p) __atomic_load_n((p), __ATOMIC_ACQUIRE)
    #define TC_ATOMIC_STORE(p, v) __atomic_store_n((p), (v), __ATOMIC_RELEASE)
    #define TC_ATOMIC_CAS(p, expected, desired) \
        __atomic_compare_exchange_n((p), (expected), (desired), 0, __ATOMIC_ACQ_REL, __ATOMIC_ACQUIRE)
    """
    int32_t TC_ATOMIC_LOAD(int32_t *p) nogil
    void TC_ATOMIC_STORE(int32_t *p, int32_t v) nogil
    bint TC_ATOMIC_CAS(int32_t *p, int32_t *expected, int32_t desired) nogil

# ... as reference counts of what threads share read-only (a compiled program, the
# axis correction tables): the count after the change; the one that reaches 0 frees.
cdef extern from *:
    """
    #define TC_REF_ADD(p) __atomic_add_fetch((p), 1, __ATOMIC_RELAXED)
    #define TC_REF_SUB(p) __atomic_sub_fetch((p), 1, __ATOMIC_ACQ_REL)
    """
    int32_t TC_REF_ADD(int32_t *p) nogil
    int32_t TC_REF_SUB(int32_t *p) nogil

# ... and on doubles set by one thread and read by others (the feed override).
cdef extern from *:
    """
    static inline double TC_ATOMIC_LOAD_D(double *p) { double v; __atomic_load(p, &v, __ATOMIC_ACQUIRE); return v; }
    static inline void TC_ATOMIC_STORE_D(double *p, double v) { __atomic_store(p, &v, __ATOMIC_RELEASE); }
    """
    double TC_ATOMIC_LOAD_D(double *p) nogil
    void TC_ATOMIC_STORE_D(double *p, double v) nogil

# Copies of parts into memory that is not read back soon (the merge of inserted
# parts): non-temporal stores skip reading each destination line first, a third of
# the merge's memory traffic; 16 bytes at a time where the destination allows. dst
# lies above src by at least 16 bytes (they may overlap): highest word first. The parts are copied as 8-byte words (may_alias), between compiler barriers
# so that no access to them as parts moves across the copy. tc_stream_fence orders
# the stores before the program is handed to other threads.
cdef extern from *:
    """
    #if defined(__x86_64__)
    #include <immintrin.h>
    typedef long long __attribute__((__may_alias__)) tc_word;
    static inline void tc_stream_up(void *dst, const void *src, size_t words) {
        tc_word *d = (tc_word *)dst;
        const tc_word *s = (const tc_word *)src;
        __asm__ __volatile__("" ::: "memory");
        /* highest first: a lone word up to a 16-byte boundary of the destination,
           then 16-byte stores, then a lone word at the bottom */
        if (words && ((size_t)(d + words) & 15)) {
            words--;
            _mm_stream_si64((long long *)(d + words), s[words]);
        }
        while (words >= 2) {
            words -= 2;
            _mm_stream_si128((__m128i *)(d + words), _mm_loadu_si128((const __m128i *)(s + words)));
        }
        if (words)
            _mm_stream_si64((long long *)d, s[0]);
        __asm__ __volatile__("" ::: "memory");
    }
    static inline void tc_stream_fence(void) { _mm_sfence(); }
    #else
    #include <string.h>
    static inline void tc_stream_up(void *dst, const void *src, size_t words) { memmove(dst, src, words * 8); }
    static inline void tc_stream_fence(void) {}
    #endif
    """
    void tc_stream_up(void *dst, const void *src, size_t words) nogil
    void tc_stream_fence() nogil


# Trailing and leading zero bits of a nonzero 64-bit word (the box index's levels:
# the largest group that starts at a position, or fits in a count).
cdef extern from *:
    int __builtin_ctzll(unsigned long long) nogil
    int __builtin_clzll(unsigned long long) nogil
