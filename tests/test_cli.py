"""The README's main job: `sf-tch demo` on the bundled sample, and `sf-tch info`."""
import re
import subprocess
import sys

import pytest


def sf_tch(*args):
    return subprocess.run([sys.executable, "-m", "sf_tch.cli", *args], capture_output=True, text=True,
                          timeout=120)


def test_demo_compiles_compensates_and_simulates_the_sample():
    proc = sf_tch("demo")
    assert proc.returncode == 0, proc.stderr
    out = proc.stdout
    assert re.search(r"parts:\s+28 motion, 16 M functions", out)
    # the outline is cut outside (G42) with the default 1 mm radius
    box = re.search(r"box compensated:\s+X (\S+)\.\.(\S+)\s+Y (\S+)\.\.(\S+)", out)
    assert [float(v) for v in box.groups()] == pytest.approx([-1.0, 121.0, -8.0, 81.0])
    assert "PRINT:         plate done" in out
    assert re.search(r"run time:\s+\d+\.\d+ s", out)
    assert "errors:        none" in out


def test_demo_reports_a_tool_too_big_for_the_slot_with_its_line(tmp_path):
    proc = sf_tch("demo", "--radius", "6")
    assert proc.returncode == 1
    assert re.search(r"demo\.nc:28: error 503: Arc radius 5 smaller than the tool radius 6", proc.stderr)


def test_demo_of_a_user_program(tmp_path):
    program = tmp_path / "square.nc"
    program.write_text("G0 X0 Y0\nG1 X10 F600\nG1 Y10\nG1 X0\nG1 Y0\nM30\n")
    proc = sf_tch("demo", str(program))
    assert proc.returncode == 0, proc.stderr
    assert re.search(r"cut length:\s+40\.000 mm in 4 parts", proc.stdout)


def test_info_prints_version_cores_and_matching_sizes():
    proc = sf_tch("info")
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.startswith("SF_TCh ")
    assert "cores:   3" in proc.stdout
    assert "MISMATCH" not in proc.stdout
    assert re.search(r"SIMPLE_GM_PARAMS\s+616 / 616", proc.stdout)


def test_a_cnc_error_propagates_through_a_with_block():
    from sf_tch.core import CncError, Core
    with pytest.raises(CncError) as caught:
        with Core(0) as core:
            core.compile_text("G1 X1/0\n", "bad.nc")
    assert caught.value.number == 200 and caught.value.line == 1
