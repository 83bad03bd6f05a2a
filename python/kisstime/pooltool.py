"""pooltool interoperability: simulate a pooltool ``System`` with kisstime and compare events.

kisstime re-implements pooltool 0.6.0's event-based simulator. This module turns a
pooltool :class:`pooltool.System` into kisstime's inputs and kisstime's events back into
pooltool's terms, so that the two simulators can be run on the same shot and compared::

    import pooltool as pt
    import kisstime
    import kisstime.pooltool as kpt

    system = pt.System.example()                  # or any System at t = 0
    conv = kpt.from_system(system)                # balls, strike, table, ids
    result = conv.simulate()                      # kisstime.simulate on them
    mine = kpt.to_events(result, conv)            # [{"type", "time", "agents"}, ...]

    theirs = kpt.from_pooltool_events(pt.simulate(system))
    assert kpt.first_difference(mine, theirs) is None   # same events, times to 1e-9

or, with the pieces spelled out::

    path = conv.write_table("table.json")
    result = kisstime.simulate(conv.balls, conv.strikes, table=path)

**Ids.** kisstime's balls are integers. The i-th ball of ``system.balls`` (pooltool's
ball order, which decides exact ties in both simulators) gets id i, and
:attr:`Converted.ball_ids` keeps pooltool's id strings in that order. Cushion segments,
jaws and pockets are indices into the table's lists, which are written in the order of
pooltool's dicts (its detection order); :attr:`Converted.table_ids` keeps their ids.

**What is converted, and what kisstime assumes.** Every ball's *current* state
(``ball.state.rvw`` and ``ball.state.s``: convert a system before ``pt.simulate``, or
after ``system.reset_balls()``), the cue (``system.cue``: V0, phi, theta, a, b and
``cue_ball_id``), the table's geometry (every linear and circular cushion segment and
every pocket) and the physical parameters: the balls' ``BallParams`` (m, R, friction,
restitution, g; pooltool's names, :data:`kisstime.PHYSICS_KEYS`) and the cue's
``CueSpecs`` mass and end mass, as :attr:`Converted.physics`, which
:meth:`Converted.simulate` passes to ``kisstime.simulate(..., physics=...)``. kisstime
simulates every ball of a table with one set of ``BallParams``: :func:`from_system`
raises if the balls' differ (pooltool's own ``System`` validator demands one m and R).
The resolver is pooltool's default (version 9: frictional-inelastic ball-ball with
Alciatore friction, Stronge-compliant cushions, instantaneous-point stick with throttles
1); a non-default resolver (``~/.config/pooltool/physics/resolver.yaml`` or an
``engine=`` passed to ``pt.simulate``) cannot be seen from the ``System`` and is not
checked.

pooltool is an optional dependency, imported only when a function here needs it.
Install it with::

    pip install --no-deps pooltool-billiards==0.6.0
    pip install -r benches/pooltool_requirements.txt     # from a kisstime checkout
    pip install panda3d==1.10.16 panda3d-simplepbr==0.13.1

(pooltool's wheel pins a panda3d development build that PyPI does not have, hence
``--no-deps``; ``import pooltool`` imports panda3d and simplepbr, which PyPI's releases
satisfy. Nothing here renders.)
"""

from __future__ import annotations

import json
import math
import os
import tempfile
from dataclasses import dataclass, field
from typing import Any, Iterable, Sequence

import numpy as np

from . import EVENT_TYPES as _EVENT_TYPES
from . import PHYSICS_KEYS as _PHYSICS_KEYS

__all__ = [
    "EVENT_TYPES",
    "STATE_NAMES",
    "Converted",
    "from_system",
    "table_json",
    "to_events",
    "from_pooltool_events",
    "to_final",
    "from_pooltool_final",
    "first_difference",
]

#: kisstime's event type codes (the ``type`` column of the events array), in code order,
#: as pooltool's ``EventType`` values (the package's :data:`kisstime.EVENT_TYPES`).
EVENT_TYPES: tuple[str, ...] = _EVENT_TYPES

#: Motion state codes (kisstime's and pooltool's ``ball.state.s``), in code order.
STATE_NAMES: tuple[str, ...] = ("stationary", "spinning", "sliding", "rolling", "pocketed")

# The table section that each event type's second agent indexes (agent_b in .npy).
_SECTION_OF_TYPE = {
    2: "linear",
    3: "circular",
    4: "pockets",
}
_JSON_SECTIONS = (
    ("linear", "linear_cushion_segments"),
    ("circular", "circular_cushion_segments"),
    ("pockets", "pockets"),
)

_INSTALL = (
    "kisstime.pooltool needs pooltool 0.6.0 (pooltool-billiards). Install it with:\n"
    "    pip install --no-deps pooltool-billiards==0.6.0\n"
    "    pip install -r benches/pooltool_requirements.txt   # in a kisstime checkout\n"
    "    pip install panda3d==1.10.16 panda3d-simplepbr==0.13.1\n"
    "(pooltool's wheel pins a panda3d build that PyPI lacks, hence --no-deps.)"
)

# The cue's CueSpecs fields that the physics uses (the "cue" table of ``physics``).
_CUE_KEYS = ("M", "end_mass")


def _require_pooltool():
    """Imports pooltool, or raises an ImportError that says how to install it."""
    try:
        import pooltool
    except ImportError as e:  # pragma: no cover - depends on the environment
        raise ImportError(f"{_INSTALL}\n(import pooltool failed: {e})") from e
    return pooltool


def _kisstime():
    import kisstime

    return kisstime


@dataclass(frozen=True, eq=False)
class Converted:
    """A pooltool ``System`` as kisstime's inputs (what :func:`from_system` returns).

    Attributes:
        balls: One table's balls, a structured array of ``kisstime.BALL_DTYPE``
            (``table,ball,state,x,y,vx,vy,wx,wy,wz``), ball ids 0..n-1 in pooltool's
            ball order.
        strikes: The cue strike, a structured array of ``kisstime.STRIKE_DTYPE``
            (``table,ball,V0,phi,theta,a,b``) with one row when ``system.cue.V0 > 0``,
            else none. As in pooltool, the strike happens only if every ball is at rest.
        table: The system's table as JSON text in the format of ``table.json``
            (``linear_cushion_segments``, ``circular_cushion_segments``, ``pockets``),
            for ``kisstime.simulate(..., table=PATH)`` after :meth:`write_table`.
        ball_ids: pooltool's ball ids; ``ball_ids[i]`` is kisstime's ball ``i``.
        table_ids: pooltool's ids of the table's items in index order:
            ``{"linear": [...], "circular": [...], "pockets": [...]}`` (the form of
            ``kisstime.table_ids``).
        cue_id: pooltool's id of the cue stick (``system.cue.id``, ``"cue_stick"``),
            the first agent of a ``stick_ball`` event.
        table_id: The ``table`` column's value in :attr:`balls` and :attr:`strikes`.
        physics: The system's physical parameters with pooltool's names, what
            ``kisstime.simulate(..., physics=...)`` takes: the balls' ``BallParams``
            (``m, R, u_s, u_r, u_sp_proportionality, u_b, e_b, e_c, f_c, g``) and the cue's
            ``{"cue": {"M": ..., "end_mass": ...}}``. Empty: pooltool's defaults.
    """

    balls: np.ndarray
    strikes: np.ndarray
    table: str
    ball_ids: list[str]
    table_ids: dict[str, list[str]]
    cue_id: str = "cue_stick"
    table_id: int = 0
    physics: dict[str, Any] = field(default_factory=dict)
    _index: dict[str, int] = field(default_factory=dict, init=False, repr=False)

    def ball(self, pooltool_id: str) -> int:
        """kisstime's integer id of the ball whose pooltool id is ``pooltool_id``."""
        if not self._index:
            self._index.update({b: i for i, b in enumerate(self.ball_ids)})
        try:
            return self._index[pooltool_id]
        except KeyError:
            raise KeyError(f"no ball {pooltool_id!r} (balls: {self.ball_ids})") from None

    def write_table(self, path: str | os.PathLike) -> str:
        """Writes :attr:`table` (the JSON text) to ``path`` and returns the path as a str,
        ready for ``kisstime.simulate(..., table=path)`` or ``kisstime simulate --table``."""
        path = os.fspath(path)
        with open(path, "w", encoding="utf-8") as f:
            f.write(self.table)
        return path

    def simulate(self, **kwargs: Any):
        """``kisstime.simulate`` on these balls, this strike, this table and these
        physical parameters (:attr:`physics`).

        The table is written to a temporary file for the call. ``kwargs`` go to
        ``kisstime.simulate`` (``max_events``, ``max_time``, ``events``, ``backend``);
        ``table`` may be given to simulate on another table (``"9ft"``, ``"rectangle"`` or
        a path), but then pass the same ``layout`` to :func:`to_events`; ``physics``
        replaces :attr:`physics`.
        Returns the ``kisstime.SimResult``.
        """
        kisstime = _kisstime()
        kwargs.setdefault("physics", self.physics or None)
        strikes = self.strikes if len(self.strikes) else None
        if "table" in kwargs:
            return kisstime.simulate(self.balls, strikes, **kwargs)
        with tempfile.TemporaryDirectory(prefix="kisstime-pooltool-") as d:
            path = self.write_table(os.path.join(d, "table.json"))
            return kisstime.simulate(self.balls, strikes, table=path, **kwargs)


def _floats(v: Any, n: int, what: str) -> list[float]:
    """``v`` as a list of n finite Python floats (exact: no rounding)."""
    a = np.asarray(v, dtype=np.float64).reshape(-1)
    if a.shape != (n,):
        raise ValueError(f"{what}: expected {n} numbers, got {np.shape(v)}")
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{what}: non-finite value in {a.tolist()}")
    return [float(x) for x in a]


def _float(v: Any, what: str) -> float:
    x = float(v)
    if not math.isfinite(x):
        raise ValueError(f"{what}: non-finite value {x}")
    return x


def table_json(table: Any) -> str:
    """A pooltool ``Table`` as JSON text in the format of ``table.json`` (the table
    object itself), which ``kisstime.simulate(..., table=PATH)`` reads.

    ``linear_cushion_segments`` is ``{id: {"p1": [x, y, z], "p2": [x, y, z],
    "direction": 0|1|2}}``, ``circular_cushion_segments`` ``{id: {"center": [x, y, z],
    "radius": r}}`` and ``pockets`` ``{id: {"center": [x, y, z], "radius": r, "depth":
    d}}``, each in the order of pooltool's dicts (its detection order, which kisstime
    keeps). Floats are written with ``repr``, so they read back exactly. Raises
    ValueError on a non-finite number or an unknown cushion direction.
    """
    segs = table.cushion_segments
    linear = {}
    for sid, s in segs.linear.items():
        d = int(s.direction)
        if d not in (0, 1, 2) or d != s.direction:
            raise ValueError(f"linear segment {sid}: direction {s.direction!r}")
        linear[str(sid)] = {
            "p1": _floats(s.p1, 3, f"linear segment {sid} p1"),
            "p2": _floats(s.p2, 3, f"linear segment {sid} p2"),
            "direction": d,
        }
    circular = {
        str(cid): {
            "center": _floats(c.center, 3, f"circular segment {cid} center"),
            "radius": _float(c.radius, f"circular segment {cid} radius"),
        }
        for cid, c in segs.circular.items()
    }
    pockets = {
        str(pid): {
            "center": _floats(p.center, 3, f"pocket {pid} center"),
            "radius": _float(p.radius, f"pocket {pid} radius"),
            "depth": _float(p.depth, f"pocket {pid} depth"),
        }
        for pid, p in table.pockets.items()
    }
    doc = {
        "linear_cushion_segments": linear,
        "circular_cushion_segments": circular,
        "pockets": pockets,
    }
    return json.dumps(doc, indent=1, allow_nan=False)


def _physics_of(system: Any, check: bool) -> dict[str, Any]:
    """The system's physical parameters with pooltool's names (:attr:`Converted.physics`):
    the balls' shared ``BallParams`` and the cue's mass and end mass. With ``check``, every
    ball must have the first ball's parameters (else ValueError naming the ball and field);
    without, the first ball's are taken."""
    balls = list(system.balls.items())
    first_id, first = balls[0]
    params = {name: float(getattr(first.params, name)) for name in _PHYSICS_KEYS}
    if check:
        bad = []
        for bid, ball in balls[1:]:
            for name, want in params.items():
                got = float(getattr(ball.params, name))
                if got != want and not (got != got and want != want):
                    bad.append(f"ball {bid!r} {name} = {got!r} (ball {first_id!r}: {want!r})")
        if bad:
            raise ValueError(
                "kisstime simulates every ball of a table with the same BallParams; this "
                "system's balls differ (pass check=False to take the first ball's):\n  "
                + "\n  ".join(bad)
            )
    specs = system.cue.specs
    params["cue"] = {name: float(getattr(specs, name)) for name in _CUE_KEYS}
    return params


def from_system(system: Any, table: int = 0, *, check: bool = True) -> Converted:
    """A pooltool 0.6.0 ``System`` as kisstime's inputs: a :class:`Converted`.

    Args:
        system: The ``pooltool.System``. Every ball's current state is taken
            (``ball.state.rvw``: x, y from ``rvw[0]``, vx, vy from ``rvw[1]``, wx, wy, wz
            from ``rvw[2]``; ``ball.state.s`` the motion state), so convert a system
            before simulating it (or after ``system.reset_balls()``). The balls get ids
            0..n-1 in ``system.balls`` order. ``system.cue`` becomes a strike when its
            V0 > 0 (on ``cue.cue_ball_id``, with its phi, theta, a, b); like pooltool,
            kisstime applies it at t = 0 only if every ball is at rest.
        table: The ``table`` id written in the balls and the strike.
        check: Raise ValueError if the balls' ``BallParams`` differ from one another
            (kisstime simulates a table with one set; False: take the first ball's).

    Returns:
        A :class:`Converted` with ``balls``, ``strikes``, ``table`` (JSON text),
        ``ball_ids``, ``table_ids``, ``cue_id``, ``table_id`` and ``physics`` (the balls'
        ``BallParams`` and the cue's ``CueSpecs`` with pooltool's names, which
        :meth:`Converted.simulate` uses; any values, not only pooltool's defaults).

    Raises:
        ImportError: pooltool is not installed.
        ValueError: no balls, a bad motion state or a non-finite number, a cue ball
            that is not on the table, or (with ``check``) balls with different
            ``BallParams``. Parameters out of range are refused when simulating, with the
            command line's message (``kisstime.simulate``'s ``physics``).
    """
    _require_pooltool()
    kisstime = _kisstime()
    table = int(table)
    ball_ids = [str(b) for b in system.balls.keys()]
    if not ball_ids:
        raise ValueError("the system has no balls")
    physics = _physics_of(system, check)

    balls = np.zeros(len(ball_ids), dtype=kisstime.BALL_DTYPE)
    for i, (bid, ball) in enumerate(system.balls.items()):
        rvw = np.asarray(ball.state.rvw, dtype=np.float64)
        if rvw.shape != (3, 3):
            raise ValueError(f"ball {bid!r}: rvw has shape {rvw.shape}, not (3, 3)")
        s = int(ball.state.s)
        if not 0 <= s < len(STATE_NAMES):
            raise ValueError(f"ball {bid!r}: motion state {ball.state.s!r} (0..4)")
        x, y = _floats(rvw[0, :2], 2, f"ball {bid!r} position")
        vx, vy = _floats(rvw[1, :2], 2, f"ball {bid!r} velocity")
        wx, wy, wz = _floats(rvw[2], 3, f"ball {bid!r} angular velocity")
        balls[i] = (table, i, s, x, y, vx, vy, wx, wy, wz)

    cue = system.cue
    rows = []
    if float(cue.V0) > 0:
        cue_ball = str(cue.cue_ball_id)
        if cue_ball not in ball_ids:
            raise ValueError(f"cue_ball_id {cue_ball!r} is not a ball (balls: {ball_ids})")
        rows.append(
            (
                table,
                ball_ids.index(cue_ball),
                _float(cue.V0, "cue V0"),
                _float(cue.phi, "cue phi"),
                _float(cue.theta, "cue theta"),
                _float(cue.a, "cue a"),
                _float(cue.b, "cue b"),
            )
        )
    strikes = np.array(rows, dtype=kisstime.STRIKE_DTYPE)

    pt_table = system.table
    table_ids = {
        "linear": [str(k) for k in pt_table.cushion_segments.linear.keys()],
        "circular": [str(k) for k in pt_table.cushion_segments.circular.keys()],
        "pockets": [str(k) for k in pt_table.pockets.keys()],
    }
    return Converted(
        balls=balls,
        strikes=strikes,
        table=table_json(pt_table),
        ball_ids=ball_ids,
        table_ids=table_ids,
        cue_id=str(cue.id),
        table_id=table,
        physics=physics,
    )


def _ids_of_layout(layout: str | os.PathLike) -> dict[str, list[str]]:
    """The item ids of the table kisstime simulated on (``kisstime.table_ids``)."""
    ids = _kisstime().table_ids(os.fspath(layout))
    return {k: [str(x) for x in ids.get(k, [])] for k, _ in _JSON_SECTIONS}


def to_events(
    result: Any,
    converted: Converted,
    table: int | None = None,
    *,
    layout: str | os.PathLike | None = None,
) -> list[dict[str, Any]]:
    """kisstime's events of one table in pooltool's terms, one dict per event, in order.

    Each event is ``{"type": "ball_ball", "time": 0.2238..., "agents": ("1", "cue")}``:
    ``type`` is pooltool's ``EventType`` value, ``time`` the event time in s and
    ``agents`` pooltool's agent ids in pooltool's order: ``(cue_id, ball)`` for
    ``stick_ball``, the pair for ``ball_ball``, ``(ball, segment)``, ``(ball, jaw)`` or
    ``(ball, pocket)`` for the cushion and pocket events, ``(ball,)`` for transitions.
    This is the form of :func:`from_pooltool_events`, so comparing the two lists (with
    :func:`first_difference`, times to a tolerance) compares the simulators.

    Args:
        result: A ``kisstime.SimResult`` (its ``events``), or the events array itself
            (e.g. ``np.load`` of ``kisstime simulate -o events.npy``). Its two rows of a
            ball-ball event are merged into one event.
        converted: The :class:`Converted` the inputs came from (ball ids, cue id).
        table: Which table's events (default: ``converted.table_id``).
        layout: The table that was simulated, if not ``converted``'s own: ``"9ft"``,
            ``"rectangle"`` or a JSON path; cushion and pocket indices are turned into
            ids through its lists. None: ``converted.table_ids``.

    Raises:
        ValueError: the events name a ball, cushion or pocket index that the
            conversion does not know, or an unknown event type.
    """
    events = getattr(result, "events", result)
    if events is None:
        raise ValueError("the result has no events (simulate with events=True)")
    events = np.asarray(events)
    tid = converted.table_id if table is None else int(table)
    ids = converted.table_ids if layout is None else _ids_of_layout(layout)
    rows = events[events["table"] == tid]
    if len(rows) == 0:
        return []
    k = rows["k"]
    first = np.ones(len(rows), dtype=bool)
    first[1:] = k[1:] != k[:-1]
    rows = rows[first]

    names = converted.ball_ids

    def ball(i: int) -> str:
        if not 0 <= i < len(names):
            raise ValueError(f"ball id {i} is not one of the {len(names)} converted balls")
        return names[i]

    def item(section: str, i: int) -> str:
        lst = ids.get(section, [])
        if not 0 <= i < len(lst):
            raise ValueError(f"{section} index {i}: the table has {len(lst)}")
        return lst[i]

    out = []
    for typ, t, a, b in zip(
        rows["type"].tolist(), rows["t"].tolist(), rows["agent_a"].tolist(), rows["agent_b"].tolist()
    ):
        if not 0 <= typ < len(EVENT_TYPES):
            raise ValueError(f"unknown event type code {typ}")
        if typ == 0:
            agents = (converted.cue_id, ball(a))
        elif typ == 1:
            agents = (ball(a), ball(b))
        elif typ in _SECTION_OF_TYPE:
            agents = (ball(a), item(_SECTION_OF_TYPE[typ], b))
        else:
            agents = (ball(a),)
        out.append({"type": EVENT_TYPES[typ], "time": float(t), "agents": agents})
    return out


def from_pooltool_events(system: Any) -> list[dict[str, Any]]:
    """A simulated pooltool ``System``'s events in the form of :func:`to_events`.

    One ``{"type", "time", "agents"}`` dict per event of ``system.events``, in order,
    without pooltool's ``none`` events (the initial and the terminal one): ``type`` the
    ``EventType`` value, ``time`` the event time, ``agents`` the agents' ids.
    """
    _require_pooltool()
    from pooltool.events import EventType

    none = EventType.NONE
    out = []
    for e in system.events:
        if e.event_type == none:
            continue
        out.append(
            {
                "type": str(e.event_type.value),
                "time": float(e.time),
                "agents": tuple(str(a.id) for a in e.agents),
            }
        )
    return out


def to_final(
    result: Any,
    converted: Converted,
    table: int | None = None,
    *,
    layout: str | os.PathLike | None = None,
) -> dict[str, dict[str, Any]]:
    """kisstime's final ball states of one table, by pooltool ball id.

    ``{ball_id: {"state": "stationary", "x": ..., "y": ..., "vx": ..., "vy": ...,
    "wx": ..., "wy": ..., "wz": ..., "pocket": "rc" or None}}`` in ball order, the
    form of :func:`from_pooltool_final`. ``state`` is the motion state's name,
    ``pocket`` the pocket's id for a pocketed ball. Arguments as for :func:`to_events`
    (``result`` a ``kisstime.SimResult`` or its ``final`` array).
    """
    final = getattr(result, "final", result)
    final = np.asarray(final)
    tid = converted.table_id if table is None else int(table)
    ids = converted.table_ids if layout is None else _ids_of_layout(layout)
    pockets = ids.get("pockets", [])
    out = {}
    for r in final[final["table"] == tid]:
        i, p = int(r["ball"]), int(r["pocket"])
        if not 0 <= i < len(converted.ball_ids):
            raise ValueError(f"ball id {i} is not one of the converted balls")
        if p >= len(pockets):
            raise ValueError(f"pocket index {p}: the table has {len(pockets)}")
        out[converted.ball_ids[i]] = {
            "state": STATE_NAMES[int(r["state"])],
            **{c: float(r[c]) for c in ("x", "y", "vx", "vy", "wx", "wy", "wz")},
            "pocket": pockets[p] if p >= 0 else None,
        }
    return out


def from_pooltool_final(system: Any) -> dict[str, dict[str, Any]]:
    """A pooltool ``System``'s current ball states in the form of :func:`to_final`.

    ``state`` is the name of ``ball.state.s``, x, y, vx, vy, wx, wy, wz come from
    ``ball.state.rvw``, and ``pocket`` is the id of the pocket that holds the ball
    (``pocket.contains``), else None.
    """
    _require_pooltool()
    holder = {}
    for pid, pocket in system.table.pockets.items():
        for bid in pocket.contains:
            holder[str(bid)] = str(pid)
    out = {}
    for bid, ball in system.balls.items():
        rvw = np.asarray(ball.state.rvw, dtype=np.float64)
        vals = (rvw[0, 0], rvw[0, 1], rvw[1, 0], rvw[1, 1], rvw[2, 0], rvw[2, 1], rvw[2, 2])
        out[str(bid)] = {
            "state": STATE_NAMES[int(ball.state.s)],
            **{c: float(v) for c, v in zip(("x", "y", "vx", "vy", "wx", "wy", "wz"), vals)},
            "pocket": holder.get(str(bid)),
        }
    return out


def _same_agents(x: dict, y: dict, unordered_pairs: bool) -> bool:
    if x["type"] != y["type"]:
        return False
    a, b = tuple(x["agents"]), tuple(y["agents"])
    if unordered_pairs and x["type"] == "ball_ball":
        return sorted(a) == sorted(b)
    return a == b


def first_difference(
    a: Sequence[dict] | Iterable[dict],
    b: Sequence[dict] | Iterable[dict],
    *,
    rel_tol: float = 1e-9,
    abs_tol: float = 1e-9,
    unordered_pairs: bool = False,
) -> int | None:
    """The index of the first event where two event lists differ, or None if they agree.

    Events agree when their ``type`` and ``agents`` are equal and their times are within
    ``math.isclose(ta, tb, rel_tol=rel_tol, abs_tol=abs_tol)``. With ``unordered_pairs``,
    a ``ball_ball`` event's two balls may come in either order (as the fullshots checker
    compares them). When one list is a prefix of the other, the index is the shorter
    one's length.
    """
    a, b = list(a), list(b)
    for i, (x, y) in enumerate(zip(a, b)):
        if not _same_agents(x, y, unordered_pairs):
            return i
        if not math.isclose(x["time"], y["time"], rel_tol=rel_tol, abs_tol=abs_tol):
            return i
    if len(a) != len(b):
        return min(len(a), len(b))
    return None
