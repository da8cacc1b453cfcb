/*
 * c_hmi -- a minimal operator panel in C: libSF_TCh.so without Python.
 *
 *     cc -O2 -I include examples/c_hmi/c_hmi.c -o c_hmi -ldl -lpthread
 *     ./c_hmi path/to/libSF_TCh.so SF_TCh.ini demo.nc [options]
 *
 * Loads the library with dlopen (no link-time dependency, no libpython), then does
 * what a panel does: Init, and on each core LoadFromIni, G-code parameters, the
 * compilation in the library's thread while polling the core until it is done, a
 * simulation (regime 10) whose parts come through the driver callbacks DriverGFunc /
 * DriverMFunc (PRINT texts through the output log), a summary and DestroyCNC.
 * Options:
 *
 *   --cores N       run the job on cores 0..N-1 at once, one host thread each
 *                   (default 1)
 *   --radius R      tool radius of G41..G48 in mm (default: as the INI sets it)
 *   --abs-mode M    GCODE_PARAMETERS.absMode (default: as the INI sets it)
 *   --pollers N     N more threads call StatusCNC + GetPos of every core in a loop
 *                   meanwhile, as a panel's timers do (default 0)
 *   --parts         also print every motion part
 *   --host-locale   take the locale from the environment (setlocale(LC_ALL, ""), as
 *                   GUI toolkits do); the report is still printed in the C locale
 *
 * Exit status: 0 done, 1 the library reported an error (printed as file:line: error
 * N: text on stderr), 2 bad arguments or the library could not be loaded or used.
 * The report compares byte for byte with the same run done through Python's ctypes
 * (tests/test_hosts.py).
 */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <locale.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "tgm_cnc.h"

/* The library's functions, typed by the header's own prototypes (__typeof__ of
 * GCC and Clang), so the example cannot drift from the ABI. */
#define TC_FUNCTIONS(X)                                                            \
    X(ToolChainCore_Init) X(ToolChainCore_LoadFromIni) X(ToolChainCore_DestroyCNC) \
    X(ToolChainCore_GetVersionString) X(ToolChainCore_GetGCodeParameters)         \
    X(ToolChainCore_SetGCodeParameters) X(ToolChainCore_CompileFromFile)          \
    X(ToolChainCore_StatusCNC) X(ToolChainCore_IsBusy) X(ToolChainCore_GetLastError) \
    X(ToolChainCore_IdxToFile) X(ToolChainCore_GetGCodeSizeInfo)                   \
    X(ToolChainCore_ResetCNC) X(ToolChainCore_StartCNCEx) X(ToolChainCore_GetPos)  \
    X(ToolChainCore_SetCallBack)

static struct {
#define X(name) __typeof__(&name) name;
    TC_FUNCTIONS(X)
#undef X
} tc;

/* Parts handed to the driver callbacks, in order (the core's worker thread appends,
 * the job's thread reads once the run is over). */
typedef struct {
    SIMPLE_GM_PARAMS *items;
    size_t count, capacity;
    int out_of_memory;
} PartList;

typedef struct {
    pthread_mutex_t lock;
    PartList motion, m_functions;
    char printed[4096];         /* PRINT / M29 texts (output log tab 2), one a line */
} RunLog;

static void append_part(RunLog *log, PartList *list, const SIMPLE_GM_PARAMS *part) {
    pthread_mutex_lock(&log->lock);
    if (list->count == list->capacity) {
        size_t capacity = list->capacity ? 2 * list->capacity : 64;
        SIMPLE_GM_PARAMS *grown = realloc(list->items, capacity * sizeof *grown);
        if (grown == NULL) {
            list->out_of_memory = 1;   /* reported once the run is over */
            pthread_mutex_unlock(&log->lock);
            return;
        }
        list->items = grown;
        list->capacity = capacity;
    }
    list->items[list->count++] = *part;
    pthread_mutex_unlock(&log->lock);
}

static int32_t on_g_function(intptr_t user, const SIMPLE_GM_PARAMS *part) {
    RunLog *log = (RunLog *)user;
    append_part(log, &log->motion, part);
    return 0;
}

static int32_t on_m_function(intptr_t user, const SIMPLE_GM_PARAMS *part) {
    RunLog *log = (RunLog *)user;
    append_part(log, &log->m_functions, part);
    return 0;
}

static int32_t on_output(intptr_t user, uint32_t tab, TGM_LPCTSTR text, CALLBACK_INFO *info) {
    RunLog *log = (RunLog *)user;
    (void)info;
    if ((tab & 0xFF) == OUTPUT_TAB_PRINT && text != NULL) {
        pthread_mutex_lock(&log->lock);
        size_t used = strlen(log->printed);
        snprintf(log->printed + used, sizeof log->printed - used, "%s\n", text);
        pthread_mutex_unlock(&log->lock);
    }
    return 0;
}

/* A panel's timer: StatusCNC and GetPos of every core as fast as it can until told
 * to stop. */
typedef struct {
    pthread_t thread;
    uint32_t n_cores;
    atomic_int *stop;
    long polls, failures;
} Poller;

static void *poll_cores(void *arg) {
    Poller *p = arg;
    SIMPLE_GM_PARAMS pos;
    GM_PARAMS_ENHANCED enh;
    while (!atomic_load(p->stop)) {
        for (uint32_t core = 0; core < p->n_cores; core++) {
            int32_t status = tc.ToolChainCore_StatusCNC(core);
            if (status == CNC_STATUS_INVALID || tc.ToolChainCore_GetPos(core, 0, &pos, &enh) != 0)
                p->failures++;
            p->polls++;
        }
    }
    return NULL;
}

static void sleep_ms(long ms) {
    struct timespec t = {ms / 1000, (ms % 1000) * 1000000L};
    nanosleep(&t, NULL);
}

/* Polls until the core is idle; 0, or -1 after timeout_s seconds. */
static int wait_idle(uint32_t core, double timeout_s) {
    struct timespec t0, t;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    while (tc.ToolChainCore_IsBusy(core) > 0) {
        clock_gettime(CLOCK_MONOTONIC, &t);
        if ((t.tv_sec - t0.tv_sec) + (t.tv_nsec - t0.tv_nsec) * 1e-9 > timeout_s)
            return -1;
        sleep_ms(1);
    }
    return 0;
}

/* The whole job on one core, run by a host thread of its own. */
typedef struct {
    pthread_t thread;
    uint32_t core;
    const char *ini, *program;
    double radius;              /* used when set_radius */
    int set_radius, abs_mode;   /* abs_mode < 0: as the INI sets it */
    /* results */
    int failed;                 /* 0 done, 1 the library reported an error, 2 other */
    char error[2048];           /* the message for stderr */
    uint32_t n_cores;
    int32_t status;
    RunLog run;
    GCODE_INFO info;
    GM_PARAMS_ENHANCED enh;
} Job;

/* Records the core's last error as file:line: error N: text; 1 if there was one. */
static int take_error(Job *job) {
    CALLBACK_INFO info;
    memset(&info, 0, sizeof info);
    if (tc.ToolChainCore_GetLastError(job->core, &info) != 1)
        return 0;
    snprintf(job->error, sizeof job->error, "%s:%d: error %d: %s\n",
             tc.ToolChainCore_IdxToFile(job->core, info.fileIdx), info.actLine, info.stringId,
             info.m_fullError ? info.m_fullError : "");
    return 1;
}

/* A call that did not return 0: the library's error (1), or the return code (2). */
static int refused(Job *job, const char *call, int32_t rc) {
    if (take_error(job))
        return 1;
    snprintf(job->error, sizeof job->error, "c_hmi: %s on core %u returned %d\n", call, job->core, rc);
    return 2;
}

static void *run_job(void *arg) {
    Job *job = arg;
    uint32_t core = job->core;
    int32_t rc = tc.ToolChainCore_LoadFromIni(core, job->ini, &job->n_cores);
    if (rc != TOOL_CHAIN_SUCCESS) {
        job->failed = refused(job, "LoadFromIni", rc);
        return NULL;
    }
    GCODE_PARAMETERS params;
    tc.ToolChainCore_GetGCodeParameters(core, &params);
    for (int k = 0; job->set_radius && k < 8; k++)
        params.correction[k].size = job->radius;
    if (job->abs_mode >= 0)
        params.absMode = job->abs_mode;
    if ((rc = tc.ToolChainCore_SetGCodeParameters(core, &params)) != TOOL_CHAIN_SUCCESS) {
        job->failed = refused(job, "SetGCodeParameters", rc);
        return NULL;
    }

    /* compile in the core's thread; this thread polls until it is done */
    if ((rc = tc.ToolChainCore_CompileFromFile(core, job->program)) != TOOL_CHAIN_SUCCESS) {
        job->failed = refused(job, "CompileFromFile", rc);
        return NULL;
    }
    if (wait_idle(core, 600.0) != 0) {
        snprintf(job->error, sizeof job->error, "c_hmi: the compilation did not end\n");
        job->failed = 2;
        return NULL;
    }
    if ((job->failed = take_error(job)))
        return NULL;

    /* simulate: every part goes through the driver callbacks, in order */
    RunLog *run = &job->run;
    tc.ToolChainCore_SetCallBack(core, CB_DRIVER_G_FUNC, (intptr_t)run, (void *)on_g_function);
    tc.ToolChainCore_SetCallBack(core, CB_DRIVER_M_FUNC, (intptr_t)run, (void *)on_m_function);
    tc.ToolChainCore_SetCallBack(core, CB_ADD_OUTPUT_LOG, (intptr_t)run, (void *)on_output);
    tc.ToolChainCore_ResetCNC(core, RESET_MARK_START_ONLY, 0, NULL);
    if ((rc = tc.ToolChainCore_StartCNCEx(core, RUN_SIMULATION, NULL)) != TOOL_CHAIN_SUCCESS) {
        job->failed = refused(job, "StartCNCEx", rc);
    } else if (wait_idle(core, 600.0) != 0) {
        snprintf(job->error, sizeof job->error, "c_hmi: the simulation did not end\n");
        job->failed = 2;
    } else {
        job->failed = take_error(job);
    }
    tc.ToolChainCore_SetCallBack(core, CB_DRIVER_G_FUNC, 0, NULL);
    tc.ToolChainCore_SetCallBack(core, CB_DRIVER_M_FUNC, 0, NULL);
    tc.ToolChainCore_SetCallBack(core, CB_ADD_OUTPUT_LOG, 0, NULL);
    if (!job->failed && (run->motion.out_of_memory || run->m_functions.out_of_memory)) {
        snprintf(job->error, sizeof job->error, "c_hmi: out of memory\n");
        job->failed = 2;
    }
    job->status = tc.ToolChainCore_StatusCNC(core);
    tc.ToolChainCore_GetGCodeSizeInfo(core, &job->info);
    tc.ToolChainCore_GetPos(core, 0, NULL, &job->enh);
    return NULL;
}

static void print_box(const char *title, const GCODE_SIZE *size) {
    printf("box %-13s X %.6f..%.6f  Y %.6f..%.6f  Z %.6f..%.6f\n", title,
           size->m_minimalPos.x, size->m_maximalPos.x, size->m_minimalPos.y,
           size->m_maximalPos.y, size->m_minimalPos.z, size->m_maximalPos.z);
}

static void print_summary(const Job *job, int list_parts) {
    const RunLog *run = &job->run;
    double cut = 0, rapid = 0;
    size_t n_cut = 0, n_rapid = 0;
    for (size_t k = 0; k < run->motion.count; k++) {
        const SIMPLE_GM_PARAMS *p = &run->motion.items[k];
        /* the simulation hands every part with its length in the N address */
        if (p->m_func != 0) { cut += p->m_pars.N; n_cut++; }
        else { rapid += p->m_pars.N; n_rapid++; }
        if (list_parts)
            printf("part %zu: G%d line %u end X %.9g Y %.9g Z %.9g compensated X %.9g Y %.9g length %.9g\n",
                   k, p->m_func, p->m_editorLine, p->m_e.x, p->m_e.y, p->m_e.z,
                   p->m_calcE.x, p->m_calcE.y, (double)p->m_pars.N);
    }
    printf("program:       %s\n", job->program);
    printf("status:        %d\n", job->status);
    printf("parts:         %zu motion, %zu M functions\n", run->motion.count, run->m_functions.count);
    printf("cut length:    %.6f mm in %zu parts\n", cut, n_cut);
    printf("rapid length:  %.6f mm in %zu parts\n", rapid, n_rapid);
    print_box("programmed:", &job->info.m_size[0]);
    print_box("compensated:", &job->info.m_size[1]);
    printf("run time:      %.6f s (estimate)\n", job->enh.m_cncRunTime);
    for (const char *line = run->printed; *line; ) {
        const char *end = strchr(line, '\n');
        printf("PRINT:         %.*s\n", (int)(end - line), line);
        line = end + 1;
    }
    printf("errors:        none\n");
}

static int usage(void) {
    fprintf(stderr, "usage: c_hmi LIBRARY INI PROGRAM [--cores N] [--radius R] [--abs-mode M]"
                    " [--pollers N] [--parts] [--host-locale]\n");
    return 2;
}

int main(int argc, char **argv) {
    Job template = {.abs_mode = -1};
    int n_jobs = 1, n_pollers = 0, list_parts = 0, host_locale = 0;
    if (argc < 4)
        return usage();
    for (int i = 4; i < argc; i++) {
        const char *next = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(argv[i], "--cores") && next) n_jobs = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--radius") && next) {
            template.radius = strtod(argv[++i], NULL);
            template.set_radius = 1;
        }
        else if (!strcmp(argv[i], "--abs-mode") && next) template.abs_mode = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--pollers") && next) n_pollers = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--parts")) list_parts = 1;
        else if (!strcmp(argv[i], "--host-locale")) host_locale = 1;
        else return usage();
    }
    if (n_jobs < 1 || n_jobs > TOOL_CHAIN_MAX_CORES || n_pollers < 0 || n_pollers > 64)
        return usage();
    template.ini = argv[2];
    template.program = argv[3];
    if (host_locale)   /* the library then runs in the host's locale, on every thread */
        setlocale(LC_ALL, "");

    void *lib = dlopen(argv[1], RTLD_NOW | RTLD_LOCAL);
    if (lib == NULL) {
        fprintf(stderr, "c_hmi: cannot load the library: %s\n", dlerror());
        return 2;
    }
#define X(name)                                                             \
    if ((*(void **)&tc.name = dlsym(lib, #name)) == NULL) {                 \
        fprintf(stderr, "c_hmi: the library does not export %s\n", #name); \
        return 2;                                                           \
    }
    TC_FUNCTIONS(X)
#undef X
    DLL_INIT_STRUCT init = {".", ".", ".", 2}; /* offline mode */
    if (tc.ToolChainCore_Init(&init) != TOOL_CHAIN_SUCCESS) {
        fprintf(stderr, "c_hmi: Init failed\n");
        return 2;
    }

    /* one host thread per core, and the pollers, all at once */
    atomic_int stop = 0;
    Job *jobs = calloc((size_t)n_jobs, sizeof *jobs);
    Poller *pollers = calloc((size_t)n_pollers + 1, sizeof *pollers);
    if (jobs == NULL || pollers == NULL) {
        fprintf(stderr, "c_hmi: out of memory\n");
        return 2;
    }
    for (int k = 0; k < n_pollers; k++) {
        pollers[k].n_cores = (uint32_t)n_jobs;
        pollers[k].stop = &stop;
        if (pthread_create(&pollers[k].thread, NULL, poll_cores, &pollers[k]) != 0) {
            fprintf(stderr, "c_hmi: cannot start a thread\n");
            return 2;
        }
    }
    for (int k = 0; k < n_jobs; k++) {
        jobs[k] = template;
        jobs[k].core = (uint32_t)k;
        pthread_mutex_init(&jobs[k].run.lock, NULL);
        if (pthread_create(&jobs[k].thread, NULL, run_job, &jobs[k]) != 0) {
            fprintf(stderr, "c_hmi: cannot start a thread\n");
            return 2;
        }
    }
    for (int k = 0; k < n_jobs; k++)
        pthread_join(jobs[k].thread, NULL);
    atomic_store(&stop, 1);
    long polls = 0, poll_failures = 0;
    for (int k = 0; k < n_pollers; k++) {
        pthread_join(pollers[k].thread, NULL);
        polls += pollers[k].polls;
        poll_failures += pollers[k].failures;
    }

    /* the report, in the C locale whatever the host's */
    locale_t c_locale = newlocale(LC_ALL_MASK, "C", (locale_t)0);
    locale_t host = uselocale(c_locale);
    int failed = 0;
    printf("library:       %s\n", tc.ToolChainCore_GetVersionString(0));
    printf("cores:         %u\n", jobs[0].n_cores);
    for (int k = 0; k < n_jobs; k++) {
        if (n_jobs > 1)
            printf("core %d\n", k);
        if (jobs[k].failed) {
            fputs(jobs[k].error, stderr);
            failed = jobs[k].failed > failed ? jobs[k].failed : failed;
        } else {
            print_summary(&jobs[k], list_parts);
        }
    }
    if (poll_failures) {
        fprintf(stderr, "c_hmi: %ld of %ld polls failed\n", poll_failures, polls);
        failed = 2;
    }
    if (n_pollers)
        fprintf(stderr, "c_hmi: %d threads polled StatusCNC + GetPos %ld times\n", n_pollers, polls);
    uselocale(host);
    freelocale(c_locale);

    for (int k = 0; k < n_jobs; k++) {
        tc.ToolChainCore_DestroyCNC(jobs[k].core);
        free(jobs[k].run.motion.items);
        free(jobs[k].run.m_functions.items);
        pthread_mutex_destroy(&jobs[k].run.lock);
    }
    free(jobs);
    free(pollers);
    dlclose(lib);
    return failed;
}
