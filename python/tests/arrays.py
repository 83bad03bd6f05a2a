"""Input arrays the tests build from the repository's CSV examples."""

from __future__ import annotations

import pathlib

import numpy as np

import kisstime


def balls_array(path: pathlib.Path) -> np.ndarray:
    """A balls CSV (state as a name or a code) as a structured array of BALL_DTYPE."""
    balls = np.genfromtxt(path, delimiter=",", names=True, dtype=None, encoding="utf-8")
    arr = np.zeros(len(balls), dtype=kisstime.BALL_DTYPE)
    for name in kisstime.BALL_DTYPE.names:
        if name == "state":
            arr[name] = [kisstime.STATES[s] if isinstance(s, str) else s for s in balls[name]]
        else:
            arr[name] = balls[name]
    return arr


def strike_columns(path: pathlib.Path) -> dict:
    """A strikes CSV as a dict of STRIKE_DTYPE's columns."""
    s = np.genfromtxt(path, delimiter=",", names=True, dtype=None, encoding="utf-8")
    return {n: np.atleast_1d(s[n]) for n in kisstime.STRIKE_DTYPE.names}
