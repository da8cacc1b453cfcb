"""The plan in two pieces (pipeline.pyx plan_in_two, as the library plans a large
program beside its extent): split at a part where the machine stands, the two
ranges planned by two threads give exactly the plan of the whole program in one
piece, for every split point of random contours with waiting M functions and dwells,
every window depth and with the angle slow-down, axis limits and sine ramps."""
import random

from test_planner import harness_module, params
from test_planner_random import random_program

SETTINGS = (
    dict(),
    dict(startAngle=30.0, endAngle=120.0, minAngleFeed=600.0),
    dict(axis=[(0, 3000.0, 200.0, 300.0)], motion=[None, (1000.0, 300.0, 800.0, 2)]),
)


def test_two_pieces_equal_one():
    ph = harness_module()
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


def test_no_stop_no_split():
    ph = harness_module()
    text = "G1 X0 Y0 F3000\n" + "".join(f"G1 X{k % 7} Y{k % 5}\n" for k in range(1, 200))
    whole, _, _ = ph.plan_text(text, None, 0, 0)
    parts, _, timing = ph.plan_text(text, None, 0, 0, True, 50)
    assert timing["split"] == 0 and parts == whole
