#!/usr/bin/env python3
"""Reference verdicts of pooltool 0.6.0's four rule sets (9-ball, 8-ball, snooker,
three-cushion), one JSON Lines file a game, for kisstime's game judges (issue 28).

What it does
------------
Every shot is built here from pooltool's own pieces (its default table for the game,
``pt.Table.from_game_type``; its rack, ``pt.get_rack``; its default ball parameters for
the game, ``pt.BallParams.default(game_type)``; a default ``pt.Cue``), simulated by
pooltool itself (``pt.simulate(system, inplace=True)``) and judged by pooltool's own rule
set the way its game loop judges a shot: a fresh ruleset object (``_NineBall``,
``_EightBall``, ``_Snooker``, ``_ThreeCushion``) with two players (``shooter`` to play,
``opponent``), its ``shot_number`` (0 for a break), its ``shot_constraints`` (the group,
the call, the ball on, the cue ball) and, for snooker and three-cushion, the score before
the shot; then ``ruleset.build_shot_info(system)``, which is what
``Ruleset.process_shot`` calls. Nothing here re-implements a rule: the category tallies
below only sort pooltool's verdicts.

Shots are drawn from per-game scenarios (breaks from pooltool's rack; mid-game positions
with a random subset of the balls at random non-overlapping places; pots set up along a
ball-to-pocket line, plants, aims at a wrong ball, at nothing, at a pocket, soft touches),
so that every verdict and every foul of each game occurs many times. A category that is
already full (``CAP`` shots) rejects further shots; categories still short of ``MIN``
after the main pass are hunted with their scenario (bounded). Everything is seeded
(``SEED``; one numpy generator a game; pooltool's rack randomness re-seeded from it before
every rack), so a run writes the same bytes every time. The script re-executes itself
with ``PYTHONHASHSEED=0``: pooltool's rack draws ball ids from Python sets, whose order
follows string hashing.

Run
---
With pooltool 0.6.0 installed as ``.ci/run`` installs it (``pip install --no-deps
pooltool-billiards==0.6.0``, ``pip install -r benches/pooltool_requirements.txt``,
``pip install panda3d==1.10.16 panda3d-simplepbr==0.13.1``), from the repository root::

    python tools/rules_reference/generate.py                    # all four games
    python tools/rules_reference/generate.py nine_ball snooker  # some
    python tools/rules_reference/generate.py --limit 20 --out /tmp/r nine_ball

``--limit N`` stops each game after its first N accepted shots (the same lines as a full
run's first N: a quick test can re-make a prefix and compare). ``--out DIR`` (default
``data/rules``). It prints each file's verdict counts (pasted in ``data/rules/README.md``).

Time on one core of the 2-core dev machine (numba's JIT first, ~25 s a process): 9-ball
~4 min, 8-ball ~6 min (most of both in hunting for the 9 or the 8 pocketed on the break,
about 1 break in 100), snooker ~3 min, three-cushion ~1 min.

What it writes
--------------
``DIR/<game>.jsonl`` (``nine_ball``, ``eight_ball``, ``snooker``, ``three_cushion``), one
shot a line; a file over 3 MB is written gzipped instead (``<game>.jsonl.gz``). Fields
(see ``data/rules/README.md`` for the full description):

- ``shot`` (0..), ``game``, ``scenario`` (how it was drawn; a label only),
- ``table``: kisstime's name of pooltool's table (``7ft``, ``snooker``, ``billiard``),
  ``table_file`` (``data/tables/<name>.json``: the script checks that pooltool's table
  dumps to exactly that file's text), ``pooltool_table`` (pooltool's table name),
- ``ball_params``: pooltool's ``BallParams`` of every ball (the game's defaults),
- ``balls``: ``[{"id", "x", "y"}]`` in pooltool's system order, at rest; a ball that is
  already pocketed also has ``"pocket": id`` (it lies at that pocket's centre, ``z =
  -depth``, state 4) - only 8-ball positions where the shooter is on the 8 have them,
  because pooltool's 8-ball score needs the finished group in the pockets,
- ``strike``: ``{"cue_ball", "V0", "phi", "theta", "a", "b"}`` as ``Cue.set_state`` takes
  them (the cue otherwise pooltool's default ``Cue``),
- ``context``: the shot's constraints (``break``, ``hittable``, ``group``, ``call_shot``,
  ``ball_call``, ``pocket_call``, ``score_before``, ...; per game),
- ``events``: ``[[type, t, [agent ids]], ...]``, pooltool's events in order without its
  null events (``type`` is ``EventType``'s value, ``t`` the time, the ids all agents':
  balls, cushion segment ids, pocket ids, ``cue_stick``),
- ``verdict``: ``legal``, ``reason`` (pooltool's text, ``""`` when legal), ``foul`` (a
  code, ``""`` when legal), ``turn_over``, ``game_over``, ``winner`` (``shooter``,
  ``opponent`` or null), ``score`` (pooltool's ``ShotInfo.score`` after the shot, both
  players), and for snooker and three-cushion ``points`` (each player's gain).
"""

from __future__ import annotations

import argparse
import gzip
import json
import math
import os
import random
import subprocess
import sys
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SEED = 28
GAMES = ("nine_ball", "eight_ball", "snooker", "three_cushion")
#: shots accepted in the main pass, a category's cap, the minimum the hunt goes for
N_MAIN = {"nine_ball": 480, "eight_ball": 520, "snooker": 480, "three_cushion": 400}
CAP = {"nine_ball": 60, "eight_ball": 50, "snooker": 45, "three_cushion": 90}
MIN = 12
HUNT_TRIES = 4000
MAX_BYTES = 3_000_000

#: pooltool's foul reasons (``ShotInfo.reason``) and the codes written beside them
FOUL_CODES = {
    "Cue ball in pocket!": "cue_pocketed",
    "No ball contacted": "no_hit",
    "No ball contacted!": "no_hit",  # snooker's wording
    "Lowest ball not hit first": "wrong_ball_first",
    "First contact wasn't made with target balls": "wrong_ball_first",
    "First contact made with a ball that's not on!": "wrong_ball_first",
    "Cushion not contacted after first contact": "no_rail",
    "4 rails must be contacted, or 1 ball potted": "break_rails",
    "Shot not called, but it was required!": "not_called",
    "8-ball sunk illegally (out of turn or wrong pocket)!": "eight_illegal",
    "Pocketed a ball that's not on!": "off_ball_pocketed",
}

# ----------------------------------------------------------------------------------------
# geometry


def rot(u, deg):
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    return (u[0] * c - u[1] * s, u[0] * s + u[1] * c)


def unit(dx, dy):
    n = math.hypot(dx, dy)
    return (dx / n, dy / n)


def angle_of(frm, to):
    return math.degrees(math.atan2(to[1] - frm[1], to[0] - frm[0])) % 360


def seg_dist(p, a, b):
    ax, ay = a
    bx, by = b
    dx, dy = bx - ax, by - ay
    L2 = dx * dx + dy * dy
    t = 0.0 if L2 == 0 else max(0.0, min(1.0, ((p[0] - ax) * dx + (p[1] - ay) * dy) / L2))
    return math.hypot(p[0] - ax - t * dx, p[1] - ay - t * dy)


class Geo:
    """The table's playing area, cushions and pockets, for placing balls."""

    def __init__(self, table, R):
        self.w, self.l, self.R = table.w, table.l, R
        segs = table.cushion_segments
        self.lines = [(tuple(s.p1[:2]), tuple(s.p2[:2])) for s in segs.linear.values()]
        self.arcs = [(tuple(c.center[:2]), c.radius) for c in segs.circular.values()]
        self.pockets = {pid: ((p.a, p.b), p.radius) for pid, p in table.pockets.items()}

    def inside(self, p, pocket_clear):
        R = self.R
        if not (R + 0.002 <= p[0] <= self.w - R - 0.002):
            return False
        if not (R + 0.002 <= p[1] <= self.l - R - 0.002):
            return False
        if any(seg_dist(p, a, b) < R + 0.002 for a, b in self.lines):
            return False
        if any(math.dist(p, c) < r + R + 0.002 for c, r in self.arcs):
            return False
        return all(math.dist(p, c) >= max(pocket_clear, r + R + 0.005)
                   for c, r in self.pockets.values())

    def free(self, p, placed, gap=0.001):
        return all(math.dist(p, q) >= 2 * self.R + gap for q in placed)

    def spot(self, rng, placed, pocket_clear=0.12, box=None, tries=2000):
        x0, x1, y0, y1 = box if box else (0, self.w, 0, self.l)
        for _ in range(tries):
            p = (float(rng.uniform(x0, x1)), float(rng.uniform(y0, y1)))
            if self.inside(p, pocket_clear) and self.free(p, placed):
                return p
        return None

    def path_clear(self, a, b, placed, skip=()):
        """No ball of ``placed`` (other than those at indices ``skip``) within 2R of the
        segment a-b (a ball's path from a to b)."""
        return all(seg_dist(q, a, b) >= 2 * self.R + 0.0005
                   for i, q in enumerate(placed) if i not in skip)

    def into_table(self, pid):
        (cx, cy), _ = self.pockets[pid]
        return unit(self.w / 2 - cx, self.l / 2 - cy) if pid[1] != "c" else (
            (1.0, 0.0) if pid[0] == "l" else (-1.0, 0.0))

    def pot_line(self, rng, pid, placed, d=(0.12, 0.7), spread=30.0):
        """An object ball position on a line into pocket ``pid``: returns (O, u) where u is
        the unit direction from O to the pocket's centre, or None."""
        (cx, cy), r = self.pockets[pid]
        base = self.into_table(pid)
        lim = spread if pid[1] != "c" else 40.0
        for _ in range(200):
            u_in = rot(base, float(rng.uniform(-lim, lim)))
            dist = float(rng.uniform(*d))
            O = (cx + u_in[0] * dist, cy + u_in[1] * dist)
            if self.inside(O, r + self.R + 0.01) and self.free(O, placed):
                return O, (-u_in[0], -u_in[1])
        return None

    def cue_behind(self, rng, O, u, placed, e=(0.12, 0.9), cut=(-12.0, 12.0)):
        """A cue ball position behind ghost ball of O for direction u (object to pocket),
        with a cut angle; returns (C, phi) or None."""
        G = (O[0] - 2 * self.R * u[0], O[1] - 2 * self.R * u[1])
        for _ in range(100):
            v = rot(u, float(rng.uniform(*cut)))
            dist = float(rng.uniform(*e))
            C = (G[0] - v[0] * dist, G[1] - v[1] * dist)
            if (self.inside(C, 0.12) and self.free(C, placed + [O], 0.002)
                    and self.path_clear(C, G, placed)):
                return C, angle_of(C, G)
        return None


# ----------------------------------------------------------------------------------------
# pooltool glue


def table_json_text(table) -> str:
    """pooltool's table as the text of data/tables/*.json (kisstime.pooltool.table_json's
    format: insertion order, floats by repr, indent 1)."""
    segs = table.cushion_segments
    doc = {
        "linear_cushion_segments": {
            str(k): {"p1": [float(v) for v in s.p1], "p2": [float(v) for v in s.p2],
                     "direction": int(s.direction)}
            for k, s in segs.linear.items()},
        "circular_cushion_segments": {
            str(k): {"center": [float(v) for v in c.center], "radius": float(c.radius)}
            for k, c in segs.circular.items()},
        "pockets": {
            str(k): {"center": [float(v) for v in p.center], "radius": float(p.radius),
                     "depth": float(p.depth)}
            for k, p in table.pockets.items()},
    }
    return json.dumps(doc, indent=1, allow_nan=False) + "\n"


class Game:
    """Per-game pooltool objects and the shot builder/judge."""

    def __init__(self, name):
        import pooltool as pt
        from pooltool.game.datatypes import GameType

        self.pt = pt
        self.name = name
        self.gt = {"nine_ball": GameType.NINEBALL, "eight_ball": GameType.EIGHTBALL,
                   "snooker": GameType.SNOOKER,
                   "three_cushion": GameType.THREECUSHION}[name]
        self.table = pt.Table.from_game_type(self.gt)
        self.table_name = {"nine_ball": "7ft", "eight_ball": "7ft", "snooker": "snooker",
                           "three_cushion": "billiard"}[name]
        self.table_file = f"data/tables/{self.table_name}.json"
        have = (ROOT / self.table_file).read_text(encoding="utf-8")
        if have != table_json_text(self.table):
            raise SystemExit(f"{self.table_file} is not pooltool's {self.gt} table")
        self.params = pt.BallParams.default(game_type=self.gt)
        self.R = self.params.R
        self.geo = Geo(self.table, self.R)
        self.cue_id = {"nine_ball": "cue", "eight_ball": "cue", "snooker": "white",
                       "three_cushion": "white"}[name]
        from pooltool.objects.table.collection import _default_game_type_map

        self.pooltool_table = _default_game_type_map[self.gt].name  # pooltool's TableName
        import attrs
        self.params_dict = {k: float(v) for k, v in attrs.asdict(self.params).items()}

    # ---- racks and balls

    def rack(self, rng):
        # pooltool's rack jitter and id draw use the global random / np.random
        import numpy as np
        random.seed(int(rng.integers(1 << 31)))
        np.random.seed(int(rng.integers(1 << 31)))
        balls = self.pt.get_rack(self.gt, table=self.table)
        return {bid: tuple(float(v) for v in b.state.rvw[0][:2]) for bid, b in balls.items()}

    def order(self, ids):
        if self.name in ("nine_ball", "eight_ball"):
            return sorted(ids, key=lambda b: 0 if b == "cue" else int(b))
        if self.name == "snooker":
            rank = {"white": -1, "yellow": 100, "green": 101, "brown": 102, "blue": 103,
                    "pink": 104, "black": 105}
            return sorted(ids, key=lambda b: rank[b] if b in rank else int(b[4:]))
        return sorted(ids, key=("white", "yellow", "red").index)

    def system(self, pos, strike, pocketed=None):
        """pos: {id: (x, y)}, pocketed: {id: pocket id}."""
        import numpy as np
        from pooltool.objects.ball.datatypes import BallState
        import pooltool.constants as const

        pt = self.pt
        pocketed = pocketed or {}
        balls = {}
        for bid in self.order(list(pos) + list(pocketed)):
            if bid in pos:
                balls[bid] = pt.Ball.create(bid, xy=pos[bid], **self.params_dict)
            else:
                p = self.table.pockets[pocketed[bid]]
                b = pt.Ball.create(bid, xy=(p.a, p.b), **self.params_dict)
                rvw = np.array([[p.a, p.b, -p.depth], [0, 0, 0], [0, 0, 0]], dtype=float)
                b.state = BallState(rvw, const.pocketed)
                balls[bid] = b
        cue = pt.Cue(cue_ball_id=strike["cue_ball"])
        cue.set_state(V0=strike["V0"], phi=strike["phi"], theta=strike["theta"],
                      a=strike["a"], b=strike["b"])
        return pt.System(cue=cue, table=self.table.copy(), balls=balls)

    # ---- judging (pooltool's own rule sets)

    def judge(self, system, ctx):
        from pooltool.ruleset import Player
        from pooltool.ruleset.datatypes import BallInHandOptions, ShotConstraints, ShotInfo
        from pooltool.ruleset.eight_ball import _EightBall
        from pooltool.ruleset.nine_ball import _NineBall
        from pooltool.ruleset.snooker import _Snooker
        from pooltool.ruleset.three_cushion import _ThreeCushion

        players = [Player("shooter"), Player("opponent")]
        if self.name == "nine_ball":
            game = _NineBall(players)
        elif self.name == "eight_ball":
            game = _EightBall(players)
            game.shot_constraints = ShotConstraints(
                ball_in_hand=BallInHandOptions.BEHIND_LINE if ctx["break"]
                else BallInHandOptions.NONE,
                movable=["cue"] if ctx["break"] else [],
                cueable=["cue"],
                hittable=tuple(ctx["hittable"]),
                call_shot=ctx["call_shot"],
                ball_call=ctx["ball_call"],
                pocket_call=ctx["pocket_call"],
            )
        elif self.name == "snooker":
            game = _Snooker(players)
            game.shot_constraints = ShotConstraints(
                ball_in_hand=BallInHandOptions.SEMICIRCLE if ctx["break"]
                else BallInHandOptions.NONE,
                movable=["white"] if ctx["break"] else [],
                cueable=["white"],
                hittable=tuple(ctx["hittable"]),
                call_shot=ctx["call_shot"],
                ball_call=ctx["ball_call"],
                pocket_call=ctx["pocket_call"],
            )
        else:
            game = _ThreeCushion(players, win_condition=ctx["win_condition"])
            game.shot_constraints = ShotConstraints(
                ball_in_hand=BallInHandOptions.NONE, movable=[],
                cueable=[ctx["cue_ball"]], hittable=tuple(), call_shot=False)
        game.shot_number = 0 if ctx.get("break") else 1
        game.turn_number = 0
        game.active_idx = 0
        before = Counter(ctx.get("score_before", {}))
        game.score = Counter(before)
        # pooltool's 8-ball get_score, on the 8, reads self.shot_info.legal: the PREVIOUS
        # shot's info (build_shot_info sets it only after). The game loop always has one;
        # here it is a legal shot of the shooter's (only the score depends on it).
        game.shot_info = ShotInfo(player=players[0], legal=True, reason="", turn_over=False,
                                  game_over=False, winner=None, score=Counter(before))
        info = game.build_shot_info(system)
        score = {p.name: int(info.score.get(p.name, 0)) for p in players}
        v = {
            "legal": bool(info.legal),
            "reason": str(info.reason),
            "foul": "" if info.legal else FOUL_CODES[str(info.reason)],
            "turn_over": bool(info.turn_over),
            "game_over": bool(info.game_over),
            "winner": None if info.winner is None else info.winner.name,
            "score": score,
        }
        if self.name in ("snooker", "three_cushion"):
            v["points"] = {p: score[p] - int(before.get(p, 0)) for p in score}
        return v


def event_digest(system):
    from pooltool.events.datatypes import EventType

    return [[e.event_type.value, float(e.time), [str(i) for i in e.ids]]
            for e in system.events if e.event_type != EventType.NONE]


def pocketed_ids(events):
    return [e[2][0] for e in events if e[0] == "ball_pocket"]


def strike(cue_ball, V0, phi, theta=0.0, a=0.0, b=0.0):
    return {"cue_ball": cue_ball, "V0": float(V0), "phi": float(phi % 360),
            "theta": float(theta), "a": float(a), "b": float(b)}


def spin(rng, s=0.3):
    return float(rng.uniform(-s, s)), float(rng.uniform(-s, s))


def elevation(rng):
    return float(rng.choice([0.0, 0.0, 0.0, float(rng.uniform(0, 8))]))


# ----------------------------------------------------------------------------------------
# pool (9-ball and 8-ball) positions


def head_spot(g, rng, placed):
    """The cue ball behind the head string (y below l/4), as on a break."""
    return g.geo.spot(rng, placed, box=(0.15 * g.geo.w, 0.85 * g.geo.w, 0.05, g.geo.l / 4 - g.R))


def pool_break(g, rng, soft=False):
    pos = g.rack(rng)
    pos.pop("cue", None)
    placed = list(pos.values())
    C = head_spot(g, rng, placed)
    if C is None:
        return None
    apex = min(pos, key=lambda b: pos[b][1])
    phi = angle_of(C, pos[apex]) + float(rng.normal(0, 1.0))
    V0 = float(rng.uniform(0.3, 2.0)) if soft else float(rng.uniform(2.0, 9.0))
    a, b = spin(rng, 0.2)
    pos = {"cue": C, **pos}
    return pos, strike("cue", V0, phi, 0.0, a, b)


def scatter(g, rng, ids, placed=None, pocket_clear=0.12):
    placed = list(placed or [])
    pos = {}
    for bid in ids:
        p = g.geo.spot(rng, placed, pocket_clear)
        if p is None:
            return None
        pos[bid] = p
        placed.append(p)
    return pos


def pot_position(g, rng, obj, others, cut=(-12.0, 12.0), d=(0.12, 0.7), e=(0.12, 0.9)):
    """``obj`` on a line into a random pocket, the cue ball behind its ghost ball, the
    ``others`` scattered; returns (pos, phi, pocket) or None."""
    pid = str(rng.choice(sorted(g.geo.pockets)))
    r = g.geo.pot_line(rng, pid, [], d=d)
    if r is None:
        return None
    O, u = r
    rc = g.geo.cue_behind(rng, O, u, [], e=e, cut=cut)
    if rc is None:
        return None
    C, phi = rc
    rest = scatter(g, rng, others, [C, O])
    if rest is None:
        return None
    if not g.geo.path_clear(C, O, list(rest.values())):
        return None
    return {g.cue_id: C, obj: O, **rest}, phi, pid


def plant_position(g, rng, first, second, others):
    """cue ball -> ``first`` -> ``second`` -> pocket, all nearly on one line."""
    pid = str(rng.choice(sorted(g.geo.pockets)))
    r = g.geo.pot_line(rng, pid, [], d=(0.12, 0.45))
    if r is None:
        return None
    O2, u = r
    gap = float(rng.uniform(0.0, 0.12))
    O1 = (O2[0] - (2 * g.R + 0.002 + gap) * u[0], O2[1] - (2 * g.R + 0.002 + gap) * u[1])
    if not g.geo.inside(O1, 0.12):
        return None
    rc = g.geo.cue_behind(rng, O1, u, [O2], e=(0.12, 0.7), cut=(-4.0, 4.0))
    if rc is None:
        return None
    C, phi = rc
    rest = scatter(g, rng, others, [C, O1, O2])
    if rest is None:
        return None
    return {g.cue_id: C, first: O1, second: O2, **rest}, phi, pid


def aim_away(g, rng, C, others_xy, tries=60):
    """A direction from C whose straight path (to 3 m) passes no ball."""
    for _ in range(tries):
        phi = float(rng.uniform(0, 360))
        end = (C[0] + 3 * math.cos(math.radians(phi)), C[1] + 3 * math.sin(math.radians(phi)))
        if g.geo.path_clear(C, end, others_xy):
            return phi
    return None


def aim_pocket(g, rng, C, others_xy):
    """A pocket whose centre C can roll straight to, and the direction."""
    pids = sorted(g.geo.pockets)
    rng.shuffle(pids)
    for pid in pids:
        P = g.geo.pockets[pid][0]
        if g.geo.path_clear(C, P, others_xy):
            return pid, angle_of(C, P) + float(rng.normal(0, 0.4))
    return None


def soft_touch(g, rng, target, others):
    """Cue ball and target well away from the cushions, a slow straight hit: no cushion
    after contact unless it rolls far."""
    geo = g.geo
    box = (0.25, geo.w - 0.25, 0.3, geo.l - 0.3)
    T = geo.spot(rng, [], box=box)
    if T is None:
        return None
    for _ in range(50):
        v = rot((1.0, 0.0), float(rng.uniform(0, 360)))
        dist = float(rng.uniform(2 * g.R + 0.03, 0.35))
        C = (T[0] - v[0] * dist, T[1] - v[1] * dist)
        if geo.inside(C, 0.15) and geo.free(C, [T], 0.01):
            break
    else:
        return None
    rest = scatter(g, rng, others, [C, T])
    if rest is None or not geo.path_clear(C, T, list(rest.values())):
        return None
    V0 = float(rng.uniform(0.12, 0.9))
    a, b = spin(rng, 0.2)
    phi = angle_of(C, T) + float(rng.normal(0, 1.5))
    return {g.cue_id: C, target: T, **rest}, strike(g.cue_id, V0, phi, 0.0, a, b)


# ---- 9-ball


def nine_shot(g, rng, scen):
    """(pos, strike, ctx, pocketed) for a 9-ball scenario."""
    ctx = {"break": scen.startswith("break")}
    if scen in ("break", "break_soft"):
        r = pool_break(g, rng, soft=scen == "break_soft")
        if r is None:
            return None
        pos, st = r
    else:
        k = int(rng.integers(1, 10))
        ids = sorted(int(i) for i in rng.choice(range(1, 10), size=k, replace=False))
        if scen == "nine_alone":  # the 9 the last ball: the lowest and the highest
            ids = [9]
        ids_s = [str(i) for i in ids]
        lowest = ids_s[0]
        others = [b for b in ids_s]
        if scen in ("pot_lowest", "in_off", "nine_alone"):
            obj = lowest if scen != "nine_alone" else lowest
            r = pot_position(g, rng, obj, [b for b in others if b != obj],
                             cut=(-20.0, 20.0) if scen != "in_off" else (-3.0, 3.0))
            if r is None:
                return None
            pos, phi, _ = r
            if scen == "in_off":
                V0, a, b = float(rng.uniform(1.5, 4.0)), float(rng.uniform(-0.1, 0.1)), float(rng.uniform(0.3, 0.6))
            else:
                V0 = float(rng.uniform(0.6, 4.0))
                a, b = spin(rng)
            st = strike("cue", V0, phi + float(rng.normal(0, 0.3)), elevation(rng), a, b)
        elif scen == "combo_nine":
            if len(ids_s) < 2 or "9" not in ids_s:
                ids_s = sorted(set(ids_s) | {"9"}, key=int)
                if len(ids_s) < 2:
                    ids_s = ["1", "9"]
            lowest = ids_s[0]
            r = plant_position(g, rng, lowest, "9", [b for b in ids_s if b not in (lowest, "9")])
            if r is None:
                return None
            pos, phi, _ = r
            a, b = spin(rng, 0.2)
            st = strike("cue", float(rng.uniform(1.0, 4.0)), phi, 0.0, a, b)
        elif scen == "wrong_first":
            if len(ids_s) < 2:
                ids_s = sorted(set(ids_s) | {str(int(rng.integers(1, 10)))}, key=int)
                if len(ids_s) < 2:
                    return None
            obj = str(rng.choice(ids_s[1:]))
            r = pot_position(g, rng, obj, [b for b in ids_s if b != obj], cut=(-20.0, 20.0))
            if r is None:
                return None
            pos, phi, _ = r
            a, b = spin(rng, 0.4)
            st = strike("cue", float(rng.uniform(0.6, 4.0)), phi, elevation(rng), a, b)
        elif scen in ("miss", "scratch_direct"):
            pos = scatter(g, rng, ["cue"] + ids_s)
            if pos is None:
                return None
            C = pos["cue"]
            rest = [pos[b] for b in ids_s]
            if scen == "miss":
                phi = aim_away(g, rng, C, rest)
                V0 = float(rng.uniform(0.3, 2.0))
            else:
                r = aim_pocket(g, rng, C, rest)
                phi = None if r is None else r[1]
                V0 = float(rng.uniform(1.0, 3.5))
            if phi is None:
                return None
            a, b = spin(rng, 0.1)
            st = strike("cue", V0, phi, 0.0, a, b)
        elif scen == "soft":
            r = soft_touch(g, rng, lowest, [b for b in ids_s if b != lowest])
            if r is None:
                return None
            pos, st = r
        else:
            raise ValueError(scen)
    ids = [b for b in pos if b != "cue"]
    ctx["hittable"] = [str(min(int(b) for b in ids))]  # worked out from the table (lowest)
    return pos, st, ctx, None


NINE_SCENARIOS = {
    "break": 0.10, "break_soft": 0.03, "pot_lowest": 0.27, "in_off": 0.08,
    "nine_alone": 0.06, "combo_nine": 0.06, "wrong_first": 0.14, "miss": 0.07,
    "scratch_direct": 0.04, "soft": 0.15,
}


def nine_key(ctx, v, events):
    k = ("break " if ctx["break"] else "") + (v["foul"] or "legal")
    if v["legal"]:
        k += ", pot" if not v["turn_over"] else ", no pot"
    if v["game_over"]:
        k += f", game over ({v['winner']} wins)"
    return k


NINE_HUNT = {"break legal, pot, game over (shooter wins)": "break",
             "break cue_pocketed": "break", "break break_rails": "break_soft"}

# ---- 8-ball

SOLIDS = tuple(str(i) for i in range(1, 8))
STRIPES = tuple(str(i) for i in range(9, 16))
OPEN = tuple(str(i) for i in range(1, 16) if i != 8)


def eight_position(g, rng, group):
    """Ball ids on the table and those already in the pockets, for the shooter's group."""
    pocketed = {}
    if group == "eight":
        mine = SOLIDS if rng.uniform() < 0.5 else STRIPES
        theirs = STRIPES if mine is SOLIDS else SOLIDS
        k = int(rng.integers(0, 8))
        on = sorted(rng.choice(theirs, size=k, replace=False).tolist(), key=int) + ["8"]
        pids = sorted(g.geo.pockets)
        for b in mine:
            pocketed[b] = str(rng.choice(pids))
        for b in theirs:
            if b not in on:
                pocketed[b] = str(rng.choice(pids))
        if rng.uniform() < 0.5:  # the opponent's finished balls needn't be in the pockets
            pocketed = {b: p for b, p in pocketed.items() if b in mine}
        return sorted(on, key=int), pocketed
    k = int(rng.integers(1, 16))
    on = sorted(rng.choice(range(1, 16), size=k, replace=False).tolist())
    on = [str(i) for i in on]
    hittable = {"solids": SOLIDS, "stripes": STRIPES, "open": OPEN}[group]
    if not any(b in hittable for b in on):
        on = sorted(set(on) | {str(rng.choice(hittable))}, key=int)
    return on, pocketed


EIGHT_GROUPS = {"solids": SOLIDS, "stripes": STRIPES, "open": OPEN, "eight": ("8",)}


def eight_shot(g, rng, scen):
    pid_list = sorted(g.geo.pockets)
    if scen in ("break", "break_soft"):
        r = pool_break(g, rng, soft=scen == "break_soft")
        if r is None:
            return None
        pos, st = r
        ctx = {"break": True, "group": "open", "hittable": list(OPEN), "call_shot": False,
               "ball_call": None, "pocket_call": None}
        return pos, st, ctx, None
    group = {"pot_eight": "eight", "eight_scratch": "eight"}.get(scen)
    if group is None:
        group = str(rng.choice(["solids", "stripes", "open", "eight"], p=[0.38, 0.38, 0.14, 0.10]))
        if scen in ("not_called", "eight_early", "eight_combo"):
            group = str(rng.choice(["solids", "stripes", "open"]))
    hittable = EIGHT_GROUPS[group]
    on, pocketed = eight_position(g, rng, group)
    mine = [b for b in on if b in hittable]
    theirs = [b for b in on if b not in hittable]
    ball_call, pocket_call = None, None
    if scen in ("pot_called", "not_called", "pot_eight", "eight_scratch", "in_off",
                "eight_early", "wrong_first"):
        if scen in ("pot_eight", "eight_scratch"):
            obj = "8"
        elif scen == "eight_early":
            if "8" not in on:
                on = sorted(on + ["8"], key=int)
            obj = "8"
        elif scen == "wrong_first":
            if not theirs:
                return None
            obj = str(rng.choice(theirs))
        else:
            obj = str(rng.choice(mine))
        r = pot_position(g, rng, obj, [b for b in on if b != obj],
                         cut=(-3.0, 3.0) if scen in ("in_off", "eight_scratch") else (-20.0, 20.0))
        if r is None:
            return None
        pos, phi, pid = r
        if scen in ("in_off", "eight_scratch"):
            V0, a, b = float(rng.uniform(1.5, 4.0)), float(rng.uniform(-0.1, 0.1)), float(rng.uniform(0.3, 0.6))
            th = 0.0
        else:
            V0 = float(rng.uniform(0.6, 4.0))
            a, b = spin(rng)
            th = elevation(rng)
        st = strike("cue", V0, phi + float(rng.normal(0, 0.3)), th, a, b)
        call = obj if obj in hittable else (str(rng.choice(mine)) if mine else None)
        ball_call = call
        pocket_call = pid if rng.uniform() < 0.75 else str(rng.choice(pid_list))
        if scen == "not_called":
            u = rng.uniform()
            if u < 0.4:
                ball_call = None
            elif u < 0.8:
                pocket_call = None
            else:
                ball_call, pocket_call = None, None
    elif scen == "eight_combo":
        if not mine:
            return None
        first = str(rng.choice(mine))
        r = plant_position(g, rng, first, "8", [b for b in on if b not in (first, "8")])
        if r is None:
            return None
        pos, phi, pid = r
        a, b = spin(rng, 0.2)
        st = strike("cue", float(rng.uniform(1.0, 4.0)), phi, 0.0, a, b)
        ball_call, pocket_call = first, str(rng.choice(pid_list))
    elif scen in ("miss", "scratch_direct"):
        pos = scatter(g, rng, ["cue"] + on)
        if pos is None:
            return None
        C = pos["cue"]
        rest = [pos[b] for b in on]
        if scen == "miss":
            phi = aim_away(g, rng, C, rest)
            V0 = float(rng.uniform(0.3, 2.0))
        else:
            r = aim_pocket(g, rng, C, rest)
            phi = None if r is None else r[1]
            V0 = float(rng.uniform(1.0, 3.5))
        if phi is None:
            return None
        a, b = spin(rng, 0.1)
        st = strike("cue", V0, phi, 0.0, a, b)
        ball_call, pocket_call = str(rng.choice(mine)), str(rng.choice(pid_list))
    elif scen == "soft":
        target = str(rng.choice(mine))
        r = soft_touch(g, rng, target, [b for b in on if b != target])
        if r is None:
            return None
        pos, st = r
        ball_call, pocket_call = target, str(rng.choice(pid_list))
    else:
        raise ValueError(scen)
    if group == "eight":
        ball_call = "8"  # pooltool's game (get_score) requires it on the 8
        if pocket_call is None:
            pocket_call = str(rng.choice(pid_list))
    ctx = {"break": False, "group": group, "hittable": list(hittable), "call_shot": True,
           "ball_call": ball_call, "pocket_call": pocket_call}
    return pos, st, ctx, pocketed


EIGHT_SCENARIOS = {
    "break": 0.09, "break_soft": 0.03, "pot_called": 0.26, "in_off": 0.06,
    "pot_eight": 0.07, "eight_scratch": 0.02, "eight_early": 0.05, "eight_combo": 0.03,
    "wrong_first": 0.10, "not_called": 0.06, "miss": 0.06, "scratch_direct": 0.04,
    "soft": 0.13,
}


def eight_key(ctx, v, events):
    k = ("break " if ctx["break"] else "") + (v["foul"] or "legal")
    if v["legal"]:
        if not v["turn_over"]:
            k += ", keeps the table"
        elif any(p != "cue" for p in pocketed_ids(events)):
            k += ", pot, turn over"
        else:
            k += ", no pot"
    if v["game_over"]:
        k += f", game over ({v['winner']} wins)"
    return k


EIGHT_HUNT = {"break legal, keeps the table, game over (shooter wins)": "break",
              "break cue_pocketed": "break", "break break_rails": "break_soft",
              "eight_illegal, game over (opponent wins)": "eight_early",
              "legal, keeps the table, game over (shooter wins)": "pot_eight",
              "cue_pocketed, game over (opponent wins)": "eight_scratch"}

# ---- snooker

REDS = tuple(f"red_{i:02d}" for i in range(1, 16))
COLOURS = ("yellow", "green", "brown", "blue", "pink", "black")
VALUE = {"yellow": 2, "green": 3, "brown": 4, "blue": 5, "pink": 6, "black": 7}


def d_spot(g, rng, placed):
    """The white in the D: behind the baulk line (brown's spot), within the D's radius
    (green's spot to brown's)."""
    geo = g.geo
    cx, cy, r = 0.5 * geo.w, 0.2 * geo.l, (0.666 - 0.5) * geo.w
    for _ in range(500):
        p = (float(rng.uniform(cx - r, cx + r)), float(rng.uniform(cy - r, cy)))
        if math.dist(p, (cx, cy)) <= r and geo.inside(p, 0.1) and geo.free(p, placed, 0.002):
            return p
    return None


def snooker_ctx(phase, ball_call=None, brk=False):
    if phase == "reds":
        return {"break": brk, "phase": "reds", "hittable": list(REDS), "call_shot": False,
                "ball_call": None, "pocket_call": None}
    if phase == "colours":
        return {"break": False, "phase": "colours", "hittable": list(COLOURS),
                "call_shot": True, "ball_call": ball_call, "pocket_call": "lb"}
    return {"break": False, "phase": phase, "hittable": [ball_call], "call_shot": True,
            "ball_call": ball_call, "pocket_call": "lb"}


def snooker_score(rng, phase):
    if phase == "black":
        s = int(rng.integers(20, 70))
        return {"shooter": s, "opponent": s + int(rng.choice([-14, -7, -5, -3, 0, 0, 3, 5, 7, 10]))}
    if rng.uniform() < 0.5:
        return {"shooter": 0, "opponent": 0}
    return {"shooter": int(rng.integers(0, 60)), "opponent": int(rng.integers(0, 60))}


def snooker_shot(g, rng, scen):
    rack = g.rack(rng)
    spots = {c: rack[c] for c in COLOURS}
    if scen in ("break", "break_colour"):
        pos = dict(rack)
        placed = [p for b, p in pos.items() if b != "white"]
        C = d_spot(g, rng, placed)
        if C is None:
            return None
        pos["white"] = C
        if scen == "break_colour" or rng.uniform() < 0.05:
            tgt = str(rng.choice(COLOURS)) if scen == "break_colour" else None
            if tgt is None:
                phi = float(rng.uniform(0, 360))
            else:
                phi = angle_of(C, pos[tgt]) + float(rng.normal(0, 0.5))
        else:
            # a red the white can reach straight (the baulk colours stand in the way of some)
            others = {b: p for b, p in pos.items() if b != "white"}
            open_reds = [b for b in REDS if g.geo.path_clear(
                C, pos[b], [p for o, p in others.items() if o != b])]
            if not open_reds:
                return None
            near = sorted(open_reds, key=lambda b: math.dist(C, pos[b]))[: int(rng.integers(1, 5))]
            tgt = str(rng.choice(near))
            phi = angle_of(C, pos[tgt]) + float(rng.normal(0, 1.5))
        a, b = spin(rng, 0.3)
        st = strike("white", float(rng.uniform(0.8, 6.0)), phi, 0.0, a, b)
        ctx = snooker_ctx("reds", brk=True)
        ctx["score_before"] = {"shooter": 0, "opponent": 0}
        return pos, st, ctx, None

    # mid-game: choose the phase the scenario needs
    phase = {"reds_pot": "reds", "reds_colour": "reds", "reds_plant": "reds",
             "colours_pot": "colours", "colours_wrong": "colours", "colours_plant": "colours",
             "seq_pot": "sequential", "seq_wrong": "sequential", "black_pot": "black",
             "black_scratch": "black"}.get(scen)
    if phase is None:
        phase = str(rng.choice(["reds", "colours", "sequential", "black"], p=[0.4, 0.3, 0.2, 0.1]))
    if phase in ("reds", "colours"):
        nred = int(rng.integers(1, 16))
        reds = sorted(rng.choice(REDS, size=nred, replace=False).tolist())
        colours = list(COLOURS)
    elif phase == "sequential":
        first = int(rng.integers(0, 5))  # yellow..pink lowest; black alone is the 'black' phase
        colours = list(COLOURS[first:])
        reds = []
    else:
        colours, reds = ["black"], []
    on_spot = [c for c in colours if rng.uniform() < 0.6]
    if phase == "colours":
        ball_call = str(rng.choice(colours))
    elif phase in ("sequential", "black"):
        ball_call = colours[0]
    else:
        ball_call = None
    # the ball the strike is about, by scenario
    others_pool = reds + colours
    obj = second = None
    if scen in ("reds_pot", "in_off") and phase == "reds":
        obj = str(rng.choice(reds))
    elif scen == "reds_colour" or (scen == "wrong_first" and phase == "reds"):
        obj = str(rng.choice(colours))
    elif scen == "reds_plant":
        obj, second = str(rng.choice(reds)), str(rng.choice(colours))
    elif scen in ("colours_pot", "seq_pot", "black_pot", "black_scratch", "in_off"):
        obj = ball_call
    elif scen in ("colours_wrong", "seq_wrong", "wrong_first"):
        choices = [b for b in others_pool if b != ball_call]
        if not choices:
            return None
        obj = str(rng.choice(choices))
    elif scen == "colours_plant":
        obj = ball_call
        choices = [b for b in others_pool if b != ball_call]
        if not choices:
            return None
        second = str(rng.choice(choices))
    # place: fixed colour spots first (they must not overlap the set-up balls)
    if scen in ("miss", "scratch_direct", "soft"):
        fixed = {c: spots[c] for c in on_spot}
        rest_ids = [b for b in others_pool if b not in fixed]
        pos = scatter(g, rng, ["white"] + rest_ids, list(fixed.values()), 0.1)
        if pos is None:
            return None
        pos.update(fixed)
        C = pos["white"]
        rest = [p for b, p in pos.items() if b != "white"]
        if scen == "miss":
            phi = aim_away(g, rng, C, rest)
            V0 = float(rng.uniform(0.3, 3.0))
        elif scen == "scratch_direct":
            r = aim_pocket(g, rng, C, rest)
            phi = None if r is None else r[1]
            V0 = float(rng.uniform(1.0, 4.0))
        else:
            tgt = ball_call if ball_call else str(rng.choice(reds))
            T = pos[tgt]
            phi = angle_of(C, T) + float(rng.normal(0, 1.0))
            V0 = float(rng.uniform(0.3, 2.5))
        if phi is None:
            return None
        a, b = spin(rng, 0.2)
        st = strike("white", V0, phi, 0.0, a, b)
    else:
        if second is None:
            r = pot_position(g, rng, obj, [], cut=(-3.0, 3.0) if scen in ("in_off", "black_scratch") else (-20.0, 20.0))
        else:
            r = plant_position(g, rng, obj, second, [])
        if r is None:
            return None
        pos, phi, _ = r
        used = list(pos.values())
        fixed = {c: spots[c] for c in on_spot if c not in pos
                 and g.geo.free(spots[c], used, 0.002)
                 and g.geo.path_clear(pos["white"], pos[obj], [spots[c]])}
        rest_ids = [b for b in others_pool if b not in pos and b not in fixed]
        rest = scatter(g, rng, rest_ids, used + list(fixed.values()), 0.1)
        if rest is None:
            return None
        pos.update(fixed)
        pos.update(rest)
        if not g.geo.path_clear(pos["white"], pos[obj], [p for b, p in pos.items() if b not in ("white", obj)]):
            return None
        if scen in ("in_off", "black_scratch"):
            V0, a, b = float(rng.uniform(1.5, 4.5)), float(rng.uniform(-0.1, 0.1)), float(rng.uniform(0.3, 0.6))
        else:
            V0 = float(rng.uniform(0.6, 4.5))
            a, b = spin(rng)
        st = strike("white", V0, phi + float(rng.normal(0, 0.3)), 0.0, a, b)
    ctx = snooker_ctx({"sequential": "sequential", "black": "black"}.get(phase, phase), ball_call)
    ctx["score_before"] = snooker_score(rng, phase)
    return pos, st, ctx, None


SNOOKER_SCENARIOS = {
    "break": 0.08, "break_colour": 0.02, "reds_pot": 0.14, "reds_colour": 0.06,
    "reds_plant": 0.06, "colours_pot": 0.10, "colours_wrong": 0.05, "colours_plant": 0.05,
    "seq_pot": 0.06, "seq_wrong": 0.04, "black_pot": 0.06, "black_scratch": 0.03,
    "in_off": 0.06, "wrong_first": 0.03, "miss": 0.06, "scratch_direct": 0.04, "soft": 0.06,
}


def snooker_key(ctx, v, events):
    ph = "break" if ctx["break"] else ctx["phase"]
    k = f"{ph}: " + (v["foul"] or "legal")
    if v["legal"]:
        k += ", pot" if not v["turn_over"] else ", no pot"
    if v["game_over"]:
        k += ", game over"
    return k


SNOOKER_HUNT = {}

# ---- three-cushion


def three_shot(g, rng, scen):
    if scen == "opening":
        pos = g.rack(rng)
        cue_ball = "white"
    else:
        pos = scatter(g, rng, ["white", "yellow", "red"], [], 0.0)
        if pos is None:
            return None
        cue_ball = "white" if rng.uniform() < 0.5 else "yellow"
    C = pos[cue_ball]
    others = [b for b in pos if b != cue_ball]
    u = rng.uniform()
    if scen == "opening":
        phi = angle_of(C, pos["red"]) + float(rng.normal(0, 4.0))
    elif u < 0.75:  # at a ball, full to thin
        phi = angle_of(C, pos[str(rng.choice(others))]) + float(rng.normal(0, 10.0))
    else:
        phi = float(rng.uniform(0, 360))
    a, b = spin(rng, 0.5)
    st = strike(cue_ball, float(rng.uniform(1.5, 6.0)), phi, elevation(rng), a, b)
    score = int(rng.choice([0, 0, 3, 5, 9, 9])) if scen != "opening" else 0
    ctx = {"break": scen == "opening", "cue_ball": cue_ball, "win_condition": 10,
           "score_before": {"shooter": score, "opponent": int(rng.integers(0, 10))}}
    return pos, st, ctx, None


THREE_SCENARIOS = {"opening": 0.1, "random": 0.9}


def three_key(ctx, v, events):
    if not v["turn_over"]:
        return "point" + (", game over" if v["game_over"] else "")
    cue = ctx["cue_ball"]
    hit = []
    for e in events:
        if e[0] == "ball_ball" and cue in e[2]:
            o = [i for i in e[2] if i != cue][0]
            if o not in hit:
                hit.append(o)
    if len(hit) < 2:
        return f"no point ({len(hit)} ball{'s' if len(hit) != 1 else ''} hit)"
    return "no point (both hit, < 3 cushions first)"


THREE_HUNT = {"point, game over": "random"}

SPECS = {
    "nine_ball": (nine_shot, NINE_SCENARIOS, nine_key, NINE_HUNT),
    "eight_ball": (eight_shot, EIGHT_SCENARIOS, eight_key, EIGHT_HUNT),
    "snooker": (snooker_shot, SNOOKER_SCENARIOS, snooker_key, SNOOKER_HUNT),
    "three_cushion": (three_shot, THREE_SCENARIOS, three_key, THREE_HUNT),
}

# ----------------------------------------------------------------------------------------


def run(game_name: str, out: Path, limit: int | None):
    import numpy as np
    import pooltool as pt

    g = Game(game_name)
    build, scenarios, key_of, hunt = SPECS[game_name]
    rng = np.random.default_rng([SEED, GAMES.index(game_name)])
    names = list(scenarios)
    weights = np.array([scenarios[n] for n in names])
    weights = weights / weights.sum()
    lines: list[str] = []
    counts: Counter[str] = Counter()
    fouls: Counter[str] = Counter()
    tags: Counter[str] = Counter()
    tries = Counter()

    def attempt(scen, only=None):
        tries[scen] += 1
        shot = build(g, rng, scen)
        if shot is None:
            return False
        pos, st, ctx, pocketed = shot
        system = g.system(pos, st, pocketed)
        pt.simulate(system, inplace=True)
        v = g.judge(system, ctx)
        events = event_digest(system)
        key = key_of(ctx, v, events)
        if only is not None and key != only:
            return False
        if counts[key] >= CAP[game_name] and only is None:
            return False
        counts[key] += 1
        fouls[(("break " if ctx.get("break") else "") + (v["foul"] or "legal"))] += 1
        pk = pocketed_ids(events)
        if not v["legal"] and v["foul"] != "cue_pocketed" and g.cue_id in pk:
            tags[f"{v['foul']} with the cue ball pocketed too"] += 1
        if game_name == "nine_ball" and not v["legal"] and "9" in pk:
            tags["foul with the 9 pocketed (no game over)"] += 1
        if game_name == "eight_ball" and v["foul"] == "eight_illegal":
            tags["eight_illegal: " + ("8 out of turn" if ctx["group"] != "eight" else "8 in the wrong pocket")] += 1
        if game_name == "snooker" and not v["legal"]:
            tags[f"foul worth {v['points']['opponent']}"] += 1
        if game_name == "three_cushion":
            tags["cue ball " + ctx["cue_ball"]] += 1
        balls = []
        for bid, b in system.balls.items():
            x, y = (float(c) for c in b.history[0].rvw[0][:2])
            d = {"id": bid, "x": x, "y": y}
            if pocketed and bid in pocketed:
                d["pocket"] = pocketed[bid]
            balls.append(d)
        rec = {
            "shot": len(lines), "game": game_name, "scenario": scen,
            "table": g.table_name, "table_file": g.table_file,
            "pooltool_table": g.pooltool_table, "ball_params": g.params_dict,
            "balls": balls, "strike": st, "context": ctx, "events": events, "verdict": v,
        }
        lines.append(json.dumps(rec, separators=(",", ":"), allow_nan=False))
        return True

    done = lambda: limit is not None and len(lines) >= limit  # noqa: E731
    n_main = N_MAIN[game_name]
    guard = 0
    while len(lines) < n_main and not done() and guard < 40 * n_main:
        guard += 1
        attempt(str(rng.choice(names, p=weights)))
    for want, scen in hunt.items():
        n = 0
        while counts[want] < MIN and n < HUNT_TRIES and not done():
            n += 1
            attempt(scen, only=want)
    body = ("\n".join(lines) + "\n").encode()
    path = out / f"{game_name}.jsonl"
    gz = path.with_name(path.name + ".gz")
    for stale in (path, gz):
        if stale.exists():
            stale.unlink()
    if len(body) > MAX_BYTES:
        with open(gz, "wb") as f, gzip.GzipFile(fileobj=f, mode="wb", mtime=0, filename="") as z:
            z.write(body)
        path = gz
    else:
        path.write_bytes(body)
    print(f"== {game_name}: {len(lines)} shots -> {path.relative_to(out.parent) if out.parent in path.parents else path} "
          f"({path.stat().st_size} bytes); draws per scenario {dict(sorted(tries.items()))}")
    print("   verdict categories:")
    for k in sorted(counts):
        print(f"   {counts[k]:5d}  {k}")
    print("   fouls (by code):")
    for k in sorted(fouls):
        print(f"   {fouls[k]:5d}  {k}")
    print("   also:")
    for k in sorted(tags):
        print(f"   {tags[k]:5d}  {k}")
    short = [k for k in hunt if counts[k] < MIN]
    if short:
        print(f"   SHORT of {MIN}: {short}")
    sys.stdout.flush()


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("games", nargs="*", help="some of " + ", ".join(GAMES) + " (default: all)")
    ap.add_argument("--out", type=Path, default=ROOT / "data" / "rules")
    ap.add_argument("--limit", type=int, default=None)
    args = ap.parse_args()
    bad = [name for name in args.games if name not in GAMES]
    if bad:
        ap.error(f"unknown game(s) {bad}: choose from {', '.join(GAMES)}")
    args.out.mkdir(parents=True, exist_ok=True)
    import pooltool as pt

    if pt.__version__ != "0.6.0":
        raise SystemExit(f"pooltool {pt.__version__}: the reference is pooltool 0.6.0's")
    for name in args.games or GAMES:
        run(name, args.out, args.limit)


if __name__ == "__main__":
    if os.environ.get("PYTHONHASHSEED") != "0":
        env = dict(os.environ, PYTHONHASHSEED="0")
        sys.exit(subprocess.run([sys.executable, *sys.argv], env=env).returncode)
    main()
