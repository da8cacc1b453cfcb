"""The box index (toolchain/box_index.pyx) alone, through tests/harness: random boxes
(seeded) appended, cut back, dropped from the front, and every search forwards and
backwards between two positions compared with a plain scan of the boxes: the same
elements, in the same order. Paths that wander (a random walk of short pieces, as the
compensation's pieces come) and boxes scattered anywhere; query boxes small and
large, with and without a margin t."""
import random

import pytest


@pytest.fixture(scope="module")
def bx(harness):
    return harness


def hit(a, b, t):
    """box_hit of box_index.pxd."""
    return a[0] <= b[2] + t and b[0] <= a[2] + t and a[1] <= b[3] + t and b[1] <= a[3] + t


def walk_boxes(rng, n, step=1.0):
    """Boxes of n pieces of a random walk (consecutive pieces share an end)."""
    x = y = 0.0
    out = []
    for _ in range(n):
        nx, ny = x + rng.uniform(-step, step), y + rng.uniform(-step, step)
        out.append([min(x, nx), min(y, ny), max(x, nx), max(y, ny)])
        x, y = nx, ny
    return out


def scattered_boxes(rng, n, size=100.0):
    out = []
    for _ in range(n):
        x, y = rng.uniform(-size, size), rng.uniform(-size, size)
        w, h = rng.expovariate(0.5), rng.expovariate(0.5)
        out.append([x, y, x + w, y + h])
    return out


def query_box(rng, boxes):
    """A query near the boxes: round one of them, grown, or anywhere."""
    if boxes and rng.random() < 0.8:
        b = rng.choice(boxes)
        g = rng.choice([0.0, 0.5, 3.0, 30.0])
        return [b[0] - g, b[1] - g, b[2] + g, b[3] + g]
    x, y = rng.uniform(-150, 150), rng.uniform(-150, 150)
    return [x, y, x + rng.uniform(0, 20), y + rng.uniform(0, 20)]


class Model:
    """The plain scan the index must agree with: boxes held, the base."""

    def __init__(self):
        self.boxes, self.base = [], 0

    def scan(self, lo, hi, q, t):
        lo, hi = max(lo, self.base), min(hi, len(self.boxes))
        return [j for j in range(lo, hi) if hit(self.boxes[j], q, t)]


def check_searches(rng, ix, model, count=30):
    n = len(model.boxes)
    for _ in range(count):
        q = query_box(rng, model.boxes)
        t = rng.choice([0.0, 0.0, 0.25, 2.0])
        lo = rng.choice([0, model.base, rng.randint(0, n + 2)])
        hi = rng.choice([n, n + 5, rng.randint(0, n + 2)])
        want = model.scan(lo, hi, q, t)
        assert ix.all_next(lo, hi, q, t) == want
        assert ix.all_prev(lo, hi, q, t) == want[::-1]
        assert ix.next(lo, hi, q, t) == (want[0] if want else -1)
        assert ix.prev(lo, hi, q, t) == (want[-1] if want else -1)


@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("kind", ["walk", "scattered"])
def test_append_and_search(bx, seed, kind):
    """Searches after every batch of appends, across group sizes 4 .. 4096 and more."""
    rng = random.Random(1000 * seed + (kind == "walk"))
    n = rng.choice([1, 3, 4, 17, 300, 5000, 20000])
    boxes = walk_boxes(rng, n) if kind == "walk" else scattered_boxes(rng, n)
    ix, model = bx.Boxes(), Model()
    assert ix.next(0, 10, [0, 0, 1, 1]) == -1 and ix.prev(0, 10, [0, 0, 1, 1]) == -1
    k = 0
    while k < n:
        m = rng.randint(1, max(1, n // 5))
        for b in boxes[k:k + m]:
            ix.append(b)
            model.boxes.append(b)
        k += m
        assert ix.n == len(model.boxes)
        check_searches(rng, ix, model, 15)


@pytest.mark.parametrize("seed", range(8))
def test_window_cut_and_drop(bx, seed):
    """A window moved along a chain as the crossings search moves it: pieces appended,
    the newest ones cut back (a loop removed) and replaced, the oldest dropped; the
    positions go down by what drop returns, and searches still agree."""
    rng = random.Random(seed)
    walk = walk_boxes(rng, 20000, step=rng.choice([0.5, 2.0]))
    ix, model = bx.Boxes(), Model()
    window = rng.choice([50, 700, 3000, 9000])
    for i, b in enumerate(walk):
        if model.boxes and rng.random() < 0.003:
            cut = rng.randint(max(model.base, len(model.boxes) - rng.choice([3, 100, window])), len(model.boxes) - 1)
            ix.truncate(cut)
            del model.boxes[cut:]
            assert ix.n == cut
            check_searches(rng, ix, model, 5)
        if len(model.boxes) - model.base > window:
            base = len(model.boxes) - window
            shift = ix.drop(base)
            model.base = base
            if shift:
                assert shift % 4096 == 0 and shift <= base
                del model.boxes[:shift]
                model.base -= shift
            assert ix.base == model.base and ix.n == len(model.boxes)
        ix.append(b)
        model.boxes.append(b)
        if rng.random() < 0.003:
            check_searches(rng, ix, model, 5)
            assert ix.box(len(model.boxes) - 1) == b
    check_searches(rng, ix, model, 50)


def test_drop_gives_memory_back(bx):
    """Dropped elements more than half the index, at least two top groups (4096): whole
    top groups move out, the positions go down by their count."""
    rng = random.Random(3)
    ix, model = bx.Boxes(), Model()
    for b in walk_boxes(rng, 20000):
        ix.append(b)
        model.boxes.append(b)
    assert ix.drop(8000) == 0       # under two top groups
    assert ix.drop(9000) == 0       # not more than half
    assert ix.drop(15000) == 12288
    del model.boxes[:12288]
    model.base = 15000 - 12288
    assert (ix.n, ix.base) == (20000 - 12288, model.base)
    check_searches(rng, ix, model, 50)


def test_truncate_below_base_and_clear(bx):
    rng = random.Random(7)
    ix, model = bx.Boxes(), Model()
    for b in walk_boxes(rng, 9000):
        ix.append(b)
        model.boxes.append(b)
    assert ix.drop(100) == 0
    model.base = 100
    check_searches(rng, ix, model)
    ix.truncate(50)
    del model.boxes[50:]
    model.base = 50
    assert (ix.n, ix.base) == (50, 50)
    check_searches(rng, ix, model)
    ix.truncate(60)                 # no growth by truncate
    assert ix.n == 50
    ix.clear()
    assert (ix.n, ix.base) == (0, 0)
    model = Model()
    for b in scattered_boxes(rng, 5000):
        ix.append(b)
        model.boxes.append(b)
    check_searches(rng, ix, model)


def test_empty_boxes_and_points(bx):
    """Boxes that cover nothing (box_empty) are never found; points and touching
    boxes are (the comparisons are closed)."""
    ix = bx.Boxes()
    empty = [1e300, 1e300, -1e300, -1e300]
    for k in range(40):
        ix.append(empty if k % 3 else [k, k, k, k])
    assert ix.all_next(0, 40, [-1e9, -1e9, 1e9, 1e9]) == list(range(0, 40, 3))
    assert ix.all_next(0, 40, [3, 3, 3, 3]) == [3]
    assert ix.all_prev(0, 40, [4, 4, 6, 6]) == [6]
    assert ix.all_next(0, 40, [6.5, 6.5, 8, 8], 0.5) == [6]
