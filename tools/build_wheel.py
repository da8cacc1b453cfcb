"""Builds the wheel to distribute: ``wheelhouse/sf_tch-<version>-py3-none-manylinux_2_17_x86_64.whl``.

    python tools/build_wheel.py [--glibc 2.17] [--out wheelhouse]

Run it with the interpreter of the README's venv (``.venv/bin/python
tools/build_wheel.py``), or any Python >= 3.9 with pip. Its two tools are the ``wheel``
extra (the ``test`` extra includes it): where the interpreter lacks them, they are
installed once into ``build/wheel-tools/`` of the checkout (not into the venv, and the
installed package is not built again). A wheel's platform tag is the newest
glibc symbol version its library uses, so the library is compiled here by Zig's C
compiler (the PyPI package ``ziglang``) against the symbol versions of glibc 2.17
(``-target x86_64-linux-gnu.2.17``) instead of the build machine's: GCC on a glibc
2.36 system links hypot@GLIBC_2.35, pthread_create/join/once@2.34, fstat64@2.33 and
pow/log@2.29, and such a wheel installs only on systems as new. Then ``pip wheel``
(scikit-build-core, CMake) and ``auditwheel repair`` check and tag it; the library
needs no shared object beyond glibc, so nothing is grafted and auditwheel runs
without patchelf (``--patcher none``). The library is built in a build directory of
its own (the one ``pip install .`` keeps in ``build/`` has the system's compiler).
Prints the wheel's path.
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
TOOLS = ROOT / "build" / "wheel-tools"      # the wheel extra, when this interpreter lacks it


def wheel_extra() -> list:
    """The requirements of pyproject.toml's ``wheel`` extra (read without tomllib,
    which CPython 3.9 and 3.10 lack)."""
    text = (ROOT / "pyproject.toml").read_text()
    match = re.search(r"^wheel\s*=\s*\[([^\]]*)\]", text, re.M)
    return re.findall(r'"([^"]+)"', match.group(1)) if match else ["ziglang", "auditwheel"]


def tool_environment() -> dict:
    """The environment in which ziglang and auditwheel import: this interpreter's, or
    with build/wheel-tools/ on PYTHONPATH, installed there first when missing."""
    env = dict(os.environ)
    probe = [sys.executable, "-c", "import ziglang, auditwheel"]
    if subprocess.run(probe, capture_output=True).returncode == 0:
        return env
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(TOOLS), env.get("PYTHONPATH")]))
    if subprocess.run(probe, capture_output=True, env=env).returncode != 0:
        print(f"build_wheel: installing the wheel extra ({', '.join(wheel_extra())}) into {TOOLS}", file=sys.stderr,
              flush=True)
        subprocess.run([sys.executable, "-m", "pip", "install", "-q", "--upgrade", "--target", str(TOOLS),
                        *wheel_extra()], check=True)
    return env


def zig_cc(glibc: str, env: dict) -> str:
    """The C compiler command that targets x86_64 Linux with that glibc's symbols."""
    where = subprocess.run([sys.executable, "-c", "import ziglang; print(ziglang.__file__)"], env=env,
                           capture_output=True, text=True, check=True).stdout.strip()
    zig = Path(where).resolve().parent / "zig"
    return f"{zig} cc -target x86_64-linux-gnu.{glibc}"


def build(out: Path, glibc: str) -> Path:
    """Builds, repairs and returns the manylinux wheel in `out`."""
    out.mkdir(parents=True, exist_ok=True)
    tools = tool_environment()
    # the version string has the build's date and time (__DATE__): Zig warns, as an error, that it is not reproducible
    env = dict(os.environ, CC=zig_cc(glibc, tools), CFLAGS=(os.environ.get("CFLAGS", "") + " -Wno-date-time").strip())
    with tempfile.TemporaryDirectory(prefix="sf_tch_wheel_") as tmp:
        dist = Path(tmp) / "dist"
        print("build_wheel: building the library with Zig's C compiler (pip wheel) ...", file=sys.stderr, flush=True)
        subprocess.run([sys.executable, "-m", "pip", "wheel", "-q", "--no-deps", "-w", str(dist),
                        "--config-settings", f"build-dir={Path(tmp) / 'build'}", str(ROOT)], check=True, env=env)
        (built,) = dist.glob("*.whl")
        subprocess.run([sys.executable, "-m", "auditwheel", "repair", "--patcher", "none", "-w", str(out),
                        str(built)], check=True, env=tools)
    name, version = built.name.split("-")[:2]
    return max(out.glob(f"{name}-{version}-py3-none-manylinux*.whl"), key=lambda wheel: wheel.stat().st_mtime)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--glibc", default="2.17", help="the oldest glibc the wheel runs on (default 2.17)")
    parser.add_argument("--out", type=Path, default=ROOT / "wheelhouse", help="where the wheel goes")
    args = parser.parse_args()
    print(build(args.out, args.glibc))
    return 0


if __name__ == "__main__":
    sys.exit(main())
