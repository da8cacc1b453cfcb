"""The Pythonic API: sf_tch.compile() and Program, diagnostics with file, line and
column, progress and cancellation, cores always released, enums, repr/to_dict,
library_path(), the version, docstrings, and the README's snippet."""
import ctypes
import gc
import inspect
import json
import logging
import re
import sys
import threading
import warnings
from importlib import metadata
from pathlib import Path

import pytest

import sf_tch
from compiler_host import SEED_PROGRAM
from sf_tch import ErrorNumber, Status, abi

README = Path(__file__).resolve().parents[1] / "README.md"
SQUARE = "G0 X0 Y0 Z0\nG1 X10 F600\nG1 Y10\nG1 X0\nG1 Y0\nM30\n"


def test_compile_text_gives_a_program_with_results():
    with sf_tch.compile(SQUARE, name="square.nc") as program:
        assert program.ok and program.errors == [] and program.warnings == []
        assert program.toolpath.to_dict()["cut_length"] == pytest.approx(40)
        size = program.size_info.m_size[0]
        assert (size.m_minimalPos.x, size.m_maximalPos.y) == (0, 10)
        # 4 lines of 10 mm at 600 mm/min from rest to rest (trapezoids: at least 4 s)
        assert program.run_time >= 4.0
        assert repr(program) == "<Program 'square.nc' ok, 0 warning(s), 6 parts>"
        json.dumps(program.to_dict())


def test_compile_a_file_and_the_seed_program(tmp_path):
    path = tmp_path / "seed.nc"
    path.write_text(SEED_PROGRAM + "\n")
    with sf_tch.compile(path, params={"absMode": 0}) as program:
        assert program.ok and program.name == str(path)
    # absolute: the arc-centre error on line 4, with the file's name
    with sf_tch.compile(str(path)) as program:
        assert not program.ok
        error = program.errors[0]
        assert (error.number, error.line, error.file) == (ErrorNumber.ARC_CENTRE, 4, str(path))
        assert str(error).startswith(f"{path}:4:17: error 400: Wrongly entered centre")
        with pytest.raises(sf_tch.CncError) as caught:
            program.check()
        assert caught.value.line == 4 and caught.value.file == str(path)
        assert program.size_info is None and program.run_time is None and len(program.toolpath) == 0


@pytest.mark.parametrize("code, number, column", [
    ("G1 X10 F100\nG1 X(1+)\n", ErrorNumber.BAD_EXPRESSION, 8),
    ("G1 X10 F100\nG1 Q1 W2 HH\n", ErrorNumber.UNKNOWN_WORD, 10),
    ("G1 X10 F100\nG4 P1\n", ErrorNumber.P_WORD, 4),                     # the P word
    ("G1 X10 F100\nG1 X1.2.3\n", ErrorNumber.BAD_NUMBER, 5),
    ("G1 X10 F100\nG1 X1/0\n", ErrorNumber.DIVISION_BY_ZERO, 1),           # no column given: the block's
    ("G1 X10 F100\n  G1 X1/0\n", ErrorNumber.DIVISION_BY_ZERO, 3),
    ("\ufeffG1 X10 F100\nG1 X1.2.3\n", ErrorNumber.BAD_NUMBER, 5),       # a byte-order mark is no line
])
def test_errors_carry_file_line_and_column(code, number, column):
    with sf_tch.compile(code, name="cols.nc") as program:
        (error,) = program.errors
    assert (error.file, error.line, error.column, error.number) == ("cols.nc", 2, column, number)
    assert str(error).startswith(f"cols.nc:2:{column}: " if column else "cols.nc:2: ")
    assert error.to_dict()["name"] == number.name


def test_iso_mode_is_the_calls_own():
    # a core keeps its parameters from one user to the next: iso=False means off
    dwell_p = "G1 X10 F100\nG4 P1\n"
    with sf_tch.compile(dwell_p, iso=True, core=0) as program:
        assert program.errors == []                     # ISO: G4 P1 is one second
    with sf_tch.compile(dwell_p, core=0) as program:
        assert [e.number for e in program.errors] == [ErrorNumber.P_WORD]


def test_warnings_are_collected():
    code = "G0 X0 Y0 Z0\nG41\nG3 X20 Y0 I10 J0 F1000\nG1 Y-10\nG40 X0\nM30\n"
    with sf_tch.compile(code, radius=1.0, name="comp.nc") as program:
        assert program.ok
        (warning,) = program.warnings
    assert warning.severity == "warning" and warning.number == ErrorNumber.COMPENSATION_WARNING
    assert warning.line == 3 and warning.file == "comp.nc"


def test_bad_sources_and_arguments(tmp_path):
    with pytest.raises(FileNotFoundError, match="no such file"):
        sf_tch.compile(tmp_path / "missing.nc")
    with pytest.raises(IsADirectoryError):
        sf_tch.compile(tmp_path)
    with pytest.raises(ValueError, match="radius"):
        sf_tch.compile(SQUARE, radius=-1)
    with pytest.raises(FileNotFoundError, match="INI"):
        sf_tch.compile(SQUARE, ini=tmp_path / "none.ini")
    with pytest.raises(AttributeError, match="noSuchField"):
        sf_tch.compile(SQUARE, params={"noSuchField": 1})
    with pytest.raises(IndexError):
        sf_tch.Core(3)
    # none of these kept a core
    programs = [sf_tch.compile(SQUARE, keep_core=True) for _ in range(3)]
    assert sorted(p.core.index for p in programs) == [0, 1, 2]
    for p in programs:
        p.close()


def test_cores_are_claimed_and_always_released():
    programs = [sf_tch.compile(SQUARE, keep_core=True) for _ in range(3)]
    with pytest.raises(sf_tch.NoFreeCoreError):
        sf_tch.compile(SQUARE)
    with pytest.raises(sf_tch.NoFreeCoreError, match="core 1 is in use"):
        sf_tch.Core(1)
    programs[1].close()
    with sf_tch.compile(SQUARE, keep_core=True) as again:
        assert again.core.index == 1
    assert again.core.closed and again.core.status == Status.NOTHING_LOADED
    for p in programs:
        p.close()
    # an exception inside the block releases the core too
    with pytest.raises(KeyError):
        with sf_tch.compile(SQUARE, keep_core=True) as program:
            raise KeyError("x")
    assert program.core.closed


def test_a_program_holds_no_core_after_its_compile(tmp_path):
    """[sf_tch.compile(f) for f in files]: each program's results are copied into
    Python and its core given back before compile() returns, so any number of
    programs live at once; simulate() takes a free core for its run."""
    files = []
    for k in range(20):
        files.append(tmp_path / f"part{k}.nc")
        files[-1].write_text(f"G0 X0 Y0 Z0\nG1 X{k + 1} Y10 F600\nPRINT \"part {k}\"\nM30\n")
    programs = [sf_tch.compile(f) for f in files]
    held = [sf_tch.compile(SQUARE, name=f"square{k}.nc") for k in range(100)]
    assert all(p.core is None for p in programs + held)
    for k, program in enumerate(programs):
        assert program.ok and program.printed == [f"part {k}"] and program.run_time > 0
        assert program.toolpath.records["end"][1].tolist() == [k + 1, 10, 0]
        assert program.size_info.m_size[0].m_maximalPos.x == k + 1
        assert program.to_dict()["toolpath"]["cut_length"] == pytest.approx(((k + 1) ** 2 + 100) ** 0.5)
    for program in held:
        assert program.summary()["cut_length"] == pytest.approx(40) and program.run_time >= 4.0
    # three Cores can still be taken meanwhile, and a program simulates on a free one
    cores = [sf_tch.Core() for _ in range(2)]
    run = held[42].simulate()
    assert len(run) == 5 and run.m_functions["m_func"].tolist() == [30]
    cores.append(sf_tch.Core())
    with pytest.raises(sf_tch.NoFreeCoreError):
        held[0].simulate()
    for core in cores:
        core.close()
    # a failed compile keeps its errors, with nothing else
    failed = sf_tch.compile("G1 X10 F100\nG1 X1/0\n", name="bad.nc")
    assert failed.core is None and failed.errors[0].line == 2 and failed.run_time is None
    assert failed.size_info is None and len(failed.toolpath) == 0
    with pytest.raises(sf_tch.CncError):
        failed.simulate()


def test_a_kept_core_given_back_reads_nothing_more_from_it():
    with sf_tch.compile(SQUARE, name="kept.nc", keep_core=True) as program:
        assert program.core.index in (0, 1, 2) and program.run_time >= 4.0
    # read before close(): kept; not read: a clear error instead of another user's core
    assert program.run_time >= 4.0
    with pytest.raises(RuntimeError, match="core of 'kept.nc' was given back"):
        program.toolpath
    assert len(program.simulate()) == 5                  # compiled again on a free core


def test_a_loop_of_compiles_gives_each_core_back_at_once():
    """A batch over many programs without close() or `with`: a Program nothing
    references releases its core at once (no reference cycle waits for the garbage
    collector, which is off here), with at most a ResourceWarning."""
    def summary_of(text):
        program = sf_tch.compile(text)          # out of scope at the return
        return program.summary()

    gc.collect()
    gc.disable()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            warnings.simplefilter("ignore", ResourceWarning)
            for _ in range(10):
                p = sf_tch.compile(SQUARE, keep_core=True)  # the name rebound: the last program's core comes back
                assert p.run_time >= 4.0 and p.printed == [] and len(p.toolpath) == 6
                p.simulate()
            del p
            for _ in range(10):
                assert summary_of(SQUARE)["cut_length"] == pytest.approx(40)
            for _ in range(10):                 # a job iterated for its progress, never asked for its result
                job = sf_tch.start_compile(SQUARE)
                assert list(job)[-1] == 100
            del job
            for _ in range(10):
                failed = sf_tch.compile("G1 X1/0\n")
                assert not failed.ok
            del failed
            for _ in range(10):
                core = sf_tch.Core()
                core.compile_text(SQUARE)
                assert len(core.simulate()) == 5
            del core
            # every core is free again
            held = [sf_tch.compile(SQUARE, keep_core=True) for _ in range(3)]
            assert sorted(program.core.index for program in held) == [0, 1, 2]
    finally:
        gc.enable()
    for program in held:
        program.close()


def test_a_one_line_program_as_text_is_told_to_end_in_a_line_break(tmp_path):
    with pytest.raises(FileNotFoundError, match=re.escape("'G1 X10 Y10 F1000': no such file; G-code given as "
                                                          "text needs a line break (a one-line program: "
                                                          "'G1 X10 Y10 F1000\\n')")):
        sf_tch.compile("G1 X10 Y10 F1000")
    for text in ("g0 x0", "M30", "N10 G1 X1", "X-1.5", "P10 = 3", "(comment", "; note"):
        with pytest.raises(FileNotFoundError, match="needs a line break"):
            sf_tch.compile(text)
    with pytest.raises(FileNotFoundError) as missing:        # a file name stays a file name
        sf_tch.compile(str(tmp_path / "part.nc"))
    assert "line break" not in str(missing.value)
    with sf_tch.compile("G1 X10 Y10 F1000\n") as program:     # the line break makes it text
        assert program.ok
    # a file of that name is a file
    (tmp_path / "G1 X5").write_text("G1 X5 F100\n")
    with sf_tch.compile(str(tmp_path / "G1 X5")) as program:
        assert program.toolpath.records["end"][-1][0] == 5


def _long_program(lines: int) -> str:
    return "G0 X0 Y0 Z0\n" + "".join(f"G1 X{k % 100} Y{k % 37} F1000\n" for k in range(lines))


def test_progress_callback_and_iterator():
    seen = []
    with sf_tch.compile(_long_program(200_000), progress=seen.append) as program:
        assert program.ok
    assert seen and seen == sorted(seen) and seen[-1] == 100
    job = sf_tch.start_compile(_long_program(200_000))
    try:
        percents = list(job)
        assert percents == sorted(percents) and percents[-1] == 100 and len(set(percents)) == len(percents)
        assert job.result().ok
    finally:
        job.core.close()


def test_cancellation_by_event_and_by_method():
    endless = "L1:\nG1 X1 F100\nG1 X0\nGOTO L1\n"     # stopped by the block limit, if not cancelled first
    event = threading.Event()

    def cancel_at_first_progress(percent):
        event.set()

    event.set()
    with pytest.raises(sf_tch.Cancelled) as caught:
        sf_tch.compile(endless, cancel=event, progress=cancel_at_first_progress)
    assert caught.value.number == ErrorNumber.CANCELLED
    job = sf_tch.start_compile(endless)
    job.cancel()
    with pytest.raises(sf_tch.Cancelled):
        job.result()
    job.core.close()
    # every core is free again
    programs = [sf_tch.compile(SQUARE) for _ in range(3)]
    for p in programs:
        p.close()


def test_enums_compare_with_the_librarys_ints():
    assert Status.COMPILED == abi.STATUS_COMPILED and Status(-10) is Status.SIMULATION_DONE
    assert sf_tch.Callback.DRIVER_G_FUNC == abi.CB_DRIVER_G_FUNC
    assert sf_tch.Regime.TEST == abi.RUN_TEST
    assert set(sf_tch.Callback) == set(abi.CALLBACK_NUMBERS)
    assert sf_tch.PartKind.PRINT == abi.TC_TOOLPATH_PRINT
    assert sf_tch.ToolpathFlag.HELIX == abi.TC_TOOLPATH_HELIX


def test_every_structure_has_a_readable_repr_and_to_dict():
    for name, cls in abi.STRUCTURES.items():
        value = cls()
        text = repr(value)
        assert text.startswith(name + "(") and " object at 0x" not in text
        json.dumps(value.to_dict())
    with sf_tch.Core() as core:
        params = core.params.to_dict()
    assert params["absMode"] == 1 and params["motion"][0]["feed"] == 10000.0


def test_library_path_honours_the_environment(run_python, lib_path, tmp_path):
    out = run_python(f"""
        import os, sf_tch
        os.environ["SF_TCH_LIBRARY"] = {str(tmp_path / "nope.so")!r}
        try:
            sf_tch.library_path()
        except sf_tch.LibraryNotFoundError as exc:
            print("missing:", exc)
        os.environ["SF_TCH_LIBRARY"] = LIB_PATH
        print("found:", sf_tch.library_path() == LIB_PATH)
    """).stdout
    assert "missing: SF_TCH_LIBRARY=" in out and "no such file" in out and "found: True" in out


def test_the_ctypes_layer_loads_without_numpy(run_python):
    # numpy's OpenBLAS threads spin after its import and slow the library's compile
    # threads on a two-core panel: the ctypes layer must not bring it in
    out = run_python("""
        import sys
        import sf_tch
        from sf_tch import abi, library, enums, errors, logs
        library.load()
        print("numpy before:", "numpy" in sys.modules)
        from sf_tch import Core, Toolpath, compile
        print("numpy after:", "numpy" in sys.modules, Core.__module__, Toolpath.__module__, compile.__module__)
        print("listed:", all(name in dir(sf_tch) for name in sf_tch.__all__))
        try:
            sf_tch.no_such_name
        except AttributeError as exc:
            print("missing:", exc)
    """).stdout
    assert "numpy before: False" in out
    assert "numpy after: True sf_tch.core sf_tch.toolpath sf_tch.program" in out
    assert "listed: True" in out and "missing: module 'sf_tch' has no attribute 'no_such_name'" in out


def test_version_is_the_package_metadata():
    assert sf_tch.__version__ == metadata.version("sf-tch")
    assert re.fullmatch(r"\d+\.\d+\.\d+.*", sf_tch.__version__)


def test_every_public_name_has_a_docstring():
    missing = []
    for module_name in ("sf_tch", "sf_tch.core", "sf_tch.program", "sf_tch.toolpath", "sf_tch.errors",
                        "sf_tch.enums", "sf_tch.library", "sf_tch.cli", "sf_tch.plot"):
        module = __import__(module_name, fromlist=["_"])
        if not module.__doc__:
            missing.append(module_name)
        for name, obj in vars(module).items():
            if name.startswith("_") or getattr(obj, "__module__", None) != module.__name__:
                continue
            if not (inspect.isclass(obj) or inspect.isfunction(obj)):
                continue
            if not inspect.getdoc(obj):
                missing.append(f"{module_name}.{name}")
            if inspect.isclass(obj) and not issubclass(obj, (int, Exception)):
                for member, value in vars(obj).items():
                    if member.startswith("_") or not (inspect.isfunction(value) or isinstance(value, property)):
                        continue
                    if not inspect.getdoc(value):
                        missing.append(f"{module_name}.{name}.{member}")
    assert missing == []


def test_the_package_is_typed():
    assert (Path(sf_tch.__file__).parent / "py.typed").exists()


def _readme_example(heading: str) -> str:
    text = README.read_text()
    section = text[text.index(heading):]
    return re.search(r"```python\n(.*?)```", section, re.S).group(1)


def test_the_readme_python_example_runs(run_python, tmp_path):
    snippet = _readme_example("### From Python")
    run_python(snippet, cwd=str(tmp_path))
    assert (tmp_path / "program.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    # in the venv of the README's first command (no matplotlib) it ends saying how to install it
    bare = tmp_path / "bare"
    bare.mkdir()
    out = run_python("import sys\nsys.modules['matplotlib'] = None\n" + snippet, cwd=str(bare)).stdout
    assert out.splitlines()[-1] == f"plotting needs matplotlib: {sys.executable} -m pip install matplotlib"
    assert not (bare / "program.png").exists()


def test_the_readme_ctypes_example_tells_success_from_failure(run_python, tmp_path):
    out = run_python(_readme_example("### From a panel, through ctypes"), cwd=str(tmp_path)).stdout
    assert out.splitlines() == ["compiled", "line 2: error 200: Division by zero"]


def test_core_simulate_returns_a_sized_result():
    with sf_tch.Core() as core:
        core.compile_text(SQUARE)
        run = core.simulate()
    assert len(run) == 5 and len(run.m_functions) == 1
    assert run.parts["m_func"].tolist() == [0, 1, 1, 1, 1]
    assert "5 motion parts" in repr(run) and run.to_dict()["status"] == Status.SIMULATION_DONE
    assert ctypes.sizeof(abi.SIMPLE_GM_PARAMS) == run.parts.dtype.itemsize


def test_library_output_goes_to_the_logger(caplog):
    with caplog.at_level(logging.DEBUG, logger="sf_tch"):
        with sf_tch.compile("G1 X1/0\n", name="bad.nc") as program:
            assert not program.ok
        with sf_tch.compile('G0 X0 Y0 Z0\nPRINT "hello"\nM30\n') as program:
            assert program.printed == ["hello"]
    levels = {(r.levelno, r.getMessage().split(": ", 1)[1]) for r in caplog.records if r.name == "sf_tch"}
    assert (logging.ERROR, "Division by zero") in levels and (logging.INFO, "hello") in levels


def test_simulate_keeps_every_part_beyond_the_programs_own():
    # StartCNCEx's addCode sends its M functions before the program: more parts than it has
    add_code = " ".join(f"M{100 + k}" for k in range(40))
    with sf_tch.Core() as core:
        core.compile_text(SQUARE)
        run = core.simulate(add_code=add_code)
        again = core.simulate()
    assert run.m_functions["m_func"].tolist() == list(range(100, 140)) + [30]
    assert len(run) == 5 and again.m_functions["m_func"].tolist() == [30]
    assert run.parts.tobytes() == again.parts.tobytes()


def test_an_error_of_no_file_names_no_place(tmp_path):
    with sf_tch.Core() as core:
        with pytest.raises(sf_tch.CncError) as caught:
            core.compile_file(tmp_path / "missing.nc")
    assert caught.value.number == ErrorNumber.FILE_OPEN
    assert str(caught.value) == f"error 1: Cannot open file '{tmp_path / 'missing.nc'}'"


def test_the_start_position():
    relative = "G91 G1 X10 F600\nG1 Y10\nM30\n"
    with sf_tch.compile(relative, start=(5, 7, 1)) as program:
        rec = program.toolpath.records
        ends = rec["end"][rec["kind"] == sf_tch.PartKind.MOTION]
        assert rec["start"][0].tolist() == [5, 7, 1]
        assert ends.tolist() == [[15, 7, 1], [15, 17, 1]]
        box = program.size_info.m_size[0]
        assert (box.m_minimalPos.x, box.m_maximalPos.y) == (5, 17)
