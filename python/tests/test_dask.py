"""kisstime.dask: a shot study on a local Dask cluster equals the single-process study.

The clusters are real (worker processes under nannies), so these tests also check that the
tasks pickle, that workers import kisstime, and that a worker killed mid-run is replaced
and its chunks re-run without changing the result.
"""

from __future__ import annotations

import logging
import os
import signal
import threading
import time
from pathlib import Path

import distributed
import numpy as np
import pytest

import kisstime
import kisstime.dask

# the reference sets live in the repository's data/ (as for the crate's tests: CARGO_MANIFEST_DIR/data).
STUDIES = Path(__file__).resolve().parents[2] / "data" / "studies"
DEV_SCENARIO = STUDIES / "dev_scenario.json"
DEV_STRIKES = STUDIES / "dev_strikes.csv"
STUDY_TOML = Path(__file__).resolve().parents[2] / "examples" / "study.toml"


def _cluster() -> distributed.LocalCluster:
    return distributed.LocalCluster(
        n_workers=2,
        threads_per_worker=1,
        processes=True,
        dashboard_address=None,  # no dashboard; the HTTP server on a free port:
        scheduler_kwargs={"dashboard_address": ":0"},
        silence_logs=logging.ERROR,
    )


@pytest.fixture(scope="module")
def client():
    with _cluster() as cluster, distributed.Client(cluster) as client:
        yield client


def assert_same_study(got: kisstime.Study, want: kisstime.Study) -> None:
    """Equal summaries (repr: exact floats, NaN equal to NaN), rows bit for bit, potted."""
    assert repr(got.summary) == repr(want.summary)
    assert got.samples.dtype == want.samples.dtype
    assert got.samples.shape == want.samples.shape
    assert got.samples.tobytes() == want.samples.tobytes()
    assert list(got.potted) == list(want.potted)


@pytest.fixture(scope="module")
def builtin_3000() -> kisstime.Study:
    return kisstime.shot_study(samples=3000)


@pytest.mark.parametrize("chunk", [700, 3000])
def test_builtin_study_equals_single_process(client, builtin_3000, chunk):
    study = kisstime.dask.shot_study(client, samples=3000, chunk=chunk)
    assert study.summary["samples"] == 3000
    assert study.samples.shape == (3000,)
    assert np.array_equal(study.samples["sample"], np.arange(3000))
    assert_same_study(study, builtin_3000)


def test_options_reach_the_workers(client):
    options = dict(seed=7, noise=0.5, until="first-contact", max_events=50, max_time=2.0)
    want = kisstime.shot_study(samples=2000, **options)
    assert_same_study(kisstime.dask.shot_study(client, samples=2000, chunk=600, **options), want)


def test_default_client_and_a_scenario_without_its_file(client, tmp_path):
    copy = tmp_path / "study.toml"
    copy.write_text(STUDY_TOML.read_text(encoding="utf-8"), encoding="utf-8")
    sc = kisstime.scenario(copy)
    want = kisstime.shot_study(copy, samples=1500)
    copy.unlink()  # the tasks carry the scenario's text
    got = kisstime.dask.shot_study(None, sc, 1500, chunk=400)  # None: the default client
    assert_same_study(got, want)


def _dev_strikes(rows: int) -> np.ndarray:
    strikes = np.genfromtxt(DEV_STRIKES, delimiter=",", names=True, dtype=None, max_rows=rows)
    assert strikes.shape == (rows,)
    return strikes


@pytest.mark.skipif(
    not (DEV_SCENARIO.is_file() and DEV_STRIKES.is_file()), reason=f"no {STUDIES}"
)
def test_given_strikes_equal_single_process(client):
    strikes = _dev_strikes(500)
    want = kisstime.shot_study(str(DEV_SCENARIO), strikes=strikes)
    got = kisstime.dask.shot_study(client, DEV_SCENARIO, strikes=strikes, chunk=130)
    assert got.summary["samples"] == 500
    assert np.array_equal(got.samples["sample"], strikes["sample"])
    assert_same_study(got, want)
    # The columns as a dict of arrays give the same study.
    columns = {name: strikes[name] for name in strikes.dtype.names}
    assert_same_study(
        kisstime.dask.shot_study(client, DEV_SCENARIO, strikes=columns, chunk=200), want
    )


def test_npy_writes_the_samples(client, builtin_3000, tmp_path):
    path = tmp_path / "study.npy"
    study = kisstime.dask.shot_study(client, samples=3000, chunk=1000, npy=path)
    back = np.load(path)
    assert back.dtype == study.samples.dtype
    assert back.tobytes() == study.samples.tobytes()
    assert back.tobytes() == builtin_3000.samples.tobytes()


@pytest.mark.parametrize(
    "kwargs",
    [
        {"samples": 0},
        {"samples": -5},
        {"samples": 2.5},
        {"chunk": 0},
        {"chunk": -1},
        {"chunk": 1.5},
        {"retries": -1},
        {"until": "nowhere"},
        {"max_events": 0},
        {"max_time": -1.0},
        {"noise": -1.0},
        {"scenario": {"balls": "not a list"}},
        {"strikes": np.zeros(3, dtype=[("sample", "i8"), ("V0", "f8")])},
        {"strikes": [1, 2, 3]},
    ],
)
def test_bad_arguments_raise_value_error(client, kwargs):
    before = client.run_on_scheduler(_chunk_states)
    with pytest.raises(ValueError):
        kisstime.dask.shot_study(client, **kwargs)
    # ... on the client, before any task was sent
    assert client.run_on_scheduler(_chunk_states) == before


def _chunk_states(dask_scheduler) -> dict[str, int]:
    """On the scheduler: how many times kisstime chunk tasks entered each state, ever."""
    prefix = dask_scheduler.task_prefixes.get("kisstime-chunk")
    return {} if prefix is None else dict(prefix.state_counts)


def test_no_strikes_are_refused_as_by_one_process(client):
    # as `kisstime shots --strikes` refuses a file without rows
    strikes = np.zeros(0, dtype=kisstime.SAMPLE_STRIKE_DTYPE)
    with pytest.raises(ValueError, match="no strikes") as one:
        kisstime.shot_study(strikes=strikes)
    with pytest.raises(ValueError, match="no strikes") as many:
        kisstime.dask.shot_study(client, strikes=strikes)
    assert str(one.value) == str(many.value)


def _chunk_keys_by_worker(dask_scheduler) -> dict[str, tuple[int, int, int]]:
    """On the scheduler: each worker's (chunks held, chunks running, pid)."""
    counts = {}
    for address, ws in dask_scheduler.workers.items():
        held = [ts for ts in ws.has_what if str(ts.key).startswith("kisstime-chunk-")]
        running = [ts for ts in ws.processing if str(ts.key).startswith("kisstime-chunk-")]
        counts[address] = (len(held), len(running), ws.pid)
    return counts


def _worker_pids(dask_scheduler) -> list[int]:
    return [ws.pid for ws in dask_scheduler.workers.values()]


def test_worker_killed_mid_run_gives_the_same_study():
    samples, chunk = 100_000, 2_500  # 40 chunks of about 0.1 s each
    want = kisstime.shot_study(samples=samples)

    with _cluster() as cluster, distributed.Client(cluster) as client:
        killed: dict = {}
        errors: list[BaseException] = []
        done = threading.Event()

        def kill_one_worker() -> None:
            try:
                # Wait for the first finished chunk, then SIGKILL the worker holding it:
                # its finished chunks are lost with it and must be computed again.
                while not done.is_set():
                    counts = client.run_on_scheduler(_chunk_keys_by_worker)
                    holders = [(h, addr, pid) for addr, (h, _, pid) in counts.items() if h]
                    if holders:
                        held, address, pid = max(holders)
                        assert pid and pid > 0 and pid != os.getpid(), counts
                        killed.update(
                            address=address, pid=pid, held=held, counts=counts, at=time.time()
                        )
                        os.kill(pid, signal.SIGKILL)
                        return
                    time.sleep(0.005)
            except BaseException as exc:  # noqa: BLE001 - reported by the test
                errors.append(exc)

        killer = threading.Thread(target=kill_one_worker, daemon=True)
        killer.start()
        try:
            got = kisstime.dask.shot_study(client, samples=samples, chunk=chunk)
        finally:
            done.set()
            killer.join(timeout=30)
        assert not errors, errors
        assert killed, "no chunk finished before the study did"
        assert killed["held"] >= 1
        # The kill came mid-run: not every chunk had finished.
        finished = sum(h for h, _, _ in killed["counts"].values())
        assert finished < samples // chunk, killed
        # The lost chunks ran again: more chunk results than chunks.
        assert client.run_on_scheduler(_chunk_states)["memory"] > samples // chunk
        # The nanny replaced the worker.
        client.wait_for_workers(2, timeout=30)
        pids = client.run_on_scheduler(_worker_pids)
        assert len(pids) == 2 and killed["pid"] not in pids, (pids, killed)

    assert_same_study(got, want)
