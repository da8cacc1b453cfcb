#!/usr/bin/env bash
# The 32-bit x86 builds of the same sources, for 32-bit panels (docs/hosts.md):
#
#   tools/build_x86.sh windows [BUILD_DIR]   SF_TCh.dll for Windows x86 (mingw-w64 i686,
#                                            cmake/mingw-w64-i686.cmake) and the C panel
#                                            tests/windows/panel.c as panel.exe; the panel
#                                            runs under Wine's 32-bit half where it is
#                                            installed (wine32), else that is said and
#                                            skipped: BUILD_DIR/windows-x86/
#   tools/build_x86.sh linux [BUILD_DIR]     libSF_TCh.so for Linux i686 (gcc -m32,
#                                            cmake/linux-i686.cmake) and the same panel,
#                                            run natively: the 32-bit code tested where
#                                            Windows x86 cannot run: BUILD_DIR/linux-i686/
#
# (default BUILD_DIR: build-x86). Each writes the panel's report (UTF-8, LF line ends) to
# run/report.txt of its folder; tests/test_x86.py compares it with the x86_64 Linux
# library's. Both use SSE2 floating point (-msse2 -mfpmath=sse), so the numbers are
# those of x86_64. Needs Debian's gcc-mingw-w64-i686 (windows) or gcc-multilib (linux);
# without them it says so and exits 77. $PYTHON (with Cython) runs Cython, default python3.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
TARGET="${1:-}"
BUILD="$(realpath -m "${2:-$ROOT/build-x86}")"
PYTHON="${PYTHON:-python3}"
GENERATOR=()
command -v ninja > /dev/null && GENERATOR=(-G Ninja)

# configure_and_build DIR TOOLCHAIN_FILE
configure_and_build() {
    cmake -S "$ROOT" -B "$1" "${GENERATOR[@]}" -DCMAKE_BUILD_TYPE=Release \
          -DCMAKE_TOOLCHAIN_FILE="$ROOT/cmake/$2" -DPython_EXECUTABLE="$(command -v "$PYTHON")" > /dev/null
    cmake --build "$1" > "$1/build.log" 2>&1 || { tail -50 "$1/build.log" >&2; exit 1; }
}

# a fresh run directory with the bundled INI and program
run_dir() {
    rm -rf "$1"
    mkdir -p "$1"
    cp "$ROOT/python/sf_tch/data/SF_TCh.ini" "$ROOT/python/sf_tch/data/demo.nc" "$1/"
}

case "$TARGET" in
windows)
    CC32="$(command -v i686-w64-mingw32-gcc-win32 || command -v i686-w64-mingw32-gcc || true)"
    if [ -z "$CC32" ]; then
        echo "build_x86: needs mingw-w64 for i686 (apt-get install --no-install-recommends" \
             "gcc-mingw-w64-i686): not installed, nothing built" >&2
        exit 77
    fi
    OUT="$BUILD/windows-x86"
    mkdir -p "$OUT"
    configure_and_build "$OUT" mingw-w64-i686.cmake
    "$CC32" -std=gnu11 -O2 -msse2 -mfpmath=sse -Wall -Wextra -Werror -D__USE_MINGW_ANSI_STDIO=1 \
        -I "$ROOT/include" "$ROOT/tests/windows/panel.c" -o "$OUT/panel.exe" -static-libgcc
    RUN="$OUT/run"
    run_dir "$RUN"
    # Wine's 32-bit loader comes with Debian's wine32 (an i386 package)
    WINE32="${WINE32:-}"
    [ -z "$WINE32" ] && [ -x /usr/lib/wine/wine ] && WINE32=/usr/lib/wine/wine
    if [ -z "$WINE32" ]; then
        echo "wine32 is not installed (Debian: dpkg --add-architecture i386; apt-get install wine32):" \
             "the x86 panel was built, not run" > "$OUT/not-run.txt"
        echo "build_x86: $OUT/SF_TCh.dll; $(cat "$OUT/not-run.txt")"
        exit 0
    fi
    cp "$OUT/SF_TCh.dll" "$OUT/panel.exe" "$RUN/"
    unset LD_PRELOAD
    export WINEPREFIX="${WINEPREFIX:-$OUT/wineprefix32}" WINEARCH=win32 WINEDEBUG=-all WINEDLLOVERRIDES="mscoree,mshtml="
    mkdir -p "$WINEPREFIX"
    (cd "$RUN" && timeout 600 "$WINE32" panel.exe SF_TCh.dll < /dev/null > report.crlf 2> report.stderr) || {
        echo "build_x86: the x86 panel failed under Wine:" >&2
        cat "$RUN/report.stderr" >&2
        exit 1
    }
    tr -d '\r' < "$RUN/report.crlf" > "$RUN/report.txt"
    WINESERVER="$(dirname "$WINE32")/wineserver"
    [ -x "$WINESERVER" ] && "$WINESERVER" -w
    echo "build_x86: $OUT/SF_TCh.dll; the panel's report under Wine: $RUN/report.txt"
    ;;
linux)
    probe="$(mktemp -d)"
    trap 'rm -rf "$probe"' EXIT
    printf '#include <math.h>\n#include <pthread.h>\nint main(void) { return (int)sqrt(4.0) - 2; }\n' > "$probe/m32.c"
    if ! gcc -m32 "$probe/m32.c" -o "$probe/m32" -lm -lpthread -ldl > /dev/null 2>&1 || ! "$probe/m32"; then
        echo "build_x86: gcc -m32 cannot build or run 32-bit programs here (apt-get install" \
             "--no-install-recommends gcc-multilib): nothing built" >&2
        exit 77
    fi
    OUT="$BUILD/linux-i686"
    mkdir -p "$OUT"
    configure_and_build "$OUT" linux-i686.cmake
    gcc -m32 -msse2 -mfpmath=sse -std=gnu11 -O2 -Wall -Wextra -Werror -I "$ROOT/include" \
        "$ROOT/tests/windows/panel.c" -o "$OUT/panel" -ldl -lpthread
    RUN="$OUT/run"
    run_dir "$RUN"
    # the panel checks that the log goes to Init's directory
    (cd "$RUN" && env -u SF_TCH_LOG_DIR -u LD_PRELOAD timeout 600 "$OUT/panel" "$OUT/libSF_TCh.so" \
        < /dev/null > report.txt 2> report.stderr) || {
        echo "build_x86: the i686 panel failed:" >&2
        cat "$RUN/report.stderr" >&2
        exit 1
    }
    echo "build_x86: $OUT/libSF_TCh.so; the panel's report: $RUN/report.txt"
    ;;
*)
    echo "usage: tools/build_x86.sh windows|linux [BUILD_DIR]" >&2
    exit 2
    ;;
esac
