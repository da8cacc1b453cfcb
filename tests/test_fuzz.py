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


# seconds per target: about a minute in all (SF_TCH_SLOW_SCALE multiplies it)
SECONDS = 12 * int(os.environ.get("SF_TCH_SLOW_SCALE", "1"))


@pytest.fixture(scope="module")
def target_binary():
    try:
        return fuzzing.build(log=lambda text: None)
    except fuzzing.Unavailable as why:
        pytest.skip(f"no libFuzzer: {why}")


@pytest.mark.slow
@pytest.mark.timeout(1800)
@pytest.mark.parametrize("target", fuzzing.TARGETS)
def test_fuzz(target_binary, target, tmp_path):
    # from the seeds alone, so that the time stays bounded (a corpus grown by earlier runs
    # would be replayed whole first); runs by hand grow tests/fuzz/corpus
    proc = fuzzing.run(target, SECONDS, binary=target_binary, corpus=tmp_path)
    stats = fuzzing.stats(proc.stderr)
    print(target, stats)
    assert proc.returncode == 0, f"libFuzzer found a defect in {target}:\n{proc.stderr[-12000:]}"
    assert stats.get("number_of_executed_units", 0) > 0, proc.stderr[-3000:]


# ------------------------------------------------------------------ what the fuzzer found
# Each runs in every build, so the ASan + UBSan suite (test_sanitizers) checks it too.

@pytest.mark.parametrize("code, indexes", [
    (b'PRINT "a"\nPRINT "b"\nG1 X1 F100\nG1 X2\n', [4, 6]),
    (b'PRINT "Hello world"\nM29 second text  \nG1 X1\n', [4]),
    (b'G1 X1 F100\nPRINT "a"\nG1 X2\n', [0, 2]),
])
def test_parts_after_a_leading_print_are_numbered_without_overflow(tmp_path, code, indexes):
    """program_number_parts: a part no driver gets (PRINT) before any that one gets took
    INT32_MIN minus its index as the shift of the next (signed overflow, UBSan)."""
    from compiler_host import Host
    host = Host(0, tmp_path)
    try:
        result = host.compile(code)
        assert result.error is None
        assert [p.gindex for p in result.parts if p.kind == "G"] == indexes
    finally:
        host.close()
