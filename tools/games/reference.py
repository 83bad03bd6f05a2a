#!/usr/bin/env python3
"""Reference verdicts of pooltool 0.6.0's 9-ball and 8-ball rules, for kisstime's game
judges (``src/game/``).

Every shot is built here, simulated by pooltool itself (``pt.simulate``) on pooltool's
default table (``pt.Table.default()``, kisstime's ``7ft``), and judged by pooltool's own
rule functions the way its rule sets' ``build_shot_info`` calls them
(``pooltool.ruleset.nine_ball``: ``is_legal``, ``is_turn_over``, ``is_game_over``;
``pooltool.ruleset.eight_ball``: the same with the shot's ``ShotConstraints``, and
``decide_winner``). Nothing here re-implements a rule.

The shots (seeded: the same files every run):

- breaks (every tenth shot, the first included): pooltool's rack of the game (``pt.get_rack``), the cue ball behind the head
  string, aimed at the rack's apex with a little noise, V0 from 0.5 to 8 m/s (the soft
  ones foul: fewer than four balls reach a cushion);
- ordinary shots: the cue ball and some numbered balls (9-ball: 1 to 9 of 1..9; 8-ball: 1
  to 15 of 1..15) at random places on the table, none touching another, a cushion or a
  pocket; the cue ball aimed at a ball the player may hit first (most often), at another
  ball (wrong ball first), or anywhere (no hit), V0 from 0.2 to 4 m/s (the slow ones
  reach no cushion), with a little spin. 8-ball shots also draw the player's group
  (solids, stripes, the open table, the 8) and the call (the aimed ball and a pocket, the
  one nearest the ball's line or any; now and then none, or a call not asked for).

Writes into the folder given (``data/games/nine_ball`` or ``data/games/eight_ball``):

- ``shots.csv``: ``shot,break,v0,phi,theta,a,b,legal,reason,turn_over,game_over,n_events``
  and for 8-ball ``hittable,call_shot,ball_call,pocket_call,won`` (hittable ball numbers
  joined by ``;``, the pocket's id; ``won``: the player who shot won the game); the
  strike as ``Cue.set_state`` takes it, ``reason`` pooltool's text (empty when legal),
  ``n_events`` pooltool's events without its two null events;
- ``balls.csv``: ``shot,ball,x,y``: every ball at rest at the start, in pooltool's ball
  order; ``ball`` 0 is the cue ball, the others their numbers;
- ``events.csv``: ``shot,k,type,t,ball,other``: pooltool's events in order (without the
  null events): its type name, time, and the ids of its ball agents (``other`` empty
  unless ball–ball), as the digest a replay checks its own events against.

Run (a minute or two each; pooltool 0.6.0 installed as .ci/run installs it):

    python tools/games/reference.py nine_ball data/games/nine_ball [LIMIT]
    python tools/games/reference.py eight_ball data/games/eight_ball [LIMIT]

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
from pooltool.ruleset import eight_ball, nine_ball
from pooltool.ruleset.datatypes import BallInHandOptions, ShotConstraints

SEED = 28
N_BREAKS = 60
N_SHOTS = 540
# 8-ball's groups (pooltool's BallGroup) and how often ordinary shots draw each
GROUPS = {
    "solids": tuple(str(i) for i in range(1, 8)),
    "stripes": tuple(str(i) for i in range(9, 16)),
    "open": tuple(str(i) for i in range(1, 16) if i != 8),
    "eight": ("8",),
}
GROUP_ODDS = {"solids": 0.35, "stripes": 0.35, "open": 0.15, "eight": 0.15}


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


def place(rng, table, ids):
    """The cue ball and the numbered balls `ids` at random clear spots: the balls and the
    cue ball's centre."""
    R = pt.BallParams.default().R
    placed = []
    balls = {}
    for bid in ["cue"] + [str(i) for i in ids]:
        xy = clear_spot(rng, table, placed, R)
        placed.append(xy)
        balls[bid] = pt.Ball.create(bid, xy=xy)
    return balls, placed[0]


def aim(rng, balls, cue_xy, target):
    """The direction from the cue ball to `target` with 1° of noise, or anywhere."""
    if target is None:
        return rng.uniform(0, 360)
    tx, ty = balls[target].state.rvw[0][:2]
    return math.degrees(math.atan2(ty - cue_xy[1], tx - cue_xy[0])) + rng.normal(0, 1.0)


def ordinary_strike(rng, phi):
    """An ordinary shot's strike in direction `phi`."""
    return dict(
        V0=float(rng.uniform(0.2, 4.0)),
        phi=float(phi % 360),
        theta=float(rng.choice([0.0, 0.0, 0.0, rng.uniform(0, 10)])),
        a=float(rng.uniform(-0.3, 0.3)),
        b=float(rng.uniform(-0.3, 0.3)),
    )


def ordinary(rng, table):
    k = int(rng.integers(1, 10))
    ids = sorted(rng.choice(np.arange(1, 10), size=k, replace=False).tolist())
    balls, cue_xy = place(rng, table, ids)
    u = rng.uniform()
    if u < 0.6:
        target = str(ids[0])
    elif u < 0.85:
        target = str(ids[int(rng.integers(0, k))])
    else:
        target = None
    return balls, ordinary_strike(rng, aim(rng, balls, cue_xy, target))


def a_break(rng, table, game=GameType.NINEBALL):
    balls = pt.get_rack(game, table=table)
    R = pt.BallParams.default().R
    x = rng.uniform(0.3 * table.w, 0.7 * table.w)
    y = rng.uniform(0.1, table.l / 4 - R)
    balls["cue"] = pt.Ball.create("cue", xy=(x, y))
    # the rack's apex: the 1 in 9-ball, the ball nearest the cue ball's end in 8-ball
    apex = "1" if game == GameType.NINEBALL else min(
        balls, key=lambda b: balls[b].state.rvw[0][1] if b != "cue" else math.inf
    )
    tx, ty = balls[apex].state.rvw[0][:2]
    phi = math.degrees(math.atan2(ty - y, tx - x)) + rng.normal(0, 0.5)
    strike = dict(
        V0=float(rng.uniform(0.5, 8.0)),
        phi=float(phi % 360),
        theta=0.0,
        a=float(rng.uniform(-0.1, 0.1)),
        b=float(rng.uniform(-0.2, 0.2)),
    )
    return balls, strike


def pocket_along(table, cue_xy, target_xy):
    """The pocket nearest the line from the cue ball through the target ball, beyond it."""
    dx, dy = target_xy[0] - cue_xy[0], target_xy[1] - cue_xy[1]

    def off_line(p):
        px, py = p.center[0] - target_xy[0], p.center[1] - target_xy[1]
        ahead = px * dx + py * dy
        return math.inf if ahead <= 0 else abs(px * dy - py * dx) / math.hypot(dx, dy)

    return min(table.pockets.values(), key=off_line).id


def ordinary8(rng, table):
    """An 8-ball position, strike and the player's constraints (group and call)."""
    group = str(rng.choice(list(GROUP_ODDS), p=list(GROUP_ODDS.values())))
    k = int(rng.integers(1, 16))
    ids = sorted(rng.choice(np.arange(1, 16), size=k, replace=False).tolist())
    if group == "eight" and 8 not in ids:
        ids = sorted(ids + [8])
    balls, cue_xy = place(rng, table, ids)
    hittable = GROUPS[group]
    mine = [b for b in balls if b in hittable]
    u = rng.uniform()
    if u < 0.65 and mine:
        target = mine[int(rng.integers(0, len(mine)))]
    elif u < 0.85:
        others = [b for b in balls if b != "cue"]
        target = others[int(rng.integers(0, len(others)))]
    else:
        target = None
    phi = aim(rng, balls, cue_xy, target)
    # the call: the aimed ball (if the player may hit it) in the pocket along its line or
    # in any pocket; now and then no call at all, or a shot that needs none
    pockets = sorted(table.pockets)
    u = rng.uniform()
    if u < 0.08:
        ball_call, pocket_call = None, None
    else:
        ball_call = target if target in hittable else (mine[0] if mine else None)
        if ball_call is not None and rng.uniform() < 0.6:
            pocket_call = pocket_along(table, cue_xy, balls[ball_call].state.rvw[0][:2])
        else:
            pocket_call = pockets[int(rng.integers(0, len(pockets)))]
    call_shot = bool(rng.uniform() >= 0.05)
    constraints = ShotConstraints(
        ball_in_hand=BallInHandOptions.NONE,
        movable=[],
        cueable=["cue"],
        hittable=hittable,
        call_shot=call_shot,
        ball_call=ball_call,
        pocket_call=pocket_call,
    )
    return balls, ordinary_strike(rng, phi), constraints


def break_constraints():
    """The 8-ball break's constraints (pooltool's initial_shot_constraints)."""
    return ShotConstraints(
        ball_in_hand=BallInHandOptions.BEHIND_LINE,
        movable=["cue"],
        cueable=["cue"],
        hittable=GROUPS["open"],
        call_shot=False,
    )


def ball_agents(event):
    return [a.id for a in event.agents if a.agent_type == AgentType.BALL]


def main(game: str, out: Path, limit: int | None = None) -> None:
    """Writes the set of `game` (nine_ball, eight_ball) into `out`; with `limit`, only its
    first `limit` shots (the same rows as the whole set's first ones: how
    python/tests/test_games_reference.py checks the files are this script's)."""
    eight = game == "eight_ball"
    if game not in ("nine_ball", "eight_ball"):
        raise SystemExit(f"unknown game {game!r}: nine_ball or eight_ball")
    rng = np.random.default_rng(SEED)
    random.seed(SEED)
    np.random.seed(SEED)
    out.mkdir(parents=True, exist_ok=True)
    table = pt.Table.default()
    shots = open(out / "shots.csv", "w", newline="")
    balls_f = open(out / "balls.csv", "w", newline="")
    events_f = open(out / "events.csv", "w", newline="")
    ws, wb, we = csv.writer(shots), csv.writer(balls_f), csv.writer(events_f)
    head = ["shot", "break", "v0", "phi", "theta", "a", "b", "legal", "reason",
            "turn_over", "game_over", "n_events"]
    if eight:
        head += ["hittable", "call_shot", "ball_call", "pocket_call", "won"]
    ws.writerow(head)
    wb.writerow(["shot", "ball", "x", "y"])
    we.writerow(["shot", "k", "type", "t", "ball", "other"])
    counts: dict[str, int] = {}
    total = N_BREAKS + N_SHOTS if limit is None else min(limit, N_BREAKS + N_SHOTS)
    for n in range(total):
        # every tenth shot a break, so that any first shots hold both kinds
        is_break = n % ((N_BREAKS + N_SHOTS) // N_BREAKS) == 0
        constraints = None
        if eight and is_break:
            balls, strike = a_break(rng, table, GameType.EIGHTBALL)
            constraints = break_constraints()
        elif eight:
            balls, strike, constraints = ordinary8(rng, table)
        elif is_break:
            balls, strike = a_break(rng, table)
        else:
            balls, strike = ordinary(rng, table)
        # the balls in pooltool's order: the cue ball, then by number
        order = sorted(balls, key=numbered)
        balls = {bid: balls[bid] for bid in order}
        for b in balls.values():
            assert b.params == pt.BallParams.default(), "default ball parameters only"
        cue = pt.Cue(cue_ball_id="cue")
        cue.set_state(**strike)
        system = pt.System(cue=cue, table=table, balls=balls)
        pt.simulate(system, inplace=True)
        if eight:
            legal, reason = eight_ball.is_legal(system, constraints, break_shot=is_break)
            turn_over = eight_ball.is_turn_over(system, constraints, legal)
            game_over = eight_ball.is_game_over(system)
            won = eight_ball.decide_winner(game_over, legal, "shooter", "other") == "shooter"
        else:
            legal, reason = nine_ball.is_legal(system, break_shot=is_break)
            turn_over = nine_ball.is_turn_over(system, legal)
            game_over = nine_ball.is_game_over(system, legal)
        events = [e for e in system.events if e.event_type != EventType.NONE]
        row = [n, int(is_break), repr(strike["V0"]), repr(strike["phi"]),
               repr(strike["theta"]), repr(strike["a"]), repr(strike["b"]),
               int(legal), reason, int(turn_over), int(game_over), len(events)]
        if eight:
            row += [";".join(constraints.hittable), int(constraints.call_shot),
                    constraints.ball_call or "", constraints.pocket_call or "", int(won)]
        ws.writerow(row)
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
    if len(sys.argv) < 3:
        raise SystemExit("usage: reference.py nine_ball|eight_ball OUT [LIMIT]")
    main(sys.argv[1], Path(sys.argv[2]), int(sys.argv[3]) if len(sys.argv) > 3 else None)
