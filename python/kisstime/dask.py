"""Shot studies on a Dask cluster: :func:`shot_study` with a ``dask.distributed`` client.

A shot study is one shot struck many times with noise, every strike simulated to rest
(or to the cue ball's first contact). Each sample's noise depends only on the seed and
the sample's index, so the study splits into independent chunks of samples. This module
sends one task per chunk to a Dask cluster, gathers the chunks' results in order and
merges them on the client::

    from dask.distributed import Client
    import kisstime.dask

    client = Client("tcp://scheduler-host:8786")
    study = kisstime.dask.shot_study(client, "study.toml", samples=10_000_000, chunk=100_000)
    print(study.summary["outcome"]["pot"])

**The result is identical to one process's.** Every task calls the same function that
:func:`kisstime.shot_study` calls for its chunks (``kisstime._study_chunk``), on the same
sample ranges, and the client merges the chunks in sample order with the same
``kisstime._study_merge``. The :class:`~kisstime.Study` (its ``summary``, its per-sample
``samples`` array bit for bit and ``potted``) is therefore the same as
``kisstime.shot_study(scenario, samples=...)`` gives in one process, whatever the chunk
size, the number of workers, the order in which the tasks ran, and whether a task was run
again after a worker died.

**Failures.** When a worker dies, the scheduler runs its tasks again elsewhere, including
the finished chunks whose results lived only on that worker; a task is given up after it
was on ``distributed.scheduler.allowed-failures`` (default 3) workers that died. A task that
raises is retried ``retries`` times. The tasks are deterministic, so a re-run gives the
same bytes.

**Running on a real cluster.** Every worker needs kisstime installed (the same version
as the client): ``pip install ./python`` from a checkout of the repository (or the built
wheel) in the worker's environment, with ``pip install 'dask[distributed]'``. The scenario
travels with the tasks as text, so workers need none of the client's files, except a
table file that a TOML scenario names (``[table] kind = "table.json"``): each worker
reads that file itself, at the path it has on the client (a relative one is taken from the
study file's folder there).

* By hand: start a scheduler on one machine and a worker on each of the others::

      dask scheduler                                   # listens on tcp://<host>:8786
      dask worker tcp://<host>:8786 --nworkers 1 --nthreads 1

  (``dask-scheduler`` and ``dask-worker tcp://<host>:8786`` in older Dask releases), then
  ``Client("tcp://<host>:8786")`` on the client. A task runs its chunk's samples on all
  of the worker's cores (Rayon; ``RAYON_NUM_THREADS`` limits them), so one worker process
  per machine, with one thread, is enough.

* On a SLURM cluster, with `dask-jobqueue <https://jobqueue.dask.org>`_::

      from dask_jobqueue import SLURMCluster
      from dask.distributed import Client

      cluster = SLURMCluster(cores=8, memory="16GB", processes=1, walltime="01:00:00")
      cluster.scale(jobs=10)            # ten SLURM jobs (one worker each) of 8 cores
      client = Client(cluster)
      study = kisstime.dask.shot_study(client, "study.toml", samples=50_000_000,
                                       chunk=100_000)

  (``PBSCluster``, ``SGECluster`` and the others take the same arguments; the jobs run
  the Python of the client's environment unless ``python=`` says otherwise.)

* On one machine, ``distributed.LocalCluster()`` gives a cluster of local processes.

**Memory.** The client holds every chunk's result before the merge (about 200 bytes a
sample, then the 152-byte rows of ``Study.samples``), so size ``samples`` for the
client's memory. ``chunk`` is the size of one task: tens of thousands of samples keep
the scheduler's overhead small (a task of 10,000 samples to rest takes a few tenths of a
second on one core) and a lost worker's work short.
"""

from __future__ import annotations

import operator
import os
import uuid
from collections.abc import Mapping, Sequence
from typing import Any, Union

import numpy

try:
    import distributed
except ImportError as exc:  # pragma: no cover - exercised only without dask installed
    raise ImportError(
        "kisstime.dask needs Dask's distributed scheduler: pip install 'dask[distributed]'"
    ) from exc

import kisstime

__all__ = ["shot_study"]

#: What ``scenario`` may be: anything :func:`kisstime.scenario` accepts.
ScenarioLike = Union[kisstime.Scenario, str, "os.PathLike[str]", Mapping[str, Any], None]

_STRIKE_NUMBERS = ("V0", "phi", "theta", "a", "b")


def _run_chunk(
    scenario: kisstime.Scenario,
    first: int,
    n: int,
    strikes: Mapping[str, numpy.ndarray] | None,
    **options: Any,
) -> bytes:
    """One task: samples ``first .. first + n`` (or rows ``first .. first + n`` of
    ``strikes``), with :func:`kisstime.shot_study`'s ``options`` (``seed``, ``until``,
    ``noise``, ``max_events``, ``max_time``, ``backend``, ``precision``)."""
    if strikes is not None:
        # Arrays that arrive in a task's arguments can lie at unaligned addresses in the
        # message's buffer; the extension reads aligned contiguous columns only.
        strikes = {name: numpy.require(col, requirements="CA") for name, col in strikes.items()}
    return kisstime._study_chunk(scenario, first, n, strikes=strikes, **options)


def _count(name: str, value: Any, minimum: int) -> int:
    """``value`` as an int of at least ``minimum``; ValueError otherwise."""
    if isinstance(value, bool):
        raise ValueError(f"{name} must be an integer, not {value!r}")
    try:
        number = operator.index(value)
    except TypeError:
        raise ValueError(f"{name} must be an integer, not {value!r}") from None
    if number < minimum:
        raise ValueError(f"{name} must be at least {minimum}, not {number}")
    return number


def _strike_columns(strikes: Any) -> dict[str, numpy.ndarray]:
    """The six strike columns (as :func:`kisstime.shot_study` reads them), as a dict."""
    try:
        ids, numbers = kisstime._strike_columns(strikes)
    except TypeError:
        raise ValueError(
            "strikes: expected a structured array of kisstime.SAMPLE_STRIKE_DTYPE or a dict "
            f"of its columns, not {type(strikes).__name__}"
        ) from None
    columns = {"sample": ids, **dict(zip(_STRIKE_NUMBERS, numbers))}
    lengths = {len(column) for column in columns.values()}
    if len(lengths) != 1:
        raise ValueError(f"strikes: columns of different lengths {sorted(lengths)}")
    return columns


def shot_study(
    client: distributed.Client | None,
    scenario: ScenarioLike = None,
    samples: int = 100_000,
    *,
    chunk: int = 10_000,
    seed: int = 42,
    strikes: numpy.ndarray | Mapping[str, Any] | None = None,
    until: str = "rest",
    noise: float | None = None,
    max_events: int = 10_000,
    max_time: float = 600.0,
    npy: str | os.PathLike[str] | None = None,
    retries: int = 3,
    backend: str = "cpu",
    precision: str | None = None,
    physics: kisstime.PhysicsLike = None,
    physics_noise: Mapping[str, Any] | None = None,
) -> kisstime.Study:
    """A shot study run on a Dask cluster; the same :class:`~kisstime.Study` as one process gives.

    Splits the samples ``0 .. samples`` (or the rows of ``strikes``) into chunks of
    ``chunk``, runs one task per chunk on ``client``'s cluster, gathers the chunks' results
    in sample order and merges them here. The result equals
    ``kisstime.shot_study(scenario, samples=samples, seed=seed, ...)`` exactly (summary,
    per-sample rows bit for bit, potted balls), whatever ``chunk`` and the cluster.

    Parameters
    ----------
    client
        A ``distributed.Client`` (synchronous). ``None`` uses the current default client
        (``distributed.get_client()``).
    scenario
        What :func:`kisstime.scenario` takes: ``None`` for the built-in study, the path of a
        ``.toml`` or ``.json`` scenario (read here, on the client), a dict in the TOML
        schema, or a :class:`kisstime.Scenario`.
    samples
        The number of noisy strikes, samples ``0 .. samples``, at least 1. Ignored with
        ``strikes``.
    chunk
        Samples (or strike rows) per task, at least 1; the last task takes the rest.
    seed
        The noise seed; sample ``i``'s noise depends only on ``(seed, i)``.
    strikes
        Given strikes (a structured array or a mapping of columns with
        ``sample, V0, phi, theta, a, b``: :data:`kisstime.SAMPLE_STRIKE_DTYPE`) to run
        instead of noisy ones: every row, in order, each sample numbered by its ``sample``.
        Each task carries only its own rows. With no rows nothing is sent and the result
        is :func:`kisstime.shot_study`'s.
    until, noise, max_events, max_time, backend, precision
        As for :func:`kisstime.shot_study`; ``backend`` applies on each worker (``"auto"``
        uses a worker's GPU where it has one and its CPU elsewhere).
    physics
        As for :func:`kisstime.shot_study`: parameters (a dict of pooltool's names, or a
        TOML file read here, on the client) replacing the scenario's own; they travel with
        the scenario to every task.
    physics_noise
        As for :func:`kisstime.shot_study`: the physics' spread across samples (a dict of
        pooltool's ball parameter names, each a relative spread or ``[lo, hi]``).
    npy
        If given, the per-sample rows (``Study.samples``) are written there as ``.npy``
        (``Study.save``).
    retries
        How many times a task that raises is run again (worker deaths are counted apart,
        by the scheduler's ``allowed-failures``).

    Returns
    -------
    kisstime.Study

    Raises
    ------
    ValueError
        For a bad argument (``samples`` or ``chunk`` below 1 or not an integer, negative
        ``retries``, an unknown ``until``, bad ``strikes``, ``noise``, ``max_events`` or
        ``max_time``, a scenario that does not parse), before any task is sent: the
        client first runs an empty chunk, which checks them all as the workers would.
    OSError
        An unreadable scenario file.
    distributed.KilledWorker
        A task was on too many workers that died.
    """
    chunk = _count("chunk", chunk, 1)
    retries = _count("retries", retries, 0)
    columns = None if strikes is None else _strike_columns(strikes)
    total = _count("samples", samples, 1) if columns is None else len(columns["sample"])
    # the client gathers every chunk's result: refuse what would not fit, before starting
    kisstime._check_samples(total)
    sc = kisstime._with_physics(kisstime.scenario(scenario), physics, physics_noise)
    options = kisstime._study_options(
        seed, until, noise, max_events, max_time, backend, precision
    )
    if total == 0:
        # No strike rows: nothing to send; whatever one process gives.
        study = kisstime.shot_study(sc, strikes=columns, **options)
        if npy is not None:
            study.save(npy)
        return study
    # An empty chunk here checks the scenario, the options and the strikes as the tasks
    # will, so that a bad argument raises ValueError now rather than on every worker.
    kisstime._study_chunk(sc, 0, 0, strikes=columns, **options)
    if client is None:
        client = distributed.get_client()

    starts = range(0, total, chunk)
    sizes = [min(chunk, total - start) for start in starts]
    if columns is None:
        firsts: Sequence[int] = list(starts)
        pieces: list[Any] = [None] * len(sizes)
    else:
        # Each task carries only its own rows (first = 0 within them): the task specs hold
        # the strikes once in all, and the scheduler can run any task again anywhere.
        firsts = [0] * len(sizes)
        pieces = [
            {name: column[start : start + size].copy() for name, column in columns.items()}
            for start, size in zip(starts, sizes)
        ]

    token = uuid.uuid4().hex
    futures = client.map(
        _run_chunk,
        [sc] * len(sizes),
        firsts,
        sizes,
        pieces,
        key=[f"kisstime-chunk-{token}-{i}" for i in range(len(sizes))],
        retries=retries,
        **options,
    )
    try:
        blobs: list[bytes] = client.gather(futures)
    finally:
        client.cancel(futures)  # frees the workers' copies (and stops the rest on an error)
    study = kisstime._study_merge(sc, blobs, until=until)
    if npy is not None:
        study.save(npy)
    return study
