/*
 * linked.c -- a Windows panel that links SF_TCh.lib (the import library) instead of
 * LoadLibrary: the header declares the functions __declspec(dllimport) for it.
 * tools/build_windows.sh builds it with mingw-w64 and runs it under Wine.
 */
#include <stdio.h>
#include <wchar.h>

#include "tgm_cnc.h"

int main(void) {
    uint32_t sizes[9] = {0};
    TGM_LPCTSTR version = ToolChainCore_GetVersionString(0);
    ToolChainCore_GetStructuresSize(0, 9, sizes);
    printf("linked: version %s, structure sizes:", version != NULL && wcsncmp(version, L"SF_TCh ", 7) == 0 ? "yes" : "no");
    for (int k = 0; k < 9; k++)
        printf(" %u", sizes[k]);
    printf("\n");
    return 0;
}
