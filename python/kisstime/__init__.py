"""kisstime: billiards physics at scale, from Python.

Exact ball-ball collision times for every pair of many tables (``pair_times``,
``next_collisions``), pooltool 0.6.0's event-based simulation of whole shots from the cue
strike to rest (``simulate``), and Monte Carlo shot studies (``shot_study``), all with NumPy
arrays in and out. The computation is the kisstime Rust library's, the same code as the
``kisstime`` command line: for the same input the arrays are the command line's ``.npy``
outputs, bit for bit.

Every long call releases the GIL and can be interrupted with Ctrl-C (between chunks of
tables or samples). Bad input raises ``ValueError`` with the command line's message (the
input is named ``balls`` or ``strikes`` where the command line names the file), a GPU
failure ``RuntimeError``, an unreadable file ``OSError``.

Balls are a structured array of :data:`BALL_DTYPE` (``table, ball, state, x, y, vx, vy,
wx, wy, wz``: int64 ids and motion-state code, float64 numbers in m, m/s, rad/s; rows in
any order), or a dict of those 1-D columns. Motion-state codes are pooltool's: 0
stationary, 1 spinning, 2 sliding, 3 rolling, 4 pocketed (:data:`STATES`).

Whole shots run with pooltool's default ball and cue parameters unless ``physics=`` says
otherwise: a dict with pooltool 0.6.0's names (:data:`PHYSICS_KEYS`, the cue's under
``"cue"``) or a TOML file, read by the same parser as ``kisstime simulate --physics``.

Past one machine, :mod:`kisstime.dask` spreads a study over a Dask cluster; pooltool users
convert systems with :mod:`kisstime.pooltool`.
"""

from __future__ import annotations

import atexit
import dataclasses
import io
import json
import operator
import os
import shutil
import tempfile
from dataclasses import dataclass, field
from typing import Any, Mapping, NamedTuple, Optional, Sequence, Union

import numpy as np

from . import _kisstime

__all__ = [
    "BALL_DTYPE",
    "STRIKE_DTYPE",
    "SAMPLE_STRIKE_DTYPE",
    "PAIR_DTYPE",
    "NEXT_DTYPE",
    "STATES",
    "EVENT_TYPES",
    "FOULS",
    "Batch",
    "pair_times",
    "next_collisions",
    "simulate",
    "SimResult",
    "PHYSICS_KEYS",
    "table_ids",
    "release_engines",
    "Scenario",
    "scenario",
    "Study",
    "shot_study",
    "SAMPLE_FIELDS",
    "Plan",
    "plan",
    "NOISE_PRESETS",
]

#: The balls' structured dtype (the command line's ``.npy`` input layout).
BALL_DTYPE = np.dtype(
    [
        ("table", "<i8"),
        ("ball", "<i8"),
        ("state", "<i8"),
        ("x", "<f8"),
        ("y", "<f8"),
        ("vx", "<f8"),
        ("vy", "<f8"),
        ("wx", "<f8"),
        ("wy", "<f8"),
        ("wz", "<f8"),
    ]
)
#: Cue strikes for :func:`simulate` (``kisstime simulate --strikes``): pooltool's
#: ``Cue.set_state`` fields, V0 in m/s, phi and theta in degrees, a and b fractions of R.
STRIKE_DTYPE = np.dtype(
    [
        ("table", "<i8"),
        ("ball", "<i8"),
        ("V0", "<f8"),
        ("phi", "<f8"),
        ("theta", "<f8"),
        ("a", "<f8"),
        ("b", "<f8"),
    ]
)
#: Given strikes for :func:`shot_study` (``kisstime shots --strikes``).
SAMPLE_STRIKE_DTYPE = np.dtype(
    [
        ("sample", "<i8"),
        ("V0", "<f8"),
        ("phi", "<f8"),
        ("theta", "<f8"),
        ("a", "<f8"),
        ("b", "<f8"),
    ]
)
#: :func:`pair_times`' output: ``t`` the first contact time in s (``inf`` if none within
#: the horizon), ``status`` 0 none, 1 hit, 2 overlap, ``horizon`` the time both motions last.
PAIR_DTYPE = np.dtype(
    [
        ("table", "<i8"),
        ("i", "<i8"),
        ("j", "<i8"),
        ("t", "<f8"),
        ("status", "<i8"),
        ("horizon", "<f8"),
    ]
)
#: :func:`next_collisions`' output: one row per table (``i = j = -1`` when none).
NEXT_DTYPE = np.dtype(
    [("table", "<i8"), ("t", "<f8"), ("i", "<i8"), ("j", "<i8"), ("status", "<i8")]
)
#: Motion-state codes.
STATES = {"stationary": 0, "spinning": 1, "sliding": 2, "rolling": 3, "pocketed": 4}
#: Event type codes of :func:`simulate`'s ``events`` (pooltool's ``EventType`` names).
EVENT_TYPES = (
    "stick_ball",
    "ball_ball",
    "ball_linear_cushion",
    "ball_circular_cushion",
    "ball_pocket",
    "sliding_rolling",
    "rolling_spinning",
    "rolling_stationary",
    "spinning_stationary",
)

_BALL_INT = ("table", "ball", "state")
_BALL_NUM = ("x", "y", "vx", "vy", "wx", "wy", "wz")

ArrayLike = Union[np.ndarray, Mapping[str, Any]]


def _quiet_mesa(backend: str) -> None:
    """Before the first call that may open a GPU: Mesa's Vulkan drivers print
    ``error: XDG_RUNTIME_DIR is invalid or not set`` on stderr (several times) when that
    variable is unset, though compute needs no runtime directory. Where it is unset, point
    it at a private temporary folder, removed when the interpreter exits (the command line
    does the same). CPU calls touch nothing."""
    if backend == "cpu" or os.environ.get("XDG_RUNTIME_DIR"):
        return
    folder = tempfile.mkdtemp(prefix="kisstime-xdg-")
    os.environ["XDG_RUNTIME_DIR"] = folder
    atexit.register(shutil.rmtree, folder, True)


#: Bytes a row of input takes once converted (the crate's ``limits::BYTES_PER_BALL``).
_BYTES_PER_ROW = 88


def _available_memory() -> Optional[int]:
    """The memory available now in bytes (``MemAvailable``), or None where unknown: what
    the crate's ``limits::check_memory`` compares with."""
    try:
        with open("/proc/meminfo") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    return None


def _check_rows(rows: int, what: str) -> None:
    """Refuses an input of `rows` rows that would not fit the available memory once
    converted, before any copy: an array may claim far more rows than it holds (a
    broadcast view of one row), and copying its columns would exhaust memory."""
    need = rows * _BYTES_PER_ROW
    avail = _available_memory()
    if avail is not None and need > avail:
        raise ValueError(
            f"{what}: {rows} rows are too large: they need about {need / 1e9:.1f} GB of "
            f"memory, more than the {avail / 1e9:.1f} GB available"
        )


def _count(value: Any, name: str) -> int:
    """A count (``max_events``, ``samples``, ``chunk``) as an int: a ``TypeError`` for what
    is not an integer (1.5 is not truncated), a ``ValueError`` beyond 64 bits or below 0."""
    try:
        n = operator.index(value)
    except TypeError:
        raise TypeError(f"{name} must be an integer, not {type(value).__name__}") from None
    if not 0 <= n < 2**64:
        raise ValueError(f"{name} {n}: out of range (0 to 2**64 - 1)")
    return n


#: Bytes a study's sample takes on the client until the study is merged (a chunk's result,
#: then its row of ``Study.samples``): what ``shot_study`` checks the samples against.
_BYTES_PER_SAMPLE = 400


def _check_samples(samples: int) -> None:
    """Refuses a study whose results would not fit the available memory, before it starts
    (a study of 10**15 samples would otherwise run chunk after chunk until memory ran out)."""
    need = samples * _BYTES_PER_SAMPLE
    avail = _available_memory()
    if avail is not None and need > avail:
        raise ValueError(
            f"samples {samples}: too large: the study's results need about "
            f"{need / 1e9:.1f} GB of memory, more than the {avail / 1e9:.1f} GB available"
        )


def _column(data: ArrayLike, name: str, dtype: str, what: str) -> np.ndarray:
    """One 1-D C-contiguous column of a structured array or dict."""
    try:
        col = data[name]
    except (KeyError, ValueError, IndexError, TypeError):
        raise ValueError(f"{what}: no column {name!r}") from None
    arr = np.asarray(col)
    if arr.ndim != 1:
        raise ValueError(f"{what}: column {name!r} must be 1-D, it has shape {arr.shape}")
    _check_rows(arr.shape[0], what)
    if dtype == "<i8" and arr.dtype.kind not in "iu":
        # whole numbers in a float column are fine (as in the CLI's plain float64 .npy)
        whole = arr.dtype.kind == "f" and bool(
            np.all(np.isfinite(arr)) and np.all(arr == np.round(arr))
        )
        if not whole:
            raise ValueError(
                f"{what}: column {name!r} must hold integers, it is {arr.dtype}"
            )
    if dtype == "<i8" and arr.size:
        # ids beyond int64 would wrap (uint64) or be undefined (floats) when converted
        if (arr.dtype.kind == "u" and int(arr.max()) > 2**63 - 1) or (
            arr.dtype.kind == "f" and float(np.max(np.abs(arr))) >= 2.0**63
        ):
            raise ValueError(f"{what}: column {name!r} holds integers beyond int64")
    if dtype == "<f8" and arr.dtype.kind not in "fiu":
        # complex numbers would lose their imaginary part, booleans become 0 and 1, and
        # strings be parsed: refused rather than converted quietly
        raise ValueError(f"{what}: column {name!r} must hold real numbers, it is {arr.dtype}")
    # C-contiguous and aligned (arrays unpickled by Dask can sit at odd addresses)
    return np.require(arr, dtype=dtype, requirements=["C", "A"])


def _balls(balls: ArrayLike) -> list:
    """The ten input columns, in the extension's order."""
    if isinstance(balls, np.ndarray) and balls.dtype.names is None:
        raise ValueError(
            "balls: expected a structured array of kisstime.BALL_DTYPE or a dict of columns"
        )
    cols = [_column(balls, n, "<i8", "balls") for n in _BALL_INT]
    cols += [_column(balls, n, "<f8", "balls") for n in _BALL_NUM]
    lengths = {len(c) for c in cols}
    if len(lengths) != 1:
        raise ValueError(f"balls: columns of different lengths {sorted(lengths)}")
    return cols


def _load(data: bytes) -> np.ndarray:
    """An array from ``.npy`` bytes."""
    return np.load(io.BytesIO(data), allow_pickle=False)


def _params(radius: float, mu_s: float, mu_r: float, mu_sp: Optional[float], g: float):
    return (
        float(radius),
        float(mu_s),
        float(mu_r),
        float(0.444 * radius if mu_sp is None else mu_sp),
        float(g),
    )


#: pooltool 0.6.0's ``BallParams`` names, the keys of ``physics={...}`` (the cue's,
#: ``M`` and ``end_mass``, go under ``"cue"``).
PHYSICS_KEYS = ("m", "R", "u_s", "u_r", "u_sp_proportionality", "u_b", "e_b", "e_c", "f_c", "g")

PhysicsLike = Union[None, str, os.PathLike, Mapping[str, Any]]


def _toml_value(v: Any) -> str:
    """One value of a physics mapping as TOML (the Rust parser judges it)."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, Mapping):
        return "{ " + ", ".join(f"{json.dumps(str(k))} = {_toml_value(x)}" for k, x in v.items()) + " }"
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    if isinstance(v, (float, np.floating)):
        x = float(v)
        if x != x:
            return "nan"
        if x in (float("inf"), float("-inf")):
            return "inf" if x > 0 else "-inf"
        return repr(x)
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    return json.dumps(str(v))  # anything else: refused as "a string"


def _physics(physics: PhysicsLike) -> Optional[tuple]:
    """``physics=`` as the extension takes it: ``None``; ``("dict", TOML text, "physics")``
    for a dict of pooltool's names; ``("toml", text, path)`` for a TOML file (read now)."""
    if physics is None:
        return None
    if isinstance(physics, Mapping):
        lines = [f"{json.dumps(str(k))} = {_toml_value(v)}" for k, v in physics.items()]
        return ("dict", "\n".join(lines) + "\n", "physics")
    if isinstance(physics, (str, os.PathLike)):
        path = os.fspath(physics)
        with open(path, encoding="utf-8") as f:
            return ("toml", f.read(), path)
    raise TypeError(
        f"physics: expected a dict of pooltool's BallParams names (and \"cue\": {{...}}) or "
        f"the path of a TOML file, not {type(physics).__name__}"
    )


class Batch:
    """Balls converted once and kept on the Rust side: pass it to :func:`next_collisions`
    again and again (an event loop's question after every event) without converting the
    arrays each time. Built from what :func:`pair_times` takes; checked the same way."""

    def __init__(self, balls: ArrayLike):
        if (
            isinstance(balls, np.ndarray)
            and balls.dtype == BALL_DTYPE
            and balls.ndim == 1
            and balls.flags["C_CONTIGUOUS"]
        ):
            # the array's own buffer, read in one pass on the Rust side (no column copies)
            self._batch = _kisstime.Batch.from_records(balls.view(np.uint8))
        else:
            self._batch = _kisstime.Batch(*_balls(balls))

    @property
    def num_tables(self) -> int:
        """The number of tables."""
        return self._batch.num_tables

    @property
    def num_balls(self) -> int:
        """The number of balls."""
        return self._batch.num_balls

    @property
    def num_pairs(self) -> int:
        """The number of ball pairs."""
        return self._batch.num_pairs


def _as_batch(balls: Union[ArrayLike, "Batch"]) -> "Batch":
    return balls if isinstance(balls, Batch) else Batch(balls)


def pair_times(
    balls: Union[ArrayLike, "Batch"],
    *,
    backend: str = "cpu",
    precision: Optional[str] = None,
    radius: float = 0.028575,
    mu_s: float = 0.2,
    mu_r: float = 0.01,
    mu_sp: Optional[float] = None,
    g: float = 9.81,
) -> np.ndarray:
    """Every ball pair's first contact while approaching, within the time both current
    motions last (``kisstime pairs``).

    ``backend`` is ``"cpu"`` (Rayon, f64, the reference), ``"gpu"`` (wgpu) or ``"auto"``
    (the backend measured faster: the CPU for these kernels, which are slower end to end on
    the GPU, unless ``KISSTIME_AUTO_GPU=always``); ``precision`` ``"f32"`` or ``"f64"`` (default:
    f64 on the CPU, f32 on a GPU). Returns a structured array of :data:`PAIR_DTYPE`, tables
    in ascending id order and pairs ``(i, j)`` with ``i < j`` in ball-id order.
    """
    _quiet_mesa(backend)
    data = _kisstime.pair_times(
        _as_batch(balls)._batch, _params(radius, mu_s, mu_r, mu_sp, g), backend, precision
    )
    return _load(data)


def next_collisions(
    balls: Union[ArrayLike, Batch],
    *,
    backend: str = "cpu",
    precision: Optional[str] = None,
    radius: float = 0.028575,
    mu_s: float = 0.2,
    mu_r: float = 0.01,
    mu_sp: Optional[float] = None,
    g: float = 9.81,
) -> np.ndarray:
    """Each table's next collision: the earliest pair in contact (``kisstime next``).

    Ties go to the smallest time, then the smallest ``(i, j)``. Returns a structured array
    of :data:`NEXT_DTYPE`, one row per table in ascending id order; ``t = inf``,
    ``i = j = -1``, ``status = 0`` where no pair of the table collides. ``balls`` may be a
    :class:`Batch` (converted once, for repeated calls).
    """
    params = _params(radius, mu_s, mu_r, mu_sp, g)
    _quiet_mesa(backend)
    raw = _kisstime.next_collisions(_as_batch(balls)._batch, params, backend, precision)
    return np.frombuffer(raw, dtype=NEXT_DTYPE).copy()


class SimResult(NamedTuple):
    """What :func:`simulate` returns: the command line's three ``.npy`` outputs."""

    #: Every event, one row per involved ball (``None`` when ``events=False``).
    events: Optional[np.ndarray]
    #: Every ball's final state (``pocket``: the pocket's index, or -1).
    final: np.ndarray
    #: One row per table: ``table, events, t_end, cut`` (cut 0 none, 1 max_events,
    #: 2 max_time).
    outcomes: np.ndarray


#: What a ``table=`` argument takes: a built-in name (``"9ft"``, ``"7ft"``,
#: ``"rectangle"``, ``"snooker"``, ``"carom"``), the path of a JSON table, the JSON text itself, or a pooltool ``Table``.
TableLike = Union[str, os.PathLike, Any]


def _table(table: TableLike) -> tuple:
    """``table=`` as the extension takes it: ``(name or path, None)`` or ``("table", JSON
    text)``. A str whose first non-blank character is ``{`` is JSON text (what
    :func:`kisstime.pooltool.table_json` produces); an object with pooltool's
    ``cushion_segments`` and ``pockets`` is converted by ``table_json`` (no file is
    written)."""
    if isinstance(table, str):
        if table.lstrip().startswith("{"):
            return ("table", table)
        return (table, None)
    if isinstance(table, os.PathLike):
        return (os.fspath(table), None)
    if hasattr(table, "cushion_segments") and hasattr(table, "pockets"):
        from .pooltool import table_json

        return ("table", table_json(table))
    raise TypeError(
        "table: expected a built-in name (\"9ft\", \"7ft\", \"rectangle\", \"snooker\", \"carom\"), a path, JSON "
        f"text or a pooltool Table, not {type(table).__name__}"
    )


def simulate(
    balls: Union[ArrayLike, "Batch"],
    strikes: Optional[ArrayLike] = None,
    *,
    table: TableLike = "9ft",
    max_events: int = 200_000,
    max_time: float = 3600.0,
    events: bool = True,
    backend: str = "cpu",
    precision: Optional[str] = None,
    physics: PhysicsLike = None,
    rules: Optional[str] = None,
    context: Union[None, str, os.PathLike, Mapping] = None,
    wpa: bool = False,
    _rule_ids: Optional[Mapping[int, int]] = None,
) -> SimResult:
    """Whole shots from the cue strike to rest with pooltool 0.6.0's physics
    (``kisstime simulate``).

    ``rules`` (``"9-ball"``, ``"8-ball"``, ``"snooker"`` or ``"three-cushion"``) judges
    every shot as pooltool 0.6.0's rule sets judge it (``kisstime simulate --rules``):
    ``outcomes`` then has the fields ``legal``, ``foul`` (an index in :data:`FOULS`, -1 for
    none), ``turn_over``, ``game_over`` and ``won`` (0/1), ``points`` (snooker's pots,
    three-cushion's point) and ``foul_points`` (snooker's penalty to the opponent). Ball
    ids are the game's: 0 the cue ball, the object balls their numbers (snooker: reds 1 to
    15, yellow 16 … black 21). ``context`` gives each shot's context (``--context``): the
    path of a CSV file ``table,break,hittable,ball_call,pocket_call[,score,opponent_score]``,
    or a dict of equal-length columns with those names (``hittable``: a list of ball ids,
    or a str of ids joined by ``;``, per table; ``ball_call`` -1 or ``None`` for none,
    snooker's balls also by name (``"black"``); ``pocket_call`` a pocket id such as
    ``"lb"`` or ``""``; ``score``, ``opponent_score`` the points before the shot); tables
    without one play an ordinary shot on an open table (snooker: the balls on worked out
    from the table) with no call. Errors (an unknown game, a table not in the input, a ball not on the table, a
    pocket the table lacks) raise ``ValueError``. ``wpa=True`` takes the WPA's reading
    where pooltool departs from it (``--wpa``: 9-ball's break must hit the 1 first; 8-ball's
    8 on the break ends no game). (``_rule_ids``, for the pooltool bridge:
    each ball id's id in the game, where they differ.)

    ``physics`` sets the balls' and the cue's parameters (``kisstime simulate
    --physics``): a dict with pooltool 0.6.0's ``BallParams`` names (:data:`PHYSICS_KEYS`:
    ``m, R, u_s, u_r, u_sp_proportionality, u_b, e_b, e_c, f_c, g``; as in pooltool, the
    spinning friction is ``u_sp_proportionality * R``) and the cue's ``CueSpecs`` names
    under ``"cue"`` (``{"M": ..., "end_mass": ...}``), or the path of a TOML file with those
    keys (the cue's in a ``[cue]`` table; ``data/physics/physics.toml``). Keys left out keep
    pooltool's defaults; ``None`` is all defaults. **Per table**: a dict with a ``"table"``
    array of table ids (one entry per table of the batch) and arrays for the parameters
    that vary (``{"table": ids, "u_r": u_r, "e_c": e_c, "R": 0.02619}``; the cue's as
    ``{"cue": {"M": array}}``): each table gets the single values with its own entries in
    place (``kisstime simulate --physics FILE.csv``). An unknown key (kisstime's former names
    ``radius``, ``mu_s``, … say which pooltool name to use), a value that is not a number or
    out of range raises ``ValueError`` with the command line's message (a dict is named
    ``physics``).

    ``backend`` is ``"cpu"`` (Rayon, f64, every core: the reference), ``"gpu"`` (the WGSL
    event loop, one workgroup per table, up to 64 balls a table; ``RuntimeError`` when no
    GPU is usable) or ``"auto"`` (the backend measured faster: never a software adapter, the
    GPU from 512 tables per CPU thread, else the CPU; a ``RuntimeWarning`` says why where a
    GPU could not be used; a GPU failure mid-batch is redone on the CPU).
    ``precision`` is ``"f64"`` (the default and the only one for whole shots; the GPU needs
    ``SHADER_F64``); ``"f32"`` is refused with a ``ValueError`` (in f32 the GPU decides
    contacts to a micrometre and about half of the reference shots end elsewhere).

    ``strikes`` (at most one per table, applied at t = 0) is a structured array of
    :data:`STRIKE_DTYPE` or a dict of its columns. ``table`` is ``"9ft"`` (pooltool's 9-ft
    pocket table), ``"7ft"`` (pooltool's default table, ``pt.Table.default()``),
    ``"rectangle"`` (the 9-ft playing surface, no pockets), ``"snooker"``, ``"carom"``
    (pooltool's snooker and three-cushion tables; without ``physics`` they play their
    game's balls, as pooltool's ``BallParams.default``), the path of a JSON table in the
    format of ``data/fullshots/table.json``, that JSON text itself (a str starting with
    ``{``), or a pooltool ``Table`` object (pocket, snooker or billiard; converted with
    :func:`kisstime.pooltool.table_json`, no file written). A table is cut after
    ``max_events`` events or before an event later than ``max_time`` s (see
    ``outcomes['cut']``). The arrays' layouts are those of the command line's ``.npy``
    outputs (``-o``, ``--final``, ``--outcomes``); ``events['type']`` indexes
    :data:`EVENT_TYPES`, ``agent_b`` is the other ball's id or the cushion's, jaw's or
    pocket's index in :func:`table_ids`' lists (-1 if none).
    """
    batch = _as_batch(balls)
    strike_cols = None
    if strikes is not None:
        ints = [_column(strikes, n, "<i8", "strikes") for n in ("table", "ball")]
        nums = [
            _column(strikes, n, "<f8", "strikes") for n in ("V0", "phi", "theta", "a", "b")
        ]
        strike_cols = (ints[0], ints[1], nums)
    name, text = _table(table)
    _quiet_mesa(backend)
    ev, fin, oc = _kisstime.simulate(
        batch._batch,
        strike_cols,
        name,
        _count(max_events, "max_events"),
        float(max_time),
        bool(events),
        backend,
        precision,
        *_physics_per_table(physics),
        text,
        rules,
        _context_csv(context),
        None if _rule_ids is None else (
            np.ascontiguousarray(list(_rule_ids.keys()), dtype="<i8"),
            np.ascontiguousarray(list(_rule_ids.values()), dtype="<i8"),
        ),
        bool(wpa),
    )
    return SimResult(_load(ev) if ev is not None else None, _load(fin), _load(oc))


#: The fouls ``simulate(..., rules=...)`` reports, in the order ``outcomes['foul']``
#: indexes (kisstime's codes; ``kisstime.game::Foul::ALL``).
FOULS = (
    "cue_pocketed",
    "no_hit",
    "wrong_ball_first",
    "no_rail",
    "break_rails",
    "not_called",
    "eight_illegal",
    "off_ball_pocketed",
)


def _context_csv(context) -> Optional[str]:
    """``simulate``'s ``context`` as the CSV text the extension reads."""
    if context is None:
        return None
    if not isinstance(context, Mapping):
        with open(os.fspath(context), newline="") as f:
            return f.read()
    cols = ("table", "break", "hittable", "ball_call", "pocket_call", "score", "opponent_score")
    unknown = set(context) - set(cols)
    if unknown:
        raise ValueError(f"context: unknown columns {sorted(unknown)}; the columns are {cols}")
    if "table" not in context:
        raise ValueError("context: a 'table' column is needed")
    n = len(context["table"])
    for c in context:
        if len(context[c]) != n:
            raise ValueError(f"context: {c} has {len(context[c])} values for {n} tables")

    def cell(c: str, i: int) -> str:
        if c not in context:
            return ""
        v = context[c][i]
        if c == "hittable":
            return v if isinstance(v, str) else ";".join(
                b if isinstance(b, str) else str(int(b)) for b in v
            )
        if c == "break":
            return "1" if bool(v) else "0"
        if c == "ball_call":
            if isinstance(v, str):
                return v
            return "" if v is None or int(v) < 0 else str(int(v))
        if c == "pocket_call":
            return "" if v is None else str(v)
        return str(int(v))

    lines = [",".join(cols)]
    lines += [",".join(cell(c, i) for c in cols) for i in range(n)]
    return "\n".join(lines) + "\n"


def _physics_per_table(physics: PhysicsLike) -> tuple:
    """``simulate``'s ``physics`` as the extension takes it: ``(physics, columns)``, where
    ``columns`` is ``None``, or, for a mapping with a ``"table"`` entry, ``(table ids,
    [(name, values)])``: its array values, one per table (the cue's named ``cue.M``), the
    single values staying in ``physics`` as every table's base."""
    if not (isinstance(physics, Mapping) and "table" in physics):
        return (_physics(physics), None)
    ids = np.ascontiguousarray(np.asarray(physics["table"]), dtype="<i8")
    if ids.ndim != 1:
        raise ValueError("physics: 'table' must be a 1-D array of table ids")
    single: dict = {}
    columns: list = []

    def split(prefix: str, items: Any, into: dict) -> None:
        for k, v in items:
            if isinstance(v, Mapping):
                sub: dict = {}
                split(f"{prefix}{k}.", v.items(), sub)
                if sub:
                    into[k] = sub
            elif np.ndim(v) == 1:
                columns.append((f"{prefix}{k}", np.ascontiguousarray(v, dtype="<f8")))
            else:
                into[k] = v

    split("", ((k, v) for k, v in physics.items() if k != "table"), single)
    return (_physics(single), (ids, columns))


def table_ids(table: TableLike = "9ft") -> dict:
    """The ids of a table's items in index order: ``{"linear": [...], "circular": [...],
    "pockets": [...]}`` (pooltool's segment, jaw and pocket ids), to read the indices in
    :func:`simulate`'s outputs. ``table`` as for :func:`simulate`."""
    name, text = _table(table)
    linear, circular, pockets = _kisstime.table_ids(name, text)
    return {"linear": list(linear), "circular": list(circular), "pockets": list(pockets)}


def release_engines() -> int:
    """Closes the whole-shot engines kept between calls and returns how many there were.

    :func:`simulate`, :func:`shot_study` (each of its chunks), :func:`plan` and Dask's
    tasks reuse an engine opened for the same backend, precision and environment
    (``WGPU_*``, ``VK_*``, ``KISSTIME_*`` variables) by an earlier call in the process, so
    that a GPU's device and pipelines are built once rather than for every call; the idle
    engines hold their GPU memory until this is called (or the process ends). The next
    call opens an engine again."""
    return int(_kisstime.release_engines())


# ----------------------------------------------------------------------- shot studies


@dataclass(frozen=True)
class Scenario:
    """A shot study's scenario as text (picklable, so that Dask workers need no file):
    ``kind`` is ``builtin``, ``toml``, ``json`` (the reference format of
    ``data/studies``) or ``dict``. Make one with :func:`scenario`."""

    kind: str
    text: str = ""
    source: str = "built-in study (examples/study.toml)"
    dir: Optional[str] = None
    #: Parameters replacing the scenario's ``[physics]`` (what ``shot_study(physics=...)``
    #: gives), as the extension takes them; ``None``: the scenario's own.
    physics: Optional[tuple] = None
    #: The physics' spread across samples replacing the scenario's ``[noise.physics]``
    #: (what ``shot_study(physics_noise=...)`` gives), as that table's TOML body.
    physics_noise: Optional[str] = None

    def _args(self) -> tuple:
        return (self.kind, self.text, self.source, self.dir, self.physics, self.physics_noise)


def scenario(
    x: Union[None, str, os.PathLike, Mapping[str, Any], Scenario] = None, **sections: Any
) -> Scenario:
    """The scenario ``x`` names: ``None`` the built-in study; a path to a TOML study
    (``examples/study.toml``'s format) or to a ``.json`` scenario in ``data/studies``'
    format; a dict with the TOML file's schema (``{"balls": [...], "shot": {...}, ...}``).
    Or, with no ``x``, the sections as keyword arguments: ``scenario(balls=[{"id": "cue",
    "x": 0.6, "y": 0.5}, ...], shot={"cue_ball": "cue", "object_ball": 1, "v0": 1.5,
    "phi": 90, "theta": 5, "a": 0, "b": 0.2}, table={"kind": "9ft"}, target={...},
    noise={...}, physics={...})`` (``physics`` with pooltool's names, as the TOML's
    ``[physics]`` table and :func:`simulate`'s ``physics``). A file is read now; everything is checked when the
    study runs (:func:`shot_study` raises ``ValueError`` naming the file and key)."""
    if sections:
        if x is not None:
            raise ValueError("give a scenario or its sections as keywords, not both")
        return Scenario("dict", json.dumps(sections), "scenario arguments", None)
    if x is None:
        return Scenario("builtin")
    if isinstance(x, Scenario):
        return x
    if isinstance(x, Mapping):
        return Scenario("dict", json.dumps(x), "scenario dict", None)
    path = os.fspath(x)
    with open(path, encoding="utf-8") as f:
        text = f.read()
    kind = "json" if path.lower().endswith(".json") else "toml"
    return Scenario(kind, text, path, os.path.dirname(os.path.abspath(path)))


#: The fields of :attr:`Study.samples`, one row per sample. ``first_contact``: 0 a ball,
#: 1 a cushion or jaw, 2 a pocket, 3 stopped, 4 nothing; ``first_index`` the ball's index
#: in :attr:`Study.ball_ids` (or the cushion's, jaw's or pocket's in the table), else -1;
#: ``result``: 0 pot, 1 pot + scratch, 2 scratch, 3 miss (-1 with ``until="first-contact"``);
#: ``intended_pocket``, ``cue_pocket``: a pocket index in :attr:`Study.pocket_ids`, or -1;
#: ``cut``: 0 none, 1 max_events, 2 max_time. With a game (the scenario's ``game``
#: section) the verdict: ``legal``, ``turn_over``, ``game_over``, ``won`` 0 or 1, ``foul``
#: an index in :data:`FOULS` or -1, ``points`` and ``foul_points`` (snooker, three-cushion;
#: 0 in pool); all -1 without a game.
SAMPLE_FIELDS = (
    ("sample", "<i8"),
    ("V0", "<f8"),
    ("phi", "<f8"),
    ("theta", "<f8"),
    ("a", "<f8"),
    ("b", "<f8"),
    ("first_contact", "<i8"),
    ("first_index", "<i8"),
    ("first_t", "<f8"),
    ("speed", "<f8"),
    ("cut_angle", "<f8"),
    ("result", "<i8"),
    ("intended_pocket", "<i8"),
    ("cue_pocket", "<i8"),
    ("cue_x", "<f8"),
    ("cue_y", "<f8"),
    ("n_events", "<i8"),
    ("duration", "<f8"),
    ("cut", "<i8"),
    ("legal", "<i8"),
    ("foul", "<i8"),
    ("turn_over", "<i8"),
    ("game_over", "<i8"),
    ("won", "<i8"),
    ("points", "<i8"),
    ("foul_points", "<i8"),
)
_SAMPLE_DTYPE = np.dtype(list(SAMPLE_FIELDS))


@dataclass
class Study:
    """A shot study's result.

    ``summary`` is what ``kisstime shots --json`` prints, less the run's description:
    every count as ``{"count", "fraction", "ci95"}`` (Wilson 95 % interval), every
    statistic as ``{"n", "mean", "std", "p5", "p50", "p95"}``. ``samples`` has one row per
    sample (fields :data:`SAMPLE_FIELDS`), ``potted`` each sample's pocketed balls as
    ``ball@pocket;…`` in order (``data/studies``' vocabulary).
    """

    summary: dict
    samples: np.ndarray
    potted: list
    ball_ids: list = field(default_factory=list)
    pocket_ids: list = field(default_factory=list)

    def save(self, path: Union[str, os.PathLike]) -> None:
        """Writes :attr:`samples` as a ``.npy`` file."""
        np.save(path, self.samples, allow_pickle=False)

    @property
    def pot_fraction(self) -> float:
        """The fraction of samples that potted the intended ball (any pocket)."""
        return float(self.summary["intended_potted"]["fraction"])


_STRIKE_FIELDS = ("V0", "phi", "theta", "a", "b")


def _strike_columns(strikes: ArrayLike) -> tuple:
    ids = _column(strikes, "sample", "<i8", "strikes")
    nums = [_column(strikes, n, "<f8", "strikes") for n in _STRIKE_FIELDS]
    return (ids, nums)


def _study_chunk(
    scenario: Scenario,
    first: int,
    n: int,
    *,
    seed: int = 42,
    strikes: Optional[ArrayLike] = None,
    until: str = "rest",
    noise: Optional[float] = None,
    max_events: int = 10_000,
    max_time: float = 600.0,
    backend: str = "cpu",
    precision: Optional[str] = None,
) -> bytes:
    """Samples ``first .. first + n`` of a study (noisy from ``seed``, or rows of the given
    strikes) as an opaque blob for :func:`_study_merge` (what a Dask task computes)."""
    strike_cols = None if strikes is None else _strike_columns(strikes)
    _quiet_mesa(backend)
    return _kisstime.study_chunk(
        *scenario._args(),
        int(first),
        int(n),
        int(seed),
        strike_cols,
        until,
        None if noise is None else float(noise),
        _count(max_events, "max_events"),
        float(max_time),
        backend,
        precision,
    )


def _study_merge(scenario: Scenario, blobs: Sequence[bytes], *, until: str = "rest") -> Study:
    """The blobs of a study's chunks, in order, as one :class:`Study`."""
    summary, cols, potted = _kisstime.study_merge(*scenario._args(), list(blobs), until)
    samples = np.empty(len(cols["sample"]), dtype=_SAMPLE_DTYPE)
    for name, _ in SAMPLE_FIELDS:
        samples[name] = cols[name]
    balls, pockets, _linear, _circular, _cue, _intended = _kisstime.study_ids(*scenario._args())
    return Study(json.loads(summary), samples, list(potted), list(balls), list(pockets))


_scenario = scenario


def _with_physics(
    sc: Scenario, physics: PhysicsLike, physics_noise: Optional[Mapping[str, Any]]
) -> Scenario:
    """``sc`` with ``shot_study``'s ``physics`` and ``physics_noise`` in place of its own
    (they travel with the scenario to Dask's workers)."""
    if physics is not None:
        sc = dataclasses.replace(sc, physics=_physics(physics))
    if physics_noise is not None:
        if not isinstance(physics_noise, Mapping):
            raise ValueError(
                "physics_noise: expected a dict of pooltool's ball parameter names, "
                f"not {type(physics_noise).__name__}"
            )
        lines = [f"{json.dumps(str(k))} = {_toml_value(v)}" for k, v in physics_noise.items()]
        sc = dataclasses.replace(sc, physics_noise="\n".join(lines) + "\n")
    return sc


def _study_options(
    seed: int,
    until: str,
    noise: Optional[float],
    max_events: int,
    max_time: float,
    backend: str,
    precision: Optional[str],
) -> dict:
    """The keyword arguments of :func:`_study_chunk` that every chunk of a study shares."""
    return dict(
        seed=seed,
        until=until,
        noise=noise,
        max_events=_count(max_events, "max_events"),
        max_time=max_time,
        backend=backend,
        precision=precision,
    )


def shot_study(
    scenario: Union[None, str, os.PathLike, Mapping[str, Any], Scenario] = None,
    *,
    samples: int = 100_000,
    seed: int = 42,
    strikes: Optional[ArrayLike] = None,
    until: str = "rest",
    noise: Optional[float] = None,
    max_events: int = 10_000,
    max_time: float = 600.0,
    chunk: Optional[int] = None,
    backend: str = "cpu",
    precision: Optional[str] = None,
    physics: PhysicsLike = None,
    physics_noise: Optional[Mapping[str, Any]] = None,
) -> Study:
    """A Monte Carlo shot study (``kisstime shots``): one table, one intended shot,
    ``samples`` noisy strikes drawn from ``seed`` (sample i's noise depends on (seed, i)
    only), every sample simulated from the strike to rest (``until="rest"``) or to the cue
    ball's first contact (``until="first-contact"``).

    ``scenario`` is anything :func:`kisstime.scenario` takes (default: the built-in study).
    ``strikes`` (a structured array of :data:`SAMPLE_STRIKE_DTYPE` or a dict of its
    columns) evaluates exactly those strikes without noise instead. ``noise`` multiplies the
    scenario's standard deviations (0 replays the intended shot). ``chunk`` samples run
    between two checks for Ctrl-C (default 16,384); the result does not depend on it.
    ``backend`` and ``precision`` are :func:`simulate`'s (the GPU runs each chunk's samples
    as one batch of tables). ``physics`` (what :func:`simulate` takes: a dict of pooltool's
    names or a TOML file; ``kisstime shots --physics``) replaces the scenario's own
    parameters (its ``[physics]`` table, or a ``.json`` scenario's ``ball_params``) as a
    whole; the layout is checked again with its ``R``. ``physics_noise`` varies the
    physics from sample to sample (the scenario's ``[noise.physics]``, ``kisstime shots
    --physics-noise``): a dict of pooltool's ball parameter names (not ``R``), each a
    relative spread (``{"u_r": 0.1}``: u_r drawn uniformly in ±10 % of its value) or a
    range ``[lo, hi]``; sample i's draw depends on (seed, i) only, and leaves its strike
    as it would be without it; ``noise`` scales it too.
    """
    sc = _with_physics(_scenario(scenario), physics, physics_noise)
    if isinstance(chunk, (int, np.integer)) and chunk < 1:
        raise ValueError(f"chunk {chunk}: at least 1")
    per = 16_384 if chunk is None else _count(chunk, "chunk")
    options = _study_options(seed, until, noise, max_events, max_time, backend, precision)
    if strikes is None:
        if isinstance(samples, (int, np.integer)) and samples < 1:
            raise ValueError(f"samples {samples}: at least 1")
        total = _count(samples, "samples")
        if total < 1:
            raise ValueError(f"samples {samples}: at least 1")
        _check_samples(total)
        blobs = [
            _study_chunk(sc, first, min(per, total - first), **options)
            for first in range(0, total, per)
        ]
        return _study_merge(sc, blobs, until=until)
    # the strikes are converted and checked once, as a whole (rows and repeated ids named
    # as in the file), then each chunk gets its own rows
    ids, nums = _strike_columns(strikes)
    total = len(ids)
    _study_chunk(sc, 0, 0, strikes={"sample": ids, **dict(zip(_STRIKE_FIELDS, nums))}, **options)
    blobs = []
    for first in range(0, total, per):
        rows = slice(first, first + per)
        part = {"sample": ids[rows], **{n: c[rows] for n, c in zip(_STRIKE_FIELDS, nums)}}
        blobs.append(_study_chunk(sc, 0, len(ids[rows]), strikes=part, **options))
    return _study_merge(sc, blobs, until=until)


#: The cue-noise presets ``plan(noise=...)`` takes (``kisstime::study::NOISE_PRESETS``):
#: ``fastfiz`` (the computational-pool tournaments' model: σ V0 0.075 m/s, φ 0.125°,
#: θ 0.1°, a and b 0.5 mm), ``club`` (twice that), ``casual`` (four times), ``none``.
NOISE_PRESETS = ("fastfiz", "club", "casual", "none")

_NOISE_KEYS = ("V0", "phi", "theta", "a", "b")


def _noise_arg(noise: Any) -> tuple:
    """A ``noise=`` argument as ``(preset, sigmas)``, one of them ``None``: a preset's name,
    or a dict of σ in pooltool's units keyed by :data:`_NOISE_KEYS` (missing ones 0)."""
    if isinstance(noise, str):
        return noise, None
    if isinstance(noise, Mapping):
        unknown = set(noise) - set(_NOISE_KEYS)
        if unknown:
            raise ValueError(f"noise: unknown keys {sorted(unknown)} (keys: {_NOISE_KEYS})")
        return None, tuple(float(noise.get(k, 0.0)) for k in _NOISE_KEYS)
    raise TypeError(f"noise: a preset name or a dict of sigmas, not {type(noise).__name__}")


@dataclass
class Plan:
    """The shot to play (:func:`plan`).

    Attributes:
        strike: The chosen strike in pooltool's ``Cue`` conventions: ``V0`` (m/s), ``phi``,
            ``theta`` (degrees), ``a``, ``b`` (fractions of the ball radius).
        ranked: The finalists, best first, each a dict: ``kind`` (``"pot"``, ``"bank"``,
            ``"combo"``, ``"kick"``, ``"safety"`` or ``"break"``), ``first`` (the ball the
            cue ball is to hit first), ``ball`` (the ball called) and ``pocket`` (ids;
            ``None`` on a break), ``cut`` (degrees), ``strike``, ``samples``, ``p_keep``,
            ``p_foul``, ``p_scratch`` (each ``[p, low, high]``: the 95 % Wilson interval),
            ``p_won``, ``p_lost``, ``position`` (the next shot's ease, 0 to 1, over the
            samples that keep the table), ``opponent`` (the opponent's next shot's ease
            over the legal misses) and ``value``; estimated on noise draws of their own,
            not those that chose them.
        candidates: Candidates tried (the refinement's strikes included).
        samples: Samples simulated in all.
        rounds: Rounds of successive halving.
        seconds: Wall-clock seconds.
        rules: The game.
        placement: With ``ball_in_hand`` or ``break_shot``: where to place the cue ball,
            ``(x, y)`` in m; else ``None``.
        refined: Of the candidates, the strikes the refinement drew.
    """

    strike: dict
    ranked: list
    candidates: int
    samples: int
    rounds: int
    seconds: float
    rules: str
    placement: Optional[tuple] = None
    refined: int = 0

    @property
    def best(self) -> dict:
        """The first of :attr:`ranked`."""
        return self.ranked[0]


def _plan_balls(balls: Any) -> tuple:
    """``balls=`` of :func:`plan` as (ids, xs, ys): a mapping ``{id: (x, y)}``, rows
    ``(id, x, y)``, or a :data:`BALL_DTYPE` array of one table (pocketed balls left out)."""
    if isinstance(balls, Mapping):
        ids = [int(k) for k in balls.keys()]
        xy = [tuple(v) for v in balls.values()]
        if any(len(v) != 2 for v in xy):
            raise ValueError("balls: each value must be (x, y)")
        return ids, [float(v[0]) for v in xy], [float(v[1]) for v in xy]
    arr = np.asarray(balls)
    if arr.dtype.names is not None:
        if len(np.unique(arr["table"])) > 1:
            raise ValueError("balls: plan takes one table's balls")
        arr = arr[arr["state"] != STATES["pocketed"]]
        return (
            [int(b) for b in arr["ball"]],
            [float(x) for x in arr["x"]],
            [float(y) for y in arr["y"]],
        )
    arr = np.asarray(balls, dtype=np.float64)
    if arr.ndim != 2 or arr.shape[1] != 3:
        raise ValueError(f"balls: expected rows (id, x, y), got shape {arr.shape}")
    if not np.all(arr[:, 0] == np.round(arr[:, 0])):
        raise ValueError("balls: ids must be integers")
    return [int(i) for i in arr[:, 0]], [float(x) for x in arr[:, 1]], [float(y) for y in arr[:, 2]]


def plan(
    balls: Any,
    *,
    rules: str,
    hittable: Optional[Sequence[int]] = None,
    table: TableLike = "9ft",
    physics: PhysicsLike = None,
    noise: Union[str, Mapping[str, float]] = "fastfiz",
    noise_scale: float = 1.0,
    budget_s: Optional[float] = 1.0,
    budget_samples: Optional[int] = None,
    seed: int = 1,
    top: int = 5,
    backend: str = "cpu",
    ball_in_hand: Optional[str] = None,
    break_shot: bool = False,
) -> Plan:
    """Which shot to play from an 8-ball or 9-ball position, under cue noise and the
    game's rules (``kisstime plan``; docs/plan.md).

    The planner tries each ball the player may hit into each pocket where the ghost-ball
    aim is playable, over speeds and spins, with one-rail banks, two-ball combinations,
    safeties and (with no ball on in straight reach) one-rail kicks; plays every candidate
    under the same noise draws, judged by the rules (8-ball: called on that ball and
    pocket), halving the field each round; refines the best three in the continuous strike
    (the cross-entropy method); then estimates the ``top`` finalists again on fresh draws.

    Args:
        balls: The position, every ball at rest: ``{id: (x, y)}``, rows ``(id, x, y)`` or
            a :data:`BALL_DTYPE` array of one table (pocketed balls are left out). Ids are
            the game's: 0 the cue ball, object balls their numbers.
        rules: ``"8-ball"`` or ``"9-ball"``.
        hittable: 8-ball: the player's group, the numbers of its balls on the table (a
            ball not on it is an error; an empty list: the group is down, the 8 is the
            ball on); ``None``: an open table. 9-ball works it out.
        table, physics: As :func:`simulate`'s.
        noise: A preset of :data:`NOISE_PRESETS`, or a dict of standard deviations in
            pooltool's units, ``{"V0": 0.1, "phi": 0.1, "theta": 0.1, "a": 0.003, "b":
            0.003}`` (m/s; degrees; fractions of the ball radius, as pooltool's ``Cue``).
        noise_scale: Every σ times this.
        budget_s: About this many seconds; or ``budget_samples`` (then ``budget_s=None``):
            at most this many samples, and the same seed gives the same plan.
        seed: The noise draws' seed.
        top: Finalists estimated again and returned.
        backend: ``"cpu"``, ``"gpu"`` or ``"auto"``.
        ball_in_hand: ``"anywhere"`` or ``"kitchen"`` (behind the head string): the cue
            ball is in hand, and the plan chooses its placement too (:attr:`Plan.placement`;
            a cue ball in ``balls`` is ignored, and may be left out). docs/plan.md.
        break_shot: Plan the break of the rack in ``balls``: the cue ball's spot behind the
            head string (:attr:`Plan.placement`) and the strike.

    Raises:
        ValueError: a game other than 8-ball and 9-ball, balls off the table or
            overlapping, no cue ball, a hittable ball not on the table, no playable direct
            pot, an unknown preset, a bad budget.
    """
    ids, xs, ys = _plan_balls(balls)
    name, text = _table(table)
    preset, sigma = _noise_arg(noise)
    if (budget_s is None) == (budget_samples is None):
        raise ValueError("give one budget: budget_s or budget_samples (with budget_s=None)")
    _quiet_mesa(backend)
    text_json = _kisstime.plan(
        ids,
        xs,
        ys,
        name,
        text,
        _physics(physics),
        rules,
        None if hittable is None else [int(h) for h in hittable],
        preset,
        sigma,
        float(noise_scale),
        None if budget_s is None else float(budget_s),
        None if budget_samples is None else int(budget_samples),
        int(seed),
        int(top),
        backend,
        ball_in_hand,
        bool(break_shot),
    )
    out = json.loads(text_json)
    return Plan(
        strike=out["strike"],
        ranked=out["ranked"],
        candidates=out["candidates"],
        samples=out["samples"],
        rounds=out["rounds"],
        seconds=out["seconds"],
        rules=out["rules"],
        placement=None if out.get("placement") is None else (out["placement"]["x"], out["placement"]["y"]),
        refined=out.get("refined", 0),
    )
