"""The Python functions on the GPU event loop (``backend="gpu"`` / ``"auto"``): a study
gives the CPU's samples (f64; f32 is refused), ``simulate`` runs whole shots there, and
``auto`` without a usable GPU warns and gives the CPU's arrays bit for bit.

Without a GPU (no Vulkan driver) the GPU tests skip with the reason; with
``KISSTIME_REQUIRE_GPU=1`` (CI, on Mesa's lavapipe) a missing GPU fails them."""

from __future__ import annotations

import os
import pathlib
import warnings

import numpy as np
import pytest

import kisstime
from arrays import balls_array, strike_columns

ROOT = pathlib.Path(__file__).resolve().parents[2]
DATA = ROOT / "data"
SCENARIO = DATA / "studies" / "dev_scenario.json"


def strikes(n: int) -> np.ndarray:
    return np.genfromtxt(DATA / "studies" / "dev_strikes.csv", delimiter=",", names=True)[:n]


def need_gpu(precision: str = "f64") -> None:
    """Skips (or fails, with KISSTIME_REQUIRE_GPU=1) when no GPU runs the event loop."""
    try:
        kisstime.shot_study(SCENARIO, strikes=strikes(1), backend="gpu", precision=precision)
    except RuntimeError as e:
        if os.environ.get("KISSTIME_REQUIRE_GPU") == "1":
            pytest.fail(f"KISSTIME_REQUIRE_GPU=1 but no usable GPU: {e}")
        pytest.skip(f"no usable GPU: {e}")


def break_example() -> tuple[np.ndarray, dict]:
    return (
        balls_array(ROOT / "examples" / "break.csv"),
        strike_columns(ROOT / "examples" / "break_strike.csv"),
    )


def test_a_study_on_the_gpu_gives_the_cpus_samples_in_f64_and_refuses_f32():
    need_gpu()
    rows = strikes(400)
    cpu = kisstime.shot_study(SCENARIO, strikes=rows)
    gpu = kisstime.shot_study(SCENARIO, strikes=rows, backend="gpu", precision="f64", chunk=150)
    assert gpu.potted == cpu.potted
    assert np.array_equal(gpu.samples["first_contact"], cpu.samples["first_contact"])
    assert np.array_equal(gpu.samples["n_events"], cpu.samples["n_events"])
    assert np.allclose(gpu.samples["cue_x"], cpu.samples["cue_x"], rtol=0, atol=1e-6)
    assert np.allclose(gpu.samples["cue_y"], cpu.samples["cue_y"], rtol=0, atol=1e-6)
    for backend in ("gpu", "auto"):
        with pytest.raises(ValueError, match="f64 only"):
            kisstime.shot_study(SCENARIO, strikes=rows, backend=backend, precision="f32")
        with pytest.raises(ValueError, match="f64 only"):
            kisstime.simulate(*break_example(), backend=backend, precision="f32")


def test_calls_reuse_one_engine_a_backend_until_released():
    """Every call (a study's every chunk) takes the idle engine opened for its backend,
    precision and environment instead of opening a GPU again; ``release_engines`` closes
    them; a changed environment (another adapter asked for) opens another; the results
    are the same whether the engine was new or reused."""
    need_gpu()
    kisstime.release_engines()
    rows = strikes(120)
    first = kisstime.shot_study(SCENARIO, strikes=rows, backend="gpu", chunk=40)
    again = kisstime.shot_study(SCENARIO, strikes=rows, backend="gpu", chunk=40)
    arr, strike = break_example()
    kisstime.simulate(arr, strike, backend="gpu", events=False)
    # six chunks and a simulate, one after another: one GPU engine, reused
    assert kisstime.release_engines() == 1
    assert kisstime.release_engines() == 0
    # the collision kernels' engines likewise, apart
    pairs = [kisstime.pair_times(arr, backend="gpu", precision="f64") for _ in range(2)]
    assert pairs[0].tobytes() == pairs[1].tobytes()
    assert len(kisstime.pair_times(arr)) == len(pairs[0])
    assert kisstime.release_engines() == 2  # the GPU's and the CPU's
    assert again.potted == first.potted
    assert again.samples.tobytes() == first.samples.tobytes()
    fresh = kisstime.shot_study(SCENARIO, strikes=rows, backend="gpu", chunk=120)
    assert fresh.samples.tobytes() == first.samples.tobytes()
    kisstime.shot_study(SCENARIO, strikes=rows[:5])
    assert kisstime.release_engines() == 2  # the GPU's and the CPU's
    mp = pytest.MonkeyPatch()
    try:
        kisstime.shot_study(SCENARIO, strikes=rows[:5], backend="gpu")
        mp.setenv("WGPU_ADAPTER_NAME", "no-such-adapter-anywhere")
        with pytest.raises(RuntimeError, match="no-such-adapter-anywhere"):
            kisstime.shot_study(SCENARIO, strikes=rows[:5], backend="gpu")
    finally:
        mp.undo()
    # the failed call kept nothing; the first engine is still there
    assert kisstime.release_engines() == 1


def test_simulate_runs_whole_shots_on_the_gpu():
    need_gpu()
    arr, strike = break_example()
    cpu = kisstime.simulate(arr, strike)
    gpu = kisstime.simulate(arr, strike, backend="gpu")
    assert gpu.final.dtype == cpu.final.dtype and gpu.final.shape == cpu.final.shape
    assert gpu.events.dtype == cpu.events.dtype
    assert gpu.outcomes["cut"][0] == 0 and gpu.outcomes["events"][0] > 50
    # the first events of a break are the CPU's (chaos parts them late)
    n = 20
    assert np.array_equal(gpu.events["type"][:n], cpu.events["type"][:n])
    assert np.allclose(gpu.events["t"][:n], cpu.events["t"][:n], rtol=0, atol=1e-9)
    quiet = kisstime.simulate(arr, strike, backend="gpu", events=False)
    assert quiet.events is None and np.array_equal(quiet.final, gpu.final)


def test_auto_without_a_gpu_warns_and_gives_the_cpus_arrays(monkeypatch):
    arr, strike = break_example()
    cpu = kisstime.simulate(arr, strike)
    monkeypatch.setenv("WGPU_ADAPTER_NAME", "no-such-adapter-anywhere")
    with pytest.warns(RuntimeWarning, match="simulating on the CPU"):
        auto = kisstime.simulate(arr, strike, backend="auto")
    assert auto.events.tobytes() == cpu.events.tobytes()
    assert auto.final.tobytes() == cpu.final.tobytes()
    with pytest.warns(RuntimeWarning, match="no-such-adapter-anywhere"):
        study = kisstime.shot_study(SCENARIO, strikes=strikes(50), backend="auto")
    assert study.potted == kisstime.shot_study(SCENARIO, strikes=strikes(50)).potted
    with pytest.raises(RuntimeError, match="no-such-adapter-anywhere"):
        kisstime.simulate(arr, strike, backend="gpu")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(ValueError, match="backend"):
            kisstime.simulate(arr, strike, backend="tpu")
        with pytest.raises(ValueError, match="f64 only"):
            kisstime.shot_study(SCENARIO, strikes=strikes(5), precision="f32")


def test_mesa_runtime_dir_noise_does_not_reach_the_user():
    """Mesa's drivers print ``error: XDG_RUNTIME_DIR is invalid or not set`` when it is
    unset; the package sets a private one before opening a GPU, so a user sees none of it,
    and a CPU call leaves the variable alone."""
    need_gpu()
    import subprocess
    import sys

    env = {k: v for k, v in os.environ.items() if k != "XDG_RUNTIME_DIR"}
    code = (
        "import os, kisstime\n"
        "kisstime.shot_study(samples=50, backend='cpu')\n"
        "assert 'XDG_RUNTIME_DIR' not in os.environ, 'a CPU call set it'\n"
        "kisstime.shot_study(samples=50, backend='gpu')\n"
        "kisstime.shot_study(samples=50, backend='auto')\n"
        "print(os.environ['XDG_RUNTIME_DIR'])\n"
    )
    run = subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=600
    )
    assert run.returncode == 0, run.stderr
    assert "XDG_RUNTIME_DIR" not in run.stderr, run.stderr
    assert not any(line.startswith("error:") for line in run.stderr.splitlines()), run.stderr
    folder = run.stdout.strip()
    assert folder and not os.path.exists(folder), "the private folder is removed at exit"
