# What the library needs from the operating system, declared from platform.h (Linux
# and Windows x64): threads under their POSIX names, memory advice, a monotonic clock
# and sleeps, the local time, regular files opened without blocking, numbers in the C
# locale, and the host's texts at the export boundary (TGM_LPCTSTR: UTF-8 on Linux,
# UTF-16 on Windows).
from libc.stdint cimport int64_t, uint64_t
from libc.stdio cimport FILE
from libc.time cimport tm
from includes.tgm_cnc cimport TGM_LPCTSTR

cdef extern from "platform.h" nogil:
    # threads (a zero-initialised mutex, condition or once is valid on both systems)
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
    void tc_cond_wait_seconds(pthread_cond_t *c, pthread_mutex_t *m, double seconds)   # at most that long
    int pthread_cond_destroy(pthread_cond_t *c)
    int pthread_mutex_destroy(pthread_mutex_t *m)
    int pthread_once(pthread_once_t *once, void (*init)() noexcept nogil)
    # a key's destructor runs at the end of each thread that set a value (not NULL)
    ctypedef struct pthread_key_t:
        pass
    int pthread_key_create(pthread_key_t *key, void (*destructor)(void *) noexcept nogil)
    int pthread_key_delete(pthread_key_t key)
    int pthread_setspecific(pthread_key_t key, const void *value)

    # the one allocator: every allocation of the library (free() releases it); NULL when
    # memory is exhausted, or at the test-only fault tc_alloc_fail_nth arms (the nth
    # allocation from now fails once; returns what the previous setting had left to go)
    void *tc_malloc(size_t n)
    void *tc_calloc(size_t count, size_t n)
    void *tc_realloc(void *p, size_t n)         # NULL: p unchanged
    char *tc_strdup(const char *s)
    # the calling thread's stage, named by ERR_OUT_OF_MEMORY ("Out of memory (%s)")
    void tc_set_stage(const char *stage)
    const char *tc_stage()
    int64_t tc_alloc_fail_nth(int64_t n)

    # memory advice: faulting pages in ahead of their writer; only a hint (refused: a
    # hint less)
    int madvise(void *addr, size_t length, int advice)
    int MADV_POPULATE_WRITE

    # time
    double tc_monotonic_seconds()
    void tc_sleep_seconds(double seconds)
    void tc_local_time_now(tm *local, long *milliseconds)

    # regular files by UTF-8 name, never opened blocking
    ctypedef int tc_file                # a descriptor (Linux) or a HANDLE (Windows)
    enum:
        TC_FILE_OK
        TC_FILE_CANNOT_OPEN
        TC_FILE_NOT_REGULAR
        TC_FILE_UNREADABLE
    int tc_file_open_regular(const char *path, tc_file *file, uint64_t *size)
    int64_t tc_file_read(tc_file file, void *buf, size_t n)     # bytes read, 0 at the end, -1 error
    void tc_file_close(tc_file file)
    FILE *tc_fopen(const char *path, const char *mode)

    # numbers with a '.' decimal point whatever the process's or thread's locale
    double c_strtod "tc_c_strtod"(const char *s, char **end)
    int c_snprintf "tc_c_snprintf"(char *buf, size_t size, const char *fmt, ...)

    # the host's texts (TGM_LPCTSTR). In: its UTF-8, valid until free(owned[0]) (NULL
    # for NULL, or out of memory). Out for one call: valid until free(owned[0]), never
    # NULL. Out to keep: valid until the library is unloaded, never rewritten.
    const char *text_from_host "tc_text_from_host"(TGM_LPCTSTR text, char **owned)
    TGM_LPCTSTR text_to_host "tc_text_to_host"(const char *utf8, void **owned)
    TGM_LPCTSTR text_to_host_kept "tc_text_to_host_kept"(const char *utf8)
    # the host's narrow texts (TGM_LPCSTR): Windows' ANSI code page (or UTF-8 by the INI),
    # Linux's UTF-8. In: its UTF-8 (malloc'ed), NULL when the text is UTF-8 as it is.
    # Out: the host's (malloc'ed), NULL when the UTF-8 is it. set_narrow_utf8: the mode.
    char *narrow_from_host "tc_narrow_from_host"(const char *text)
    char *narrow_to_host "tc_narrow_to_host"(const char *utf8)
    void set_narrow_utf8 "tc_set_narrow_utf8"(int on)
