"""The test suite against sanitized builds of the library (slow; CI runs them through
the README's test command):

- AddressSanitizer + UndefinedBehaviorSanitizer: every test module but this one;
- ThreadSanitizer: the runtime, stress, pipeline and offline-machine tests (test_runtime.py,
  test_stress.py, test_pipeline.py: the stages side by side, test_machine*.py);

slow ones too, without the tests marked `harness`: they run the stages compiled into a
test harness without the sanitizer, never the sanitized library (under ASan they took
three quarters of the run, mostly in shapely's allocations through ASan's malloc).

Each library is built once per source state (CMake option SF_TCH_SANITIZE, into
pytest's cache directory; a fixture, so beside other tests), then a child pytest runs
with SF_TCH_LIBRARY naming it and the sanitizer's runtime preloaded (the interpreter
itself is not instrumented), in parallel as every run is (tests/conftest.py) and alone:
the tests are exclusive. The sanitizers write their reports to files (log_path), so
that a report from any process of the run, even one whose exit status a test ignores,
fails the test."""
import fcntl
import hashlib
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import sf_tch

# the time limit of a test: its library's build and its run (900 s each at most), and
# waiting for the other one, which may run on another worker meanwhile
pytestmark = [pytest.mark.slow, pytest.mark.exclusive, pytest.mark.timeout(3600)]

ROOT = Path(__file__).resolve().parents[1]
TSAN_SUPPRESSIONS = Path(__file__).resolve().parent / "tsan.supp"    # each one documented there


def sources_digest() -> str:
    digest = hashlib.sha256()
    files = sorted([*ROOT.glob("toolchain/**/*.pyx"), *ROOT.glob("toolchain/**/*.pxd"),
                    *ROOT.glob("include/*.h"), ROOT / "CMakeLists.txt"])
    for path in files:
        digest.update(str(path.relative_to(ROOT)).encode())
        digest.update(path.read_bytes())
    return digest.hexdigest()[:16]


def tool(name: str) -> str:
    """cmake / ninja of the test extra (next to the interpreter), else from PATH."""
    beside = Path(sys.executable).parent / name
    return str(beside) if beside.exists() else name


def build_library(cache_dir: Path, sanitize: str) -> Path:
    """The sanitized library of the current sources, built once: parallel test processes
    (test_alloc_failure's leak check beside this file's runs) wait on a file lock and
    take the same build."""
    kind = sanitize.replace(",", "-")
    with open(cache_dir / f"{kind}.lock", "a") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        try:
            return _build_library(cache_dir, sanitize, kind)
        finally:
            fcntl.flock(lock, fcntl.LOCK_UN)


def _build_library(cache_dir: Path, sanitize: str, kind: str) -> Path:
    build = cache_dir / f"{kind}-{sources_digest()}"
    library = build / "libSF_TCh.so"
    if library.exists():
        return library
    for stale in cache_dir.glob(f"{kind}-*"):     # builds of older sources
        shutil.rmtree(stale, ignore_errors=True)
    build.mkdir(parents=True, exist_ok=True)
    configure = [tool("cmake"), "-S", str(ROOT), "-B", str(build), "-G", "Ninja",
                 f"-DCMAKE_MAKE_PROGRAM={tool('ninja')}", f"-DPython_EXECUTABLE={sys.executable}",
                 "-DCMAKE_BUILD_TYPE=RelWithDebInfo", f"-DSF_TCH_SANITIZE={sanitize}"]
    # laid out as installed: the package's files beside the library
    package = Path(sf_tch.__file__).resolve().parent
    for name in ("data", "include"):
        if not (build / name).exists():
            (build / name).symlink_to(package / name, target_is_directory=True)
    for command in (configure, [tool("cmake"), "--build", str(build)]):
        proc = subprocess.run(command, capture_output=True, text=True, timeout=900)
        assert proc.returncode == 0, f"{' '.join(command)}\n{proc.stdout[-4000:]}\n{proc.stderr[-4000:]}"
    return library


def runtime(name: str) -> str:
    path = subprocess.run(["gcc", f"-print-file-name={name}"], capture_output=True, text=True).stdout.strip()
    if not os.path.isabs(path):
        pytest.skip(f"gcc does not know {name}")
    return path


@pytest.fixture(scope="module")
def cache_dir(request) -> Path:
    if os.environ.get("SF_TCH_LIBRARY"):
        pytest.skip("already running against the library that SF_TCH_LIBRARY names")
    return Path(request.config.cache.mkdir("sanitized-libraries"))


@pytest.fixture
def asan_library(cache_dir) -> Path:
    return build_library(cache_dir, "address,undefined")


@pytest.fixture
def tsan_library(cache_dir) -> Path:
    return build_library(cache_dir, "thread")


def run_suite(library: Path, preload: list[str], options: dict, tests: list[str], reports: Path,
              time_scale: int, timeout: float):
    env = dict(os.environ, SF_TCH_LIBRARY=str(library), LD_PRELOAD=" ".join(preload),
               SF_TCH_TIME_SCALE=str(time_scale), **options)
    command = [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "-m", "not harness",
               "--ignore", str(Path(__file__)),
               # the Windows tests build and run another binary (SF_TCh.dll under Wine), which the
               # preloaded sanitizer runtimes would only break
               "--ignore", str(ROOT / "tests" / "test_windows.py"),
               # nor do the fuzzer (clang's own ASan runtime) and Mono's host
               "--ignore", str(ROOT / "tests" / "test_fuzz.py"), "--ignore", str(ROOT / "tests" / "test_dotnet.py"),
               *tests]
    proc = subprocess.run(command, cwd=ROOT, env=env, capture_output=True, text=True, timeout=timeout)
    found = sorted(reports.parent.glob(reports.name + "*"))
    report_text = "\n".join(f"--- {path.name}\n{path.read_text(errors='replace')[:6000]}" for path in found[:5])
    assert not found, f"{len(found)} sanitizer report(s):\n{report_text}\n--- pytest\n{proc.stdout[-3000:]}"
    assert proc.returncode == 0, f"pytest under the sanitizer failed:\n{proc.stdout[-8000:]}\n{proc.stderr[-3000:]}"
    return proc.stdout


def test_suite_under_address_and_undefined_behaviour_sanitizers(asan_library, tmp_path):
    reports = tmp_path / "asan"
    options = {
        # CPython's own allocations are not freed at exit: leaks are not ours to judge
        "ASAN_OPTIONS": f"detect_leaks=0:halt_on_error=1:abort_on_error=0:log_path={reports}",
        "UBSAN_OPTIONS": f"halt_on_error=1:print_stacktrace=1:log_path={reports}",
    }
    out = run_suite(asan_library, [runtime("libasan.so"), runtime("libubsan.so")], options, ["tests"], reports,
                    time_scale=3, timeout=900)
    assert " passed" in out, out[-2000:]


def test_runtime_and_stress_under_thread_sanitizer(tsan_library, tmp_path):
    reports = tmp_path / "tsan"
    # the uninstrumented interpreter's memory accesses are invisible to TSan and its locks
    # are the intercepted pthread ones: the suppressions are for glibc only
    options = {"TSAN_OPTIONS": f"halt_on_error=1:second_deadlock_stack=1:suppressions={TSAN_SUPPRESSIONS}"
                               f":log_path={reports}"}
    out = run_suite(tsan_library, [runtime("libtsan.so")], options,
                    ["tests/test_runtime.py", "tests/test_stress.py", "tests/test_pipeline.py", "tests/test_machine.py",
                     "tests/test_machine_connect.py", "tests/test_machine_corrections.py"], reports, time_scale=6,
                    timeout=900)
    assert " passed" in out, out[-2000:]
