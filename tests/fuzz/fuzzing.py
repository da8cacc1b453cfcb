"""Coverage-guided fuzzing of the library with libFuzzer (clang): the compiler in TG's
dialect and in the ISO mode, the TAB0.KOR and ACHS3D??.KOR readers and the INI reader.

The target is the library's sources (fuzz_entry.pyx: every stage, and a synchronous
compilation) with fuzz_main.c, built by clang with
-fsanitize=fuzzer,address,undefined,float-cast-overflow into build-fuzz/ (once per
state of the sources). Each target starts from seeds made of the repository's programs
and files (seeds()) and grows its corpus in tests/fuzz/corpus/<target> (ignored by git).

By hand (docs/testing.md, "Fuzzing"):

    python tests/fuzz/fuzzing.py TARGET [SECONDS] [libFuzzer options...]

builds the target if need be and fuzzes TARGET (tg, iso, tool_table, axis_table, ini)
for SECONDS (default 600); a crash leaves its input in build-fuzz/artifacts/."""
import ast
import fcntl
import hashlib
import os
import re
import shutil
import subprocess
import sys
import sysconfig
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]
TESTS = HERE.parent
BUILD = ROOT / "build-fuzz"
CORPUS = HERE / "corpus"
TARGETS = ("tg", "iso", "tool_table", "axis_table", "ini")
SANITIZERS = "fuzzer,address,undefined,float-cast-overflow"
MAX_LEN = 16384                 # bytes of one input (the seeds' largest fit)


class Unavailable(Exception):
    """No clang with libFuzzer here: the reason."""


def clang() -> str:
    """A clang that links -fsanitize=fuzzer,address,undefined programs."""
    candidates = [os.environ.get("CC_FUZZ"), "clang", *(f"clang-{v}" for v in range(20, 13, -1))]
    found = [c for c in candidates if c and shutil.which(c)]
    if not found:
        raise Unavailable("no clang on PATH (Debian: apt-get install clang libclang-rt-14-dev)")
    with tempfile.TemporaryDirectory() as scratch:
        probe = Path(scratch) / "probe.c"
        probe.write_text("#include <stdint.h>\n#include <stddef.h>\n"
                         "int LLVMFuzzerTestOneInput(const uint8_t *d, size_t n) { return 0; }\n")
        for cc in found:
            proc = subprocess.run([cc, f"-fsanitize={SANITIZERS}", str(probe), "-o", str(Path(scratch) / "probe")],
                                  capture_output=True, text=True)
            if proc.returncode == 0:
                return cc
    raise Unavailable(f"{found[0]} cannot link -fsanitize={SANITIZERS} (Debian: apt-get install "
                      f"libclang-rt-14-dev, the runtime of clang 14): {proc.stderr.strip()[-300:]}")


def _digest(cc: str) -> str:
    digest = hashlib.sha256()
    for path in sorted([*ROOT.glob("toolchain/**/*.pyx"), *ROOT.glob("toolchain/**/*.pxd"),
                        *ROOT.glob("toolchain/**/*.pxi"), *ROOT.glob("toolchain/**/*.h"),
                        *ROOT.glob("include/*.h"), *HERE.glob("fuzz_*")]):
        digest.update(str(path.relative_to(ROOT)).encode())
        digest.update(path.read_bytes())
    digest.update(cc.encode())
    return digest.hexdigest()[:16]


def _python_link() -> list[str]:
    """The linker's arguments for this interpreter's libpython (shared, else static)."""
    var = sysconfig.get_config_var
    if var("Py_ENABLE_SHARED"):
        return [f"-L{var('LIBDIR')}", f"-lpython{var('LDVERSION')}", f"-Wl,-rpath,{var('LIBDIR')}"]
    return [str(Path(var("LIBPL")) / var("LIBRARY")), *(var("LIBS") or "").split(), *(var("SYSLIBS") or "").split()]


def build(log=print) -> Path:
    """The fuzz target for the sources as they are now (built first: a few minutes;
    parallel test processes wait for one build under a file lock)."""
    cc = clang()
    target = BUILD / f"fuzz-{_digest(cc)}"
    BUILD.mkdir(exist_ok=True)
    with open(BUILD / "build.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if not target.exists():
            _build(cc, target, log)
    return target


def _build(cc: str, target: Path, log) -> None:
    c_file = BUILD / "fuzz_entry.c"
    log(f"fuzzing: building {target.name} with {cc}")
    subprocess.run([sys.executable, "-m", "cython", "-3", "--fast-fail", "-I", str(ROOT / "toolchain"),
                    "-I", str(ROOT / "include"), str(HERE / "fuzz_entry.pyx"), "-o", str(c_file)],
                   check=True, capture_output=True, text=True)
    scratch = BUILD / "building"
    # The Cython module's own code (PyInit and what only it reaches) references libpython;
    # it never runs, but the link needs the interpreter's library.
    proc = subprocess.run([cc, "-O1", "-g", f"-fsanitize={SANITIZERS}", "-fno-sanitize-recover=all", "-w",
                           "-I", str(ROOT / "include"), "-I", str(ROOT / "toolchain" / "includes"),
                           "-I", sysconfig.get_paths()["include"], str(c_file), str(HERE / "fuzz_main.c"),
                           "-o", str(scratch), *_python_link(), "-lm", "-lpthread"],
                          capture_output=True, text=True)
    if proc.returncode != 0:
        raise RuntimeError(f"building the fuzz target failed:\n{proc.stderr[-4000:]}")
    for stale in BUILD.glob("fuzz-*"):
        stale.unlink()
    scratch.rename(target)
    c_file.unlink()


# ------------------------------------------------------------------ seeds

def _test_strings(pattern: str) -> list[str]:
    """Every string constant of the test modules that matches `pattern` (a regex)."""
    found = []
    for path in sorted(TESTS.glob("*.py")):
        try:
            tree = ast.parse(path.read_text())
        except SyntaxError:
            continue
        for node in ast.walk(tree):
            if isinstance(node, ast.Constant) and isinstance(node.value, (str, bytes)):
                text = node.value if isinstance(node.value, str) else node.value.decode("latin-1")
                if re.search(pattern, text) and len(text) <= MAX_LEN:
                    found.append(text)
    return found


def _programs() -> list[bytes]:
    sys.path.insert(0, str(TESTS))
    import cam_corpus
    programs = [(ROOT / "python" / "sf_tch" / "data" / "demo.nc").read_bytes()]
    programs += [p.read_bytes() for p in sorted((TESTS / "comp_repro").glob("*.nc"))]
    programs += [text.encode("latin-1", "replace") for _, _, text, _ in cam_corpus.corpus(1)]
    programs += [t.encode("latin-1", "replace") for t in _test_strings(r"(?i)\b[GM]\d+[^\n]*[XYZFIJ]-?[\d.]|\bo\d+ ")]
    return [p[:MAX_LEN] for p in programs]


def _axis_tables() -> list[bytes]:
    import struct
    tables = []
    for letters, definition in (("ZXY", ((0, 10, 3), (0, 20, 5))), ("X", ((0, 100, 11),)),
                                ("zxyc", ((-5, 5, 2), (0, 1, 2), (0, 360, 4))), ("YY", ((0, 50, 51),))):
        count = 1
        for _, _, n in definition:
            count *= n
        header = letters.encode() + b"\0"
        header = header.ljust(127, b"\0") + bytes([1])
        block = b"".join(struct.pack("<ffI", lo, hi, n) for lo, hi, n in definition)
        tables.append(header + block + struct.pack(f"<{count}f", *(0.001 * k for k in range(count))))
    return tables


def seeds(target: str) -> list[bytes]:
    """The repository's inputs for `target`: programs (the sample, the compensation
    reproducers, the CAM corpus's styles, every program text in the tests), the tool
    tables, axis tables and INI texts of the tests and the package."""
    if target in ("tg", "iso"):
        return _programs()
    if target == "tool_table":
        return [t.encode("latin-1", "replace") for t in _test_strings(r"\$KOR")]
    if target == "axis_table":
        return _axis_tables()
    inis = [(ROOT / "python" / "sf_tch" / "data" / "SF_TCh.ini").read_bytes()]
    return inis + [t.encode("latin-1", "replace") for t in _test_strings(r"(?m)^\s*\[[A-Za-z]+\]\s*$")]


def run(target: str, seconds: int, extra=(), binary: Path | None = None, log=print,
        corpus: Path | None = None) -> subprocess.CompletedProcess:
    """Fuzzes `target` for `seconds` (after a pass over the corpus, which libFuzzer does
    not count) from its corpus and its seeds; the corpus grows in `corpus`, by default
    tests/fuzz/corpus/<target>; crashes go to build-fuzz/artifacts/."""
    binary = binary or build(log)
    corpus = corpus or CORPUS / target
    corpus.mkdir(parents=True, exist_ok=True)
    artifacts = BUILD / "artifacts"
    artifacts.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as scratch:
        seed_dir = Path(scratch)
        for k, data in enumerate(seeds(target)):
            (seed_dir / f"seed{k:04d}").write_bytes(data)
        env = dict(os.environ, SF_TCH_FUZZ_TARGET=target,
                   ASAN_OPTIONS="detect_leaks=1:allocator_may_return_null=1",
                   UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1")
        command = [str(binary), f"-max_total_time={seconds}", "-timeout=10", f"-max_len={MAX_LEN}",
                   "-rss_limit_mb=4096", "-malloc_limit_mb=2048", "-print_final_stats=1",
                   f"-artifact_prefix={artifacts}/{target}-", *extra, str(corpus), str(seed_dir)]
        return subprocess.run(command, env=env, capture_output=True, text=True, timeout=seconds + 600)


def stats(output: str) -> dict:
    """libFuzzer's final figures (-print_final_stats) and its last coverage line."""
    out = {k: int(v) for k, v in re.findall(r"stat::(\w+):\s+(\d+)", output)}
    last = re.findall(r"#(\d+)\s+\w+\s+cov: (\d+) ft: (\d+) corp: (\d+)", output)
    if last:
        out.update(dict(zip(("inputs", "cov", "ft", "corpus"), map(int, last[-1]))))
    return out


def main(argv):
    if not argv or argv[0] not in TARGETS:
        print(__doc__)
        return 2
    seconds = int(argv[1]) if len(argv) > 1 else 600
    proc = run(argv[0], seconds, argv[2:])
    sys.stderr.write(proc.stderr[-20000:])
    print(stats(proc.stderr))
    return proc.returncode


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
