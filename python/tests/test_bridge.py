"""The pooltool bridge at batch scale (kisstime.pooltool.simulate_strikes / simulate_systems).

One pooltool position (an 8-ball-like layout on pooltool's default 7-ft table) is fanned
out into 10,000 noisy strikes in one call; a sample of them (pots, a scratch, misses) is
simulated by ``pt.simulate`` itself and compared event for event and ball for ball through
``from_pooltool_events``/``from_pooltool_final``. Tables as pooltool objects, JSON text,
paths and the built-in ``7ft`` give the same results; pooltool's snooker and billiard
tables convert and simulate as pooltool does; ``on_error="report"`` flags exactly the bad
shots and simulates the others as a clean run does; ``from_pooltool_final`` reads a
pocketed ball from its own state, not from a reused table's pocket contents.

As in test_pooltool.py, ``pt.simulate`` runs in a subprocess with ``NUMBA_DISABLE_JIT=1``
(exact pure Python, no minute-long compile); each shot here takes well under a second.
"""

from __future__ import annotations

import json
import math
import re
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

if os.environ.get("CI"):
    import pooltool as pt
else:
    pt = pytest.importorskip("pooltool")
from pooltool.game.datatypes import GameType  # noqa: E402
from pooltool.objects.ball.datatypes import BallState  # noqa: E402

import kisstime  # noqa: E402
import kisstime.pooltool as kpt  # noqa: E402

TABLES = Path(__file__).resolve().parents[2] / "data" / "tables"
TOL = dict(rel_tol=1e-9, abs_tol=1e-9)
N_FAN = 10_000
SEED = 2025

# the intended shot: ball "1" into the top-right corner, with some follow and side
SHOT = dict(V0=2.0, phi=62.5, theta=5.0, a=0.1, b=0.2)
LAYOUT = [("cue", (0.5, 1.2)), ("1", (0.8, 1.75)), ("2", (0.3, 1.6)), ("8", (0.5, 0.5)),
          ("3", (0.2, 0.3))]


def pt_table(kind: str):
    if kind == "7ft":
        return pt.Table.default()
    if kind == "snooker":
        return pt.Table.from_game_type(GameType.SNOOKER)
    if kind == "billiard":
        return pt.Table.from_game_type(GameType.THREECUSHION)
    raise ValueError(kind)


# BallParams other than pooltool's defaults (every ball's), for per-system physics
PARAMS = dict(u_s=0.15, u_r=0.012, e_c=0.8, f_c=0.15)


def position(kind: str = "7ft", params: dict | None = None, n_balls: int = len(LAYOUT),
             **shot: float) -> "pt.System":
    """The position on table `kind` (its first `n_balls` balls, each with BallParams
    `params`), the cue set to SHOT (updated by `shot`)."""
    balls = {bid: pt.Ball.create(bid, xy=xy, **(params or {})) for bid, xy in LAYOUT[:n_balls]}
    cue = pt.Cue(cue_ball_id="cue")
    cue.set_state(**{**SHOT, **shot})
    return pt.System(cue=cue, table=pt_table(kind), balls=balls)


def noisy_strikes(n: int = N_FAN) -> dict[str, np.ndarray]:
    """n noisy versions of SHOT (V0, phi, a, b noisy; theta the cue's)."""
    rng = np.random.default_rng(SEED)
    return {
        "V0": SHOT["V0"] + rng.normal(0.0, 0.15, n),
        "phi": SHOT["phi"] + rng.normal(0.0, 1.0, n),
        "a": SHOT["a"] + rng.normal(0.0, 0.05, n),
        "b": SHOT["b"] + rng.normal(0.0, 0.05, n),
    }


def strike_of(strikes: dict, k: int) -> dict[str, float]:
    return {c: float(strikes[c][k]) for c in strikes}


# ------------------------------------------------------------------- pooltool's results
def _main_pt_simulate(request: dict) -> None:
    """pooltool's events and final states for the request's shots (run as a script)."""
    out: dict = {"fan": {}, "tables": {}}
    strikes = noisy_strikes()
    for k in request["fan"]:
        done = pt.simulate(position("7ft", **strike_of(strikes, k)))
        out["fan"][str(k)] = {
            "events": kpt.from_pooltool_events(done),
            "final": kpt.from_pooltool_final(done),
        }
    for kind in ("snooker", "billiard", "params"):
        system = position("7ft", PARAMS, phi=70.0) if kind == "params" else position(kind)
        done = pt.simulate(system)
        out["tables"][kind] = {
            "events": kpt.from_pooltool_events(done),
            "final": kpt.from_pooltool_final(done),
        }
    # a scratch, then the cue ball re-spotted on the same (reused) table
    k = request["scratch"]
    done = pt.simulate(position("7ft", **strike_of(strikes, k)))
    before = kpt.from_pooltool_final(done)
    done.balls["cue"].state = BallState(
        rvw=np.array([[0.5, 0.4, 0.028575], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]]), s=0
    )
    out["respot"] = {
        "before": before,
        "after": kpt.from_pooltool_final(done),
        "contains": {str(p): sorted(map(str, x.contains)) for p, x in done.table.pockets.items()},
    }
    print(json.dumps(out))


@pytest.fixture(scope="module")
def fan() -> kpt.BatchResult:
    """The 10,000 noisy strikes of the position, in one call, with events."""
    return kpt.simulate_strikes(position(), noisy_strikes(), events=True)


def _sample(fan: kpt.BatchResult) -> dict:
    """Shots to check against pooltool: two pots of ball 1, a scratch, three others."""
    ids = fan.ball_ids
    pocketed = fan.pocketed
    pots = np.flatnonzero(pocketed[:, ids.index("1")] & ~pocketed[:, ids.index("cue")])
    scratches = np.flatnonzero(pocketed[:, ids.index("cue")])
    misses = np.flatnonzero(~pocketed.any(axis=1))
    assert len(pots) >= 2 and len(scratches) >= 1 and len(misses) >= 3, (
        len(pots), len(scratches), len(misses))
    fan_shots = [int(x) for x in (*pots[:2], scratches[0], *misses[:2], N_FAN - 1)]
    return {"fan": fan_shots, "scratch": int(scratches[0])}


@pytest.fixture(scope="module")
def pooltool_results(fan) -> dict:
    request = _sample(fan)
    env = dict(os.environ, NUMBA_DISABLE_JIT="1", PYTHONPATH=os.pathsep.join(sys.path))
    run = subprocess.run(
        [sys.executable, __file__, "--pt-simulate", json.dumps(request)],
        env=env, capture_output=True, text=True, timeout=600,
    )
    assert run.returncode == 0, run.stderr[-4000:]
    out = json.loads(run.stdout.strip().splitlines()[-1])
    out["request"] = request
    return out


def assert_same_final(mine: dict, theirs: dict) -> None:
    assert list(mine) == list(theirs)
    for bid, f in mine.items():
        g = theirs[bid]
        assert (f["state"], f["pocket"]) == (g["state"], g["pocket"]), bid
        assert math.hypot(f["x"] - g["x"], f["y"] - g["y"]) < 1e-6, bid


def assert_same_events(mine: list, theirs: list) -> None:
    assert len(mine) == len(theirs), (len(mine), len(theirs))
    first = kpt.first_difference(mine, theirs, **TOL)
    assert first is None, f"event {first}: kisstime {mine[first]} pooltool {theirs[first]}"


# ------------------------------------------------------------------- the fan
def test_ten_thousand_noisy_strikes_in_one_call_are_pooltools_shots(fan, pooltool_results):
    assert len(fan) == N_FAN
    assert fan.ok.all() and fan.errors == {}
    assert fan.final_states.shape == (N_FAN, len(LAYOUT))
    assert fan.outcomes["table"].tolist() == list(range(N_FAN))
    assert (fan.outcomes["cut"] == 0).all()
    assert fan.event_offsets[-1] == len(fan.events)
    # every shot has its strike first, on the cue ball, at t = 0
    firsts = fan.events[fan.event_offsets[:-1]]
    assert (firsts["type"] == 0).all() and (firsts["t"] == 0).all()
    assert (firsts["agent_a"] == fan.ball_ids.index("cue")).all()
    # the sampled strikes, simulated by pt.simulate itself
    for k in pooltool_results["request"]["fan"]:
        theirs = pooltool_results["fan"][str(k)]
        assert_same_events(fan.to_events(k), [dict(e, agents=tuple(e["agents"])) for e in theirs["events"]])
        assert_same_final(fan.to_final(k), theirs["final"])
    # the vectorised arrays say what the per-shot dicts say
    k = pooltool_results["request"]["fan"][0]
    names = fan.pocket_names()
    for i, bid in enumerate(fan.ball_ids):
        f = fan.to_final(k)[bid]
        assert names[k, i] == f["pocket"]
        assert fan.final_states["x"][k, i] == f["x"]
    assert fan.event_types()[fan.event_offsets[k]] == "stick_ball"


def test_fan_equals_the_same_strikes_one_table_at_a_time(fan):
    """The batch form's index mapping: shot k is the position with strike k (each table of
    kisstime.simulate built by hand as from_system builds one)."""
    system = position()
    strikes = noisy_strikes()
    conv = kpt.from_system(system)
    picks = [0, 1, 977, 5000, N_FAN - 1]
    balls = np.concatenate([conv.balls] * len(picks))
    balls["table"] = np.repeat(picks, len(conv.balls))
    rows = np.zeros(len(picks), dtype=kisstime.STRIKE_DTYPE)
    rows["table"] = picks
    rows["ball"] = conv.ball("cue")
    for c in ("V0", "phi", "theta", "a", "b"):
        rows[c] = strikes[c][picks] if c in strikes else SHOT[c]
    by_hand = kisstime.simulate(balls, rows, table=conv.table, physics=conv.physics)
    for k in picks:
        assert kpt.to_events(by_hand, conv, table=k) == fan.to_events(k)
        assert kpt.to_final(by_hand, conv, table=k) == fan.to_final(k)
    # final states only (events=False): the same final states
    quiet = kpt.simulate_strikes(system, {c: v[:50] for c, v in strikes.items()})
    assert quiet.events is None and quiet.event_offsets is None
    assert quiet.final_states.tobytes() == fan.final_states[:50].tobytes()


def test_respotted_cue_ball_is_not_pocketed_on_a_reused_table(fan, pooltool_results):
    r = pooltool_results["respot"]
    k = pooltool_results["request"]["scratch"]
    pocket = r["before"]["cue"]["pocket"]
    assert r["before"]["cue"]["state"] == "pocketed" and pocket is not None
    assert fan.to_final(k)["cue"]["pocket"] == pocket
    # pooltool's pocket still lists the cue ball; its state says it is back on the table
    assert "cue" in r["contains"][pocket]
    assert r["after"]["cue"]["state"] == "stationary"
    assert r["after"]["cue"]["pocket"] is None
    assert (r["after"]["cue"]["x"], r["after"]["cue"]["y"]) == (0.5, 0.4)


# ------------------------------------------------------------------- tables
def test_pooltools_tables_are_the_data_files_and_7ft_is_built_in():
    for name, kind in (("7ft.json", "7ft"), ("snooker.json", "snooker"), ("billiard.json", "billiard")):
        assert kpt.table_json(pt_table(kind)) + "\n" == (TABLES / name).read_text(), name
    ids = kisstime.table_ids("7ft")
    assert ids == kisstime.table_ids(pt.Table.default()) == kisstime.table_ids(TABLES / "7ft.json")
    assert ids == kisstime.table_ids("9ft")  # the same items; other geometry:
    system = position()
    conv = kpt.from_system(system)
    builtin = conv.simulate(table="7ft")
    own = conv.simulate()
    assert builtin.events.tobytes() == own.events.tobytes()
    nine = conv.simulate(table="9ft")
    assert nine.final.tobytes() != own.final.tobytes()


def test_table_as_object_json_text_path_or_name_gives_the_same_result(tmp_path):
    system = position()
    strikes = {c: v[:200] for c, v in noisy_strikes().items()}
    path = tmp_path / "t.json"
    path.write_text(kpt.table_json(system.table))
    results = [
        kpt.simulate_strikes(system, strikes, table=t, events=True)
        for t in (None, system.table, kpt.table_json(system.table), path, str(path), "7ft")
    ]
    for r in results[1:]:
        assert r.events.tobytes() == results[0].events.tobytes()
        assert r.final_states.tobytes() == results[0].final_states.tobytes()
        assert r.table_ids_of(0) == results[0].table_ids_of(0)
    # kisstime.simulate and table_ids take them too
    conv = kpt.from_system(system)
    a = kisstime.simulate(conv.balls, conv.strikes, table=system.table)
    b = kisstime.simulate(conv.balls, conv.strikes, table=path)
    assert a.events.tobytes() == b.events.tobytes()
    # bad JSON text is named as a file would be
    with pytest.raises(ValueError, match=r"^table JSON: table: pockets must be an object"):
        kisstime.simulate(conv.balls, conv.strikes, table='{"pockets": 3}')
    with pytest.raises(TypeError, match="table"):
        kisstime.simulate(conv.balls, conv.strikes, table=3.5)


@pytest.mark.parametrize("kind", ["snooker", "billiard"])
def test_snooker_and_billiard_tables_are_pooltools(kind, pooltool_results):
    system = position(kind)
    conv = kpt.from_system(system)
    expect = {"snooker": (18, 12, 6), "billiard": (4, 0, 0)}[kind]
    assert tuple(len(conv.table_ids[s]) for s in ("linear", "circular", "pockets")) == expect
    theirs = pooltool_results["tables"][kind]
    result = conv.simulate()
    assert_same_events(kpt.to_events(result, conv), [dict(e, agents=tuple(e["agents"])) for e in theirs["events"]])
    assert_same_final(kpt.to_final(result, conv), theirs["final"])
    # the object itself as the table, in the batch form
    fan = kpt.simulate_strikes(system, {"V0": [SHOT["V0"]]}, table=system.table, events=True)
    assert fan.to_events(0) == kpt.to_events(result, conv)


# ------------------------------------------------------------------- per-shot status
def test_report_flags_exactly_the_bad_strikes_and_simulates_the_others_as_a_clean_run():
    system = position()
    strikes = {c: v[:300].copy() for c, v in noisy_strikes().items()}
    bad = {3: ("a", 0.95, r"a² \+ b² > 1"), 50: ("V0", -1.0, r"V0 = -1 < 0"),
           51: ("phi", np.nan, "non-finite"), 299: ("b", np.inf, "non-finite")}
    for k, (c, v, _) in bad.items():
        strikes[c][k] = v
        if c == "a":
            strikes["b"][k] = 0.95
    with pytest.raises(ValueError, match=r"^shot 3: strike: a² \+ b² > 1"):
        kpt.simulate_strikes(system, strikes)
    rep = kpt.simulate_strikes(system, strikes, on_error="report", events=True)
    assert sorted(rep.errors) == sorted(bad)
    for k, (_, _, msg) in bad.items():
        assert rep.status[k].startswith(f"shot {k}: strike: ") and re.search(msg, rep.status[k])
    assert rep.ok.sum() == 300 - len(bad)
    good = np.flatnonzero(rep.ok)
    clean = kpt.simulate_strikes(system, {c: v[good] for c, v in strikes.items()}, events=True)
    for j, k in enumerate(good):
        assert rep.to_events(k) == clean.to_events(j)
    for name in ("state", "x", "y", "vx", "vy", "wx", "wy", "wz", "pocket"):
        assert rep.final_states[name][good].tobytes() == clean.final_states[name].tobytes()
    # the bad shots: no events, NaN and -1 states, cut -1
    for k in bad:
        assert len(rep.events_of(k)) == 0
        assert np.isnan(rep.final_states["x"][k]).all() and (rep.final_states["state"][k] == -1).all()
        assert rep.outcomes["cut"][k] == -1
        with pytest.raises(ValueError, match="not simulated"):
            rep.to_final(k)
    with pytest.raises(ValueError, match="on_error"):
        kpt.simulate_strikes(system, strikes, on_error="ignore")


def test_simulate_systems_flags_bad_positions_and_mixes_tables(pooltool_results):
    good_a = position("7ft")
    good_b = position("snooker", phi=80.0)
    overlap = position("7ft")
    overlap.balls["2"] = pt.Ball.create("2", xy=(0.51, 1.2))  # on the cue ball
    off = position("7ft")
    off.balls["3"] = pt.Ball.create("3", xy=(0.2, 2.5))  # beyond the 7-ft table's end
    nan = position("7ft")
    nan.balls["8"] = pt.Ball.create("8", xy=(0.5, float("nan")))
    systems = [good_a, overlap, good_b, off, nan]
    # raised: a system that does not convert first, then the first bad shot (numbered in
    # the whole call, though the snooker system is simulated apart)
    with pytest.raises(ValueError, match=r"^system 4: ball '8' position: non-finite"):
        kpt.simulate_systems(systems)
    with pytest.raises(ValueError, match=r"^shot 3: ball '3': .*off the table"):
        kpt.simulate_systems([good_a, good_b, good_a, off])
    rep = kpt.simulate_systems(systems, on_error="report", events=True)
    assert sorted(rep.errors) == [1, 3, 4]
    assert rep.status[1].startswith("shot 1: balls 'cue' and '2' overlap")
    assert rep.status[3].startswith("shot 3: ball '3': ") and "off the table" in rep.status[3]
    assert rep.status[4].startswith("system 4: ") and "non-finite" in rep.status[4]
    for k, system in ((0, good_a), (2, good_b)):
        conv = kpt.from_system(system)
        alone = conv.simulate()
        assert rep.to_events(k) == kpt.to_events(alone, conv)
        assert rep.to_final(k) == kpt.to_final(alone, conv)
        assert rep.table_ids_of(k) == conv.table_ids
    # no system converts: nothing simulated, every shot flagged, the arrays empty
    none = kpt.simulate_systems([nan, nan], on_error="report", events=True)
    assert sorted(none.errors) == [0, 1] and none.final_states.shape == (2, 0)
    conv = kpt.from_system(good_a)
    real = conv.simulate()
    assert none.events.dtype == real.events.dtype and none.final.dtype == real.final.dtype
    assert none.outcomes.dtype == real.outcomes.dtype
    # several positions times many strikes: a "system" column
    # several positions times many strikes (a "system" column), with other ball counts,
    # tables and BallParams: each system's own physics, checked against pt.simulate
    three = position("7ft", n_balls=3)
    params = position("7ft", PARAMS)
    strikes = {"system": np.array([2, 0, 2, 3, 1]), "phi": np.array([80.0, 62.5, 81.0, 70.0, 60.0])}
    many = kpt.simulate_systems([good_a, three, good_b, params], strikes, events=True)
    assert many.ok.all() and many.final_states.shape == (5, len(LAYOUT))
    assert (many.final_states["ball"][4] == [0, 1, 2, -1, -1]).all()
    assert np.isnan(many.final_states["x"][4, 3:]).all()
    assert list(many.to_final(4)) == ["cue", "1", "2"]
    theirs = pooltool_results["tables"]["params"]
    assert_same_events(many.to_events(3), [dict(e, agents=tuple(e["agents"])) for e in theirs["events"]])
    assert_same_final(many.to_final(3), theirs["final"])
    default = kpt.simulate_strikes(good_a, {"phi": [70.0]})
    assert default.to_final(0) != many.to_final(3)  # the parameters matter here
    one = kpt.simulate_strikes(good_b, {"phi": np.array([80.0, 81.0])})
    for j, k in enumerate((0, 2)):
        assert many.to_final(k) == one.to_final(j)
    assert many.to_final(1) == kpt.simulate_strikes(good_a, {"phi": [62.5]}).to_final(0)
    with pytest.raises(ValueError, match="'system'"):
        kpt.simulate_systems([good_a], {"phi": [1.0]})
    with pytest.raises(ValueError, match="unknown columns"):
        kpt.simulate_strikes(good_a, {"phi": [1.0], "system": [0]})


# ------------------------------------------------------------------- to_events at scale
def test_to_events_and_to_final_slice_large_results():
    system = position()
    conv = kpt.from_system(system)
    fan = kpt.simulate_strikes(system, {c: v[:2000] for c, v in noisy_strikes().items()}, events=True)
    # kisstime's arrays are sorted by table: table k's rows are a slice, found by search
    for k in (0, 1, 1234, 1999):
        assert kpt.to_events(fan.events, conv, table=k) == fan.to_events(k)
        assert kpt.to_final(fan.final, conv, table=k) == fan.to_final(k)
    assert kpt.to_events(fan.events, conv, table=5000) == []
    # rows in another order still work (a mask)
    shuffled = fan.events[::-1].copy()
    rows = kpt._table_rows(shuffled, 7)
    assert rows.tobytes() == shuffled[shuffled["table"] == 7].tobytes()


# ------------------------------------------------------------------- on the GPU
def test_the_batch_form_on_the_gpu_gives_the_cpus_shots():
    """backend="gpu" (skipped without a GPU; required in CI, on lavapipe): the same shots,
    the bad ones flagged the same way."""
    system = position()
    strikes = {c: v[:64].copy() for c, v in noisy_strikes().items()}
    strikes["a"][5] = 2.0
    cpu = kpt.simulate_strikes(system, strikes, events=True, on_error="report")
    try:
        gpu = kpt.simulate_strikes(system, strikes, events=True, on_error="report", backend="gpu")
    except RuntimeError as e:
        if os.environ.get("KISSTIME_REQUIRE_GPU") == "1":
            pytest.fail(f"KISSTIME_REQUIRE_GPU=1 but no usable GPU: {e}")
        pytest.skip(f"no usable GPU: {e}")
    assert gpu.errors == cpu.errors and list(gpu.errors) == [5]
    for k in np.flatnonzero(cpu.ok):
        assert kpt.first_difference(gpu.to_events(k), cpu.to_events(k), **TOL) is None, k
        g, c = gpu.to_final(k), cpu.to_final(k)
        for bid in c:
            assert (g[bid]["state"], g[bid]["pocket"]) == (c[bid]["state"], c[bid]["pocket"])
            assert math.hypot(g[bid]["x"] - c[bid]["x"], g[bid]["y"] - c[bid]["y"]) < 1e-9


if __name__ == "__main__" and sys.argv[1:2] == ["--pt-simulate"]:
    _main_pt_simulate(json.loads(sys.argv[2]))
