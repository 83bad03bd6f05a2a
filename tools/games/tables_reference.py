"""Reference shots on pooltool 0.6.0's snooker and three-cushion (carom) tables, with their
own balls, in the format of data/fullshots (so that data/fullshots/check_fullshots.py
--ref judges a replay against them).

    python tools/games/tables_reference.py snooker data/snooker
    python tools/games/tables_reference.py carom data/carom

Every shot is simulated by pooltool itself (`pt.simulate`, default engine and resolver) on
`pt.Table.from_game_type(GameType.SNOOKER)` or `(GameType.THREECUSHION)` with the balls
pooltool gives that game (`BallParams.default(game_type)`: snooker balls R = 26.19 mm,
m = 0.14 kg, u_s 0.5, f_c 0.5; carom balls R = 30.75 mm, m = 0.21 kg, f_c 0.15), and then
re-simulated six times with tiny input changes (the cue ball moved 1e-12, 1e-9 and 1e-6 m
along a random direction u1, 1e-9 and 1e-6 m along u2, V0 times 1 + 1e-12), pooltool's own
sensitivity that the checker's pass rule reads from stability.csv (data/fullshots/README.md
explains the rule).

- snooker: 10 breaks (pooltool's full snooker rack, `get_rack(SNOOKER, spacing_factor=1e-3)`,
  the cue ball where pooltool puts it, struck at a red of the pack at V0 U(3, 7) m/s) and
  30 ordinary shots (the white and 4 to 14 of the 21 object balls at random clear spots,
  struck towards one of them: V0 U(0.3, 4) m/s, a and b U(-0.4, 0.4), theta 0 or U(0, 10)°).
- carom: 40 three-cushion shots (white, yellow and red at random spots; the white struck
  at the yellow or the red with a random cut, V0 U(1.5, 6) m/s, a and b U(-0.5, 0.5),
  theta 0 or U(0, 8)°): long runs around the table with many cushion contacts. Its
  shots.csv has one more column, `point`: pooltool's own `three_cushion.is_point` on the
  shot (1: the white met both other balls, three cushions or more before the second).
  Every other carom shot hunts for a point: random strikes (V0 U(2.5, 6), any direction,
  a U(-0.5, 0.5), b U(-0.3, 0.5)) from its position until pooltool scores one (300 tries at
  most), so that the set holds points and misses alike.

Each shot depends on the seed (28 for snooker, 29 for carom) and its index only; Python's
string hashing is fixed (PYTHONHASHSEED=0, the script re-executes itself) because
pooltool's rack orders ball ids through a set. python/tests/test_games_reference.py
re-makes the first shots of each set (KISSTIME_REF_NO_STABILITY=1: without the six
perturbed runs) and compares them with the files.
"""

from __future__ import annotations

import csv
import gzip
import math
import os
import random
import subprocess
import sys
from pathlib import Path

import attrs
import numpy as np
import pooltool as pt
from pooltool.events.datatypes import AgentType, EventType
from pooltool.game.datatypes import GameType
from pooltool.ruleset import three_cushion

from kisstime.pooltool import table_json

# the game sets' generator, beside this file: its clear spots on the cloth
from reference import clear_spot  # noqa: E402

SETS = {
    "snooker": dict(game=GameType.SNOOKER, seed=28, breaks=10, ordinary=30, cue="white"),
    "carom": dict(game=GameType.THREECUSHION, seed=29, breaks=0, ordinary=40, cue="white"),
}
# the checker's perturbations (check_fullshots.CAL_PERTS + BAR_PERTS)
PERTS = ("d1e-12", "d1e-9", "d1e-9b", "V0_1e-12", "d1e-6", "d1e-6b")
FIELDS = ("same_events", "first_div", "same_pocketed", "max_dfinal", "n_events", "pocketed")


def strike_at(rng, cue_xy, target_xy, R, speed, spin, elevation, cut=0.9):
    """A strike from the cue ball towards a ball at `target_xy`: within `cut` of the
    half-angle that still hits it."""
    dx, dy = target_xy[0] - cue_xy[0], target_xy[1] - cue_xy[1]
    d = math.hypot(dx, dy)
    half = math.degrees(math.asin(min(1.0, 2 * R / d)))
    phi = math.degrees(math.atan2(dy, dx)) + rng.uniform(-cut, cut) * half
    theta = 0.0 if rng.uniform() < 0.6 else float(rng.uniform(0, elevation))
    return dict(
        V0=float(rng.uniform(*speed)),
        phi=float(phi % 360),
        theta=theta,
        a=float(rng.uniform(-spin, spin)),
        b=float(rng.uniform(-spin, spin)),
    )


def a_shot(name, rng, table, is_break):
    """`(positions {id: (x, y)} in pooltool's ball order, strike, kind, target)`."""
    spec = SETS[name]
    params = pt.BallParams.default(spec["game"])
    R = params.R
    if is_break:
        rack = pt.get_rack(spec["game"], table, spacing_factor=1e-3)
        pos = {bid: tuple(float(v) for v in b.state.rvw[0][:2]) for bid, b in rack.items()}
        reds = [bid for bid in pos if bid.startswith("red")]
        target = reds[int(rng.integers(0, len(reds)))]
        strike = strike_at(rng, pos["white"], pos[target], R, (3.0, 7.0), 0.3, 5.0, 0.5)
        return pos, strike, "break", target
    if name == "snooker":
        ids = sorted(pt.get_rack(GameType.SNOOKER, table))
        others = [i for i in ids if i != "white"]
        k = int(rng.integers(4, 15))
        chosen = sorted(rng.choice(others, size=k, replace=False).tolist())
        order = ["white"] + chosen
        speed, spin, elevation = (0.3, 4.0), 0.4, 10.0
    else:
        order = ["white", "yellow", "red"]
        speed, spin, elevation = (1.5, 6.0), 0.5, 8.0
    placed, pos = [], {}
    for bid in order:
        xy = clear_spot(rng, table, placed, R)
        placed.append(xy)
        pos[bid] = xy
    target = order[1 + int(rng.integers(0, len(order) - 1))]
    strike = strike_at(rng, pos["white"], pos[target], R, speed, spin, elevation)
    return pos, strike, "ordinary", target


def simulate(name, table, pos, strike, shift=(0.0, 0.0), v0_scale=1.0):
    """pooltool's run of a shot, the cue ball moved by `shift`, V0 times `v0_scale`."""
    params = pt.BallParams.default(SETS[name]["game"])
    balls = {}
    for bid, (x, y) in pos.items():
        if bid == "white":
            x, y = x + shift[0], y + shift[1]
        balls[bid] = pt.Ball.create(bid, xy=(x, y), **attrs.asdict(params))
    cue = pt.Cue(cue_ball_id="white")
    cue.set_state(**dict(strike, V0=strike["V0"] * v0_scale))
    system = pt.System(cue=cue, table=table, balls=balls)
    pt.simulate(system, inplace=True)
    return system


def events_of(system):
    return [e for e in system.events if e.event_type != EventType.NONE]


def identity(e):
    """The checker's event identity: type and agents, a ball-ball pair unordered, the
    stick strike by its ball only."""
    t = e.event_type.value
    ids = [a.id for a in e.agents]
    if t == "ball_ball":
        return (t, tuple(sorted(ids)))
    if t == "stick_ball":
        return (t, tuple(a.id for a in e.agents if a.agent_type == AgentType.BALL))
    return (t, tuple(ids))


def finals(system):
    """{id: (state, x, y, pocket)} at rest."""
    out = {}
    for bid, b in system.balls.items():
        x, y = (float(v) for v in b.state.rvw[0][:2])
        pocket = ""
        if b.state.s == 4:
            pocket = min(system.table.pockets.values(),
                         key=lambda p: math.dist(p.center[:2], (x, y))).id
        out[bid] = (int(b.state.s), x, y, pocket)
    return out


def compare(ref, other):
    """One stability row's six fields: the other run against the reference run."""
    ea, eb = [identity(e) for e in events_of(ref)], [identity(e) for e in events_of(other)]
    first = next((k for k, (x, y) in enumerate(zip(ea, eb)) if x != y), None)
    if first is None and len(ea) != len(eb):
        first = min(len(ea), len(eb))
    fa, fb = finals(ref), finals(other)
    pa = sorted(b for b, f in fa.items() if f[0] == 4)
    pb = sorted(b for b, f in fb.items() if f[0] == 4)
    on = [b for b in fa if fa[b][0] != 4 and fb[b][0] != 4]
    drift = max((math.dist(fa[b][1:3], fb[b][1:3]) for b in on), default=0.0)
    return dict(same_events=int(first is None), first_div="" if first is None else first,
                same_pocketed=int(pa == pb), max_dfinal=repr(drift), n_events=len(eb),
                pocketed=";".join(pb))


def unit(rng):
    a = rng.uniform(0, 2 * math.pi)
    return math.cos(a), math.sin(a)


def main(name: str, out: Path, limit: int | None = None) -> None:
    spec = SETS[name]
    rng = np.random.default_rng(spec["seed"])
    # pooltool's rack draws from `random` and `np.random`
    random.seed(spec["seed"])
    np.random.seed(spec["seed"])
    table = pt.Table.from_game_type(spec["game"])
    params = pt.BallParams.default(spec["game"])
    out.mkdir(parents=True, exist_ok=True)
    n_total = spec["breaks"] + spec["ordinary"]
    n = n_total if limit is None else min(limit, n_total)
    sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "data" / "fullshots"))
    import check_fullshots as checker

    shots_rows, initial, events, event_balls, final, stab = [], [], [], [], [], []
    for s in range(n):
        is_break = s < spec["breaks"]
        pos, strike, kind, target = a_shot(name, rng, table, is_break)
        ref = simulate(name, table, pos, strike)
        if name == "carom" and s % 2 == 1:
            # every other carom shot hunts for a point: random strikes from the same
            # position until one scores by pooltool's is_point (or 300 tries)
            for _ in range(300):
                if three_cushion.is_point(ref):
                    break
                strike = dict(V0=float(rng.uniform(2.5, 6.0)), phi=float(rng.uniform(0, 360)),
                              theta=0.0, a=float(rng.uniform(-0.5, 0.5)),
                              b=float(rng.uniform(-0.3, 0.5)))
                ref = simulate(name, table, pos, strike)
            target = ""
        u1, u2 = unit(rng), unit(rng)
        evs = events_of(ref)
        shots_rows.append([s, spec["seed"] * 1000 + s, kind, name, repr(float(table.l)),
                           repr(float(table.w)),
                           "white", repr(strike["V0"]), repr(strike["phi"]),
                           repr(strike["theta"]), repr(strike["a"]), repr(strike["b"]),
                           len(pos), target, len(evs), repr(float(evs[-1].time))]
                          + ([int(three_cushion.is_point(ref))] if name == "carom" else []))
        for i, (bid, (x, y)) in enumerate(pos.items()):
            initial.append([s, i, bid, repr(x), repr(y)])
        for k, e in enumerate(evs):
            events.append([s, k, repr(float(e.time)), e.event_type.value,
                           ";".join(a.id for a in e.agents)])
            for a in e.agents:
                if a.agent_type != AgentType.BALL:
                    continue
                st = a.final.state
                r, v, w = st.rvw
                event_balls.append([s, k, a.id, STATES[int(st.s)], *(
                    repr(float(c)) for c in (r[0], r[1], v[0], v[1], w[0], w[1], w[2]))])
        for i, (bid, f) in enumerate(finals(ref).items()):
            final.append([s, i, bid, STATES[f[0]], repr(f[1]), repr(f[2]), f[3]])
        row = {"shot": s, "seed": spec["seed"] * 1000 + s, "kind": kind, "n_events": len(evs),
               "pocketed": ";".join(sorted(b for b, f in finals(ref).items() if f[0] == 4))}
        runs = {
            "d1e-12": dict(shift=(1e-12 * u1[0], 1e-12 * u1[1])),
            "d1e-9": dict(shift=(1e-9 * u1[0], 1e-9 * u1[1])),
            "d1e-9b": dict(shift=(1e-9 * u2[0], 1e-9 * u2[1])),
            "V0_1e-12": dict(v0_scale=1 + 1e-12),
            "d1e-6": dict(shift=(1e-6 * u1[0], 1e-6 * u1[1])),
            "d1e-6b": dict(shift=(1e-6 * u2[0], 1e-6 * u2[1])),
        }
        if os.environ.get("KISSTIME_REF_NO_STABILITY") == "1":
            runs = {}  # the test's quick re-make: the shots only, no stability.csv
        for p, kw in runs.items():
            for f, v in compare(ref, simulate(name, table, pos, strike, **kw)).items():
                row[f"{p}_{f}"] = v
        if not runs:
            print(f"{name} shot {s}: {kind}, {len(pos)} balls, {len(evs)} events", flush=True)
            continue
        rule = checker.shot_rule({k: str(v) for k, v in row.items()}, row["pocketed"])
        row.update({"class": rule["cls"], "drift": repr(rule["drift"]),
                    "final_tol": repr(rule["final_tol"]),
                    "event_bar": "" if rule["event_bar"] == math.inf else rule["event_bar"]})
        stab.append(row)
        print(f"{name} shot {s}: {kind}, {len(pos)} balls, {len(evs)} events, "
              f"pocketed {{{row['pocketed']}}}, {rule['cls']}", flush=True)

    def write(fname, head, rows, gz=False):
        opener = gzip.open if gz else open
        with opener(out / fname, "wt", newline="") as f:
            w = csv.writer(f, lineterminator="\n")
            w.writerow(head)
            w.writerows(rows)

    write("shots.csv", ["shot", "seed", "kind", "game", "table_l", "table_w", "cue_ball_id",
                        "V0", "phi", "theta", "a", "b", "n_balls", "target", "n_events",
                        "duration"] + (["point"] if name == "carom" else []), shots_rows)
    write("initial.csv", ["shot", "ball", "ball_id", "x", "y"], initial)
    write("events.csv.gz", ["shot", "k", "t", "type", "agents"], events, gz=True)
    write("event_balls.csv.gz", ["shot", "k", "ball_id", "state", "x", "y", "vx", "vy", "wx",
                                 "wy", "wz"], event_balls, gz=True)
    write("final.csv", ["shot", "ball", "ball_id", "state", "x", "y", "pocket"], final)
    head = ["shot", "seed", "kind", "n_events", "pocketed", "class", "drift", "final_tol",
            "event_bar"] + [f"{p}_{f}" for p in PERTS for f in FIELDS]
    if stab:
        write("stability.csv", head, [[r[h] for h in head] for r in stab])
    (out / "table.json").write_text(table_json(table) + "\n", encoding="utf-8")
    keys = ("m", "R", "u_s", "u_r", "u_sp_proportionality", "u_b", "e_b", "e_c", "f_c", "g")
    (out / "physics.toml").write_text(
        f"# pooltool 0.6.0's BallParams.default(GameType.{spec['game'].name})\n"
        + "".join(f"{k} = {getattr(params, k)!r}\n" for k in keys), encoding="utf-8")


STATES = ("stationary", "spinning", "sliding", "rolling", "pocketed")

if __name__ == "__main__":
    if os.environ.get("PYTHONHASHSEED") != "0":
        env = dict(os.environ, PYTHONHASHSEED="0")
        sys.exit(subprocess.run([sys.executable, *sys.argv], env=env).returncode)
    if len(sys.argv) < 3 or sys.argv[1] not in SETS:
        raise SystemExit("usage: tables_reference.py snooker|carom OUT [LIMIT]")
    main(sys.argv[1], Path(sys.argv[2]), int(sys.argv[3]) if len(sys.argv) > 3 else None)
