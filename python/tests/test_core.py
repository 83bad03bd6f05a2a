"""The Python package against the command line: the same input gives the same arrays,
bit for bit; structured and dict input; bad input raises with the CLI's message; the GIL
is released and Ctrl-C interrupts a long call."""

from __future__ import annotations

import _thread
import csv
import json
import os
import pathlib
import subprocess
import threading
import time

import numpy as np
import pytest

import kisstime
from arrays import balls_array, strike_columns

ROOT = pathlib.Path(__file__).resolve().parents[2]
DATA = ROOT / "data"


def cli() -> str:
    """The kisstime binary: $KISSTIME_BIN, else the one cargo built in target/."""
    env = os.environ.get("KISSTIME_BIN")
    if env:
        return env
    for profile in ("release", "debug"):
        exe = ROOT / "target" / profile / "kisstime"
        if exe.exists():
            return str(exe)
    pytest.fail("no kisstime binary: build it with cargo build, or set KISSTIME_BIN")


def run(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([cli(), *args], capture_output=True, text=True)


@pytest.fixture(scope="module")
def workload(tmp_path_factory) -> tuple[pathlib.Path, np.ndarray]:
    """A generated midshot batch as the CLI writes it (.npy), and as loaded."""
    d = tmp_path_factory.mktemp("w")
    path = d / "balls.npy"
    out = run("gen", "--tables", "300", "--seed", "7", "-o", str(path))
    assert out.returncode == 0, out.stderr
    return path, np.load(path)


def same(a: np.ndarray, b: np.ndarray) -> bool:
    """Same dtype, shape and bytes (NaN and -0.0 included)."""
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


def test_pair_times_and_next_collisions_match_the_cli(workload, tmp_path):
    path, balls = workload
    for cmd, fn in (("pairs", kisstime.pair_times), ("next", kisstime.next_collisions)):
        out = tmp_path / f"{cmd}.npy"
        r = run(cmd, str(path), "-o", str(out))
        assert r.returncode == 0, r.stderr
        ours = fn(balls)
        assert same(ours, np.load(out)), cmd
        assert ours.dtype == (kisstime.PAIR_DTYPE if cmd == "pairs" else kisstime.NEXT_DTYPE)
    # a dict of columns, rows shuffled: the same answers (the batch sorts by ids)
    rng = np.random.default_rng(1)
    shuffled = balls[rng.permutation(len(balls))]
    cols = {name: shuffled[name].copy() for name in balls.dtype.names}
    assert same(kisstime.next_collisions(cols), kisstime.next_collisions(balls))
    assert same(kisstime.pair_times(cols), kisstime.pair_times(balls))


def test_simulate_matches_the_cli_on_the_break_example(tmp_path):
    balls_csv = ROOT / "examples" / "break.csv"
    strikes_csv = ROOT / "examples" / "break_strike.csv"
    ev, fin, oc = (tmp_path / n for n in ("e.npy", "f.npy", "o.npy"))
    r = run(
        "simulate",
        str(balls_csv),
        "--strikes",
        str(strikes_csv),
        "-o",
        str(ev),
        "--final",
        str(fin),
        "--outcomes",
        str(oc),
    )
    assert r.returncode == 0, r.stderr
    # the same input as arrays: the CLI's own .npy of the balls, the strikes as a dict
    npy_in = tmp_path / "in.npy"
    arr = balls_array(balls_csv)
    np.save(npy_in, arr)
    strike_cols = strike_columns(strikes_csv)
    res = kisstime.simulate(arr, strike_cols)
    assert same(res.events, np.load(ev))
    assert same(res.final, np.load(fin))
    assert same(res.outcomes, np.load(oc))
    assert res.outcomes["cut"][0] == 0 and res.outcomes["events"][0] > 50
    # events=False: no events, the same final states
    quiet = kisstime.simulate(arr, strike_cols, events=False)
    assert quiet.events is None and same(quiet.final, res.final)
    assert npy_in.exists()


@pytest.mark.parametrize(
    "flag, value",
    [("max-time", "0"), ("max-time", "-1.5"), ("max-time", "nan"), ("max-events", "0")],
)
def test_bad_limits_give_the_clis_message(flag, value):
    """One rule for the limits (Limits::new): the CLI and Python refuse the same value
    with the same message, for whole shots and for studies."""
    balls_csv = ROOT / "examples" / "break.csv"
    strikes_csv = ROOT / "examples" / "break_strike.csv"
    r = run("simulate", str(balls_csv), "--strikes", str(strikes_csv), f"--{flag}", value)
    assert r.returncode == 2, r.stderr
    message = r.stderr.strip().splitlines()[-1].split("error: ", 1)[-1]
    assert flag.replace("-", "_") in message, message
    kw = {flag.replace("-", "_"): float(value) if flag == "max-time" else int(value)}
    with pytest.raises(ValueError) as raised:
        kisstime.simulate(balls_array(balls_csv), strike_columns(strikes_csv), **kw)
    assert str(raised.value) == message
    r = run("shots", "--samples", "10", f"--{flag}", value)
    assert r.returncode == 2, r.stderr
    assert r.stderr.strip().splitlines()[-1].split("error: ", 1)[-1] == message
    with pytest.raises(ValueError) as raised:
        kisstime.shot_study(samples=10, **kw)
    assert str(raised.value) == message


def test_no_time_limit_is_inf():
    balls_csv = ROOT / "examples" / "break.csv"
    strikes_csv = ROOT / "examples" / "break_strike.csv"
    arr, cols = balls_array(balls_csv), strike_columns(strikes_csv)
    assert same(
        kisstime.simulate(arr, cols, max_time=float("inf")).final,
        kisstime.simulate(arr, cols).final,
    )


def test_shot_study_matches_the_cli(tmp_path):
    out = tmp_path / "s.csv"
    r = run("shots", "--samples", "3000", "--seed", "5", "-o", str(out), "--json")
    assert r.returncode == 0, r.stderr
    cli_summary = json.loads(r.stdout)
    study = kisstime.shot_study(samples=3000, seed=5, chunk=1000)
    # the summary: the CLI's, less the run's description
    for key in ("seed", "strikes", "noise", "seconds", "samples_per_s", "threads", "backend"):
        cli_summary.pop(key)
    assert study.summary == cli_summary
    rows = list(csv.DictReader(open(out)))
    assert len(rows) == len(study.samples) == 3000
    results = ["pot", "pot+scratch", "scratch", "miss"]
    for row, s, potted in zip(rows, study.samples, study.potted):
        assert int(row["sample"]) == s["sample"]
        for name in ("V0", "phi", "theta", "a", "b", "first_t", "cut_angle", "cue_x", "cue_y", "duration"):
            text = row[name]
            want = float(text) if text else float("nan")
            got = float(s[name])
            assert (np.isnan(want) and np.isnan(got)) or want == got, (name, row, s)
        assert row["result"] == results[s["result"]]
        assert int(row["n_events"]) == s["n_events"]
        assert row["potted"] == potted
    # chunking does not change a thing
    again = kisstime.shot_study(samples=3000, seed=5, chunk=777)
    assert same(again.samples, study.samples) and again.summary == study.summary


def test_shot_study_scenarios_strikes_and_modes():
    scen = DATA / "studies" / "dev_scenario.json"
    strikes = np.genfromtxt(DATA / "studies" / "dev_strikes.csv", delimiter=",", names=True)[:300]
    study = kisstime.shot_study(scen, strikes=strikes)
    ref = list(csv.DictReader(open(DATA / "studies" / "dev_full.csv")))[:300]
    assert [r["potted"] for r in ref] == study.potted
    assert list(study.samples["sample"]) == [int(r["sample"]) for r in ref]
    # a dict scenario: the built-in study's TOML as a dict gives the built-in study
    import tomllib

    builtin = tomllib.loads((ROOT / "examples" / "study.toml").read_text())
    a = kisstime.shot_study(builtin, samples=500)
    b = kisstime.shot_study(samples=500)
    assert same(a.samples, b.samples)
    # and the same sections as keyword arguments
    c = kisstime.shot_study(kisstime.scenario(**builtin), samples=500)
    assert same(c.samples, b.samples)
    with pytest.raises(ValueError, match="not both"):
        kisstime.scenario(builtin, balls=[])
    # first contact only: the same first contacts, no outcome
    fc = kisstime.shot_study(samples=500, until="first-contact")
    assert np.array_equal(fc.samples["first_t"], b.samples["first_t"])
    assert (fc.samples["result"] == -1).all() and "outcome" not in fc.summary
    # noise 0: every sample the intended shot
    z = kisstime.shot_study(samples=20, noise=0)
    assert len(set(z.samples["cue_x"])) == 1
    # the study saved as .npy reads back
    path = pathlib.Path(os.environ.get("TMPDIR", "/tmp")) / f"kt-{os.getpid()}.npy"
    z.save(path)
    assert same(np.load(path), z.samples)
    path.unlink()


def test_physics_matches_the_cli_and_bad_keys_give_its_message(tmp_path):
    import tomllib

    balls_csv = ROOT / "examples" / "break.csv"
    strikes_csv = ROOT / "examples" / "break_strike.csv"
    physics_toml = DATA / "physics" / "physics.toml"
    fin = tmp_path / "f.npy"
    r = run("simulate", str(balls_csv), "--strikes", str(strikes_csv), "--final", str(fin),
            "--physics", str(physics_toml))
    assert r.returncode == 0, r.stderr
    arr, cols = balls_array(balls_csv), strike_columns(strikes_csv)
    # a TOML file, and the same keys as a dict: the CLI's final states, bit for bit
    from_file = kisstime.simulate(arr, cols, physics=physics_toml, events=False)
    assert same(from_file.final, np.load(fin))
    as_dict = tomllib.loads(physics_toml.read_text())
    assert set(as_dict) <= set(kisstime.PHYSICS_KEYS)
    from_dict = kisstime.simulate(arr, cols, physics=as_dict, events=False)
    assert same(from_dict.final, from_file.final)
    # the parameters matter; an empty dict is pooltool's defaults, bit for bit
    default = kisstime.simulate(arr, cols, events=False)
    assert not same(default.final, from_dict.final)
    assert same(kisstime.simulate(arr, cols, physics={}, events=False).final, default.final)
    cue = kisstime.simulate(arr, cols, physics={"cue": {"M": 0.4}}, events=False)
    assert not same(cue.final, default.final)

    # bad keys and values: the CLI's message (a dict is named "physics", without a line)
    for text, key, needle in [
        ("u_s = 0.2\nradius = 0.03\n", "radius", "`R`"),
        ("u_s = 0.2\nmu_sp = 0.0127\n", "mu_sp", "`u_sp_proportionality`"),
        ("u_s = 0.2\ne_c = 1.5\n", "e_c", "(0, 1]"),
        ("u_s = 0.2\nfoo = 1\n", "foo", "u_sp_proportionality"),
    ]:
        bad = tmp_path / "bad.toml"
        bad.write_text(text)
        r = run("simulate", str(balls_csv), "--physics", str(bad))
        assert r.returncode == 2, r.stderr
        cli_msg = r.stderr.strip().removeprefix("kisstime: error: ")
        assert f"`{key}`" in cli_msg and needle in cli_msg, cli_msg
        with pytest.raises(ValueError) as e:
            kisstime.simulate(arr, cols, physics=bad)
        assert str(e.value) == cli_msg
        with pytest.raises(ValueError) as e:
            kisstime.simulate(arr, cols, physics=tomllib.loads(text))
        assert str(e.value) == cli_msg.replace(f"{bad}, line 2", "physics")
    with pytest.raises(ValueError, match="key `g` is NaN"):
        kisstime.simulate(arr, cols, physics={"g": float("nan")})
    with pytest.raises(ValueError, match="key `cue.M` is a string"):
        kisstime.simulate(arr, cols, physics={"cue": {"M": "heavy"}})
    with pytest.raises(TypeError, match="physics"):
        kisstime.simulate(arr, cols, physics=3)

    # shot studies: physics= replaces the scenario's [physics], as shots --physics does
    r = run("shots", "--samples", "300", "--json", "--physics", str(physics_toml))
    assert r.returncode == 0, r.stderr
    cli_summary = json.loads(r.stdout)
    study = kisstime.shot_study(samples=300, physics=as_dict)
    for key in ("seed", "strikes", "noise", "seconds", "samples_per_s", "threads", "backend"):
        cli_summary.pop(key)
    assert study.summary == cli_summary
    builtin = tomllib.loads((ROOT / "examples" / "study.toml").read_text())
    builtin["physics"] = as_dict
    assert same(kisstime.shot_study(builtin, samples=300).samples, study.samples)
    assert not same(kisstime.shot_study(samples=300).samples, study.samples)
    with pytest.raises(ValueError, match="R = 0.5 from physics"):
        kisstime.shot_study(samples=3, physics={"R": 0.5})


def test_bad_input_raises_with_the_clis_message(workload, tmp_path):
    _, balls = workload
    bad = balls.copy()
    bad["x"][5] = np.nan
    path = tmp_path / "bad.npy"
    np.save(path, bad)
    r = run("next", str(path))
    assert r.returncode == 2
    cli_msg = r.stderr.strip().removeprefix("kisstime: error: ")
    with pytest.raises(ValueError) as e:
        kisstime.next_collisions(bad)
    assert str(e.value) == cli_msg.replace(str(path), "balls")
    with pytest.raises(ValueError, match="no column 'wz'"):
        kisstime.pair_times({n: balls[n] for n in balls.dtype.names if n != "wz"})
    with pytest.raises(ValueError, match="backend"):
        kisstime.pair_times(balls, backend="tpu")
    with pytest.raises(ValueError, match="strike: a² \\+ b² > 1"):
        kisstime.shot_study(
            strikes={"sample": [0], "V0": [1.0], "phi": [0.0], "theta": [0.0], "a": [0.9], "b": [0.9]}
        )
    with pytest.raises(ValueError, match="shot.v0"):
        kisstime.shot_study({"balls": [{"id": 0, "x": 0.5, "y": 0.5}, {"id": 1, "x": 0.5, "y": 1.5}],
                             "shot": {"cue_ball": 0, "object_ball": 1, "v0": -1, "phi": 90,
                                      "theta": 0, "a": 0, "b": 0}}, samples=5)
    with pytest.raises(OSError):
        kisstime.shot_study("/nonexistent/study.toml")


def test_long_calls_release_the_gil_and_stop_on_ctrl_c():
    ticks = []
    stop = threading.Event()

    def tick():
        while not stop.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.005)

    t = threading.Thread(target=tick)
    t.start()
    start = time.perf_counter()
    kisstime.shot_study(samples=60_000, chunk=60_000)  # one call into the extension
    end = time.perf_counter()
    stop.set()
    t.join()
    during = [x for x in ticks if start < x < end]
    # the thread kept running while the study ran (it would get no tick with the GIL held)
    assert end - start > 0.1 and len(during) >= 5, (end - start, len(during))
    # Ctrl-C (SIGINT, as the terminal sends it) stops a long study between chunks
    threading.Timer(0.3, _thread.interrupt_main).start()
    began = time.perf_counter()
    with pytest.raises(KeyboardInterrupt):
        kisstime.shot_study(samples=5_000_000, chunk=4096)
    assert time.perf_counter() - began < 10


def test_physics_noise_matches_the_cli_and_varies_per_sample(tmp_path):
    """shot_study(physics_noise=...) is `kisstime shots --physics-noise`: the same summary,
    the same strikes as without it, and other outcomes; a bad key raises the CLI's message."""
    out = tmp_path / "s.csv"
    r = run(
        "shots", "--samples", "2000", "--seed", "5", "--json", "-o", str(out),
        "--physics-noise", "u_r=0.1", "--physics-noise", "e_c=[0.8,0.9]",
    )
    assert r.returncode == 0, r.stderr
    cli_summary = json.loads(r.stdout)
    assert cli_summary["noise"]["physics"]["u_r"] == [-0.1, 0.1]
    study = kisstime.shot_study(
        samples=2000, seed=5, chunk=700, physics_noise={"u_r": 0.1, "e_c": [0.8, 0.9]}
    )
    for key in ("seed", "strikes", "noise", "seconds", "samples_per_s", "threads", "backend"):
        cli_summary.pop(key)
    assert study.summary == cli_summary
    plain = kisstime.shot_study(samples=2000, seed=5, chunk=700)
    for f in ("V0", "phi", "theta", "a", "b"):
        assert np.array_equal(study.samples[f], plain.samples[f]), f
    moved = np.count_nonzero(study.samples["cue_x"] != plain.samples["cue_x"])
    assert moved > 1000, moved
    r = run("shots", "--samples", "10", "--physics-noise", "R=0.1")
    assert r.returncode == 2
    with pytest.raises(ValueError, match="noise.physics.R"):
        kisstime.shot_study(samples=10, physics_noise={"R": 0.1})


def test_per_table_physics_is_each_table_alone():
    """physics={"table": ids, "u_r": array, ...}: each table is simulated with its own
    parameters, as it is alone with a dict of its values; a table without an entry
    raises naming it."""
    balls = balls_array(ROOT / "examples" / "break.csv")
    strikes = strike_columns(ROOT / "examples" / "break_strike.csv")
    n = 4
    tables = np.concatenate([np.where(balls["table"] == 0, k, 0) for k in range(n)])
    many = np.concatenate([balls] * n)
    many["table"] = tables
    s = {k: np.concatenate([np.asarray(v)] * n) for k, v in strikes.items()}
    s["table"] = np.arange(n)
    u_r = np.array([0.008, 0.01, 0.012, 0.011])
    m = np.array([0.5, 0.567, 0.6, 0.7])
    per = kisstime.simulate(
        many, s, events=False, physics={"table": np.arange(n), "u_r": u_r, "e_c": 0.9, "cue": {"M": m}}
    )
    for k in range(n):
        alone = kisstime.simulate(
            balls, strikes, events=False, physics={"u_r": u_r[k], "e_c": 0.9, "cue": {"M": m[k]}}
        )
        mine = per.final[per.final["table"] == k].copy()
        mine["table"] = 0
        assert same(mine, alone.final), k
    assert not same(per.final[per.final["table"] == 0], per.final[per.final["table"] == 2])
    with pytest.raises(ValueError, match="table 3"):
        kisstime.simulate(many, s, physics={"table": np.arange(3), "u_r": u_r[:3]})


def test_a_dict_scenario_error_names_the_key_not_a_line():
    """A scenario given as a dict has no lines: its errors name the key and the ball only."""
    import tomllib

    with open(ROOT / "examples" / "study.toml", "rb") as f:
        scen = tomllib.load(f)
    scen["shot"]["v0"] = "fast"
    with pytest.raises(ValueError) as e:
        kisstime.shot_study(scen, samples=10)
    assert str(e.value).startswith("scenario dict: key `v0`"), str(e.value)
    assert "line" not in str(e.value)
    scen["shot"]["v0"] = 1.0
    scen["balls"][1]["x"] = 9.0
    with pytest.raises(ValueError, match=r"scenario dict: key `balls\[1\]`.*off the table"):
        kisstime.shot_study(scen, samples=10)
