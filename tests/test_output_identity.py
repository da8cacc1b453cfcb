"""What a compile produces stays bit for bit what it was when the digests of
tests/output_digests.json were recorded (tests/output_digest.py): the tool path
records, the extents, the run time, the warnings and errors, and on the smaller
programs every part the driver callbacks receive. The speed work on the compile
(docs/benchmarks.md) changes where and when things are computed, never what: the
benchmark's programs of 1,000,000 lines (the CAM job and the long cutting path,
radius 0 and radius 0.15 with strategy 0xA0600) and, when SF_TCH_CORPUS names a
corpus of real programs, each of them in the ISO mode.

A change meant to change an output records the digests again
(`python tests/output_digest.py --record`, with the corpus) and says why."""
import json
import tempfile
from pathlib import Path

import pytest

import output_digest

REFERENCE = json.loads(output_digest.REFERENCE.read_text())


def _compare(found: dict) -> None:
    differ = {name: {k: (REFERENCE[name].get(k), v) for k, v in got.items() if REFERENCE[name].get(k) != v}
              for name, got in found.items()}
    differ = {name: d for name, d in differ.items() if d}
    assert not differ, json.dumps(differ, indent=1)[:4000]


def test_benchmark_programs_compile_as_recorded():
    with tempfile.TemporaryDirectory() as tmp:
        cases = output_digest.cases(Path(tmp), None)
        assert {name for name, _ in cases} <= set(REFERENCE)
        _compare(output_digest.digests(cases))


@pytest.mark.skipif(output_digest.corpus_dir() is None, reason="SF_TCH_CORPUS does not name a corpus directory")
def test_corpus_compiles_as_recorded():
    cases = output_digest.cases(None, output_digest.corpus_dir())
    recorded = {name for name in REFERENCE if name.startswith("corpus/")}
    assert {name for name, _ in cases} == recorded
    _compare(output_digest.digests(cases))
