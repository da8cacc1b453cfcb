"""ABI conformance check of libSF_TCh.

Compares four descriptions of the library's binary interface:

- the C header ``tgm_cnc.h`` (parsed here, then measured by a C probe compiled
  with ``cc`` against it: ``sizeof``/``offsetof``/``_Alignof`` of every field);
- the ctypes mirror ``sf_tch.abi`` (``STRUCTURES`` and ``FUNCTIONS``);
- the built library (``ToolChainCore_GetStructuresSize`` and its exported symbols);
- the sizes the vendor's structures description gives on Linux x86_64
  (:data:`SPEC_SIZES`, written down apart from the header; docs/structures.md).

Both systems: the header's TGM_LPCTSTR is ``char*`` on Linux and ``wchar_t*`` on
Windows x64; :func:`check_layouts` compares the header as a mingw-w64 probe measures
it (run under Wine) with the Windows mirror (``sf_tch.abi.mirror(windows=True)``).
32-bit x86 (``pointer_bits=32``): the header as ``gcc -m32`` or i686 mingw-w64 lays it
out (the latter only compiled, its numbers read from the assembly) against
``sf_tch.abi.mirror(windows, pointer_bits=32)`` and :data:`SPEC_SIZES_32`.

``run()`` returns the list of differences (empty: conformant); ``python -m sf_tch.abi_check``
(installed with the package; ``python -m abi_check`` in a source checkout) also prints a
table and exits non-zero on any difference.
"""
from __future__ import annotations

import ctypes
import os
import re
import shutil
import subprocess
import sys
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

# The sizes the vendor's field order gives on Linux x86_64 (natural alignment, 8-byte
# pointers), written down here apart from the header: an independent check of it.
SPEC_SIZES = {
    "P10DOUBLE": 80, "P10BOOL": 40, "P26FLOAT": 104, "DLL_INIT_STRUCT": 32,
    "SIMPLE_GM_PARAMS": 616, "GM_PARAMS_ENHANCED": 112, "CALLBACK_INFO": 32,
    "MACHINE_STATUS": 52, "GCODE_PARAMETERS": 1112, "GCODE_SIZE": 320, "GCODE_INFO": 1280,
    "MACHINE_PARAMETERS": 448, "GCODE_FEED": 32, "GCODE_CORRECTION": 16,
    "ARC_FEED_TABLE": 16, "INTERNAL_MFUNC_INSERT_TABLE": 24, "AXIS_LIMITS": 24,
}

# The same on 32-bit x86 (Windows x86; Linux i686 gives the same sizes): only the
# structures holding pointers shrink, 4 bytes a pointer.
SPEC_SIZES_32 = {**SPEC_SIZES, "DLL_INIT_STRUCT": 16, "CALLBACK_INFO": 24}

# ToolChainCore_GetStructuresSize: entry [0] is the number of sizes that follow.
STRUCTURES_SIZE_COUNT = 8

# C type names as they appear in the header -> one canonical spelling (Linux; on
# Windows the host's text type is wchar_t).
_C_ALIASES = {
    "TGM_LPCTSTR": "char*", "TGM_LPCSTR": "char*", "TGM_LPTSTR": "char*",
    "intptr_t": "int64_t", "ssize_t": "int64_t", "size_t": "uint64_t",
}
_WINDOWS_ALIASES = {**_C_ALIASES, "TGM_LPCTSTR": "wchar_t*", "TGM_LPTSTR": "wchar_t*"}


# ------------------------------------------------------------------ header parsing

@dataclass
class Field:
    name: str
    ctype: str           # canonical element type ("double", "char*", "P10DOUBLE", ...)
    length: int | None   # array length, None for a scalar

    @property
    def type_text(self) -> str:
        return self.ctype if self.length is None else f"{self.ctype}[{self.length}]"


def _strip_comments(text: str) -> str:
    text = re.sub(r"/\*.*?\*/", " ", text, flags=re.S)
    return re.sub(r"//[^\n]*", " ", text)


def _canonical(ctype: str, windows: bool = False) -> str:
    """'const GCODE_PARAMETERS *' -> 'GCODE_PARAMETERS*', 'TGM_LPCSTR' -> 'char*'."""
    ctype = re.sub(r"\b(const|volatile|struct)\b", " ", ctype)
    stars = ctype.count("*")
    base = ctype.replace("*", " ").split()
    base = " ".join(base)
    base = (_WINDOWS_ALIASES if windows else _C_ALIASES).get(base, base)
    return base + "*" * stars


def parse_structs(header_text: str, windows: bool = False) -> dict[str, list[Field]]:
    """Every ``typedef struct [tag] { ... } NAME;`` of the header, fields in order.
    Handles comma-separated declarators (``double x, y;``) and arrays (``T a[8]``);
    `windows`: the types as they are on Windows x64."""
    text = _strip_comments(header_text)
    structs = {}
    for match in re.finditer(r"typedef\s+struct\s*\w*\s*\{(.*?)\}\s*(\w+)\s*;", text, re.S):
        body, name = match.group(1), match.group(2)
        fields = []
        for decl in body.split(";"):
            decl = " ".join(decl.split())
            if not decl:
                continue
            m = re.match(r"((?:(?:const|unsigned|signed|struct|volatile)\s+)*\w+)\s*(.+)$", decl)
            if not m:
                raise ValueError(f"{name}: cannot parse declaration {decl!r}")
            base, declarators = m.groups()
            for d in declarators.split(","):
                dm = re.fullmatch(r"\s*(\**)\s*(\w+)\s*(?:\[\s*(\d+)\s*\])?\s*", d)
                if not dm:
                    raise ValueError(f"{name}: cannot parse declarator {d!r}")
                stars, fname, length = dm.groups()
                fields.append(Field(fname, _canonical(base + stars, windows), int(length) if length else None))
        structs[name] = fields
    return structs


def parse_prototypes(header_text: str, windows: bool = False) -> dict[str, tuple[str, list[str]]]:
    """Every ``TOOLCHAIN_API ret TOOLCHAIN_CALLTYPE name(args);``: name -> (ret, [arg types])."""
    text = _strip_comments(header_text)
    protos = {}
    pattern = r"TOOLCHAIN_API\s+([\w\s\*]+?)\s*TOOLCHAIN_CALLTYPE\s+(\w+)\s*\(([^)]*)\)\s*;"
    for ret, name, args in re.findall(pattern, text):
        types = []
        for arg in args.split(","):
            arg = " ".join(arg.split())
            if not arg or arg == "void":
                continue
            # drop the parameter name: the last identifier when something precedes it
            m = re.match(r"(.*?[\w\*])\s*\b(\w+)$", arg)
            types.append(_canonical(m.group(1) if m and m.group(1).strip() else arg, windows))
        protos[name] = (_canonical(ret, windows), types)
    return protos


# ------------------------------------------------------------------ ctypes side

_CTYPES_NAMES = [
    (ctypes.c_int32, "int32_t"), (ctypes.c_uint32, "uint32_t"), (ctypes.c_int64, "int64_t"),
    (ctypes.c_uint64, "uint64_t"), (ctypes.c_int16, "int16_t"), (ctypes.c_uint16, "uint16_t"),
    (ctypes.c_int8, "int8_t"), (ctypes.c_uint8, "uint8_t"), (ctypes.c_double, "double"),
    (ctypes.c_float, "float"), (ctypes.c_char_p, "char*"), (ctypes.c_wchar_p, "wchar_t*"), (ctypes.c_void_p, "void*"),
    (ctypes.c_char, "char"),
]


def ctype_name(t) -> str:
    """Canonical C spelling of a ctypes type (same vocabulary as the header parser)."""
    if t is None:
        return "void"
    if getattr(t, "_c_name_", None):         # a stand-in of sf_tch.abi's 32-bit layouts
        return t._c_name_
    for ct, name in _CTYPES_NAMES:
        if t is ct:
            return name
    if isinstance(t, type) and issubclass(t, ctypes.Array):
        return f"{ctype_name(t._type_)}[{t._length_}]"
    if isinstance(t, type) and issubclass(t, ctypes._Pointer):
        return ctype_name(t._type_) + "*"
    if isinstance(t, type) and issubclass(t, (ctypes.Structure, ctypes.Union)):
        return t.__name__
    if hasattr(t, "_argtypes_"):        # CFUNCTYPE
        return "void*"
    return getattr(t, "__name__", repr(t))


# ------------------------------------------------------------------ C probe

NO_COMPILER = "no C compiler found ($CC, cc or gcc on PATH): the C probe cannot measure the header"


def find_compiler() -> str | None:
    """Full path of the C compiler: $CC (a name on PATH or a path), else cc, else gcc."""
    cc = os.environ.get("CC")
    if cc:
        return shutil.which(cc)      # a $CC that does not exist is no compiler, not a fallback
    return shutil.which("cc") or shutil.which("gcc")


def probe(header: str, structs: dict[str, list[Field]], cc: str | None = None, run: tuple = (),
          cflags: tuple = (), compile_only: bool = False) -> dict:
    """Compiles and runs a C program that prints sizeof/_Alignof of every struct and
    offsetof/sizeof of every field, against `header`. Returns
    {struct: {"size": n, "align": n, "fields": {name: (offset, size, align)}}}.
    `cc` may be a cross compiler (mingw-w64: the program is probe.exe), `cflags` its
    options (``-m32``) and `run` the command that runs its program (e.g. Wine's).
    `compile_only`: nothing runs; the numbers are read from the compiler's assembly of
    a constant table (a target this machine cannot run, such as Windows x86 without
    Wine's 32-bit half)."""
    cc = cc or find_compiler()
    if not cc:
        raise RuntimeError(NO_COMPILER)
    header = Path(header).resolve()
    lines = [f'#include "{header.name}"', "#include <stdio.h>", "#include <stddef.h>"]
    values = []            # (kind, struct, field or None, C expressions)
    for name, fields in structs.items():
        values.append(("S", name, None, (f"sizeof({name})", f"_Alignof({name})")))
        for f in fields:
            member = f"(({name} *)0)->{f.name}"
            values.append(("F", name, f.name, (f"offsetof({name}, {f.name})", f"sizeof({member})",
                                              f"_Alignof(__typeof__({member}))")))
    if compile_only:
        exprs = [e for *_, es in values for e in es]
        lines += ["const unsigned int tc_probe_values[] = {", ",\n".join(f"  (unsigned int)({e})" for e in exprs), "};", ""]
    else:
        lines.append("int main(void) {")
        for kind, name, fname, es in values:
            label = f"{kind} {name}" + (f" {fname}" if fname else "")
            lines.append(f'  printf("{label}' + " %zu" * len(es) + '\\n", ' + ", ".join(es) + ");")
        lines += ["  return 0;", "}", ""]
    with tempfile.TemporaryDirectory(prefix="abi_check_") as tmp:
        mingw = "mingw32" in Path(cc).name
        src, exe = Path(tmp) / "probe.c", Path(tmp) / ("probe.exe" if mingw else "probe")
        src.write_text("\n".join(lines))
        out_args = ["-S", "-o", str(Path(tmp) / "probe.s")] if compile_only else ["-o", str(exe)]
        build = subprocess.run([cc, *cflags, "-std=gnu11", "-Wall", *(["-D__USE_MINGW_ANSI_STDIO=1"] if mingw else []),
                                "-I", str(header.parent), str(src), *out_args], capture_output=True, text=True)
        if build.returncode != 0:
            raise RuntimeError(f"probe does not compile against {header}:\n{build.stderr.strip()}")
        if compile_only:
            numbers = _assembled_values((Path(tmp) / "probe.s").read_text())
            out, k = [], 0
            for kind, name, fname, es in values:
                label = f"{kind} {name}" + (f" {fname}" if fname else "")
                out.append(label + "".join(f" {v}" for v in numbers[k:k + len(es)]))
                k += len(es)
            out = "\n".join(out)
        else:
            out = subprocess.run([*run, str(exe)], stdin=subprocess.DEVNULL, capture_output=True, text=True,
                                 check=True).stdout
    result = {}
    for line in out.splitlines():
        kind, *rest = line.split()
        if kind == "S":
            result[rest[0]] = {"size": int(rest[1]), "align": int(rest[2]), "fields": {}}
        else:
            result[rest[0]]["fields"][rest[1]] = tuple(int(v) for v in rest[2:5])
    return result


def _assembled_values(assembly: str) -> list[int]:
    """The 4-byte values of tc_probe_values in GNU assembler output (.long N; a run of
    zeros may be .zero 4n)."""
    body = re.split(r"^_?tc_probe_values:\s*$", assembly, maxsplit=1, flags=re.M)[1]
    numbers = []
    for line in body.splitlines():
        line = line.strip()
        if m := re.fullmatch(r"\.(?:long|int)\s+(\d+)", line):
            numbers.append(int(m[1]))
        elif m := re.fullmatch(r"\.zero\s+(\d+)", line):
            numbers += [0] * (int(m[1]) // 4)
        elif line.startswith(".") and not line.startswith((".long", ".int", ".zero")) or line.endswith(":"):
            if numbers:
                break
    return numbers


# ------------------------------------------------------------------ library side

def library_sizes(lib: ctypes.CDLL) -> tuple[int, list[int]]:
    """(return code, the 9 entries) of ToolChainCore_GetStructuresSize(0, 9, items)."""
    fn = lib.ToolChainCore_GetStructuresSize
    fn.restype = ctypes.c_int32
    fn.argtypes = (ctypes.c_uint32, ctypes.c_uint32, ctypes.POINTER(ctypes.c_uint32))
    items = (ctypes.c_uint32 * 9)(*([0xFFFFFFFF] * 9))
    rc = fn(0, 9, items)
    return rc, list(items)


def exported_symbols(path: str) -> set[str] | None:
    """Defined dynamic symbols of the library (``nm -D``), None without nm."""
    nm = shutil.which("nm")
    if not nm:
        return None
    out = subprocess.run([nm, "-D", "--defined-only", path], capture_output=True, text=True)
    if out.returncode != 0:
        return None
    return {line.split()[-1] for line in out.stdout.splitlines() if line.strip()}


# ------------------------------------------------------------------ the check

@dataclass
class Report:
    rows: list = field(default_factory=list)         # (struct, field, type, c_off, ct_off, c_size, ct_size, status)
    differences: list = field(default_factory=list)

    def diff(self, text: str) -> None:
        self.differences.append(text)


def default_header() -> str:
    try:
        import sf_tch
        path = Path(sf_tch.header_path())
        if path.exists():
            return str(path)
    except Exception:
        pass
    return str(Path(__file__).resolve().parents[1] / "include" / "tgm_cnc.h")


def default_library() -> str:
    import sf_tch
    return sf_tch.library_path()


def check(header: str | None = None, library: str | None = None, structures: dict | None = None,
          functions=None, size_order=None, spec_sizes: dict | None = None) -> Report:
    """The full comparison; see :func:`run`."""
    if structures is None or functions is None or size_order is None:
        from sf_tch import abi
        structures = abi.STRUCTURES if structures is None else structures
        functions = abi.FUNCTIONS if functions is None else functions
        size_order = abi.STRUCTURES_SIZE_ORDER if size_order is None else size_order
    header = header or default_header()
    report = Report()
    text = Path(header).read_text()
    measured = _compare_layouts(report, header, structures, spec_sizes, windows=False, cc=None, run=())

    # library: GetStructuresSize and exports
    library = library or default_library()
    lib = ctypes.CDLL(library)
    rc, items = library_sizes(lib)
    if rc != 0:
        report.diff(f"ToolChainCore_GetStructuresSize returned {rc}, expected 0")
    if items[0] != STRUCTURES_SIZE_COUNT:
        report.diff(f"ToolChainCore_GetStructuresSize[0] = {items[0]}, expected {STRUCTURES_SIZE_COUNT}")
    for i, name in enumerate(size_order, start=1):
        expected = measured.get(name, {}).get("size")
        status = "OK" if items[i] == expected else "DIFF"
        report.rows.append(("GetStructuresSize", f"[{i}] {name}", "uint32_t", "", "", expected, items[i], status))
        if status != "OK":
            report.diff(f"ToolChainCore_GetStructuresSize[{i}] ({name}) = {items[i]}, C sizeof = {expected}")

    protos = parse_prototypes(text)
    table = {name: (restype, argtypes) for name, restype, argtypes in functions}
    for name in sorted(set(protos) - set(table)):
        report.diff(f"{name}: prototype in the header, missing in sf_tch.abi.FUNCTIONS")
    for name in sorted(set(table) - set(protos)):
        report.diff(f"{name}: in sf_tch.abi.FUNCTIONS, no prototype in the header")
    exported = exported_symbols(library)
    for name, (restype, argtypes) in table.items():
        problems = []
        if not hasattr(lib, name):
            problems.append("not exported by the library")
        if name in protos:
            c_ret, c_args = protos[name]
            ct_ret, ct_args = ctype_name(restype), [ctype_name(a) for a in argtypes]
            if c_ret != ct_ret:
                problems.append(f"returns {c_ret} in C, {ct_ret} in ctypes")
            if c_args != ct_args:
                problems.append(f"arguments ({', '.join(c_args)}) in C, ({', '.join(ct_args)}) in ctypes")
        sig = f"{protos[name][0]}({', '.join(protos[name][1])})" if name in protos else "?"
        report.rows.append(("function", name, sig, "", "", "", "", "DIFF" if problems else "OK"))
        for p in problems:
            report.diff(f"{name}: {p}")
    if exported is not None:
        for name in sorted(s for s in exported if s.startswith("ToolChain") and s not in protos):
            report.diff(f"{name}: exported by the library, no prototype in the header")
    return report


def check_layouts(windows: bool, cc: str | None = None, run: tuple = (), header: str | None = None,
                  pointer_bits: int = 64, cflags: tuple = (), compile_only: bool = False) -> Report:
    """Header vs ctypes mirror vs the vendor's sizes, structure by structure, on Linux or (windows)
    on Windows: the probe compiled by `cc` (for Windows a mingw-w64 gcc) with `cflags` and
    run by `run` (Wine), or only compiled (`compile_only`: see probe), the mirror
    sf_tch.abi.mirror(windows, pointer_bits). 32 bits: Windows x86 (i686 mingw-w64) or
    Linux i686 (``cflags=("-m32",)``), the vendor's 32-bit sizes (SPEC_SIZES_32)."""
    from sf_tch import abi
    report = Report()
    structures, _ = abi.mirror(windows, pointer_bits)
    _compare_layouts(report, header or default_header(), structures, SPEC_SIZES_32 if pointer_bits == 32 else SPEC_SIZES,
                     windows, cc, run, cflags, compile_only)
    return report


def _compare_layouts(report: Report, header: str, structures: dict, spec_sizes: dict | None, windows: bool,
                     cc: str | None, run: tuple, cflags: tuple = (), compile_only: bool = False) -> dict:
    """The structures of `header` measured by the probe against the mirror and the
    vendor's sizes; returns the measurements."""
    spec_sizes = SPEC_SIZES if spec_sizes is None else spec_sizes
    parsed = parse_structs(Path(header).read_text(), windows)
    try:
        measured = probe(header, parsed, cc, run, cflags, compile_only)
    except (RuntimeError, subprocess.CalledProcessError) as exc:
        report.diff(f"C probe: {exc}")
        measured = {}
    for name in sorted(set(parsed) - set(structures)):
        report.diff(f"{name}: in the header, missing in the ctypes mirror")
    for name in sorted(set(structures) - set(parsed)):
        report.diff(f"{name}: in the ctypes mirror, missing in the header")
    for name in sorted(set(spec_sizes) - set(parsed)):
        report.diff(f"{name}: a vendor structure, missing in the header")
    for name, fields in parsed.items():
        c = measured.get(name)
        cls = structures.get(name)
        if c is None or cls is None:
            continue
        _compare_struct(report, name, fields, c, cls, spec_sizes.get(name))
    return measured


def _compare_struct(report: Report, name: str, fields: list[Field], c: dict, cls, spec_size) -> None:
    ct_fields = list(getattr(cls, "_fields_", []))
    ct_names = [f[0] for f in ct_fields]
    c_names = [f.name for f in fields]
    if ct_names != c_names:
        report.diff(f"{name}: field names/order differ: header {c_names}, ctypes {ct_names}")
    for extra in [n for n in ct_names if n not in c_names]:
        report.diff(f"{name}.{extra}: in ctypes, missing in the header")
    ct_by_name = {f[0]: f[1] for f in ct_fields}
    end = 0
    for f in fields:
        off, size, align = c["fields"][f.name]
        notes = []
        if off - end >= align:           # the parser must not have skipped a member
            notes.append(f"gap of {off - end} bytes before it")
        end = off + size
        ct_type = ct_by_name.get(f.name)
        if ct_type is None:
            ct_off = ct_size = "-"
            notes.append("missing in ctypes")
        else:
            desc = getattr(cls, f.name)
            ct_off, ct_size = desc.offset, desc.size
            if ct_off != off:
                notes.append(f"offset C {off} ctypes {ct_off}")
            if ct_size != size:
                notes.append(f"size C {size} ctypes {ct_size}")
            if ctype_name(ct_type) != f.type_text:
                notes.append(f"type C {f.type_text} ctypes {ctype_name(ct_type)}")
        report.rows.append((name, f.name, f.type_text, off, ct_off, size, ct_size, "DIFF" if notes else "OK"))
        for n in notes:
            report.diff(f"{name}.{f.name}: {n}")
    if c["size"] - end >= c["align"]:
        report.diff(f"{name}: {c['size'] - end} bytes after the last field (member missed by the parser?)")
    ct_size = ctypes.sizeof(cls)
    notes = []
    if ct_size != c["size"]:
        notes.append(f"sizeof C {c['size']} ctypes {ct_size}")
    if ctypes.alignment(cls) != c["align"]:
        notes.append(f"alignment C {c['align']} ctypes {ctypes.alignment(cls)}")
    if spec_size is not None and c["size"] != spec_size:
        notes.append(f"sizeof C {c['size']}, vendor {spec_size}")
    report.rows.append((name, "(sizeof)", "extension" if spec_size is None else f"vendor {spec_size}", "", "", c["size"], ct_size, "DIFF" if notes else "OK"))
    for n in notes:
        report.diff(f"{name}: {n}")


def run(header: str | None = None, library: str | None = None, **overrides) -> list[str]:
    """The differences between header, ctypes mirror, library and the vendor's sizes (empty
    list: conformant). `overrides` (structures=, functions=, size_order=, spec_sizes=)
    replace the tables of sf_tch.abi / SPEC_SIZES, e.g. to prove a wrong mirror is caught."""
    return check(header, library, **overrides).differences


def format_report(report: Report, diff_only: bool = False) -> str:
    head = ("struct", "field", "type", "C off", "ct off", "C size", "ct size", "")
    shown = [r for r in report.rows if r[-1] != "OK"] if diff_only else report.rows
    rows = [head] + [tuple("" if v is None else str(v) for v in row) for row in shown]
    widths = [max(len(r[i]) for r in rows) for i in range(len(head))]
    lines = ["  ".join(v.ljust(w) if i < 3 else v.rjust(w) for i, (v, w) in enumerate(zip(r, widths))).rstrip()
             for r in rows] if shown else []
    if report.differences:
        lines.append("")
        lines += [f"DIFF {d}" for d in report.differences]
    n_fields = sum(1 for r in report.rows if r[1] != "(sizeof)" and r[0] not in ("function", "GetStructuresSize"))
    n_structs = sum(1 for r in report.rows if r[1] == "(sizeof)")
    n_funcs = sum(1 for r in report.rows if r[0] == "function")
    lines.append(f"abi_check: {n_structs} structures, {n_fields} fields, {n_funcs} functions, "
                 f"{len(report.differences)} difference(s)")
    return "\n".join(lines)
