#!/usr/bin/env python3
"""Time pooltool 0.6.0 on the snooker study of `examples/snooker.toml`, judged.

Each sample is what kisstime's study does per sample: the strike of the example with its
noise drawn (V0 ± 0.1 m/s, phi ± 0.2°, a and b ± 1 mm at the ball's surface, normal),
`pt.simulate` from the strike to rest, then pooltool's own snooker verdict (`_Snooker`'s
`build_shot_info`, through `tools/games/reference.py`'s `snooker_judge`). One process, one
thread; the first sample (numba's compile) is not timed.

Run from the repository root, in a venv with pooltool (benches/pooltool_requirements.txt):

    python benches/pooltool_snooker_study.py 500

and compare with `kisstime shots examples/snooker.toml --samples 500000 --threads 1`.
"""
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tools" / "games"))
import reference as ref  # noqa: E402
import pooltool as pt  # noqa: E402
from pooltool.game.datatypes import GameType  # noqa: E402
table = pt.Table.from_game_type(GameType.SNOOKER)
pos = {"white": (0.694, 2.7475), "red_01": (0.30, 3.20), "red_02": (1.2, 2.6),
       "blue": (0.873, 1.772), "pink": (0.873, 2.6), "black": (0.873, 3.2205)}
rng = np.random.default_rng(42)
R = 0.02625  # snooker ball radius (m): noise in metres at the surface / R


def strike():
    return dict(V0=2.0 + rng.normal(0, 0.1), phi=131.05 + rng.normal(0, 0.2), theta=0.0,
                a=rng.normal(0, 0.001) / R, b=(-0.3 + rng.normal(0, 0.001) / R))
n = int(sys.argv[1]) if len(sys.argv) > 1 else 200
s = ref.snooker_simulate(table, pos, strike()); ref.snooker_judge(s, None, 0, 0)  # warm-up (numba)
t0 = time.perf_counter(); sims = 0.0; pots = legal = 0
for _ in range(n):
    a = time.perf_counter(); s = ref.snooker_simulate(table, pos, strike()); sims += time.perf_counter() - a
    _, info = ref.snooker_judge(s, None, 0, 0)
    legal += info.legal
dt = time.perf_counter() - t0
print(f"{n} samples in {dt:.2f} s: {n/dt:.1f} samples/s (simulate {sims/dt*100:.0f} % of it); legal {legal/n:.2f}")
