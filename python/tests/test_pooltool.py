"""kisstime.pooltool: pooltool Systems converted, simulated by kisstime, compared with pooltool.

Shots of the full-shot reference set (data/fullshots: a break and ordinary shots, with
linear and circular cushion hits, a pot and a scratch) are built as pooltool ``System``s
the way the set was made, converted with ``from_system``, simulated by
``kisstime.simulate`` and turned back with ``to_events``; the events must be pooltool's
recorded ones (``events.csv.gz``): the same types and agents in the same order, times
within 1e-9 (relative or absolute), over the stretch the set's rule demands (the whole
shot, or up to the first event at which pooltool's own 1 µm-nudged runs diverge).

``pt.simulate`` itself runs on two short shots and a shot with a moving ball, in a
subprocess with ``NUMBA_DISABLE_JIT=1``: pooltool's numba code takes about a minute to
compile on a cold cache, and is exact pure Python without it (same reference events).

pooltool is required in CI (``CI`` set): there a missing install fails the import
instead of skipping.
"""

from __future__ import annotations

import csv
import gzip
import json
import math
import os
import subprocess
import sys
from functools import lru_cache
from pathlib import Path

import numpy as np
import pytest

if os.environ.get("CI"):
    import pooltool as pt
else:
    pt = pytest.importorskip("pooltool")
import pooltool.constants as pt_const  # noqa: E402
from pooltool.events.datatypes import AgentType  # noqa: E402
from pooltool.objects.ball.datatypes import BallState  # noqa: E402
from pooltool.objects.table.specs import PocketTableSpecs  # noqa: E402

import kisstime  # noqa: E402
import kisstime.pooltool as kpt  # noqa: E402

# the reference sets live in the repository's data/ (as for the crate's tests: CARGO_MANIFEST_DIR/data).
FULLSHOTS = Path(__file__).resolve().parents[2] / "data" / "fullshots"
# 120 shots made with every ball's BallParams changed as physics.toml says
PHYSICS = Path(__file__).resolve().parents[2] / "data" / "physics"

# Times: 1e-9 relative or absolute (the longest shot here, a 859-event break, is within
# 8.3e-10 s of pooltool; the ordinary shots within 1e-11 s).
TOL = dict(rel_tol=1e-9, abs_tol=1e-9)

REFERENCE_SHOTS = [1, 105, 122, 150, 250, 254]  # break; jaw hit; pot; ordinary; scratch
PT_SIMULATE_SHOTS = [105, 254]


# --------------------------------------------------------------------------- the set
@lru_cache(maxsize=None)
def _shots(ref: Path = FULLSHOTS) -> dict[int, dict[str, str]]:
    with open(ref / "shots.csv", newline="") as f:
        return {int(r["shot"]): r for r in csv.DictReader(f)}


@lru_cache(maxsize=None)
def _initial(ref: Path = FULLSHOTS) -> dict[int, list[dict[str, str]]]:
    out: dict[int, list[dict[str, str]]] = {}
    with open(ref / "initial.csv", newline="") as f:
        for r in csv.DictReader(f):
            out.setdefault(int(r["shot"]), []).append(r)
    for rows in out.values():
        rows.sort(key=lambda r: int(r["ball"]))
    return out


@lru_cache(maxsize=None)
def _events(ref: Path = FULLSHOTS) -> dict[int, list[dict]]:
    out: dict[int, list[dict]] = {}
    with gzip.open(ref / "events.csv.gz", "rt", newline="") as f:
        for r in csv.DictReader(f):
            out.setdefault(int(r["shot"]), []).append(
                {"type": r["type"], "time": float(r["t"]), "agents": tuple(r["agents"].split(";"))}
            )
    return out


@lru_cache(maxsize=None)
def _final() -> dict[int, dict[str, dict[str, str]]]:
    out: dict[int, dict[str, dict[str, str]]] = {}
    with open(FULLSHOTS / "final.csv", newline="") as f:
        for r in csv.DictReader(f):
            out.setdefault(int(r["shot"]), {})[r["ball_id"]] = r
    return out


@lru_cache(maxsize=None)
def _event_bar(ref: Path = FULLSHOTS) -> dict[int, float]:
    """The set's k_s: events 0..k_s-1 must match (inf: the whole shot)."""
    with open(ref / "stability.csv", newline="") as f:
        return {
            int(r["shot"]): math.inf if r["event_bar"] == "" else int(r["event_bar"])
            for r in csv.DictReader(f)
        }


def _table_json() -> dict:
    with open(FULLSHOTS / "table.json") as f:
        return json.load(f)["table"]


def make_system(shot: int, ref: Path = FULLSHOTS, **params: float) -> "pt.System":
    """Shot `shot` of the set `ref` as a pooltool System before the strike (as it was
    made: every ball with the BallParams `params`, pooltool's defaults for the rest)."""
    s = _shots(ref)[shot]
    balls = {
        r["ball_id"]: pt.Ball.create(r["ball_id"], xy=(float(r["x"]), float(r["y"])), **params)
        for r in _initial(ref)[shot]
    }
    cue = pt.Cue(cue_ball_id=s["cue_ball_id"])
    cue.set_state(
        V0=float(s["V0"]), phi=float(s["phi"]), theta=float(s["theta"]),
        a=float(s["a"]), b=float(s["b"]),
    )
    table = pt.Table.from_table_specs(PocketTableSpecs(l=2.54, w=1.27))
    return pt.System(cue=cue, table=table, balls=balls)


def moving_system() -> "pt.System":
    """Three balls, the cue ball sliding with spin toward ball "2" (no strike: the cue's
    V0 is 0). pooltool's ball order (cue, 2, 1) is not the ids' sorted order."""
    balls = {
        "cue": pt.Ball.create("cue", xy=(0.5, 0.6)),
        "2": pt.Ball.create("2", xy=(0.52, 1.5)),
        "1": pt.Ball.create("1", xy=(1.0, 2.2)),
    }
    balls["cue"].state = BallState(
        rvw=np.array([[0.5, 0.6, 0.028575], [0.05, 1.8, 0.0], [-20.0, 5.0, 12.0]]),
        s=pt_const.sliding,
    )
    cue = pt.Cue(cue_ball_id="cue")
    cue.set_state(V0=0.0)
    table = pt.Table.from_table_specs(PocketTableSpecs(l=2.54, w=1.27))
    return pt.System(cue=cue, table=table, balls=balls)


def kisstime_events(system, **kw):
    conv = kpt.from_system(system)
    result = conv.simulate(**kw)
    return conv, result, kpt.to_events(result, conv)


def assert_same_events(got: list[dict], want: list[dict], upto: float = math.inf) -> None:
    """Same types and agents in the same order and times within TOL, over events
    0..upto-1 (upto inf: all of them, and the same number of events)."""
    n = len(want) if upto == math.inf else int(upto)
    if upto == math.inf:
        assert len(got) == len(want), f"{len(got)} events, pooltool {len(want)}"
    else:
        assert len(got) >= n and len(want) >= n
    first = kpt.first_difference(got[:n], want[:n], **TOL)
    if first is not None:
        lo = max(0, first - 2)
        pytest.fail(
            f"event {first} differs:\n  kisstime {got[lo:first + 2]}\n  pooltool {want[lo:first + 2]}"
        )


# --------------------------------------------------------------------------- from_system
def test_from_system_balls_strike_and_ids():
    shot = 150
    system = make_system(shot)
    conv = kpt.from_system(system)
    rows = _initial()[shot]
    assert conv.ball_ids == [r["ball_id"] for r in rows] == list(system.balls)
    assert conv.balls.dtype == kisstime.BALL_DTYPE
    b = conv.balls
    assert b["table"].tolist() == [0] * len(rows)
    assert b["ball"].tolist() == list(range(len(rows)))
    assert b["state"].tolist() == [0] * len(rows)
    assert b["x"].tolist() == [float(r["x"]) for r in rows]
    assert b["y"].tolist() == [float(r["y"]) for r in rows]
    for c in ("vx", "vy", "wx", "wy", "wz"):
        assert not b[c].any()

    s = _shots()[shot]
    assert conv.strikes.dtype == kisstime.STRIKE_DTYPE
    assert len(conv.strikes) == 1
    st = conv.strikes[0]
    assert int(st["table"]) == 0
    assert int(st["ball"]) == conv.ball(s["cue_ball_id"]) == conv.ball_ids.index("cue")
    for c in ("V0", "phi", "theta", "a", "b"):
        assert float(st[c]) == float(s[c]), c
    assert conv.cue_id == "cue_stick"
    assert conv.table_id == 0

    other = kpt.from_system(system, table=7)
    assert other.balls["table"].tolist() == [7] * len(rows)
    assert other.strikes["table"].tolist() == [7]
    with pytest.raises(KeyError):
        conv.ball("no such ball")


def test_from_system_moving_ball_and_no_strike():
    system = moving_system()
    conv = kpt.from_system(system)
    assert conv.ball_ids == ["cue", "2", "1"]
    assert len(conv.strikes) == 0
    cue = conv.balls[0]
    assert int(cue["state"]) == 2  # sliding
    assert [float(cue[c]) for c in ("x", "y", "vx", "vy", "wx", "wy", "wz")] == [
        0.5, 0.6, 0.05, 1.8, -20.0, 5.0, 12.0,
    ]
    assert conv.balls["state"].tolist() == [2, 0, 0]


def test_table_json_is_the_sets_table():
    conv = kpt.from_system(make_system(250))
    mine = json.loads(conv.table)
    ref = _table_json()
    for key in ("linear_cushion_segments", "circular_cushion_segments", "pockets"):
        assert list(mine[key]) == list(ref[key]), key  # same ids in the same order
    for sid, seg in mine["linear_cushion_segments"].items():
        r = ref["linear_cushion_segments"][sid]
        assert (seg["p1"], seg["p2"], seg["direction"]) == (r["p1"], r["p2"], r["direction"])
    for cid, seg in mine["circular_cushion_segments"].items():
        r = ref["circular_cushion_segments"][cid]
        assert (seg["center"], seg["radius"]) == (r["center"], r["radius"])
    for pid, p in mine["pockets"].items():
        r = ref["pockets"][pid]
        assert (p["center"], p["radius"], p["depth"]) == (r["center"], r["radius"], r["depth"])
    assert conv.table_ids == {
        "linear": list(ref["linear_cushion_segments"]),
        "circular": list(ref["circular_cushion_segments"]),
        "pockets": list(ref["pockets"]),
    }
    # kisstime's built-in 9-ft table lists the same items in the same order
    ids = kisstime.table_ids("9ft")
    assert {k: list(ids[k]) for k in ("linear", "circular", "pockets")} == conv.table_ids
    assert list(ids["pockets"]) == ["lb", "lc", "lt", "rb", "rc", "rt"]


def test_write_table_round_trips(tmp_path):
    conv = kpt.from_system(make_system(250))
    path = conv.write_table(tmp_path / "t.json")
    assert path == str(tmp_path / "t.json")
    assert Path(path).read_text() == conv.table
    assert kpt._ids_of_layout(path) == conv.table_ids
    # the whole table.json file (table under "table") gives the same ids
    assert kpt._ids_of_layout(FULLSHOTS / "table.json") == conv.table_ids


def _physics_params() -> dict[str, float]:
    import tomllib

    return tomllib.loads((PHYSICS / "physics.toml").read_text())


def test_default_parameters_convert_to_pooltools_defaults():
    conv = kpt.from_system(make_system(250))
    d = pt.objects.BallParams()
    assert conv.physics == {
        **{k: float(getattr(d, k)) for k in kisstime.PHYSICS_KEYS},
        "cue": {"M": 0.567, "end_mass": 0.170097 / 30},
    }


@pytest.mark.parametrize("shot", [0, 3, 57, 100])  # ordinary shots and a break
def test_non_default_ball_params_are_carried_and_replay_the_physics_set(shot):
    """A System whose balls all have the physics set's BallParams converts with them, and
    simulating the converted system gives pooltool's recorded events under them."""
    params = _physics_params()
    system = make_system(shot, PHYSICS, **params)
    conv = kpt.from_system(system)
    for k, v in params.items():
        assert conv.physics[k] == v, k
    assert conv.physics["u_s"] != pt.objects.BallParams().u_s
    result = conv.simulate()
    assert_same_events(
        kpt.to_events(result, conv), _events(PHYSICS)[shot], _event_bar(PHYSICS)[shot]
    )
    # with pooltool's defaults instead, the same shot goes elsewhere
    default = conv.simulate(physics=None)
    assert kpt.first_difference(kpt.to_events(default, conv), _events(PHYSICS)[shot], **TOL) is not None


def test_balls_with_different_params_are_refused():
    system = make_system(250)
    first, last = list(system.balls)[0], list(system.balls)[-1]
    ball = system.balls[last]
    system.balls[last] = pt.Ball.create(last, xy=tuple(ball.state.rvw[0][:2]), u_r=0.011)
    with pytest.raises(ValueError, match=rf"ball '{last}' u_r = 0\.011 \(ball '{first}': 0\.01\)"):
        kpt.from_system(system)
    conv = kpt.from_system(system, check=False)  # the first ball's
    assert len(conv.balls) == len(system.balls) and conv.physics["u_r"] == 0.01


def test_out_of_range_params_are_refused_when_simulating():
    system = make_system(250, e_c=1.5)
    conv = kpt.from_system(system)
    with pytest.raises(ValueError, match=r"^physics: key `e_c` is 1\.5, it must be in \(0, 1\]"):
        conv.simulate()


def test_missing_pooltool_says_how_to_install(monkeypatch):
    monkeypatch.setitem(sys.modules, "pooltool", None)  # import pooltool -> ImportError
    with pytest.raises(ImportError, match=r"pip install --no-deps pooltool-billiards==0\.6\.0"):
        kpt.from_system(object())


# --------------------------------------------------------------------------- to_events
@pytest.mark.parametrize("shot", REFERENCE_SHOTS)
def test_events_are_pooltools_recorded_events(shot):
    conv, result, got = kisstime_events(make_system(shot))
    want = _events()[shot]
    assert want[0]["agents"] == ("cue_stick", "cue")
    assert_same_events(got, want, _event_bar()[shot])
    if _event_bar()[shot] == math.inf:
        # the same end: pocketed set and final positions (within the set's 1 mm bar,
        # and in fact far closer)
        final = kpt.to_final(result, conv)
        ref = _final()[shot]
        assert list(final) == list(ref)
        for bid, r in ref.items():
            f = final[bid]
            assert f["state"] == r["state"], bid
            assert (f["pocket"] or "") == r["pocket"], bid
            assert math.hypot(f["x"] - float(r["x"]), f["y"] - float(r["y"])) < 1e-6, bid


def test_to_events_shapes():
    conv, result, got = kisstime_events(make_system(254))
    types = [e["type"] for e in got]
    assert types == [
        "stick_ball", "sliding_rolling", "ball_ball", "ball_pocket", "sliding_rolling",
        "rolling_stationary",
    ]
    assert got[0] == {"type": "stick_ball", "time": 0.0, "agents": ("cue_stick", "cue")}
    assert got[2]["agents"] == ("cue", "14")
    assert got[3]["agents"] == ("cue", "rc")
    assert got[1]["agents"] == ("cue",)
    # the events array itself works as well, and an explicit table id
    assert kpt.to_events(result.events, conv, 0) == got
    # one dict per event: the two rows of a ball-ball event are merged
    assert len(got) == len(np.unique(result.events["k"]))
    assert kpt.to_events(result, conv, table=3) == []


def test_json_table_gives_the_same_events_as_9ft():
    for shot in (1, 105):
        conv = kpt.from_system(make_system(shot))
        via_json = conv.simulate()
        builtin = conv.simulate(table="9ft")
        assert via_json.events.dtype == builtin.events.dtype
        assert via_json.events.tobytes() == builtin.events.tobytes()
        assert via_json.final.tobytes() == builtin.final.tobytes()
        assert via_json.outcomes.tobytes() == builtin.outcomes.tobytes()
        assert kpt.to_events(builtin, conv, layout="9ft") == kpt.to_events(via_json, conv)
        assert kpt.to_final(builtin, conv, layout="9ft") == kpt.to_final(via_json, conv)


def test_simulate_by_hand_equals_converted_simulate(tmp_path):
    conv = kpt.from_system(make_system(122))
    path = conv.write_table(tmp_path / "table.json")
    by_hand = kisstime.simulate(conv.balls, conv.strikes, table=path)
    assert by_hand.events.tobytes() == conv.simulate().events.tobytes()
    assert kpt.to_events(by_hand, conv, layout=path) == kpt.to_events(by_hand, conv)


def test_no_strike_at_rest_gives_no_events():
    system = make_system(250)
    system.cue.set_state(V0=0.0)
    conv, result, got = kisstime_events(system)
    assert len(conv.strikes) == 0
    assert got == []
    assert result.outcomes["events"].tolist() == [0]


def test_first_difference():
    a = [
        {"type": "stick_ball", "time": 0.0, "agents": ("cue_stick", "cue")},
        {"type": "ball_ball", "time": 1.0, "agents": ("cue", "1")},
    ]
    b = [dict(a[0]), {"type": "ball_ball", "time": 1.0 + 1e-12, "agents": ("1", "cue")}]
    assert kpt.first_difference(a, a) is None
    assert kpt.first_difference(a, b) == 1
    assert kpt.first_difference(a, b, unordered_pairs=True) is None
    assert kpt.first_difference(a, a[:1]) == 1
    c = [dict(a[0]), dict(a[1], time=1.1)]
    assert kpt.first_difference(a, c) == 1


# --------------------------------------------------------------------------- pt.simulate
def _pt_simulate_in_subprocess() -> dict:
    """from_pooltool_events / from_pooltool_final of pt.simulate on PT_SIMULATE_SHOTS and
    moving_system(), run by this file as a script without numba's JIT."""
    env = dict(os.environ, NUMBA_DISABLE_JIT="1", PYTHONPATH=os.pathsep.join(sys.path))
    run = subprocess.run(
        [sys.executable, __file__, "--pt-simulate"],
        env=env, capture_output=True, text=True, timeout=300,
    )
    assert run.returncode == 0, run.stderr[-4000:]
    return json.loads(run.stdout.strip().splitlines()[-1])


@pytest.fixture(scope="module")
def pt_results() -> dict:
    return _pt_simulate_in_subprocess()


@pytest.mark.parametrize("shot", PT_SIMULATE_SHOTS)
def test_to_events_equals_pt_simulate(pt_results, shot):
    theirs = [dict(e, agents=tuple(e["agents"])) for e in pt_results[str(shot)]["events"]]
    # pooltool here is pooltool of the reference set
    assert_same_events(theirs, _events()[shot])
    conv, result, mine = kisstime_events(make_system(shot))
    assert kpt.first_difference(mine, theirs, **TOL) is None
    final, pt_final = kpt.to_final(result, conv), pt_results[str(shot)]["final"]
    assert list(final) == list(pt_final)
    for bid, f in final.items():
        g = pt_final[bid]
        assert (f["state"], f["pocket"]) == (g["state"], g["pocket"]), bid
        assert math.hypot(f["x"] - g["x"], f["y"] - g["y"]) < 1e-6, bid


def test_moving_ball_equals_pt_simulate(pt_results):
    theirs = [dict(e, agents=tuple(e["agents"])) for e in pt_results["moving"]["events"]]
    assert theirs and theirs[0]["type"] != "stick_ball"
    assert "ball_ball" in [e["type"] for e in theirs]
    conv, result, mine = kisstime_events(moving_system())
    assert kpt.first_difference(mine, theirs, **TOL) is None
    final = kpt.to_final(result, conv)
    for bid, g in pt_results["moving"]["final"].items():
        assert final[bid]["state"] == g["state"], bid
        assert math.hypot(final[bid]["x"] - g["x"], final[bid]["y"] - g["y"]) < 1e-6, bid


def jaw_system() -> "pt.System":
    """FUZZING.md's finding 30: on the 7-ft table, under scaled frictions and restitutions,
    the cue ball struck hard with draw ends chattering between ball "1" and the jaw 11t,
    and each ball–ball kiss (Q1) presses it further into the jaw, where pooltool's
    detection (roots τ > EPS only, Q6) finds no jaw contact."""
    params = dict(
        u_s=0.10703053615979914, u_r=0.005351526807989957,
        u_sp_proportionality=0.006796439046147245 / 0.028575,
        e_b=0.6372528076171875, e_c=0.4548797786791463, f_c=0.10706676685817214,
    )
    xy = {
        "cue": (0.26190203704833986, 0.5338272994995117),
        "1": (0.2680727123695044, 0.5906429130597868),
        "2": (0.32274157165991874, 0.5739864331195599),
        "3": (0.25930369188503394, 0.647115874765602),
    }
    balls = {bid: pt.Ball.create(bid, xy=p, **params) for bid, p in xy.items()}
    cue = pt.Cue(cue_ball_id="cue")
    cue.set_state(V0=6.2689208984375, phi=112.5, theta=16.5234375,
                  a=-0.10865749163367232, b=0.7001047596694929)
    return pt.System(cue=cue, table=pt.Table.default(), balls=balls)


def test_a_ball_pressed_into_a_jaw_goes_in_as_in_pooltool(pt_results):
    """Finding 30 is pooltool's own behaviour, reproduced: the same events, and the cue
    ball ends inside the contact circle of the jaw 11t (its centre closer than r_jaw + R
    to the jaw's centre) in both. The Rust twin,
    `a_ball_pressed_into_a_jaw_goes_in_as_in_pooltool` in tests/fuzz_regressions.rs, checks
    that the invariant checker tells it apart as `RailTunnel`."""
    theirs = [dict(e, agents=tuple(e["agents"])) for e in pt_results["jaw"]["events"]]
    conv, result, mine = kisstime_events(jaw_system())
    assert kpt.first_difference(mine, theirs, **TOL) is None
    jaw = pt.Table.default().cushion_segments.circular["11t"]
    contact = jaw.radius + 0.028575
    final = kpt.to_final(result, conv)
    for who, end in (("pooltool", pt_results["jaw"]["final"]["cue"]), ("kisstime", final["cue"])):
        d = math.hypot(end["x"] - jaw.center[0], end["y"] - jaw.center[1])
        assert contact - 5e-5 < d < contact - 1e-5, (who, d, contact)
    g = pt_results["jaw"]["final"]["cue"]
    assert math.hypot(final["cue"]["x"] - g["x"], final["cue"]["y"] - g["y"]) < 1e-9


def touching_system() -> "pt.System":
    """FUZZING.md's finding 31: three balls in a row, each pair exactly 2R apart as
    pooltool's quartic sees it (its constant coefficient is 0), the end ball struck away
    from its neighbour at 1e-9 m/s with massé."""
    xy = {
        "1": (0.3205843640387058, 0.191408986531198),
        "2": (0.28262233721207614, 0.23412908741139543),
        "cue": (0.2363870159835479, 0.2005371602428806),
    }
    balls = {bid: pt.Ball.create(bid, xy=p) for bid, p in xy.items()}
    cue = pt.Cue(cue_ball_id="cue")
    cue.set_state(V0=1e-9, phi=215.9967041015625, theta=53.988189697265625,
                  a=-0.629118477661764, b=-0.45188581056623933)
    table = pt.Table.from_table_specs(PocketTableSpecs(l=2.54, w=1.27))
    return pt.System(cue=cue, table=table, balls=balls)


def test_exactly_touching_balls_collide_at_once_as_in_pooltool(pt_results):
    """pooltool's root filter keeps τ = 0, so exactly touching balls collide at once even
    when moving apart; kisstime gives the same events (three kisses at t = 0) and ends."""
    theirs = [dict(e, agents=tuple(e["agents"])) for e in pt_results["touching"]["events"]]
    assert [e["time"] for e in theirs if e["type"] == "ball_ball"] == [0.0, 0.0, 0.0]
    conv, result, mine = kisstime_events(touching_system())
    assert kpt.first_difference(mine, theirs, **TOL) is None
    final = kpt.to_final(result, conv)
    for bid, g in pt_results["touching"]["final"].items():
        assert math.hypot(final[bid]["x"] - g["x"], final[bid]["y"] - g["y"]) < 1e-9, bid


def _fuzzed_moving_ball(bid: str, xy: tuple[float, float], **params: float) -> "pt.Ball":
    """A ball sliding at (−3, −3) m/s with (−100, −100, −100) rad/s of spin, as the
    `event_loop` fuzz target's already-moving balls, with the BallParams `params`."""
    ball = pt.Ball.create(bid, xy=xy, **params)
    ball.state = BallState(
        rvw=np.array([[*xy, ball.params.R], [-3.0, -3.0, 0.0], [-100.0, -100.0, -100.0]]),
        s=pt_const.sliding,
    )
    return ball


def cushion_energy_system() -> "pt.System":
    """FUZZING.md's finding 16: a ball sliding at 4.2 m/s with 173 rad/s of spin into the
    foot rail, under a cushion friction four times pooltool's default."""
    R = 0.028575
    params = dict(
        u_s=0.055084161926952604, u_r=0.002500317317734928,
        u_sp_proportionality=0.019301464723413223 / R, e_b=0.5,
        e_c=0.26104106999514737, f_c=0.7913824105551804,
    )
    cue_ball = _fuzzed_moving_ball("cue", (0.09667239379882812, 2.4915564453125003), **params)
    balls = {"cue": cue_ball, "2": pt.Ball.create("2", xy=(1.0, 0.3), **params)}
    cue = pt.Cue(cue_ball_id="cue")
    cue.set_state(V0=0.0)
    table = pt.Table.from_table_specs(PocketTableSpecs(l=2.54, w=1.27))
    return pt.System(cue=cue, table=table, balls=balls)


def test_a_cushion_adds_energy_as_in_pooltool(pt_results):
    """Finding 16 is pooltool's cushion model, reproduced: pooltool's own run gains energy
    at a cushion event (the ball's kinetic energy after it above that before it), and
    kisstime gives the same events."""
    gains = pt_results["cushion_energy"]["gains"]
    assert any(g["type"] == "ball_linear_cushion" and g["after"] > 1.3 * g["before"]
               for g in gains), gains
    theirs = [dict(e, agents=tuple(e["agents"]))
              for e in pt_results["cushion_energy"]["events"]]
    conv, result, mine = kisstime_events(cushion_energy_system())
    assert len(mine) == len(theirs)
    assert kpt.first_difference(mine, theirs, **TOL) is None


def pocket_circle_system() -> "pt.System":
    """FUZZING.md's finding 32: a ball with 170 rad/s of spin chatters along the left rail
    of the 7-ft table into the corner pocket lb, and a cushion's kiss leaves its centre a
    rounding error inside the pocket's circle."""
    R = 0.028575
    params = dict(
        u_s=0.1879169515578241, u_r=0.013252366431597414,
        u_sp_proportionality=0.004261549747994339 / R, e_b=0.5,
        e_c=0.21333772610400897, f_c=0.050544464302585024,
    )
    xy = (0.6960367782592773, 0.974774609375)
    cue_ball = _fuzzed_moving_ball("cue", xy, **params)
    balls = {"cue": cue_ball, "2": pt.Ball.create("2", xy=(0.8, 1.8), **params)}
    cue = pt.Cue(cue_ball_id="cue")
    cue.set_state(V0=0.0)
    return pt.System(cue=cue, table=pt.Table.default(), balls=balls)


def test_a_ball_inside_a_pocket_circle_falls_in_as_in_pooltool(pt_results):
    """pooltool's quartic takes the first crossing of a pocket's circle either way, so a
    ball a kiss left inside it is pocketed where it leaves; kisstime gives the same events
    and pockets it in lb too."""
    theirs = [dict(e, agents=tuple(e["agents"]))
              for e in pt_results["pocket_circle"]["events"]]
    assert theirs[-1]["type"] == "ball_pocket" and theirs[-1]["agents"] == ("cue", "lb")
    conv, result, mine = kisstime_events(pocket_circle_system())
    assert len(mine) == len(theirs)
    assert kpt.first_difference(mine, theirs, **TOL) is None
    assert kpt.to_final(result, conv)["cue"]["pocket"] == "lb"


def billiard_system() -> "pt.System":
    """FUZZING.md's finding 19: on a 3 m × 3 m billiard table (no pockets), with a cushion
    friction of 1e-9 (pooltool refuses 0, and so does kisstime), a ball sliding with 173
    rad/s of spin off the bottom and left rails into the top one."""
    from pooltool.objects.table.specs import BilliardTableSpecs

    side = 2.9999618530273438
    xy = (2.8219471886157987, 0.07527489512860774)
    cue_ball = _fuzzed_moving_ball("cue", xy, f_c=1e-9)
    balls = {"cue": cue_ball, "2": pt.Ball.create("2", xy=(1.5, 2.5), f_c=1e-9)}
    cue = pt.Cue(cue_ball_id="cue")
    cue.set_state(V0=0.0)
    table = pt.Table.from_table_specs(BilliardTableSpecs(l=side, w=side))
    return pt.System(cue=cue, table=table, balls=balls)


def test_a_nearly_frictionless_cushion_shot_on_a_billiard_table_is_pooltools(pt_results):
    """kisstime's events are pooltool's on its billiard table, and the ball meets the top
    rail at y = l − R (with f_c = 0 the cushion left an acceleration of ~1e-14 along the
    rail and the copied quadratic lost its root; f_c = 0 is refused now, as in pooltool)."""
    theirs = [dict(e, agents=tuple(e["agents"])) for e in pt_results["billiard"]["events"]]
    conv, result, mine = kisstime_events(billiard_system())
    assert len(mine) == len(theirs)
    assert kpt.first_difference(mine, theirs, **TOL) is None
    with pytest.raises(ValueError, match="f_c"):
        conv.simulate(physics=dict(conv.physics, f_c=0.0))


def chatter_system() -> "pt.System":
    """FUZZING.md's finding 33: a massé into two balls by the left rail of a 0.735 m
    square billiard table."""
    from pooltool.objects.table.specs import BilliardTableSpecs

    R = 0.028575
    params = dict(
        u_s=0.050010577705338156, u_r=0.0025, u_sp_proportionality=0.003175 / R,
        e_b=0.5688400268554688, e_c=0.2125, f_c=0.05007409094683693,
    )
    xy = {
        "cue": (0.07692935004085302, 0.32022825556844475),
        "1": (0.0306652158588171, 0.4391806460296735),
        "2": (0.08881520060002804, 0.43918064602967344),
    }
    balls = {bid: pt.Ball.create(bid, xy=p, **params) for bid, p in xy.items()}
    cue = pt.Cue(cue_ball_id="cue")
    cue.set_state(V0=1.68304443359375, phi=8.4320068359375, theta=89.99862670898438,
                  a=0.998044963916957, b=0.0)
    table = pt.Table.from_table_specs(
        BilliardTableSpecs(l=0.7353286743164063, w=0.73529052734375, cushion_height=0.036576)
    )
    return pt.System(cue=cue, table=table, balls=balls)


def test_a_chattering_masse_is_pooltools_until_pooltool_raises(pt_results):
    """pooltool's own run raises in its cushion resolver (the ball does not approach the
    cushion, Q16), where kisstime gives no impulse and goes on; every event before is
    pooltool's."""
    run = pt_results["chatter"]
    assert run["raised"] == "AssertionError", run["raised"]
    theirs = [dict(e, agents=tuple(e["agents"])) for e in run["events"]]
    assert len(theirs) > 150
    conv, result, mine = kisstime_events(chatter_system(), max_events=400)
    assert len(mine) == 400 > len(theirs)
    assert kpt.first_difference(mine[: len(theirs)], theirs, **TOL) is None


def throat_system() -> "pt.System":
    """FUZZING.md's finding 34: a ball with 170 rad/s of spin chatters along the throat
    of the 7-ft table's corner pocket lb and, rolling in, clips the deep end of its
    segment."""
    R = 0.028575
    params = dict(
        u_s=0.20322407042678328, u_r=0.004767399444076855,
        u_sp_proportionality=0.0031786287836843797 / R, e_b=0.5, e_c=0.2125,
        f_c=0.050544464302585024,
    )
    xy = (0.322786402130127, 0.6505086463928222)
    moving = _fuzzed_moving_ball("1", xy, **params)
    balls = {"0": pt.Ball.create("0", xy=(0.6509302291870117, 0.6450686683654785), **params),
             "1": moving}
    cue = pt.Cue(cue_ball_id="0")
    cue.set_state(V0=0.0)
    return pt.System(cue=cue, table=pt.Table.default(), balls=balls)


def test_a_ball_clipping_a_throat_segment_end_is_pooltools(pt_results):
    """pooltool has no event where a ball passes the bare end of a straight cushion, and
    pockets it; kisstime gives the same 141 events."""
    theirs = [dict(e, agents=tuple(e["agents"])) for e in pt_results["throat"]["events"]]
    assert theirs[-1]["type"] == "ball_pocket" and theirs[-1]["agents"] == ("1", "lb")
    conv, result, mine = kisstime_events(throat_system())
    assert len(mine) == len(theirs)
    assert kpt.first_difference(mine, theirs, **TOL) is None


def _energy_gains(system) -> list[dict]:
    """The events of a simulated pooltool System at which a ball's kinetic energy
    (translation and rotation) rose, with the energy before and after."""
    gains = []
    for ev in system.events:
        for agent in ev.agents:
            if agent.agent_type != AgentType.BALL or agent.initial is None or agent.final is None:
                continue
            params = agent.initial.params

            def energy(rvw):
                v, w = rvw[1], rvw[2]
                return 0.5 * params.m * (v @ v) + 0.2 * params.m * params.R**2 * (w @ w)

            before, after = energy(agent.initial.state.rvw), energy(agent.final.state.rvw)
            if after > before + 1e-9 and ev.event_type.value != "stick_ball":
                gains.append({"type": ev.event_type.value, "before": before, "after": after})
    return gains


def _main_pt_simulate() -> None:
    out = {}
    systems = {str(s): make_system(s) for s in PT_SIMULATE_SHOTS}
    systems["moving"] = moving_system()
    systems["jaw"] = jaw_system()
    systems["touching"] = touching_system()
    systems["cushion_energy"] = cushion_energy_system()
    systems["pocket_circle"] = pocket_circle_system()
    systems["billiard"] = billiard_system()
    systems["throat"] = throat_system()
    for name, system in systems.items():
        done = pt.simulate(system)
        out[name] = {
            "events": kpt.from_pooltool_events(done),
            "final": kpt.from_pooltool_final(done),
            "gains": _energy_gains(done),
        }
    # a run pooltool stops by raising: the events it had recorded
    system = chatter_system()
    try:
        pt.simulate(system, inplace=True, max_events=400)
        raised = None
    except Exception as e:  # noqa: BLE001 - which exception is what the test checks
        raised = type(e).__name__
    out["chatter"] = {"events": kpt.from_pooltool_events(system), "raised": raised}
    print(json.dumps(out))


if __name__ == "__main__" and sys.argv[1:] == ["--pt-simulate"]:
    _main_pt_simulate()
