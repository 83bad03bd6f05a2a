"""The planner from Python (issue 29): ``kisstime.plan`` on a position given as a dict,
rows or the balls' array, and ``kisstime.pooltool.plan`` on pooltool's objects. The plan
pots the ball on, is the same for the same seed and sample budget, equals the command
line's, takes the noise as a preset or as a dict in pooltool's units, and refuses bad
input with a clear ValueError. Through the bridge the chosen strike is in pooltool's
``Cue`` conventions: set on the system's cue, pooltool simulates it."""

from __future__ import annotations

import json
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

import kisstime

ROOT = Path(__file__).resolve().parents[2]
POSITION = {0: (0.635, 0.9), 1: (0.4, 1.9), 2: (0.9, 1.6), 5: (0.3, 0.5), 9: (0.8, 2.2)}
BUDGET = dict(budget_s=None, budget_samples=30_000, top=3)


def test_the_plan_pots_the_ball_on_and_is_the_command_lines():
    a = kisstime.plan(POSITION, rules="9-ball", **BUDGET)
    assert a.best["ball"] == "1" and a.rules == "9-ball"
    assert set(a.strike) == {"V0", "phi", "theta", "a", "b"}
    assert a.strike == a.best["strike"]
    p, lo, hi = a.best["p_keep"]
    assert lo <= p <= hi and p > 0.6
    assert len(a.ranked) == 3 and a.samples <= 30_000 + 3 * 64
    # rows and the balls' array give the same plan
    rows = np.array([(k, *xy) for k, xy in POSITION.items()], dtype=float)
    assert kisstime.plan(rows, rules="9-ball", **BUDGET).ranked == a.ranked
    arr = np.zeros(len(POSITION), dtype=kisstime.BALL_DTYPE)
    for i, (k, (x, y)) in enumerate(POSITION.items()):
        arr[i] = (0, k, 0, x, y, 0, 0, 0, 0, 0)
    assert kisstime.plan(arr, rules="9-ball", **BUDGET).ranked == a.ranked
    # the command line's plan of the same position
    binary = os.environ.get("KISSTIME_BIN", str(ROOT / "target" / "debug" / "kisstime"))
    if Path(binary).exists():
        out = subprocess.run(
            [binary, "plan", str(ROOT / "examples" / "nine_ball_position.csv"), "--rules",
             "9-ball", "--budget", "30000", "--top", "3", "--json"],
            capture_output=True, text=True, check=True,
        )
        assert json.loads(out.stdout)["ranked"] == a.ranked


def test_noise_as_a_preset_or_in_pooltools_units():
    fastfiz = kisstime.plan(POSITION, rules="9-ball", **BUDGET)
    # fastfiz's sigmas in pooltool's units: a and b as fractions of R (0.5 mm / R)
    r = 0.028575
    same = kisstime.plan(
        POSITION, rules="9-ball",
        noise={"V0": 0.075, "phi": 0.125, "theta": 0.1, "a": 0.0005 / r, "b": 0.0005 / r},
        **BUDGET,
    )
    assert [x["strike"] for x in same.ranked] == [x["strike"] for x in fastfiz.ranked]
    for k in ("p_keep", "p_foul"):
        assert np.allclose(same.best[k], fastfiz.best[k], atol=0.02)
    wide = kisstime.plan(POSITION, rules="9-ball", noise="casual", **BUDGET)
    assert wide.best["p_keep"][0] < fastfiz.best["p_keep"][0]


def test_eight_ball_plans_the_group():
    pos = {0: (0.635, 0.9), 3: (0.4, 1.9), 8: (0.9, 1.6), 12: (0.8, 2.2)}
    solids = kisstime.plan(pos, rules="8-ball", hittable=[3], **BUDGET)
    assert {r["ball"] for r in solids.ranked} == {"3"}
    # the group down: the 8
    on_eight = kisstime.plan(pos, rules="8-ball", hittable=[], **BUDGET)
    assert {r["ball"] for r in on_eight.ranked} == {"8"}


@pytest.mark.parametrize(
    "kwargs, message",
    [
        (dict(rules="snooker"), "8-ball and 9-ball"),
        (dict(rules="9-ball", noise="wild"), "not a preset"),
        (dict(rules="9-ball", noise={"V0": 0.1, "spin": 1.0}), "unknown keys"),
        (dict(rules="9-ball", noise={"V0": -0.1}), "sigma"),
        (dict(rules="8-ball", hittable=[4]), "ball 4"),
        (dict(rules="9-ball", budget_samples=100), "one budget"),
        (dict(rules="9-ball", budget_s=0.0), "budget"),
        (dict(rules="9-ball", budget_s=None, budget_samples=10), "too small"),
        (dict(rules="9-ball", top=0), "top"),
        (dict(rules="cricket"), "unknown game"),
    ],
)
def test_bad_input_is_a_clear_error(kwargs, message):
    with pytest.raises(ValueError, match=message):
        kisstime.plan(POSITION, **kwargs)


def test_a_bad_position_is_a_clear_error():
    with pytest.raises(ValueError, match="overlap"):
        kisstime.plan({**POSITION, 2: (0.41, 1.9)}, rules="9-ball")
    with pytest.raises(ValueError, match="no cue ball"):
        kisstime.plan({k: v for k, v in POSITION.items() if k != 0}, rules="9-ball")


def test_the_bridge_plans_on_pooltools_objects():
    if os.environ.get("CI"):
        import pooltool as pt
    else:
        pt = pytest.importorskip("pooltool")
    import kisstime.pooltool as kpt

    table = pt.Table.default()
    layout = {"cue": (0.5, 0.5), "1": (0.3, 1.3), "2": (0.8, 1.4), "9": (0.6, 1.8)}
    balls = {bid: pt.Ball.create(bid, xy=xy) for bid, xy in layout.items()}
    plan = kpt.plan(balls, table, rules="9-ball", noise={"V0": 0.1, "phi": 0.1,
                    "theta": 0.1, "a": 0.003, "b": 0.003}, budget_s=None,
                    budget_samples=20_000, top=2)
    assert plan.best["ball"] == "1"
    assert set(plan.strike) == {"V0", "phi", "theta", "a", "b"}
    # the same from a System; its strike set on pooltool's cue, pooltool simulates it
    system = pt.System(cue=pt.Cue(cue_ball_id="cue"), table=table, balls=balls)
    again = kpt.plan(system, rules="9-ball", noise={"V0": 0.1, "phi": 0.1, "theta": 0.1,
                     "a": 0.003, "b": 0.003}, budget_s=None, budget_samples=20_000, top=2)
    assert again.ranked == plan.ranked
    system.cue.set_state(**plan.strike)
    pt.simulate(system, inplace=True)
    assert len(system.events) > 2
    with pytest.raises(ValueError, match="pool balls"):
        kpt.plan({"cue": pt.Ball.create("cue", xy=(0.5, 0.5)),
                  "ghost": pt.Ball.create("ghost", xy=(0.3, 1.3))}, table, rules="9-ball")


def test_ball_in_hand_chooses_the_placement_and_a_shot_from_it():
    balls = {0: (0.3, 0.3), 1: (0.9, 1.9), 2: (0.4, 2.2), 9: (0.635, 1.0)}
    out = kisstime.plan(balls, rules="9-ball", budget_s=None, budget_samples=30_000, ball_in_hand="anywhere")
    x, y = out.placement
    assert 0.0 < x < 1.27 and 0.0 < y < 2.54
    # clear of every object ball
    for bid, (bx, by) in balls.items():
        if bid:
            assert np.hypot(bx - x, by - y) > 2 * 0.028575
    # the same position with the cue ball left out, and behind the head string
    del balls[0]
    kitchen = kisstime.plan(balls, rules="9-ball", budget_s=None, budget_samples=30_000, ball_in_hand="kitchen")
    assert kitchen.placement[1] < 0.635
    # from the chosen spot, the ball on (the 1) is hit first in most samples
    assert kitchen.best["p_foul"][0] < 0.5
    with pytest.raises(ValueError, match="ball in hand 'nowhere'|ball in hand \"nowhere\""):
        kisstime.plan(balls, rules="9-ball", ball_in_hand="nowhere")


def test_the_break_and_the_kinds_of_shot():
    # the 9-ball rack of examples/nine_ball_rack.csv (its cue ball is placed by the plan)
    rows = np.loadtxt(ROOT / "examples" / "nine_ball_rack.csv", delimiter=",", skiprows=1,
                      usecols=(1, 3, 4))
    rack = {int(i): (x, y) for i, x, y in rows if i != 0}
    out = kisstime.plan(rack, rules="9-ball", budget_s=None, budget_samples=4_000, top=2,
                        break_shot=True)
    x, y = out.placement
    assert 0.0 < x < 1.27 and y < 0.635, "behind the head string"
    assert out.best["kind"] == "break" and out.best["pocket"] is None
    assert out.best["first"] == "1"
    assert out.best["p_keep"][0] > 0.5
    with pytest.raises(ValueError, match="break"):
        kisstime.plan(rack, rules="9-ball", break_shot=True, ball_in_hand="anywhere")
    # the 1 behind a wall: only kicks, named with their cushion
    walled = {0: (0.635, 0.5), 1: (0.635, 1.5), 2: (0.635, 1.0), 3: (0.57, 1.0),
              4: (0.70, 1.0)}
    kick = kisstime.plan(walled, rules="9-ball", **BUDGET)
    assert {r["kind"] for r in kick.ranked} == {"kick"}
    assert all(r["rail"] is not None and r["first"] == "1" for r in kick.ranked)
    assert kick.refined > 0
