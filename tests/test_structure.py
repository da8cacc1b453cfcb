"""The structure rules of toolchain/ (tools/check_structure.py, docs/architecture.md):
the library keeps them, and the checker finds each kind of violation in small trees."""
import sys
import textwrap
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tools"))

import check_structure  # noqa: E402


def tree(tmp_path: Path, files: dict) -> Path:
    for name, text in files.items():
        path = tmp_path / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
    return tmp_path


def problems(tmp_path: Path, files: dict) -> list:
    return [f"{rel}:{line}: {message}" for rel, line, message in
            check_structure.check(tree(tmp_path, files), "lib.pyx")]


# a small library: lib.pxd includes the face; lib.pyx a stage of two files (the
# second includes a third in the middle of its own text) and a one-file stage
BASE = {name: textwrap.dedent(text).lstrip() for name, text in {
    "lib.pxd": """
        include "face.pxd"
    """,
    "face.pxd": """
        # the face: its types and what other stages call
        ctypedef struct Point:
            double x, y
        cdef enum:
            LIMIT = 4
        cdef double later(double v) noexcept nogil
    """,
    "lib.pyx": """
        include "stage/first.pyx"
        include "stage/second.pyx"
        include "other.pyx"
    """,
    "stage/first.pyx": """
        cdef double early(Point *p) noexcept nogil:
            \"\"\"second_only and _helper in a docstring are no use.\"\"\"
            cdef double second_only = 1.0       # a local named like a later global
            return later(p.x) + LIMIT + second_only   # later: declared by the face
    """,
    "stage/second.pyx": """
        cdef double _helper(double v) noexcept nogil:
            \"\"\"v itself.\"\"\"
            return v
        include "stage/nested.pyx"
        cdef double later(double v) noexcept nogil:
            # a comment before the docstring leaves it the first statement
            r\"\"\"Twice v.\"\"\"
            return _helper(v) + nested(v)
        cdef double second_only(double v) noexcept nogil:
            \"\"\"v past the first.\"\"\"
            return early(NULL) + v
    """,
    "stage/nested.pyx": """
        cdef double nested(double v) noexcept nogil:
            \"\"\"v through the helper.\"\"\"
            return _helper(v)
    """,
    "other.pyx": """
        cdef double other(Point *p) noexcept nogil:
            \"\"\"Another stage's use of the face.\"\"\"
            return later(p.y)                   # another stage: through the face
    """,
}.items()}


def test_the_library_keeps_its_structure(capsys):
    status = check_structure.main([str(ROOT / "toolchain")])
    assert status == 0, capsys.readouterr().out


def test_a_well_formed_tree_passes(tmp_path):
    files = dict(BASE)
    files["stage/second.pyx"] = files["stage/second.pyx"].replace("_helper", "helper")
    files["stage/nested.pyx"] = files["stage/nested.pyx"].replace("_helper", "helper")
    assert problems(tmp_path, files) == []


def test_a_name_used_before_the_file_defining_it(tmp_path):
    files = dict(BASE)
    files["stage/first.pyx"] = files["stage/first.pyx"].replace("return later(p.x)", "return nested(p.x)")
    files["stage/second.pyx"] = files["stage/second.pyx"].replace("_helper", "helper")
    files["stage/nested.pyx"] = files["stage/nested.pyx"].replace("_helper", "helper")
    assert problems(tmp_path, files) == [
        "stage/first.pyx:4: nested is used before stage/nested.pyx defines it (declare it in a face, or include that file first)"]


def test_a_private_name_used_from_another_file(tmp_path):
    # nested.pyx, included inside second.pyx, is another file all the same
    assert problems(tmp_path, BASE) == [
        "stage/nested.pyx:3: private _helper of stage/second.pyx used here: give it a public name and declare it in its face"]


def test_a_private_name_declared_in_a_face(tmp_path):
    files = dict(BASE)
    files["stage/nested.pyx"] = files["stage/nested.pyx"].replace("_helper(v)", "v")
    files["face.pxd"] += "cdef double _helper(double v) noexcept nogil\n"
    assert problems(tmp_path, files) == [
        "face.pxd:7: private _helper of stage/second.pyx declared here: a name other files use must not start with _"]


def test_a_type_in_a_pyx(tmp_path):
    files = dict(BASE)
    files["stage/nested.pyx"] = files["stage/nested.pyx"].replace("_helper(v)", "v")
    files["stage/second.pyx"] += "cdef enum Mode:\n    MODE_A = 1\nctypedef double (*hook)(double) noexcept nogil\n"
    assert problems(tmp_path, files) == [
        "stage/second.pyx:12: type Mode defined in a .pyx: it belongs in its stage's face",
        "stage/second.pyx:14: type hook defined in a .pyx: it belongs in its stage's face"]


def test_the_command_line_prints_file_and_line(tmp_path, capsys):
    assert check_structure.main([str(tree(tmp_path, BASE)), "--root", "lib.pyx"]) == 1
    out = capsys.readouterr().out.splitlines()
    assert out == [f"{tmp_path / 'stage/nested.pyx'}:3: private _helper of stage/second.pyx used here: "
                   "give it a public name and declare it in its face"]


def test_a_function_another_stage_uses_without_a_face(tmp_path):
    files = dict(BASE)
    files["stage/nested.pyx"] = files["stage/nested.pyx"].replace("_helper(v)", "v")
    files["other.pyx"] = files["other.pyx"].replace("later(p.y)", "later(p.y) + nested(p.x)")
    assert problems(tmp_path, files) == [
        "other.pyx:3: nested of stage/nested.pyx is used by another stage: declare it in its stage's face"]


def test_an_error_recorded_by_hand(tmp_path):
    """record_error is the generated constructors' (catalogue.pxi): a stage that calls it
    fills the arguments by hand, which no build checks."""
    files = dict(BASE)
    files["stage/nested.pyx"] = files["stage/nested.pyx"].replace("_helper(v)", "v")
    files["face.pxd"] += "cdef void record_error(double v) noexcept nogil\n"
    files["other.pyx"] = files["other.pyx"].replace("return later(p.y)", "record_error(p.x)\n    return later(p.y)")
    found = problems(tmp_path, files)
    assert len(found) == 1 and found[0].startswith("other.pyx:3: record_error used here: record an error with "
                                                   "its generated constructor")


def test_a_core_field_named_outside_its_owners(tmp_path):
    """core.pxd's groups of Core fields name their owners; another stage calls them."""
    files = {name: textwrap.dedent(text).lstrip() for name, text in {
        "lib.pxd": """
            include "core.pxd"
        """,
        "core.pxd": """
            ctypedef struct Core:
                # -- the lock (owners: core runtime)
                int lock
                # -- what the host set (owners: configuration; lock: it writes,
                # -- the others call it)
                double params, rel_feed
            cdef double config_rel_feed(Core *core) noexcept nogil
        """,
        "lib.pyx": """
            include "configuration.pyx"
            include "exports.pyx"
        """,
        "configuration.pyx": """
            cdef double config_rel_feed(Core *core) noexcept nogil:
                '''The feed override.'''
                return core.rel_feed + core.lock
        """,
        "exports.pyx": """
            cdef double set_feed(Core *core) noexcept nogil:
                '''core.params in a docstring is no use.'''
                # nor in a comment: core.params
                return config_rel_feed(core) + core.params
        """,
    }.items()}
    assert problems(tmp_path, files) == [
        "configuration.pyx:3: core.lock used by stage configuration: its owners (core runtime, core.pxd) "
        "have the function to call",
        "exports.pyx:4: core.params used by stage exports: its owners (configuration, core.pxd) "
        "have the function to call"]


def test_a_function_without_a_docstring(tmp_path):
    """Every function of a .pyx opens with its docstring; a comment or a string later in
    the body is none, and the faces' inline functions and declarations are not asked."""
    files = dict(BASE)
    files["stage/nested.pyx"] = files["stage/nested.pyx"].replace("_helper(v)", "v")
    files["stage/second.pyx"] = files["stage/second.pyx"].replace('    """v itself."""\n', "")
    files["other.pyx"] += ("cdef double commented(double v) noexcept nogil:\n"
                           "    # what it does, in a comment\n"
                           "    cdef double w = v\n"
                           "    \"\"\"too late for a docstring\"\"\"\n"
                           "    return w\n"
                           "def documented(v):\n"
                           "    \"\"\"v unchanged.\"\"\"\n"
                           "    return v\n")
    files["face.pxd"] += "cdef inline double bare(double v) noexcept nogil:\n    return v\n"
    assert problems(tmp_path, files) == [
        "stage/second.pyx:1: _helper has no docstring: say what it does (and why, where it is not plain) "
        "in a line under its signature",
        "other.pyx:4: commented has no docstring: say what it does (and why, where it is not plain) "
        "in a line under its signature"]


def test_a_literal_tolerance(tmp_path):
    """A number with a negative exponent in code is a tolerance without a name: it is
    named in geometry.pxd (the tolerances' face), which alone may write one; C text (a
    #define in a `cdef extern from *` block), comments, docstrings and other numbers
    are not code of that kind."""
    files = dict(BASE)
    files["stage/second.pyx"] = files["stage/second.pyx"].replace("_helper", "helper")
    files["lib.pxd"] += 'include "geometry.pxd"\n'
    files["geometry.pxd"] = textwrap.dedent('''
        cdef extern from *:
            """
            #define TC_NEAR 1e-9
            """
            const double NEAR "TC_NEAR"
        cdef inline bint close(double d) noexcept nogil:
            """Whether d is within 1e-8 of nothing."""
            return d <= 1e-8
    ''').lstrip()
    files["stage/nested.pyx"] = textwrap.dedent('''
        cdef double nested(double v) noexcept nogil:
            """v through the helper, unless it is below 1e-9 (not code)."""
            if v < 1e-9:                        # 1e-9: a comment is no code
                return 0.0
            return helper(v) * 1e6 + NEAR + 2.5E-7 * v / .5e-3
    ''').lstrip()
    assert problems(tmp_path, files) == [
        "stage/nested.pyx:3: literal 1e-9: name it (a tolerance in geometry.pxd, with its unit and "
        "what it guards; a stage's own constant in its stage's block)",
        "stage/nested.pyx:5: literal .5e-3: name it (a tolerance in geometry.pxd, with its unit and "
        "what it guards; a stage's own constant in its stage's block)",
        "stage/nested.pyx:5: literal 2.5E-7: name it (a tolerance in geometry.pxd, with its unit and "
        "what it guards; a stage's own constant in its stage's block)"]


def test_a_field_or_enum_member_named_like_a_windows_macro(tmp_path):
    """Cython writes a struct's fields and an enum's members into the C as they are
    named, and <windows.h> defines `far`, `near`, `small`, `ERROR` ... as macros: the
    mingw-w64 builds would not compile (a clearance field `far` did that). Such names
    elsewhere (a local, a function) are mangled by Cython and pass."""
    files = dict(BASE)
    files["stage/second.pyx"] = files["stage/second.pyx"].replace("_helper", "helper")
    files["face.pxd"] = files["face.pxd"].replace("    double x, y\n", "    double x, y\n    double far\n") \
        .replace("    LIMIT = 4\n", "    LIMIT = 4\n    ERROR = 5\n")
    files["stage/nested.pyx"] = files["stage/nested.pyx"].replace(
        '"""v through the helper."""\n', '"""v through the helper."""\n    cdef double near = v\n') \
        .replace("return _helper(v)", "return helper(near)")
    found = problems(tmp_path, files)
    assert [p.split(": ")[0] for p in found] == ["face.pxd:4", "face.pxd:7"]
    assert found[0].endswith("far: a macro of the Windows headers, and Cython writes this name into the C as it "
                             "is (the mingw-w64 builds fail): name it otherwise")
    assert "ERROR: a macro of the Windows headers" in found[1]
