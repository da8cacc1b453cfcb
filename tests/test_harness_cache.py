"""The test harness's build cache (tests/harness): one build per source state, shared
by parallel processes, rebuilt when a source changes; the compiler is replaced by a
stand-in that records its calls."""
import os
import threading
import time

import pytest

import harness

pytestmark = pytest.mark.harness     # the harness's build code, not the library


@pytest.fixture
def sources(tmp_path, monkeypatch):
    """A source tree of the harness's shape in tmp_path, an empty cache, and the list
    of builds the stand-in made."""
    root = tmp_path / "root"
    (root / "toolchain").mkdir(parents=True)
    (root / "include").mkdir()
    (root / "toolchain" / "stage.pyx").write_text("cdef int a\n")
    (root / "include" / "api.h").write_text("int a;\n")
    here = root / "tests" / "harness"
    here.mkdir(parents=True)
    (here / "stages.pyx").write_text('include "libSF_TCh.pyx"\n')
    monkeypatch.setattr(harness, "ROOT", root)
    monkeypatch.setattr(harness, "HERE", here)
    monkeypatch.setenv("SF_TCH_HARNESS_CACHE", str(tmp_path / "cache"))
    builds = []

    def build(target, opt):
        builds.append((target.name, opt))
        time.sleep(0.2)                 # long enough for the other threads to arrive
        scratch = target.with_name("scratch")
        scratch.mkdir()
        scratch.rename(target)

    monkeypatch.setattr(harness, "_build", build)
    return root, builds


def test_parallel_loads_build_once(sources):
    root, builds = sources
    paths = []
    threads = [threading.Thread(target=lambda: paths.append(harness.built())) for _ in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert len(builds) == 1 and len(set(paths)) == 1 and len(paths) == 4
    assert harness.built() == paths[0] and len(builds) == 1


def test_a_changed_source_or_optimisation_builds_again(sources):
    root, builds = sources
    first = harness.built()
    (root / "toolchain" / "stage.pyx").write_text("cdef int b\n")
    second = harness.built()
    third = harness.built("-O3")
    assert len({first, second, third}) == 3 and len(builds) == 3
    assert [opt for _, opt in builds] == ["-O1", "-O1", "-O3"]


def test_builds_unused_for_a_week_are_removed(sources):
    root, builds = sources
    old = harness.built().parent
    week_ago = time.time() - harness.STALE_SECONDS - 60
    os.utime(old, (week_ago, week_ago))
    (root / "include" / "api.h").write_text("int b;\n")
    new = harness.built().parent
    assert new.exists() and not old.exists() and not os.path.exists(f"{old}.lock")
