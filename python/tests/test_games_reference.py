"""The game reference sets (``data/games/``) are their generators' output: the first
shots of ``data/games/nine_ball`` are made again by ``tools/games/nine_ball_reference.py``
(pooltool 0.6.0 simulating and judging, seeded) and must be the files' first rows, cell for
cell (event times to 1e-9). (``tests/games.rs`` checks kisstime's judge against the
files.)

pooltool runs in a subprocess with ``NUMBA_DISABLE_JIT=1``, as in test_bridge.py: a few
shots cost less than numba's compilation.
"""

import csv
import math
import os
import subprocess
import sys
from pathlib import Path

import pytest

if not os.environ.get("CI"):
    pytest.importorskip("pooltool")

ROOT = Path(__file__).resolve().parents[2]
SHOTS = 4


def rows(path: Path) -> list[list[str]]:
    with open(path, newline="") as f:
        return list(csv.reader(f))


def test_the_nine_ball_set_is_its_generators_output(tmp_path):
    env = dict(os.environ, NUMBA_DISABLE_JIT="1", PYTHONPATH=os.pathsep.join(sys.path))
    run = subprocess.run(
        [sys.executable, str(ROOT / "tools" / "games" / "nine_ball_reference.py"),
         str(tmp_path), str(SHOTS)],
        env=env, capture_output=True, text=True, timeout=900,
    )
    assert run.returncode == 0, run.stderr[-4000:]
    kept = ROOT / "data" / "games" / "nine_ball"
    for name in ["shots.csv", "balls.csv", "events.csv"]:
        made = rows(tmp_path / name)
        first = [r for r in rows(kept / name) if r[0] == "shot" or int(r[0]) < SHOTS]
        assert len(made) > SHOTS, name
        assert len(made) == len(first), name
        for a, b in zip(made, first):
            if name == "events.csv" and a[0] != "shot":
                # numba's compiled pooltool and its pure-Python run (here) may differ in
                # an event time's last bits
                assert a[:3] + a[4:] == b[:3] + b[4:], (name, a, b)
                assert math.isclose(float(a[3]), float(b[3]), rel_tol=1e-9, abs_tol=1e-9)
            else:
                assert a == b, (name, a, b)
