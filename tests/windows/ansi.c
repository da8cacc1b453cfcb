/*
 * ansi.c -- the narrow texts (TGM_LPCSTR) of SF_TCh.dll as a Windows panel decodes them:
 * in the process's ANSI code page by default, UTF-8 after an INI file's [Texts]
 * Narrow=utf8. tools/build_windows.sh runs it under Wine in a Czech (1250) and a Western
 * (1252) code page:
 *
 *     ansi LIBRARY        (in a directory holding SF_TCh.ini)
 *
 * Prints (UTF-8, one fact a line) the code page, and for each mode: GetLastCallError's
 * m_fullError of a file name with Czech letters, its bytes beyond ASCII in hex, the text
 * decoded as the mode says; a line written by ToolChain_LogANSI in the code page as the
 * log hook hands it back and as the log file holds it (UTF-8); a G-code program with a
 * PRINT of Czech letters given in the code page, as AddOutputLog hands it (UTF-16).
 */
#define WIN32_LEAN_AND_MEAN
#include <windows.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tgm_cnc.h"

static HMODULE lib;

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

/* text in code page `from` as UTF-8 (kept: the program is short) */
static const char *to_utf8(const char *text, UINT from) {
    int n = MultiByteToWideChar(from, 0, text, -1, NULL, 0);
    wchar_t *wide = malloc((size_t)n * sizeof *wide);
    MultiByteToWideChar(from, 0, text, -1, wide, n);
    n = WideCharToMultiByte(CP_UTF8, 0, wide, -1, NULL, 0, NULL, NULL);
    char *utf8 = malloc((size_t)n);
    WideCharToMultiByte(CP_UTF8, 0, wide, -1, utf8, n, NULL, NULL);
    free(wide);
    return utf8;
}

/* UTF-8 in code page `to`, unmappable characters as '?', as the library does (kept) */
static const char *from_utf8(const char *utf8, UINT to) {
    int n = MultiByteToWideChar(CP_UTF8, 0, utf8, -1, NULL, 0);
    wchar_t *wide = malloc((size_t)n * sizeof *wide);
    MultiByteToWideChar(CP_UTF8, 0, utf8, -1, wide, n);
    DWORD flags = to == CP_UTF8 ? 0 : WC_NO_BEST_FIT_CHARS;
    const char *replacement = to == CP_UTF8 ? NULL : "?";
    n = WideCharToMultiByte(to, flags, wide, -1, NULL, 0, replacement, NULL);
    char *text = malloc((size_t)n);
    WideCharToMultiByte(to, flags, wide, -1, text, n, replacement, NULL);
    free(wide);
    return text;
}

static void high_bytes(const char *text, char *out) {
    out[0] = 0;
    for (const unsigned char *c = (const unsigned char *)text; *c; c++)
        if (*c >= 0x80)
            out += sprintf(out, "%02X ", *c);
}

static char hooked[512];

static void on_log(intptr_t user, uint32_t source, TGM_LPCSTR text) {
    (void)user;
    if (source == 0)
        snprintf(hooked, sizeof hooked, "%s", text);
}

static char printed[512];

static int32_t on_output(intptr_t user, uint32_t tab, TGM_LPCTSTR text, CALLBACK_INFO *info) {
    (void)user;
    (void)info;
    if (tab == 2)
        WideCharToMultiByte(CP_UTF8, 0, text, -1, printed, sizeof printed, NULL, NULL);
    return 0;
}

static void texts(const char *mode, UINT decode_as) {
    CALLBACK_INFO info;
    char hex[256], line[512] = "";
    printf("== %s\n", mode);
    F(ToolChainCore_CompileFromFile)(0, L"Zkou\u0161ka_chyb\u00ed_\u0159.nc");
    memset(&info, 0, sizeof info);
    F(ToolChainCore_GetLastCallError)(0, &info);
    high_bytes(info.m_fullError, hex);
    printf("error %d: %s\n", info.stringId, to_utf8(info.m_fullError, decode_as));
    printf("bytes beyond ASCII: %s\n", hex);
    printf("arguments: %s\n", to_utf8(info.m_errorArguments, decode_as));

    /* a log line written in the panel's narrow texts */
    const char *written = from_utf8("\u0159\u00e1dek \u017elu\u0165ou\u010dk\u00fd", decode_as);
    hooked[0] = 0;
    F(ToolChain_SetLogHook)(0, (void *)on_log);
    F(ToolChainCore_SetLogValue)(LOG_TO_FILE);
    F(ToolChain_LogANSI)(written);
    F(ToolChain_FlushLogFile)();
    F(ToolChainCore_SetLogValue)(0);
    F(ToolChain_SetLogHook)(0, NULL);
    printf("log hook: %s, the same bytes: %s\n", to_utf8(hooked, decode_as), strcmp(hooked, written) == 0 ? "yes" : "no");
    FILE *f = fopen("SF_TCh.log", "rb");
    while (f != NULL && fgets(line, sizeof line, f) != NULL)
        ;     /* the last line */
    if (f != NULL)
        fclose(f);
    line[strcspn(line, "\r\n")] = 0;
    printf("log file has it in UTF-8: %s\n", strstr(line, to_utf8(written, decode_as)) ? "yes" : "no");

    /* G-code in the panel's narrow texts: its PRINT comes back on AddOutputLog as UTF-16 */
    char code[256];
    snprintf(code, sizeof code, "PRINT %s\nG1 X1 F100\nM2\n", from_utf8("\u0161rouby \u010d. 5", decode_as));
    printed[0] = 0;
    F(ToolChainCore_SetCallBack)(0, 1, 0, (void *)on_output);
    F(ToolChainCore_CompileFromMemory)(0, L"tisk.nc", code);
    while (F(ToolChainCore_IsBusy)(0) > 0)
        Sleep(1);
    F(ToolChainCore_ResetCNC)(0, RESET_MARK_START_ONLY, 0, NULL);
    F(ToolChainCore_StartCNCEx)(0, RUN_SIMULATION, NULL);
    while (F(ToolChainCore_IsBusy)(0) > 0)
        Sleep(1);
    F(ToolChainCore_SetCallBack)(0, 1, 0, NULL);
    printf("PRINT: %s\n", printed);
}

int main(int argc, char **argv) {
    wchar_t path[MAX_PATH];
    if (argc != 2) {
        fprintf(stderr, "usage: ansi LIBRARY\n");
        return 2;
    }
    MultiByteToWideChar(CP_UTF8, 0, argv[1], -1, path, MAX_PATH);
    lib = LoadLibraryW(path);
    if (lib == NULL) {
        printf("cannot load the library\n");
        return 2;
    }
    printf("code page: %u\n", GetACP());
    DLL_INIT_STRUCT init = {L".", L".", L".", 2};
    F(ToolChainCore_Init)(&init);
    F(ToolChainCore_LoadFromIni)(0, L"SF_TCh.ini", NULL);
    texts("default: the ANSI code page", CP_ACP);
    FILE *ini = fopen("utf8.ini", "wb");
    fputs("[Texts]\nNarrow=utf8\n", ini);
    fclose(ini);
    printf("INI utf8: %d\n", F(ToolChainCore_LoadFromIni)(0, L"utf8.ini", NULL));
    texts("[Texts] Narrow=utf8", CP_UTF8);
    F(ToolChainCore_DestroyCNC)(0);
    fflush(stdout);
    return 0;
}
