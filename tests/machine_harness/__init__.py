"""The test-only machine_harness module: the library's stages + Python entry points
that run the offline machine's step (toolchain/machine/motion.pyx) on a compiled
program without its threads, built into a temporary directory (harness_build.py)."""
from pathlib import Path

from harness_build import build_harness


def build(tmp: Path):
    return build_harness(Path(__file__).with_name("machine_harness.pyx"), tmp)
