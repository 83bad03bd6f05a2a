"""Gymnasium environments on kisstime's batched engine: 8-ball, 9-ball and a potting drill,
many tables stepped in one engine call (docs/rl.md).

- :class:`PoolVectorEnv`: a Gymnasium 1.x vector environment of ``num_envs`` tables
  (1 … 10⁵), CPU or GPU; one step is one shot on every table, simulated to rest and judged
  by the game's rules (pooltool 0.6.0's). Autoreset: Gymnasium's "next step" mode.
- :class:`PoolEnv`: one table, registered as ``kisstime/EightBall-v0``,
  ``kisstime/NineBall-v0`` and ``kisstime/PotDrill-v0`` (``gymnasium.make``; with
  ``gymnasium.make_vec`` they build a :class:`PoolVectorEnv`).

**Action** (``Box`` of 7, float32): ``V0`` (m/s, 0–8), ``phi`` (degrees, 0–360), ``theta``
(degrees, 0–60), ``a``, ``b`` (the tip's offsets as fractions of the ball radius, −0.5–0.5:
pooltool's ``Cue``), ``x``, ``y`` (m, where to place the cue ball; used only with the cue
ball in hand — the free spot nearest to it). Actions outside the bounds are clipped; NaN or
infinite ones raise ``ValueError``.

**Observation** (``Box``, float32), from the point of view of the player to shoot: for each
ball of the game (8-ball the cue ball and 1–15, 9-ball 0–9, the drill the cue ball and its
balls) ``x, y`` (m; 0 when off the table), on the table (0/1), may be hit first (0/1: the
group, the lowest ball, the 8 when it is on); then the cue ball in hand, the break, the
player to shoot (0/1), the shots played as a fraction of ``max_shots``.

**Reward**, to the player who shot: ``pot`` per own ball potted on a legal shot, ``foul``
per foul, ``win``/``loss`` at the game's end (also when the opponent's shot ends it);
defaults +1, −1, +10, −10. 8-ball shots are called as they go (the ball the shooter may pot
that went down first, in its pocket).

**Opponent**: ``None`` (the agent plays both seats; the observation says whose turn),
``"greedy"``, ``"sampler"`` or ``"planner"`` (kisstime's agents), or a callable
``policy(obs) -> actions`` on a batch of observations: the opponent's turns are then played
inside ``step`` and the agent sees only its own; breaks alternate from episode to episode.
"""

from __future__ import annotations

from typing import Any, Callable, Mapping, Optional, Union

import numpy as np

import gymnasium as gym
from gymnasium import spaces
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space

from . import _kisstime, _noise_arg, _quiet_mesa

__all__ = [
    "ACTION_NAMES",
    "ACTION_LOW",
    "ACTION_HIGH",
    "PoolEnv",
    "PoolVectorEnv",
    "observation_names",
]

#: The action's components.
ACTION_NAMES = ("V0", "phi", "theta", "a", "b", "x", "y")
#: The action's lower bounds (``ACTION_NAMES`` order).
ACTION_LOW = np.array([0.0, 0.0, 0.0, -0.5, -0.5, 0.0, 0.0], dtype=np.float32)
#: The action's upper bounds; the table's playing area is 1.27 × 2.54 m (the 9-ft table).
ACTION_HIGH = np.array([8.0, 360.0, 60.0, 0.5, 0.5, 1.27, 2.54], dtype=np.float32)

_GAMES = ("8-ball", "9-ball", "drill")
_AGENTS = ("greedy", "sampler", "planner")
_REWARD_KEYS = ("pot", "foul", "win", "loss")
_DEFAULT_REWARDS = {"pot": 1.0, "foul": -1.0, "win": 10.0, "loss": -10.0}


def _ball_ids(game: str, drill_balls: int) -> list:
    if game == "8-ball":
        return list(range(16))
    if game == "9-ball":
        return list(range(10))
    return [0] + list(range(max(1, 10 - drill_balls), 10))


def observation_names(game: str = "9-ball", drill_balls: int = 1) -> list:
    """The names of the observation's numbers, in order (``"x1"``, ``"on1"``, …)."""
    names = []
    for i in _ball_ids(game, drill_balls):
        names += [f"x{i}", f"y{i}", f"on{i}", f"hittable{i}"]
    return names + ["in_hand", "break", "shooter", "shots"]


def _spaces(game: str, drill_balls: int):
    ids = _ball_ids(game, drill_balls)
    high = []
    for _ in ids:
        high += [1.27, 2.54, 1.0, 1.0]
    high += [1.0, 1.0, 1.0, 1.0]
    obs = spaces.Box(0.0, np.array(high, dtype=np.float32), dtype=np.float32)
    act = spaces.Box(ACTION_LOW, ACTION_HIGH, dtype=np.float32)
    return obs, act


def _seed_of(seed: Any) -> int:
    if isinstance(seed, (bool, np.bool_)) or not isinstance(seed, (int, np.integer)):
        raise TypeError(f"seed must be an integer or None, not {type(seed).__name__}")
    seed = int(seed)
    if not 0 <= seed < 2**64:
        raise ValueError(f"seed {seed}: an integer in [0, 2**64)")
    return seed


class PoolVectorEnv(VectorEnv):
    """``num_envs`` tables of 8-ball, 9-ball or the drill, stepped in one engine call
    (module docs).

    Args:
        num_envs: Tables, 1 to 2**24.
        game: ``"8-ball"``, ``"9-ball"`` or ``"drill"`` (pot ``drill_balls`` balls — the
            highest numbers up to the 9, lowest first, by 9-ball's rules — from a random
            position; the episode ends when the 9 is potted legally).
        drill_balls: The drill's object balls, 1 to 9.
        max_shots: Shots of both players after which an episode is truncated (default
            100; the drill 5).
        rewards: Any of ``pot``, ``foul``, ``win``, ``loss`` (module docs).
        noise: The cue noise every shot is played under: ``"none"`` (default), a preset
            of :data:`kisstime.NOISE_PRESETS`, or a dict of σ in pooltool's units.
        noise_scale: Every σ times this.
        opponent: ``None``, an agent's name, or a callable (module docs).
        planner_samples: The planner opponent's samples per decision.
        max_events: Events after which a shot is cut (its moving balls stopped where they
            are; ``info["cut"]``).
        backend: ``"cpu"``, ``"gpu"`` or ``"auto"`` (f64 everywhere).
        autoreset_mode: Gymnasium's ``AutoresetMode.NEXT_STEP`` (default: the step after
            an episode's end resets that table, its action ignored, reward 0) or
            ``SAME_STEP`` (the ending step returns the new episode's observation, the last
            one in ``info["final_obs"]``, as stable-baselines3 expects).
    """

    metadata = {"autoreset_mode": AutoresetMode.NEXT_STEP, "render_modes": []}

    def __init__(
        self,
        num_envs: int = 1,
        *,
        game: str = "9-ball",
        drill_balls: int = 1,
        max_shots: Optional[int] = None,
        rewards: Optional[Mapping[str, float]] = None,
        noise: Union[str, Mapping[str, float]] = "none",
        noise_scale: float = 1.0,
        opponent: Union[None, str, Callable[[np.ndarray], Any]] = None,
        planner_samples: int = 20_000,
        max_events: int = 5_000,
        backend: str = "cpu",
        autoreset_mode: AutoresetMode = AutoresetMode.NEXT_STEP,
    ) -> None:
        if autoreset_mode not in (AutoresetMode.NEXT_STEP, AutoresetMode.SAME_STEP):
            raise ValueError(f"autoreset_mode {autoreset_mode}: NEXT_STEP or SAME_STEP")
        self.metadata = {**self.metadata, "autoreset_mode": autoreset_mode}
        if isinstance(num_envs, bool) or not isinstance(num_envs, (int, np.integer)):
            raise TypeError(f"num_envs must be an integer, not {type(num_envs).__name__}")
        if game not in _GAMES:
            raise ValueError(f"game {game!r}: one of {', '.join(_GAMES)}")
        if max_shots is None:
            max_shots = 5 if game == "drill" else 100
        weights = dict(_DEFAULT_REWARDS)
        for key, value in dict(rewards or {}).items():
            if key not in _REWARD_KEYS:
                raise ValueError(f"rewards: unknown key {key!r} (keys: {_REWARD_KEYS})")
            weights[key] = float(value)
        preset, sigma = _noise_arg(noise)
        self._policy = None
        if opponent is None:
            who = "self"
        elif callable(opponent):
            who, self._policy = "policy", opponent
        elif opponent in _AGENTS:
            who = opponent
        else:
            raise ValueError(f"opponent {opponent!r}: None, one of {_AGENTS}, or a callable")
        _quiet_mesa(backend)
        self._core = _kisstime.VecEnv(
            game,
            int(drill_balls),
            int(num_envs),
            int(max_shots),
            tuple(weights[k] for k in _REWARD_KEYS),
            preset,
            sigma,
            float(noise_scale),
            who,
            int(planner_samples),
            int(max_events),
            backend,
        )
        self.num_envs = int(num_envs)
        self.game = game
        self.max_shots = int(max_shots)
        self.rewards = weights
        self.single_observation_space, self.single_action_space = _spaces(game, drill_balls)
        self.observation_space = batch_space(self.single_observation_space, self.num_envs)
        self.action_space = batch_space(self.single_action_space, self.num_envs)
        self.render_mode = None

    def _observe(self) -> np.ndarray:
        return self._core.observe().reshape(self.num_envs, self._core.obs_len)

    def _call_policy(self, obs: np.ndarray) -> Any:
        return self._policy(obs)

    @property
    def backend(self) -> str:
        """What ran (the engine's description)."""
        return self._core.describe()

    def reset(
        self,
        *,
        seed: Union[int, list, None] = None,
        options: Optional[dict] = None,
    ) -> tuple:
        """New episodes on every table: with ``seed``, table ``k`` from ``seed + k`` (or
        ``seed[k]`` from a list); without, each table's next episode."""
        if seed is None:
            seeds = None
        elif isinstance(seed, (list, tuple, np.ndarray)):
            seeds = [_seed_of(s) for s in seed]
            if len(seeds) != self.num_envs:
                raise ValueError(f"{len(seeds)} seeds for {self.num_envs} tables")
        else:
            first = _seed_of(seed)
            seeds = [(first + k) % 2**64 for k in range(self.num_envs)]
        if seed is not None:
            super().reset(seed=seeds[0])
        shots = self._core.reset(seeds, self._policy and self._call_policy)
        info = {"opponent_shots": np.asarray(shots, dtype=np.int64)}
        return self._observe(), info

    def step(self, actions: Any) -> tuple:
        a = np.asarray(actions, dtype=np.float64)
        if a.shape != (self.num_envs, 7):
            raise ValueError(f"actions of shape {a.shape}: expected ({self.num_envs}, 7)")
        rewards, terminated, truncated, info = self._core.step(
            np.ascontiguousarray(a).reshape(-1), self._policy and self._call_policy
        )
        infos = {
            "reset": np.asarray(info["reset"], dtype=bool),
            "fouled": np.asarray(info["fouled"], dtype=bool),
            "potted": np.asarray(info["potted"], dtype=np.int64),
            "won": np.asarray(info["won"], dtype=bool),
            "opponent_shots": np.asarray(info["opponent_shots"], dtype=np.int64),
            "cut": np.asarray(info["cut"], dtype=bool),
        }
        obs = self._observe()
        ended = np.asarray(terminated, dtype=bool) | np.asarray(truncated, dtype=bool)
        if self.metadata["autoreset_mode"] == AutoresetMode.SAME_STEP and ended.any():
            infos["final_obs"] = obs.copy()
            infos["_final_obs"] = ended
            _, shots = self._core.reset_ended(self._policy and self._call_policy)
            infos["opponent_shots"] += np.asarray(shots, dtype=np.int64)
            obs = self._observe()
        return (
            obs,
            np.asarray(rewards, dtype=np.float64),
            np.asarray(terminated, dtype=bool),
            np.asarray(truncated, dtype=bool),
            infos,
        )


class PoolEnv(gym.Env):
    """One table of :class:`PoolVectorEnv` (the same arguments but ``num_envs``); a
    Gymnasium environment: ``reset(seed=s)`` plays as table ``k`` of a vector environment
    reset with ``seed=s - k``."""

    metadata = {"render_modes": []}

    def __init__(self, **kwargs: Any) -> None:
        if "num_envs" in kwargs:
            raise TypeError("PoolEnv is one table: use PoolVectorEnv for num_envs")
        self._vec = PoolVectorEnv(1, **kwargs)
        self.observation_space = self._vec.single_observation_space
        self.action_space = self._vec.single_action_space
        self.render_mode = None

    def reset(self, *, seed: Optional[int] = None, options: Optional[dict] = None) -> tuple:
        super().reset(seed=seed)
        obs, info = self._vec.reset(seed=seed)
        return obs[0], {k: v[0] for k, v in info.items()}

    def step(self, action: Any) -> tuple:
        a = np.asarray(action, dtype=np.float64).reshape(1, -1)
        if a.shape != (1, 7):
            raise ValueError(f"an action of {a.size} numbers: expected 7 ({', '.join(ACTION_NAMES)})")
        obs, reward, terminated, truncated, info = self._vec.step(a)
        return (
            obs[0],
            float(reward[0]),
            bool(terminated[0]),
            bool(truncated[0]),
            {k: v[0] for k, v in info.items() if k != "reset"},
        )


def _register() -> None:
    for name, kwargs in (
        ("EightBall-v0", {"game": "8-ball"}),
        ("NineBall-v0", {"game": "9-ball"}),
        ("PotDrill-v0", {"game": "drill"}),
    ):
        env_id = f"kisstime/{name}"
        if env_id not in gym.registry:
            gym.register(
                id=env_id,
                entry_point="kisstime.gym:PoolEnv",
                vector_entry_point="kisstime.gym:PoolVectorEnv",
                kwargs=kwargs,
            )


_register()
