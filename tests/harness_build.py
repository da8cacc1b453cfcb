"""Builds a test-only Cython module that includes the library's stages
(toolchain/libSF_TCh.pyx) and adds Python entry points to one of them
(tests/comp_harness, tests/plan_harness), into a temporary directory, and imports it."""
import importlib.util
import os
import subprocess
import sys
import sysconfig
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def build_harness(pyx: Path, tmp: Path, opt: str = "-O1"):
    name = pyx.stem
    c_file = tmp / f"{name}.c"
    so = tmp / f"{name}{sysconfig.get_config_var('EXT_SUFFIX')}"
    subprocess.run([sys.executable, "-m", "cython", "-3", "--fast-fail",
                    "-I", str(ROOT / "toolchain"), "-I", str(ROOT / "include"),
                    str(pyx), "-o", str(c_file)], check=True)
    cc = os.environ.get("CC", "gcc")
    subprocess.run([cc, *opt.split(), "-shared", "-fPIC", "-w", "-I", str(ROOT / "include"),
                    "-I", str(ROOT / "toolchain" / "includes"),
                    "-I", sysconfig.get_paths()["include"], str(c_file), "-o", str(so),
                    "-lpthread", "-lm"], check=True)
    spec = importlib.util.spec_from_file_location(name, so)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module
