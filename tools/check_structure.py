"""The structure rules of the library's sources (docs/architecture.md).

The library is one Cython module: toolchain/libSF_TCh.pyx includes every stage's
.pyx, and its own toolchain/libSF_TCh.pxd includes the faces (one .pxd per stage)
first. This script reads that include tree the way Cython does (the .pxd, then the
.pyx, every nested include in place) and fails on

  (a) a name used in a file that comes before the file defining it, unless a face
      declares it (the faces come first: they are the stages' doors);
  (b) a private name (a leading underscore) defined in one file and used, or
      declared, in another;
  (c) a struct, union, enum or ctypedef in a .pyx (types live in the faces);
  (d) a function or variable of one stage used by another stage without a face
      declaring it (a stage: a directory of toolchain/, or a top-level module);
  (e) a name only some files may use (RESTRICTED) used elsewhere: an error is recorded
      by its generated constructor, never by record_error with hand-filled arguments;
  (f) `core.<field>` of a Core field (core.pxd) in a stage its group's "owners:" line
      does not name: the face says who owns each field, the others call its owners;
  (g) a function of a .pyx (a cdef, cpdef or def at column 0 with a body) without a
      docstring: the .pyx keeps what each function does, the face only a line;
  (h) a literal tolerance: a number with a negative exponent (1e-9) in code outside
      the tolerances' face (TOLERANCES): a tolerance is named there, with its unit and
      what it guards; a stage's own constant (a unit, a limit of its own) is named in
      its stage's block. C text (a `cdef extern from *` block's #defines) is not code;
  (i) a struct field or enum member named like an object-like macro of the Windows
      headers (WINDOWS_MACROS: `far`, `near`, `small`, `ERROR` ...): Cython writes
      those names into the C as they are, and the mingw-w64 builds see the macro.

Plain Python, no dependencies; it reads the sources as text, not as Cython does:
top-level definitions start at column 0, a function's parameters and its cdef/for/
assigned locals shadow the globals inside it, and names after a dot are fields.

    python tools/check_structure.py [TOOLCHAIN_DIR] [--root libSF_TCh.pyx]

prints one `file:line: message` per violation; exit status 1 when there is any.
"""
import argparse
import re
import sys
from pathlib import Path

IDENT = re.compile(r"[A-Za-z_]\w*")
INCLUDE = re.compile(r'^\s*include\s+"([^"]+)"')
TYPE_BLOCK = re.compile(r"^(?:cdef|ctypedef)\s+(?:packed\s+)?(struct|union|enum)\b\s*(\w*)")
FUNC_POINTER = re.compile(r"\(\s*\*\s*(\w+)\s*\)")
# name -> the files that may use it, and why
# the face where the tolerances are named, with their units and reasons
TOLERANCES = "geometry.pxd"
# a number with a negative exponent: 1e-9, 2.5E-7, .5e-3
TOLERANCE_LITERAL = re.compile(r"(?<![\w.])(?:\d+\.?\d*|\.\d+)[eE]-\d+(?!\w)")
# object-like macros of <windows.h> and what it includes (windef.h, rpcndr.h,
# objbase.h, winnt.h, wingdi.h) that a C field or enum constant could be named
WINDOWS_MACROS = {"far", "near", "FAR", "NEAR", "small", "hyper", "interface", "pascal", "cdecl", "PASCAL",
                  "CDECL", "IN", "OUT", "OPTIONAL", "CONST", "VOID", "TRUE", "FALSE", "ERROR", "DELETE",
                  "ABSOLUTE", "RELATIVE", "TRANSPARENT", "OPAQUE", "CALLBACK", "WINAPI", "APIENTRY"}
RESTRICTED = {
    "record_error": ({"errors.pyx", "errors.pxd", "catalogue.pxi"},
                     "record an error with its generated constructor (err_...), whose arguments Cython checks"),
}


def strip_code(text: str) -> list:
    """The lines of `text` with comments and string literals blanked (line breaks kept)."""
    out = []
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        if c == "#":
            while i < n and text[i] != "\n":
                i += 1
            continue
        if c in "'\"":
            # a string prefix (b, r, f, u...) directly before the quote goes with it
            j = len(out)
            while j > 0 and out[j - 1] in "bBrRfFuU":
                j -= 1
            if j < len(out) and (j == 0 or not (out[j - 1].isalnum() or out[j - 1] == "_")):
                del out[j:]
            quote = text[i:i + 3] if text[i:i + 3] in ('"""', "'''") else c
            i += len(quote)
            out.append('""')        # where it starts: a string's first line is its statement's
            while i < n and text[i:i + len(quote)] != quote:
                if text[i] == "\\":
                    i += 1
                elif text[i] == "\n":
                    out.append("\n")
                i += 1
            i += len(quote)
            continue
        out.append(c)
        i += 1
    return "".join(out).split("\n")


def logical_lines(lines: list):
    """(first line number, indent, text) of every logical line: brackets join lines."""
    buf, start, depth = [], 0, 0
    for number, line in enumerate(lines, 1):
        if not buf:
            if not line.strip():
                continue
            start = number
        buf.append(line)
        depth += sum(line.count(o) for o in "([{") - sum(line.count(c) for c in ")]}")
        if depth > 0 or line.rstrip().endswith("\\"):
            continue
        text = " ".join(buf)
        yield start, len(text) - len(text.lstrip()), text.strip()
        buf, depth = [], 0


def split_top(text: str, sep: str = ",") -> list:
    """`text` split at `sep` outside brackets."""
    parts, depth, cur = [], 0, []
    for c in text:
        if c in "([{":
            depth += 1
        elif c in ")]}":
            depth -= 1
        if c == sep and depth == 0:
            parts.append("".join(cur))
            cur = []
        else:
            cur.append(c)
    parts.append("".join(cur))
    return parts


def declarator_names(decl: str) -> list:
    """Names declared by `TYPE a, *b = 1, c[3]` (or a function pointer `(*f)(...)`)."""
    names = []
    for k, chunk in enumerate(split_top(decl)):
        chunk = split_top(chunk, "=")[0]
        m = FUNC_POINTER.search(chunk)
        if m:
            names.append(m.group(1))
            continue
        chunk = re.sub(r"\[[^\]]*\]", "", chunk)
        ids = IDENT.findall(chunk)
        if ids:
            names.append(ids[0] if k else ids[-1])
    return names


def typedef_name(rest: str) -> str:
    """The name a ctypedef (without the word) declares: `T name` or `R (*name)(...)`."""
    m = FUNC_POINTER.search(rest)
    return m.group(1) if m else declarator_names(rest)[-1]


def matching_paren(text: str, open_at: int) -> int:
    depth = 0
    for i in range(open_at, len(text)):
        if text[i] == "(":
            depth += 1
        elif text[i] == ")":
            depth -= 1
            if depth == 0:
                return i
    return len(text)


class Source:
    """One file of the include tree: what it defines (name -> line, kind), the types it
    defines, and the global names it uses (name -> the lines)."""

    def __init__(self, path: Path, rel: str, face: bool):
        self.path, self.rel, self.face = path, rel, face
        self.raw = path.read_text(encoding="utf-8").split("\n")
        self.defines = {}       # name -> (line, kind): kind func, inline, declaration, type, value
        self.types = []         # (line, name) of struct/union/enum/ctypedef
        self.uses = {}          # name -> [lines]
        self.includes = []      # (line, relative path)
        self.undocumented = []  # (line, name) of functions whose body opens with no docstring
        self.tolerances = []    # (line, literal) of numbers with a negative exponent in code
        self.windows_names = [] # (line, name) of fields and enum members named like a Windows macro
        for number, line in enumerate(self.raw, 1):
            m = INCLUDE.match(line)
            if m:
                self.includes.append((number, m.group(1)))
        self._parse()

    def _define(self, name, line, kind):
        if name and name not in self.defines:
            self.defines[name] = (line, kind)

    def _use(self, text, line, hidden=()):
        for m in IDENT.finditer(text):
            name = m.group(0)
            before = text[:m.start()].rstrip()
            if before.endswith(".") or name in hidden:
                continue
            self.uses.setdefault(name, []).append(line)

    def _parse(self):
        block = None            # (kind, locals) of the top-level statement being read
        opening = None          # (line, name) of a function whose body has not begun yet
        code = strip_code("\n".join(self.raw))
        for number, text in enumerate(code, 1):
            self.tolerances += [(number, m.group(0)) for m in TOLERANCE_LITERAL.finditer(text)]
        for line, indent, text in logical_lines(code):
            if opening is not None and (indent == 0 or text != '""'):
                self.undocumented.append(opening)       # its first statement is no string
            opening = None
            if indent == 0:
                block = self._top(line, text)
                if block and block[0] == "func":
                    opening = block[2]
                continue
            kind = block[0] if block else None
            if kind == "func":
                self._body(line, text, block[1])
            elif kind == "struct":
                fields = declarator_names(text)
                self.windows_names += [(line, f) for f in fields if f in WINDOWS_MACROS]
                self._use(text, line, hidden=set(fields) | block[1])
            elif kind == "enum":
                member = IDENT.match(text)
                if member:
                    if member.group(0) in WINDOWS_MACROS:
                        self.windows_names.append((line, member.group(0)))
                    self._define(member.group(0), line, "value")
                    self._use(text[member.end():], line)
            elif kind == "extern":
                self._extern(line, indent, text, block)
            else:
                self._use(text, line)

    def _top(self, line, text):
        if re.match(r"(from\s+\S+\s+)?c?import\b", text) or text.startswith("include "):
            return None
        m = TYPE_BLOCK.match(text)
        if m:
            self.types.append((line, m.group(2) or m.group(1)))
            self._define(m.group(2), line, "type")
            return (m.group(1) if m.group(1) != "union" else "struct", set())
        if text.startswith("ctypedef "):
            rest = text[len("ctypedef "):]
            name = typedef_name(rest)
            self.types.append((line, name))
            self._define(name, line, "type")
            self._use(rest, line, hidden={name} | set(self._params(rest)))
            return None
        if text.startswith("cdef extern"):
            return ("extern", {})
        m = re.match(r"(cdef|cpdef|def)\s", text)
        if m:
            return self._declaration(line, text[m.end():], m.group(1))
        self._use(text, line)
        return None

    def _params(self, text):
        """Parameter names of the first parameter list in `text`."""
        start = text.find("(")
        if start < 0:
            return []
        names = []
        for chunk in split_top(text[start + 1:matching_paren(text, start)]):
            names += declarator_names(chunk)
        return names

    def _declaration(self, line, rest, word):
        """A cdef/def at column 0: a function (with a body or declared) or variables."""
        head = rest.split("=", 1)[0]
        m = FUNC_POINTER.search(head)
        paren = head.find("(")
        if paren >= 0 and not (m and m.start() <= paren):
            name = IDENT.findall(head[:paren])[-1]
            params = set(self._params(rest[paren:]))
            body = rest.endswith(":")
            inline = " inline " in f" {head[:paren]} "
            self._define(name, line, ("inline" if inline else "func") if body else "declaration")
            self._use(rest[:paren], line, hidden={name})
            self._use(rest[paren:], line, hidden=params)
            return ("func", params, (line, name)) if body else None
        names = declarator_names(rest)
        for name in names:
            self._define(name, line, "value")
        self._use(rest, line, hidden=set(names))
        return None

    def _body(self, line, text, local):
        m = re.match(r"cdef\s+", text)
        if m:
            names = declarator_names(text[m.end():])
            local.update(names)
        else:
            m = re.match(r"for\s+(.*?)\s+in\s", text)
            if m:
                local.update(IDENT.findall(m.group(1)))
            m = re.match(r"([\w\s,]+?)\s*=(?!=)", text)
            if m:
                local.update(IDENT.findall(m.group(1)))
            for m in re.finditer(r"\bas\s+(\w+)", text):
                local.add(m.group(1))
        self._use(text, line, hidden=local)

    def _extern(self, line, indent, text, block):
        """A line of a `cdef extern` block: a type, a function or variables; the
        lines inside one of its types (deeper than its first line) are fields."""
        top = block[1].setdefault("indent", indent)
        if indent > top:
            return
        m = TYPE_BLOCK.match(text)
        if m or text.startswith("ctypedef "):
            name = m.group(2) if m else typedef_name(text[len("ctypedef "):])
            self.types.append((line, name))
            self._define(name, line, "type")
            return
        paren = text.find("(")
        if paren >= 0 and not FUNC_POINTER.search(text[:paren + 3]):
            self._define(IDENT.findall(text[:paren])[-1], line, "declaration")
        else:
            for name in declarator_names(text):
                self._define(name, line, "declaration")


def include_tree(toolchain: Path, root: str):
    """The files in the order Cython reads them: the module's .pxd (the faces it
    includes, in order), then the .pyx with every include in place. Returns the
    Sources and a position (order of reading) for every (file, line)."""
    sources, positions, seen = [], {}, set()

    def visit(rel, face):
        path = toolchain / rel
        if rel in seen or not path.exists():
            return
        seen.add(rel)
        src = Source(path, rel, face)
        sources.append(src)
        includes = dict(src.includes)
        for number in range(1, len(src.raw) + 1):
            positions[(rel, number)] = len(positions)
            if number in includes:
                visit(includes[number], face or includes[number].endswith(".pxd"))

    pxd = str(Path(root).with_suffix(".pxd"))
    visit(pxd, True)
    visit(root, False)
    return sources, positions


def stage(rel: str) -> str:
    """A file's stage: its directory under toolchain/, else its own name."""
    return rel.split("/")[0] if "/" in rel else rel.rsplit(".", 1)[0]


def private(name: str) -> bool:
    return name.startswith("_") and not name.startswith("__")


CORE_GROUP = re.compile(r"^\s*# -- (.*)$")
OWNERS = re.compile(r"\(owners: ([^;)]*)")
CORE_FIELD_USE = re.compile(r"\bcore\.(\w+)")


def core_owners(source) -> dict:
    """Core's fields (core.pxd, `ctypedef struct Core:`) -> the stages that own them,
    from the `# -- ... (owners: a b c; ...)` line(s) heading each group of fields."""
    owners, current, header, inside = {}, set(), [], False
    for line in source.raw:
        if line.startswith("ctypedef struct Core:"):
            inside = True
            continue
        if not inside:
            continue
        if line and not line[0].isspace():
            break
        group = CORE_GROUP.match(line)
        if group:
            header.append(group.group(1))
            m = OWNERS.search(" ".join(header))
            if m:
                current = set(m.group(1).replace(",", " ").split())
            continue
        header = []
        code = line.split("#", 1)[0].strip()
        if code:
            for name in declarator_names(code):
                owners[name] = current
    return owners


def check(toolchain: Path, root: str = "libSF_TCh.pyx") -> list:
    sources, pos = include_tree(toolchain, root)
    problems = []
    core_face = next((src for src in sources if src.rel == "core.pxd"), None)
    owners = core_owners(core_face) if core_face is not None else {}
    for src in sources:
        code = strip_code("\n".join(src.raw))
        for number, text in enumerate(code, 1):
            for m in CORE_FIELD_USE.finditer(text):
                field = m.group(1)
                if field in owners and stage(src.rel) not in owners[field]:
                    problems.append((src.rel, number, f"core.{field} used by stage {stage(src.rel)}: its owners "
                                     f"({' '.join(sorted(owners[field]))}, core.pxd) have the function to call"))
    first_def = {}          # name -> (position, source) of its first definition or declaration
    definer = {}            # name -> the source that defines it (a body, a type, a value)
    for src in sources:
        for name, (line, kind) in src.defines.items():
            p = pos[(src.rel, line)]
            if name not in first_def or p < first_def[name][0]:
                first_def[name] = (p, src)
            if kind != "declaration":
                definer[name] = src
    for name, (p, src) in first_def.items():
        definer.setdefault(name, src)
    faces = [src for src in sources if src.face]
    for src in sources:
        if not src.face:
            for line, name in src.types:
                problems.append((src.rel, line, f"type {name} defined in a .pyx: it belongs in its stage's face"))
        for name, lines in src.uses.items():
            if name not in first_def:
                continue
            home = definer[name]
            for line in lines:
                p = pos[(src.rel, line)]
                if home is not src and p < first_def[name][0] and name not in src.defines:
                    problems.append((src.rel, line, f"{name} is used before {home.rel} defines it "
                                     "(declare it in a face, or include that file first)"))
                    break
        for name, lines in src.uses.items():
            home = definer.get(name)
            if home is not None and not home.face and stage(home.rel) != stage(src.rel) \
                    and not any(name in face.defines for face in faces) and name not in src.defines:
                problems.append((src.rel, lines[0], f"{name} of {home.rel} is used by another stage: "
                                 "declare it in its stage's face"))
        for name, (line, kind) in src.defines.items():
            if private(name) and definer[name] is not src:
                problems.append((src.rel, line, f"private {name} of {definer[name].rel} declared here: "
                                 "a name other files use must not start with _"))
        for name, lines in src.uses.items():
            if name in RESTRICTED and src.rel not in RESTRICTED[name][0]:
                problems.append((src.rel, lines[0], f"{name} used here: {RESTRICTED[name][1]}"))
        if src.rel != TOLERANCES:
            for line, literal in src.tolerances:
                problems.append((src.rel, line, f"literal {literal}: name it (a tolerance in {TOLERANCES}, with "
                                 "its unit and what it guards; a stage's own constant in its stage's block)"))
        for line, name in src.windows_names:
            problems.append((src.rel, line, f"{name}: a macro of the Windows headers, and Cython writes this "
                             "name into the C as it is (the mingw-w64 builds fail): name it otherwise"))
        if src.rel.endswith(".pyx"):
            for line, name in src.undocumented:
                problems.append((src.rel, line, f"{name} has no docstring: say what it does (and why, "
                                 "where it is not plain) in a line under its signature"))
        for name, lines in src.uses.items():
            if private(name) and name in definer and definer[name] is not src and name not in src.defines:
                problems.append((src.rel, lines[0], f"private {name} of {definer[name].rel} used here: "
                                 "give it a public name and declare it in its face"))
    return sorted(set(problems), key=lambda p: (pos.get((p[0], p[1]), 0), p[2]))


def main(argv=None) -> int:
    here = Path(__file__).resolve().parents[1]
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("toolchain", nargs="?", default=str(here / "toolchain"))
    ap.add_argument("--root", default="libSF_TCh.pyx", help="the module's .pyx inside TOOLCHAIN")
    args = ap.parse_args(argv)
    problems = check(Path(args.toolchain), args.root)
    for rel, line, message in problems:
        print(f"{Path(args.toolchain, rel)}:{line}: {message}")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
