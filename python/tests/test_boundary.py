"""The Python boundary under bad and odd input (issue 31): arrays of the wrong dtype,
non-contiguous, empty, with NaN or inf, read-only, huge (shapes that claim more than
memory, without allocating it), and threads calling at once (the GIL released during the
engine's work, the results deterministic), for the main entry points: ``simulate``,
``shot_study``, ``pair_times``, ``next_collisions`` and ``Batch``.

Every bad input must raise a clear ``ValueError`` or ``TypeError`` at once: never a
crash, a hang, another exception, or an attempt to allocate what the shape claims.
Property tests (hypothesis) feed arbitrary values; the whole file runs in a few seconds.
"""

from __future__ import annotations

import threading
import time

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import kisstime

R = 0.028575
FIELDS = kisstime.BALL_DTYPE.names
NUMS = ("x", "y", "vx", "vy", "wx", "wy", "wz")
SETTINGS = settings(
    max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow]
)


def tables(n: int, balls: int = 3) -> np.ndarray:
    """`n` tables of `balls` still balls on a grid of the 9-ft table (ids 0..)."""
    a = np.zeros(n * balls, dtype=kisstime.BALL_DTYPE)
    a["table"] = np.repeat(np.arange(n), balls)
    a["ball"] = np.tile(np.arange(balls), n)
    k = np.tile(np.arange(balls), n)
    a["x"] = 0.3 + 0.2 * (k % 4)
    a["y"] = 0.5 + 0.3 * (k // 4)
    return a


def strikes(n: int, v0: float = 2.0) -> np.ndarray:
    s = np.zeros(n, dtype=kisstime.STRIKE_DTYPE)
    s["table"] = np.arange(n)
    s["V0"] = v0
    s["phi"] = np.linspace(0, 359, n)
    s["theta"] = 5.0
    s["a"] = 0.1
    return s


def moving(n: int) -> np.ndarray:
    """`n` tables whose ball 0 slides (for pair_times / next_collisions)."""
    a = tables(n)
    a["state"] = kisstime.STATES["sliding"]
    a["vx"] = 1.0
    a["vy"] = np.linspace(-1, 1, len(a))
    return a


def same(a, b) -> bool:
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


def same_sim(a: kisstime.SimResult, b: kisstime.SimResult) -> bool:
    return all(same(x, y) for x, y in zip(a, b))


# ---------------------------------------------------------------- dtypes


def test_plain_and_wrongly_typed_arrays_are_value_or_type_errors():
    good = tables(4)
    bad_inputs = [
        np.zeros((12, 10)),  # plain float array, no fields
        np.zeros(12, dtype=[("table", "<i8"), ("ball", "<i8")]),  # fields missing
        "table,ball",  # not an array at all
        12,
        None,
    ]
    for bad in bad_inputs:
        for call in (kisstime.simulate, kisstime.pair_times, kisstime.next_collisions):
            with pytest.raises((ValueError, TypeError)):
                call(bad)
    # a column of strings, of objects, of fractional ids, of complex numbers, of bools
    for name, value in [
        ("x", np.array(["a"] * 12)),
        ("x", np.array([object()] * 12, dtype=object)),
        ("table", np.full(12, 0.5)),
        ("ball", np.array(["0"] * 12)),
        ("x", np.full(12, 0.5 + 1j)),
        ("y", np.ones(12, dtype=bool)),
    ]:
        cols = {f: good[f] for f in FIELDS}
        cols[name] = value
        with pytest.raises((ValueError, TypeError), match=name):
            kisstime.simulate(cols)
    # strikes with a missing or non-numeric field
    with pytest.raises((ValueError, TypeError), match="strikes"):
        kisstime.simulate(good, {"table": np.arange(4)})
    bad_strikes = {f: strikes(4)[f] for f in kisstime.STRIKE_DTYPE.names}
    bad_strikes["V0"] = np.array(["fast"] * 4)
    with pytest.raises((ValueError, TypeError), match="V0"):
        kisstime.simulate(good, bad_strikes)


def test_other_numeric_dtypes_that_hold_the_values_exactly_are_accepted():
    good = tables(4)
    want = kisstime.simulate(good, strikes(4))
    cols = {f: good[f] for f in FIELDS}
    cols["table"] = good["table"].astype(np.int32)
    cols["ball"] = good["ball"].astype(np.float64)  # whole numbers in a float column
    cols["x"] = good["x"].astype(">f8")  # big-endian
    got = kisstime.simulate(cols, strikes(4))
    assert same_sim(got, want)


# ---------------------------------------------------------------- layouts


def test_non_contiguous_and_read_only_arrays_give_the_same_results():
    base = tables(8)
    s = strikes(8)
    want = kisstime.simulate(base, s)
    # every other row of a doubled array: strided
    doubled = np.zeros(2 * len(base), dtype=kisstime.BALL_DTYPE)
    doubled[::2] = base
    strided = doubled[::2]
    assert not strided.flags["C_CONTIGUOUS"]
    assert same_sim(kisstime.simulate(strided, s), want)
    # columns sliced out of a 2-D array (strided columns in a dict)
    grid = np.zeros((len(base), 10))
    for k, f in enumerate(FIELDS):
        grid[:, k] = base[f]
    cols = {f: grid[:, k] for k, f in enumerate(FIELDS)}
    assert not cols["x"].flags["C_CONTIGUOUS"]
    assert same_sim(kisstime.simulate(cols, s), want)
    # read-only arrays (and a read-only strike array)
    frozen = base.copy()
    frozen.setflags(write=False)
    fs = s.copy()
    fs.setflags(write=False)
    assert same_sim(kisstime.simulate(frozen, fs), want)
    assert same(kisstime.next_collisions(frozen), kisstime.next_collisions(base))
    assert same(kisstime.pair_times(frozen), kisstime.pair_times(base))
    assert not frozen.flags["WRITEABLE"]  # and not written to
    assert same(frozen, base)
    # a misaligned buffer (an odd offset into bytes)
    raw = np.zeros(base.nbytes + 1, dtype=np.uint8)
    odd = raw[1:].view(kisstime.BALL_DTYPE)
    odd[:] = base
    assert same_sim(kisstime.simulate(odd, s), want)


def test_empty_inputs_are_refused_or_empty_never_a_crash():
    empty = np.zeros(0, dtype=kisstime.BALL_DTYPE)
    for call in (kisstime.simulate, kisstime.pair_times, kisstime.next_collisions):
        try:
            out = call(empty)
        except ValueError as e:
            assert str(e)
        else:
            arrays = out if isinstance(out, tuple) else (out,)
            assert all(a is None or len(a) == 0 for a in arrays)
    # an empty strike array: no table struck
    good = tables(2)
    no_strikes = np.zeros(0, dtype=kisstime.STRIKE_DTYPE)
    assert same_sim(kisstime.simulate(good, no_strikes), kisstime.simulate(good))
    with pytest.raises(ValueError, match="no strikes"):
        kisstime.shot_study(strikes=np.zeros(0, dtype=kisstime.SAMPLE_STRIKE_DTYPE))
    with pytest.raises(ValueError):
        kisstime.shot_study(samples=0)


# ---------------------------------------------------------------- NaN, inf


@SETTINGS
@given(
    field=st.sampled_from(NUMS),
    row=st.integers(0, 11),
    value=st.sampled_from([np.nan, np.inf, -np.inf]),
)
def test_nan_and_inf_in_balls_are_value_errors_naming_the_column(field, row, value):
    a = tables(4)
    a[field][row] = value
    for call in (kisstime.simulate, kisstime.pair_times, kisstime.next_collisions):
        with pytest.raises(ValueError, match=field):
            call(a)


@SETTINGS
@given(
    field=st.sampled_from(["V0", "phi", "theta", "a", "b"]),
    value=st.sampled_from([np.nan, np.inf, -np.inf]),
)
def test_nan_and_inf_in_strikes_are_value_errors(field, value):
    s = strikes(4)
    s[field][2] = value
    with pytest.raises(ValueError):
        kisstime.simulate(tables(4), s)
    sample = np.zeros(3, dtype=kisstime.SAMPLE_STRIKE_DTYPE)
    sample["sample"] = [0, 1, 2]
    sample["V0"] = 1.0
    sample[field][1] = value
    with pytest.raises(ValueError):
        kisstime.shot_study(strikes=sample)


finite = st.floats(allow_nan=True, allow_infinity=True, width=64)


@SETTINGS
@given(
    data=st.lists(st.tuples(*[finite] * 7), min_size=2, max_size=8),
    states=st.lists(st.integers(-2, 6), min_size=8, max_size=8),
    strike=st.tuples(*[finite] * 5),
)
def test_arbitrary_values_are_simulated_or_refused_with_value_error(data, states, strike):
    a = np.zeros(len(data), dtype=kisstime.BALL_DTYPE)
    a["table"] = 7
    a["ball"] = np.arange(len(data))
    a["state"] = states[: len(data)]
    for k, f in enumerate(NUMS):
        a[f] = [row[k] for row in data]
    s = np.zeros(1, dtype=kisstime.STRIKE_DTYPE)
    s["table"] = 7
    for k, f in enumerate(("V0", "phi", "theta", "a", "b")):
        s[f] = strike[k]
    try:
        out = kisstime.simulate(a, s, max_events=200, max_time=10.0)
    except ValueError as e:
        assert str(e)
    else:
        assert len(out.outcomes) == 1 and len(out.final) == len(data)
    for call in (kisstime.pair_times, kisstime.next_collisions):
        try:
            call(a)
        except ValueError as e:
            assert str(e)


# ---------------------------------------------------------------- huge


def test_huge_shapes_are_refused_without_allocating_them():
    # 10**12 rows that share one row's memory (stride 0): a copy would need 80 TB
    one = tables(1, balls=2)[:1]
    huge = np.broadcast_to(one, (10**12,))
    assert huge.base is not None and huge.strides == (0,)
    for call in (kisstime.simulate, kisstime.pair_times, kisstime.next_collisions):
        start = time.perf_counter()
        with pytest.raises(ValueError, match="too large|memory"):
            call(huge)
        assert time.perf_counter() - start < 2.0
    cols = {f: np.broadcast_to(one[f], (10**12,)) for f in FIELDS}
    with pytest.raises(ValueError, match="too large|memory"):
        kisstime.simulate(cols)
    big_strikes = np.broadcast_to(strikes(1), (10**12,))
    with pytest.raises(ValueError, match="too large|memory"):
        kisstime.simulate(tables(2), big_strikes)
    # a study of more samples than memory holds, refused before it starts
    start = time.perf_counter()
    with pytest.raises(ValueError, match="too large|memory"):
        kisstime.shot_study(samples=10**15)
    assert time.perf_counter() - start < 2.0


def test_negative_and_absurd_counts_are_value_or_type_errors():
    for kwargs in (
        {"samples": -1},
        {"samples": 2**70},
        {"samples": 1.5},
        {"samples": "many"},
        {"samples": 10, "chunk": 0},
        {"samples": 10, "max_events": -5},
        {"samples": 10, "max_time": float("nan")},
    ):
        with pytest.raises((ValueError, TypeError)):
            kisstime.shot_study(**kwargs)
    for kwargs in ({"max_events": -1}, {"max_events": 2**70}, {"max_time": -1.0}):
        with pytest.raises((ValueError, TypeError)):
            kisstime.simulate(tables(2), **kwargs)


# ---------------------------------------------------------------- threads


def test_threads_in_parallel_get_the_same_results():
    balls, s = tables(64), strikes(64)
    want = kisstime.simulate(balls, s)
    want_next = kisstime.next_collisions(moving(64))
    got: dict = {}

    def work(k: int) -> None:
        if k % 2:
            got[k] = kisstime.simulate(balls, s)
        else:
            got[k] = kisstime.next_collisions(moving(64))

    threads = [threading.Thread(target=work, args=(k,)) for k in range(8)]
    for t in threads:
        t.start()
    for t in threads:
        t.join(timeout=60)
    assert sorted(got) == list(range(8))
    for k, out in got.items():
        assert same_sim(out, want) if k % 2 else same(out, want_next), k


def longest_pause(call) -> tuple[float, float]:
    """Runs `call` on a thread while this one counts: the call's wall time and the longest
    time this thread could not run Python during it (the GIL held)."""
    done = threading.Event()
    result: list = []

    def run() -> None:
        try:
            result.append(call())
        finally:
            done.set()

    t = threading.Thread(target=run)
    # from before the start: a call that holds the GIL may hold it before start() returns
    start = last = time.perf_counter()
    pause = 0.0
    t.start()
    while not done.is_set():
        now = time.perf_counter()
        pause = max(pause, now - last)
        last = now
        time.sleep(0.001)
    # the last wait too (a call that held the GIL ends it)
    pause = max(pause, time.perf_counter() - last)
    t.join()
    assert result
    return time.perf_counter() - start, pause


@pytest.mark.parametrize(
    "name,call",
    [
        ("simulate", lambda n: kisstime.simulate(tables(n, 6), strikes(n, 3.0))),
        ("shot_study", lambda n: kisstime.shot_study(samples=n)),
        ("pair_times", lambda n: kisstime.pair_times(moving(20 * n))),
    ],
)
def test_the_gil_is_released_during_engine_calls(name, call):
    # sized up until the call takes long enough to tell (0.2 s), at most a few seconds
    n = 1000
    while True:
        wall, pause = longest_pause(lambda: call(n))
        if wall > 0.2 or n >= 1 << 20:
            break
        n *= 4
    assert wall > 0.2, f"{name}: too quick to tell ({wall:.3f} s)"
    # the engine's work took the wall time, and the other thread kept running meanwhile
    assert pause < wall / 2, f"{name}: the other thread waited {pause:.3f} of {wall:.3f} s"


@pytest.mark.skipif(not hasattr(__import__("os"), "sched_getaffinity"), reason="Linux libc")
def test_the_pause_detector_sees_a_held_gil():
    # the control: a C call made with the GIL held (ctypes.PyDLL) stops the other thread
    import ctypes

    held = ctypes.PyDLL(None)
    wall, pause = longest_pause(lambda: held.usleep(300_000))
    assert pause > wall / 2, (wall, pause)
    released = ctypes.CDLL(None)
    wall, pause = longest_pause(lambda: released.usleep(300_000))
    assert pause < wall / 2, (wall, pause)
