"""The test-only module `stages` (stages.pyx: the library's stages with Python entry
points into the geometry, the compensation, the planner, the connection search and
the offline machine), built once per source state and shared by every test process.

The build is cached under $SF_TCH_HARNESS_CACHE, else $XDG_CACHE_HOME/sf_tch-harness
(~/.cache/sf_tch-harness), in a directory named by a hash of toolchain/, include/,
this directory's sources, the Python version, the C compiler and the optimisation.
A file lock makes parallel test processes (pytest-xdist workers) build it once:
the others wait and load the same file. Builds unused for a week are removed."""
import fcntl
import hashlib
import importlib.util
import os
import shutil
import subprocess
import sys
import sysconfig
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]
STALE_SECONDS = 7 * 24 * 3600
_loaded = {}


def cache_dir() -> Path:
    if os.environ.get("SF_TCH_HARNESS_CACHE"):
        return Path(os.environ["SF_TCH_HARNESS_CACHE"])
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "sf_tch-harness"


def source_key(opt: str) -> str:
    digest = hashlib.sha256()
    sources = sorted([*ROOT.glob("toolchain/**/*.pyx"), *ROOT.glob("toolchain/**/*.pxd"),
                      *ROOT.glob("toolchain/**/*.pxi"), *ROOT.glob("toolchain/**/*.h"),
                      *ROOT.glob("include/*.h"), *HERE.glob("*.py*")])
    for path in sources:
        digest.update(str(path.relative_to(ROOT)).encode())
        digest.update(path.read_bytes())
    for part in (sys.version, sysconfig.get_config_var("EXT_SUFFIX"), os.environ.get("CC", "gcc"), opt):
        digest.update(part.encode())
    return digest.hexdigest()[:20]


def _build(target: Path, opt: str) -> None:
    """Cython and the C compiler in a scratch directory beside `target`, which then
    appears whole (a rename)."""
    scratch = Path(tempfile.mkdtemp(prefix="build-", dir=target.parent))
    try:
        c_file = scratch / "stages.c"
        subprocess.run([sys.executable, "-m", "cython", "-3", "--fast-fail",
                        "-I", str(ROOT / "toolchain"), "-I", str(ROOT / "include"),
                        str(HERE / "stages.pyx"), "-o", str(c_file)], check=True)
        so = scratch / f"stages{sysconfig.get_config_var('EXT_SUFFIX')}"
        subprocess.run([os.environ.get("CC", "gcc"), *opt.split(), "-shared", "-fPIC", "-w",
                        "-I", str(ROOT / "include"), "-I", str(ROOT / "toolchain" / "includes"),
                        "-I", sysconfig.get_paths()["include"], str(c_file), "-o", str(so), "-lpthread", "-lm"], check=True)
        c_file.unlink()
        scratch.rename(target)
    finally:
        shutil.rmtree(scratch, ignore_errors=True)


def _remove_stale(cache: Path, keep: Path) -> None:
    now = time.time()
    for entry in cache.iterdir():
        if entry != keep and entry.is_dir() and now - entry.stat().st_mtime > STALE_SECONDS:
            shutil.rmtree(entry, ignore_errors=True)
            Path(f"{entry}.lock").unlink(missing_ok=True)


def built(opt: str = "-O1") -> Path:
    """The module's file for the sources as they are now (at C optimisation `opt`),
    built first if no process has built it yet; a process that finds another one
    building it waits for that build."""
    cache = cache_dir()
    cache.mkdir(parents=True, exist_ok=True)
    target = cache / source_key(opt)
    with open(cache / f"{target.name}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if not target.exists():
            _build(target, opt)
            _remove_stale(cache, target)
        os.utime(target)                # in use: not stale
    return target / f"stages{sysconfig.get_config_var('EXT_SUFFIX')}"


def load(opt: str = "-O1"):
    """The module `stages` (built(opt)), imported once per process."""
    if opt not in _loaded:
        spec = importlib.util.spec_from_file_location("stages", built(opt))
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
        _loaded[opt] = module
    return _loaded[opt]
