"""The game reference sets (``data/games/``: nine_ball, eight_ball, snooker) are their
generator's output: the first shots of each (a break and ordinary shots) are made again by
``tools/games/reference.py`` (pooltool 0.6.0 simulating and judging, seeded) and must be
the files' first rows, cell for cell (event times to 1e-6 s). (``tests/games.rs`` checks
kisstime's judge against the files.)

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


@pytest.mark.parametrize("game", ["nine_ball", "eight_ball", "snooker"])
def test_each_set_is_its_generators_output(tmp_path, game):
    env = dict(os.environ, NUMBA_DISABLE_JIT="1", PYTHONPATH=os.pathsep.join(sys.path))
    run = subprocess.run(
        [sys.executable, str(ROOT / "tools" / "games" / "reference.py"), game,
         str(tmp_path), str(SHOTS)],
        env=env, capture_output=True, text=True, timeout=900,
    )
    assert run.returncode == 0, run.stderr[-4000:]
    kept = ROOT / "data" / "games" / game
    for name in ["shots.csv", "balls.csv", "events.csv"]:
        made = rows(tmp_path / name)
        first = [r for r in rows(kept / name) if r[0] == "shot" or int(r[0]) < SHOTS]
        assert len(made) > SHOTS, name
        assert len(made) == len(first), name
        for a, b in zip(made, first):
            if name == "events.csv" and a[0] != "shot":
                # numba's compiled pooltool and its pure-Python run (here) may differ in
                # an event time's last bits, which a break's many contacts grow to ~1e-9 s
                assert a[:3] + a[4:] == b[:3] + b[4:], (name, a, b)
                assert math.isclose(float(a[3]), float(b[3]), rel_tol=0, abs_tol=1e-6)
            else:
                assert a == b, (name, a, b)


def close_rows(a, b, name):
    """Cell for cell, floats (times, positions) to 1e-6."""
    assert len(a) == len(b), (name, a, b)
    for x, y in zip(a, b):
        if x == y:
            continue
        try:
            assert math.isclose(float(x), float(y), rel_tol=0, abs_tol=1e-6), (name, a, b)
        except ValueError:
            raise AssertionError((name, a, b)) from None


@pytest.mark.parametrize("name,shots", [("snooker", 1), ("carom", 2)])
def test_each_table_set_is_its_generators_output(tmp_path, name, shots):
    """data/snooker and data/carom (tests/sim_tables.rs replays them) are
    tools/games/tables_reference.py's output: its first shots made again (without the
    perturbed runs of stability.csv) are the files' first rows."""
    env = dict(os.environ, NUMBA_DISABLE_JIT="1", KISSTIME_REF_NO_STABILITY="1",
               PYTHONPATH=os.pathsep.join(sys.path))
    run = subprocess.run(
        [sys.executable, str(ROOT / "tools" / "games" / "tables_reference.py"), name,
         str(tmp_path), str(shots)],
        env=env, capture_output=True, text=True, timeout=900,
    )
    assert run.returncode == 0, run.stderr[-4000:]
    import gzip

    kept = ROOT / "data" / name
    for fname in ["shots.csv", "initial.csv", "final.csv", "events.csv.gz", "physics.toml",
                  "table.json"]:
        opener = gzip.open if fname.endswith(".gz") else open
        with opener(tmp_path / fname, "rt", newline="") as f:
            made = list(csv.reader(f))
        with opener(kept / fname, "rt", newline="") as f:
            first = [r for r in csv.reader(f)
                     if not fname.endswith((".csv", ".gz")) or r[0] == "shot"
                     or int(r[0]) < shots]
        assert len(made) == len(first) and len(made) > 1, fname
        for a, b in zip(made, first):
            close_rows(a, b, fname)
