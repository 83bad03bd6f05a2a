#!/usr/bin/env python3
"""Steps per second of a 9-ball learning environment written on pooltool 0.6.0, against
kisstime's (``kisstime.gym.PoolVectorEnv``) doing the same work per step.

One step, both sides: the agent's strike (drawn uniformly from the action bounds, the same
stream for both), the cue ball placed first when in hand, the shot simulated from the strike
to rest, judged by the 9-ball rules (pooltool: its own ``nine_ball.is_legal``,
``is_turn_over``, ``is_game_over``), the table updated (pocketed balls off, the 9 spotted
again after a foul), the observation built (every ball's x, y, on-table flag), and a new
rack when the game is over or after 100 shots. pooltool's side is what such environments
are written as today (one table, ``pt.simulate`` per step); kisstime's steps N tables in one
engine call.

Run from the repository root, in a venv with pooltool (benches/pooltool_requirements.txt),
gymnasium and kisstime installed:

    python benches/pooltool_env.py            # pooltool ~60 s, kisstime at N = 1, 1,024, 65,536

Prints one line per measurement: ``name  N  steps  seconds  steps/s``.
"""
from __future__ import annotations

import argparse
import math
import time

import numpy as np

LOW = np.array([0.0, 0.0, 0.0, -0.5, -0.5, 0.0, 0.0])
HIGH = np.array([8.0, 360.0, 60.0, 0.5, 0.5, 1.27, 2.54])


def pooltool_steps(seconds: float, seed: int) -> tuple[int, float]:
    import pooltool as pt
    from pooltool.game.datatypes import GameType
    from pooltool.ruleset import nine_ball

    table = pt.Table.default()
    R = pt.BallParams.default().R
    rng = np.random.default_rng(seed)

    def rack() -> dict:
        balls = pt.get_rack(GameType.NINEBALL, table=table)
        balls["cue"] = pt.Ball.create("cue", xy=(table.w / 2, table.l / 4 - 0.1))
        return balls

    def free(balls: dict, x: float, y: float) -> tuple[float, float]:
        x = min(max(x, R + 1e-3), table.w - R - 1e-3)
        y = min(max(y, R + 1e-3), table.l - R - 1e-3)
        for _ in range(200):
            if all(math.hypot(b.state.rvw[0][0] - x, b.state.rvw[0][1] - y) > 2 * R + 1e-3
                   for k, b in balls.items() if k != "cue"):
                return x, y
            x, y = rng.uniform(R, table.w - R), rng.uniform(R, table.l - R)
        return x, y

    balls, break_shot, in_hand, shots = rack(), True, False, 0
    # warm-up (numba's compile), not timed
    cue = pt.Cue(cue_ball_id="cue")
    cue.set_state(V0=2.0, phi=90.0)
    pt.simulate(pt.System(cue=cue, table=table, balls=rack()), inplace=True)
    steps, started = 0, time.perf_counter()
    while time.perf_counter() - started < seconds:
        a = rng.uniform(LOW, HIGH)
        if in_hand:
            balls["cue"] = pt.Ball.create("cue", xy=free(balls, a[5], a[6]))
        cue = pt.Cue(cue_ball_id="cue")
        cue.set_state(V0=float(a[0]), phi=float(a[1]), theta=float(a[2]), a=float(a[3]), b=float(a[4]))
        system = pt.System(cue=cue, table=table, balls=balls)
        pt.simulate(system, inplace=True, max_events=5000)
        legal, _ = nine_ball.is_legal(system, break_shot=break_shot)
        nine_ball.is_turn_over(system, legal)
        over = nine_ball.is_game_over(system, legal)
        shots += 1
        if over or shots >= 100:
            balls, break_shot, in_hand, shots = rack(), True, False, 0
        else:
            balls = {}
            for k, b in system.balls.items():
                if b.state.s != pt.constants.pocketed:
                    x, y = b.state.rvw[0][:2]
                    balls[k] = pt.Ball.create(k, xy=(float(x), float(y)))
            if "9" not in balls:
                balls["9"] = pt.Ball.create("9", xy=free(balls, table.w / 2, table.l * 0.75))
            in_hand = not legal or "cue" not in balls
            if in_hand:
                balls.pop("cue", None)
                balls["cue"] = pt.Ball.create("cue", xy=free(balls, table.w / 2, table.l / 4))
            break_shot = False
        # the observation
        np.array([[*b.state.rvw[0][:2], 1.0] for b in balls.values()], dtype=np.float32)
        steps += 1
    return steps, time.perf_counter() - started


def kisstime_steps(n: int, seconds: float, seed: int, backend: str) -> tuple[int, float]:
    from kisstime.gym import PoolVectorEnv

    env = PoolVectorEnv(n, game="9-ball", backend=backend)
    env.reset(seed=seed)
    rng = np.random.default_rng(seed)
    env.step(rng.uniform(LOW, HIGH, size=(n, 7)))  # warm-up
    steps, started = 0, time.perf_counter()
    while time.perf_counter() - started < seconds or steps == 0:
        env.step(rng.uniform(LOW, HIGH, size=(n, 7)))
        steps += n
    return steps, time.perf_counter() - started


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--seconds", type=float, default=60.0, help="per measurement")
    p.add_argument("--sizes", default="1,1024,65536", help="kisstime's N")
    p.add_argument("--backend", default="cpu")
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--skip-pooltool", action="store_true")
    args = p.parse_args()
    if not args.skip_pooltool:
        steps, dt = pooltool_steps(args.seconds, args.seed)
        print(f"pooltool  1  {steps}  {dt:.1f}  {steps / dt:.1f}", flush=True)
    for n in (int(s) for s in args.sizes.split(",")):
        steps, dt = kisstime_steps(n, args.seconds, args.seed, args.backend)
        print(f"kisstime-{args.backend}  {n}  {steps}  {dt:.1f}  {steps / dt:.1f}", flush=True)


if __name__ == "__main__":
    main()
