/*
 * panel.c -- one C panel for both systems: loads libSF_TCh.so (Linux: dlopen) or
 * SF_TCh.dll (Windows x64: LoadLibraryW; run under Wine by tools/build_windows.sh),
 * runs the same scenarios and prints one report. tests/test_windows.py builds it for
 * both and compares the two reports: a Windows panel must get what a Linux panel gets.
 *
 *     panel LIBRARY          (in a directory holding demo.nc and SF_TCh.ini)
 *
 * The scenarios: the version and the structure sizes; the interpolator manual's
 * example program through compile and simulation (absolute and relative); the demo
 * program simulated with every callback set; a regime-30 run of the offline machine
 * on the three cores at once while three threads poll GetPos; errors with non-ASCII file names and texts
 * (a missing file, a directory, a G-code error, a program in memory, a bad INI, the
 * file table, the log file in a non-ASCII directory); the correction tables by
 * non-ASCII names, directly and from an INI file, and the smoothing it sets.
 *
 *     panel LIBRARY --decimal-comma LOCALE
 *
 * instead sets the host's locale (every thread's) to LOCALE, whose decimal point is a
 * comma, and checks that the library reads and writes numbers as in the C locale: an
 * INI value, a long G-code number, an error text with numbers (one line of yes/no).
 *
 * Every text is UTF-8 in the report. On Windows the panel speaks UTF-16 to the
 * library wherever the header says TGM_LPCTSTR, converting its UTF-8 with
 * MultiByteToWideChar, and writes its files by wide names; its narrow texts
 * (TGM_LPCSTR) are UTF-8 by an INI file's [Texts] Narrow=utf8. Numbers are printed with
 * 9 significant digits: the two C runtimes' libm may differ in the last bits. Exit
 * status 0, or 2 when the library could not be loaded or a run did not end.
 */
#if defined(_WIN32)
#  define WIN32_LEAN_AND_MEAN
#  include <windows.h>
#  include <direct.h>
#else
#  define _GNU_SOURCE
#  include <dlfcn.h>
#  include <pthread.h>
#  include <sys/stat.h>
#  include <time.h>
#  include <unistd.h>
#endif
#include <locale.h>
#include <stdatomic.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tgm_cnc.h"

/* ------------------------------------------------------------------ the system */
#if defined(_WIN32)
/* UTF-8 -> the library's text type. The panel is short-lived: converted texts are kept. */
static TGM_LPCTSTR T(const char *utf8) {
    int n = MultiByteToWideChar(CP_UTF8, 0, utf8, -1, NULL, 0);
    wchar_t *wide = malloc((size_t)n * sizeof *wide);
    MultiByteToWideChar(CP_UTF8, 0, utf8, -1, wide, n);
    return wide;
}
/* the library's text type -> UTF-8 (kept, as above) */
static const char *U(TGM_LPCTSTR text) {
    int n = WideCharToMultiByte(CP_UTF8, 0, text, -1, NULL, 0, NULL, NULL);
    char *utf8 = malloc((size_t)n);
    WideCharToMultiByte(CP_UTF8, 0, text, -1, utf8, n, NULL, NULL);
    return utf8;
}
static FILE *open_file(const char *utf8, const char *mode) { return _wfopen(T(utf8), T(mode)); }
static void make_dir(const char *utf8) { _wmkdir(T(utf8)); }
static void sleep_ms(int ms) { Sleep((DWORD)ms); }
static double seconds_now(void) { return (double)GetTickCount64() / 1000.0; }
typedef HANDLE thread_t;
#  define THREAD_FN(name) static DWORD WINAPI name(LPVOID arg)
static void thread_start(thread_t *t, LPTHREAD_START_ROUTINE fn, void *arg) {
    *t = CreateThread(NULL, 0, fn, arg, 0, NULL);
}
static void thread_join(thread_t t) {
    WaitForSingleObject(t, INFINITE);
    CloseHandle(t);
}
static void *load_library(const char *path) { return (void *)LoadLibraryW(T(path)); }
static void *library_symbol(void *lib, const char *name) {
    FARPROC f = GetProcAddress((HMODULE)lib, name);
    void *p;
    memcpy(&p, &f, sizeof p);
    return p;
}
#else
static TGM_LPCTSTR T(const char *utf8) { return utf8; }
static const char *U(TGM_LPCTSTR text) { return text; }
static FILE *open_file(const char *utf8, const char *mode) { return fopen(utf8, mode); }
static void make_dir(const char *utf8) { mkdir(utf8, 0755); }
static void sleep_ms(int ms) {
    struct timespec t = {ms / 1000, (ms % 1000) * 1000000L};
    nanosleep(&t, NULL);
}
static double seconds_now(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + (double)t.tv_nsec * 1e-9;
}
typedef pthread_t thread_t;
#  define THREAD_FN(name) static void *name(void *arg)
static void thread_start(thread_t *t, void *(*fn)(void *), void *arg) { pthread_create(t, NULL, fn, arg); }
static void thread_join(thread_t t) { pthread_join(t, NULL); }
static void *load_library(const char *path) { return dlopen(path, RTLD_NOW | RTLD_LOCAL); }
static void *library_symbol(void *lib, const char *name) { return dlsym(lib, name); }
#endif

/* ------------------------------------------------------------------ the library */
#define TC_FUNCTIONS(X)                                                                      \
    X(ToolChainCore_Init) X(ToolChainCore_LoadFromIni) X(ToolChainCore_DestroyCNC)           \
    X(ToolChainCore_GetVersionString) X(ToolChainCore_GetStructuresSize)                     \
    X(ToolChainCore_GetGCodeParameters) X(ToolChainCore_SetGCodeParameters)                  \
    X(ToolChainCore_CompileFromFile) X(ToolChainCore_CompileFromMemory)                      \
    X(ToolChainCore_StatusCNC) X(ToolChainCore_IsBusy) X(ToolChainCore_GetLastError)         \
    X(ToolChainCore_GetLastCallError) X(ToolChainCore_FileToIdx) X(ToolChainCore_IdxToFile)  \
    X(ToolChainCore_GetGCodeSizeInfo) X(ToolChainCore_GetGCodeRunTime)                       \
    X(ToolChainCore_ResetCNC) X(ToolChainCore_StartCNCEx) X(ToolChainCore_GetPos)            \
    X(ToolChainCore_SetCallBack) X(ToolChainCore_SetTimeScale) X(ToolChainCore_SetLogValue)  \
    X(ToolChain_LogANSI) X(ToolChain_FlushLogFile) X(ToolChainCore_LoadToolTable)            \
    X(ToolChainCore_GetToolCorrection) X(ToolChainCore_LoadAxisCorrections)                  \
    X(ToolChainCore_CorrectPosition) X(ToolChainCore_GetSmoothing) X(ToolChainCore_SmoothSamples)

static struct {
#define X(name) __typeof__(&name) name;
    TC_FUNCTIONS(X)
#undef X
} tc;

/* The example program of the vendor's interpolator manual. */
static const char SEED_PROGRAM[] =
    "G00 X60.6051 Y40.7723\nG42\nM51\nG02 X0 Y-2.5202 I3.0336 J-1.2601\n"
    "G02 X0.922 Y-1.5646 I6.0604 J2.5173\nG02 X1.079 Y-1.0269 I4.2143 J3.3479\n"
    "G02 X2.2624 Y-1.3678 I9.8772 J13.7817\nG02 X1.9856 Y-0.8109 I6.1778 J12.2908\n"
    "G02 X3.015 Y-0.7892 I8.8515 J27.6632\nG02 X6.2889 Y0 I3.1444 J33.011\nM50\nG40\n"
    "G00 X-28.9085 Y30.4365\nG42\nM51\nG40\nM2\n";

static void write_bytes(const char *name, const void *bytes, size_t n) {
    FILE *f = open_file(name, "wb");
    if (f == NULL || fwrite(bytes, 1, n, f) != n) {
        fprintf(stderr, "panel: cannot write %s\n", name);
        exit(2);
    }
    fclose(f);
}

static void write_file(const char *name, const char *text) { write_bytes(name, text, strlen(text)); }

/* ------------------------------------------------------------------ recording callbacks */
/* What the callbacks of one core saw; the worker appends, the panel reads once the run
 * is over (under the lock: SetCallBack's removal is the barrier, the lock is for the
 * reader's sanitizers). */
enum { N_SLOTS = 24 };
static const uint32_t CALLBACK_NUMBERS[N_SLOTS] = {1, 2, 3, 4, 5, 6, 7, 10, 11, 12, 13, 14, 17, 18,
                                                   31, 32, 1001, 1002, 1003, 1004, 1005, 1006, 1007, 2001};
typedef struct {
    atomic_long calls[N_SLOTS];
    char texts[16384];          /* text callbacks, one a line, in order */
    atomic_flag busy;
    size_t n_parts, n_m;
    double cut, rapid;
    char parts[16384];          /* motion parts, one a line */
} Record;

static int slot_of(uint32_t number) {
    for (int k = 0; k < N_SLOTS; k++)
        if (CALLBACK_NUMBERS[k] == number)
            return k;
    return -1;
}

/* counts a call of callback `number`; `line` (may be NULL) goes to the texts */
static void note(Record *r, uint32_t number, const char *line) {
    atomic_fetch_add(&r->calls[slot_of(number)], 1);
    if (line == NULL)
        return;
    while (atomic_flag_test_and_set(&r->busy))
        ;
    size_t used = strlen(r->texts);
    snprintf(r->texts + used, sizeof r->texts - used, "  %u %s\n", number, line);
    atomic_flag_clear(&r->busy);
}

static int32_t on_output(intptr_t user, uint32_t tab, TGM_LPCTSTR text, CALLBACK_INFO *info) {
    char line[2048];
    snprintf(line, sizeof line, "tab %u: %s (error %d)", tab, U(text), info->stringId);
    note((Record *)user, 1, line);
    return 0;
}
static int32_t on_status_text(intptr_t user, uint32_t pane, TGM_LPCTSTR text, CALLBACK_INFO *info) {
    char line[2048];
    snprintf(line, sizeof line, "pane %u: %s (lines %d)", pane, U(text), info->nLines);
    note((Record *)user, 2, line);
    return 0;
}
static int32_t on_flag(intptr_t user) { note((Record *)user, 3, NULL); return 0; }
static int32_t on_verbose(intptr_t user) { note((Record *)user, 4, NULL); return 0; }
static TGM_LPCTSTR on_lib_path(intptr_t user) { note((Record *)user, 5, NULL); return T("."); }
static TGM_LPCTSTR on_tool_path(intptr_t user) { note((Record *)user, 6, NULL); return T("."); }
static TGM_LPCTSTR on_system_path(intptr_t user) { note((Record *)user, 7, NULL); return T("."); }
static int64_t on_time_stamp(intptr_t user, int32_t file) { (void)file; note((Record *)user, 10, NULL); return 0; }
static int32_t on_yield(intptr_t user, int32_t message_only) { (void)message_only; note((Record *)user, 11, NULL); return 0; }
static void on_ini_string(intptr_t user, TGM_LPCTSTR s, TGM_LPCTSTR k, TGM_LPCTSTR d, TGM_LPTSTR buf, uint32_t n) {
    (void)s; (void)k; (void)d; (void)buf; (void)n;
    note((Record *)user, 12, NULL);
}
static double on_ini_double(intptr_t user, TGM_LPCTSTR s, TGM_LPCTSTR k, double d) {
    (void)s; (void)k; note((Record *)user, 13, NULL); return d;
}
static int32_t on_ini_int(intptr_t user, TGM_LPCTSTR s, TGM_LPCTSTR k, int32_t d) {
    (void)s; (void)k; note((Record *)user, 14, NULL); return d;
}
static int32_t on_breakpoint(intptr_t user, uint32_t line, int32_t file) {
    (void)line; (void)file; note((Record *)user, 17, NULL); return 0;
}
static int32_t on_error(intptr_t user, uint32_t line, int32_t file, TGM_LPCTSTR text, CALLBACK_INFO *info) {
    char where[2048];
    (void)file;
    snprintf(where, sizeof where, "line %u: %s (error %d)", line, U(text), info->stringId);
    note((Record *)user, 18, where);
    return 0;
}
static int32_t on_message_box(intptr_t user, uint32_t tab, uint32_t buttons, TGM_LPCTSTR text, CALLBACK_INFO *info) {
    char line[2048];
    (void)buttons; (void)info;
    snprintf(line, sizeof line, "tab %u: %s", tab, U(text));
    note((Record *)user, 31, line);
    return 0;
}
static int32_t on_progress(intptr_t user, uint32_t percent) { (void)percent; note((Record *)user, 32, NULL); return 0; }
static int32_t on_driver_init(intptr_t user, double *params, uint32_t n, int32_t mode) {
    char line[64];
    (void)params;
    snprintf(line, sizeof line, "%u parameters, run mode %d", n, mode);
    note((Record *)user, 1001, line);
    return 0;
}
static int32_t on_g_function(intptr_t user, const SIMPLE_GM_PARAMS *p) {
    Record *r = (Record *)user;
    note(r, 1002, NULL);
    /* the simulation hands every part with its length in the N address */
    if (p->m_func != 0) r->cut += p->m_pars.N; else r->rapid += p->m_pars.N;
    size_t used = strlen(r->parts);
    snprintf(r->parts + used, sizeof r->parts - used,
             "  part %zu: G%d line %u end X %.9g Y %.9g Z %.9g compensated X %.9g Y %.9g length %.9g\n",
             r->n_parts++, p->m_func, p->m_editorLine, p->m_e.x, p->m_e.y, p->m_e.z, p->m_calcE.x,
             p->m_calcE.y, (double)p->m_pars.N);
    return 0;
}
static int32_t on_m_function(intptr_t user, const SIMPLE_GM_PARAMS *p) {
    Record *r = (Record *)user;
    char line[64];
    r->n_m++;
    snprintf(line, sizeof line, "M%d line %u", p->m_func % 10000, p->m_editorLine);
    note(r, 1003, line);
    return 0;
}
static int32_t on_connect_start(intptr_t user, uint32_t t, uint32_t n, const double *c, uint32_t axes) {
    (void)t; (void)n; (void)c; (void)axes; note((Record *)user, 1004, NULL); return 0;
}
static int32_t on_connect(intptr_t user, const SIMPLE_GM_PARAMS *p, double *d, P10DOUBLE *pt) {
    (void)p; (void)d; (void)pt; note((Record *)user, 1005, NULL); return 0;
}
static int32_t on_connect_end(intptr_t user, SIMPLE_GM_PARAMS *p, P10DOUBLE *pt) {
    (void)p; (void)pt; note((Record *)user, 1006, NULL); return 0;
}
static int32_t on_driver_end(intptr_t user) { note((Record *)user, 1007, NULL); return 0; }
static int32_t on_math_warning(intptr_t user, CALLBACK_INFO *info) {
    char line[2048];
    snprintf(line, sizeof line, "%s (error %d line %d)", info->m_fullError, info->stringId, info->actLine);
    note((Record *)user, 2001, line);
    return 0;
}

static void *const HANDLERS[N_SLOTS] = {
    (void *)on_output, (void *)on_status_text, (void *)on_flag, (void *)on_verbose, (void *)on_lib_path,
    (void *)on_tool_path, (void *)on_system_path, (void *)on_time_stamp, (void *)on_yield, (void *)on_ini_string,
    (void *)on_ini_double, (void *)on_ini_int, (void *)on_breakpoint, (void *)on_error,
    (void *)on_message_box, (void *)on_progress, (void *)on_driver_init, (void *)on_g_function,
    (void *)on_m_function, (void *)on_connect_start, (void *)on_connect, (void *)on_connect_end,
    (void *)on_driver_end, (void *)on_math_warning};

/* every callback (1..2001) on `core`, or none (r NULL) */
static void set_callbacks(uint32_t core, Record *r) {
    for (int k = 0; k < N_SLOTS; k++)
        tc.ToolChainCore_SetCallBack(core, CALLBACK_NUMBERS[k], (intptr_t)r, r ? HANDLERS[k] : NULL);
}

static void print_record(const Record *r, int with_parts) {
    static const char *NAMES[N_SLOTS] = {
        "AddOutputLog", "SetStatusBarText", "IsDebugMode", "IsVerboseMode", "GetLibPath", "GetToolPath",
        "GetSystemPath", "GetFileTimeStamp", "DoYield", "ReadIniString", "ReadIniDouble", "ReadIniInt",
        "IsBreakpoint", "DispAndLocateError", "AddOutputLogWithMsgBox", "SetStatusBarProgress",
        "DriverInitialize", "DriverGFunc", "DriverMFunc", "ConnectPointCalcStart", "ConnectPointCalc",
        "ConnectPointCalcEnd", "DriverEnd", "MathWarning"};
    for (int k = 0; k < N_SLOTS; k++)
        /* progress reports come as the work goes: how many depends on the machine */
        if (CALLBACK_NUMBERS[k] != 32)
            printf("callback %u %s: %ld\n", CALLBACK_NUMBERS[k], NAMES[k], atomic_load(&r->calls[k]));
    printf("callback 32 SetStatusBarProgress called: %s\n", atomic_load(&r->calls[slot_of(32)]) ? "yes" : "no");
    fputs(r->texts, stdout);
    printf("motion parts: %zu, cut %.9g mm, rapid %.9g mm\n", r->n_parts, r->cut, r->rapid);
    if (with_parts)
        fputs(r->parts, stdout);
}

/* ------------------------------------------------------------------ one core */
static int wait_idle(uint32_t core) {
    double t0 = seconds_now();
    while (tc.ToolChainCore_IsBusy(core) > 0) {
        if (seconds_now() - t0 > 300.0) {
            fprintf(stderr, "panel: core %u did not end\n", core);
            exit(2);
        }
        sleep_ms(1);
    }
    return 0;
}

static void print_error(uint32_t core, const char *what, int last_call) {
    CALLBACK_INFO info;
    memset(&info, 0, sizeof info);
    int32_t rc = last_call ? tc.ToolChainCore_GetLastCallError(core, &info) : tc.ToolChainCore_GetLastError(core, &info);
    if (rc != 1) {
        printf("%s: none\n", what);
        return;
    }
    printf("%s: %d line %d file %s: %s\n", what, info.stringId, info.actLine,
           U(tc.ToolChainCore_IdxToFile(core, info.fileIdx)), info.m_fullError);
    printf("%s arguments: %s\n", what, info.m_errorArguments);
}

static void print_boxes(uint32_t core) {
    GCODE_INFO info;
    if (tc.ToolChainCore_GetGCodeSizeInfo(core, &info) != 0)
        return;
    for (int k = 0; k < 2; k++) {
        const GCODE_SIZE *s = &info.m_size[k];
        printf("box %d: X %.9g..%.9g Y %.9g..%.9g Z %.9g..%.9g\n", k, s->m_minimalPos.x, s->m_maximalPos.x,
               s->m_minimalPos.y, s->m_maximalPos.y, s->m_minimalPos.z, s->m_maximalPos.z);
    }
}

/* Compiles `file` on core 0 with absMode (-1: the INI's) and radius (< 0: the INI's),
 * then simulates it with every callback recorded. */
static void compile_and_simulate(const char *title, const char *file, int abs_mode, double radius) {
    static Record record;
    GCODE_PARAMETERS params;
    GM_PARAMS_ENHANCED enh;
    memset(&record, 0, sizeof record);
    printf("== %s\n", title);
    tc.ToolChainCore_LoadFromIni(0, T("SF_TCh.ini"), NULL);
    tc.ToolChainCore_GetGCodeParameters(0, &params);
    if (abs_mode >= 0)
        params.absMode = abs_mode;
    for (int k = 0; radius >= 0 && k < 8; k++)
        params.correction[k].size = radius;
    params.calcTime = 1;
    tc.ToolChainCore_SetGCodeParameters(0, &params);
    set_callbacks(0, &record);
    int32_t rc = tc.ToolChainCore_CompileFromFile(0, T(file));
    printf("compile: %d\n", rc);
    wait_idle(0);
    printf("status: %d\n", tc.ToolChainCore_StatusCNC(0));
    print_error(0, "error", 0);
    if (tc.ToolChainCore_StatusCNC(0) == CNC_STATUS_COMPILED && tc.ToolChainCore_GetLastError(0, &(CALLBACK_INFO){0}) == 0) {
        print_boxes(0);
        tc.ToolChainCore_ResetCNC(0, RESET_MARK_START_ONLY, 0, NULL);
        printf("simulation: %d\n", tc.ToolChainCore_StartCNCEx(0, RUN_SIMULATION, NULL));
        wait_idle(0);
        printf("status: %d\n", tc.ToolChainCore_StatusCNC(0));
        print_error(0, "simulation error", 0);
        tc.ToolChainCore_GetPos(0, 0, NULL, &enh);
        printf("run time: %.9g s, of the file: %.9g s\n", enh.m_cncRunTime,
               tc.ToolChainCore_GetGCodeRunTime(0, tc.ToolChainCore_FileToIdx(0, T(file))));
    }
    set_callbacks(0, NULL);
    print_record(&record, 1);
    tc.ToolChainCore_DestroyCNC(0);
}

/* ------------------------------------------------------------------ regime 30 on three cores */
typedef struct {
    uint32_t core;
    Record record;
    int32_t start_rc, status;
    GM_PARAMS_ENHANCED enh;
    SIMPLE_GM_PARAMS pos;
} MachineJob;

typedef struct {
    atomic_int *stop;
    long polls, regressions, failures;
} Poller;

THREAD_FN(poll_cores) {
    Poller *p = arg;
    double last[TOOL_CHAIN_MAX_CORES] = {0};
    SIMPLE_GM_PARAMS pos;
    GM_PARAMS_ENHANCED enh;
    while (!atomic_load(p->stop)) {
        for (uint32_t core = 0; core < TOOL_CHAIN_MAX_CORES; core++) {
            if (tc.ToolChainCore_GetPos(core, 0, &pos, &enh) != 0 || enh.m_statusCNC == CNC_STATUS_INVALID) {
                p->failures++;
                continue;
            }
            /* a forward run only adds path: what GetPos shows never goes back */
            if (enh.m_actPartsLen + 1e-9 < last[core])
                p->regressions++;
            last[core] = enh.m_actPartsLen;
            p->polls++;
        }
    }
    return 0;
}

THREAD_FN(run_machine) {
    MachineJob *job = arg;
    uint32_t core = job->core;
    GCODE_PARAMETERS params;
    tc.ToolChainCore_LoadFromIni(core, T("SF_TCh.ini"), NULL);
    tc.ToolChainCore_GetGCodeParameters(core, &params);
    for (int k = 0; k < 8; k++)
        params.correction[k].size = 1.0;
    tc.ToolChainCore_SetGCodeParameters(core, &params);
    tc.ToolChainCore_SetTimeScale(core, 50.0);
    tc.ToolChainCore_CompileFromFile(core, T("demo.nc"));
    wait_idle(core);
    set_callbacks(core, &job->record);
    tc.ToolChainCore_ResetCNC(core, RESET_MARK_START_ONLY, 0, NULL);
    job->start_rc = tc.ToolChainCore_StartCNCEx(core, RUN_FORWARD, NULL);
    wait_idle(core);
    set_callbacks(core, NULL);
    job->status = tc.ToolChainCore_StatusCNC(core);
    tc.ToolChainCore_GetPos(core, 0, &job->pos, &job->enh);
    return 0;
}

static void machine_on_three_cores(void) {
    static MachineJob jobs[TOOL_CHAIN_MAX_CORES];
    Poller pollers[3];
    thread_t job_threads[TOOL_CHAIN_MAX_CORES], poll_threads[3];
    atomic_int stop = 0;
    printf("== regime 30 on three cores, three threads polling GetPos\n");
    for (int k = 0; k < 3; k++) {
        pollers[k] = (Poller){.stop = &stop};
        thread_start(&poll_threads[k], poll_cores, &pollers[k]);
    }
    for (uint32_t c = 0; c < TOOL_CHAIN_MAX_CORES; c++) {
        memset(&jobs[c], 0, sizeof jobs[c]);
        jobs[c].core = c;
        thread_start(&job_threads[c], run_machine, &jobs[c]);
    }
    for (uint32_t c = 0; c < TOOL_CHAIN_MAX_CORES; c++)
        thread_join(job_threads[c]);
    atomic_store(&stop, 1);
    long polls = 0, regressions = 0, failures = 0;
    for (int k = 0; k < 3; k++) {
        thread_join(poll_threads[k]);
        polls += pollers[k].polls;
        regressions += pollers[k].regressions;
        failures += pollers[k].failures;
    }
    fprintf(stderr, "panel: %ld polls of GetPos during the runs\n", polls);
    printf("polls failed: %ld, went back: %ld, any: %s\n", failures, regressions, polls > 0 ? "yes" : "no");
    for (uint32_t c = 0; c < TOOL_CHAIN_MAX_CORES; c++) {
        const MachineJob *j = &jobs[c];
        printf("core %u: start %d, status %d\n", c, j->start_rc, j->status);
        printf("core %u: work %d parts %.6f mm, rapid %d parts %.6f mm, all %.6f mm, M %d\n", c,
               j->enh.m_nWorkCounter, j->enh.m_actWorkPartsLen, j->enh.m_nG00Counter, j->enh.m_actG00PartsLen,
               j->enh.m_actPartsLen, j->enh.m_nMCounter);
        printf("core %u: at X %.6f Y %.6f Z %.6f, line %u\n", c, j->pos.m_calcS.x, j->pos.m_calcS.y,
               j->pos.m_calcS.z, j->enh.m_MasterEditorLine);
        print_record(&j->record, 0);
        tc.ToolChainCore_DestroyCNC(c);
    }
}

/* ------------------------------------------------------------------ errors and names */
static void errors_with_non_ascii_names(void) {
    static Record record;
    printf("== errors with non-ASCII names and texts\n");
    memset(&record, 0, sizeof record);
    tc.ToolChainCore_LoadFromIni(0, T("SF_TCh.ini"), NULL);
    set_callbacks(0, &record);

    printf("missing file: %d\n", tc.ToolChainCore_CompileFromFile(0, T("chybějící_soubor_ž.nc")));
    print_error(0, "call error", 1);

    make_dir("složka_č.nc");
    printf("directory: %d\n", tc.ToolChainCore_CompileFromFile(0, T("složka_č.nc")));
    print_error(0, "call error", 1);

    write_file("chyba_řádek_ü.nc", "G90\nG1 X10 Y5 F500 (žluťoučký kůň)\nG999 X5\nM2\n");
    printf("G-code error: %d\n", tc.ToolChainCore_CompileFromFile(0, T("chyba_řádek_ü.nc")));
    wait_idle(0);
    print_error(0, "error", 0);

    printf("in memory: %d\n", tc.ToolChainCore_CompileFromMemory(0, T("paměť_日本.nc"),
                                                                 "G1 X1 F100 (poznámka ě)\nG1 X\n"));
    wait_idle(0);
    print_error(0, "error", 0);

    write_file("nastavení_ř.ini", "[GCodeParameters]\ncorrection0=1,5\n");
    printf("INI: %d\n", tc.ToolChainCore_LoadFromIni(0, T("nastavení_ř.ini"), NULL));
    print_error(0, "call error", 1);

    /* the file table: every name back as it went in, the same pointer each time */
    const char *names[] = {"ünïcödé_名前.nc", "emoji_😀.nc", "plain.nc"};
    for (int k = 0; k < 3; k++) {
        int32_t idx = tc.ToolChainCore_FileToIdx(0, T(names[k]));
        TGM_LPCTSTR first = tc.ToolChainCore_IdxToFile(0, idx);
        TGM_LPCTSTR again = tc.ToolChainCore_IdxToFile(0, idx);
        printf("file %d: %s, same text: %s, same pointer: %s\n", idx, U(first),
               strcmp(U(first), names[k]) == 0 ? "yes" : "no", first == again ? "yes" : "no");
    }
    printf("special: %s %s %s %s\n", U(tc.ToolChainCore_IdxToFile(0, -1)), U(tc.ToolChainCore_IdxToFile(0, -2)),
           U(tc.ToolChainCore_IdxToFile(0, -3)), U(tc.ToolChainCore_IdxToFile(0, -4)));
    set_callbacks(0, NULL);
    print_record(&record, 0);
    tc.ToolChainCore_DestroyCNC(0);
}

/* ------------------------------------------------------------------ correction tables, smoothing */
/* The tables by non-ASCII names, given to the exports and named by an INI file in a
 * non-ASCII folder (relative to it); the smoothing the INI sets, over a step. */
static void tables_by_non_ascii_names(void) {
    double values[TC_TOOL_VALUES], position[10] = {5.0, 2.0, 1.0}, samples[10 * 400];
    double params[4];
    uint64_t settled = 0;
    /* ACHS3D: Z corrected over X, table 7; X from 0 to 10 mm in 2 points: 0 and 1 mm */
    unsigned char axis_table[128 + 12 + 8] = {'Z', 'X'};
    const float definition[2] = {0.0f, 10.0f}, corrections[2] = {0.0f, 1.0f};
    const uint32_t points = 2;
    axis_table[127] = 7;
    memcpy(axis_table + 128, definition, 8);
    memcpy(axis_table + 136, &points, 4);
    memcpy(axis_table + 140, corrections, 8);
    printf("== correction tables and smoothing by non-ASCII names\n");
    make_dir("korekce_ř");
    write_file("korekce_ř/nástroje_ž.kor", "Nástroje (komentář)\n$KOR\n01: R=2.5 X=1 Z=-3.25\n02: R=-1 4=0.5\n");
    write_bytes("korekce_ř/osa_é.kor", axis_table, sizeof axis_table);
    write_file("korekce_ř/stroj.ini", "[Corrections]\nToolTable=nástroje_ž.kor\nAxisTable1=osa_é.kor\n"
                                      "[Smoothing]\nIirP=1414213.562\nIirQ=2000000\nIirF=10000\nIirAxes=0x1\n");
    printf("INI: %d\n", tc.ToolChainCore_LoadFromIni(1, T("korekce_ř/stroj.ini"), NULL));
    print_error(1, "call error", 1);
    for (uint32_t entry = 1; entry <= 2; entry++) {
        tc.ToolChainCore_GetToolCorrection(1, entry, values);
        printf("D%u: %.9g %.9g %.9g %.9g %.9g\n", entry, values[0], values[1], values[2], values[3], values[4]);
    }
    tc.ToolChainCore_CorrectPosition(1, position, position);
    printf("corrected at X 5: Z %.9g\n", position[2]);
    tc.ToolChainCore_GetSmoothing(1, TC_SMOOTHING_IIR, params);
    printf("IIR registers: %.9g %.9g %.9g %.9g\n", params[0], params[1], params[2], params[3]);
    /* a step of 1 mm on X at the first sample: 400 samples of 100 us */
    memset(samples, 0, sizeof samples);
    for (int k = 1; k < 400; k++)
        samples[10 * k] = 1.0;
    printf("smooth: %d\n", tc.ToolChainCore_SmoothSamples(1, samples, 400, samples, &settled));
    printf("X after 1, 10, 100 ms: %.6f %.6f %.6f, settled from sample %llu\n", samples[10 * 10],
           samples[10 * 100], samples[10 * 399], (unsigned long long)settled);

    const char *tables[] = {"korekce_ř/osa_é.kor"};
    TGM_LPCTSTR names[1] = {T(tables[0])};
    printf("load axis table: %d\n", tc.ToolChainCore_LoadAxisCorrections(1, 1, names));
    printf("missing tool table: %d\n", tc.ToolChainCore_LoadToolTable(1, T("korekce_ř/chybí_ž.kor")));
    print_error(1, "call error", 1);
    write_file("korekce_ř/vadná_ü.kor", "$KOR\n01: R=1\n02: Q=3\n");
    printf("bad tool table: %d\n", tc.ToolChainCore_LoadToolTable(1, T("korekce_ř/vadná_ü.kor")));
    print_error(1, "call error", 1);
    names[0] = T("korekce_ř/nástroje_ž.kor");
    printf("a tool table as axis table: %d\n", tc.ToolChainCore_LoadAxisCorrections(1, 1, names));
    print_error(1, "call error", 1);
    tc.ToolChainCore_GetToolCorrection(1, 1, values);
    printf("D1 kept: %.9g\n", values[0]);
    tc.ToolChainCore_DestroyCNC(1);
}

/* The log file goes to Init's directory, a non-ASCII one here. */
static void log_in_non_ascii_directory(void) {
    char line[256] = "";
    printf("== log file in a non-ASCII directory\n");
    make_dir("záznamy_ž");
    DLL_INIT_STRUCT init = {T("záznamy_ž"), T("."), T("."), 2};
    printf("init: %d\n", tc.ToolChainCore_Init(&init));
    tc.ToolChainCore_SetLogValue(LOG_TO_FILE);
    tc.ToolChain_LogANSI("řádek žluťoučký");
    tc.ToolChain_FlushLogFile();
    tc.ToolChainCore_SetLogValue(0);
    FILE *f = open_file("záznamy_ž/SF_TCh.log", "rb");
    if (f != NULL) {
        if (fgets(line, sizeof line, f) == NULL)
            line[0] = 0;
        fclose(f);
    }
    printf("log file: %s, has the line: %s\n", f ? "yes" : "no", strstr(line, "řádek žluťoučký") ? "yes" : "no");
}

/* What the library makes of numbers in the locale the host has now: the INI's
 * correction0, the end of a G-code move with a number too long for the lexer's own
 * conversion, and the error text of the manual's example (numbers with decimals). */
typedef struct {
    double radius, end_x;
    char error[2048];
} NumberTexts;

static void numbers_now(NumberTexts *out) {
    GCODE_PARAMETERS params;
    GCODE_INFO info;
    CALLBACK_INFO error;
    memset(out, 0, sizeof *out);
    tc.ToolChainCore_GetGCodeParameters(0, &params);      /* a core keeps its parameters: 0 first */
    params.correction[0].size = 0.0;
    tc.ToolChainCore_SetGCodeParameters(0, &params);
    if (tc.ToolChainCore_LoadFromIni(0, T("čárka.ini"), NULL) == 0 && tc.ToolChainCore_GetGCodeParameters(0, &params) == 0)
        out->radius = params.correction[0].size;
    tc.ToolChainCore_CompileFromMemory(0, T("long.nc"), "G1 X1.2345678901234567890123 Y2 F100\nM2\n");
    wait_idle(0);
    if (tc.ToolChainCore_GetGCodeSizeInfo(0, &info) == 0)
        out->end_x = info.m_size[0].m_maximalPos.x;
    tc.ToolChainCore_CompileFromFile(0, T("příklad_manuálu.nc"));
    wait_idle(0);
    if (tc.ToolChainCore_GetLastError(0, &error) == 1)
        snprintf(out->error, sizeof out->error, "%s", error.m_fullError);
    tc.ToolChainCore_DestroyCNC(0);
}

static int decimal_comma_check(const char *locale_name) {
    NumberTexts c_locale, comma;
    write_file("čárka.ini", "[GCodeParameters]\nabsMode=1\ncorrection0=1.5\n");
    write_file("příklad_manuálu.nc", SEED_PROGRAM);
    numbers_now(&c_locale);
    if (setlocale(LC_ALL, locale_name) == NULL) {
        fprintf(stderr, "panel: no locale %s\n", locale_name);
        return 2;
    }
    char point[8];
    snprintf(point, sizeof point, "%s", localeconv()->decimal_point);
    numbers_now(&comma);
    setlocale(LC_ALL, "C");
    fprintf(stderr, "panel: end X %.17g (C locale) %.17g (%s)\n", c_locale.end_x, comma.end_x, locale_name);
    printf("decimal point: '%s', INI 1.5: %s, long number: %s, error text: %s (%s)\n", point,
           comma.radius == 1.5 && c_locale.radius == 1.5 ? "same" : "different",
           comma.end_x == c_locale.end_x && c_locale.end_x == 1.2345678901234567890123 ? "same" : "different",
           strcmp(comma.error, c_locale.error) == 0 && strstr(comma.error, "60.6051") ? "same" : "different",
           comma.error);
    return 0;
}

int main(int argc, char **argv) {
    if (argc != 2 && !(argc == 4 && strcmp(argv[2], "--decimal-comma") == 0)) {
        fprintf(stderr, "usage: panel LIBRARY [--decimal-comma LOCALE] (in a directory with demo.nc and SF_TCh.ini)\n");
        return 2;
    }
    void *lib = load_library(argv[1]);
    if (lib == NULL) {
        fprintf(stderr, "panel: cannot load %s\n", argv[1]);
        return 2;
    }
#define X(name)                                                             \
    if ((*(void **)&tc.name = library_symbol(lib, #name)) == NULL) {        \
        fprintf(stderr, "panel: the library does not export %s\n", #name); \
        return 2;                                                           \
    }
    TC_FUNCTIONS(X)
#undef X
    /* this panel reads the library's narrow texts (CALLBACK_INFO's) as UTF-8: on Windows
       it says so in an INI file (the default there is the ANSI code page); on Linux they
       are UTF-8 anyway and the key changes nothing */
    write_file("narrow_utf8.ini", "[Texts]\nNarrow=utf8\n");
    if (tc.ToolChainCore_LoadFromIni(0, T("narrow_utf8.ini"), NULL) != 0) {
        fprintf(stderr, "panel: [Texts] Narrow=utf8 refused\n");
        return 2;
    }
    if (argc == 4)
        return decimal_comma_check(argv[3]);

    const char *version = U(tc.ToolChainCore_GetVersionString(0));
    printf("== library\n");
    /* "SF_TCh 0.1.0 (... built <date>)": the build time differs between the builds */
    printf("version: %.*s\n", (int)strcspn(version, "("), version);
    printf("version text kept: %s\n", tc.ToolChainCore_GetVersionString(0) == tc.ToolChainCore_GetVersionString(0) ? "yes" : "no");
    printf("bad core version: \"%s\"\n", U(tc.ToolChainCore_GetVersionString(7)));
    uint32_t sizes[9] = {0};
    tc.ToolChainCore_GetStructuresSize(0, 9, sizes);
    printf("structure sizes:");
    for (int k = 0; k < 9; k++)
        printf(" %u", sizes[k]);
    printf("\n");

    log_in_non_ascii_directory();
    write_file("příklad_manuálu.nc", SEED_PROGRAM);
    compile_and_simulate("the manual's example, absolute (the INI's absMode)", "příklad_manuálu.nc", -1, -1.0);
    compile_and_simulate("the manual's example, relative (absMode 0)", "příklad_manuálu.nc", 0, -1.0);
    compile_and_simulate("demo, tool radius 1, every callback", "demo.nc", -1, 1.0);
    machine_on_three_cores();
    errors_with_non_ascii_names();
    tables_by_non_ascii_names();
    fflush(stdout);
    return 0;
}
