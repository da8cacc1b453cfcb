"""The repository stands alone: its licence is the one pyproject.toml names, the C
example's README and the README's C example build and run as written, and what builds
and examples leave in the checkout is ignored by git."""
import re
import shutil
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def test_the_licence_is_the_one_pyproject_names():
    licence = (ROOT / "LICENSE").read_text()
    assert licence.startswith("MIT License\n\nCopyright (c) 2026 the SF_TCh authors\n")
    assert "THE SOFTWARE IS PROVIDED \"AS IS\", WITHOUT WARRANTY OF ANY KIND" in licence
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    assert project["license"] == {"text": "MIT"}


def test_build_outputs_are_ignored():
    if not (ROOT / ".git").exists() or shutil.which("git") is None:
        pytest.skip("not a git checkout")
    outputs = ["wheelhouse/sf_tch-0.1.0-py3-none-manylinux_2_17_x86_64.whl", "dist/sf_tch-0.1.0.tar.gz",
               "build/libSF_TCh.so", "examples/c_hmi/c_hmi", "c_hmi", "program.png", ".venv/bin/python"]
    for output in outputs:
        proc = subprocess.run(["git", "check-ignore", "-q", output], cwd=ROOT)
        assert proc.returncode == 0, f"{output} is not ignored"
    # the sources of the examples are not
    assert subprocess.run(["git", "check-ignore", "-q", "examples/c_hmi/c_hmi.c"], cwd=ROOT).returncode == 1


def test_the_c_examples_readme_builds_and_runs_it(tmp_path):
    if shutil.which("cc") is None:
        pytest.skip("no C compiler")
    readme = (ROOT / "examples" / "c_hmi" / "README.md").read_text()
    build, run = re.findall(r"```bash\n(.*?)```", readme, re.S)
    # as written, but the program built outside the source tree and this interpreter for the venv's
    exe = str(tmp_path / "c_hmi")
    build = build.replace("examples/c_hmi/c_hmi ", f"{exe} ")
    run = run.replace("examples/c_hmi/c_hmi ", f"{exe} ").replace(".venv/bin/python", sys.executable)
    subprocess.run(["bash", "-ec", build], cwd=ROOT, check=True, timeout=120)
    proc = subprocess.run(["bash", "-ec", run], cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert [line for line in proc.stdout.splitlines() if line.startswith("core ")] == ["core 0", "core 1", "core 2"]
    assert proc.stdout.count("errors:        none") == 3 and proc.stdout.count("PRINT:         plate done") == 3
    assert re.fullmatch(r"c_hmi: 3 threads polled StatusCNC \+ GetPos \d+ times\n", proc.stderr)


def test_the_readmes_c_example_builds_and_runs(tmp_path):
    """The README's "From C": part.c as printed, built and run by the commands under it
    (the venv's interpreter this one), linked against the installed library."""
    if shutil.which("cc") is None:
        pytest.skip("no C compiler")
    readme = (ROOT / "README.md").read_text()
    section = readme[readme.index("### From C"):]
    source = re.search(r"```c\n(.*?)```", section, re.S).group(1)
    commands = re.search(r"```bash\n(.*?)```", section, re.S).group(1)
    (tmp_path / "part.c").write_text(source)
    commands = commands.replace(".venv/bin/python", sys.executable).replace("-I include", f"-I {ROOT / 'include'}")
    proc = subprocess.run(["bash", "-ec", commands], cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout == "compiled\n"
    # a program with an error: its line, number and text, exit 1
    (tmp_path / "bad.nc").write_text("G1 X10 Y10 F1000\nG1 X1/0\n")
    proc = subprocess.run([str(tmp_path / "part"), str(tmp_path / "bad.nc")], capture_output=True, text=True,
                          timeout=60)
    assert (proc.returncode, proc.stdout) == (1, "line 2: error 200: Division by zero\n")
