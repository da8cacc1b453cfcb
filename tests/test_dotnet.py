""".NET panels: the C# binding examples/dotnet/SfTch.cs and its panel Panel.cs, compiled
with Mono's mcs (warnings as errors) and run by mono against the Linux library.

The panel checks every Marshal.SizeOf against ToolChainCore_GetStructuresSize at
start-up, compiles the demo, reads an error (IntPtr texts read explicitly), simulates
with guarded callbacks whose delegates are kept while the garbage collector runs,
survives a callback that throws, runs the offline machine while it polls GetPos, and
destroys the cores. Its numbers are compared with the Python package's on the same
program. Skipped, saying why, where mcs or mono is not installed (.ci/run installs
Debian's mono-mcs and mono-runtime).
"""
import os
import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

from sf_tch import CncError
from sf_tch.core import Core

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "examples" / "dotnet"
DATA = ROOT / "python" / "sf_tch" / "data"


@pytest.fixture(scope="module")
def dotnet_report(lib_path, tmp_path_factory):
    mcs, mono = shutil.which("mcs"), shutil.which("mono")
    if mcs is None or mono is None:
        pytest.skip("Mono is not installed (apt-get install --no-install-recommends mono-mcs mono-runtime): "
                    "the C# binding is not tested")
    run = tmp_path_factory.mktemp("dotnet")
    build = subprocess.run([mcs, "-warnaserror", "-out:" + str(run / "panel.exe"), str(EXAMPLE / "SfTch.cs"),
                            str(EXAMPLE / "Panel.cs")], capture_output=True, text=True, timeout=300)
    assert build.returncode == 0, build.stdout + build.stderr
    # the binding imports "SF_TCh": Mono finds libSF_TCh.so beside the program
    shutil.copy(lib_path, run / "libSF_TCh.so")
    for name in ("SF_TCh.ini", "demo.nc"):
        shutil.copy(DATA / name, run / name)
    env = {k: v for k, v in os.environ.items() if k != "LD_PRELOAD"}
    proc = subprocess.run([mono, "panel.exe"], cwd=run, capture_output=True, timeout=300, env=env)
    assert proc.returncode == 0, proc.stdout.decode(errors="replace")[-3000:] + proc.stderr.decode(errors="replace")
    return proc.stdout.decode()


def field(report: str, pattern: str) -> re.Match:
    match = re.search(pattern, report, re.M)
    assert match, f"{pattern!r} not in the report:\n{report}"
    return match


def test_the_binding_checks_its_structures_against_the_library(dotnet_report):
    assert "structure sizes: 8 1112 616 112 32 1280 52 448 32, checked" in dotnet_report
    assert "pointer size: 8" in dotnet_report
    assert re.search(r"^version: SF_TCh \d", dotnet_report, re.M)


def test_compile_error_simulation_and_machine_run_agree_with_the_package(dotnet_report):
    with Core() as core:
        core.set_tool_radius(1.0)
        core.update_params(calcTime=1)
        core.compile_file(str(DATA / "demo.nc"))
        result = core.simulate()
        with pytest.raises(CncError) as error:
            core.compile_text("G90\nG1 X10 Y5 F500\nG999 X5\nM2\n", name="chyba_řádek.nc")
    parts = result.parts
    cut = float(np.sum(parts["m_pars"]["N"][parts["m_func"] != 0].astype(float)))
    rapid = float(np.sum(parts["m_pars"]["N"][parts["m_func"] == 0].astype(float)))

    assert "== compile\nload: 0, cores 3\nparameters: 0\ncompile: 0, status -1\n" in dotnet_report
    # the error through GetLastError (IntPtr texts, read as UTF-8 on Linux) and DispAndLocateError
    m = field(dotnet_report, r"^error: (\d+) line (\d+) file (\S+): (.*)$")
    assert (int(m[1]), int(m[2]), m[3]) == (int(error.value.number), error.value.line, "chyba_řádek.nc")
    assert m[4].startswith("Unknown G function G999")
    assert field(dotnet_report, r"^DispAndLocateError: (\d+), line 3: Unknown G function G999")[1] == "1"

    m = field(dotnet_report, r"^== simulation with callbacks\nsimulation: 0\nstatus: -10\n"
                             r"motion parts: (\d+), cut (\S+) mm, rapid (\S+) mm, M (\d+)$")
    assert int(m[1]) == len(parts) > 0 and int(m[4]) == len(result.m_functions)
    assert float(m[2]) == pytest.approx(cut, rel=1e-12) and float(m[3]) == pytest.approx(rapid, rel=1e-12)
    assert "initialize 1, end 1, progress reports: yes" in dotnet_report

    # an exception in a callback body is caught by the guard: the run ends as usual
    m = field(dotnet_report, r"^status: -10, M (\d+), caught: (\d+) \(a panel's bug in DriverMFunc\)$")
    assert m[1] == m[2] == str(len(result.m_functions))

    m = field(dotnet_report, r"^== offline machine, GetPos polled\nstart: 0\nstatus: -32\n"
                             r"polls: yes, failed 0, went back 0, callbacks during the polls: yes\n"
                             r"machine parts: (\d+), M (\d+), all (\S+) mm")
    assert int(m[1]) == len(parts) and int(m[2]) == len(result.m_functions)
    assert float(m[3]) == pytest.approx(cut + rapid, abs=1e-5)
    assert dotnet_report.endswith(f"== destroy\ndestroyed, status 0, faults {len(result.m_functions)}\n")
