"""Builds the test-only comp_harness module (the library's stages + a Python entry
point to compensate_program) into a temporary directory and imports it."""
import importlib.util
import os
import subprocess
import sys
import sysconfig
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def build(tmp: Path):
    src = Path(__file__).with_name("comp_harness.pyx")
    c_file = tmp / "comp_harness.c"
    ext = sysconfig.get_config_var("EXT_SUFFIX")
    so = tmp / f"comp_harness{ext}"
    subprocess.run([sys.executable, "-m", "cython", "-3", "--fast-fail",
                    "-I", str(ROOT / "toolchain"), "-I", str(ROOT / "include"),
                    str(src), "-o", str(c_file)], check=True)
    cc = os.environ.get("CC", "gcc")
    subprocess.run([cc, "-O1", "-shared", "-fPIC", "-w", "-I", str(ROOT / "include"),
                    "-I", sysconfig.get_paths()["include"], str(c_file), "-o", str(so),
                    "-lpthread", "-lm"], check=True)
    spec = importlib.util.spec_from_file_location("comp_harness", so)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod
