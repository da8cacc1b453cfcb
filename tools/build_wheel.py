"""Builds the wheel to distribute: ``wheelhouse/sf_tch-<version>-py3-none-manylinux_2_17_x86_64.whl``.

    python tools/build_wheel.py [--glibc 2.17] [--out wheelhouse]

Run it with the interpreter of a venv that has the ``wheel`` extra (``pip install
'.[wheel]'``; the ``test`` extra includes it). A wheel's platform tag is the newest
glibc symbol version its library uses, so the library is compiled here by Zig's C
compiler (the PyPI package ``ziglang``) against the symbol versions of glibc 2.17
(``-target x86_64-linux-gnu.2.17``) instead of the build machine's: GCC on a glibc
2.36 system links hypot@GLIBC_2.35, pthread_create/join/once@2.34, fstat64@2.33 and
pow/log@2.29, and such a wheel installs only on systems as new. Then ``pip wheel``
(scikit-build-core, CMake) and ``auditwheel repair`` check and tag it; the library
needs no shared object beyond glibc, so nothing is grafted and auditwheel runs
without patchelf (``--patcher none``). Prints the wheel's path.
"""
import argparse
import os
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def zig_cc(glibc: str) -> str:
    """The C compiler command that targets x86_64 Linux with that glibc's symbols."""
    try:
        import ziglang
    except ImportError:
        sys.exit(f"build_wheel: needs Zig's C compiler: {sys.executable} -m pip install '.[wheel]'")
    zig = Path(ziglang.__file__).resolve().parent / "zig"
    return f"{zig} cc -target x86_64-linux-gnu.{glibc}"


def build(out: Path, glibc: str) -> Path:
    """Builds, repairs and returns the manylinux wheel in `out`."""
    out.mkdir(parents=True, exist_ok=True)
    # the version string has the build's date and time (__DATE__): Zig warns, as an error, that it is not reproducible
    env = dict(os.environ, CC=zig_cc(glibc), CFLAGS=(os.environ.get("CFLAGS", "") + " -Wno-date-time").strip())
    with tempfile.TemporaryDirectory(prefix="sf_tch_wheel_") as tmp:
        dist = Path(tmp)
        subprocess.run([sys.executable, "-m", "pip", "wheel", "-q", "--no-deps", "-w", str(dist), str(ROOT)],
                       check=True, env=env)
        (built,) = dist.glob("*.whl")
        subprocess.run([sys.executable, "-m", "auditwheel", "repair", "--patcher", "none", "-w", str(out),
                        str(built)], check=True)
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
