# GetLastError and GetLastCallError: the errors a core keeps for the host. Each kept
# error is a PublishedError, written once and then only read: a new error replaces
# the core's pointer under core.lock (a pointer swap), never the text a host may be
# reading on another thread. Every holder counts: the core (while it is the current
# error) and each thread that read it, until that thread reads the same kind of
# error of that core again or ends. The last release frees it, so a text a thread
# got stays valid while that thread holds it, whatever other threads do meanwhile.
from libc.stdlib cimport free
from libc.string cimport memset

cdef extern from *:
    """
    /* what each thread read last: [core][0 GetLastError, 1 GetLastCallError] */
    static __thread void *tc_held_errors[3][2];
    static pthread_key_t tc_held_key;
    static int tc_held_key_made = 0;
    /* a thread that ends after the library was unloaded must not run its release; a
       pinned module (Windows) is detached only at the process's end: nothing to do */
    __attribute__((destructor)) static void tc_held_key_drop(void) {
        if (tc_held_key_made && !TC_MODULE_PINNED_AT_DETACH())
            pthread_key_delete(tc_held_key);
    }
    """
    void *tc_held_errors[3][2]
    pthread_key_t tc_held_key
    int tc_held_key_made

# the error kept when there is no memory for a copy of the one to keep: never freed
cdef PublishedError g_out_of_memory_error
cdef pthread_once_t g_held_once


cdef void _make_held_key() noexcept nogil:
    """Once per process: the never-freed 'out of memory' error, and the key whose destructor
    releases the errors a thread read when it ends."""
    global tc_held_key_made
    err_out_of_memory(&g_out_of_memory_error.info, -1, 0)
    g_out_of_memory_error.refs = 1
    tc_held_key_made = pthread_key_create(&tc_held_key, _release_held) == 0


cdef void _release_held(void *unused) noexcept nogil:
    """At a thread's end: the errors it read are released."""
    cdef int core, kind
    for core in range(TOOL_CHAIN_MAX_CORES):
        for kind in range(2):
            published_error_release(<PublishedError *>tc_held_errors[core][kind])
            tc_held_errors[core][kind] = NULL


cdef PublishedError *published_error_new(const ErrorInfo *err) noexcept nogil:
    """A copy of `err` to publish (one reference); NULL for no error (number 0). The
    never-freed "out of memory" error for err NULL (the caller had no memory for it)
    and when there is no memory for the copy."""
    cdef PublishedError *e
    pthread_once(&g_held_once, _make_held_key)
    if err != NULL and err.number == 0:
        return NULL
    e = <PublishedError *>tc_malloc(sizeof(PublishedError)) if err != NULL else NULL
    if e == NULL:
        TC_REF_ADD(&g_out_of_memory_error.refs)
        return &g_out_of_memory_error
    e.refs = 1
    e.info = err[0]
    e.narrow_text = narrow_to_host(e.info.text)
    e.narrow_args = narrow_to_host(e.info.args)
    return e


cdef void published_error_release(PublishedError *e) noexcept nogil:
    """Drops a reference (e may be NULL); the last one frees it."""
    if e != NULL and TC_REF_SUB(&e.refs) == 0 and e != &g_out_of_memory_error:
        free(e.narrow_text)
        free(e.narrow_args)
        free(e)


cdef void core_keep_error(Core *core, bint of_calls, const ErrorInfo *err) noexcept nogil:
    """Publishes `err` as the core's GetLastError (of_calls False) or GetLastCallError
    error (number 0: none; NULL: out of memory)."""
    cdef PublishedError *e = published_error_new(err)
    pthread_mutex_lock(&core.lock)
    e = core_swap_error_locked(core, of_calls, e)
    pthread_mutex_unlock(&core.lock)
    published_error_release(e)


cdef PublishedError *core_swap_error_locked(Core *core, bint of_calls, PublishedError *e) noexcept nogil:
    """With core.lock held: `e` (a reference the core takes over) becomes the kept
    error; returns the one it replaces, for the caller to release after unlocking."""
    cdef PublishedError *old
    if of_calls:
        old = core.call_error
        core.call_error = e
    else:
        old = core.error
        core.error = e
    return old


cdef int32_t core_read_error_column(Core *core, bint of_calls, int32_t *column) noexcept nogil:
    """The column of the error GetLastError (of_calls False) / GetLastCallError gives:
    1 and *column filled, 0 when the core keeps no such error."""
    cdef PublishedError *e
    pthread_mutex_lock(&core.lock)
    e = core.call_error if of_calls else core.error
    if e != NULL:
        column[0] = e.info.column
    pthread_mutex_unlock(&core.lock)
    return 1 if e != NULL else 0


cdef int32_t core_read_error(Core *core, bint of_calls, CALLBACK_INFO *info) noexcept nogil:
    """GetLastError (of_calls False) / GetLastCallError: 1 and info filled, 0 when the
    core keeps no such error. The calling thread holds the error read (its texts stay
    valid) until it reads this kind of error of this core again."""
    cdef PublishedError *e
    cdef PublishedError *before
    pthread_once(&g_held_once, _make_held_key)
    pthread_mutex_lock(&core.lock)
    e = core.call_error if of_calls else core.error
    if e != NULL:
        TC_REF_ADD(&e.refs)
    pthread_mutex_unlock(&core.lock)
    if e == NULL:
        return 0
    before = <PublishedError *>tc_held_errors[core.index][1 if of_calls else 0]
    tc_held_errors[core.index][1 if of_calls else 0] = e
    if tc_held_key_made:
        pthread_setspecific(tc_held_key, <void *>1)     # the thread's end releases what it holds
    published_error_release(before)
    fill_callback_info(&e.info, info)
    if e.narrow_text != NULL:
        info.m_fullError = e.narrow_text
    if e.narrow_args != NULL:
        info.m_errorArguments = e.narrow_args
    return 1
