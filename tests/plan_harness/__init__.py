"""The test-only plan_harness module: the library's stages + Python entry points to
the feed planner, built into a temporary directory (harness_build.py)."""
from pathlib import Path

from harness_build import build_harness


def build(tmp: Path, opt: str = "-O1"):
    return build_harness(Path(__file__).with_name("plan_harness.pyx"), tmp, opt)
