"""The binary layouts: header, ctypes mirror, library and the vendor's sizes agree (abi_check),
the offsets of the vendor's field order hold field by field (docs/structures.md), and abi_check does catch a wrong mirror. abi_check
is installed as sf_tch.abi_check and runs as ``python -m abi_check`` in the source tree."""
import ctypes
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from sf_tch import abi, abi_check, header_path

ROOT = Path(__file__).resolve().parents[1]

# The offsets the vendor's field order gives on Linux x86_64 (field -> offset), written down
# apart from the header.
SPEC_DLL_INIT_STRUCT = {"CNC_Dll_Dir": 0, "Macros_Dir": 8, "Comm_Int2_Dir": 16, "Local_Core_Mode": 24}

SPEC_SIMPLE_GM_PARAMS = {
    "m_s": 0, "m_e": 80, "m_calcS": 160, "m_calcE": 240, "m_zero": 320, "m_cc": 400, "m_pars": 480,
    "m_func": 584, "m_planeTool": 588, "m_reserved": 592, "m_editorLine": 596, "m_fileIdx": 600,
    "m_gCodeIndex": 604, "m_bFeedIsMin": 608, "m_fp": 612,
}

SPEC_GM_PARAMS_ENHANCED = {
    "m_setFeed": 0, "m_calcFeed": 8, "m_actFeed": 16, "m_relFeed": 24, "m_actPartLen": 32,
    "m_actPartRemain": 40, "m_actWorkPartsLen": 48, "m_actG00PartsLen": 56, "m_actPartsLen": 64,
    "m_nWorkCounter": 72, "m_nG00Counter": 76, "m_nG00ToWorkChanges": 80, "m_nWorkToG00Changes": 84,
    "m_nMCounter": 88, "m_MasterEditorLine": 92, "m_MasterFileIdx": 96, "m_statusCNC": 100,
    "m_cncRunTime": 104,
}

SPEC_CALLBACK_INFO = {"stringId": 0, "nLines": 4, "actLine": 8, "fileIdx": 12, "m_fullError": 16,
                      "m_errorArguments": 24}

SPEC_GCODE_PARAMETERS = {
    "absMode": 0, "swapG2G3": 4, "correctionStrategy": 8, "forceMode": 12, "motion": 16,
    "correction": 272, "maxConnectionDistance": 400, "startAngle": 408, "endAngle": 416,
    "minAngleFeed": 424, "disableG0FeedOverride": 432, "interpolatorConfig0": 436, "overrideInc": 440,
    "arcFeedTable": 448, "centripetalAcc": 528, "mFuncInsertTable": 536, "MfuncInsertType": 608,
    "paddingTo8Bytes_2": 612, "reserved": 616, "M02_programEnd1": 624, "insertArcMode": 704,
    "paddingTo8Bytes_3": 708, "insertArcToleranceRMax": 712, "insertArcToleranceRMin": 720,
    "insertArcMaxAngle": 728, "insertArcMinAngle": 736, "insertArcPlane": 744, "rezerva1": 748,
    "calcTime": 752, "rezerva2": 756, "dynamicG41Correction_mm": 760, "dynamicG42Correction_mm": 768,
    "axisLimits": 776, "dynamicG41Correction_percent": 1016, "dynamicG42Correction_percent": 1024,
    "tolerance": 1032,
}
# M02_programEnd1 ... M99_defFeed: each at 624 + 4*i, in the vendor's order.
SPEC_M_FUNCTIONS = ["M02", "M30", "M03", "M04", "M05", "M06", "M07", "M08", "M09", "M17", "M29",
                    "M80", "M81", "M82", "M83", "M84", "M85", "M86", "M87", "M99"]


@pytest.fixture(scope="module")
def report():
    return abi_check.check()


@pytest.fixture(scope="module")
def probe():
    header = header_path()
    return abi_check.probe(header, abi_check.parse_structs(Path(header).read_text()))


def test_abi_check_finds_no_difference(report):
    assert report.differences == []
    # it did look at everything
    assert {r[0] for r in report.rows} >= set(abi_check.SPEC_SIZES)
    assert sum(1 for r in report.rows if r[0] == "function") == len(abi.FUNCTIONS) == 40 + len(abi.EXTENSION_FUNCTIONS)


def test_spec_sizes_cover_every_structure():
    assert set(abi_check.SPEC_SIZES) == set(abi.STRUCTURES) - set(abi.EXTENSION_STRUCTURES)
    for name, size in abi_check.SPEC_SIZES.items():
        assert ctypes.sizeof(abi.STRUCTURES[name]) == size, name


def test_command_line_exits_zero(run_python):
    proc = run_python("import sys, sf_tch.abi_check.__main__ as m; sys.exit(m.main(['--diff-only']))", check=False)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "0 difference(s)" in proc.stdout


def _module(name: str, cwd, env: dict | None = None) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", name, "--diff-only"], capture_output=True, text=True,
                          cwd=cwd, env=env, timeout=120)


def test_installed_under_the_package_only(tmp_path):
    """Outside the source tree: sf_tch.abi_check runs, no top-level abi_check is installed."""
    proc = _module("sf_tch.abi_check", tmp_path)
    assert proc.returncode == 0 and "0 difference(s)" in proc.stdout, proc.stdout + proc.stderr
    assert Path(abi_check.__file__).parent.parent == Path(abi.__file__).parent
    proc = _module("abi_check", tmp_path)
    assert proc.returncode == 1 and "No module named abi_check" in proc.stderr, proc.stdout + proc.stderr


def test_source_checkout_module():
    proc = _module("abi_check", ROOT)
    assert proc.returncode == 0 and "0 difference(s)" in proc.stdout, proc.stdout + proc.stderr


@pytest.mark.parametrize("cc", [None, "/nonexistent/cc"])
def test_without_a_c_compiler_the_first_line_says_so(tmp_path, cc):
    env = {k: v for k, v in os.environ.items() if k != "CC"}
    env["PATH"] = str(tmp_path)          # an empty directory: no cc, no gcc
    if cc:
        env["CC"] = cc
    for name, cwd in (("sf_tch.abi_check", tmp_path), ("abi_check", ROOT)):
        proc = _module(name, cwd, env)
        first = proc.stdout.splitlines()[0] if proc.stdout else ""
        assert first.startswith(f"{name}: no C compiler found"), proc.stdout + proc.stderr
        assert proc.returncode == 1 and "Traceback" not in proc.stderr, proc.stdout + proc.stderr


SPEC_TABLES = {
    "DLL_INIT_STRUCT": SPEC_DLL_INIT_STRUCT,
    "SIMPLE_GM_PARAMS": SPEC_SIMPLE_GM_PARAMS,
    "GM_PARAMS_ENHANCED": SPEC_GM_PARAMS_ENHANCED,
    "CALLBACK_INFO": SPEC_CALLBACK_INFO,
    "GCODE_PARAMETERS": SPEC_GCODE_PARAMETERS,
}


@pytest.mark.parametrize("struct", sorted(SPEC_TABLES))
def test_spec_offsets(struct, probe):
    cls = abi.STRUCTURES[struct]
    for name, offset in SPEC_TABLES[struct].items():
        assert getattr(cls, name).offset == offset, f"ctypes {struct}.{name}"
        assert probe[struct]["fields"][name][0] == offset, f"C {struct}.{name}"


def test_spec_offsets_of_m_function_numbers(probe):
    for i, name in enumerate(abi.M_FUNCTION_FIELDS):
        assert name.startswith(SPEC_M_FUNCTIONS[i] + "_")
        assert getattr(abi.GCODE_PARAMETERS, name).offset == 624 + 4 * i
        assert probe["GCODE_PARAMETERS"]["fields"][name][0] == 624 + 4 * i
    assert len(abi.M_FUNCTION_FIELDS) == len(SPEC_M_FUNCTIONS)


def test_building_blocks():
    for i, axis in enumerate(("x", "y", "z", "c", "b", "u", "v", "w", "a", "o")):
        assert getattr(abi.P10DOUBLE, axis).offset == 8 * i
        assert getattr(abi.P10BOOL, axis).offset == 4 * i
    for i in range(26):
        assert getattr(abi.P26FLOAT, chr(ord("A") + i)).offset == 4 * i
    assert abi.GCODE_PARAMETERS.motion.size == 8 * 32
    assert abi.GCODE_PARAMETERS.tolerance.size == 10 * 8


def test_library_structures_size(lib):
    items = (ctypes.c_uint32 * 9)()
    assert lib.ToolChainCore_GetStructuresSize(0, 9, items) == 0
    assert list(items) == [8, 1112, 616, 112, 32, 1280, 52, 448, 32]


# ------------------------------------------------------------------ abi_check can fail

class CALLBACK_INFO_MISSING(ctypes.Structure):
    """fileIdx missing (the padding takes its place: sizes and offsets still match)."""
    _fields_ = [("stringId", ctypes.c_int32), ("nLines", ctypes.c_int32), ("actLine", ctypes.c_int32),
                ("m_fullError", ctypes.c_char_p), ("m_errorArguments", ctypes.c_char_p)]


class CALLBACK_INFO_WIDE(ctypes.Structure):
    """nLines 64-bit: every later field moves."""
    _fields_ = [("stringId", ctypes.c_int32), ("nLines", ctypes.c_int64), ("actLine", ctypes.c_int32),
                ("fileIdx", ctypes.c_int32), ("m_fullError", ctypes.c_char_p), ("m_errorArguments", ctypes.c_char_p)]


class ARC_FEED_TABLE_SWAPPED(ctypes.Structure):
    """Same size and offsets, fields swapped: only names/order can tell."""
    _fields_ = [("m_relFeed", ctypes.c_double), ("m_r", ctypes.c_double)]


class GCODE_CORRECTION_SIGNED(ctypes.Structure):
    """Same layout, a float where the header has int32_t."""
    _fields_ = [("size", ctypes.c_double), ("gCode", ctypes.c_float), ("padding1", ctypes.c_int32)]


def _with(**replaced):
    structures = dict(abi.STRUCTURES)
    structures.update(replaced)
    return structures


def test_detects_missing_field():
    diffs = abi_check.run(structures=_with(CALLBACK_INFO=CALLBACK_INFO_MISSING))
    assert "CALLBACK_INFO.fileIdx: missing in ctypes" in diffs
    assert any(d.startswith("CALLBACK_INFO: field names/order differ") for d in diffs), diffs
    assert len(diffs) == 2, diffs


def test_detects_moved_fields():
    diffs = abi_check.run(structures=_with(CALLBACK_INFO=CALLBACK_INFO_WIDE))
    assert "CALLBACK_INFO.nLines: offset C 4 ctypes 8" in diffs
    assert "CALLBACK_INFO.nLines: type C int32_t ctypes int64_t" in diffs
    assert "CALLBACK_INFO.m_errorArguments: offset C 24 ctypes 32" in diffs
    assert "CALLBACK_INFO: sizeof C 32 ctypes 40" in diffs
    assert all(d.startswith("CALLBACK_INFO") for d in diffs), diffs


def test_detects_swapped_fields_and_wrong_types():
    diffs = abi_check.run(structures=_with(ARC_FEED_TABLE=ARC_FEED_TABLE_SWAPPED,
                                           GCODE_CORRECTION=GCODE_CORRECTION_SIGNED))
    assert any("ARC_FEED_TABLE: field names/order differ" in d for d in diffs), diffs
    assert any("ARC_FEED_TABLE.m_r: offset C 0 ctypes 8" in d for d in diffs), diffs
    assert any("GCODE_CORRECTION.gCode: type C int32_t ctypes float" in d for d in diffs), diffs


def test_detects_missing_structure_and_function_table_errors():
    structures = dict(abi.STRUCTURES)
    del structures["AXIS_LIMITS"]
    functions = [f for f in abi.FUNCTIONS if f[0] != "ToolChainCore_MFunc"]
    functions.append(("ToolChainCore_NoSuchFunction", ctypes.c_int32, ()))
    functions = [(n, r, (ctypes.c_int32,) if n == "ToolChainCore_StatusCNC" else a) for n, r, a in functions]
    diffs = abi_check.run(structures=structures, functions=functions)
    assert "AXIS_LIMITS: in the header, missing in the ctypes mirror" in diffs
    assert "ToolChainCore_MFunc: prototype in the header, missing in sf_tch.abi.FUNCTIONS" in diffs
    assert any(d.startswith("ToolChainCore_NoSuchFunction: not exported") for d in diffs), diffs
    assert "ToolChainCore_StatusCNC: arguments (uint32_t) in C, (int32_t) in ctypes" in diffs


def test_detects_wrong_size_order_and_spec():
    order = list(abi.STRUCTURES_SIZE_ORDER)
    order[0], order[1] = order[1], order[0]
    diffs = abi_check.run(size_order=order, spec_sizes={**abi_check.SPEC_SIZES, "GCODE_INFO": 1288})
    assert any(d.startswith("ToolChainCore_GetStructuresSize[1]") for d in diffs), diffs
    assert "GCODE_INFO: sizeof C 1280, vendor 1288" in diffs


def test_detects_a_changed_header(tmp_path):
    text = Path(header_path()).read_text()
    header = tmp_path / "tgm_cnc.h"
    # rename a field and make another double a float: the mirror no longer matches
    changed = re.sub(r"double m_relFeed;(\s*\} ARC_FEED_TABLE;)", r"double m_relFeedX;\1", text)
    changed = changed.replace("double maxDec;", "float maxDec;")
    assert changed.count("m_relFeedX") == 1 and "float maxDec;" in changed
    header.write_text(changed)
    diffs = abi_check.run(header=str(header))
    assert any("ARC_FEED_TABLE: field names/order differ" in d for d in diffs), diffs
    assert any(d.startswith("AXIS_LIMITS.maxDec:") for d in diffs), diffs
    # a field less that the padding hides: same offsets, only the names tell
    assert "int32_t  rezerva2;" in text
    header.write_text(text.replace("int32_t  rezerva2;", ""))
    diffs = abi_check.run(header=str(header))
    assert len(diffs) == 2 and "GCODE_PARAMETERS.rezerva2: in ctypes, missing in the header" in diffs, diffs
    # 8 bytes less: the header's own static asserts stop the probe
    assert "double   reserved;" in text
    header.write_text(text.replace("double   reserved;", ""))
    diffs = abi_check.run(header=str(header))
    assert any(d.startswith("C probe:") and "GCODE_PARAMETERS" in d for d in diffs), diffs


def test_command_line_fails_on_a_difference(tmp_path, run_python):
    header = tmp_path / "tgm_cnc.h"
    text = Path(header_path()).read_text()
    header.write_text(re.sub(r"int32_t(\s+)nLines;", r"int32_t\1nLinesRenamed;", text))
    proc = run_python(f"import sys, sf_tch.abi_check.__main__ as m; sys.exit(m.main(['--header', {str(header)!r}]))",
                      check=False)
    assert proc.returncode == 1, proc.stdout + proc.stderr
    assert "CALLBACK_INFO" in proc.stdout and "DIFF" in proc.stdout


def test_parser_handles_declarator_lists_and_arrays():
    structs = abi_check.parse_structs("""
        typedef struct A { double x, y , z; /* c */ int32_t n[3], m; // x
                           const char *s, **t; } A;
        typedef struct { GCODE_FEED motion[8]; } B;
    """)
    assert [(f.name, f.type_text) for f in structs["A"]] == [
        ("x", "double"), ("y", "double"), ("z", "double"), ("n", "int32_t[3]"), ("m", "int32_t"),
        ("s", "char*"), ("t", "char**")]
    assert [(f.name, f.type_text) for f in structs["B"]] == [("motion", "GCODE_FEED[8]")]
