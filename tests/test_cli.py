"""The command line (`sf-tch`, `python -m sf_tch`): the README's main job `demo`,
every command, `--json` parsed back (also on failure), standard input, and every way
it ends: program errors (1), bad usage (2, one line, no traceback), Ctrl-C (130, also
during a run on the offline machine) and a closed pipe (141)."""
import json
import os
import pty
import re
import signal
import subprocess
import sys
import time
import tracemalloc
from pathlib import Path

import pytest

import sf_tch

SQUARE = "G0 X0 Y0 Z0\nG1 X10 F600\nG1 Y10\nG1 X0\nG1 Y0\nM30\n"


def as_written_ini(tmp_path):
    """The bundled INI with tolerance2 = 0: the parts as written, collinear G1 parts
    (the diagonal runs of X{k % 100} Y{k % 37}) not joined."""
    ini = tmp_path / "as_written.ini"
    ini.write_text(Path(sf_tch.default_ini()).read_text() + "\n[GCodeParameters]\ntolerance2 = 0\n")
    return ini


def sf_tch_cli(*args, module="sf_tch"):
    return subprocess.run([sys.executable, "-m", module, *args], capture_output=True, text=True, timeout=120)


def assert_usage_error(proc, pattern):
    assert proc.returncode == 2, proc.stdout + proc.stderr
    assert proc.stdout == ""
    assert len(proc.stderr.strip().splitlines()) == 1, proc.stderr
    assert re.search(pattern, proc.stderr), proc.stderr
    assert "Traceback" not in proc.stderr


@pytest.fixture
def square(tmp_path):
    path = tmp_path / "square.nc"
    path.write_text(SQUARE)
    return path


def test_demo_compiles_compensates_and_simulates_the_sample():
    proc = sf_tch_cli("demo")
    assert proc.returncode == 0, proc.stderr
    out = proc.stdout
    assert re.search(r"parts:\s+47 motion, 16 M functions", out)
    # the outline is cut outside (G42) with the default 1 mm radius
    box = re.search(r"box compensated:\s+X (\S+)\.\.(\S+)\s+Y (\S+)\.\.(\S+)", out)
    assert [float(v) for v in box.groups()] == pytest.approx([-1.0, 121.0, -8.0, 81.0])
    assert "PRINT:         plate done" in out
    assert re.search(r"run time:\s+\d+\.\d+ s", out)
    assert "errors:        none" in out


def test_the_old_module_entry_still_runs_the_demo():
    proc = sf_tch_cli("demo", module="sf_tch.cli")
    assert proc.returncode == 0 and "errors:        none" in proc.stdout


def test_demo_reports_a_tool_too_big_for_the_slot_with_its_line():
    proc = sf_tch_cli("demo", "--radius", "6")
    assert proc.returncode == 1
    assert re.search(r"demo\.nc:34:1: error 503: Arc radius 5 smaller than the tool radius 6", proc.stderr)
    assert "Traceback" not in proc.stderr


def test_demo_of_a_user_program(square):
    proc = sf_tch_cli("demo", str(square))
    assert proc.returncode == 0, proc.stderr
    assert re.search(r"cut length:\s+40\.000 mm in 4 parts", proc.stdout)


def test_compile_prints_the_summary(square):
    proc = sf_tch_cli("compile", str(square), "--radius", "0")
    assert proc.returncode == 0, proc.stderr
    assert re.search(r"parts:\s+5 motion, 1 M functions", proc.stdout)
    assert re.search(r"box programmed:\s+X 0\.000\.\.10\.000  Y 0\.000\.\.10\.000", proc.stdout)


def test_compile_error_is_file_line_column_and_exit_1(tmp_path):
    bad = tmp_path / "bad.nc"
    bad.write_text("G1 X10 F100\nG1 Q1 W2 HH\n")
    proc = sf_tch_cli("compile", str(bad))
    assert proc.returncode == 1
    assert proc.stderr.strip() == f"{bad}:2:10: error 100: Unknown word 'HH' at column 10"
    assert proc.stdout == ""


def test_every_diagnostic_is_one_line_with_a_column(tmp_path):
    # 407 (the vendor's three lines on one, the column the library keeps beside the text,
    # the arc's details in the JSON's fields), after a byte-order mark, in the ISO mode
    arc = tmp_path / "arc.nc"
    arc.write_bytes(b"\xef\xbb\xbfG21 G0 X10 Y0 F100\n  G3 X0 Y10.03 I-10 J0\n")
    proc = sf_tch_cli("compile", str(arc), "--iso")
    assert proc.returncode == 1 and proc.stderr.count("\n") == 1
    assert proc.stderr.startswith(f"{arc}:2:16: error 407: Wrongly entered centre of circular interpolation XY; "
                                  "Start X = 10 Y = 0 | End X = 0 Y = 10.03; Radius at start (10.0000000)")
    doc = json.loads(sf_tch_cli("compile", str(arc), "--iso", "--json").stdout)
    assert doc["errors"][0]["column"] == 16
    assert doc["errors"][0]["fields"] == {"plane": "XY", "start": {"X": 10, "Y": 0}, "end": {"X": 0, "Y": 10.03},
                                          "radius_start": 10, "radius_end": 10.03}
    # the compensation's 504 (strict) and 601: the block's column (its first word)
    narrow = tmp_path / "narrow.nc"
    narrow.write_text("G0 X0 Y-5\nG41 G1 X0 Y0 F100\nG1 X10\nG1 Y0.5\nG1 X0\nG1 Y1\nG1 X20\nG40 G1 X20 Y10\n")
    proc = sf_tch_cli("compile", str(narrow), "--radius", "2", "--strict")
    assert proc.returncode == 1 and proc.stderr.count("\n") == 1
    assert proc.stderr.startswith(f"{narrow}:4:1: error 504: Equidistants cross: the tool (radius 2)")
    proc = sf_tch_cli("compile", str(narrow), "--radius", "2")
    gouges = [line for line in proc.stderr.splitlines() if " warning 601: " in line]
    assert proc.returncode == 0 and gouges and all(line.startswith(f"{narrow}:") for line in gouges)
    assert [line.split(":")[2] for line in gouges] == ["1"] * len(gouges)


def test_json_is_parsed_back(square, tmp_path):
    proc = sf_tch_cli("compile", str(square), "--json")
    assert proc.returncode == 0, proc.stderr
    doc = json.loads(proc.stdout)
    assert doc["ok"] and doc["errors"] == [] and doc["toolpath"]["cut_length"] == pytest.approx(40)
    assert doc["extent"]["programmed"]["max"][:2] == [10, 10] and doc["run_time"] > 0
    bad = tmp_path / "bad.nc"
    bad.write_text("G1 X1/0\n")
    proc = sf_tch_cli("compile", str(bad), "--json")
    assert proc.returncode == 1
    doc = json.loads(proc.stdout)
    assert not doc["ok"] and doc["errors"][0]["number"] == 200 and doc["errors"][0]["line"] == 1
    assert doc["errors"][0]["name"] == "DIVISION_BY_ZERO" and doc["errors"][0]["file"] == str(bad)
    info = json.loads(sf_tch_cli("info", "--json").stdout)
    assert info["cores"] == 3 and info["structures"]["SIMPLE_GM_PARAMS"] == {"library": 616, "mirror": 616}


def test_simulate_and_test_regime(square, tmp_path):
    proc = sf_tch_cli("simulate", str(square), "--json")
    assert proc.returncode == 0, proc.stderr
    run = json.loads(proc.stdout)["run"]
    assert run["status_name"] == "SIMULATION_DONE" and run["cut_length"] == pytest.approx(40)
    assert run["cut_parts"] == 4 and run["m_functions"] == 1
    proc = sf_tch_cli("simulate", str(square), "--test")
    assert proc.returncode == 0, proc.stderr
    assert re.search(r"run:\s+test, status -20 \(TEST_DONE\)", proc.stdout)


def test_plot_writes_png_and_svg(square, tmp_path):
    for name in ("out.png", "out.svg"):
        out = tmp_path / name
        proc = sf_tch_cli("plot", str(square), "-o", str(out))
        assert proc.returncode == 0, proc.stderr
        assert out.stat().st_size > 5000
    assert (tmp_path / "out.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert b"<svg" in (tmp_path / "out.svg").read_bytes()[:500]
    assert_usage_error(sf_tch_cli("plot", str(square), "-o", str(tmp_path / "out.gif")), r"\.png, \.svg or \.pdf")


def test_plot_views(tmp_path):
    # a 3D program: two passes at Z -1 and -2, drawn from every side
    program = tmp_path / "passes.nc"
    program.write_text("G0 X0 Y0 Z5\nG1 Z-1 F300\nG1 X20 Y10 F1000\nG1 Z-2\nG1 X0 Y0\nG0 Z5\nM30\n")
    for view in ("xy", "xz", "yz", "3d"):
        out = tmp_path / f"{view}.png"
        proc = sf_tch_cli("plot", str(program), "-o", str(out), "--view", view)
        assert proc.returncode == 0, proc.stderr
        assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and out.stat().st_size > 5000
    assert_usage_error(sf_tch_cli("plot", str(program), "-o", str(tmp_path / "top.png"), "--view", "top"),
                       "invalid choice")


def test_plot_without_matplotlib_names_the_install_command(square, tmp_path):
    probe = ("import sys, runpy\nsys.modules['matplotlib'] = None\n"
             f"sys.argv = ['sf-tch', 'plot', {str(square)!r}, '-o', {str(tmp_path / 'x.png')!r}]\n"
             "runpy.run_module('sf_tch', run_name='__main__')\n")
    proc = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, timeout=60)
    assert_usage_error(proc, "^sf-tch: error: plotting needs matplotlib: " + re.escape(sys.executable)
                       + r" -m pip install matplotlib$")
    assert not (tmp_path / "x.png").exists()


def test_plot_of_a_large_program_says_it_is_drawing(tmp_path):
    program = tmp_path / "large.nc"
    program.write_text("G0 X0 Y0 Z0\n" + "".join(f"G1 X{k % 100} Y{k % 37} F1000\n" for k in range(100_000)))
    proc = sf_tch_cli("plot", str(program), "-o", str(tmp_path / "large.png"), "--radius", "0",
                      "--ini", str(as_written_ini(tmp_path)))
    assert proc.returncode == 0, proc.stderr
    assert proc.stderr == f"drawing 100,001 parts into {tmp_path / 'large.png'} ...\n"
    assert (tmp_path / "large.png").stat().st_size > 5000


def test_version_info_and_help():
    for proc in (sf_tch_cli("--version"), sf_tch_cli("--version", module="sf_tch.cli")):
        assert proc.returncode == 0 and proc.stdout.strip() == f"sf-tch {sf_tch.__version__}"
    proc = sf_tch_cli("info")
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.startswith("SF_TCh ")
    assert "cores:   3" in proc.stdout
    assert "MISMATCH" not in proc.stdout
    assert re.search(r"SIMPLE_GM_PARAMS\s+616 / 616", proc.stdout)
    assert "Exit codes" in sf_tch_cli("--help").stdout
    # every command's --help says what it does
    for command in ("demo", "compile", "simulate", "run", "plot", "info"):
        usage, description = sf_tch_cli(command, "--help").stdout.split("\n\n")[:2]
        assert usage.startswith(f"usage: sf-tch {command}") and not description.startswith("options:"), command


def test_bad_usage_is_one_line_and_exit_2(square, tmp_path):
    assert_usage_error(sf_tch_cli("compile", str(tmp_path / "missing.nc")), r"missing\.nc: no such file")
    assert_usage_error(sf_tch_cli("compile", str(tmp_path)), r"is a directory")
    assert_usage_error(sf_tch_cli("compile", str(square), "--core", "5"), r"core 5 does not exist")
    assert_usage_error(sf_tch_cli("compile", str(square), "--core", "x"), r"not a core number")
    assert_usage_error(sf_tch_cli("demo", "--radius", "-1"), r"radius >= 0")
    assert_usage_error(sf_tch_cli("demo", "--radius", "nan"), r"radius >= 0")
    assert_usage_error(sf_tch_cli("compile", str(square), "--strategy", "zz"), r"not an integer")
    assert_usage_error(sf_tch_cli("compile", str(square), "--ini", str(tmp_path / "no.ini")), r"no such INI")
    assert_usage_error(sf_tch_cli("frobnicate"), r"invalid choice")
    assert_usage_error(sf_tch_cli(), r"required")


def test_a_missing_library_is_a_usage_error(square, tmp_path):
    env = dict(os.environ, SF_TCH_LIBRARY=str(tmp_path / "gone.so"))
    proc = subprocess.run([sys.executable, "-m", "sf_tch", "compile", str(square)], capture_output=True,
                          text=True, timeout=60, env=env)
    assert_usage_error(proc, r"SF_TCH_LIBRARY=.*gone\.so: no such file")


def test_a_closed_pipe_ends_quietly(tmp_path):
    # a summary longer than the pipe reads: `sf-tch compile --json ... | head -c 10`
    program = tmp_path / "many.nc"
    program.write_text("G0 X0 Y0 Z0\n" + "".join(f"G1 X{k % 50} Y{k % 7} F900\n" for k in range(20000)))
    reader = subprocess.Popen([sys.executable, "-m", "sf_tch", "info", "--json"], stdout=subprocess.PIPE,
                              stderr=subprocess.PIPE)
    reader.stdout.read(10)
    reader.stdout.close()                  # the reader goes away before the writer has finished
    stderr = reader.stderr.read().decode()
    code = reader.wait(timeout=60)
    assert code in (0, 141), stderr
    assert "Traceback" not in stderr and "BrokenPipe" not in stderr
    shell = subprocess.run(f"{sys.executable} -m sf_tch compile --json {program} | head -c 10",
                           shell=True, capture_output=True, text=True, timeout=120)
    assert len(shell.stdout) == 10 and "Traceback" not in shell.stderr and "Broken" not in shell.stderr


def test_ctrl_c_interrupts_a_long_compile_quietly(tmp_path):
    program = tmp_path / "endless.nc"
    program.write_text("L1:\nG1 X1 F100\nG1 X0\nGOTO L1\n")      # runs until the block limit
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1")     # one thread until the compile
    # python -m sf_tch with Ctrl-C's handler: a suite started in the background (`&`) runs
    # with SIGINT ignored, and so would the command, which never gets a KeyboardInterrupt
    cli = ("import runpy, signal; signal.signal(signal.SIGINT, signal.default_int_handler); "
           "runpy.run_module('sf_tch', run_name='__main__', alter_sys=True)")
    proc = subprocess.Popen([sys.executable, "-c", cli, "compile", str(program)], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, env=env)
    deadline = time.monotonic() + 30
    while len(os.listdir(f"/proc/{proc.pid}/task")) < 2:      # the core's worker thread compiles
        assert time.monotonic() < deadline and proc.poll() is None
        time.sleep(0.01)
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=60)
    assert proc.returncode == 130, (out, err)
    assert err.strip() == "sf-tch: interrupted" and out == ""


def test_a_cnc_error_propagates_through_a_with_block():
    from sf_tch.core import CncError, Core
    with pytest.raises(CncError) as caught:
        with Core(0) as core:
            core.compile_text("G1 X1/0\n", "bad.nc")
    assert caught.value.number == 200 and caught.value.line == 1


def test_progress_bar_only_for_long_work_and_cleared(capsys):
    from sf_tch.cli import ProgressBar
    quiet = ProgressBar("compiling x", enabled=False)
    quiet.started -= 10
    quiet(50)
    fresh = ProgressBar("compiling x", enabled=True)
    fresh(10)                                   # the first half second: nothing
    bar = ProgressBar("compiling x", enabled=True)
    bar.started -= 10
    bar(40)
    bar(100)
    bar.close()
    err = capsys.readouterr().err
    assert err == ("\rcompiling x [" + "#" * 12 + " " * 18 + "]  40 %" + "\rcompiling x [" + "#" * 30 + "] 100 %"
                   + "\r\033[K")


def test_iso_option_reads_iso_g_code(tmp_path):
    """--iso: G21 and `G4 P` (ISO) compile; without it `G4 P` is the P-word error."""
    iso = tmp_path / "iso.nc"
    iso.write_text("%\nO1000\nG21 G90\nG1 X10 Y0 F600\nG4 P0.5\nG1 X20\nM30\n%\n")
    plain = sf_tch_cli("compile", str(iso), "--json")
    assert plain.returncode == 1 and '"number": 110' in plain.stdout
    proc = sf_tch_cli("compile", str(iso), "--iso", "--json")
    assert proc.returncode == 0, proc.stderr
    summary = json.loads(proc.stdout)
    assert summary["errors"] == [] and summary["toolpath"]["cut_length"] == pytest.approx(20.0)


def test_look_ahead_option(tmp_path):
    """--look-ahead: a deeper window plans dense short segments faster."""
    dense = tmp_path / "dense.nc"
    # 1 um up and down at every 0.1 mm: 0.6 degrees between the parts, none joined (tolerance[2])
    dense.write_text("G1 X0 F6000\n" + "".join(f"G1 X{0.1 * (k + 1):.6f} Y{0.001 * (k % 2):.3f}\n"
                                               for k in range(500)))
    times = [json.loads(sf_tch_cli("simulate", str(dense), "--look-ahead", n, "--json").stdout)["run_time"]
             for n in ("0", "-1")]
    assert times[0] > times[1] > 0
    assert_usage_error(sf_tch_cli("compile", str(dense), "--look-ahead", "-2"), "look-ahead|-1")


def test_run_moves_the_offline_machine_to_the_end(square):
    # the square: 40 mm at 600 mm/min with ramps; 100 times real time
    proc = sf_tch_cli("run", str(square), "--time-scale", "100", "--json")
    assert proc.returncode == 0, proc.stderr
    run = json.loads(proc.stdout)["run"]
    assert run["status"] == -32 and run["status_name"] == "AT_END"
    assert run["cut_length"] == pytest.approx(40.0, abs=1e-6)
    assert run["position"] == pytest.approx([0.0, 0.0, 0.0], abs=1e-9)
    # every side at 10 mm/s with its ramps: at least the 4 s of cruising, the plan's time
    planned = json.loads(proc.stdout)["run_time"]
    assert run["run_time"] == pytest.approx(planned, rel=0.005) and run["run_time"] >= 4.0


def test_run_rejects_a_bad_time_scale(square):
    assert_usage_error(sf_tch_cli("run", str(square), "--time-scale", "0"), r"outside \(0, 1e6\]")


def test_json_is_one_document_also_when_the_command_fails(square, tmp_path):
    cases = [(("compile", str(tmp_path / "missing.nc"), "--json"), 2, r"missing\.nc: no such file"),
             (("compile", str(tmp_path), "--json"), 2, r"is a directory"),
             (("compile", "/dev/null", "--json"), 2, r"/dev/null: not a regular file"),
             (("compile", str(square), "--core", "5", "--json"), 2, r"core 5 does not exist"),
             (("plot", str(square), "-o", str(tmp_path / "x.gif"), "--json"), 2, r"\.png, \.svg or \.pdf")]
    for args, code, pattern in cases:
        proc = sf_tch_cli(*args)
        assert proc.returncode == code, (args, proc.stdout, proc.stderr)
        doc = json.loads(proc.stdout)
        assert doc["ok"] is False and doc["exit_code"] == code and re.search(pattern, doc["error"]), doc
        assert proc.stderr == ""
    ok = json.loads(sf_tch_cli("compile", str(square), "--json").stdout)
    assert ok["ok"] is True and ok["exit_code"] == 0


def test_usage_errors_have_the_prefix_and_exit_2(square, tmp_path):
    assert_usage_error(sf_tch_cli("compile", "/dev/null"), r"^sf-tch: error: /dev/null: not a regular file")
    assert_usage_error(sf_tch_cli("compile", str(square), "--ini", str(tmp_path)),
                       r"^sf-tch: error: .*: is a directory, not an INI file")
    assert_usage_error(sf_tch_cli("compile", str(square), "--core", "5"),
                       r"^sf-tch: error: argument --core: core 5 does not exist \(0\.\.2\) \(see sf-tch compile --help\)")


def test_compile_reads_standard_input():
    proc = subprocess.run([sys.executable, "-m", "sf_tch", "compile", "-", "--radius", "0"], input=SQUARE,
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert re.search(r"^program:\s+<stdin>$", proc.stdout, re.M)
    assert re.search(r"cut length:\s+40\.000 mm in 4 parts", proc.stdout)
    bad = subprocess.run([sys.executable, "-m", "sf_tch", "compile", "-"], input="G1 X10 F100\nG1 Q1 W2 HH\n",
                         capture_output=True, text=True, timeout=120)
    assert bad.returncode == 1 and bad.stderr.strip() == "<stdin>:2:10: error 100: Unknown word 'HH' at column 10"
    # the bytes as they come: a byte-order mark and a Latin-1 comment reach the library unchanged
    marked = subprocess.run([sys.executable, "-m", "sf_tch", "compile", "-", "--iso"],
                            input=b"\xef\xbb\xbfG21 G90 (\xb0)\nG1 X10 F100\nG1 X1.2.3\n",
                            capture_output=True, timeout=120)
    assert marked.returncode == 1
    assert marked.stderr.decode().strip() == "<stdin>:3:5: error 101: Bad number '1.2.3' at column 5"


def test_one_part_is_singular(tmp_path):
    one = tmp_path / "one.nc"
    one.write_text("G0 X0 Y0 Z0\nG1 X10 F600\n")
    proc = sf_tch_cli("compile", str(one))
    assert re.search(r"cut length:\s+10\.000 mm in 1 part$", proc.stdout, re.M), proc.stdout
    assert re.search(r"rapid length:\s+0\.000 mm in 1 part$", proc.stdout, re.M), proc.stdout


def test_version_and_help_do_not_load_numpy():
    for args in (["--version"], ["--help"], ["compile", "--help"]):
        probe = ("import atexit, sys\n"
                 "atexit.register(lambda: print('numpy loaded:', 'numpy' in sys.modules, file=sys.stderr))\n"
                 f"sys.argv = ['sf-tch', *{args!r}]\n"
                 "import runpy\nrunpy.run_module('sf_tch', run_name='__main__')\n")
        proc = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, timeout=60)
        assert proc.returncode == 0 and "numpy loaded: False" in proc.stderr, (args, proc.stderr)


def test_compile_summary_reads_the_toolpath_in_chunks(tmp_path, capsys):
    """The summary of `sf-tch compile` needs a chunk of records, not the whole
    toolpath: its Python memory stays far below the records' own size."""
    from sf_tch import cli
    from sf_tch.toolpath import TOOLPATH_DTYPE
    lines = 100_000
    program = tmp_path / "long.nc"
    program.write_text("G0 X0 Y0 Z0\n" + "".join(f"G1 X{k % 100} Y{k % 37} F1000\n" for k in range(lines)))
    records_size = (lines + 1) * TOOLPATH_DTYPE.itemsize                     # 16.8 MB
    tracemalloc.start()
    try:
        code = cli.main(["compile", str(program), "--radius", "0", "--ini", str(as_written_ini(tmp_path))])
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    out = capsys.readouterr().out
    assert code == 0 and re.search(rf"parts:\s+{lines + 1} motion", out)
    assert peak < 0.25 * records_size, (peak, records_size)


def _program_lines(proc_out: str, key: str) -> str:
    return re.search(rf"^{key}.*$", proc_out, re.M).group(0)


def test_run_prints_the_compiles_box_and_progress_lines_without_a_terminal():
    compiled = sf_tch_cli("compile", sf_tch.sample_program())
    proc = sf_tch_cli("run", sf_tch.sample_program(), "--time-scale", "1000")
    assert proc.returncode == 0, proc.stderr
    for key in ("box programmed:", "box compensated:"):          # the compile's extents, not the machine's after
        assert _program_lines(proc.stdout, key) == _program_lines(compiled.stdout, key)
    assert "Z -1.000..5.000" in _program_lines(proc.stdout, "box programmed:")
    progress = [line for line in proc.stderr.splitlines() if line.startswith("run ")]
    assert len(progress) >= 2 and progress[0].startswith("run   0.0 %") and progress[-1].startswith("run 100.0 %")
    # at the end the line of the program's last part (M30), not GetPos's 0
    last = Path(sf_tch.sample_program()).read_text().splitlines().index("N420 M30") + 1
    assert re.match(rf"run 100\.0 %  line {last} ", progress[-1]), progress[-1]
    assert re.search(r"run:\s+status -32 \(AT_END\)$", proc.stdout, re.M)


def test_run_on_a_terminal_keeps_one_live_line_that_reaches_100(square):
    master, slave = pty.openpty()
    proc = subprocess.Popen([sys.executable, "-m", "sf_tch", "run", str(square), "--time-scale", "20"],
                            stdout=subprocess.PIPE, stderr=slave, text=True)
    os.close(slave)
    chunks = []
    while True:
        try:
            data = os.read(master, 4096)
        except OSError:                      # the child closed the terminal
            break
        if not data:
            break
        chunks.append(data)
    out = proc.stdout.read()
    assert proc.wait(timeout=60) == 0, out
    os.close(master)
    screen = b"".join(chunks).decode()
    live = [part for part in screen.replace("\n", "\r").split("\r") if part.startswith("run ")]
    assert len(live) >= 3 and "\n" not in screen.rstrip("\r\n").split("\r")[-1]
    assert live[-1].startswith("run 100.0 %") and "  line 0 " not in live[-1], live[-3:]


@pytest.mark.parametrize("as_json", [False, True])
def test_ctrl_c_stops_the_machine_and_exits_130(as_json):
    # the sample at real time takes half a minute: interrupted once its first progress line is out
    proc = subprocess.Popen([sys.executable, "-m", "sf_tch", "run", sf_tch.sample_program(), "--time-scale", "1"]
                            + (["--json"] if as_json else []), stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True)
    first = proc.stderr.readline()
    assert first.startswith("run   0.0 %"), first
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=60)
    assert proc.returncode == 130, (out, err)
    if as_json:
        doc = json.loads(out)
        assert doc["exit_code"] == 130 and doc["run"]["interrupted"] is True
        assert doc["run"]["status_name"] == "STOPPED" and doc["run"]["run_time"] < 30
    else:
        assert re.search(r"^run:\s+status -31 \(STOPPED\), interrupted$", out, re.M), out
        assert err.rstrip().endswith("sf-tch: interrupted: the machine stopped on the path")
    assert "Traceback" not in err
