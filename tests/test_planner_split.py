"""The plan in two pieces (pipeline.pyx plan_in_two, as the library plans a large
program beside its extent): split at a part where the machine stands, the two
ranges planned by two threads give exactly the plan of the whole program in one
piece, for every split point of random contours with waiting M functions and dwells,
every window depth and with the angle slow-down, axis limits and sine ramps."""
import random

import pytest

from test_planner import params, ph  # noqa: F401  (ph: the fixture)
from test_planner_random import random_program

SETTINGS = (
    dict(),
    dict(startAngle=30.0, endAngle=120.0, minAngleFeed=600.0),
    dict(axis=[(0, 3000.0, 200.0, 300.0)], motion=[None, (1000.0, 300.0, 800.0, 2)]),
)


def test_two_pieces_equal_one(ph):
    rng = random.Random(20261124)
    split_runs = 0
    for _ in range(30):
        text, _ = random_program(rng)
        p = params(ph, **rng.choice(SETTINGS))
        window = rng.choice((0, 2, 3, 20, -1))
        whole, error, _ = ph.plan_text(text, p, window, 0)
        assert error is None
        for near in range(0, len(whole) + 2):
            parts, error, timing = ph.plan_text(text, p, window, 0, True, near)
            assert error is None
            split = timing["split"]
            if split:
                assert whole[split]["kind"] != 1 and whole[split]["v_in"] == 0.0   # a stop
                split_runs += 1
            assert parts == whole, (text, window, near, split)      # bit for bit
    assert split_runs > 50


def test_no_stop_no_split(ph):
    text = "G1 X0 Y0 F3000\n" + "".join(f"G1 X{k % 7} Y{k % 5}\n" for k in range(1, 200))
    whole, _, _ = ph.plan_text(text, None, 0, 0)
    parts, _, timing = ph.plan_text(text, None, 0, 0, True, 50)
    assert timing["split"] == 0 and parts == whole


def test_library_plans_a_large_program_beside_its_extent(ph, fresh_core):
    """A program large enough for the library to plan it in two threads (pipeline.pyx
    PLAN_BESIDE_MIN parts, a waiting M function to split at) runs as long as the
    harness's plan in one piece says (fresh cores: the default parameters; from 0)."""
    import sf_tch
    from test_planner import total
    rng = random.Random(5)
    lines = ["G1 X0 Y0 F3000"]
    for k in range(6000):
        lines.append(f"G1 X{rng.uniform(0, 40):.3f} Y{rng.uniform(0, 40):.3f}")
        if k % 97 == 0:
            lines.append("M50")
    text = "\n".join(lines) + "\n"
    parts, error, timing = ph.plan_text(text, None, 0, 0, True, len(lines) * 3 // 8)
    assert error is None and timing["split"] > 0
    expected = total(ph.plan_text(text, None, 0, 0)[0])
    with sf_tch.compile(text, look_ahead=0, start=[0.0] * 10) as program:
        program.simulate()
        assert program.run_time == pytest.approx(expected, rel=1e-12)
