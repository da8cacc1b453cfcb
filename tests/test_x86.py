"""32-bit x86: SF_TCh.dll for Windows x86 and the same sources as libSF_TCh.so for Linux
i686 (tools/build_x86.sh; docs/hosts.md).

Wine's 32-bit half (Debian's wine32, an i386 package) often cannot be installed next to
wine64, so the 32-bit code is tested natively: the Linux i686 library (gcc -m32, SSE2
floating point) runs the C panel tests/windows/panel.c, whose report must equal the
x86_64 Linux library's line by line but for the structure sizes, which must be the
vendor's 32-bit ones (CALLBACK_INFO 24, DLL_INIT_STRUCT 16). The x86 DLL is checked
statically: a PE32 file for i386 exporting exactly the header's functions and TGM_Data,
undecorated, importing only Windows system DLLs; its layouts as i686 mingw-w64 compiles
the header (read from the compiler's output, nothing run) and as gcc -m32 does, against
the 32-bit ctypes mirror. Under wine32, where it is installed, the x86 panel's report is
compared too. Each part is skipped, saying why, where its tools are missing (.ci/run
installs gcc-mingw-w64-i686 and gcc-multilib).
"""
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from sf_tch import abi, abi_check
from test_windows import SYSTEM_DLLS, header_functions, linux_report, panel_environment, same_line

ROOT = Path(__file__).resolve().parents[1]
SCRIPT = ROOT / "tools" / "build_x86.sh"
SIZES_64 = "structure sizes: 8 1112 616 112 32 1280 52 448 32"
SIZES_32 = "structure sizes: 8 1112 616 112 24 1280 52 448 16"
OBJDUMP = "i686-w64-mingw32-objdump"


def build(target: str, tmp_path_factory) -> Path:
    build_dir = tmp_path_factory.mktemp(f"x86-{target}")
    path = os.pathsep.join([str(Path(sys.executable).parent), os.environ.get("PATH", "")])
    proc = subprocess.run(["bash", str(SCRIPT), target, str(build_dir)],
                          env={**panel_environment(), "PYTHON": sys.executable, "PATH": path},
                          capture_output=True, text=True, timeout=1800)
    if proc.returncode == 77:
        pytest.skip(proc.stderr.strip())
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    return build_dir


@pytest.fixture(scope="module")
def linux_i686(tmp_path_factory) -> Path:
    return build("linux", tmp_path_factory) / "linux-i686"


@pytest.fixture(scope="module")
def windows_x86(tmp_path_factory) -> Path:
    return build("windows", tmp_path_factory) / "windows-x86"


def compare_with_x86_64(report_32: str, lib_path: str, tmp: Path) -> None:
    ours = report_32.splitlines()
    reference = linux_report(lib_path, tmp).splitlines()
    assert SIZES_64 in reference and SIZES_32 in ours
    ours = [SIZES_64 if line == SIZES_32 else line for line in ours]
    different = [f"line {k + 1}:\n  x86_64: {a}\n  x86:    {b}"
                 for k, (a, b) in enumerate(zip(reference, ours)) if not same_line(a, b)]
    assert len(ours) == len(reference) and not different, "\n".join(different[:20])


def test_the_i686_library_gives_the_panel_what_the_x86_64_library_gives(linux_i686, lib_path, tmp_path):
    report = (linux_i686 / "run" / "report.txt").read_text(encoding="utf-8")
    compare_with_x86_64(report, lib_path, tmp_path)
    assert "polls failed: 0, went back: 0, any: yes" in report
    assert re.search(r"^motion parts: \d+, cut [1-9]", report, re.M)


def test_the_i686_library_is_32_bit_and_needs_no_python(linux_i686):
    lib = linux_i686 / "libSF_TCh.so"
    assert lib.read_bytes()[4] == 1                              # ELFCLASS32
    symbols = subprocess.run(["nm", "-D", str(lib)], capture_output=True, text=True, check=True).stdout
    exported = set(re.findall(r"^[0-9a-f]+ [TDB] (\w+)$", symbols, re.M))
    assert exported == header_functions() | {"TGM_Data"}
    assert not re.search(r"\bPy", symbols)


def test_the_header_and_the_32_bit_mirror_agree_on_linux_i686(linux_i686):
    report = abi_check.check_layouts(windows=False, pointer_bits=32, cflags=("-m32",))
    assert report.differences == []
    assert sum(1 for r in report.rows if r[1] == "(sizeof)") == len(abi.STRUCTURES)


def pe_dump(dll: Path) -> str:
    if shutil.which(OBJDUMP) is None:
        pytest.skip(f"no {OBJDUMP}")
    return subprocess.run([OBJDUMP, "-p", str(dll)], capture_output=True, text=True, check=True).stdout


def test_the_x86_dll_is_pe32_and_exports_the_header_undecorated(windows_x86):
    dump = pe_dump(windows_x86 / "SF_TCh.dll")
    assert "file format pei-i386" in dump
    assert re.search(r"^Magic\s+010b\s+\(PE32\)", dump, re.M)
    table = dump.split("[Ordinal/Name Pointer] Table", 1)[1]
    exported = set(re.findall(r"^\s*\[\s*\d+\]\s+(\S+)\s*$", table, flags=re.M))
    assert exported == header_functions() | {"TGM_Data"}              # no _name, no name@N
    listed = re.findall(r"^\s+(\w+) @\d+", (windows_x86 / "SF_TCh.def").read_text(), flags=re.M)
    assert set(listed) == exported
    imported = re.findall(r"DLL Name: (\S+)", dump)
    assert "KERNEL32.dll" in imported
    assert [name for name in imported if not SYSTEM_DLLS.fullmatch(name)] == []


def test_the_x86_dll_computes_in_sse2(windows_x86):
    """Arithmetic on doubles is SSE2 (x87 only moves return values, as the x86 ABI wants)."""
    dump = subprocess.run([OBJDUMP, "-d", str(windows_x86 / "SF_TCh.dll")], capture_output=True, text=True,
                          check=True).stdout
    assert len(re.findall(r"\s(?:mulsd|addsd|subsd|divsd)\s", dump)) > 1000


def test_i686_mingw_lays_the_header_out_as_the_32_bit_windows_mirror(windows_x86):
    cc = shutil.which("i686-w64-mingw32-gcc")
    report = abi_check.check_layouts(windows=True, pointer_bits=32, cc=cc, compile_only=True)
    assert report.differences == []
    sizes = {r[0]: r[5] for r in report.rows if r[1] == "(sizeof)"}
    assert (sizes["CALLBACK_INFO"], sizes["DLL_INIT_STRUCT"]) == (24, 16)
    dll_dir = [r for r in report.rows if r[0] == "DLL_INIT_STRUCT" and r[1] == "CNC_Dll_Dir"]
    assert dll_dir and dll_dir[0][2] == "wchar_t*"
    # the x64 mirror is wrong for x86, and the check says so
    wrong = abi_check.Report()
    abi_check._compare_layouts(wrong, abi_check.default_header(), abi.mirror(windows=True)[0],
                               abi_check.SPEC_SIZES_32, True, cc, (), (), True)
    assert "CALLBACK_INFO: sizeof C 24 ctypes 32" in wrong.differences


def test_the_x86_panel_under_wine32(windows_x86, lib_path, tmp_path):
    not_run = windows_x86 / "not-run.txt"
    if not_run.exists():
        pytest.skip(not_run.read_text().strip())
    compare_with_x86_64((windows_x86 / "run" / "report.txt").read_text(encoding="utf-8"), lib_path, tmp_path)
