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
as the client): ``pip install ./python`` from a checkout of the repository, or the built
wheel, in the worker's environment, and ``pip install 'dask[distributed]'``. The
scenario travels with the tasks as text, so workers need none of the client's files.

* By hand: start a scheduler on one machine and workers on the others::

      dask-scheduler                       # listens on tcp://<host>:8786
      dask-worker tcp://<host>:8786 --nworkers 1 --nthreads 1   # on every worker machine

  and connect with ``Client("tcp://<host>:8786")``. kisstime's simulator uses the cores
  it is given inside a task, so one thread per worker process is a good start.

* On a SLURM cluster, with `dask-jobqueue <https://jobqueue.dask.org>`_::

      from dask_jobqueue import SLURMCluster
      from dask.distributed import Client

      cluster = SLURMCluster(cores=8, memory="16GB", walltime="01:00:00")
      cluster.scale(jobs=10)            # ten SLURM jobs of 8 cores each
      client = Client(cluster)
      study = kisstime.dask.shot_study(client, "study.toml", samples=50_000_000)

  (``PBSCluster``, ``SGECluster`` and the others take the same arguments.)

* On one machine, ``distributed.LocalCluster()`` gives a cluster of local processes.

The client holds every chunk's result at the end (the per-sample rows, about a hundred
bytes a sample), so choose ``samples`` for the client's memory; ``chunk`` sets the size of
one task (tens of thousands of samples keep the scheduler's overhead small).
"""

from __future__ import annotations

import operator
import os
import uuid
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any, Union

try:
    import distributed
except ImportError as exc:  # pragma: no cover - exercised only without dask installed
    raise ImportError(
        "kisstime.dask needs Dask's distributed scheduler: pip install 'dask[distributed]'"
    ) from exc

import kisstime

if TYPE_CHECKING:
    import numpy

__all__ = ["shot_study"]

#: What ``scenario`` may be: anything :func:`kisstime.scenario` accepts.
ScenarioLike = Union["kisstime.Scenario", str, "os.PathLike[str]", Mapping[str, Any], None]

_UNTIL = ("rest", "first-contact")


def _run_chunk(
    scenario: kisstime.Scenario,
    first: int,
    n: int,
    strikes: Any,
    *,
    seed: int,
    until: str,
    noise: float | None,
    max_events: int,
    max_time: float,
) -> bytes:
    """One task: samples ``first .. first + n`` (or rows ``first .. first + n`` of ``strikes``)."""
    return kisstime._study_chunk(
        scenario,
        first,
        n,
        seed=seed,
        strikes=strikes,
        until=until,
        noise=noise,
        max_events=max_events,
        max_time=max_time,
    )


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


def _strike_rows(strikes: Any) -> int:
    """The number of strike rows in a structured array or a mapping of columns."""
    names = getattr(getattr(strikes, "dtype", None), "names", None)
    if names is not None:
        return len(strikes)
    if isinstance(strikes, Mapping):
        if "sample" not in strikes:
            raise ValueError("strikes needs the columns sample, V0, phi, theta, a, b")
        return len(strikes["sample"])
    raise ValueError(
        "strikes must be a NumPy structured array or a mapping of columns "
        "(sample, V0, phi, theta, a, b)"
    )


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
        The number of noisy strikes, samples ``0 .. samples``. Ignored with ``strikes``.
    chunk
        Samples (or strike rows) per task, at least 1; the last task takes the rest.
    seed
        The noise seed; sample ``i``'s noise depends only on ``(seed, i)``.
    strikes
        Given strikes (a structured array or a mapping of columns with
        ``sample, V0, phi, theta, a, b``) to run instead of drawn ones: every row, in order.
        Each task carries only its own rows.
    until, noise, max_events, max_time
        As for :func:`kisstime.shot_study`.
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
        For a bad argument (``samples`` or ``chunk`` below 1, negative ``retries``, an
        unknown ``until``, bad ``strikes``), before any task is sent.
    """
    chunk = _count("chunk", chunk, 1)
    retries = _count("retries", retries, 0)
    if until not in _UNTIL:
        raise ValueError(f"until must be one of {', '.join(map(repr, _UNTIL))}, not {until!r}")
    if strikes is None:
        total = _count("samples", samples, 1)
    else:
        total = _strike_rows(strikes)
        if total < 1:
            raise ValueError("strikes has no rows")
    if client is None:
        client = distributed.get_client()

    sc = kisstime.scenario(scenario)
    starts = list(range(0, total, chunk))
    sizes = [min(chunk, total - start) for start in starts]
    if strikes is None:
        firsts: Sequence[int] = starts
        pieces: list[Any] = [None] * len(starts)
    else:
        # Each task gets its own rows (first = 0 within them), so a task spec carries
        # only its chunk's strikes and the scheduler can re-run it anywhere.
        firsts = [0] * len(starts)
        pieces = [_rows(strikes, start, size) for start, size in zip(starts, sizes)]

    token = uuid.uuid4().hex
    futures = client.map(
        _run_chunk,
        [sc] * len(starts),
        firsts,
        sizes,
        pieces,
        key=[f"kisstime-chunk-{token}-{i}" for i in range(len(starts))],
        retries=retries,
        seed=seed,
        until=until,
        noise=noise,
        max_events=max_events,
        max_time=max_time,
    )
    try:
        blobs: list[bytes] = client.gather(futures)
    finally:
        client.cancel(futures)
        del futures
    study = kisstime._study_merge(sc, blobs, until=until)
    if npy is not None:
        study.save(npy)
    return study


def _rows(strikes: Any, start: int, size: int) -> Any:
    """Rows ``start .. start + size`` of a structured array or a mapping of columns, as a copy."""
    if isinstance(strikes, Mapping):
        return {name: _slice(column, start, size) for name, column in strikes.items()}
    return strikes[start : start + size].copy()


def _slice(column: Any, start: int, size: int) -> Any:
    part = column[start : start + size]
    copy = getattr(part, "copy", None)
    return copy() if copy is not None else part
