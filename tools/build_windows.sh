#!/usr/bin/env bash
# Builds SF_TCh.dll for Windows x64 (mingw-w64 cross build: cmake/mingw-w64-x86_64.cmake)
# and runs the Wine tests: the C panel tests/windows/panel.c, cross-built too, loads the
# DLL under Wine and writes its report. tests/test_windows.py runs this script, runs
# the same panel on the Linux library and compares the reports.
#
#   tools/build_windows.sh [BUILD_DIR]      (default: build-windows)
#
# Writes BUILD_DIR/SF_TCh.dll, SF_TCh.lib (import library), SF_TCh.def (exports),
# panel.exe, and in BUILD_DIR/wine-run/ the panel's reports (UTF-8, LF line ends):
# report.txt, decimal-comma.txt of a run in a German locale, unload-*.txt of
# tests/windows/unload.c (FreeLibrary while the library works) and ansi-*.txt of
# tests/windows/ansi.c (the narrow texts in code pages 1250 and 1252). Needs Debian's
# gcc-mingw-w64-x86-64 and wine64 (apt-get install --no-install-recommends
# gcc-mingw-w64-x86-64 wine64); without them it says so and exits 77. $PYTHON (with
# Cython) runs Cython, default python3; $WINEPREFIX defaults to BUILD_DIR/wineprefix.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
BUILD="$(realpath -m "${1:-$ROOT/build-windows}")"
PYTHON="${PYTHON:-python3}"

MINGW_CC="$(command -v x86_64-w64-mingw32-gcc-win32 || command -v x86_64-w64-mingw32-gcc || true)"
WINE="$(command -v wine64 || true)"
[ -z "$WINE" ] && [ -x /usr/lib/wine/wine64 ] && WINE=/usr/lib/wine/wine64
if [ -z "$MINGW_CC" ] || [ -z "$WINE" ]; then
    echo "build_windows: needs mingw-w64 and Wine (apt-get install --no-install-recommends" \
         "gcc-mingw-w64-x86-64 wine64): not installed, nothing built" >&2
    exit 77
fi

GENERATOR=()
command -v ninja > /dev/null && GENERATOR=(-G Ninja)
cmake -S "$ROOT" -B "$BUILD" "${GENERATOR[@]}" -DCMAKE_BUILD_TYPE=Release \
      -DCMAKE_TOOLCHAIN_FILE="$ROOT/cmake/mingw-w64-x86_64.cmake" -DPython_EXECUTABLE="$(command -v "$PYTHON")" > /dev/null
cmake --build "$BUILD"
"$MINGW_CC" -std=gnu11 -O2 -Wall -Wextra -Werror -D__USE_MINGW_ANSI_STDIO=1 -I "$ROOT/include" \
    "$ROOT/tests/windows/panel.c" -o "$BUILD/panel.exe" -static-libgcc
for program in unload ansi; do
    "$MINGW_CC" -std=gnu11 -O2 -Wall -Wextra -Werror -I "$ROOT/include" \
        "$ROOT/tests/windows/$program.c" -o "$BUILD/$program.exe" -static-libgcc
done
# a panel linked against the import library (the header's dllimport declarations)
"$MINGW_CC" -std=gnu11 -O2 -Wall -Wextra -Werror -I "$ROOT/include" "$ROOT/tests/windows/linked.c" \
    -o "$BUILD/linked.exe" -static-libgcc "$BUILD/SF_TCh.lib"

# the panel runs in a fresh directory holding the DLL and the bundled INI and program
RUN="$BUILD/wine-run"
rm -rf "$RUN"
mkdir -p "$RUN"
cp "$BUILD/SF_TCh.dll" "$BUILD/panel.exe" "$BUILD/unload.exe" "$BUILD/ansi.exe" "$BUILD/linked.exe" "$ROOT/python/sf_tch/data/SF_TCh.ini" "$ROOT/python/sf_tch/data/demo.nc" "$RUN/"
# a preloaded library (a sanitizer runtime, say) is a Linux one: Wine would fail to start with it
unset LD_PRELOAD
export WINEPREFIX="${WINEPREFIX:-$BUILD/wineprefix}" WINEDEBUG=-all WINEDLLOVERRIDES="mscoree,mshtml="
mkdir -p "$WINEPREFIX"

WINESERVER="$(dirname "$WINE")/wineserver"
[ -x "$WINESERVER" ] || WINESERVER="$(command -v wineserver || true)"
# the prefix first (wineboot, some 10 s), so that no panel run includes its making; then
# one server for every run (persistent until the end), so that no run starts while the
# last one's server is shutting down
if [ ! -f "$WINEPREFIX/system.reg" ]; then
    "$WINE" wineboot -i < /dev/null > "$BUILD/wineboot.log" 2>&1 || {
        echo "build_windows: Wine could not make its prefix $WINEPREFIX:" >&2
        cat "$BUILD/wineboot.log" >&2
        exit 1
    }
    [ -n "$WINESERVER" ] && "$WINESERVER" -w
fi
[ -n "$WINESERVER" ] && "$WINESERVER" -p

# run_panel REPORT [--program EXE] ARGS...: the panel (or EXE) under Wine, its report with
# LF line ends; a failure names the run and shows how far its report got
run_panel() {
    local report="$1" program=panel.exe
    shift
    if [ "${1:-}" = --program ]; then
        program="$2"
        shift 2
    fi
    (cd "$RUN" && timeout 600 "$WINE" "$program" SF_TCh.dll "$@" < /dev/null > "$report.crlf" 2> "$report.stderr") || {
        status=$?
        echo "build_windows: $program $* failed under Wine (exit $status; the panels exit 2 on" \
             "their own errors); its stderr, then the last lines of its report $report:" >&2
        cat "$RUN/$report.stderr" >&2
        tail -n 20 "$RUN/$report.crlf" | tr -d '\r' >&2
        [ -n "$WINESERVER" ] && "$WINESERVER" -k
        exit 1
    }
    tr -d '\r' < "$RUN/$report.crlf" > "$RUN/$report"
    rm "$RUN/$report.crlf"
}
run_panel report.txt
# the same library in a host whose CRT locale writes a decimal comma, on every thread
run_panel decimal-comma.txt --decimal-comma German_Germany.1252
# a panel that unloads the library while it works, without DestroyCNC: during a run,
# a compilation, a wait for an M function's confirmation, and with nothing running
for scenario in run compile mfunc idle; do
    run_panel "unload-$scenario.txt" --program unload.exe "$scenario"
done
# the narrow texts in a Czech (1250) and a Western (1252) ANSI code page: Wine takes the
# code page from the Unix locale's name
LC_ALL=cs_CZ.UTF-8 run_panel ansi-1250.txt --program ansi.exe
LC_ALL=en_US.UTF-8 run_panel ansi-1252.txt --program ansi.exe
run_panel linked.txt --program linked.exe
# the persistent server ends with the last run
if [ -n "$WINESERVER" ]; then
    "$WINESERVER" -k
    "$WINESERVER" -w
fi
echo "build_windows: $BUILD/SF_TCh.dll; the panel's report under Wine: $RUN/report.txt ($(wc -l < "$RUN/report.txt") lines)"
