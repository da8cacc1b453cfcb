"""Every host loads the same libSF_TCh.so (docs/hosts.md): the library needs no Python;
bare ctypes in each CPython >= 3.9 on the machine and the C example
examples/c_hmi (dlopen, no libpython) get the results of the package's own run
(sf_tch.core.Core in this process) on the bundled sample and on the seed program."""
import functools
import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import sf_tch
from compiler_host import SEED_PROGRAM
from sf_tch import abi
from sf_tch.core import CncError, Core, default_ini, sample_program

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "examples" / "c_hmi" / "c_hmi.c"


def tool(name):
    path = shutil.which(name)
    if path is None:
        pytest.skip(f"no {name} on this machine")
    return path


def header_prototypes() -> set:
    """Names of the functions the header declares (its exports by definition)."""
    text = Path(sf_tch.header_path()).read_text()
    return set(re.findall(r"^TOOLCHAIN_API\b[^;(]*?\b(\w+)\s*\(", text, flags=re.M))


def dynamic_symbols(path, *flags) -> list:
    out = subprocess.run([tool("nm"), "-D", *flags, path], capture_output=True, text=True, check=True).stdout
    return [line.split()[-1].split("@")[0] for line in out.splitlines() if line.strip()]


# ------------------------------------------------------------ the file itself

def test_the_library_references_no_python(lib_path):
    undefined = dynamic_symbols(lib_path, "--undefined-only")
    assert "strtod" in undefined                     # the listing works
    assert [s for s in undefined if s.startswith(("Py", "_Py"))] == []
    needed = subprocess.run([tool("readelf"), "-d", lib_path], capture_output=True, text=True,
                            check=True).stdout
    assert "NEEDED" in needed and "libpython" not in needed
    # the whole dependency tree, as the dynamic loader resolves it
    tree = subprocess.run([tool("ldd"), lib_path], capture_output=True, text=True, check=True).stdout
    assert "libc.so" in tree and "libpython" not in tree


def test_the_library_exports_the_header_and_tgm_data_only(lib_path):
    exported = set(dynamic_symbols(lib_path, "--defined-only"))
    assert len(header_prototypes()) >= 40
    assert exported == header_prototypes() | {"TGM_Data"}


def test_the_library_is_no_python_module(lib_path, tmp_path):
    """The Cython module code is gone: an import fails cleanly instead of running a
    module init built for another interpreter."""
    shutil.copy(lib_path, tmp_path / "libSF_TCh.so")
    proc = subprocess.run([sys.executable, "-c", "import libSF_TCh"], cwd=tmp_path, capture_output=True,
                          text=True, timeout=60)
    assert proc.returncode == 1
    assert "does not define module export function (PyInit_libSF_TCh)" in proc.stderr


# ------------------------------------------------------------ one run, three hosts

def summary(run: dict, cores: int = 1) -> tuple[list, str]:
    """The stdout lines and the stderr of examples/c_hmi (with --parts) for a run, done
    on `cores` cores at once (each core's report under a line "core k")."""
    lines = [f"library:       {run['version']}", f"cores:         {run['cores']}"]
    error = ""
    if run["error"] is not None:
        file, line, number, text = run["error"]
        error = f"{file}:{line}: error {number}: {text}\n"
    body = [] if error else core_summary(run)
    for k in range(cores):
        lines += ([f"core {k}"] if cores > 1 else []) + body
    return lines, error * cores


def core_summary(run: dict) -> list:
    lines = []
    cut = rapid = 0.0
    n_cut = n_rapid = 0
    for k, (func, line, ex, ey, ez, cx, cy, length) in enumerate(run["parts"]):
        if func != 0:
            cut, n_cut = cut + length, n_cut + 1
        else:
            rapid, n_rapid = rapid + length, n_rapid + 1
        lines.append(f"part {k}: G{func} line {line} end X {ex:.9g} Y {ey:.9g} Z {ez:.9g} "
                     f"compensated X {cx:.9g} Y {cy:.9g} length {length:.9g}")
    lines += [f"program:       {run['program']}", f"status:        {run['status']}",
              f"parts:         {len(run['parts'])} motion, {run['m_functions']} M functions",
              f"cut length:    {cut:.6f} mm in {n_cut} parts",
              f"rapid length:  {rapid:.6f} mm in {n_rapid} parts"]
    for title, (x0, x1, y0, y1, z0, z1) in zip(("programmed:", "compensated:"), run["boxes"]):
        lines.append(f"box {title:<13} X {x0:.6f}..{x1:.6f}  Y {y0:.6f}..{y1:.6f}  Z {z0:.6f}..{z1:.6f}")
    lines.append(f"run time:      {run['run_time']:.6f} s (estimate)")
    lines += [f"PRINT:         {text}" for text in run["printed"]]
    lines.append("errors:        none")
    return lines


def part_row(p) -> list:
    return [int(p.m_func), int(p.m_editorLine), float(p.m_e.x), float(p.m_e.y), float(p.m_e.z),
            float(p.m_calcE.x), float(p.m_calcE.y), float(p.m_pars.N)]


def boxes(info) -> list:
    return [[s.m_minimalPos.x, s.m_maximalPos.x, s.m_minimalPos.y, s.m_maximalPos.y,
             s.m_minimalPos.z, s.m_maximalPos.z] for s in info.m_size[:2]]


def package_run(lib, program: str, abs_mode: int | None = None, radius: float = 1.0) -> dict:
    """The run through the package (sf_tch.core.Core) in this process, from the
    position of a fresh process (0 on every axis)."""
    run = {"version": lib.ToolChainCore_GetVersionString(0).decode(), "program": program, "error": None}
    with Core(0, default_ini()) as core:
        run["cores"] = core.cores
        p = core.params
        for k in range(8):
            p.correction[k].size = radius
        if abs_mode is not None:
            p.absMode = abs_mode
        core.params = p
        core.reset([0.0] * 10)
        try:
            core.compile_file(program)
            result = core.simulate()
        except CncError as error:
            run["error"] = [error.file, error.line, error.number, error.text]
            return run
        records = [abi.SIMPLE_GM_PARAMS.from_buffer_copy(r.tobytes()) for r in result.parts]
        run.update(status=core.status, parts=[part_row(p) for p in records],
                   m_functions=len(result.m_functions), boxes=boxes(core.size_info()),
                   run_time=core.run_time(), printed=result.printed)
    return run


@pytest.fixture(scope="module")
def c_hmi(tmp_path_factory):
    """examples/c_hmi built with the system cc, without libpython."""
    cc = tool("cc")
    exe = tmp_path_factory.mktemp("c_hmi") / "c_hmi"
    subprocess.run([cc, "-std=c11", "-O2", "-Wall", "-Wextra", "-Werror",
                    "-I", str(Path(sf_tch.header_path()).parent), str(EXAMPLE), "-o", str(exe),
                    "-ldl", "-lpthread"], check=True, timeout=120)
    needed = subprocess.run([tool("readelf"), "-d", str(exe)], capture_output=True, text=True).stdout
    assert "libpython" not in needed and "libSF_TCh" not in needed
    return exe


def run_c_hmi(exe, lib_path, program, *options, cwd, ini=None, env=None):
    return subprocess.run([str(exe), lib_path, ini or default_ini(), program, "--parts", *options],
                          capture_output=True, text=True, timeout=120, cwd=cwd,
                          env={**os.environ, **(env or {})})


@pytest.fixture(scope="module")
def seed_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("seed") / "seed.nc"
    path.write_text(SEED_PROGRAM)
    return str(path)


# name: (program, absMode or None for the INI's, tool radius)
CASES = {"sample": ("sample", None, 1.0), "seed relative": ("seed", 0, 1.0),
         "seed absolute (error)": ("seed", 1, 1.0), "sample, tool too big (error)": ("sample", None, 6.0)}


def case_args(case, seed_file):
    program, abs_mode, radius = CASES[case]
    return (sample_program() if program == "sample" else seed_file), abs_mode, radius


@pytest.mark.parametrize("cores, pollers", [(1, 0), (1, 3), (3, 3)])
@pytest.mark.parametrize("case", CASES)
def test_c_program_gets_the_package_results(fresh_core, c_hmi, lib_path, seed_file, tmp_path, case, cores,
                                            pollers):
    """On one core, or on three cores at once from three host threads; with none or
    three more threads polling StatusCNC + GetPos meanwhile."""
    program, abs_mode, radius = case_args(case, seed_file)
    expected = package_run(fresh_core, program, abs_mode, radius)
    options = ["--radius", repr(radius), "--cores", str(cores), "--pollers", str(pollers)]
    if abs_mode is not None:
        options += ["--abs-mode", str(abs_mode)]
    proc = run_c_hmi(c_hmi, lib_path, program, *options, cwd=tmp_path)
    lines, error = summary(expected, cores)
    assert proc.stdout.splitlines() == lines
    assert proc.returncode == (1 if error else 0), proc.stderr
    if pollers:
        assert re.fullmatch(r"c_hmi: 3 threads polled StatusCNC \+ GetPos \d+ times\n",
                            proc.stderr.replace(error, "")), proc.stderr
    else:
        assert proc.stderr == error


def test_the_package_run_is_the_documented_one(fresh_core, seed_file):
    """The oracle itself against the figures of test_cli and test_compiler."""
    sample = package_run(fresh_core, sample_program())
    assert len(sample["parts"]) == 47 and sample["m_functions"] == 16
    assert sample["boxes"][1][:4] == pytest.approx([-1.0, 121.0, -8.0, 81.0])
    assert sample["printed"] == ["plate done"]
    seed = package_run(fresh_core, seed_file, abs_mode=1)
    assert seed["error"][1:3] == [4, 400]
    assert seed["error"][3].startswith("Wrongly entered centre of circular interpolation XY\nStart X = 60.6051 ")


# A C++ host: the header compiled as C++17, every function typed by decltype of its
# prototype; compiles argv[2] (absMode argv[3]) and prints the extents, or the error.
CPP_HOST = r"""
#include <dlfcn.h>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <thread>
#include "tgm_cnc.h"

template <typename F> F lookup(void *lib, const char *name) {
    void *fn = dlsym(lib, name);
    if (!fn) { std::fprintf(stderr, "missing %s\n", name); std::exit(2); }
    return reinterpret_cast<F>(fn);
}
#define LOOKUP(lib, name) lookup<decltype(&name)>(lib, #name)

int main(int argc, char **argv) {
    void *lib = dlopen(argv[1], RTLD_NOW | RTLD_LOCAL);
    if (!lib) { std::fprintf(stderr, "%s\n", dlerror()); return 2; }
    auto get_params = LOOKUP(lib, ToolChainCore_GetGCodeParameters);
    auto set_params = LOOKUP(lib, ToolChainCore_SetGCodeParameters);
    auto compile = LOOKUP(lib, ToolChainCore_CompileFromFile);
    auto status = LOOKUP(lib, ToolChainCore_StatusCNC);
    auto last_error = LOOKUP(lib, ToolChainCore_GetLastError);
    auto size_info = LOOKUP(lib, ToolChainCore_GetGCodeSizeInfo);
    GCODE_PARAMETERS params{};
    get_params(1, &params);
    params.absMode = std::atoi(argv[3]);
    if (set_params(1, &params) != TOOL_CHAIN_SUCCESS || compile(1, argv[2]) != TOOL_CHAIN_SUCCESS) return 2;
    while (status(1) == CNC_STATUS_COMPILING)
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    CALLBACK_INFO info{};
    if (last_error(1, &info) == 1) {
        std::printf("error %d line %d\n", info.stringId, info.actLine);
        return 1;
    }
    GCODE_INFO extents{};
    size_info(1, &extents);
    for (const GCODE_SIZE &s : extents.m_size)
        std::printf("%.17g %.17g %.17g %.17g\n", s.m_minimalPos.x, s.m_maximalPos.x,
                    s.m_minimalPos.y, s.m_maximalPos.y);
    return 0;
}
"""


@pytest.mark.parametrize("abs_mode", [0, 1])
def test_a_cpp_host_gets_the_package_results(fresh_core, lib_path, seed_file, tmp_path, abs_mode):
    cxx = tool("c++")
    source, exe = tmp_path / "host.cpp", tmp_path / "host"
    source.write_text(CPP_HOST)
    subprocess.run([cxx, "-std=c++17", "-O1", "-Wall", "-Werror", "-I", str(Path(sf_tch.header_path()).parent),
                    str(source), "-o", str(exe), "-ldl", "-pthread"], check=True, timeout=120)
    proc = subprocess.run([str(exe), lib_path, seed_file, str(abs_mode)], capture_output=True, text=True,
                          timeout=120, cwd=tmp_path)
    with Core(1, default_ini()) as core:
        core.update_params(absMode=abs_mode)
        core.reset([0.0] * 10)                  # the position of a fresh process
        try:
            core.compile_file(seed_file)
        except CncError as error:
            assert (proc.returncode, proc.stdout) == (1, f"error {error.number} line {error.line}\n")
            return
        expected = "".join(f"{s.m_minimalPos.x:.17g} {s.m_maximalPos.x:.17g} "
                           f"{s.m_minimalPos.y:.17g} {s.m_maximalPos.y:.17g}\n" for s in core.size_info().m_size)
    assert (proc.returncode, proc.stdout) == (0, expected), proc.stderr


def test_a_decimal_comma_locale_of_the_host_changes_nothing(c_hmi, lib_path, seed_file, comma_locale, tmp_path):
    """GUI toolkits set the process's locale from the environment (setlocale(LC_ALL,
    "")): the library's threads then run in it, and numbers must not change."""
    name, env = comma_locale
    ini = tmp_path / "radius.ini"
    ini.write_text(Path(default_ini()).read_text() + "correction0=1.5\ncorrection1=1.5\n")
    long_number = tmp_path / "long_number.nc"        # more digits than the lexer's exact path takes
    long_number.write_text("G1 X12.50000000000000000000 Y1 F1000\n")
    for program, options, config in ((seed_file, ["--abs-mode", "1"], None), (sample_program(), [], str(ini)),
                                     (str(long_number), [], None)):
        plain = run_c_hmi(c_hmi, lib_path, program, *options, cwd=tmp_path, ini=config)
        host = run_c_hmi(c_hmi, lib_path, program, "--host-locale", *options, cwd=tmp_path, ini=config,
                         env=dict(env, LC_ALL=name))
        assert (host.returncode, host.stdout, host.stderr) == (plain.returncode, plain.stdout, plain.stderr)


# bare ctypes: no sf_tch import; the structure layouts come from the ctypes mirror
# abi.py loaded by its path (it needs nothing but ctypes)
BARE_CTYPES_RUN = r"""
import ctypes, importlib.util, json, sys, time
lib_path, abi_path, ini, program, abs_mode, radius = sys.argv[1:7]
spec = importlib.util.spec_from_file_location("tgm_abi", abi_path)
abi = importlib.util.module_from_spec(spec)
spec.loader.exec_module(abi)
lib = ctypes.CDLL(lib_path)
for name, restype, argtypes in abi.FUNCTIONS:
    getattr(lib, name).restype, getattr(lib, name).argtypes = restype, argtypes

def wait():
    deadline = time.monotonic() + 120
    while lib.ToolChainCore_IsBusy(0) > 0:
        assert time.monotonic() < deadline
        time.sleep(0.001)

def error():
    info = abi.CALLBACK_INFO()
    if lib.ToolChainCore_GetLastError(0, ctypes.byref(info)) != 1:
        return None
    return [lib.ToolChainCore_IdxToFile(0, info.fileIdx).decode(), info.actLine, info.stringId,
            info.m_fullError.decode()]

run = {"python": list(sys.version_info[:2]), "version": lib.ToolChainCore_GetVersionString(0).decode(),
       "program": program, "error": None}
init = abi.DLL_INIT_STRUCT(b".", b".", b".", 2)
assert lib.ToolChainCore_Init(ctypes.byref(init)) == 0
cores = ctypes.c_uint32()
assert lib.ToolChainCore_LoadFromIni(0, ini.encode(), ctypes.byref(cores)) == 0
run["cores"] = cores.value
p = abi.GCODE_PARAMETERS()
lib.ToolChainCore_GetGCodeParameters(0, ctypes.byref(p))
for k in range(8):
    p.correction[k].size = float(radius)
if abs_mode != "ini":
    p.absMode = int(abs_mode)
assert lib.ToolChainCore_SetGCodeParameters(0, ctypes.byref(p)) == 0
assert lib.ToolChainCore_CompileFromFile(0, program.encode()) == 0
wait()
run["error"] = error()
if run["error"] is None:
    parts, m_functions, printed = [], [], []
    def on_g(user, part):
        q = part.contents
        parts.append([q.m_func, q.m_editorLine, q.m_e.x, q.m_e.y, q.m_e.z, q.m_calcE.x, q.m_calcE.y,
                      q.m_pars.N])
        return 0
    def on_m(user, part):
        m_functions.append(part.contents.m_func)
        return 0
    def on_output(user, tab, text, info):
        if tab & 0xFF == 2:
            printed.append(text.decode())
        return 0
    keep = (abi.DriverGFunc(on_g), abi.DriverMFunc(on_m), abi.AddOutputLog(on_output))
    for number, fn in zip((abi.CB_DRIVER_G_FUNC, abi.CB_DRIVER_M_FUNC, abi.CB_ADD_OUTPUT_LOG), keep):
        assert lib.ToolChainCore_SetCallBack(0, number, 0, ctypes.cast(fn, ctypes.c_void_p)) == 0
    lib.ToolChainCore_ResetCNC(0, 1, 0, None)
    assert lib.ToolChainCore_StartCNCEx(0, 10, None) == 0
    wait()
    run["error"] = error()
    info, enh = abi.GCODE_INFO(), abi.GM_PARAMS_ENHANCED()
    lib.ToolChainCore_GetGCodeSizeInfo(0, ctypes.byref(info))
    lib.ToolChainCore_GetPos(0, 0, None, ctypes.byref(enh))
    run.update(status=lib.ToolChainCore_StatusCNC(0), parts=parts, m_functions=len(m_functions),
               boxes=[[s.m_minimalPos.x, s.m_maximalPos.x, s.m_minimalPos.y, s.m_maximalPos.y,
                       s.m_minimalPos.z, s.m_maximalPos.z] for s in info.m_size[:2]],
               run_time=enh.m_cncRunTime, printed=printed)
assert lib.ToolChainCore_DestroyCNC(0) == 0
run["modules"] = sorted(m for m in sys.modules if "sf_tch" in m or "SF_TCh" in m)
print(json.dumps(run))
"""


@functools.lru_cache(maxsize=None)
def find_cpython(minor: int) -> str | None:
    """A CPython 3.<minor> of this machine: on PATH or under pyenv's versions."""
    pyenv = Path(os.environ.get("PYENV_ROOT", Path.home() / ".pyenv"))
    candidates = [shutil.which(f"python3.{minor}")]
    candidates += sorted(str(p) for p in pyenv.glob(f"versions/3.{minor}.*/bin/python3.{minor}"))
    for exe in filter(None, candidates):
        try:
            out = subprocess.run([exe, "-c", "import platform, sys; "
                                  "print(platform.python_implementation(), *sys.version_info[:2])"],
                                 capture_output=True, text=True, timeout=30).stdout.split()
        except OSError:
            continue
        if out == ["CPython", "3", str(minor)]:
            return exe
    return None


@pytest.mark.parametrize("minor", [9, 10, 11, 12, 13, 14])
@pytest.mark.parametrize("case", CASES)
def test_bare_ctypes_in_each_cpython_gets_the_package_results(fresh_core, lib_path, seed_file, tmp_path,
                                                                case, minor):
    exe = find_cpython(minor)
    if exe is None:
        pytest.skip(f"no CPython 3.{minor} on this machine (PATH, pyenv)")
    program, abs_mode, radius = case_args(case, seed_file)
    expected = package_run(fresh_core, program, abs_mode, radius)
    proc = subprocess.run([exe, "-I", "-c", BARE_CTYPES_RUN, lib_path, abi.__file__, default_ini(), program,
                           "ini" if abs_mode is None else str(abs_mode), repr(radius)],
                          capture_output=True, text=True, timeout=120, cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    run = json.loads(proc.stdout)
    assert run.pop("python") == [3, minor]
    assert run.pop("modules") == []
    assert summary(run) == summary(expected)
