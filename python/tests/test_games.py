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


def arrays(shots, balls, strike_columns):
    """The balls (rows with shot, ball, x, y) and the strikes (one row a shot, the strike's
    fields under `strike_columns`' names) as kisstime's arrays, one table a shot."""
    b = np.zeros(len(balls), dtype=kisstime.BALL_DTYPE)
    b["table"] = [int(r["shot"]) for r in balls]
    b["ball"] = [int(r["ball"]) for r in balls]
    b["x"] = [float(r["x"]) for r in balls]
    b["y"] = [float(r["y"]) for r in balls]
    s = np.zeros(len(shots), dtype=kisstime.STRIKE_DTYPE)
    s["table"] = [int(r["shot"]) for r in shots]
    for k, c in zip(("V0", "phi", "theta", "a", "b"), strike_columns):
        s[k] = [float(r[c]) for r in shots]
    return b, s


def reference():
    shots = rows("shots.csv")
    b, s = arrays(shots, rows("balls.csv"), ("v0", "phi", "theta", "a", "b"))
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
        kisstime.simulate(balls, strikes, table="7ft", rules="pyramid")
    with pytest.raises(ValueError, match="table 9999"):
        kisstime.simulate(balls, strikes, table="7ft", rules="8-ball",
                          context={"table": [9999], "break": [False]})
    with pytest.raises(ValueError, match="pocket_call"):
        kisstime.simulate(balls, strikes, table="7ft", rules="8-ball",
                          context={"table": [5], "pocket_call": ["zz"]})
    with pytest.raises(ValueError, match="rules"):
        kisstime.simulate(balls, strikes, table="7ft", context={"table": [5]})


def test_the_pooltool_bridge_judges_in_pooltools_terms():
    """A pooltool position (the reference set's 9-ball break, shot 0, and an 8-ball shot)
    through ``from_system(...).simulate(rules=...)``: pooltool's own verdict."""
    pt = pytest.importorskip("pooltool")
    import kisstime.pooltool as kpt

    for game, rules, shot_no in [("nine_ball", "9-ball", 0), ("eight_ball", "8-ball", 1)]:
        data = DATA.parent / game

        def rows_of(name):
            with open(data / name, newline="") as f:
                return list(csv.DictReader(f))

        shot = [r for r in rows_of("shots.csv") if int(r["shot"]) == shot_no][0]
        balls = {}
        # pooltool's dict order: the racks' own, here the cue ball last (kisstime keeps
        # the system's order through the bridge whatever the game's ids)
        layout = [r for r in rows_of("balls.csv") if int(r["shot"]) == shot_no]
        for r in layout[1:] + layout[:1]:
            bid = "cue" if r["ball"] == "0" else r["ball"]
            balls[bid] = pt.Ball.create(bid, xy=(float(r["x"]), float(r["y"])))
        cue = pt.Cue(cue_ball_id="cue")
        cue.set_state(V0=float(shot["v0"]), phi=float(shot["phi"]),
                      theta=float(shot["theta"]), a=float(shot["a"]), b=float(shot["b"]))
        system = pt.System(cue=cue, table=pt.Table.default(), balls=balls)
        conv = kpt.from_system(system)
        hittable = shot.get("hittable") or None
        res = conv.simulate(
            rules=rules,
            break_shot=shot["break"] == "1",
            hittable=tuple(hittable.split(";")) if hittable else None,
            ball_call=shot.get("ball_call") or None,
            pocket_call=shot.get("pocket_call") or None,
            events=False,
        )
        oc = res.outcomes[0]
        assert int(oc["legal"]) == int(shot["legal"]), game
        assert int(oc["turn_over"]) == int(shot["turn_over"]), game
        assert int(oc["game_over"]) == int(shot["game_over"]), game
    with pytest.raises(ValueError, match="is not a ball"):
        conv.simulate(rules="8-ball", ball_call="99")


def test_three_cushion_points_through_python_are_pooltools():
    """``table="carom", rules="three-cushion"`` on data/carom's shots (the carom balls come
    with the table): a point (``turn_over`` 0) exactly where pooltool's is_point scored."""
    carom = DATA.parents[1] / "carom"
    with open(carom / "shots.csv", newline="") as f:
        shots = list(csv.DictReader(f))
    with open(carom / "initial.csv", newline="") as f:
        balls = list(csv.DictReader(f))
    b, s = arrays(shots, balls, ("V0", "phi", "theta", "a", "b"))
    res = kisstime.simulate(b, s, table="carom", rules="three-cushion", events=False)
    points = np.array([r["point"] == "1" for r in shots])
    assert 5 <= points.sum() <= len(shots) - 5
    assert res.outcomes["legal"].all()
    assert ((res.outcomes["turn_over"] == 0) == points).all()


def test_a_study_with_a_game_reports_its_verdicts_through_python_and_chunks():
    """A scenario dict with a ``game`` section: the summary's ``game`` counts are the
    samples' verdict fields, the same whatever the chunking (the blob Dask's tasks return
    carries the verdicts), and they equal the command line's."""
    import tomllib

    root = DATA.parents[2]
    with open(root / "examples" / "study.toml", "rb") as f:
        scen = tomllib.load(f)
    scen["game"] = {"rules": "8-ball", "hittable": [1, 2, 3, 4, 5, 7], "ball_call": 7,
                    "pocket_call": "lb"}
    study = kisstime.shot_study(scen, samples=2000, seed=5)
    g = study.summary["game"]
    rows = study.samples
    assert g["rules"] == "8-ball"
    assert g["legal"]["count"] == int((rows["legal"] == 1).sum())
    assert g["turn_kept"]["count"] == int((rows["turn_over"] == 0).sum())
    cue = kisstime.FOULS.index("cue_pocketed")
    assert g["fouls"]["cue_pocketed"]["count"] == int((rows["foul"] == cue).sum()) > 0
    assert ((rows["legal"] == 1) == (rows["foul"] == -1)).all()
    assert (rows["points"] == 0).all() and (rows["foul_points"] == 0).all(), "pool scores none"
    again = kisstime.shot_study(scen, samples=2000, seed=5, chunk=300)
    assert again.summary["game"] == g
    assert (again.samples == rows).all()
    # without a game every verdict field is -1
    # snooker's points come back through Python and through chunks
    with open(root / "examples" / "snooker.toml", "rb") as f:
        snooker = tomllib.load(f)
    sn = kisstime.shot_study(snooker, samples=600, seed=5, chunk=200)
    kept = sn.samples["turn_over"] == 0
    assert kept.sum() > 200
    assert (sn.samples["points"][kept] == 1).all(), "a red scores 1"
    assert (sn.samples["foul_points"][sn.samples["legal"] == 0] == 4).all(), "the white in: 4"
    assert sn.summary["game"]["points"]["mean"] == sn.samples["points"].mean()
    del scen["game"]
    plain = kisstime.shot_study(scen, samples=50, seed=5)
    assert "game" not in plain.summary or plain.summary["game"] is None
    assert (plain.samples["legal"] == -1).all()


def test_the_wpa_reading_through_python():
    """``wpa=True`` (``--wpa``) on the 8-ball reference set: the verdicts are pooltool's but
    on the breaks that pocket the 8, where the WPA ends no game (and a legal one keeps
    the table); the set has such a break."""
    eight = DATA.parent / "eight_ball"
    with open(eight / "shots.csv", newline="") as f:
        shots = list(csv.DictReader(f))
    with open(eight / "balls.csv", newline="") as f:
        balls = list(csv.DictReader(f))
    b, s = arrays(shots, balls, ("v0", "phi", "theta", "a", "b"))
    on = {}
    for r in balls:
        on.setdefault(r["shot"], set()).add(int(r["ball"]))
    context = {
        "table": [int(r["shot"]) for r in shots],
        "break": [r["break"] == "1" for r in shots],
        # the group, less its balls no longer on the table
        "hittable": [[h for h in r["hittable"].split(";") if h and int(h) in on[r["shot"]]]
                     for r in shots],
        "ball_call": [int(r["ball_call"]) if r["ball_call"] else -1 for r in shots],
        "pocket_call": [r["pocket_call"] for r in shots],
    }
    run = lambda wpa: kisstime.simulate(b, s, table="7ft", rules="8-ball", context=context,
                                        wpa=wpa)
    plain, wpa = run(False), run(True)
    eight_down = np.zeros(len(shots), dtype=bool)
    fin = plain.final
    down = fin[(fin["ball"] == 8) & (fin["state"] == 4)]["table"]
    eight_down[np.searchsorted(plain.outcomes["table"], down)] = True
    breaks = np.array([r["break"] == "1" for r in shots])
    parts = breaks & eight_down
    assert parts.sum() >= 1
    p, w = plain.outcomes, wpa.outcomes
    for f in ("legal", "foul", "turn_over", "game_over", "won"):
        assert (p[f][~parts] == w[f][~parts]).all(), f
    assert (w["game_over"][parts] == 0).all() and (p["game_over"][parts] == 1).all()
    assert (w["turn_over"][parts] == 1 - w["legal"][parts]).all()


SNOOKER = DATA.parent / "snooker"
# pooltool's snooker ball ids, in kisstime's order (white 0, red_01..red_15 1-15, yellow 16
# to black 21)
SNOOKER_NAMES = ["white", *(f"red_{i:02d}" for i in range(1, 16)), "yellow", "green", "brown",
                 "blue", "pink", "black"]
SNOOKER_REASONS = {
    "": "",
    "cue_pocketed": "Cue ball in pocket!",
    "no_hit": "No ball contacted!",
    "wrong_ball_first": "First contact made with a ball that's not on!",
    "off_ball_pocketed": "Pocketed a ball that's not on!",
}


def snooker_rows(name: str) -> list[dict]:
    with open(SNOOKER / name, newline="") as f:
        return list(csv.DictReader(f))


def test_snooker_verdicts_and_points_through_python_are_pooltools():
    """``rules="snooker"`` on data/games/snooker (pooltool's own ``_Snooker`` verdicts) with
    each shot's context as a dict of columns — hittable and the call by pooltool's names —
    and the score before it: legal, the reason, turn over, game over, the points, the foul
    points and the winner are pooltool's on every shot with pooltool's event count."""
    shots = snooker_rows("shots.csv")
    layout = snooker_rows("balls.csv")
    b, s = arrays(shots, layout, ("v0", "phi", "theta", "a", "b"))
    on = {}
    for r in layout:
        on.setdefault(r["shot"], set()).add(int(r["ball"]))
    names = SNOOKER_NAMES
    context = {
        "table": [int(r["shot"]) for r in shots],
        "break": [r["break"] == "1" for r in shots],
        # the group's balls on the table, by name
        "hittable": [[h for h in r["hittable"].split(";") if names.index(h) in on[r["shot"]]]
                     for r in shots],
        "ball_call": [r["ball_call"] or None for r in shots],
        "score": [int(r["score"]) for r in shots],
        "opponent_score": [int(r["opponent_score"]) for r in shots],
    }
    res = kisstime.simulate(b, s, table="snooker", events=False, rules="snooker",
                            context=context)
    oc = res.outcomes
    judged = 0
    for row, shot in zip(oc, shots):
        if int(row["events"]) != int(shot["n_events"]):
            continue
        judged += 1
        foul = kisstime.FOULS[row["foul"]] if row["foul"] >= 0 else ""
        assert SNOOKER_REASONS[foul] == shot["reason"], shot["shot"]
        got = tuple(int(row[k]) for k in ("legal", "turn_over", "game_over", "won", "points",
                                          "foul_points"))
        want = tuple(int(shot[k]) for k in ("legal", "turn_over", "game_over", "won",
                                            "points", "foul_points"))
        assert got == want, shot["shot"]
    assert judged >= 396
    assert oc["points"].max() >= 2 and set(oc["foul_points"]) >= {0, 4, 5, 6, 7}


def test_the_pooltool_bridge_judges_snooker_in_pooltools_terms():
    """A snooker position of the reference set through ``from_system(...).simulate(
    rules="snooker", hittable=..., ball_call=..., score=...)``, pooltool's ball ids and
    groups as they are: pooltool's verdict, points and winner, on a frame-ending final
    black and on a foul."""
    pt = pytest.importorskip("pooltool")
    import kisstime.pooltool as kpt
    from pooltool.game.datatypes import GameType

    shots = snooker_rows("shots.csv")
    layout = snooker_rows("balls.csv")
    names = SNOOKER_NAMES
    final = next(r for r in shots if r["game_over"] == "1" and r["legal"] == "1")
    foul = next(r for r in shots if r["reason"] and r["ball_call"] and r["break"] == "0")
    import attrs

    params = attrs.asdict(pt.BallParams.default(GameType.SNOOKER))
    for shot in (final, foul):
        balls = {}
        for r in layout:
            if r["shot"] == shot["shot"]:
                bid = names[int(r["ball"])]
                balls[bid] = pt.Ball.create(bid, xy=(float(r["x"]), float(r["y"])), **params)
        cue = pt.Cue(cue_ball_id="white")
        cue.set_state(V0=float(shot["v0"]), phi=float(shot["phi"]),
                      theta=float(shot["theta"]), a=float(shot["a"]), b=float(shot["b"]))
        table = pt.Table.from_game_type(GameType.SNOOKER)
        conv = kpt.from_system(pt.System(cue=cue, table=table, balls=balls))
        res = conv.simulate(
            rules="snooker",
            hittable=tuple(shot["hittable"].split(";")),
            ball_call=shot["ball_call"] or None,
            score=(int(shot["score"]), int(shot["opponent_score"])),
            events=False,
        )
        oc = res.outcomes[0]
        for k in ("legal", "turn_over", "game_over", "won", "points", "foul_points"):
            assert int(oc[k]) == int(shot[k]), (shot["shot"], k)
    with pytest.raises(ValueError, match="call one"):
        conv.simulate(rules="snooker", hittable=("yellow", "green", "brown", "blue", "pink",
                                                 "black"), events=False)
    with pytest.raises(ValueError, match="snooker takes the balls"):
        kpt.from_system(pt.System(cue=pt.Cue(cue_ball_id="cue"), table=table,
                                  balls={"cue": pt.Ball.create("cue", xy=(0.5, 0.5)),
                                         "1": pt.Ball.create("1", xy=(0.5, 1.0))})
                        ).simulate(rules="snooker")
