#!/usr/bin/env python3
"""Reference verdicts of pooltool 0.6.0's 9-ball rules, for kisstime's game judge.

Every shot is built here, simulated by pooltool itself (``pt.simulate``) on pooltool's
default table (``pt.Table.default()``, kisstime's ``7ft``), and judged by pooltool's own
9-ball functions (``pooltool.ruleset.nine_ball.is_legal``, ``is_turn_over``,
``is_game_over``), the way its ``_NineBall.build_shot_info`` calls them. Nothing here
re-implements a rule.

The shots (seeded: the same files every run):

- breaks: pooltool's 9-ball rack (``pt.get_rack``), the cue ball behind the head string,
  aimed at the 1 with a little noise, V0 from 0.5 to 8 m/s (the soft ones foul: fewer than
  four balls reach a cushion);
- ordinary shots: the cue ball and 1 to 9 numbered balls (a random subset of 1..9) at
  random places on the table, none touching another, a cushion or a pocket; the cue ball
  aimed at the lowest ball (most often), at another ball (wrong ball first), or anywhere
  (no hit), V0 from 0.2 to 4 m/s (the slow ones reach no cushion), with a little spin.

Writes into ``data/games/nine_ball/`` (the folder given as the first argument):

- ``shots.csv``: ``shot,break,v0,phi,theta,a,b,legal,reason,turn_over,game_over,n_events``
  (the strike as ``Cue.set_state`` takes it; ``reason`` pooltool's text, empty when
  legal; ``n_events`` pooltool's events without its two null events);
- ``balls.csv``: ``shot,ball,x,y``: every ball at rest at the start, in pooltool's ball
  order; ``ball`` 0 is the cue ball, the others their numbers;
- ``events.csv``: ``shot,k,type,t,ball,other``: pooltool's events in order (without the
  null events): its type name, time, and the ids of its ball agents (``other`` empty
  unless ball–ball), as the digest a replay checks its own events against.

Run (about a minute; pooltool 0.6.0 installed as .ci/run installs it):

    python tools/games/nine_ball_reference.py data/games/nine_ball [LIMIT]

(with LIMIT, only the first LIMIT shots).
"""

from __future__ import annotations

import csv
import math
import os
import random
import subprocess
import sys
from pathlib import Path

import numpy as np
import pooltool as pt
from pooltool.events.datatypes import AgentType, EventType
from pooltool.game.datatypes import GameType
from pooltool.ruleset import nine_ball

SEED = 28
N_BREAKS = 60
N_SHOTS = 540


def numbered(bid: str) -> int:
    return 0 if bid == "cue" else int(bid)


def clear_spot(rng, table, placed, R):
    """A random centre on the cloth at least 1 mm from every placed ball, 2 mm from the
    cushions' noses and clear of the pockets' mouths."""
    pockets = [p.center[:2] for p in table.pockets.values()]
    for _ in range(10_000):
        x = rng.uniform(R + 0.002, table.w - R - 0.002)
        y = rng.uniform(R + 0.002, table.l - R - 0.002)
        if any(math.dist((x, y), q) < 2 * R + 0.001 for q in placed):
            continue
        if any(math.dist((x, y), p) < 0.12 for p in pockets):
            continue
        return x, y
    raise RuntimeError("no room")


def ordinary(rng, table):
    R = pt.BallParams.default().R
    k = int(rng.integers(1, 10))
    ids = sorted(rng.choice(np.arange(1, 10), size=k, replace=False).tolist())
    placed = []
    balls = {}
    for bid in ["cue"] + [str(i) for i in ids]:
        xy = clear_spot(rng, table, placed, R)
        placed.append(xy)
        balls[bid] = pt.Ball.create(bid, xy=xy)
    cue_xy = placed[0]
    u = rng.uniform()
    if u < 0.6:
        target = str(ids[0])
    elif u < 0.85:
        target = str(ids[int(rng.integers(0, k))])
    else:
        target = None
    if target is None:
        phi = rng.uniform(0, 360)
    else:
        tx, ty = balls[target].state.rvw[0][:2]
        phi = math.degrees(math.atan2(ty - cue_xy[1], tx - cue_xy[0])) + rng.normal(0, 1.0)
    strike = dict(
        V0=float(rng.uniform(0.2, 4.0)),
        phi=float(phi % 360),
        theta=float(rng.choice([0.0, 0.0, 0.0, rng.uniform(0, 10)])),
        a=float(rng.uniform(-0.3, 0.3)),
        b=float(rng.uniform(-0.3, 0.3)),
    )
    return balls, strike


def a_break(rng, table):
    balls = pt.get_rack(GameType.NINEBALL, table=table)
    R = pt.BallParams.default().R
    x = rng.uniform(0.3 * table.w, 0.7 * table.w)
    y = rng.uniform(0.1, table.l / 4 - R)
    balls["cue"] = pt.Ball.create("cue", xy=(x, y))
    tx, ty = balls["1"].state.rvw[0][:2]
    phi = math.degrees(math.atan2(ty - y, tx - x)) + rng.normal(0, 0.5)
    strike = dict(
        V0=float(rng.uniform(0.5, 8.0)),
        phi=float(phi % 360),
        theta=0.0,
        a=float(rng.uniform(-0.1, 0.1)),
        b=float(rng.uniform(-0.2, 0.2)),
    )
    return balls, strike


def ball_agents(event):
    return [a.id for a in event.agents if a.agent_type == AgentType.BALL]


def main(out: Path, limit: int | None = None) -> None:
    """Writes the set into `out`; with `limit`, only its first `limit` shots (the same
    rows as the whole set's first ones: how python/tests/test_games_reference.py checks the
    files are this script's)."""
    rng = np.random.default_rng(SEED)
    random.seed(SEED)
    np.random.seed(SEED)
    out.mkdir(parents=True, exist_ok=True)
    table = pt.Table.default()
    shots = open(out / "shots.csv", "w", newline="")
    balls_f = open(out / "balls.csv", "w", newline="")
    events_f = open(out / "events.csv", "w", newline="")
    ws, wb, we = csv.writer(shots), csv.writer(balls_f), csv.writer(events_f)
    ws.writerow(["shot", "break", "v0", "phi", "theta", "a", "b", "legal", "reason",
                 "turn_over", "game_over", "n_events"])
    wb.writerow(["shot", "ball", "x", "y"])
    we.writerow(["shot", "k", "type", "t", "ball", "other"])
    counts: dict[str, int] = {}
    total = N_BREAKS + N_SHOTS if limit is None else min(limit, N_BREAKS + N_SHOTS)
    for n in range(total):
        is_break = n < N_BREAKS
        balls, strike = a_break(rng, table) if is_break else ordinary(rng, table)
        # the balls in pooltool's order: the cue ball, then by number
        order = sorted(balls, key=numbered)
        balls = {bid: balls[bid] for bid in order}
        for b in balls.values():
            assert b.params == pt.BallParams.default(), "default ball parameters only"
        cue = pt.Cue(cue_ball_id="cue")
        cue.set_state(**strike)
        system = pt.System(cue=cue, table=table, balls=balls)
        pt.simulate(system, inplace=True)
        legal, reason = nine_ball.is_legal(system, break_shot=is_break)
        turn_over = nine_ball.is_turn_over(system, legal)
        game_over = nine_ball.is_game_over(system, legal)
        events = [e for e in system.events if e.event_type != EventType.NONE]
        ws.writerow([n, int(is_break), repr(strike["V0"]), repr(strike["phi"]),
                     repr(strike["theta"]), repr(strike["a"]), repr(strike["b"]),
                     int(legal), reason, int(turn_over), int(game_over), len(events)])
        for bid in order:
            x, y = system.balls[bid].history[0].rvw[0][:2]
            wb.writerow([n, numbered(bid), repr(float(x)), repr(float(y))])
        for k, e in enumerate(events):
            ids = ball_agents(e)
            other = numbered(ids[1]) if len(ids) > 1 else ""
            we.writerow([n, k, e.event_type.value, repr(float(e.time)),
                         numbered(ids[0]) if ids else "", other])
        key = ("break " if is_break else "") + ("legal" if legal else reason)
        key += ", game over" if game_over else ""
        counts[key] = counts.get(key, 0) + 1
    for f in (shots, balls_f, events_f):
        f.close()
    for key in sorted(counts):
        print(f"{counts[key]:5d}  {key}")


if __name__ == "__main__":
    # pooltool's rack spreads its jitter over sets of ball ids, whose order follows
    # Python's string hashing: fixed here, or the racks differ from run to run
    if os.environ.get("PYTHONHASHSEED") != "0":
        env = dict(os.environ, PYTHONHASHSEED="0")
        sys.exit(subprocess.run([sys.executable, *sys.argv], env=env).returncode)
    main(
        Path(sys.argv[1] if len(sys.argv) > 1 else "data/games/nine_ball"),
        int(sys.argv[2]) if len(sys.argv) > 2 else None,
    )
