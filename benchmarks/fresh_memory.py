"""How fast this machine backs fresh memory: the cost a compile pays for every new byte.

    python benchmarks/fresh_memory.py [--mb 200] [--rounds 3] [--pause 3]

Compiles a small C probe (cc -O2) that maps --mb MiB, asks for transparent huge pages
(madvise MADV_HUGEPAGE) or not, writes one byte per 4 KiB page and reports the time.
Each round runs the probe with huge pages twice back to back, then with 4 KiB pages,
then sleeps --pause seconds. On a VM whose balloon driver reports freed memory to the
host (virtio-balloon free page reporting: 2 MB blocks, about 2 s after they are
freed), the first huge-page run of a round touches blocks the host has taken back and
is slow; the second reuses the blocks the first just freed. The compile benchmark's
figures swing with this (docs/benchmarks.md); run this before comparing rounds.
"""
from __future__ import annotations

import argparse
import shutil
import subprocess
import tempfile
import time
from pathlib import Path

PROBE_C = r"""
#include <stdio.h>
#include <stdlib.h>
#include <sys/mman.h>
#include <time.h>
int main(int argc, char **argv) {
    size_t n = (size_t)atol(argv[1]) << 20;
    char *p = mmap(NULL, n, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (p == MAP_FAILED) return 1;
    if (atoi(argv[2])) madvise(p, n, MADV_HUGEPAGE);
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    for (size_t i = 0; i < n; i += 4096) p[i] = 1;
    clock_gettime(CLOCK_MONOTONIC, &t1);
    printf("%.3f\n", (t1.tv_sec - t0.tv_sec) * 1e3 + (t1.tv_nsec - t0.tv_nsec) * 1e-6);
    return 0;
}
"""


def balloon_reports_free_pages() -> bool | None:
    """True when a virtio-balloon device offers free page reporting (feature bit 5)."""
    found = None
    for features in Path("/sys/bus/virtio/drivers/virtio_balloon").glob("virtio*/features"):
        bits = features.read_text().strip()
        found = len(bits) > 5 and bits[5] == "1"
    return found


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--mb", type=int, default=200)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--pause", type=float, default=3.0)
    args = ap.parse_args()
    thp = Path("/sys/kernel/mm/transparent_hugepage/enabled")
    print(f"transparent huge pages: {thp.read_text().strip() if thp.exists() else 'unknown'}")
    print(f"balloon free page reporting: {balloon_reports_free_pages()}")
    with tempfile.TemporaryDirectory() as tmp:
        exe = Path(tmp) / "probe"
        src = Path(tmp) / "probe.c"
        src.write_text(PROBE_C)
        subprocess.run([shutil.which("cc") or "gcc", "-O2", str(src), "-o", str(exe)], check=True)

        def run(huge: int) -> float:
            out = subprocess.run([str(exe), str(args.mb), str(huge)], check=True, capture_output=True, text=True)
            return float(out.stdout)

        for k in range(args.rounds):
            first, second, small = run(1), run(1), run(0)
            print(f"round {k + 1}: {args.mb} MiB huge pages {first:.1f} ms, again {second:.1f} ms; "
                  f"4 KiB pages {small:.1f} ms")
            time.sleep(args.pause)


if __name__ == "__main__":
    main()
