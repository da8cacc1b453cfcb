"""The test-only connect_harness module: the library's stages + Python entry points
to the connection search of ConnectCNCEx_Plane (toolchain/machine/connect_search.pyx),
built into a temporary directory (harness_build.py)."""
from pathlib import Path

from harness_build import build_harness


def build(tmp: Path, opt: str = "-O1"):
    return build_harness(Path(__file__).with_name("connect_harness.pyx"), tmp, opt)
