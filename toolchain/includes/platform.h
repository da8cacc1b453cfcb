/*
 * platform.h -- what the library needs from the operating system, for Linux and for
 * Windows x64 and x86 (mingw-w64), so that the stages stay free of #ifdefs. Declared for the
 * Cython sources in platform.pxd. Every function here is nogil C.
 *
 *   threads     the POSIX subset the library uses (create/join, mutexes, condition
 *               variables, once, thread-specific keys), under the POSIX names; on
 *               Windows implemented over CreateThread, SRW locks, condition variables,
 *               InitOnce and fiber-local storage, with no pthread library: a
 *               zero-initialised mutex, condition or once is valid on both systems,
 *               as the library's static ones rely on. On Windows the first thread or
 *               key pins the module (FreeLibrary while a worker runs is safe)
 *   memory      the one allocator (tc_malloc, tc_calloc, tc_realloc, tc_strdup) with
 *               its test-only fault; the madvise prefault hint, refused on Windows
 *   time        a monotonic clock in seconds, sleeps, the local wall-clock time
 *   files       regular files opened without blocking (a FIFO, a device, a console
 *               is refused before any read) by UTF-8 names; fopen by UTF-8 name
 *   numbers     strtod and snprintf with a '.' decimal point whatever the locale
 *   host texts  TGM_LPCTSTR of the export boundary: char (UTF-8) on Linux, the very
 *               pointer; wchar_t (UTF-16) on Windows, converted once on the way in
 *               to UTF-8 and on the way out into owned buffers. TGM_LPCSTR: UTF-8
 *               on Linux; on Windows the ANSI code page (or UTF-8 by the INI's choice)
 */
#ifndef TC_PLATFORM_H
#define TC_PLATFORM_H

#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* ------------------------------------------------------------------ memory */
/* Every allocation of the library goes through these four (free() releases what they
   return). They are the C library's, but for a test-only fault, SQLite-style: after
   tc_alloc_fail_nth(n), the nth allocation from then on (on any thread) fails once, as
   an exhausted memory would, so that a test can fail each allocation of an operation in
   turn (ToolChain_TestAllocFail in tgm_cnc.h). Off, the cost is one relaxed load. */
static int64_t tc_alloc_countdown;      /* > 0: allocations left until the one that fails */

/* Where the failure happens: a debugger's breakpoint (gdb: break tc_alloc_failed, then bt). */
__attribute__((noinline)) static int tc_alloc_failed(void) {
    __asm__ volatile("");
    return 1;
}

static inline int tc_alloc_fails(void) {
    int64_t left = __atomic_load_n(&tc_alloc_countdown, __ATOMIC_RELAXED);
    while (left > 0)
        if (__atomic_compare_exchange_n(&tc_alloc_countdown, &left, left - 1, 0,
                                        __ATOMIC_RELAXED, __ATOMIC_RELAXED))
            return left == 1 && tc_alloc_failed();
    return 0;
}

/* Arms the fault (n > 0: the nth allocation from now fails; 0: none) and returns how many
   allocations the previous setting still had to go: 0 once its failure happened. */
static inline int64_t tc_alloc_fail_nth(int64_t n) {
    return __atomic_exchange_n(&tc_alloc_countdown, n > 0 ? n : 0, __ATOMIC_SEQ_CST);
}

static inline void *tc_malloc(size_t n) {
    return tc_alloc_fails() ? NULL : malloc(n);
}

static inline void *tc_calloc(size_t count, size_t n) {
    return tc_alloc_fails() ? NULL : calloc(count, n);
}

/* NULL when refused, the block then unchanged */
static inline void *tc_realloc(void *p, size_t n) {
    return tc_alloc_fails() ? NULL : realloc(p, n);
}

static inline char *tc_strdup(const char *s) {
    size_t n = strlen(s) + 1;
    char *copy = (char *)tc_malloc(n);
    if (copy != NULL)
        memcpy(copy, s, n);
    return copy;
}

/* The stage the calling thread works in (a static text: "compiling", "the compensation",
   "the plan", ...), named by error 4 "Out of memory (%s)" when an allocation fails there. */
static __thread const char *tc_stage_name;

static inline void tc_set_stage(const char *stage) {
    tc_stage_name = stage;
}

static inline const char *tc_stage(void) {
    return tc_stage_name != NULL ? tc_stage_name : "a call of the library";
}

/* ================================================================== Windows */
#if defined(_WIN32)

#define WIN32_LEAN_AND_MEAN
#define NOMINMAX
#include <windows.h>
#include <errno.h>
#include <locale.h>

/* ------------------------------------------------------------------ threads */
typedef struct { HANDLE handle; } pthread_t;
typedef SRWLOCK pthread_mutex_t;
typedef CONDITION_VARIABLE pthread_cond_t;
typedef INIT_ONCE pthread_once_t;
typedef struct { int unused; } pthread_attr_t, pthread_mutexattr_t, pthread_condattr_t;
#define PTHREAD_MUTEX_INITIALIZER SRWLOCK_INIT
#define PTHREAD_ONCE_INIT INIT_ONCE_STATIC_INIT

/* A worker's stack: reserved, committed as it grows; as large as glibc's default. */
#define TC_THREAD_STACK_BYTES (8u << 20)

typedef struct {
    void *(*start)(void *);
    void *arg;
} tc_thread_start;

static DWORD WINAPI tc_thread_main(LPVOID param) {
    tc_thread_start run = *(tc_thread_start *)param;
    free(param);
    run.start(run.arg);
    return 0;
}

/* The library stays loaded once it has a thread of its own (a core's worker, the
   offline machine's pacer) or a thread-end callback (a key): a panel that calls
   FreeLibrary while the machine runs, without DestroyCNC first (MFC, Delphi and .NET
   panels do on exit), would otherwise unmap the code a worker runs. Pinned, FreeLibrary
   only drops the panel's reference; the module goes with the process, whose exit ends
   the threads before DLL_PROCESS_DETACH (which then waits for nothing: see
   TC_MODULE_PINNED_AT_DETACH). A LoadLibrary after it finds the same library, its cores
   as they were. */
static volatile LONG tc_module_pinned;

static void tc_pin_module(void) {
    HMODULE self;
    if (tc_module_pinned)
        return;
    if (GetModuleHandleExW(GET_MODULE_HANDLE_EX_FLAG_FROM_ADDRESS | GET_MODULE_HANDLE_EX_FLAG_PIN,
                           (LPCWSTR)(void *)&tc_module_pinned, &self))
        InterlockedExchange(&tc_module_pinned, 1);
}

/* At DLL_PROCESS_DETACH (the C runtime's destructors): a pinned module is only detached
   when the process ends, its other threads already gone; whatever they held (locks,
   thread-end callbacks) is left to the system, and nothing is waited for under the
   loader lock. */
#define TC_MODULE_PINNED_AT_DETACH() (tc_module_pinned != 0)

static int pthread_create(pthread_t *thread, const pthread_attr_t *attr, void *(*start)(void *), void *arg) {
    tc_thread_start *run = (tc_thread_start *)tc_malloc(sizeof *run);
    (void)attr;
    if (run == NULL)
        return ENOMEM;
    tc_pin_module();
    run->start = start;
    run->arg = arg;
    thread->handle = CreateThread(NULL, TC_THREAD_STACK_BYTES, tc_thread_main, run,
                                  STACK_SIZE_PARAM_IS_A_RESERVATION, NULL);
    if (thread->handle == NULL) {
        free(run);
        return EAGAIN;
    }
    return 0;
}

static int pthread_join(pthread_t thread, void **result) {
    if (result != NULL)
        *result = NULL;
    WaitForSingleObject(thread.handle, INFINITE);
    CloseHandle(thread.handle);
    return 0;
}

static inline int pthread_mutex_init(pthread_mutex_t *m, const pthread_mutexattr_t *a) {
    (void)a;
    InitializeSRWLock(m);
    return 0;
}
static inline int pthread_mutex_destroy(pthread_mutex_t *m) { (void)m; return 0; }
static inline int pthread_mutex_lock(pthread_mutex_t *m) { AcquireSRWLockExclusive(m); return 0; }
static inline int pthread_mutex_unlock(pthread_mutex_t *m) { ReleaseSRWLockExclusive(m); return 0; }

static inline int pthread_cond_init(pthread_cond_t *c, const pthread_condattr_t *a) {
    (void)a;
    InitializeConditionVariable(c);
    return 0;
}
static inline int pthread_cond_destroy(pthread_cond_t *c) { (void)c; return 0; }
static inline int pthread_cond_wait(pthread_cond_t *c, pthread_mutex_t *m) {
    SleepConditionVariableSRW(c, m, INFINITE, 0);
    return 0;
}
static inline int pthread_cond_broadcast(pthread_cond_t *c) { WakeAllConditionVariable(c); return 0; }

/* Waits on `c` at most `seconds` (a whole millisecond at least). */
static inline void tc_cond_wait_seconds(pthread_cond_t *c, pthread_mutex_t *m, double seconds) {
    double ms = seconds * 1000.0;
    SleepConditionVariableSRW(c, m, ms < 1.0 ? 1 : (DWORD)ms, 0);
}

static BOOL CALLBACK tc_once_main(PINIT_ONCE once, PVOID init, PVOID *context) {
    (void)once;
    (void)context;
    (*(void (**)(void))&init)();
    return TRUE;
}

static int pthread_once(pthread_once_t *once, void (*init)(void)) {
    void *param;
    memcpy(&param, &init, sizeof param);
    InitOnceExecuteOnce(once, tc_once_main, param, NULL);
    return 0;
}

/* Thread-specific keys over fiber-local storage, whose callback runs at a thread's end
   as a key's destructor does (for a value that is not NULL). The callback is WINAPI
   (stdcall on x86, where a cdecl destructor called in its place would leave the stack
   off by its argument): each key's destructor is called by a trampoline of its own. */
typedef DWORD pthread_key_t;

#define TC_MAX_KEYS 4
static void (*tc_key_destructors[TC_MAX_KEYS])(void *);
static volatile LONG tc_keys_made;
#define TC_KEY_TRAMPOLINE(k) \
    static VOID WINAPI tc_key_trampoline_##k(PVOID value) { tc_key_destructors[k](value); }
TC_KEY_TRAMPOLINE(0)
TC_KEY_TRAMPOLINE(1)
TC_KEY_TRAMPOLINE(2)
TC_KEY_TRAMPOLINE(3)
static const PFLS_CALLBACK_FUNCTION tc_key_trampolines[TC_MAX_KEYS] = {
    tc_key_trampoline_0, tc_key_trampoline_1, tc_key_trampoline_2, tc_key_trampoline_3};

static void tc_pin_module(void);

static int pthread_key_create(pthread_key_t *key, void (*destructor)(void *)) {
    LONG slot = InterlockedIncrement(&tc_keys_made) - 1;
    if (slot >= TC_MAX_KEYS)
        return EAGAIN;
    tc_key_destructors[slot] = destructor;
    /* the callback runs when any thread that set a value ends, loaded or not */
    tc_pin_module();
    *key = FlsAlloc(destructor != NULL ? tc_key_trampolines[slot] : NULL);
    return *key == FLS_OUT_OF_INDEXES ? EAGAIN : 0;
}
static inline int pthread_key_delete(pthread_key_t key) { return FlsFree(key) ? 0 : EINVAL; }
static inline int pthread_setspecific(pthread_key_t key, const void *value) {
    return FlsSetValue(key, (PVOID)value) ? 0 : EINVAL;
}

/* ------------------------------------------------------------------ memory advice */
/* Windows has no such hint for heap memory: MADV_POPULATE_WRITE is refused, so the
   library stops asking. */
#define MADV_POPULATE_WRITE 23
static inline int madvise(void *addr, size_t length, int advice) {
    (void)addr;
    (void)length;
    (void)advice;
    return -1;
}

/* ------------------------------------------------------------------ time */
static double tc_monotonic_seconds(void) {
    static LARGE_INTEGER frequency;     /* constant since boot: a racy first store is harmless */
    LARGE_INTEGER now;
    if (frequency.QuadPart == 0)
        QueryPerformanceFrequency(&frequency);
    QueryPerformanceCounter(&now);
    return (double)now.QuadPart / (double)frequency.QuadPart;
}

/* Sleeps at least `seconds` (the system timer's resolution: 1 to 15.6 ms). */
static void tc_sleep_seconds(double seconds) {
    double ms = seconds * 1000.0;
    Sleep(ms < 1.0 ? 1 : (DWORD)ms);
}

static void tc_local_time_now(struct tm *local, long *milliseconds) {
    SYSTEMTIME st;
    GetLocalTime(&st);
    memset(local, 0, sizeof *local);
    local->tm_year = st.wYear - 1900;
    local->tm_mon = st.wMonth - 1;
    local->tm_mday = st.wDay;
    local->tm_hour = st.wHour;
    local->tm_min = st.wMinute;
    local->tm_sec = st.wSecond;
    local->tm_wday = st.wDayOfWeek;
    local->tm_isdst = -1;
    *milliseconds = st.wMilliseconds;
}

/* ------------------------------------------------------------------ host texts */
typedef wchar_t tc_host_char;

/* The UTF-16 text of NUL-terminated UTF-8 (malloc'ed), NULL out of memory. Bytes that
   are not UTF-8 become U+FFFD. */
static wchar_t *tc_utf8_to_wide(const char *utf8) {
    int n = MultiByteToWideChar(CP_UTF8, 0, utf8, -1, NULL, 0);
    wchar_t *wide = n > 0 ? (wchar_t *)tc_malloc((size_t)n * sizeof(wchar_t)) : NULL;
    if (wide != NULL && MultiByteToWideChar(CP_UTF8, 0, utf8, -1, wide, n) != n) {
        free(wide);
        wide = NULL;
    }
    return wide;
}

/* The UTF-8 text of NUL-terminated UTF-16 (malloc'ed), NULL out of memory. An unpaired
   surrogate becomes U+FFFD. */
static char *tc_wide_to_utf8(const wchar_t *wide) {
    int n = WideCharToMultiByte(CP_UTF8, 0, wide, -1, NULL, 0, NULL, NULL);
    char *utf8 = n > 0 ? (char *)tc_malloc((size_t)n) : NULL;
    if (utf8 != NULL && WideCharToMultiByte(CP_UTF8, 0, wide, -1, utf8, n, NULL, NULL) != n) {
        free(utf8);
        utf8 = NULL;
    }
    return utf8;
}

/* A host text on the way in: its UTF-8, valid until free(*owned). NULL for NULL, and
   out of memory. */
static const char *tc_text_from_host(const tc_host_char *text, char **owned) {
    *owned = text != NULL ? tc_wide_to_utf8(text) : NULL;
    return *owned;
}

/* A text for the host during one call (a callback's argument): valid until
   free(*owned); out of memory an empty text, never NULL. */
static const tc_host_char *tc_text_to_host(const char *utf8, void **owned) {
    *owned = tc_utf8_to_wide(utf8 != NULL ? utf8 : "");
    return *owned != NULL ? (const wchar_t *)*owned : L"";
}

/* A text the host may keep until the library is unloaded (GetVersionString,
   IdxToFile): every distinct text is converted once and kept, never rewritten. */
typedef struct tc_kept_text {
    struct tc_kept_text *next;
    char *utf8;
    wchar_t *wide;
} tc_kept_text;

static SRWLOCK tc_kept_texts_lock = SRWLOCK_INIT;
static tc_kept_text *tc_kept_texts;

static const tc_host_char *tc_text_to_host_kept(const char *utf8) {
    tc_kept_text *t;
    const wchar_t *found = L"";
    AcquireSRWLockExclusive(&tc_kept_texts_lock);
    for (t = tc_kept_texts; t != NULL; t = t->next)
        if (strcmp(t->utf8, utf8) == 0)
            break;
    if (t == NULL && (t = (tc_kept_text *)tc_calloc(1, sizeof *t)) != NULL) {
        t->utf8 = tc_strdup(utf8);
        t->wide = tc_utf8_to_wide(utf8);
        if (t->utf8 == NULL || t->wide == NULL) {
            free(t->utf8);
            free(t->wide);
            free(t);
            t = NULL;
        } else {
            t->next = tc_kept_texts;
            tc_kept_texts = t;
        }
    }
    if (t != NULL)
        found = t->wide;
    ReleaseSRWLockExclusive(&tc_kept_texts_lock);
    return found;
}

/* ------------------------------------------------------------------ narrow texts */
/* TGM_LPCSTR (G-code text, add codes, ToolChain_LogANSI and the log hook's lines,
   CALLBACK_INFO's m_fullError / m_errorArguments) is the vendor's "ANSI": the process's
   ANSI code page (CP_ACP: 1250 on Czech Windows, 1252 on Western) by default, or UTF-8
   when an INI file says so ([Texts] Narrow=utf8; process-wide, the last LoadFromIni
   that names it decides) or the process's code page is UTF-8 already. Inside, the
   library works in UTF-8: a narrow text is converted on the way in and on the way out;
   an ASCII text, the same in every code page, is passed as it is. */
static volatile LONG tc_narrow_utf8;

static void tc_set_narrow_utf8(int on) { InterlockedExchange(&tc_narrow_utf8, on != 0); }

static int tc_narrow_needs_conversion(const char *text) {
    const unsigned char *c;
    if (text == NULL || tc_narrow_utf8 || GetACP() == CP_UTF8)
        return 0;
    for (c = (const unsigned char *)text; *c != 0; c++)
        if (*c >= 0x80)
            return 1;
    return 0;
}

/* A narrow text of the host as UTF-8 (malloc'ed), or NULL when the text is UTF-8
   already (ASCII, UTF-8 mode, NULL; out of memory too: the caller uses it as it is). */
static char *tc_narrow_from_host(const char *text) {
    wchar_t *wide;
    char *utf8;
    int n;
    if (!tc_narrow_needs_conversion(text))
        return NULL;
    n = MultiByteToWideChar(CP_ACP, 0, text, -1, NULL, 0);
    wide = n > 0 ? (wchar_t *)tc_malloc((size_t)n * sizeof(wchar_t)) : NULL;
    if (wide == NULL || MultiByteToWideChar(CP_ACP, 0, text, -1, wide, n) != n) {
        free(wide);
        return NULL;
    }
    utf8 = tc_wide_to_utf8(wide);
    free(wide);
    return utf8;
}

/* A UTF-8 text as the host's narrow text (malloc'ed), or NULL when the UTF-8 is it
   (ASCII, UTF-8 mode, NULL; out of memory too). A character the code page cannot hold
   becomes '?', visibly (no "best fit": 'ř' is not silently made 'r'). */
static char *tc_narrow_to_host(const char *utf8) {
    wchar_t *wide;
    char *ansi;
    int n;
    if (!tc_narrow_needs_conversion(utf8))
        return NULL;
    wide = tc_utf8_to_wide(utf8);
    if (wide == NULL)
        return NULL;
    n = WideCharToMultiByte(CP_ACP, WC_NO_BEST_FIT_CHARS, wide, -1, NULL, 0, "?", NULL);
    ansi = n > 0 ? (char *)tc_malloc((size_t)n) : NULL;
    if (ansi != NULL && WideCharToMultiByte(CP_ACP, WC_NO_BEST_FIT_CHARS, wide, -1, ansi, n, "?", NULL) != n) {
        free(ansi);
        ansi = NULL;
    }
    free(wide);
    return ansi;
}

/* ------------------------------------------------------------------ files */
typedef HANDLE tc_file;

enum { TC_FILE_OK = 0, TC_FILE_CANNOT_OPEN, TC_FILE_NOT_REGULAR, TC_FILE_UNREADABLE };

/* Opens the regular file `path` (UTF-8) for reading and tells its size now. Opening
   never blocks: a pipe without a server fails, a device or console opens and is then
   refused by its type before anything is read. A directory is "not regular", as on
   Linux. */
static int tc_file_open_regular(const char *path, tc_file *file, uint64_t *size) {
    BY_HANDLE_FILE_INFORMATION info;
    LARGE_INTEGER bytes;
    wchar_t *wide = tc_utf8_to_wide(path);
    HANDLE h;
    if (wide == NULL)
        return TC_FILE_CANNOT_OPEN;
    h = CreateFileW(wide, GENERIC_READ, FILE_SHARE_READ | FILE_SHARE_WRITE | FILE_SHARE_DELETE, NULL,
                    OPEN_EXISTING, FILE_FLAG_BACKUP_SEMANTICS, NULL);
    free(wide);
    if (h == INVALID_HANDLE_VALUE)
        return TC_FILE_CANNOT_OPEN;
    if (GetFileType(h) != FILE_TYPE_DISK) {
        CloseHandle(h);
        return TC_FILE_NOT_REGULAR;
    }
    if (!GetFileInformationByHandle(h, &info) || !GetFileSizeEx(h, &bytes)) {
        CloseHandle(h);
        return TC_FILE_UNREADABLE;
    }
    if (info.dwFileAttributes & (FILE_ATTRIBUTE_DIRECTORY | FILE_ATTRIBUTE_DEVICE)) {
        CloseHandle(h);
        return TC_FILE_NOT_REGULAR;
    }
    *file = h;
    *size = (uint64_t)bytes.QuadPart;
    return TC_FILE_OK;
}

/* Up to `n` bytes: the number read, 0 at the end, -1 on an error. */
static int64_t tc_file_read(tc_file file, void *buf, size_t n) {
    DWORD got = 0;
    if (n > 0x40000000u)
        n = 0x40000000u;
    if (!ReadFile(file, buf, (DWORD)n, &got, NULL))
        return -1;
    return (int64_t)got;
}

static void tc_file_close(tc_file file) { CloseHandle(file); }

static FILE *tc_fopen(const char *path, const char *mode) {
    wchar_t *wide_path = tc_utf8_to_wide(path);
    wchar_t *wide_mode = tc_utf8_to_wide(mode);
    FILE *f = wide_path != NULL && wide_mode != NULL ? _wfopen(wide_path, wide_mode) : NULL;
    free(wide_path);
    free(wide_mode);
    return f;
}

/* ------------------------------------------------------------------ numbers */
/* mingw-w64's strtod (David Gay's gdtoa: correctly rounded) and C99 vsnprintf read and
   write the decimal point of the calling thread's CRT locale. In the rare host that
   changed LC_NUMERIC, the calling thread switches to the C locale around the call (per
   thread: other threads never see it) and back. */
typedef struct {
    int switched;
    int previous_mode;          /* _configthreadlocale's before */
    char *previous;             /* this thread's LC_NUMERIC before */
} tc_c_numbers;

static void tc_c_numbers_enter(tc_c_numbers *g) {
    const char *point = localeconv()->decimal_point;
    g->switched = !(point[0] == '.' && point[1] == 0);
    if (!g->switched)
        return;
    g->previous_mode = _configthreadlocale(_ENABLE_PER_THREAD_LOCALE);
    g->previous = tc_strdup(setlocale(LC_NUMERIC, NULL));
    setlocale(LC_NUMERIC, "C");
}

static void tc_c_numbers_leave(tc_c_numbers *g) {
    if (!g->switched)
        return;
    if (g->previous != NULL)
        setlocale(LC_NUMERIC, g->previous);
    free(g->previous);
    _configthreadlocale(g->previous_mode);
}

static double tc_c_strtod(const char *s, char **end) {
    tc_c_numbers g;
    double value;
    tc_c_numbers_enter(&g);
    value = __mingw_strtod(s, end);
    tc_c_numbers_leave(&g);
    return value;
}

static int tc_c_snprintf(char *buf, size_t size, const char *fmt, ...) {
    tc_c_numbers g;
    va_list ap;
    int n;
    tc_c_numbers_enter(&g);
    va_start(ap, fmt);
    n = __mingw_vsnprintf(buf, size, fmt, ap);
    va_end(ap);
    tc_c_numbers_leave(&g);
    return n;
}

/* ================================================================== Linux */
#else

#include <errno.h>
#include <fcntl.h>
#include <locale.h>
#include <pthread.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#ifndef MADV_POPULATE_WRITE
#define MADV_POPULATE_WRITE 23    /* Linux 5.14; older kernels refuse it, a hint less */
#endif

/* ------------------------------------------------------------------ threads */
/* Waits on `c` at most `seconds` (CLOCK_REALTIME, the condition's clock). */
static inline void tc_cond_wait_seconds(pthread_cond_t *c, pthread_mutex_t *m, double seconds) {
    struct timespec until;
    long ns = (long)(seconds * 1e9);
    clock_gettime(CLOCK_REALTIME, &until);
    until.tv_sec += ns / 1000000000L;
    until.tv_nsec += ns % 1000000000L;
    until.tv_sec += until.tv_nsec / 1000000000L;
    until.tv_nsec %= 1000000000L;
    pthread_cond_timedwait(c, m, &until);
}

/* dlclose unloads the library (its destructors run; docs/hosts.md) */
#define TC_MODULE_PINNED_AT_DETACH() 0

/* ------------------------------------------------------------------ time */
static inline double tc_monotonic_seconds(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static inline void tc_sleep_seconds(double seconds) {
    struct timespec nap;
    nap.tv_sec = (time_t)seconds;
    nap.tv_nsec = (long)((seconds - (double)nap.tv_sec) * 1e9);
    nanosleep(&nap, NULL);
}

static inline void tc_local_time_now(struct tm *local, long *milliseconds) {
    struct timespec now;
    time_t seconds;
    clock_gettime(CLOCK_REALTIME, &now);
    seconds = now.tv_sec;
    localtime_r(&seconds, local);
    *milliseconds = now.tv_nsec / 1000000;
}

/* ------------------------------------------------------------------ host texts */
/* The host's texts are the library's: UTF-8 bytes, passed through as they are. */
typedef char tc_host_char;

static inline const char *tc_text_from_host(const tc_host_char *text, char **owned) {
    *owned = NULL;
    return text;
}

static inline const tc_host_char *tc_text_to_host(const char *utf8, void **owned) {
    *owned = NULL;
    return utf8;
}

static inline const tc_host_char *tc_text_to_host_kept(const char *utf8) { return utf8; }

/* Narrow texts (TGM_LPCSTR) are UTF-8 on Linux, as every text: nothing to convert
   ([Texts] Narrow of an INI file changes nothing here). */
static inline void tc_set_narrow_utf8(int on) { (void)on; }
static inline char *tc_narrow_from_host(const char *text) { (void)text; return NULL; }
static inline char *tc_narrow_to_host(const char *utf8) { (void)utf8; return NULL; }

/* ------------------------------------------------------------------ files */
typedef int tc_file;

enum { TC_FILE_OK = 0, TC_FILE_CANNOT_OPEN, TC_FILE_NOT_REGULAR, TC_FILE_UNREADABLE };

/* O_NONBLOCK: a FIFO without a writer, a device that waits for a carrier, cannot hang
   the open; the type then comes from the open descriptor (fstat), not from the name,
   so nothing can be swapped in between. */
static int tc_file_open_regular(const char *path, tc_file *file, uint64_t *size) {
    struct stat st;
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
    if (fd < 0)
        return TC_FILE_CANNOT_OPEN;
    if (fstat(fd, &st) != 0) {
        close(fd);
        return TC_FILE_UNREADABLE;
    }
    if (!S_ISREG(st.st_mode)) {
        close(fd);
        return TC_FILE_NOT_REGULAR;
    }
    *file = fd;
    *size = (uint64_t)st.st_size;
    return TC_FILE_OK;
}

static int64_t tc_file_read(tc_file file, void *buf, size_t n) {
    ssize_t got;
    do
        got = read(file, buf, n);
    while (got < 0 && errno == EINTR);
    return (int64_t)got;
}

static inline void tc_file_close(tc_file file) { close(file); }

static inline FILE *tc_fopen(const char *path, const char *mode) { return fopen(path, mode); }

/* ------------------------------------------------------------------ numbers */
/* One C locale object, created once, used by strtod_l and, per call and per thread,
   around vsnprintf (uselocale only changes the calling thread, so a host thread gets
   its own locale back at once). */
static locale_t tc_c_locale_obj = (locale_t)0;
static pthread_once_t tc_c_locale_once = PTHREAD_ONCE_INIT;

static void tc_c_locale_create(void) {
    tc_c_locale_obj = newlocale(LC_ALL_MASK, "C", (locale_t)0);
}

/* The C locale, or 0 when it could not be created (out of memory). */
static locale_t tc_c_locale(void) {
    pthread_once(&tc_c_locale_once, tc_c_locale_create);
    return tc_c_locale_obj;
}

static double tc_c_strtod(const char *s, char **end) {
    locale_t c = tc_c_locale();
    locale_t old;
    double value;
    if (c != (locale_t)0)
        return strtod_l(s, end, c);
    /* no locale object: the global one, which is "C" unless the host changed it */
    old = uselocale(LC_GLOBAL_LOCALE);
    value = strtod(s, end);
    uselocale(old);
    return value;
}

static int tc_c_snprintf(char *buf, size_t size, const char *fmt, ...) {
    locale_t c = tc_c_locale();
    locale_t old = (locale_t)0;
    va_list ap;
    int n;
    if (c != (locale_t)0)
        old = uselocale(c);
    va_start(ap, fmt);
    n = vsnprintf(buf, size, fmt, ap);
    va_end(ap);
    if (c != (locale_t)0)
        uselocale(old);
    return n;
}

#endif
#endif /* TC_PLATFORM_H */
