"""The conformance suite (python -m sf_tch.conformance, docs/conformance.md): every
check holds against this library; a deliberately wrong library (tests/conformance/
shim.c: the real one with a few answers altered) is reported check by check, a crash
and a hang as verdicts of their own; the command line's options; the suite's Windows
code path (text types, library loading) with the platform monkeypatched."""
import ctypes
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from runtime_host import TIME_SCALE
from sf_tch import abi, header_path, library_path
from sf_tch.conformance import AREAS, all_checks, host as chost

SHIM = Path(__file__).resolve().parent / "conformance" / "shim.c"
# What the shim alters, and the one check that reads each answer.
# A sanitized library (tests/test_sanitizers.py: SF_TCH_TIME_SCALE > 1) runs the offline
# machine's real time several times slower in each step: the real-time area is left out then,
# and so is the wrong library, which links against the library under the sanitizer's runtime.
SANITIZED = TIME_SCALE > 1
SHIM_DIFFERS = {"structures.default_insertArcToleranceRMin", "structures.size_CALLBACK_INFO",
                "errors.seed_absolute_400", "machine.stop_distance"}


def suite(*args, env=None, timeout=240):
    """Runs the command line; (exit status, parsed --json output or stdout)."""
    proc = subprocess.run([sys.executable, "-m", "sf_tch.conformance", *args], capture_output=True, text=True,
                          timeout=timeout, env=dict(os.environ, **(env or {})))
    if "--json" in args and proc.returncode in (0, 1):
        return proc.returncode, json.loads(proc.stdout)
    return proc.returncode, proc.stdout + proc.stderr


@pytest.fixture(scope="module")
def shim(tmp_path_factory):
    if SANITIZED:
        pytest.skip("a sanitized library: the wrong library is built against the plain one only")
    cc = shutil.which("cc") or shutil.which("gcc")
    if cc is None:
        pytest.skip("no C compiler (cc): the wrong library cannot be built")
    real = library_path()
    out = tmp_path_factory.mktemp("shim") / "libSF_TCh_wrong.so"
    lib_dir = os.path.dirname(real)
    cmd = [cc, "-shared", "-fPIC", "-O1", f"-DREAL_LIBRARY=\"{real}\"", f"-I{os.path.dirname(header_path())}",
           str(SHIM), "-o", str(out), f"-L{lib_dir}", "-Wl,--no-as-needed", f"-l:{os.path.basename(real)}",
           f"-Wl,-rpath,{lib_dir}", "-ldl", "-lpthread"]
    proc = subprocess.run(cmd, capture_output=True, text=True)
    if proc.returncode != 0:
        pytest.skip(f"the wrong library did not build: {proc.stderr[-500:]}")
    return str(out)


@pytest.mark.exclusive       # the offline machine runs in real time: no other test beside it
def test_every_check_holds_against_this_library():
    areas = [a for a in AREAS if not (SANITIZED and a == "machine")]
    rc, report = suite("--json", "--only", ",".join(areas), "--timeout", str(30 * TIME_SCALE))
    bad = [(r["id"], r["verdict"], r.get("expected"), r.get("got"), r.get("detail")) for r in report["checks"]
           if r["verdict"] != "holds"]
    assert bad == [] and rc == 0
    assert {r["area"] for r in report["checks"]} == set(areas)
    assert report["summary"]["holds"] == len(report["checks"]) >= 100


@pytest.mark.exclusive
def test_a_wrong_library_is_reported_check_by_check(shim):
    rc, report = suite("--json", "--library", shim, "--only", "structures,errors,machine")
    assert rc == 1
    verdicts = {r["id"]: r for r in report["checks"]}
    assert {i for i, r in verdicts.items() if r["verdict"] != "holds"} == SHIM_DIFFERS
    assert all(verdicts[i]["verdict"] == "differs" for i in SHIM_DIFFERS)
    size = verdicts["structures.size_CALLBACK_INFO"]
    assert (size["expected"], size["got"]) == (ctypes.sizeof(abi.CALLBACK_INFO), ctypes.sizeof(abi.CALLBACK_INFO) + 8)
    assert (verdicts["errors.seed_absolute_400"]["expected"], verdicts["errors.seed_absolute_400"]["got"]) == \
        ("(400, 4)", "(400, 5)")
    assert verdicts["structures.default_insertArcToleranceRMin"]["got"] == 0.05
    stop = verdicts["machine.stop_distance"]
    assert stop["expected"] == "5 mm (± 0.15) after the call" and 7 < stop["got"] < 9    # 5 mm + 30 ms at 100 mm/s


def test_a_crash_is_a_verdict_and_the_area_goes_on(shim):
    rc, report = suite("--json", "--library", shim, "--only", "returns", env={"SHIM_CRASH": "1"})
    assert rc == 1
    verdicts = {r["id"]: r["verdict"] for r in report["checks"]}
    assert verdicts.pop("returns.bad_core") == "crashed"      # GetVersionString(3) aborts
    assert verdicts.pop("returns.version") == "crashed"
    # the checks after them ran in a new process
    assert set(verdicts.values()) == {"holds"}, [r for r in report["checks"] if r["verdict"] != "holds"]
    crashed = next(r for r in report["checks"] if r["id"] == "returns.version")
    assert "SIGABRT" in crashed["detail"]


def test_a_hang_is_timed_out_by_the_check_bound(shim):
    rc, report = suite("--json", "--library", shim, "--only", "returns", "--timeout", "1.5", env={"SHIM_HANG": "1"})
    assert rc == 1
    verdicts = {r["id"]: r["verdict"] for r in report["checks"]}
    assert verdicts.pop("returns.bad_core") == "timed out"
    assert verdicts.pop("returns.version") == "timed out"
    assert set(verdicts.values()) == {"holds"}, [r for r in report["checks"] if r["verdict"] != "holds"]


def test_table_summary_and_only():
    rc, out = suite("--only", "structures")
    assert rc == 0, out
    lines = out.strip().splitlines()
    assert lines[0] == f"structures: {len([c for c in all_checks() if c.area == 'structures'])}/" \
                       f"{len([c for c in all_checks() if c.area == 'structures'])} hold"
    assert lines[-1].startswith("conformance: ") and " 0 differ," in lines[-1]


def test_list_names_every_statement():
    rc, out = suite("--list")
    assert rc == 0
    assert len(out.strip().splitlines()) == len(all_checks())
    for c in all_checks():
        assert c.statement and c.document.endswith(".md") and c.section


def test_usage_errors():
    assert suite("--only", "nowhere")[0] == 2
    rc, out = suite("--library", "/nonexistent/libSF_TCh.so")
    assert rc == 2 and "no such file" in out


def test_every_check_is_listed_in_the_docs():
    doc = (Path(__file__).resolve().parents[1] / "docs" / "conformance.md").read_text(encoding="utf-8")
    missing = [c.id for c in all_checks() if f"`{c.id}`" not in doc]
    assert missing == []
    rc, tables = suite("--list", "--markdown")
    assert rc == 0 and doc.endswith(tables), "docs/conformance.md: run python -m sf_tch.conformance --list --markdown"


def test_nothing_written_outside_a_temporary_directory(tmp_path):
    before = set(os.listdir(tmp_path))
    proc = subprocess.run([sys.executable, "-m", "sf_tch.conformance", "--only", "errors"], cwd=tmp_path,
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert set(os.listdir(tmp_path)) == before


def test_runs_on_the_oldest_cpython(tmp_path):
    """CPython 3.9 (the oldest the package supports), where this machine has one: the suite's own code
    (the package from this interpreter's installation, no numpy) runs there as well."""
    from test_hosts import find_cpython
    python = find_cpython(9)
    if python is None:
        pytest.skip("no CPython 3.9 on this machine (PATH, pyenv)")
    import sf_tch
    root = os.path.dirname(os.path.dirname(sf_tch.__file__))
    proc = subprocess.run([python, "-m", "sf_tch.conformance", "--library", library_path(), "--only",
                           "structures,errors"], capture_output=True, text=True, timeout=120, cwd=tmp_path,
                          env=dict(os.environ, PYTHONPATH=root, PYTHONNOUSERSITE="1"))
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert " 0 differ, " in proc.stdout.splitlines()[-1]


# ---------------------------------------------------------------- the Windows code path

def test_platform_choice(monkeypatch):
    assert chost.is_windows("win32") and not chost.is_windows("linux")
    monkeypatch.setattr(sys, "platform", "win32")
    assert chost.is_windows()
    assert chost.library_file_name(True) == "SF_TCh.dll"


def test_windows_texts_are_utf16_str():
    texts = chost.Texts(windows=True)
    assert texts.type is ctypes.c_wchar_p
    assert texts.arg("Příklad.nc") == "Příklad.nc"                 # str: ctypes passes it as wchar_t *
    assert texts.back("Příklad.nc") == "Příklad.nc"
    assert texts.back(None) == ""
    types = texts.callback_types()
    assert types[abi.CB_DISP_AND_LOCATE_ERROR]._argtypes_[3] is ctypes.c_wchar_p
    assert types[abi.CB_ADD_OUTPUT_LOG]._argtypes_[2] is ctypes.c_wchar_p
    linux = chost.Texts(windows=False)
    assert linux.type is ctypes.c_char_p and linux.arg("Příklad.nc") == "Příklad.nc".encode()


def test_windows_library_loading(monkeypatch):
    """load() on Windows: ctypes.CDLL (cdecl) and the prototypes of the UTF-16 build."""
    class Fn:
        pass

    class FakeDll:
        def __init__(self, path):
            self.path = path
            self.fns = {}

        def __getattr__(self, name):
            if name == "ToolChainCore_TestClock":
                raise AttributeError(name)             # an export the library lacks is skipped
            return self.fns.setdefault(name, Fn())

    monkeypatch.setattr(sys, "platform", "win32")
    monkeypatch.setattr(chost.ctypes, "CDLL", FakeDll)
    lib = chost.load("C:\\TG\\SF_TCh.dll")
    assert lib.path == "C:\\TG\\SF_TCh.dll"
    assert lib.fns["ToolChainCore_CompileFromMemory"].argtypes[1] is ctypes.c_wchar_p
    assert lib.fns["ToolChainCore_CompileFromMemory"].argtypes[2] is ctypes.c_char_p     # G-code stays narrow
    assert lib.fns["ToolChainCore_IdxToFile"].restype is ctypes.c_wchar_p
    init = lib.fns["ToolChainCore_Init"].argtypes[0]._type_
    assert dict(init._fields_)["CNC_Dll_Dir"] is ctypes.c_wchar_p
    assert "ToolChainCore_TestClock" not in lib.fns


def test_every_public_name_has_a_docstring():
    import importlib
    import inspect
    missing = []
    for module_name in ("checks", "host", "worker", "runner", "cli", *AREAS):
        module = importlib.import_module(f"sf_tch.conformance.{module_name}")
        if not module.__doc__:
            missing.append(module_name)
        for name, obj in vars(module).items():
            if name.startswith("_") or getattr(obj, "__module__", None) != module.__name__:
                continue
            if (inspect.isclass(obj) or inspect.isfunction(obj)) and not inspect.getdoc(obj):
                missing.append(f"{module_name}.{name}")
            if inspect.isclass(obj) and not issubclass(obj, Exception):
                missing += [f"{module_name}.{name}.{m}" for m, v in vars(obj).items()
                            if not m.startswith("_") and (inspect.isfunction(v) or isinstance(v, property))
                            and not inspect.getdoc(v)]
    assert missing == []


def test_extensions_missing_are_not_applicable(tmp_path):
    """The checks that need this project's extension exports (tool table, axis tables,
    smoothing, ConfirmMFunc) say 'not applicable' on a library without them; the worker
    reports them so."""
    from sf_tch.conformance.checks import NotApplicable, area_checks
    from sf_tch.conformance import worker

    class WithoutExtensions:
        def __init__(self, lib):
            self._lib = lib

        def __getattr__(self, name):
            if name in abi.EXTENSION_FUNCTIONS:
                raise AttributeError(name)
            return getattr(self._lib, name)

    host = chost.Host(library_path(), str(tmp_path))
    host.lib = WithoutExtensions(host.lib)
    needing = [c for area in ("tool_table", "axis_tables", "smoothing") for c in area_checks(area)]
    needing += [c for c in area_checks("machine") if c.name == "m_handshake_later"]
    for c in needing:
        with pytest.raises(NotApplicable, match="does not export ToolChainCore_"):
            c.run(host)

    class Out(list):
        def write(self, text):
            self.append(text)

        def flush(self):
            pass

    out = Out()
    monkey = pytest.MonkeyPatch()
    monkey.setattr(worker, "Host", lambda path, workdir: host)
    monkey.chdir(tmp_path)
    try:
        worker.run(library_path(), "smoothing", 0, str(tmp_path), out)
    finally:
        monkey.undo()
    verdicts = [json.loads(line)["verdict"] for line in out if "verdict" in line]
    assert verdicts == ["not applicable"] * len(area_checks("smoothing"))
