/*
 * unload.c -- a Windows panel that unloads SF_TCh.dll while the library works, as MFC,
 * Delphi and .NET panels do on exit (FreeLibrary, NativeLibrary.Free, an AppDomain's
 * unload) without DestroyCNC first. tools/build_windows.sh runs it under Wine:
 *
 *     unload LIBRARY run       FreeLibrary during a run of the offline machine (regime 30)
 *     unload LIBRARY compile   ... during the compilation of a long program
 *     unload LIBRARY mfunc     ... while the machine waits for an M function's confirmation
 *     unload LIBRARY idle      ... after calls that start no thread: the library goes
 *
 * (in a directory holding demo.nc and SF_TCh.ini). After FreeLibrary the panel waits,
 * looks whether the library's thread still works (its callbacks into the panel go on;
 * the process would die of a page fault had its code been unmapped), loads the library
 * again (the same module, the core as it was), and returns from main with the library's
 * thread still running: the process must end cleanly, exit status 0, and the last line
 * of the report is "exit". One fact a line.
 */
#define WIN32_LEAN_AND_MEAN
#include <windows.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tgm_cnc.h"

static HMODULE lib;
static volatile LONG g_parts, m_waiting;

static void *fn(const char *name) {
    FARPROC f = GetProcAddress(lib, name);
    void *p;
    memcpy(&p, &f, sizeof p);
    if (p == NULL) {
        printf("missing export %s\n", name);
        exit(2);
    }
    return p;
}
#define F(name) ((__typeof__(&name))fn(#name))

static int32_t on_part(intptr_t user, const SIMPLE_GM_PARAMS *part) {
    (void)user;
    (void)part;
    InterlockedIncrement(&g_parts);
    return 0;
}

/* the first M function waits for a confirmation that never comes */
static int32_t on_m_function(intptr_t user, const SIMPLE_GM_PARAMS *part) {
    (void)user;
    (void)part;
    InterlockedExchange(&m_waiting, 1);
    return TC_MFUNC_LATER;
}

static HMODULE load(const wchar_t *path) {
    HMODULE h = LoadLibraryW(path);
    if (h == NULL) {
        printf("cannot load the library\n");
        exit(2);
    }
    return h;
}

/* waits up to 10 s for `done` */
#define WAIT_FOR(done) for (int waited = 0; !(done) && waited < 10000; waited += 5) Sleep(5)

int main(int argc, char **argv) {
    wchar_t path[MAX_PATH];
    if (argc != 3) {
        fprintf(stderr, "usage: unload LIBRARY run|compile|mfunc|idle\n");
        return 2;
    }
    MultiByteToWideChar(CP_UTF8, 0, argv[1], -1, path, MAX_PATH);
    const char *scenario = argv[2];
    lib = load(path);
    printf("scenario: %s\n", scenario);

    if (strcmp(scenario, "idle") == 0) {
        printf("version: %s\n", F(ToolChainCore_GetVersionString)(0) != NULL ? "yes" : "no");
        printf("freed: %s\n", FreeLibrary(lib) ? "yes" : "no");
        printf("unloaded: %s\n", GetModuleHandleW(path) == NULL ? "yes" : "no");
        lib = load(path);
        printf("loaded again, version: %s\n", F(ToolChainCore_GetVersionString)(0) != NULL ? "yes" : "no");
        FreeLibrary(lib);
        printf("exit\n");
        fflush(stdout);
        return 0;
    }

    F(ToolChainCore_LoadFromIni)(0, L"SF_TCh.ini", NULL);
    int32_t status = 0;
    if (strcmp(scenario, "compile") == 0) {
        /* some 400,000 lines: seconds of compiling, of which the panel waits 50 ms */
        size_t n = 400000, used = 0;
        char *code = malloc(n * 32);
        for (size_t k = 0; k < n; k++)
            used += (size_t)sprintf(code + used, "G1 X%u Y%u F1000\n", (unsigned)(k % 97), (unsigned)(k % 89));
        F(ToolChainCore_CompileFromMemory)(0, L"long.nc", code);
        Sleep(50);
        status = F(ToolChainCore_StatusCNC)(0);
        printf("compiling: %s\n", status == 1 ? "yes" : "no");
    } else {
        F(ToolChainCore_CompileFromFile)(0, L"demo.nc");
        WAIT_FOR(F(ToolChainCore_IsBusy)(0) <= 0);
        F(ToolChainCore_SetCallBack)(0, 1002, 0, (void *)on_part);
        if (strcmp(scenario, "mfunc") == 0)
            F(ToolChainCore_SetCallBack)(0, 1003, 0, (void *)on_m_function);
        /* real time: the demo runs some 25 s, a part every half second, outlasting the panel */
        F(ToolChainCore_SetTimeScale)(0, 1.0);
        F(ToolChainCore_ResetCNC)(0, RESET_MARK_START_ONLY, 0, NULL);
        printf("start: %d\n", F(ToolChainCore_StartCNCEx)(0, RUN_FORWARD, NULL));
        if (strcmp(scenario, "mfunc") == 0) {
            WAIT_FOR(m_waiting);
            printf("waiting for an M function: %s\n", m_waiting ? "yes" : "no");
        } else {
            WAIT_FOR(g_parts > 1);
            printf("running: %s\n", F(ToolChainCore_StatusCNC)(0) == CNC_STATUS_FORWARD ? "yes" : "no");
        }
    }

    /* the panel ends its use of the library without DestroyCNC */
    LONG parts_before = g_parts;
    printf("freed: %s\n", FreeLibrary(lib) ? "yes" : "no");
    Sleep(1500);
    if (strcmp(scenario, "run") == 0)
        printf("the run goes on after FreeLibrary: %s\n", g_parts > parts_before ? "yes" : "no");
    HMODULE again = load(path);
    printf("loaded again: %s\n", again == lib ? "the same module" : "another module");
    lib = again;
    status = F(ToolChainCore_StatusCNC)(0);
    printf("the core still works: %s\n", status != 0 && status != CNC_STATUS_INVALID ? "yes" : "no");
    FreeLibrary(lib);
    /* and the process ends with the library's thread still at work */
    printf("exit\n");
    fflush(stdout);
    return 0;
}
