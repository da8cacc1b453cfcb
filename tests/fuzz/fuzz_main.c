/*
 * The libFuzzer target of the library (tests/test_fuzz.py builds and runs it; by hand:
 * docs/testing.md, "Fuzzing"). SF_TCH_FUZZ_TARGET chooses what one input is:
 *   tg          a program in TG's dialect, compiled (sf_tch_fuzz_compile, fuzz_entry.pyx)
 *   iso         a program in the ISO mode (GCODE_PARAMETERS.rezerva1 bit 0)
 *   tool_table  a TAB0.KOR file, ToolChainCore_LoadToolTable
 *   axis_table  an ACHS3D01.KOR file, ToolChainCore_LoadAxisCorrections
 *   ini         an INI file, ToolChainCore_LoadFromIni
 * Files are written into a directory of the process's own, a new file per input. A
 * compilation still running after WATCHDOG_SECONDS is cancelled as a host's ResetCNC
 * would (an endless loop emits parts up to the part limit otherwise); one that does not
 * end then is libFuzzer's timeout (-timeout), a defect.
 */
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <pthread.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "tgm_cnc.h"

int32_t sf_tch_fuzz_compile(const char *data, size_t size, int32_t iso);
void sf_tch_fuzz_cancel(void);

#define WATCHDOG_SECONDS 1.0
static uint64_t compiling;          /* the number of the compilation that runs, 0 none */

static void *watchdog(void *unused) {
    uint64_t seen = 0;
    struct timespec tick = {0, 100 * 1000 * 1000};
    double running = 0.0;
    (void)unused;
    for (;;) {
        uint64_t now = __atomic_load_n(&compiling, __ATOMIC_ACQUIRE);
        running = now != 0 && now == seen ? running + 0.1 : 0.0;
        seen = now;
        if (running >= WATCHDOG_SECONDS) {
            sf_tch_fuzz_cancel();
            running = -1e9;         /* once per compilation */
        }
        nanosleep(&tick, NULL);
    }
    return NULL;
}

enum { TG, ISO, TOOL_TABLE, AXIS_TABLE, INI };
static int target = -1;
static char path[512];

int LLVMFuzzerInitialize(int *argc, char ***argv) {
    static const char *names[] = {"tg", "iso", "tool_table", "axis_table", "ini"};
    static const char *files[] = {"fuzz.nc", "fuzz.ngc", "TAB0.KOR", "ACHS3D01.KOR", "fuzz.ini"};
    const char *chosen = getenv("SF_TCH_FUZZ_TARGET");
    char folder[] = "/tmp/sf_tch_fuzz_XXXXXX";
    (void)argc;
    (void)argv;
    for (int k = 0; chosen != NULL && k < 5; k++)
        if (strcmp(chosen, names[k]) == 0)
            target = k;
    if (target < 0) {
        fprintf(stderr, "SF_TCH_FUZZ_TARGET: one of tg, iso, tool_table, axis_table, ini\n");
        exit(2);
    }
    if (mkdtemp(folder) == NULL) {
        perror("mkdtemp");
        exit(2);
    }
    snprintf(path, sizeof path, "%s/%s", folder, files[target]);
    ToolChainCore_SetLogValue(0);          /* no log file, no console lines */
    if (target == TG || target == ISO) {
        pthread_t thread;
        if (pthread_create(&thread, NULL, watchdog, NULL) != 0) {
            perror("pthread_create");
            exit(2);
        }
        pthread_detach(thread);
    }
    return 0;
}

static void write_input(const uint8_t *data, size_t size) {
    FILE *f = fopen(path, "wb");
    if (f == NULL || fwrite(data, 1, size, f) != size || fclose(f) != 0) {
        perror(path);
        abort();
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    const char *names[1] = {path};
    switch (target) {
    case TG:
    case ISO: {
        static uint64_t number;
        __atomic_store_n(&compiling, ++number, __ATOMIC_RELEASE);
        sf_tch_fuzz_compile((const char *)data, size, target == ISO);
        __atomic_store_n(&compiling, 0, __ATOMIC_RELEASE);
        break;
    }
    case TOOL_TABLE:
        write_input(data, size);
        ToolChainCore_LoadToolTable(0, path);
        break;
    case AXIS_TABLE:
        write_input(data, size);
        ToolChainCore_LoadAxisCorrections(0, 1, names);
        break;
    case INI:
        write_input(data, size);
        ToolChainCore_LoadFromIni(0, path, NULL);
        break;
    }
    return 0;
}
