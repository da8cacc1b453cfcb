/* A deliberately wrong library for tests/test_conformance.py: linked against the real
 * libSF_TCh.so, so every export the suite looks up resolves to the real one, except
 * these few, which forward to the real ones (dlopen / dlsym) and alter one answer:
 *
 *   GetGCodeParameters   insertArcToleranceRMin's default 0.03 reads 0.05
 *   GetStructuresSize    the size of CALLBACK_INFO 8 bytes too large
 *   GetLastError         error 400 one line further down
 *   StopCNCEx            while running forward: returns at once and stops 30 ms later,
 *                        so the machine stands 3 mm further at 100 mm/s
 *   DestroyCNC           first waits for that late stop: it lands on the run it was
 *                        meant for, never on a later check's (every check begins
 *                        with DestroyCNC)
 *   GetVersionString     aborts with SHIM_CRASH set, hangs with SHIM_HANG set
 *
 * Built with -DREAL_LIBRARY="path of libSF_TCh.so". */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "tgm_cnc.h"

static void *real(const char *name)
{
    static void *lib;
    if (!lib)
        lib = dlopen(REAL_LIBRARY, RTLD_NOW | RTLD_LOCAL);
    void *fn = lib ? dlsym(lib, name) : NULL;
    if (!fn) {
        fprintf(stderr, "shim: %s not found in %s\n", name, REAL_LIBRARY);
        abort();
    }
    return fn;
}

int32_t ToolChainCore_GetGCodeParameters(uint32_t core, GCODE_PARAMETERS *p)
{
    int32_t (*fn)(uint32_t, GCODE_PARAMETERS *) = real("ToolChainCore_GetGCodeParameters");
    int32_t rc = fn(core, p);
    if (rc == 0 && p && p->insertArcToleranceRMin == 0.03)
        p->insertArcToleranceRMin = 0.05;
    return rc;
}

int32_t ToolChainCore_GetStructuresSize(uint32_t core, uint32_t n, uint32_t *items)
{
    int32_t (*fn)(uint32_t, uint32_t, uint32_t *) = real("ToolChainCore_GetStructuresSize");
    int32_t rc = fn(core, n, items);
    if (rc == 0 && items && n > 4)
        items[4] += 8;
    return rc;
}

int32_t ToolChainCore_GetLastError(uint32_t core, CALLBACK_INFO *info)
{
    int32_t (*fn)(uint32_t, CALLBACK_INFO *) = real("ToolChainCore_GetLastError");
    int32_t rc = fn(core, info);
    if (rc == 1 && info && info->stringId == 400)
        info->actLine += 1;
    return rc;
}

struct late_stop {
    uint32_t core;
    char *add;
};

/* The late stop still to land (at most one: a second StopCNCEx waits for the first). */
static pthread_mutex_t pending_lock = PTHREAD_MUTEX_INITIALIZER;
static pthread_t pending;
static int has_pending;

static void *stop_later(void *arg)
{
    struct late_stop *stop = arg;
    int32_t (*fn)(uint32_t, TGM_LPCSTR) = real("ToolChainCore_StopCNCEx");
    usleep(30000);
    fn(stop->core, stop->add);
    free(stop->add);
    free(stop);
    return NULL;
}

/* Waits until a late stop has landed; call with pending_lock held. */
static void join_pending(void)
{
    if (has_pending) {
        pthread_join(pending, NULL);
        has_pending = 0;
    }
}

/* Answers at once and stops 30 ms later (while moving; else as the real one). */
int32_t ToolChainCore_StopCNCEx(uint32_t core, TGM_LPCSTR addCode)
{
    int32_t (*fn)(uint32_t, TGM_LPCSTR) = real("ToolChainCore_StopCNCEx");
    int32_t (*status)(uint32_t) = real("ToolChainCore_StatusCNC");
    struct late_stop *stop;
    if (status(core) != 30)
        return fn(core, addCode);
    stop = malloc(sizeof *stop);
    if (stop == NULL)
        return fn(core, addCode);
    stop->core = core;
    stop->add = addCode ? strdup(addCode) : NULL;
    pthread_mutex_lock(&pending_lock);
    join_pending();
    if (pthread_create(&pending, NULL, stop_later, stop) != 0) {
        pthread_mutex_unlock(&pending_lock);
        free(stop->add);
        free(stop);
        return fn(core, addCode);
    }
    has_pending = 1;
    pthread_mutex_unlock(&pending_lock);
    return 0;
}

int32_t ToolChainCore_DestroyCNC(uint32_t core)
{
    int32_t (*fn)(uint32_t) = real("ToolChainCore_DestroyCNC");
    pthread_mutex_lock(&pending_lock);
    join_pending();
    pthread_mutex_unlock(&pending_lock);
    return fn(core);
}

TGM_LPCTSTR ToolChainCore_GetVersionString(uint32_t core)
{
    TGM_LPCTSTR (*fn)(uint32_t) = real("ToolChainCore_GetVersionString");
    if (getenv("SHIM_CRASH"))
        abort();
    while (getenv("SHIM_HANG"))
        pause();
    return fn(core);
}
