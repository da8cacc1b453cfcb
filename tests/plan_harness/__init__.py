"""Builds the test-only plan_harness module (the library's stages + Python entry
points to the feed planner) into a temporary directory and imports it."""
import importlib.util
import os
import subprocess
import sys
import sysconfig
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def build(tmp: Path, opt: str = "-O1"):
    src = Path(__file__).with_name("plan_harness.pyx")
    c_file = tmp / "plan_harness.c"
    ext = sysconfig.get_config_var("EXT_SUFFIX")
    so = tmp / f"plan_harness{ext}"
    subprocess.run([sys.executable, "-m", "cython", "-3", "--fast-fail",
                    "-I", str(ROOT / "toolchain"), "-I", str(ROOT / "include"),
                    str(src), "-o", str(c_file)], check=True)
    cc = os.environ.get("CC", "gcc")
    subprocess.run([cc, *opt.split(), "-shared", "-fPIC", "-w", "-I", str(ROOT / "include"),
                    "-I", sysconfig.get_paths()["include"], str(c_file), "-o", str(so),
                    "-lpthread", "-lm"], check=True)
    spec = importlib.util.spec_from_file_location("plan_harness", so)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod
