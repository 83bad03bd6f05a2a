"""kisstime.gym: the Gymnasium environments pass Gymnasium's checks, a vector environment
plays as the single environments it batches, runs are reproducible bit for bit, the
opponent's turns are played, bad input is refused, the GPU (f64) gives the CPU's
observations and rewards, and the training example runs (shortened)."""

from __future__ import annotations

import os
import pathlib
import subprocess
import sys

import numpy as np
import pytest



def need(module: str):
    """The module; without it the tests skip with the reason, except in CI (``CI=true``,
    which installs it), where they fail."""
    if os.environ.get("CI") == "true":
        return __import__(module)
    return pytest.importorskip(module, reason=f"{module} is not installed (pip install {module})")


gym = need("gymnasium")
from gymnasium.utils.env_checker import check_env  # noqa: E402
from gymnasium.vector import SyncVectorEnv  # noqa: E402

import kisstime  # noqa: E402
from kisstime.gym import ACTION_HIGH, ACTION_LOW, PoolEnv, PoolVectorEnv, observation_names  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.mark.parametrize("env_id", ["kisstime/EightBall-v0", "kisstime/NineBall-v0", "kisstime/PotDrill-v0"])
def test_the_registered_environments_pass_gymnasiums_checker(env_id):
    env = gym.make(env_id, noise="club")
    check_env(env.unwrapped, skip_render_check=True)
    obs, _ = env.reset(seed=3)
    assert env.observation_space.contains(obs)
    assert len(obs) == len(observation_names(env.unwrapped._vec.game, 1))


@pytest.mark.parametrize("game,opponent", [("9-ball", "greedy"), ("8-ball", None), ("drill", None)])
def test_a_vector_environment_plays_as_the_single_environments_it_batches(game, opponent):
    kwargs = dict(game=game, noise="club", opponent=opponent, max_shots=6)
    vec = PoolVectorEnv(4, **kwargs)
    sync = SyncVectorEnv([lambda: PoolEnv(**kwargs) for _ in range(4)])
    assert vec.metadata["autoreset_mode"] == sync.metadata["autoreset_mode"]
    assert vec.action_space == sync.action_space
    assert vec.observation_space == sync.observation_space
    # as gymnasium.utils.env_match.check_environments_match (written for single
    # environments) does, bit for bit: actions sampled from the space, the same for both;
    # autoresets included (6 shots an episode)
    vec.action_space.seed(5)
    a, b = vec.reset(seed=5)[0], sync.reset(seed=5)[0]
    assert a.tobytes() == b.tobytes()
    ended = 0
    for _ in range(14):
        action = vec.action_space.sample()
        out_a, out_b = vec.step(action), sync.step(action)
        for x, y in zip(out_a[:4], out_b[:4]):
            assert x.dtype == y.dtype and x.tobytes() == y.tobytes()
        ended += int((out_a[2] | out_a[3]).sum())
    assert ended > 0


def test_make_vec_builds_the_batched_environment():
    env = gym.make_vec("kisstime/NineBall-v0", num_envs=8, vectorization_mode="vector_entry_point")
    assert isinstance(env.unwrapped, PoolVectorEnv)
    obs, _ = env.reset(seed=1)
    assert obs.shape == (8, 44) and obs.dtype == np.float32
    obs, rew, term, trunc, info = env.step(env.action_space.sample())
    assert rew.shape == (8,) and term.dtype == bool and info["fouled"].shape == (8,)


def run(env: PoolVectorEnv, seed: int, steps: int) -> list:
    out = [env.reset(seed=seed)[0]]
    rng = np.random.default_rng(0)
    for _ in range(steps):
        a = rng.uniform(ACTION_LOW, ACTION_HIGH, size=(env.num_envs, 7))
        obs, rew, term, trunc, info = env.step(a)
        out += [obs, rew, term, trunc, info["potted"], info["reset"]]
    return out


def test_runs_are_reproducible_bit_for_bit_and_the_seed_matters():
    make = lambda: PoolVectorEnv(16, game="8-ball", noise="fastfiz", opponent="greedy", max_shots=8)  # noqa: E731
    a, b, c = run(make(), 9, 10), run(make(), 9, 10), run(make(), 10, 10)
    for x, y in zip(a, b):
        assert np.array_equal(x, y)
        assert x.tobytes() == y.tobytes()
    assert any(not np.array_equal(x, y) for x, y in zip(a, c))


def test_rewards_follow_the_rules_in_the_drill():
    env = PoolVectorEnv(32, game="drill", rewards={"win": 0.0})
    obs, _ = env.reset(seed=2)
    # the cue ball (x0, y0) straight at the 9 (x9, y9) at 1.5 m/s: a full hit
    _, rew, term, trunc, info = env.step(aimed_drill(obs, 1.5))
    assert np.array_equal(rew, info["potted"] - info["fouled"].astype(float))
    assert np.array_equal(term, info["potted"] == 1)
    # a full hit is never a foul but for a scratch
    assert info["fouled"].sum() < 32


def test_a_callable_opponent_plays_its_turns_and_its_errors_propagate():
    seen = []

    def policy(obs):
        seen.append(obs.shape)
        assert (obs[:, -2] == 1.0).all()  # player 1 to shoot
        n = obs.shape[0]
        return np.tile([2.0, 90.0, 0.0, 0.0, 0.0, 0.6, 0.6], (n, 1))

    env = PoolVectorEnv(6, game="9-ball", opponent=policy, max_shots=30)
    env.reset(seed=4)
    total = 0
    for _ in range(5):
        _, _, _, _, info = env.step(np.tile([1.0, 270.0, 0, 0, 0, 0.6, 0.6], (6, 1)))
        total += info["opponent_shots"].sum()
    assert total > 0 and seen and all(s[1] == 44 for s in seen)

    def broken(obs):
        raise KeyError("the policy broke")

    env = PoolVectorEnv(2, game="9-ball", opponent=broken)
    env.reset(seed=1)
    with pytest.raises(KeyError, match="the policy broke"):
        for _ in range(20):
            env.step(np.tile([1.0, 270.0, 0, 0, 0, 0.6, 0.6], (2, 1)))


def test_bad_input_is_refused_clearly():
    env = PoolVectorEnv(3, game="drill")
    env.reset(seed=1)
    before = env._observe().copy()
    a = np.tile([2.0, 90.0, 0, 0, 0, 0.5, 0.5], (3, 1))
    a[2, 3] = np.nan
    with pytest.raises(ValueError, match="table 2: action a is NaN"):
        env.step(a)
    assert np.array_equal(env._observe(), before)
    with pytest.raises(ValueError, match="expected \\(3, 7\\)"):
        env.step(np.zeros((3, 6)))
    # out of bounds: clipped and played
    env.step(np.tile([1e9, -720.0, 400.0, 3.0, -3.0, -5.0, 99.0], (3, 1)))
    with pytest.raises(ValueError, match="0 tables"):
        PoolVectorEnv(0)
    with pytest.raises(TypeError, match="num_envs must be an integer"):
        PoolVectorEnv(2.5)
    for seed in ("7", 1.5):
        with pytest.raises(TypeError, match="seed must be an integer"):
            env.reset(seed=seed)
    with pytest.raises(ValueError, match="seed -1"):
        env.reset(seed=-1)
    with pytest.raises(ValueError, match="game 'snooker'"):
        PoolVectorEnv(1, game="snooker")
    with pytest.raises(ValueError, match="noise \"bogus\""):
        PoolVectorEnv(1, noise="bogus")
    with pytest.raises(ValueError, match="unknown key 'bonus'"):
        PoolVectorEnv(1, rewards={"bonus": 1.0})
    with pytest.raises(ValueError, match="opponent 'shark'"):
        PoolVectorEnv(1, opponent="shark")
    with pytest.raises(ValueError, match="no opponent"):
        PoolVectorEnv(1, game="drill", opponent="greedy")


def aimed_drill(obs: np.ndarray, v0: float) -> np.ndarray:
    """Straight at the 9 (a full hit) from the drill's observations."""
    dx, dy = obs[:, 4] - obs[:, 0], obs[:, 5] - obs[:, 1]
    phi = np.degrees(np.arctan2(dy, dx)) % 360
    n = len(obs)
    return np.stack([np.full(n, v0), phi, np.zeros(n), np.zeros(n), np.zeros(n), obs[:, 0], obs[:, 1]], axis=1)


def test_the_gpu_gives_the_cpus_observations_and_rewards():
    """The drill and 8-ball from the rack, step after step: on Vulkan (the event loop as
    exact SPIR-V, docs/gpu.md "Bit for bit with the CPU"; CI's lavapipe) the GPU's
    observations, rewards and infos are the CPU's bit for bit, racks included (which are
    chaotic: a nano-degree of aim moves balls by metres within three shots, docs/rl.md).
    Elsewhere the drill's verdicts and rewards are the CPU's and its positions agree to
    1e-6 m, and of the rack only the break is compared."""
    kwargs = dict(game="drill", drill_balls=3, noise="club", max_shots=4)
    try:
        gpu = PoolVectorEnv(16, backend="gpu", **kwargs)
    except RuntimeError as e:
        if os.environ.get("KISSTIME_REQUIRE_GPU") == "1":
            pytest.fail(f"KISSTIME_REQUIRE_GPU=1 but no usable GPU: {e}")
        pytest.skip(f"no usable GPU: {e}")
    exact = "Vulkan" in gpu.backend and os.environ.get("KISSTIME_GPU_EXACT", "1") != "0"
    cpu = PoolVectorEnv(16, **kwargs)
    oc, og = cpu.reset(seed=3)[0], gpu.reset(seed=3)[0]
    assert oc.tobytes() == og.tobytes()
    for _ in range(6):
        a = aimed_drill(oc, 1.2)
        out_c, out_g = cpu.step(a), gpu.step(a)
        oc, og = out_c[0], out_g[0]
        if exact:
            assert oc.tobytes() == og.tobytes()
        else:
            np.testing.assert_allclose(oc, og, atol=1e-6)
        for x, y in zip(out_c[1:4], out_g[1:4]):
            assert np.array_equal(x, y)
        for key in ("fouled", "potted", "won", "reset"):
            assert np.array_equal(out_c[4][key], out_g[4][key]), key
    # 8-ball from the rack: the break, then (exact) a game's worth of noisy shots
    cpu = PoolVectorEnv(8, game="8-ball", noise="club")
    gpu = PoolVectorEnv(8, game="8-ball", noise="club", backend="gpu")
    cpu.reset(seed=1), gpu.reset(seed=1)
    brk = np.tile([7.5, 90.0, 0.0, 0.0, 0.0, 0.0, 0.0], (8, 1))
    out_c, out_g = cpu.step(brk), gpu.step(brk)
    if not exact:
        np.testing.assert_allclose(out_c[0], out_g[0], atol=1e-6)
        assert np.array_equal(out_c[1], out_g[1])
        return
    rng = np.random.default_rng(5)
    for _ in range(8):
        assert out_c[0].tobytes() == out_g[0].tobytes()
        for x, y in zip(out_c[1:4], out_g[1:4]):
            assert np.array_equal(x, y)
        a = np.column_stack(
            [rng.uniform(1.0, 4.0, 8), rng.uniform(0.0, 360.0, 8), np.zeros((8, 3)), np.full((8, 2), 0.5)]
        )
        out_c, out_g = cpu.step(a), gpu.step(a)
    assert out_c[0].tobytes() == out_g[0].tobytes()


def test_the_training_example_runs_shortened(tmp_path):
    need("stable_baselines3")
    need("matplotlib")
    png = tmp_path / "curve.png"
    done = subprocess.run(
        [sys.executable, str(ROOT / "examples" / "rl_drill.py"), "--steps", "512", "--envs", "64", "--out", str(png)],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert done.returncode == 0, done.stderr
    assert png.stat().st_size > 1000
    assert "mean reward" in done.stdout


def test_the_pettingzoo_aec_environment_passes_pettingzoos_api_test():
    need("pettingzoo")
    from pettingzoo.test import api_test

    from kisstime.pettingzoo import PoolAECEnv

    env = PoolAECEnv(game="9-ball", max_shots=12)
    api_test(env, num_cycles=40)
    # turns follow the rules: a player who pots shoots again
    env.reset(seed=2)
    turns = []
    for agent in env.agent_iter(max_iter=30):
        obs, reward, term, trunc, info = env.last()
        if term or trunc:
            env.step(None)
            continue
        turns.append((agent, int(obs[-2])))
        env.step(env.action_space(agent).sample())
    assert all(agent == f"player_{seat}" for agent, seat in turns)
    with pytest.raises(ValueError, match="two players"):
        PoolAECEnv(game="drill")
