"""SF_TCh.dll, the Windows x64 build of the same sources (docs/hosts.md), under Wine.

tools/build_windows.sh cross-builds the DLL with mingw-w64 and runs the C panel
tests/windows/panel.c on it under Wine; here the same panel, built with the system cc,
runs on the Linux library and the two reports must agree line by line: the
interpolator manual's example program (its error, or its parts), the demo's parts,
lengths, boxes and run time with every callback recorded, a regime-30 run on three
cores while three threads poll GetPos, and errors with non-ASCII file names and texts (numbers, lines, texts, the
names IdxToFile gives back). Also: numbers in a host with a decimal-comma locale, the
DLL exports exactly the header's functions and TGM_Data and imports only Windows
system DLLs, and a layout probe compiled by mingw-w64 and run under Wine agrees with
the Windows ctypes mirror.

Skipped, saying why, where mingw-w64 or Wine is not installed (.ci/run installs them).
"""
import ctypes
import math
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import sf_tch
from sf_tch import abi, abi_check

ROOT = Path(__file__).resolve().parents[1]
SCRIPT = ROOT / "tools" / "build_windows.sh"
PANEL = ROOT / "tests" / "windows" / "panel.c"
DATA = ROOT / "python" / "sf_tch" / "data"
OBJDUMP = "x86_64-w64-mingw32-objdump"
WINE = shutil.which("wine64") or "/usr/lib/wine/wine64"      # Debian's wine64 without its recommends
# Windows' own DLLs (the C runtime msvcrt.dll or the UCRT's api-ms-win-crt-* sets)
SYSTEM_DLLS = re.compile(r"(kernel32|msvcrt|ucrtbase|api-ms-win-[\w-]+|advapi32|user32|ntdll)\.dll", re.I)


@pytest.fixture(scope="module")
def windows_build(tmp_path_factory):
    """The build directory of tools/build_windows.sh: the DLL, and the panel's report
    under Wine in wine-run/report.txt."""
    build = tmp_path_factory.mktemp("windows") / "build"
    # cmake and ninja may come with the test extras, beside this Python
    path = os.pathsep.join([str(Path(sys.executable).parent), os.environ.get("PATH", "")])
    proc = subprocess.run(["bash", str(SCRIPT), str(build)],
                          env={**panel_environment(), "PYTHON": sys.executable, "PATH": path},
                          capture_output=True, text=True, timeout=1800)
    if proc.returncode == 77:
        pytest.skip(proc.stderr.strip())
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    yield build
    # the Wine prefix takes some 700 MB: gone once its server has ended
    prefix = build / "wineprefix"
    server = Path(WINE).parent / "wineserver"
    if server.exists():
        subprocess.run([str(server), "-w"], env={**os.environ, "WINEPREFIX": str(prefix)}, timeout=120)
    shutil.rmtree(prefix, ignore_errors=True)


def panel_environment() -> dict:
    """The suite's environment without SF_TCH_LOG_DIR (conftest's log directory per
    process): the panel checks that the log goes to Init's directory."""
    return {k: v for k, v in os.environ.items() if k != "SF_TCH_LOG_DIR"}


def linux_report(lib_path: str, tmp: Path) -> str:
    """The same panel, built with the system cc, on the Linux library."""
    cc = shutil.which("cc") or shutil.which("gcc")
    if cc is None:
        pytest.skip("no C compiler for the Linux panel")
    exe = tmp / "panel"
    subprocess.run([cc, "-std=gnu11", "-O2", "-Wall", "-Wextra", "-Werror", "-I", str(ROOT / "include"), str(PANEL),
                    "-o", str(exe), "-ldl", "-lpthread"], check=True)
    run = tmp / "run"
    run.mkdir()
    for name in ("SF_TCh.ini", "demo.nc"):
        shutil.copy(DATA / name, run / name)
    proc = subprocess.run([str(exe), lib_path], cwd=run, capture_output=True, timeout=600, env=panel_environment())
    assert proc.returncode == 0, proc.stderr.decode(errors="replace")
    return proc.stdout.decode()


NUMBER = re.compile(r"-?\d+(?:\.\d+)?(?:e[-+]?\d+)?")


def same_line(a: str, b: str) -> bool:
    """Equal texts, numbers equal to 1e-9 relative (or 1e-6 absolute): the two C
    runtimes' libm may round a last bit differently."""
    if NUMBER.sub("#", a) != NUMBER.sub("#", b):
        return False
    return all(math.isclose(float(x), float(y), rel_tol=1e-9, abs_tol=1e-6)
               for x, y in zip(NUMBER.findall(a), NUMBER.findall(b)))


def test_the_panel_gets_on_windows_what_it_gets_on_linux(windows_build, lib_path, tmp_path):
    windows = (windows_build / "wine-run" / "report.txt").read_text(encoding="utf-8").splitlines()
    linux = linux_report(lib_path, tmp_path).splitlines()
    different = [f"line {k + 1}:\n  linux:   {a}\n  windows: {b}"
                 for k, (a, b) in enumerate(zip(linux, windows)) if not same_line(a, b)]
    assert len(windows) == len(linux) and not different, "\n".join(different[:20])
    # what the reports hold, so that two equally broken runs cannot pass
    text = "\n".join(windows)
    assert "structure sizes: 8 1112 616 112 32 1280 52 448 32" in text
    assert "log file: yes, has the line: yes" in text
    assert re.search(r"^error: \d+ line \d+ file příklad_manuálu\.nc: ", text, re.M)     # absolute: refused
    assert re.search(r"^motion parts: \d+, cut [1-9]", text, re.M)                   # relative: simulated
    for core in range(3):
        assert f"core {core}: start 0, status -32" in text                # at the end of the program
    assert "polls failed: 0, went back: 0, any: yes" in text
    assert "call error: 1 line 0 file __unknown__: Cannot open file 'chybějící_soubor_ž.nc'" in text
    assert "call error: 13 line 0 file __unknown__: 'složka_č.nc' is not a regular file" in text
    assert re.search(r"^error: \d+ line 3 file chyba_řádek_ü\.nc: Unknown G function G999", text, re.M)
    assert re.search(r"^error: \d+ line 2 file paměť_日本\.nc: ", text, re.M)
    assert re.search(r"^call error: 16 line 2 file __unknown__: INI file 'nastavení_ř\.ini' line 2", text, re.M)
    assert re.search(r"^  18 line 3: Unknown G function G999", text, re.M)      # the callback's UTF-16 text
    assert text.count("same text: yes, same pointer: yes") == 3
    assert "file 5: emoji_😀.nc" in text                                      # a surrogate pair in UTF-16


def pe_dump(dll: Path) -> str:
    if shutil.which(OBJDUMP) is None:
        pytest.skip(f"no {OBJDUMP}")
    return subprocess.run([OBJDUMP, "-p", str(dll)], capture_output=True, text=True, check=True).stdout


def header_functions() -> set:
    text = Path(sf_tch.header_path()).read_text()
    return set(re.findall(r"^TOOLCHAIN_API\b[^;(]*?\b(\w+)\s*\(", text, flags=re.M))


def test_the_dll_exports_the_header_and_tgm_data_only(windows_build):
    dump = pe_dump(windows_build / "SF_TCh.dll")
    table = dump.split("[Ordinal/Name Pointer] Table", 1)[1]
    exported = set(re.findall(r"^\s*\[\s*\d+\]\s+(\S+)\s*$", table, flags=re.M))
    assert len(header_functions()) >= 40
    assert exported == header_functions() | {"TGM_Data"}
    # the export list for MSVC's lib.exe says the same, undecorated
    listed = re.findall(r"^\s+(\w+) @\d+", (windows_build / "SF_TCh.def").read_text(), flags=re.M)
    assert set(listed) == exported
    assert (windows_build / "SF_TCh.lib").stat().st_size > 0


def test_the_dll_imports_only_windows_system_dlls(windows_build):
    imported = re.findall(r"DLL Name: (\S+)", pe_dump(windows_build / "SF_TCh.dll"))
    assert "KERNEL32.dll" in imported
    assert [name for name in imported if not SYSTEM_DLLS.fullmatch(name)] == []      # no python3x, libgcc, winpthread


def test_a_layout_probe_built_by_mingw_agrees_with_the_windows_mirror(windows_build):
    cc = shutil.which("x86_64-w64-mingw32-gcc")
    run = ("env", f"WINEPREFIX={windows_build / 'wineprefix'}", "WINEDEBUG=-all", "WINEDLLOVERRIDES=mscoree,mshtml=",
           WINE)
    report = abi_check.check_layouts(windows=True, cc=cc, run=run)
    assert report.differences == []
    assert sum(1 for r in report.rows if r[1] == "(sizeof)") == len(abi.STRUCTURES)
    dll_dir = [r for r in report.rows if r[0] == "DLL_INIT_STRUCT" and r[1] == "CNC_Dll_Dir"]
    assert dll_dir and dll_dir[0][2] == "wchar_t*"
    # the Linux mirror is wrong for Windows, and the check says so
    wrong = abi_check.Report()
    abi_check._compare_layouts(wrong, abi_check.default_header(), abi.mirror(windows=False)[0], None, True, cc, run)
    assert any("DLL_INIT_STRUCT.CNC_Dll_Dir: type C wchar_t* ctypes char*" in d for d in wrong.differences)


def test_numbers_on_windows_are_read_and_written_in_the_c_locale_whatever_the_hosts(windows_build):
    """The panel in a German locale (every thread's CRT locale writes a decimal comma):
    the INI's 1.5, a G-code number too long for the lexer's own conversion (strtod) and
    an error text with decimals (snprintf) come out as in the C locale."""
    report = (windows_build / "wine-run" / "decimal-comma.txt").read_text(encoding="utf-8")
    assert report.startswith("decimal point: ',', INI 1.5: same, long number: same, error text: same"), report
    assert "Start X = 60.6051 Y = 40.7723" in report


@pytest.mark.parametrize("scenario", ["run", "compile", "mfunc"])
def test_a_panel_may_unload_the_dll_while_the_library_works(windows_build, scenario):
    """tests/windows/unload.c: FreeLibrary without DestroyCNC during a run of the offline
    machine, a compilation, a wait for an M function; the library's thread goes on (its
    code stays mapped: the module pinned itself with its first thread), a LoadLibrary
    finds the same module, and the process, returning from main with that thread still
    at work, ends cleanly (build_windows.sh fails on any other exit status)."""
    report = (windows_build / "wine-run" / f"unload-{scenario}.txt").read_text(encoding="utf-8")
    doing = {"run": "running: yes\n", "compile": "compiling: yes\n",
             "mfunc": "waiting for an M function: yes\n"}[scenario]
    assert doing in report and "freed: yes\n" in report, report
    assert "loaded again: the same module\nthe core still works: yes\nexit\n" in report, report
    if scenario == "run":
        assert "the run goes on after FreeLibrary: yes\n" in report, report


def test_a_dll_that_started_no_thread_is_unloaded_by_free_library(windows_build):
    report = (windows_build / "wine-run" / "unload-idle.txt").read_text(encoding="utf-8")
    assert report.endswith("freed: yes\nunloaded: yes\nloaded again, version: yes\nexit\n"), report


@pytest.mark.parametrize("code_page, error_bytes, file_name, printed", [
    (1250, "9A ED F8", "Zkouška_chybí_ř.nc", "šrouby č. 5"),            # Czech: every letter
    (1252, "9A ED", "Zkouška_chybí_?.nc", "šrouby ?. 5"),               # Western: ř and č replaced visibly
])
def test_narrow_texts_are_in_the_ansi_code_page_unless_the_ini_says_utf8(windows_build, code_page, error_bytes,
                                                                         file_name, printed):
    """tests/windows/ansi.c under Wine in a Czech and a Western locale: CALLBACK_INFO's
    texts, ToolChain_LogANSI and the log hook, and G-code text in the process's ANSI code
    page by default; UTF-8 after an INI file's [Texts] Narrow=utf8."""
    report = (windows_build / "wine-run" / f"ansi-{code_page}.txt").read_text(encoding="utf-8")
    default, utf8 = report.split("== [Texts] Narrow=utf8\n")
    assert default.startswith(f"code page: {code_page}\n== default: the ANSI code page\n"), report
    assert f"error 1: Cannot open file '{file_name}'\nbytes beyond ASCII: {error_bytes} \n" in default, report
    assert "the same bytes: yes\nlog file has it in UTF-8: yes\n" in default, report
    assert f"PRINT: {printed}\n" in default, report
    # the opt-in: UTF-8, every letter
    assert "INI utf8: 0\n" in default
    assert "error 1: Cannot open file 'Zkouška_chybí_ř.nc'\nbytes beyond ASCII: C5 A1 C3 AD C5 99 \n" in utf8, report
    assert "log hook: řádek žluťoučký, the same bytes: yes\nlog file has it in UTF-8: yes\n" in utf8, report
    assert "PRINT: šrouby č. 5\n" in utf8, report


def test_the_narrow_texts_key_is_read_on_linux_and_changes_nothing(tmp_path):
    """[Texts] Narrow (ansi | utf8) chooses Windows' narrow texts; on Linux they stay UTF-8
    whatever it says, and a value it does not know is refused, naming the key."""
    from sf_tch import CncError
    from sf_tch.core import Core
    for value in ("ansi", "utf8"):
        ini = tmp_path / f"{value}.ini"
        ini.write_text(f"[Texts]\nNarrow={value}\n")
        with Core(ini=str(ini)) as core:
            with pytest.raises(CncError) as error:
                core.compile_file(str(tmp_path / "chybí_ř.nc"))
            assert "chybí_ř.nc" in error.value.text
    bad = tmp_path / "bad.ini"
    bad.write_text("[Texts]\nNarrow=latin2\n")
    lib = sf_tch.library.load()
    assert lib.ToolChainCore_LoadFromIni(2, str(bad).encode(), None) == abi.TOOL_CHAIN_XEXEC
    info = abi.CALLBACK_INFO()
    texts = [lib.ToolChainCore_GetLastCallError(2, ctypes.byref(info)) and info.m_fullError,
             lib.ToolChainCore_GetLastError(2, ctypes.byref(info)) and info.m_fullError]
    lib.ToolChainCore_DestroyCNC(2)
    assert any(t and b"[Texts] Narrow" in t for t in texts), texts


def test_a_panel_linked_against_the_import_library_runs(windows_build):
    """tests/windows/linked.c calls the functions directly, through the header's
    dllimport declarations and SF_TCh.lib."""
    report = (windows_build / "wine-run" / "linked.txt").read_text(encoding="utf-8")
    assert report == "linked: version yes, structure sizes: 8 1112 616 112 32 1280 52 448 32\n", report


@pytest.mark.parametrize("target", ["x86_64-pc-windows-msvc", "i686-pc-windows-msvc"])
@pytest.mark.parametrize("language", ["c", "c++"])
def test_the_header_compiles_for_msvc_panels(target, language, tmp_path):
    """As MSVC would compile a panel (clang in MSVC mode, no Windows SDK needed): C and
    C++, x64 and x86, the functions dllimport, the layout asserts of both."""
    clang = shutil.which("clang")
    if clang is None:
        pytest.skip("no clang: the header's MSVC mode is not checked")
    source = tmp_path / ("panel.c" if language == "c" else "panel.cpp")
    source.write_text('#include "tgm_cnc.h"\nint f(void) { return ToolChainCore_DestroyCNC(0); }\n')
    proc = subprocess.run([clang, f"--target={target}", "-ffreestanding", "-fsyntax-only", "-Werror",
                           "-I", str(ROOT / "include"), str(source)], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
