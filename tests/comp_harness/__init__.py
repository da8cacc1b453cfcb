"""The test-only comp_harness module: the library's stages + a Python entry point to
compensate_program, built into a temporary directory (harness_build.py)."""
from pathlib import Path

from harness_build import build_harness


def build(tmp: Path):
    return build_harness(Path(__file__).with_name("comp_harness.pyx"), tmp)
