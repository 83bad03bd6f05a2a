"""A PettingZoo AEC environment of two players at one table of 8-ball or 9-ball
(``pip install pettingzoo``; docs/rl.md).

``PoolAECEnv`` takes turns as the game's rules say (the turn passes on a miss or a foul,
not after every shot): ``agent_selection`` is the player to shoot. Observations and actions
are :mod:`kisstime.gym`'s (the observation from the point of view of the player to shoot,
its ``shooter`` number saying who that is); each shot's reward goes to the player who shot,
and at the game's end the other player gets ``win`` or ``loss`` as well.
"""

from __future__ import annotations

from typing import Any, Optional

import numpy as np
from pettingzoo import AECEnv

from .gym import PoolVectorEnv

__all__ = ["PoolAECEnv", "env"]


class PoolAECEnv(AECEnv):
    """Two players, one table (module docs); keyword arguments as
    :class:`kisstime.gym.PoolVectorEnv`'s but ``num_envs`` and ``opponent``."""

    metadata = {"name": "kisstime_pool_v0", "render_modes": [], "is_parallelizable": False}

    def __init__(self, game: str = "9-ball", **kwargs: Any) -> None:
        super().__init__()
        if game not in ("8-ball", "9-ball"):
            raise ValueError(f"game {game!r}: two players play \"8-ball\" or \"9-ball\"")
        for key in ("num_envs", "opponent"):
            if key in kwargs:
                raise TypeError(f"PoolAECEnv takes no {key}: one table, two agents")
        self._vec = PoolVectorEnv(1, game=game, opponent=None, **kwargs)
        self.possible_agents = ["player_0", "player_1"]
        self.agents = []
        self.observation_spaces = {a: self._vec.single_observation_space for a in self.possible_agents}
        self.action_spaces = {a: self._vec.single_action_space for a in self.possible_agents}
        self.render_mode = None
        self._obs = np.zeros(self._vec.single_observation_space.shape, dtype=np.float32)

    def observation_space(self, agent: str):
        return self.observation_spaces[agent]

    def action_space(self, agent: str):
        return self.action_spaces[agent]

    def observe(self, agent: str) -> np.ndarray:
        return self._obs.copy()

    def _to_shoot(self) -> str:
        return self.possible_agents[int(self._obs[-2])]

    def reset(self, seed: Optional[int] = None, options: Optional[dict] = None) -> None:
        obs, _ = self._vec.reset(seed=seed)
        self._obs = obs[0]
        self.agents = self.possible_agents[:]
        self.rewards = {a: 0.0 for a in self.agents}
        self._cumulative_rewards = {a: 0.0 for a in self.agents}
        self.terminations = {a: False for a in self.agents}
        self.truncations = {a: False for a in self.agents}
        self.infos = {a: {} for a in self.agents}
        self.agent_selection = self._to_shoot()

    def step(self, action: Any) -> None:
        agent = self.agent_selection
        if self.terminations[agent] or self.truncations[agent]:
            self._was_dead_step(action)
            return
        self._cumulative_rewards[agent] = 0.0
        obs, reward, terminated, truncated, info = self._vec.step(
            np.asarray(action, dtype=np.float64).reshape(1, 7)
        )
        self.rewards = {a: 0.0 for a in self.agents}
        self.rewards[agent] = float(reward[0])
        if terminated[0]:
            # the game is over: the other player's win or loss too
            other = self.possible_agents[1 - self.possible_agents.index(agent)]
            winner = "player_0" if info["won"][0] else "player_1"
            w = self._vec.rewards
            self.rewards[other] = w["win"] if winner == other else w["loss"]
        self.terminations = {a: bool(terminated[0]) for a in self.agents}
        self.truncations = {a: bool(truncated[0]) for a in self.agents}
        self.infos = {a: {"fouled": bool(info["fouled"][0]), "potted": int(info["potted"][0])} for a in self.agents}
        self._obs = obs[0]
        if not (terminated[0] or truncated[0]):
            self.agent_selection = self._to_shoot()
        self._accumulate_rewards()


def env(**kwargs: Any) -> PoolAECEnv:
    """A :class:`PoolAECEnv` (PettingZoo's ``env()`` convention)."""
    return PoolAECEnv(**kwargs)
