"""``kisstime.simulate(..., rules=, context=)``: the 9-ball reference set (``data/games``,
pooltool 0.6.0's own verdicts) judged through Python, every verdict pooltool's; bad
contexts raise ValueError with the command line's message."""

import csv
from pathlib import Path

import numpy as np
import pytest

import kisstime

DATA = Path(__file__).resolve().parents[2] / "data" / "games" / "nine_ball"

REASONS = {
    "": "",
    "cue_pocketed": "Cue ball in pocket!",
    "no_hit": "No ball contacted",
    "wrong_ball_first": "Lowest ball not hit first",
    "no_rail": "Cushion not contacted after first contact",
    "break_rails": "4 rails must be contacted, or 1 ball potted",
}


def rows(name: str) -> list[dict]:
    with open(DATA / name, newline="") as f:
        return list(csv.DictReader(f))


def reference():
    shots = rows("shots.csv")
    balls = rows("balls.csv")
    b = np.zeros(len(balls), dtype=kisstime.BALL_DTYPE)
    b["table"] = [int(r["shot"]) for r in balls]
    b["ball"] = [int(r["ball"]) for r in balls]
    b["x"] = [float(r["x"]) for r in balls]
    b["y"] = [float(r["y"]) for r in balls]
    s = np.zeros(len(shots), dtype=kisstime.STRIKE_DTYPE)
    s["table"] = [int(r["shot"]) for r in shots]
    for k, c in [("V0", "v0"), ("phi", "phi"), ("theta", "theta"), ("a", "a"), ("b", "b")]:
        s[k] = [float(r[c]) for r in shots]
    return shots, b, s


def test_nine_ball_verdicts_through_python_are_pooltools():
    shots, balls, strikes = reference()
    context = {
        "table": [int(r["shot"]) for r in shots],
        "break": [r["break"] == "1" for r in shots],
    }
    res = kisstime.simulate(balls, strikes, table="7ft", events=False, rules="9-ball",
                            context=context)
    oc = res.outcomes
    assert res.events is None
    assert set(["legal", "foul", "turn_over", "game_over", "won"]) <= set(oc.dtype.names)
    judged = 0
    for row, shot in zip(oc, shots):
        assert int(row["table"]) == int(shot["shot"])
        if int(row["events"]) != int(shot["n_events"]):
            continue
        judged += 1
        foul = kisstime.FOULS[row["foul"]] if row["foul"] >= 0 else ""
        assert REASONS[foul] == shot["reason"], shot["shot"]
        assert (row["legal"], row["turn_over"], row["game_over"]) == (
            int(shot["legal"]), int(shot["turn_over"]), int(shot["game_over"])), shot["shot"]
    assert judged >= 594


def test_bad_rules_and_contexts_raise_value_error():
    shots, balls, strikes = reference()
    with pytest.raises(ValueError, match="8-ball"):
        kisstime.simulate(balls, strikes, table="7ft", rules="snooker")
    with pytest.raises(ValueError, match="table 9999"):
        kisstime.simulate(balls, strikes, table="7ft", rules="8-ball",
                          context={"table": [9999], "break": [False]})
    with pytest.raises(ValueError, match="pocket_call"):
        kisstime.simulate(balls, strikes, table="7ft", rules="8-ball",
                          context={"table": [5], "pocket_call": ["zz"]})
    with pytest.raises(ValueError, match="rules"):
        kisstime.simulate(balls, strikes, table="7ft", context={"table": [5]})
