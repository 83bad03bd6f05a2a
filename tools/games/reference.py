#!/usr/bin/env python3
"""Reference verdicts of pooltool 0.6.0's 9-ball, 8-ball and snooker rules, for kisstime's
game judges (``src/game/``).

Every shot is built here, simulated by pooltool itself (``pt.simulate``) on pooltool's
default table (``pt.Table.default()``, kisstime's ``7ft``; snooker on
``pt.Table.from_game_type(GameType.SNOOKER)`` with snooker balls,
``BallParams.default(GameType.SNOOKER)``), and judged by pooltool's own rule functions the
way its rule sets' ``build_shot_info`` calls them (``pooltool.ruleset.nine_ball``:
``is_legal``, ``is_turn_over``, ``is_game_over``; ``pooltool.ruleset.eight_ball``: the
same with the shot's ``ShotConstraints``, and ``decide_winner``; snooker: pooltool's
``_Snooker`` rule set itself, ``get_ruleset(GameType.SNOOKER)``, of two players, the
shooter to play, its constraints and score set, its ``build_shot_info``). Nothing here
re-implements a rule.

The 9-ball and 8-ball shots (seed 28; the same files every run):

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

Snooker (seed 30, its own stream: the other two sets stay as they were), 400 shots:

- breaks (every tenth shot, the first included): pooltool's full rack
  (``get_rack(SNOOKER, spacing_factor=1e-3)``), the white at a random spot in the D, aimed
  full to thin at the apex red (a quarter of them: the pink and the blue stand in the
  way from the middle of the D) or at one of the six reds nearest the white that it meets
  first on a straight line, V0 from 1 to 8 m/s; pooltool's ``initial_shot_constraints``
  (hittable: all reds, no call), scores 0 and 0;
- ordinary shots, in a phase drawn (on reds 30 %, on a colour after a red 30 %, the
  colours in sequence 20 %, the final black 20 %): on reds 1 to 15 reds and each colour
  (85 %); on a colour 0 (15 %) to 15 reds and some colours (85 % each); in sequence the
  colours from one of yellow..pink up; on the final black the black alone. Half the
  colours on their spots, the rest and the white at random clear spots (clear of the
  cushions and the pockets' jaws too). Constraints as pooltool's ``next_shot_constraints``
  makes them: on reds all 15 red ids, no call; on a colour all six colours, the call a
  colour on the table; in sequence and on the black the lowest colour, called. The shot:
  a plant set up (15 %: an on ball sent into an off ball or, on reds, half the time
  into another red nearly in line, that one towards a pocket; a plant of two reds hunts
  for both in and the white up, its strike redrawn about the first, 30 times at most,
  until pooltool's run pots them), a pot set up (25 %: an on ball on a line
  into a pocket, the white behind it at a cut under 10°), at an on ball (25 %), at an off
  ball (20 %) or anywhere (15 %); aimed at a ball, 70 % along the ghost-ball line that
  sends it to a pocket (if a pocket takes it: under 45° of cut, no ball in the way).
  V0 from 0.3 to 4 m/s, a little spin (next to no side on the pots: side's throw misses
  them). Scores before 0 to 70 each; on the final black close (the opponent's lead one
  of -8, -7, -3, 0, 3, 7, 8) so that wins, losses and ties all occur after pots and
  fouls alike.

Writes into the folder given (``data/games/nine_ball``, ``data/games/eight_ball`` or
``data/games/snooker``):

- ``shots.csv``: ``shot,break,v0,phi,theta,a,b,legal,reason,turn_over,game_over,n_events``
  and for 8-ball ``hittable,call_shot,ball_call,pocket_call,won`` (hittable ball numbers
  joined by ``;``, the pocket's id; ``won``: the player who shot won the game); the
  strike as ``Cue.set_state`` takes it, ``reason`` pooltool's text (empty when legal),
  ``n_events`` pooltool's events without its two null events; for snooker
  ``hittable,call_shot,ball_call,score,opponent_score,points,foul_points,won`` instead of
  8-ball's (pooltool's ball names; ``score``, ``opponent_score``: before the shot;
  ``points``, ``foul_points``: what the shot added to the shooter's and to the opponent's);
- ``balls.csv``: ``shot,ball,x,y``: every ball at rest at the start, in pooltool's ball
  order; ``ball`` 0 is the cue ball, the others their numbers (snooker: white 0, red_01..
  red_15 1..15, yellow 16, green 17, brown 18, blue 19, pink 20, black 21, the order of
  the system's balls);
- ``events.csv``: ``shot,k,type,t,ball,other``: pooltool's events in order (without the
  null events): its type name, time, and the ids of its ball agents (``other`` empty
  unless ball–ball), as the digest a replay checks its own events against.

Run (a minute or two each, snooker under half a minute; pooltool 0.6.0 installed as
.ci/run installs it):

    python tools/games/reference.py nine_ball data/games/nine_ball [LIMIT]
    python tools/games/reference.py eight_ball data/games/eight_ball [LIMIT]
    python tools/games/reference.py snooker data/games/snooker [LIMIT]

(with LIMIT, only the first LIMIT shots).
"""

from __future__ import annotations

import csv
import math
import os
import random
import subprocess
import sys
from collections import Counter
from pathlib import Path

import attrs
import numpy as np
import pooltool as pt
from pooltool.events.datatypes import AgentType, EventType
from pooltool.game.datatypes import GameType
from pooltool.layouts import snooker_color_locs
from pooltool.ruleset import Player, eight_ball, get_ruleset, nine_ball
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


def break_strike(rng, phi, v_min):
    """A break's strike in direction `phi`: level, a little side, V0 from `v_min` to 8 m/s."""
    return dict(
        V0=float(rng.uniform(v_min, 8.0)),
        phi=float(phi % 360),
        theta=0.0,
        a=float(rng.uniform(-0.1, 0.1)),
        b=float(rng.uniform(-0.2, 0.2)),
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
    return balls, break_strike(rng, phi, 0.5)


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
    """Writes the set of `game` (nine_ball, eight_ball, snooker) into `out`; with `limit`,
    only its first `limit` shots (the same rows as the whole set's first ones: how
    python/tests/test_games_reference.py checks the files are this script's)."""
    if game == "snooker":
        return main_snooker(out, limit)
    eight = game == "eight_ball"
    if game not in ("nine_ball", "eight_ball"):
        raise SystemExit(f"unknown game {game!r}: nine_ball, eight_ball or snooker")
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


# ---- snooker

SNOOKER_SEED = SEED + 2
SNOOKER_BREAKS = 40
SNOOKER_SHOTS = 360
REDS = tuple(f"red_{i:02d}" for i in range(1, 16))
COLOURS = ("yellow", "green", "brown", "blue", "pink", "black")
# kisstime's numeric ids of pooltool's snooker balls
SNOOKER_IDS = {"white": 0, **{r: i for i, r in enumerate(REDS, 1)},
               **{c: 16 + i for i, c in enumerate(COLOURS)}}
# the phases an ordinary shot is drawn in, and how often
PHASE_ODDS = {"reds": 0.3, "colours": 0.3, "sequential": 0.2, "black": 0.2}


def seg_dist(p, a, b):
    """The distance from point `p` to the segment a-b."""
    ax, ay, bx, by = float(a[0]), float(a[1]), float(b[0]), float(b[1])
    dx, dy = bx - ax, by - ay
    t = max(0.0, min(1.0, ((p[0] - ax) * dx + (p[1] - ay) * dy) / (dx * dx + dy * dy)))
    return math.dist(p, (ax + t * dx, ay + t * dy))


def on_cloth(table, xy, R, placed, pocket_clear=0.12):
    """Whether a ball at `xy` stands clear (2 mm) of every cushion segment (the pockets'
    jaws included), `pocket_clear` of the pockets' centres and 1 mm of `placed`."""
    segs = table.cushion_segments
    if not (R + 0.002 <= xy[0] <= table.w - R - 0.002
            and R + 0.002 <= xy[1] <= table.l - R - 0.002):
        return False
    if any(seg_dist(xy, s.p1[:2], s.p2[:2]) < R + 0.002 for s in segs.linear.values()):
        return False
    if any(math.dist(xy, c.center[:2]) < c.radius + R + 0.002
           for c in segs.circular.values()):
        return False
    if any(math.dist(xy, p.center[:2]) < pocket_clear for p in table.pockets.values()):
        return False
    return all(math.dist(xy, q) >= 2 * R + 0.001 for q in placed)


def snooker_spot(rng, table, placed, R):
    """`clear_spot`, also 2 mm clear of every cushion segment (the pockets' jaws)."""
    for _ in range(1000):
        xy = clear_spot(rng, table, placed, R)
        if on_cloth(table, xy, R, placed):
            return xy
    raise RuntimeError("no room")


def rotated(u, deg):
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    return u[0] * c - u[1] * s, u[0] * s + u[1] * c


def lineup(rng, table, R, placed, n, cut=10.0):
    """A pot (n = 1) or a plant (n = 2): the balls' positions, the ball nearest the pocket
    first, then the white's, and the strike's direction, such that the white sends the
    first ball it meets along its line into the next (a plant) or towards a pocket's
    centre: each a ghost-ball aim, the plant's at a cut under `cut`, the white's under
    10° and 0.05° off; None if 100 tries find no room (`placed`: the balls already on the
    table)."""
    pockets = sorted(table.pockets)
    for _ in range(100):
        pid = pockets[int(rng.integers(0, len(pockets)))]
        p = table.pockets[pid].center[:2]
        u_in = rotated(pocket_inward(table, pid), rng.uniform(-20, 20))
        d = rng.uniform(0.12, 0.5)
        chain = [(p[0] + d * u_in[0], p[1] + d * u_in[1])]
        u = (-u_in[0], -u_in[1])  # the direction the last ball must go
        for k in range(n):
            # the ball before it, to its ghost ball
            v = rotated(u, rng.uniform(-cut, cut) if k + 1 < n else rng.uniform(-10, 10))
            gap = rng.uniform(0.1, 0.4) if k + 1 < n else rng.uniform(0.15, 0.8)
            X = chain[-1]
            G = (X[0] - 2 * R * u[0], X[1] - 2 * R * u[1])  # its ghost ball
            chain.append((G[0] - gap * v[0], G[1] - gap * v[1]))
            u = v
        if all(on_cloth(table, xy, R, placed + chain[:k], 0.1 if k == 0 else 0.12)
               for k, xy in enumerate(chain)):
            W = chain[-1]
            phi = math.degrees(math.atan2(G[1] - W[1], G[0] - W[0])) + rng.normal(0, 0.05)
            return chain, phi
    return None


def colour_spot(table, colour):
    x, y = snooker_color_locs[colour].relative_to
    return x * table.w, y * table.l


def snooker_balls(pos):
    """pooltool balls at `pos` {id: (x, y)}, snooker parameters, in kisstime's id order."""
    params = attrs.asdict(pt.BallParams.default(GameType.SNOOKER))
    return {bid: pt.Ball.create(bid, xy=pos[bid], **params)
            for bid in sorted(pos, key=SNOOKER_IDS.__getitem__)}


def snooker_break(rng, table):
    """pooltool's full rack, the white at a random spot in the D (behind the baulk line,
    within the D's radius of the brown's spot), aimed at a red, full to thin."""
    rack = pt.get_rack(GameType.SNOOKER, table, spacing_factor=1e-3)
    pos = {bid: tuple(float(v) for v in b.state.rvw[0][:2]) for bid, b in rack.items()}
    R = pt.BallParams.default(GameType.SNOOKER).R
    cx, cy = colour_spot(table, "brown")
    r = colour_spot(table, "green")[0] - cx
    while True:
        x, y = rng.uniform(cx - r, cx + r), rng.uniform(cy - r, cy)
        if math.dist((x, y), (cx, cy)) <= r and all(
                math.dist((x, y), q) >= 2 * R + 0.002
                for b, q in pos.items() if b != "white"):
            break
    pos["white"] = (float(x), float(y))
    # the apex red (behind the pink, which with the blue stands on the line from the
    # middle of the D to it) a quarter of the time; otherwise a red the white reaches
    # first on a straight line (the nearest reds tried, full to thin, until one is)
    apex = min(REDS, key=lambda b: pos[b][1])
    near = sorted(REDS, key=lambda b: math.dist((x, y), pos[b]))[:6]
    at_apex = rng.uniform() < 0.25
    for _ in range(200):
        target = apex if at_apex else near[int(rng.integers(0, len(near)))]
        tx, ty = pos[target]
        half = math.degrees(math.asin(min(1.0, 2 * R / math.dist((x, y), (tx, ty)))))
        phi = math.degrees(math.atan2(ty - y, tx - x)) + rng.uniform(-0.9, 0.9) * half
        if at_apex or first_on_line((x, y), phi, pos, R) in REDS:
            break
    return pos, break_strike(rng, phi, 1.0)


def pocket_inward(table, pocket):
    """The unit direction from a pocket into the table: along the diagonal at a corner,
    square to the cushion at the middle pockets."""
    cx, cy = table.pockets[pocket].center[:2]
    if pocket[1] == "c":
        return (1.0, 0.0) if cx < table.w / 2 else (-1.0, 0.0)
    return (math.copysign(math.sqrt(0.5), table.w / 2 - cx),
            math.copysign(math.sqrt(0.5), table.l / 2 - cy))


def pot_aim(rng, table, R, cue_xy, obj_xy, others):
    """The ghost-ball direction that sends the ball at `obj_xy` along its line to a pocket's
    centre: of the pockets it can enter square enough (within 30° of a corner's diagonal,
    40° of a middle pocket's square) at a cut under 45°, with no ball of `others` (the
    other balls' centres) in the white's way to the ghost ball or the ball's way to the
    pocket, the one of the thinnest cut; with 0.05° of noise (a cut multiplies the cue
    ball's error by its distance over 2R); None if there is none."""
    best = None
    for pid in sorted(table.pockets):
        p = table.pockets[pid].center
        ux, uy = p[0] - obj_xy[0], p[1] - obj_xy[1]
        d = math.hypot(ux, uy)
        ux, uy = ux / d, uy / d
        ix, iy = pocket_inward(table, pid)
        entry = math.degrees(math.acos(max(-1.0, min(1.0, -(ux * ix + uy * iy)))))
        gx, gy = obj_xy[0] - 2 * R * ux, obj_xy[1] - 2 * R * uy
        cx, cy = gx - cue_xy[0], gy - cue_xy[1]
        c = math.hypot(cx, cy)
        if c < 1e-3:
            continue
        cut = math.degrees(math.acos(max(-1.0, min(1.0, (cx * ux + cy * uy) / c))))
        if entry < (40.0 if pid[1] == "c" else 30.0) and cut < 45.0 and all(
                seg_dist(q, cue_xy, (gx, gy)) >= 2 * R
                and seg_dist(q, obj_xy, p[:2]) >= 2 * R for q in others):
            if best is None or cut < best[0]:
                best = (cut, math.degrees(math.atan2(cy, cx)))
    if best is None:
        return None
    return best[1] + rng.normal(0, 0.05)


def first_on_line(cue_xy, phi, pos, R):
    """The ball of `pos` {id: (x, y)} (the white left out) that a white going straight from
    `cue_xy` along `phi` meets first; None if none."""
    dx, dy = math.cos(math.radians(phi)), math.sin(math.radians(phi))
    best, who = math.inf, None
    for bid, (x, y) in pos.items():
        if bid == "white":
            continue
        fx, fy = x - cue_xy[0], y - cue_xy[1]
        along = fx * dx + fy * dy
        off2 = fx * fx + fy * fy - along * along
        if along <= 0 or off2 >= (2 * R) ** 2:
            continue
        t = along - math.sqrt((2 * R) ** 2 - off2)
        if t < best:
            best, who = t, bid
    return who


def snooker_ordinary(rng, table):
    """A position of a phase of the frame (on reds, on a colour after a red, the colours
    in sequence, the final black), its constraints (as pooltool's next_shot_constraints
    makes them), the strike and the scores before (shooter's, opponent's)."""
    R = pt.BallParams.default(GameType.SNOOKER).R
    phase = str(rng.choice(list(PHASE_ODDS), p=list(PHASE_ODDS.values())))
    if phase == "reds":
        reds = rng.choice(REDS, size=int(rng.integers(1, 16)), replace=False).tolist()
        colours = [c for c in COLOURS if rng.uniform() < 0.85]
    elif phase == "colours":
        # the last red potted (no red left) now and then
        k = 0 if rng.uniform() < 0.15 else int(rng.integers(1, 16))
        reds = rng.choice(REDS, size=k, replace=False).tolist() if k else []
        colours = [c for c in COLOURS if rng.uniform() < 0.85]
        if not colours:
            colours = [COLOURS[int(rng.integers(0, 6))]]
    elif phase == "sequential":
        colours, reds = list(COLOURS[int(rng.integers(0, 5)):]), []
    else:
        colours, reds = ["black"], []
    colours = [c for c in COLOURS if c in colours]
    reds = sorted(reds)
    # the constraints, as pooltool's next_shot_constraints makes them; `on`: the balls
    # that may be hit first (pooltool's get_on_balls, less the reds off the table)
    if phase == "reds":
        hittable, call_shot, ball_call, on = REDS, False, None, reds
    elif phase == "colours":
        ball_call = colours[int(rng.integers(0, len(colours)))]
        hittable, call_shot, on = COLOURS, True, [ball_call]
    else:
        ball_call = colours[0]
        hittable, call_shot, on = (ball_call,), True, [ball_call]
    off = [b for b in reds + colours if b not in on]
    # the shot: a plant (an on ball sent into an off ball, or on reds half the time into
    # another red, that one towards a pocket) 15 %, a pot of an on ball set up 25 %, else
    # at an on ball (25 %), at an off ball (20 %) or anywhere (15 %)
    u = rng.uniform()
    kind = ("plant" if u < 0.15 and off else "pot" if u < 0.4 else "on" if u < 0.65
            or (u < 0.85 and not off) else "off" if u < 0.85 else "none")
    target = (on[int(rng.integers(0, len(on)))] if kind in ("on", "pot", "plant")
              else off[int(rng.integers(0, len(off)))] if kind == "off" else None)
    second, pair_of_reds = None, False
    if kind == "plant":
        reds_left = [b for b in on if b != target and b in REDS]
        pool = reds_left if reds_left and rng.uniform() < 0.5 else off
        second = pool[int(rng.integers(0, len(pool)))]
        pair_of_reds = second in REDS and target in REDS
    # the colours on their spots first (half of them), then the pot's or the plant's
    # balls, then the white and the rest at random clear spots
    pos, placed = {}, []
    for c in colours:
        if rng.uniform() < 0.5 and c not in (target, second):
            pos[c] = colour_spot(table, c)
            placed.append(pos[c])
    phi = None
    if kind in ("pot", "plant"):
        ids = [target] if kind == "pot" else [second, target]
        # two reds nearly in line: the first may follow the second in
        made = lineup(rng, table, R, placed, len(ids), 2.0 if pair_of_reds else 10.0)
        if made is None:
            pair_of_reds = False
        else:
            chain, phi = made
            pos.update(zip(ids + ["white"], chain))
            placed += chain
    for bid in ["white"] + reds + colours:
        if bid not in pos:
            pos[bid] = snooker_spot(rng, table, placed, R)
            placed.append(pos[bid])
    cue_xy = pos["white"]
    if kind in ("on", "off") and rng.uniform() < 0.7:
        others = [xy for b, xy in pos.items() if b not in ("white", target)]
        phi = pot_aim(rng, table, R, cue_xy, pos[target], others)
    # a pot's strike has next to no side (side's throw and swerve would miss the pocket)
    side = 0.3 if phi is None else 0.01
    if phi is None and target is None:
        phi = rng.uniform(0, 360)
    elif phi is None:
        tx, ty = pos[target]
        phi = math.degrees(math.atan2(ty - cue_xy[1], tx - cue_xy[0])) + rng.normal(0, 1.0)
    strike = dict(
        V0=float(rng.uniform(0.3, 4.0)),
        phi=float(phi % 360),
        theta=float(rng.choice([0.0, 0.0, 0.0, rng.uniform(0, 10)])),
        a=float(rng.uniform(-side, side)),
        b=float(rng.uniform(-0.3, 0.3)),
    )
    if phase == "black":
        # close scores: after the pot (+7 the shooter) or the foul (+7 the opponent) the
        # shooter wins, ties or loses as the opponent's lead is under, at or over +7 (-7)
        score = int(rng.integers(8, 70))
        d = int(rng.choice([-8, -7, -3, 0, 3, 7, 8]))
        opponent = score + d
    else:
        score, opponent = int(rng.integers(0, 71)), int(rng.integers(0, 71))
    constraints = ShotConstraints(
        ball_in_hand=BallInHandOptions.NONE,
        movable=[],
        cueable=["white"],
        hittable=tuple(hittable),
        call_shot=call_shot,
        ball_call=ball_call,
        # pooltool's next_shot_constraints always names this pocket (never read)
        pocket_call="lb" if call_shot else None,
    )
    return pos, strike, constraints, (score, opponent), kind == "plant" and pair_of_reds


def snooker_simulate(table, pos, strike):
    """pooltool's run of a snooker shot: the balls at `pos`, the white struck."""
    cue = pt.Cue(cue_ball_id="white")
    cue.set_state(**strike)
    system = pt.System(cue=cue, table=table, balls=snooker_balls(pos))
    pt.simulate(system, inplace=True)
    return system


def snooker_judge(system, constraints, score, opponent):
    """pooltool's verdict as its snooker rule set gives it: a `_Snooker` game of two
    players, the shooter to play (so that pooltool's `last_player` is the opponent), with
    the shot's constraints and the scores before; then its own `build_shot_info`."""
    game = get_ruleset(GameType.SNOOKER)([Player("shooter"), Player("opponent")])
    game.active_idx = 0
    assert game.active_player.name == "shooter" and game.last_player.name == "opponent"
    if constraints is None:
        constraints = game.initial_shot_constraints()
    game.shot_constraints = constraints
    game.score = Counter({"shooter": score, "opponent": opponent})
    info = game.build_shot_info(system)
    return constraints, info


def main_snooker(out: Path, limit: int | None = None) -> None:
    """Writes the snooker set into `out` (with `limit`, its first `limit` shots)."""
    rng = np.random.default_rng(SNOOKER_SEED)
    # pooltool's rack draws from `random` and `np.random`
    random.seed(SNOOKER_SEED)
    np.random.seed(SNOOKER_SEED)
    out.mkdir(parents=True, exist_ok=True)
    table = pt.Table.from_game_type(GameType.SNOOKER)
    params = pt.BallParams.default(GameType.SNOOKER)
    shots = open(out / "shots.csv", "w", newline="")
    balls_f = open(out / "balls.csv", "w", newline="")
    events_f = open(out / "events.csv", "w", newline="")
    ws, wb, we = csv.writer(shots), csv.writer(balls_f), csv.writer(events_f)
    ws.writerow(["shot", "break", "v0", "phi", "theta", "a", "b", "legal", "reason",
                 "turn_over", "game_over", "n_events", "hittable", "call_shot", "ball_call",
                 "score", "opponent_score", "points", "foul_points", "won"])
    wb.writerow(["shot", "ball", "x", "y"])
    we.writerow(["shot", "k", "type", "t", "ball", "other"])
    counts: dict[str, int] = {}
    n_all = SNOOKER_BREAKS + SNOOKER_SHOTS
    total = n_all if limit is None else min(limit, n_all)
    for n in range(total):
        is_break = n % (n_all // SNOOKER_BREAKS) == 0
        if is_break:
            pos, strike = snooker_break(rng, table)
            # pooltool's first shot: its initial_shot_constraints, no score yet
            constraints, (score, opponent), hunt = None, (0, 0), False
        else:
            pos, strike, constraints, (score, opponent), hunt = snooker_ordinary(rng, table)
        system = snooker_simulate(table, pos, strike)
        # a plant of two reds hunts for both in and the white not (pooltool's run of
        # strikes redrawn about the first, 30 at most), so that some legal pots score 2+
        for _ in range(30 if hunt else 0):
            potted = [e.agents[0].id for e in system.events
                      if e.event_type == EventType.BALL_POCKET]
            if "white" not in potted and len([b for b in potted if b in REDS]) >= 2:
                break
            strike = dict(strike, V0=float(rng.uniform(0.3, 4.0)),
                          phi=float((strike["phi"] + rng.normal(0, 0.05)) % 360),
                          b=float(rng.uniform(-0.3, 0.3)))
            system = snooker_simulate(table, pos, strike)
        balls = system.balls
        for b in balls.values():
            assert b.params == params, "snooker ball parameters only"
        constraints, info = snooker_judge(system, constraints, score, opponent)
        points = info.score["shooter"] - score
        foul_points = info.score["opponent"] - opponent
        won = info.winner is not None and info.winner.name == "shooter"
        events = [e for e in system.events if e.event_type != EventType.NONE]
        ws.writerow([n, int(is_break), repr(strike["V0"]), repr(strike["phi"]),
                     repr(strike["theta"]), repr(strike["a"]), repr(strike["b"]),
                     int(info.legal), str(info.reason), int(info.turn_over),
                     int(info.game_over), len(events), ";".join(constraints.hittable),
                     int(constraints.call_shot), constraints.ball_call or "", score,
                     opponent, points, foul_points, int(won)])
        for bid in balls:
            x, y = system.balls[bid].history[0].rvw[0][:2]
            wb.writerow([n, SNOOKER_IDS[bid], repr(float(x)), repr(float(y))])
        for k, e in enumerate(events):
            ids = ball_agents(e)
            other = SNOOKER_IDS[ids[1]] if len(ids) > 1 else ""
            we.writerow([n, k, e.event_type.value, repr(float(e.time)),
                         SNOOKER_IDS[ids[0]] if ids else "", other])
        key = ("break " if is_break else "") + ("legal" if info.legal else str(info.reason))
        if info.legal:
            key += ", potting" if points > 0 else ", nothing potted"
        else:
            key += f", {foul_points} to the opponent"
        if info.game_over:
            tie = info.winner is None
            key += ", game over " + ("tie" if tie else "won" if won else "lost")
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
        raise SystemExit("usage: reference.py nine_ball|eight_ball|snooker OUT [LIMIT]")
    main(sys.argv[1], Path(sys.argv[2]), int(sys.argv[3]) if len(sys.argv) > 3 else None)
