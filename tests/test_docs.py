"""The documentation stands alone: every link of README.md and docs/ reaches a file of the
repository, every repository path they quote exists, every page of docs/ is reachable from
the README, and nothing cites specification files or vendor documents that live outside
the repository (docs/vendor-sources.md names those documents; the pages restate them)."""
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]

# Folders whose files may not cite what lies outside the repository. toolchain/ joins them
# once its comments are rewritten.
CHECKED = ["README.md", "docs", "python", "abi_check", "examples", "include", "benchmarks", "tests"]
OUTSIDE = re.compile(r"\b(?:API|ABI|GCODE|DESIGN)\.md\b"          # the specification files
                     r"|\.\./shared\b|/work/shared\b|\bshared/(?:spec|seeds|repro|corpus)\b"
                     r"|(?i:\bseeds?\s+0\d\d\b)")                 # the vendor's documents by number

LINK = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)\)")
# a quoted path that starts at a top-level folder of the repository, e.g. `docs/api.md`
TOP = ("docs", "include", "python", "abi_check", "examples", "benchmarks", "tests", "toolchain", ".ci")
QUOTED = re.compile(r"`((?:%s)/[A-Za-z0-9_./-]*)`" % "|".join(re.escape(t) for t in TOP))


def _text_files(entry: str):
    path = ROOT / entry
    files = [path] if path.is_file() else sorted(p for p in path.rglob("*") if p.is_file())
    for f in files:
        if "__pycache__" in f.parts or f.suffix in (".png", ".so", ".pyc"):
            continue
        try:
            yield f, f.read_text(encoding="utf-8")
        except UnicodeDecodeError:
            continue


def _links(page: Path):
    for target in LINK.findall(page.read_text(encoding="utf-8")):
        if re.match(r"[a-z]+:", target) or target.startswith("#"):
            continue                                   # a web address or an anchor on the page
        yield target.split("#", 1)[0]


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.relative_to(ROOT).as_posix())
def test_every_link_reaches_a_file_of_the_repository(page):
    missing = [t for t in _links(page) if not (page.parent / t).resolve().exists()]
    outside = [t for t in _links(page) if ROOT not in (page.parent / t).resolve().parents]
    assert missing == [] and outside == []


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.relative_to(ROOT).as_posix())
def test_every_quoted_repository_path_exists(page):
    quoted = QUOTED.findall(page.read_text(encoding="utf-8"))
    assert [q for q in quoted if "*" not in q and not (ROOT / q).exists()] == []


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.relative_to(ROOT).as_posix())
def test_every_table_row_has_the_cells_of_its_header(page):
    """A stray '|' inside a cell (write it as '\\|') shifts the rest of the row."""
    bad, columns, in_code = [], None, False
    for number, line in enumerate(page.read_text(encoding="utf-8").splitlines(), 1):
        if line.startswith("```"):
            in_code = not in_code
        if in_code or not line.startswith("|"):
            columns = None
            continue
        cells = len(re.split(r"(?<!\\)\|", line.strip())) - 2
        if columns is None:
            columns = cells
        elif cells != columns:
            bad.append(f"line {number}: {cells} cells, the header has {columns}")
    assert bad == []


def test_every_page_is_reachable_from_the_readme():
    linked = {(ROOT / t).resolve() for t in _links(ROOT / "README.md")}
    assert [p.name for p in PAGES[1:] if p.resolve() not in linked] == []


def test_nothing_cites_files_outside_the_repository():
    found = []
    for entry in CHECKED:
        for path, text in _text_files(entry):
            if path == Path(__file__).resolve():
                continue                               # this file holds the pattern itself
            for number, line in enumerate(text.splitlines(), 1):
                if OUTSIDE.search(line):
                    found.append(f"{path.relative_to(ROOT)}:{number}: {line.strip()}")
    assert found == []


def test_the_pattern_finds_what_it_should():
    cited = ["the dialect of GCODE.md", "see ../shared/spec", "/work/shared/repro/fifo.py",
             "Seed 003's example", "seeds 002", "(ABI.md)", "shared/seeds/003.txt"]
    clean = ["docs/api.md", "a shared/exclusive lock", "the seed program", "seed 3 of the storm",
             "SF_TCH_STORM_SEED"]
    assert [c for c in cited if not OUTSIDE.search(c)] == []
    assert [c for c in clean if OUTSIDE.search(c)] == []
