# The library's log: a bit mask of sources and outputs (LOG_* in tgm_cnc.h), a
# file SF_TCh.log in the log directory, and stderr for the console outputs.
# Callable from any thread: one mutex guards the file.
from libc.stdio cimport FILE, fclose, fputs, fflush, fprintf, stderr, snprintf
from libc.stdlib cimport getenv, free
from libc.string cimport strlen, strncpy
from libc.time cimport tm, strftime


cdef extern from *:
    """
    /* set while this thread runs the log hook: its own lines do not reach the hook again */
    static __thread int tc_in_log_hook;
    """
    int tc_in_log_hook

cdef pthread_mutex_t g_log_lock   # zero-initialised == PTHREAD_MUTEX_INITIALIZER (glibc, platform.h)
cdef FILE *g_log_file
cdef char g_log_dir[1024]         # empty: $SF_TCH_LOG_DIR or the current directory
cdef char g_log_path[1100]
# The host's hook (ToolChain_SetLogHook): its own mutex, so that a slow hook never holds
# the file's writers, and setting it waits for a call in flight.
cdef pthread_mutex_t g_hook_lock
cdef LogHook g_hook
cdef intptr_t g_hook_user


cdef void log_set_dir(const char *directory) noexcept nogil:
    """Directory of SF_TCh.log (from ToolChainCore_Init); reopens the file on next write."""
    global g_log_file
    pthread_mutex_lock(&g_log_lock)
    strncpy(g_log_dir, directory, sizeof(g_log_dir) - 1)
    g_log_dir[sizeof(g_log_dir) - 1] = 0
    if g_log_file != NULL:
        fclose(g_log_file)
        g_log_file = NULL
    pthread_mutex_unlock(&g_log_lock)


cdef const char *log_file_path() noexcept nogil:
    """Path of SF_TCh.log: in $SF_TCH_LOG_DIR, else in Init's directory, else in '.'."""
    cdef const char *d = getenv("SF_TCH_LOG_DIR")
    if d == NULL or d[0] == 0:
        d = g_log_dir
        if d[0] == 0:
            d = "."
    snprintf(g_log_path, sizeof(g_log_path), "%s/SF_TCh.log", d)
    return g_log_path


cdef void log_set_mask(uint32_t mask) noexcept nogil:
    """The mask of what is logged; without LOG_TO_FILE the file is closed."""
    global g_log_file, g_log_mask
    pthread_mutex_lock(&g_log_lock)
    g_log_mask = mask
    if not (mask & LOG_TO_FILE) and g_log_file != NULL:
        fclose(g_log_file)
        g_log_file = NULL
    pthread_mutex_unlock(&g_log_lock)


cdef void log_line(uint32_t source, const char *text) noexcept nogil:
    """Writes one line to the outputs of the mask when `source` is enabled
    (source 0: always, e.g. ToolChain_LogANSI)."""
    global g_log_file
    cdef char stamp[64]
    cdef tm local
    cdef long milliseconds
    if text == NULL:
        return
    pthread_mutex_lock(&g_log_lock)
    if source != 0 and not (g_log_mask & source):
        pthread_mutex_unlock(&g_log_lock)
        return
    tc_local_time_now(&local, &milliseconds)
    strftime(stamp, sizeof(stamp), "%Y-%m-%d %H:%M:%S", &local)
    if g_log_mask & LOG_TO_FILE:
        if g_log_file == NULL:
            g_log_file = tc_fopen(log_file_path(), "a")
        if g_log_file != NULL:
            fprintf(g_log_file, "%s.%03ld %s\n", stamp, milliseconds, text)
    if g_log_mask & (LOG_TO_CONSOLE | LOG_TO_TGM):
        fprintf(stderr, "SF_TCh %s %s\n", stamp, text)
    pthread_mutex_unlock(&g_log_lock)
    log_to_hook(source, text)


cdef void log_to_hook(uint32_t source, const char *text) noexcept nogil:
    """A log line to the host's hook (if set) in its narrow text; a line the hook itself logs
    does not reach it again."""
    global tc_in_log_hook
    cdef char *narrow
    if tc_in_log_hook:
        return
    pthread_mutex_lock(&g_hook_lock)
    if g_hook != NULL:
        tc_in_log_hook = 1
        narrow = narrow_to_host(text)      # the host's narrow text (Windows: ANSI code page)
        if narrow != NULL:
            g_hook(g_hook_user, source, narrow)
        else:
            g_hook(g_hook_user, source, text)
        free(narrow)
        tc_in_log_hook = 0
    pthread_mutex_unlock(&g_hook_lock)


cdef int32_t log_set_hook(intptr_t user, void *fn) noexcept nogil:
    """ToolChain_SetLogHook: -1 from inside the hook (its thread holds g_hook_lock)."""
    global g_hook, g_hook_user
    if tc_in_log_hook:
        return -1
    pthread_mutex_lock(&g_hook_lock)
    g_hook = <LogHook>fn
    g_hook_user = user
    pthread_mutex_unlock(&g_hook_lock)
    return 0


cdef void log_flush() noexcept nogil:
    """Writes out what the log file holds."""
    pthread_mutex_lock(&g_log_lock)
    if g_log_file != NULL:
        fflush(g_log_file)
    pthread_mutex_unlock(&g_log_lock)
