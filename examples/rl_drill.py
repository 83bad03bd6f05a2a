"""Trains a small agent on kisstime's potting drill with stable-baselines3's PPO, on the
CPU, and draws its reward curve.

    pip install ./python gymnasium stable-baselines3 matplotlib
    python examples/rl_drill.py                      # ~3 minutes on 2 cores
    python examples/rl_drill.py --steps 512 --envs 64 --out /tmp/curve.png   # a smoke run

The environment is ``kisstime.gym.PoolVectorEnv(game="drill")``: the cue ball and the 9 at
random, one shot an episode (``max_shots=1``), +1 for the 9 potted legally, -1 for a foul,
under the ``club`` cue noise; every table of the batch is stepped in one engine call. The
agent sees the two balls' positions and chooses the strike. Two conveniences of the kind
every learner writes sit in the adapter below, not in the environment: actions in [-1, 1]
(PPO's scale), and the aim given as an offset of up to ±30° from the line to the 9, so that
a small network learns the cut in minutes rather than the geometry of ``atan2``.

stable-baselines3 steps its own ``VecEnv`` type; the adapter hands it the batched
environment in Gymnasium's "same step" autoreset mode, as SB3 expects (the ending
observation in ``terminal_observation``).
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from gymnasium import spaces
from gymnasium.vector import AutoresetMode
from stable_baselines3 import PPO
from stable_baselines3.common.vec_env import VecEnv

from kisstime.gym import ACTION_HIGH, ACTION_LOW, PoolVectorEnv

AIM_RANGE = 30.0  # degrees either side of the line to the 9
R = 0.028575  # the ball radius, m
# the 9-ft table's pocket centres (m), as kisstime's Table::nine_foot places them
POCKETS = np.array([[0.0, 0.0], [0.0, 1.27], [0.0, 2.54], [1.27, 0.0], [1.27, 1.27], [1.27, 2.54]])


def ghost_features(obs: np.ndarray) -> np.ndarray:
    """Per pocket: the ghost-ball aim's offset from the line to the 9 (/ AIM_RANGE,
    clipped to ±1) and the cut's cosine."""
    cue, nine = obs[:, 0:2].astype(np.float64), obs[:, 4:6].astype(np.float64)
    line = np.arctan2(*(nine - cue).T[::-1])
    out = []
    for p in POCKETS:
        u = p - nine
        u /= np.maximum(np.linalg.norm(u, axis=1, keepdims=True), 1e-9)
        ghost = nine - 2 * R * u
        d = ghost - cue
        aim = np.arctan2(d[:, 1], d[:, 0])
        offset = (np.degrees(aim - line) + 180.0) % 360.0 - 180.0
        cos_cut = (d * u).sum(axis=1) / np.maximum(np.linalg.norm(d, axis=1), 1e-9)
        out += [np.clip(offset / AIM_RANGE, -1, 1), cos_cut]
    return np.stack(out, axis=1).astype(np.float32)


class DrillVecEnv(VecEnv):
    """kisstime's drill as a stable-baselines3 ``VecEnv`` (module docs)."""

    def __init__(self, n: int, seed: int) -> None:
        self.pool = PoolVectorEnv(
            n,
            game="drill",
            max_shots=1,
            noise="club",
            rewards={"win": 0.0},
            autoreset_mode=AutoresetMode.SAME_STEP,
        )
        self.seed_ = seed
        self.render_mode = None
        n_obs = self.pool.single_observation_space.shape[0] + 2 * len(POCKETS)
        obs_space = spaces.Box(-1.0, 1.0, (n_obs,), np.float32)
        super().__init__(n, obs_space, spaces.Box(-1.0, 1.0, (5,), np.float32))
        self.high = self.pool.single_observation_space.high
        self.obs = None
        self.actions = None
        self.episode_rewards: list = []

    def _scale(self, obs: np.ndarray) -> np.ndarray:
        scaled = (2.0 * obs / np.maximum(self.high, 1e-9) - 1.0).astype(np.float32)
        return np.concatenate([scaled, ghost_features(obs)], axis=1)

    def reset(self):
        self.obs, _ = self.pool.reset(seed=self.seed_)
        return self._scale(self.obs)

    def step_async(self, actions: np.ndarray) -> None:
        self.actions = np.clip(actions, -1.0, 1.0)

    def step_wait(self):
        a = self.actions
        lo, hi = ACTION_LOW.astype(np.float64), ACTION_HIGH.astype(np.float64)
        full = np.empty((self.num_envs, 7))
        # from [-1, 1]: V0 up to 4 m/s; phi the line to the 9 plus the aim offset; the
        # cue level (theta 0, the third number unused); a and b within half the radius
        full[:, 0] = (a[:, 0] + 1) / 2 * 4.0
        dx = self.obs[:, 4] - self.obs[:, 0]
        dy = self.obs[:, 5] - self.obs[:, 1]
        full[:, 1] = (np.degrees(np.arctan2(dy, dx)) + AIM_RANGE * a[:, 1]) % 360.0
        full[:, 2] = 0.0
        full[:, 3] = 0.5 * a[:, 3]
        full[:, 4] = 0.5 * a[:, 4]
        full[:, 5] = self.obs[:, 0]
        full[:, 6] = self.obs[:, 1]
        np.clip(full, lo, hi, out=full)
        obs, rew, term, trunc, info = self.pool.step(full)
        done = term | trunc
        infos = [{} for _ in range(self.num_envs)]
        for k in np.flatnonzero(done):
            infos[k]["terminal_observation"] = self._scale(info["final_obs"][k : k + 1])[0]
            infos[k]["TimeLimit.truncated"] = bool(trunc[k] and not term[k])
        self.episode_rewards.extend(rew[done].tolist())
        self.obs = obs
        return self._scale(obs), rew.astype(np.float32), done, infos

    def close(self) -> None:
        pass

    def get_attr(self, attr_name, indices=None):
        return [getattr(self, attr_name)] * self.num_envs

    def set_attr(self, attr_name, value, indices=None) -> None:
        setattr(self, attr_name, value)

    def env_method(self, method_name, *args, indices=None, **kwargs):
        return [getattr(self, method_name)(*args, **kwargs)] * self.num_envs

    def env_is_wrapped(self, wrapper_class, indices=None):
        return [False] * self.num_envs


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=300_000, help="environment steps in all")
    parser.add_argument("--envs", type=int, default=256, help="tables stepped at once")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--out", default="rl_drill.png", help="the reward curve (PNG)")
    args = parser.parse_args()

    env = DrillVecEnv(args.envs, args.seed)
    # one shot an episode: short rollouts, many small updates, a narrow start to exploration
    n_steps = max(2, min(16, args.steps // args.envs))
    model = PPO(
        "MlpPolicy",
        env,
        n_steps=n_steps,
        batch_size=min(1024, n_steps * args.envs),
        learning_rate=1e-3,
        gamma=0.0,
        ent_coef=0.0,
        policy_kwargs={"log_std_init": -1.0},
        seed=args.seed,
        device="cpu",
        verbose=0,
    )
    curve = []
    started = time.perf_counter()
    done = 0
    rollout = n_steps * args.envs
    while done < args.steps:
        env.episode_rewards.clear()
        model.learn(total_timesteps=rollout, reset_num_timesteps=False)
        done += rollout
        if env.episode_rewards:
            curve.append((done, float(np.mean(env.episode_rewards))))
            print(f"{done:>8} steps  mean reward {curve[-1][1]:+.3f}  ({time.perf_counter() - started:.0f} s)")

    # the baseline a programmer writes without learning: the straightest ghost-ball pot at
    # 1 m/s, on fresh positions
    base = DrillVecEnv(args.envs, args.seed + 1)
    obs = base.pool.reset(seed=args.seed + 1)[0]
    f = ghost_features(obs)
    best = np.argmax(f[:, 1::2], axis=1)
    line = np.degrees(np.arctan2(obs[:, 5] - obs[:, 1], obs[:, 4] - obs[:, 0]))
    scripted = np.zeros((args.envs, 7))
    scripted[:, 0] = 1.0
    scripted[:, 1] = (line + AIM_RANGE * f[np.arange(args.envs), 2 * best]) % 360
    scripted[:, 5:7] = obs[:, 0:2]
    baseline = float(base.pool.step(scripted)[1].mean())
    print(f"scripted ghost-ball baseline: mean reward {baseline:+.3f}")

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    xs, ys = zip(*curve)
    fig, ax = plt.subplots(figsize=(7, 4))
    ax.plot(xs, ys, marker="o", ms=3, label="PPO")
    ax.axhline(baseline, color="grey", ls="--", label="scripted ghost-ball pot")
    ax.legend(loc="lower right")
    ax.set_xlabel("environment steps (shots)")
    ax.set_ylabel("mean reward per episode (+1 pot, -1 foul)")
    ax.set_title(f"PPO on kisstime's drill, {args.envs} tables a step, club noise")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(args.out, dpi=100)
    print(f"wrote {args.out}: {len(curve)} points, {time.perf_counter() - started:.0f} s")


if __name__ == "__main__":
    main()
