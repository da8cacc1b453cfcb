# C declarations of the system libraries the library uses that Cython's own
# includes lack: POSIX threads, memory advice and atomics. Gathered here, declared once.
from libc.stdint cimport int32_t, int64_t

cdef extern from "<pthread.h>" nogil:
    ctypedef struct pthread_t:
        pass
    ctypedef struct pthread_attr_t:
        pass
    ctypedef struct pthread_mutex_t:
        pass
    ctypedef struct pthread_mutexattr_t:
        pass
    ctypedef struct pthread_cond_t:
        pass
    ctypedef struct pthread_condattr_t:
        pass
    ctypedef struct pthread_once_t:
        pass
    pthread_mutex_t PTHREAD_MUTEX_INITIALIZER
    pthread_once_t PTHREAD_ONCE_INIT
    int pthread_create(pthread_t *thread, const pthread_attr_t *attr,
                       void *(*start)(void *) noexcept nogil, void *arg)
    int pthread_join(pthread_t thread, void **retval)
    int pthread_mutex_init(pthread_mutex_t *m, const pthread_mutexattr_t *a)
    int pthread_mutex_lock(pthread_mutex_t *m)
    int pthread_mutex_unlock(pthread_mutex_t *m)
    int pthread_cond_init(pthread_cond_t *c, const pthread_condattr_t *a)
    int pthread_cond_wait(pthread_cond_t *c, pthread_mutex_t *m)
    int pthread_cond_broadcast(pthread_cond_t *c)
    int pthread_cond_destroy(pthread_cond_t *c)
    int pthread_mutex_destroy(pthread_mutex_t *m)
    int pthread_once(pthread_once_t *once, void (*init)() noexcept nogil)
    ctypedef struct pthread_key_t:
        pass
    int pthread_key_create(pthread_key_t *key, void (*destructor)(void *) noexcept nogil)
    int pthread_setspecific(pthread_key_t key, const void *value)

# Memory advice: transparent huge pages for the large arrays, and faulting pages in
# ahead of their writer (Linux 5.14; older kernels refuse it, a hint less).
cdef extern from *:
    """
    #include <sys/mman.h>
    #ifndef MADV_POPULATE_WRITE
    #define MADV_POPULATE_WRITE 23
    #endif
    """
    int madvise(void *addr, size_t length, int advice) nogil
    int MADV_HUGEPAGE
    int MADV_POPULATE_WRITE

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
