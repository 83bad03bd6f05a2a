"""Type stubs of the compiled extension (the public API is in ``kisstime/__init__.py``)."""

from typing import Any, Optional

import numpy as np
import numpy.typing as npt

_I = npt.NDArray[np.int64]
_F = npt.NDArray[np.float64]
_Params = tuple[float, float, float, float, float]
# (kind, text, source): kind "toml" (a file's text), "dict" (a dict written as TOML) or "json"
_Physics = Optional[tuple[str, str, str]]

class Batch:
    def __init__(
        self, table: _I, ball: _I, state: _I, x: _F, y: _F, vx: _F, vy: _F, wx: _F, wy: _F, wz: _F
    ) -> None: ...
    @staticmethod
    def from_records(records: npt.NDArray[np.uint8]) -> "Batch": ...
    @property
    def num_tables(self) -> int: ...
    @property
    def num_balls(self) -> int: ...
    @property
    def num_pairs(self) -> int: ...

def pair_times(
    batch: Batch, params: _Params, backend: str, precision: Optional[str]
) -> bytes: ...
def next_collisions(
    batch: Batch, params: _Params, backend: str, precision: Optional[str]
) -> bytes: ...
def simulate(
    batch: Batch, strikes: Optional[tuple[_I, _I, list[_F]]], table_name: str,
    max_events: int, max_time: float, events: bool, backend: str, precision: Optional[str],
    physics: _Physics = None,
    physics_columns: Optional[tuple[_I, list[tuple[str, _F]]]] = None,
    table_json: Optional[str] = None,
    rules: Optional[str] = None,
    context: Optional[str] = None,
    rule_ids: Optional[tuple[_I, _I]] = None,
    wpa: bool = False,
) -> tuple[Optional[bytes], bytes, bytes]: ...
# positions as tables 0..P-1 (names: their balls' ids); shots (position, cue ball index or
# -1, [V0, phi, theta, a, b]); physics: one, or one a position; report: check every shot
# first and return the bad ones as (shot, message) instead of raising
def simulate_shots(
    positions: Batch, names: list[list[str]], shots: tuple[_I, _I, list[_F]],
    table_name: str, table_json: Optional[str], physics: list[_Physics], max_events: int,
    max_time: float, events: bool, backend: str, precision: Optional[str], report: bool,
) -> tuple[Optional[bytes], bytes, bytes, list[tuple[int, str]]]: ...
def plan(
    ids: list[int], xs: list[float], ys: list[float], table_name: str,
    table_json: Optional[str], physics: _Physics, rules: str, hittable: Optional[list[int]],
    noise_preset: Optional[str], noise_sigma: Optional[tuple[float, float, float, float, float]],
    noise_scale: float, budget_seconds: Optional[float], budget_samples: Optional[int],
    seed: int, top: int, backend: str, ball_in_hand: Optional[str] = None,
) -> str: ...
def study_chunk(
    kind: str, text: str, source: str, dir: Optional[str], physics: _Physics,
    physics_noise: Optional[str], first: int,
    n: int, seed: int,
    strikes: Optional[tuple[_I, list[_F]]], until: str, noise: Optional[float],
    max_events: int, max_time: float, backend: str, precision: Optional[str],
) -> bytes: ...
def study_merge(
    kind: str, text: str, source: str, dir: Optional[str], physics: _Physics,
    physics_noise: Optional[str], blobs: list[bytes],
    until: str,
) -> tuple[str, dict[str, np.ndarray], list[str]]: ...
def study_ids(
    kind: str, text: str, source: str, dir: Optional[str], physics: _Physics,
    physics_noise: Optional[str],
) -> tuple[list[str], list[str], list[str], list[str], int, int]: ...
def table_ids(
    name: str, json: Optional[str] = None
) -> tuple[list[str], list[str], list[str]]: ...
def release_engines() -> int: ...
class VecEnv:
    """Many games stepped at once (kisstime.gym's engine)."""
    def __init__(
        self, task: str, drill_balls: int, tables: int, max_shots: int,
        rewards: tuple[float, float, float, float], noise_preset: Optional[str],
        noise_sigma: Optional[tuple[float, float, float, float, float]], noise_scale: float,
        opponent: str, budget_samples: int, max_events: int, backend: str,
    ) -> None: ...
    @property
    def obs_len(self) -> int: ...
    @property
    def num_tables(self) -> int: ...
    def describe(self) -> str: ...
    def observe(self) -> np.ndarray: ...
    def reset(self, seeds: Optional[list[int]], policy: Optional[Any] = None) -> list[int]: ...
    def reset_ended(self, policy: Optional[Any] = None) -> tuple[list[bool], list[int]]: ...
    def step(
        self, actions: np.ndarray, policy: Optional[Any] = None
    ) -> tuple[list[float], list[bool], list[bool], dict[str, list]]: ...
