"""Coverage-guided fuzzing (libFuzzer, tests/fuzz/): the compiler in TG's dialect and in
the ISO mode, the TAB0.KOR, ACHS3D??.KOR and INI readers, each for a bounded time from
the repository's programs and files, under ASan, UBSan and float-cast-overflow. A crash, a leak, a sanitizer
report, a timeout (10 s for one input) or an allocation beyond 2 GB fails the test with
libFuzzer's report and the input. Skipped, saying why, without clang's libFuzzer; a
longer run by hand: docs/testing.md, "Fuzzing"."""
import os
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent / "fuzz"))
import fuzzing  # noqa: E402

pytestmark = [pytest.mark.slow, pytest.mark.timeout(1800)]

# seconds per target: about a minute in all (SF_TCH_SLOW_SCALE multiplies it)
SECONDS = 12 * int(os.environ.get("SF_TCH_SLOW_SCALE", "1"))


@pytest.fixture(scope="module")
def target_binary():
    try:
        return fuzzing.build(log=lambda text: None)
    except fuzzing.Unavailable as why:
        pytest.skip(f"no libFuzzer: {why}")


@pytest.mark.parametrize("target", fuzzing.TARGETS)
def test_fuzz(target_binary, target, tmp_path):
    # from the seeds alone, so that the time stays bounded (a corpus grown by earlier runs
    # would be replayed whole first); runs by hand grow tests/fuzz/corpus
    proc = fuzzing.run(target, SECONDS, binary=target_binary, corpus=tmp_path)
    stats = fuzzing.stats(proc.stderr)
    print(target, stats)
    assert proc.returncode == 0, f"libFuzzer found a defect in {target}:\n{proc.stderr[-12000:]}"
    assert stats.get("number_of_executed_units", 0) > 0, proc.stderr[-3000:]
