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

or, with the pieces spelled out (the table as JSON text, a pooltool ``Table`` object or a
path: no file needed)::

    result = kisstime.simulate(conv.balls, conv.strikes, table=system.table,
                               physics=conv.physics)

**At batch scale.** :func:`simulate_strikes` fans one position out into many strikes in
one call (no per-strike Python), :func:`simulate_systems` runs several ``System`` objects (each
with its own table and ``BallParams``), and both return a :class:`BatchResult` of NumPy
arrays::

    rng = np.random.default_rng(0)
    n = 10_000
    noisy = {"V0": 2.0 + rng.normal(0, 0.15, n), "phi": 62.5 + rng.normal(0, 1.0, n)}
    res = kpt.simulate_strikes(system, noisy)     # columns left out: system.cue's values
    potted = res.pocketed[:, res.ball_ids.index("1")]        # (n,) bools
    cue_x = res.final_states["x"][:, res.ball_ids.index("cue")]
    res.to_events(17), res.to_final(17)           # one shot in from_pooltool_*'s form

    res = kpt.simulate_strikes(system, noisy, on_error="report")
    res.ok, res.errors                            # bad strikes flagged, the rest simulated

**Tables.** Wherever a table is taken (``kisstime.simulate``, ``table_ids``,
``Converted.simulate``, the batch form, ``layout=``): a pooltool ``Table`` object (pocket,
snooker or billiard), JSON text (what :func:`table_json` produces), a path, or a built-in
name: ``"7ft"`` (pooltool's ``Table.default()``), ``"9ft"`` (``PocketTableSpecs(l=2.54,
w=1.27)``), ``"rectangle"``.

**Pocketed balls.** :func:`from_pooltool_final` reads a ball's pocket from its own state
(a pocketed ball lies at its pocket's centre), not from ``pocket.contains``: pooltool's
pockets keep the balls of every shot simulated on that ``Table`` object, so on a reused
table a re-spotted cue ball would still show as pocketed there.

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
import weakref
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
    "BatchResult",
    "simulate_strikes",
    "simulate_systems",
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
            which ``kisstime.simulate(..., table=...)`` takes as it is (or as a file,
            :meth:`write_table`, for ``kisstime simulate --table``).
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

    def simulate(
        self,
        *,
        rules: str | None = None,
        break_shot: bool = False,
        hittable: Sequence[str] | None = None,
        ball_call: str | None = None,
        pocket_call: str | None = None,
        score: tuple[int, int] = (0, 0),
        **kwargs: Any,
    ):
        """``kisstime.simulate`` on these balls, this strike, this table and these
        physical parameters (:attr:`physics`).

        With ``rules`` (``"9-ball"``, ``"8-ball"``, ``"snooker"``) the shot is judged as
        pooltool 0.6.0's rule set judges it, in pooltool's terms: ``break_shot``,
        ``hittable`` (the ball ids the player may hit first: 8-ball's group, snooker's
        ``BallGroup.REDS.balls``, ``COLORS.balls`` or the one colour on; ``None``: an open
        table, or snooker's balls on worked out from the table; 9-ball works it out),
        ``ball_call`` and ``pocket_call`` (pooltool's ids, e.g. ``"3"``, ``"black"``,
        ``"rt"``; 8-ball asks every shot but the break to be called; snooker on several
        colours asks for ``ball_call``) and ``score`` (the points of the player who shoots
        and of the opponent before the shot: snooker's and three-cushion's winner). The
        verdict is in the result's ``outcomes``: ``legal``, ``foul`` (an index in
        ``kisstime.FOULS``, -1 for none), ``turn_over``, ``game_over``, ``won``,
        ``points``, ``foul_points``. The balls must be pooltool's pool balls (``"cue"`` and
        the numbered ``"1"`` to ``"15"``) or snooker's (``"white"``, ``"red_01"`` to
        ``"red_15"``, ``"yellow"`` … ``"black"``). With ``rules="three-cushion"`` any
        balls go (the cue ball is the one struck) and of the context only ``score`` is
        used: the shot scores a point exactly when ``turn_over`` is false (pooltool's
        ``three_cushion.is_point``), and the game is won at 10.

        The table goes as JSON text (no file is written). ``kwargs`` go to
        ``kisstime.simulate`` (``max_events``, ``max_time``, ``events``, ``backend``);
        ``table`` may be given to simulate on another table (``"9ft"``, ``"7ft"``,
        ``"rectangle"``, a path, JSON text or a pooltool ``Table``), but then pass the same
        ``layout`` to :func:`to_events`; ``physics`` replaces :attr:`physics`.
        Returns the ``kisstime.SimResult``.
        """
        kisstime = _kisstime()
        kwargs.setdefault("physics", self.physics or None)
        kwargs.setdefault("table", self.table)
        strikes = self.strikes if len(self.strikes) else None
        score_cols = {"score": [int(score[0])], "opponent_score": [int(score[1])]}
        if rules == "three-cushion":
            # the point needs no ball numbers: the cue ball is the one struck
            kwargs["rules"] = rules
            kwargs["context"] = {"table": [self.table_id], **score_cols}
        elif rules is not None:
            game = {}
            for i, b in enumerate(self.ball_ids):
                if rules == "snooker":
                    if b not in _SNOOKER_IDS:
                        raise ValueError(
                            f"ball {b!r}: snooker takes the balls 'white', 'red_01' to "
                            f"'red_15', {', '.join(repr(c) for c in _SNOOKER_IDS[16:])}"
                        )
                    game[i] = _SNOOKER_IDS.index(b)
                elif b == "cue":
                    game[i] = 0
                elif b.isdigit() and 1 <= int(b) <= 15:
                    game[i] = int(b)
                else:
                    raise ValueError(
                        f"ball {b!r}: the pool rules take the balls 'cue' and '1' to '15'"
                    )

            def number(b: str, what: str) -> int:
                if b not in self.ball_ids:
                    raise ValueError(f"{what} {b!r} is not a ball (balls: {self.ball_ids})")
                return game[self.ball(b)]

            kwargs["rules"] = rules
            kwargs["_rule_ids"] = game
            kwargs["context"] = {
                "table": [self.table_id],
                "break": [bool(break_shot)],
                "hittable": [_hittable(hittable, self.ball_ids, number)],
                "ball_call": [-1 if ball_call is None else number(ball_call, "ball_call")],
                "pocket_call": [pocket_call or ""],
                **score_cols,
            }
        return kisstime.simulate(self.balls, strikes, **kwargs)


# snooker's pooltool ball ids, index = kisstime's id (kisstime.game::snooker)
_SNOOKER_IDS = (
    "white",
    *(f"red_{i:02d}" for i in range(1, 16)),
    "yellow",
    "green",
    "brown",
    "blue",
    "pink",
    "black",
)


def _hittable(hittable, ball_ids, number) -> Any:
    """pooltool's ``hittable`` as the context's: the numbers of those of its balls that are
    in the system (pooltool's groups name balls a position may lack), or ``""`` (an open
    table) for ``None``."""
    if not hittable:
        return ""
    present = [number(b, "hittable") for b in hittable if b in ball_ids]
    if not present:
        raise ValueError(f"hittable {tuple(hittable)}: none of them is a ball ({ball_ids})")
    return present


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
    """A pooltool ``Table`` (pocket, snooker or billiard) as JSON text in the format of
    ``table.json`` (the table object itself), which ``kisstime.simulate(..., table=...)``
    takes as text or from a file (``kisstime simulate --table FILE``).

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


def _ball_params(balls: Any, check: bool) -> dict[str, Any]:
    """The ``BallParams`` of pooltool's ``{id: Ball}`` with pooltool's names: the first
    ball's; with ``check`` every ball must have them (else ValueError naming the ball and
    field)."""
    items = list(balls.items())
    first_id, first = items[0]
    params = {name: float(getattr(first.params, name)) for name in _PHYSICS_KEYS}
    if check:
        bad = []
        for bid, ball in items[1:]:
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
    return params


def _physics_of(system: Any, check: bool) -> dict[str, Any]:
    """The system's physical parameters with pooltool's names (:attr:`Converted.physics`):
    the balls' shared ``BallParams`` and the cue's mass and end mass. With ``check``, every
    ball must have the first ball's parameters (else ValueError naming the ball and field);
    without, the first ball's are taken."""
    params = _ball_params(system.balls, check)
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


def _ids_of_layout(layout: Any) -> dict[str, list[str]]:
    """The item ids of the table kisstime simulated on (``kisstime.table_ids``: a name, a
    path, JSON text or a pooltool ``Table``)."""
    ids = _kisstime().table_ids(layout)
    return {k: [str(x) for x in ids.get(k, [])] for k, _ in _JSON_SECTIONS}


# Row offsets of each table in an output array, per array (arrays are not hashable: by id,
# with a weak reference that says whether the id is still that array's).
_OFFSETS: dict[int, tuple[Any, np.ndarray, np.ndarray]] = {}


def _table_rows(arr: np.ndarray, tid: int) -> np.ndarray:
    """The rows of table ``tid`` of a kisstime output (``events`` or ``final``): a slice
    when the rows come in ascending table order (kisstime's outputs always do; the
    tables' starts are found once per array, then each call is a binary search), else a
    boolean mask."""
    key = id(arr)
    hit = _OFFSETS.get(key)
    if hit is None or hit[0]() is not arr:
        tables = arr["table"]
        if len(tables) > 1 and not bool(np.all(tables[1:] >= tables[:-1])):
            return arr[tables == tid]
        ids, starts = np.unique(tables, return_index=True)
        starts = np.append(starts, len(tables))
        try:
            ref = weakref.ref(arr, lambda _r, key=key: _OFFSETS.pop(key, None))
        except TypeError:  # pragma: no cover - ndarrays take weak references
            return arr[tables == tid]
        _OFFSETS[key] = hit = (ref, ids, starts)
    _, ids, starts = hit
    i = int(np.searchsorted(ids, tid))
    if i == len(ids) or ids[i] != tid:
        return arr[:0]
    return arr[starts[i] : starts[i + 1]]


def _event_dicts(
    rows: np.ndarray, names: Sequence[str], cue_id: str, ids: dict[str, list[str]]
) -> list[dict[str, Any]]:
    """One table's event rows as :func:`to_events`' dicts."""
    if len(rows) == 0:
        return []
    k = rows["k"]
    first = np.ones(len(rows), dtype=bool)
    first[1:] = k[1:] != k[:-1]
    rows = rows[first]

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
            agents = (cue_id, ball(a))
        elif typ == 1:
            agents = (ball(a), ball(b))
        elif typ in _SECTION_OF_TYPE:
            agents = (ball(a), item(_SECTION_OF_TYPE[typ], b))
        else:
            agents = (ball(a),)
        out.append({"type": EVENT_TYPES[typ], "time": float(t), "agents": agents})
    return out


def _final_dicts(
    rows: np.ndarray, names: Sequence[str], pockets: Sequence[str]
) -> dict[str, dict[str, Any]]:
    """One table's final rows as :func:`to_final`'s dict."""
    out = {}
    for r in rows:
        i, p = int(r["ball"]), int(r["pocket"])
        if i < 0:
            continue  # padding of a batch's dense array
        if not 0 <= i < len(names):
            raise ValueError(f"ball id {i} is not one of the converted balls")
        if p >= len(pockets):
            raise ValueError(f"pocket index {p}: the table has {len(pockets)}")
        out[names[i]] = {
            "state": STATE_NAMES[int(r["state"])],
            **{c: float(r[c]) for c in ("x", "y", "vx", "vy", "wx", "wy", "wz")},
            "pocket": pockets[p] if p >= 0 else None,
        }
    return out


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
        layout: The table that was simulated, if not ``converted``'s own: what
            ``kisstime.simulate``'s ``table`` takes (a name, a JSON path or text, a
            pooltool ``Table``); cushion and pocket indices are turned into ids through its
            lists. None: ``converted.table_ids``.

    Fast for one table of a big result: the tables' row offsets are found once per array,
    then each call costs its own table's rows. For a whole batch, :func:`simulate_strikes`'
    :class:`BatchResult` gives NumPy arrays.

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
    return _event_dicts(_table_rows(events, tid), converted.ball_ids, converted.cue_id, ids)


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
    final = np.asarray(getattr(result, "final", result))
    tid = converted.table_id if table is None else int(table)
    ids = converted.table_ids if layout is None else _ids_of_layout(layout)
    return _final_dicts(_table_rows(final, tid), converted.ball_ids, ids.get("pockets", []))


def from_pooltool_final(system: Any) -> dict[str, dict[str, Any]]:
    """A pooltool ``System``'s current ball states in the form of :func:`to_final`.

    ``state`` is the name of ``ball.state.s``, x, y, vx, vy, wx, wy, wz come from
    ``ball.state.rvw``, and ``pocket`` is, for a pocketed ball, the id of the pocket it
    lies in, else None. The pocket is read from the ball's own state (pooltool puts a
    pocketed ball at its pocket's centre, ``(pocket.a, pocket.b)``; the nearest pocket
    if none is exactly there), not from ``pocket.contains``: a table's pockets keep the
    balls of every shot simulated on it, so on a reused table a re-spotted cue ball
    would still show as pocketed.
    """
    _require_pooltool()
    centres = [
        (str(pid), float(p.center[0]), float(p.center[1]))
        for pid, p in system.table.pockets.items()
    ]
    pocketed = STATE_NAMES.index("pocketed")
    out = {}
    for bid, ball in system.balls.items():
        rvw = np.asarray(ball.state.rvw, dtype=np.float64)
        vals = (rvw[0, 0], rvw[0, 1], rvw[1, 0], rvw[1, 1], rvw[2, 0], rvw[2, 1], rvw[2, 2])
        pocket = None
        if int(ball.state.s) == pocketed and centres:
            x, y = float(rvw[0, 0]), float(rvw[0, 1])
            pocket = min(centres, key=lambda c: (c[1] - x) ** 2 + (c[2] - y) ** 2)[0]
        out[str(bid)] = {
            "state": STATE_NAMES[int(ball.state.s)],
            **{c: float(v) for c, v in zip(("x", "y", "vx", "vy", "wx", "wy", "wz"), vals)},
            "pocket": pocket,
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


# ----------------------------------------------------------------------- the batch form

_STRIKE_COLUMNS = ("V0", "phi", "theta", "a", "b")
_ON_ERROR = ("raise", "report")


class BatchResult:
    """What :func:`simulate_strikes` and :func:`simulate_systems` return: N shots
    (``len(result)``), shot ``k`` being position ``position[k]`` struck by row ``k`` of the
    strikes, as NumPy arrays.

    Attributes:
        final_states: Every shot's final ball states, a structured array of shape
            ``(N, B)`` (B: the most balls of a position) with ``SimResult.final``'s fields
            (``table`` the shot, ``ball`` kisstime's ball index, ``state``, ``x``, ``y``,
            ``vx``, ``vy``, ``wx``, ``wy``, ``wz``, ``pocket``): ``final_states["x"][:, i]``
            is ball i's final x in every shot. Entries with no ball (a shot that was not
            simulated, or padding past a position's balls) have ``ball = state = pocket =
            -1`` and NaN numbers.
        outcomes: One row per shot (``table, events, t_end, cut``; a shot not simulated
            has ``events = 0``, ``t_end = NaN`` and ``cut = -1``).
        events: Every event of every shot, ``SimResult.events``' rows (``table`` the shot),
            shots in order; None unless simulated with ``events=True``.
            ``events[event_offsets[k]:event_offsets[k + 1]]`` are shot k's rows.
        event_offsets: ``N + 1`` row offsets into :attr:`events` (None without events).
        final: The final states as ``SimResult.final`` rows (simulated shots only).
        status: Per shot, ``""`` if it was simulated, else why not (``on_error="report"``),
            a NumPy str array; :attr:`ok` is ``status == ""`` and :attr:`errors` the
            ``{shot: message}`` of the others.
        position: Per shot, the index of its position in :attr:`positions`.
        positions: The :class:`Converted` positions (None for a system that did not
            convert, with ``on_error="report"``).
    """

    def __init__(self, positions, position, events, final, outcomes, status, table_ids):
        self.positions: list[Converted | None] = positions
        self.position: np.ndarray = position
        self.final: np.ndarray = final
        self.status: np.ndarray = status
        self._table_ids: list[dict[str, list[str]] | None] = table_ids
        n = len(position)
        width = max((len(c.ball_ids) for c in positions if c is not None), default=0)
        dense = np.empty((n, width), dtype=final.dtype)
        for name in final.dtype.names:
            dense[name] = np.nan if final.dtype[name].kind == "f" else -1
        dense["table"] = np.arange(n)[:, None]
        dense[final["table"], final["ball"]] = final
        self.final_states: np.ndarray = dense
        full = np.empty(n, dtype=outcomes.dtype)
        full["table"] = np.arange(n)
        full["events"] = 0
        full["t_end"] = np.nan
        full["cut"] = -1
        full[outcomes["table"]] = outcomes
        self.outcomes: np.ndarray = full
        self.events: np.ndarray | None = events
        self.event_offsets: np.ndarray | None = (
            None if events is None else np.searchsorted(events["table"], np.arange(n + 1))
        )

    def __len__(self) -> int:
        return len(self.position)

    def __repr__(self) -> str:
        bad = int(np.count_nonzero(~self.ok))
        ev = "" if self.events is None else f", {len(self.events)} event rows"
        return f"<kisstime.pooltool.BatchResult: {len(self)} shots, {bad} not simulated{ev}>"

    @property
    def ok(self) -> np.ndarray:
        """Per shot, whether it was simulated."""
        return self.status == ""

    @property
    def errors(self) -> dict[int, str]:
        """``{shot: message}`` of the shots that were not simulated."""
        bad = np.flatnonzero(~self.ok)
        return {int(k): str(self.status[k]) for k in bad}

    @property
    def ball_ids(self) -> list[str]:
        """pooltool's ball ids, ``ball_ids[i]`` being ball index i (one position only;
        else :meth:`ball_ids_of`)."""
        convs = {id(c): c for c in self.positions if c is not None}
        if len(self.positions) != 1 or not convs:
            raise ValueError("several positions: use ball_ids_of(shot)")
        return list(self.positions[0].ball_ids)

    def converted(self, shot: int) -> Converted:
        """The :class:`Converted` position of a shot."""
        conv = self.positions[int(self.position[shot])]
        if conv is None:
            raise ValueError(f"shot {shot}: {self.status[shot]}")
        return conv

    def ball_ids_of(self, shot: int) -> list[str]:
        """pooltool's ball ids of a shot's position."""
        return list(self.converted(shot).ball_ids)

    def table_ids_of(self, shot: int) -> dict[str, list[str]]:
        """The ids of the cushions, jaws and pockets of the table a shot was simulated on."""
        ids = self._table_ids[int(self.position[shot])]
        if ids is None:
            raise ValueError(f"shot {shot}: {self.status[shot]}")
        return ids

    @property
    def pocketed(self) -> np.ndarray:
        """``(N, B)`` bools: the ball ended in a pocket."""
        return self.final_states["state"] == STATE_NAMES.index("pocketed")

    def pocket_names(self) -> np.ndarray:
        """``(N, B)`` object array: the pooltool id of the pocket each ball ended in, or
        None (vectorised per table)."""
        out = np.full(self.final_states.shape, None, dtype=object)
        pockets = self.final_states["pocket"]
        for p, ids in enumerate(self._table_ids):
            if ids is None:
                continue
            names = np.array(list(ids["pockets"]) + [None], dtype=object)
            rows = self.position == p
            sel = pockets[rows]
            out[rows] = names[np.where(sel >= 0, sel, len(names) - 1)]
        return out

    def event_types(self) -> np.ndarray:
        """pooltool's event type names of :attr:`events`' rows (vectorised)."""
        if self.events is None:
            raise ValueError("simulated without events (pass events=True)")
        return np.asarray(EVENT_TYPES, dtype=object)[self.events["type"]]

    def events_of(self, shot: int) -> np.ndarray:
        """Shot ``shot``'s rows of :attr:`events` (a slice)."""
        if self.events is None or self.event_offsets is None:
            raise ValueError("simulated without events (pass events=True)")
        return self.events[self.event_offsets[shot] : self.event_offsets[shot + 1]]

    def to_events(self, shot: int) -> list[dict[str, Any]]:
        """Shot ``shot``'s events in pooltool's terms, as :func:`to_events` gives them
        (compare with :func:`from_pooltool_events`)."""
        conv = self.converted(shot)
        return _event_dicts(
            self.events_of(shot), conv.ball_ids, conv.cue_id, self.table_ids_of(shot)
        )

    def to_final(self, shot: int) -> dict[str, dict[str, Any]]:
        """Shot ``shot``'s final states in pooltool's terms, as :func:`to_final` gives them
        (compare with :func:`from_pooltool_final`)."""
        conv = self.converted(shot)
        if not self.ok[shot]:
            raise ValueError(f"shot {shot} was not simulated: {self.status[shot]}")
        return _final_dicts(
            self.final_states[shot], conv.ball_ids, self.table_ids_of(shot)["pockets"]
        )


def _on_error(on_error: str) -> bool:
    if on_error not in _ON_ERROR:
        raise ValueError(f'on_error {on_error!r}: expected "raise" or "report"')
    return on_error == "report"


def _strike_table(strikes: Any, defaults: Sequence[np.ndarray] | None, n: int | None):
    """The strike columns ``V0, phi, theta, a, b`` as float64 arrays of one length; a
    column left out takes ``defaults`` (per row)."""
    if isinstance(strikes, np.ndarray) and strikes.dtype.names is None:
        raise ValueError(
            "strikes: expected a structured array or a dict of columns V0, phi, theta, a, b"
        )
    names = set(strikes.dtype.names) if isinstance(strikes, np.ndarray) else set(strikes)
    allowed = set(_STRIKE_COLUMNS) | ({"system"} if n is not None else set())
    unknown = names - allowed
    if unknown:
        raise ValueError(
            f"strikes: unknown columns {sorted(unknown)} (expected {', '.join(sorted(allowed))}; "
            "the struck ball is the cue's cue_ball_id)"
        )
    cols = {}
    for c in _STRIKE_COLUMNS:
        if c in names:
            a = np.asarray(strikes[c], dtype=np.float64)
            if a.ndim != 1:
                raise ValueError(f"strikes: column {c!r} must be 1-D, it has shape {a.shape}")
            cols[c] = a
    lengths = {len(a) for a in cols.values()}
    if n is not None:
        lengths.add(n)
    if not cols and n is None:
        raise ValueError("strikes: no column V0, phi, theta, a or b")
    if len(lengths) != 1:
        raise ValueError(f"strikes: columns of different lengths {sorted(lengths)}")
    (length,) = lengths
    out = []
    for j, c in enumerate(_STRIKE_COLUMNS):
        if c in cols:
            out.append(np.ascontiguousarray(cols[c]))
        elif defaults is None:
            raise ValueError(f"strikes: no column {c!r}")
        else:
            out.append(np.ascontiguousarray(np.broadcast_to(defaults[j], (length,)), np.float64))
    return out, length


def _cue_values(system: Any) -> list[float]:
    cue = system.cue
    return [float(getattr(cue, c)) for c in _STRIKE_COLUMNS]


def _run_group(
    convs: list[Converted],
    pos: np.ndarray,
    cue: np.ndarray,
    cols: list[np.ndarray],
    table: Any,
    physics: list,
    opts: dict,
    report: bool,
):
    """One call of the extension: shots of positions ``convs`` on one table. Returns
    ``(events, final, outcomes, bad)`` with the shots numbered 0..len(pos)-1."""
    kisstime = _kisstime()
    balls = np.concatenate([c.balls for c in convs])
    balls["table"] = np.repeat(np.arange(len(convs)), [len(c.balls) for c in convs])
    batch = kisstime.Batch(balls)
    name, text = kisstime._table(table)
    kisstime._quiet_mesa(opts["backend"])
    ev, fin, oc, bad = kisstime._kisstime.simulate_shots(
        batch._batch,
        [list(c.ball_ids) for c in convs],
        (
            np.ascontiguousarray(pos, np.int64),
            np.ascontiguousarray(cue, np.int64),
            [np.ascontiguousarray(c, np.float64) for c in cols],
        ),
        name,
        text,
        physics,
        int(opts["max_events"]),
        float(opts["max_time"]),
        bool(opts["events"]),
        opts["backend"],
        opts["precision"],
        report,
    )
    load = kisstime._load
    return (load(ev) if ev is not None else None), load(fin), load(oc), bad


def simulate_strikes(
    system: Any,
    strikes: Any,
    *,
    cue_ball: str | None = None,
    table: Any = None,
    physics: Any = None,
    events: bool = False,
    on_error: str = "raise",
    max_events: int = 200_000,
    max_time: float = 3600.0,
    backend: str = "cpu",
    precision: str | None = None,
    check: bool = True,
) -> BatchResult:
    """One pooltool position struck in many ways, in one call: shot k is ``system``'s balls
    (their current states, as :func:`from_system` takes them) struck with row k of
    ``strikes``, from the strike to rest (``ShotEngine::simulate_with``, Rayon over shots,
    the GIL released). No per-strike Python; the results are NumPy arrays
    (:class:`BatchResult`).

    Args:
        system: The pooltool ``System`` (converted once with :func:`from_system`).
        strikes: A structured array or a dict of 1-D columns ``V0, phi, theta, a, b``
            (pooltool's ``Cue.set_state`` conventions: m/s, degrees, fractions of R); a
            column left out takes ``system.cue``'s value for every shot (e.g. only
            ``phi`` and ``V0`` noisy). A shot with ``V0 = 0`` is not struck.
        cue_ball: The struck ball's pooltool id (default ``system.cue.cue_ball_id``).
        table: The table to simulate on (default the system's own, as JSON text, no file):
            anything ``kisstime.simulate``'s ``table`` takes (``"7ft"``, ``"9ft"``, a path,
            JSON text, a pooltool ``Table``).
        physics: Replaces the system's own ``BallParams`` and ``CueSpecs``
            (:attr:`Converted.physics`); what ``kisstime.simulate``'s ``physics`` takes.
        events: Record every event (:attr:`BatchResult.events`); off, only final states
            and outcomes (faster, less memory).
        on_error: ``"raise"`` (the default): the first bad shot raises ``ValueError``
            (``shot k: ...``, naming the ball). ``"report"``: every shot is checked
            first, the bad ones (a strike with a² + b² > 1, V0 < 0 or NaN, …) are not
            simulated and flagged in :attr:`BatchResult.status` with their message; the
            others are simulated exactly as in a clean run.
        max_events, max_time, backend, precision: as for ``kisstime.simulate``.
        check: :func:`from_system`'s (the balls must share one ``BallParams``).
    """
    report = _on_error(on_error)
    conv = from_system(system, check=check)
    cols, n = _strike_table(strikes, _cue_values(system), None)
    cue_id = str(system.cue.cue_ball_id) if cue_ball is None else str(cue_ball)
    cue = np.full(n, conv.ball(cue_id), dtype=np.int64)
    cue[cols[0] == 0] = -1  # V0 = 0: no strike, as from_system
    pos = np.zeros(n, dtype=np.int64)
    kisstime = _kisstime()
    phys = [kisstime._physics((conv.physics or None) if physics is None else physics)]
    opts = dict(
        max_events=max_events, max_time=max_time, events=events, backend=backend,
        precision=precision,
    )
    tbl = conv.table if table is None else table
    ev, fin, oc, bad = _run_group([conv], pos, cue, cols, tbl, phys, opts, report)
    status = _status(n, bad)
    ids = conv.table_ids if table is None else _ids_of_layout(table)
    return BatchResult([conv], pos, ev, fin, oc, status, [ids])


def _status(n: int, bad: Iterable[tuple[int, str]]) -> np.ndarray:
    msgs = [""] * n
    for k, m in bad:
        msgs[int(k)] = str(m)
    return np.asarray(msgs, dtype=str)


def simulate_systems(
    systems: Sequence[Any],
    strikes: Any = None,
    *,
    table: Any = None,
    physics: Any = None,
    events: bool = False,
    on_error: str = "raise",
    max_events: int = 200_000,
    max_time: float = 3600.0,
    backend: str = "cpu",
    precision: str | None = None,
    check: bool = True,
) -> BatchResult:
    """Several pooltool ``System`` objects in one call (each converted by :func:`from_system`
    with its own table, ``BallParams`` and cue), as a :class:`BatchResult`.

    Without ``strikes``, shot i is system i with its own cue (no strike when its V0 is
    0). With ``strikes``, a structured array or dict with a ``system`` column (the index
    of the system each row strikes) and any of ``V0, phi, theta, a, b`` (left out: that
    system's cue values), shot k being row k: several positions times many strikes.
    Systems on the same table (the same JSON) are simulated together, each with its own
    physical parameters (``physics`` replaces them all); ``table`` puts every system on
    that table instead. ``on_error="report"`` also flags the shots of a system that does
    not convert (``system i: ...``). Other arguments as :func:`simulate_strikes`.
    """
    report = _on_error(on_error)
    kisstime = _kisstime()
    systems = list(systems)
    convs: list[Converted | None] = []
    failed: dict[int, str] = {}
    for i, system in enumerate(systems):
        try:
            convs.append(from_system(system, check=check))
        except ValueError as e:
            if not report:
                raise ValueError(f"system {i}: {e}") from e
            convs.append(None)
            failed[i] = f"system {i}: {e}"
    defaults = np.array(
        [
            _cue_values(s) if c is not None else [0.0] * 5
            for c, s in zip(convs, systems)
        ],
        dtype=np.float64,
    ).reshape(len(systems), 5)
    if strikes is None:
        pos = np.arange(len(systems), dtype=np.int64)
        cols = [np.ascontiguousarray(defaults[:, j]) for j in range(5)]
    else:
        try:
            sys_col = strikes["system"]
        except (KeyError, ValueError, IndexError):
            raise ValueError("strikes: no column 'system' (the index of each row's system)") from None
        pos = np.asarray(sys_col)
        if pos.ndim != 1 or (pos.dtype.kind not in "iu" and len(pos)):
            raise ValueError("strikes: column 'system' must be 1-D integers")
        pos = pos.astype(np.int64)
        if len(pos) and (pos.min() < 0 or pos.max() >= len(systems)):
            raise ValueError(f"strikes: a 'system' outside 0..{len(systems) - 1}")
        cols, _ = _strike_table(strikes, [defaults[pos, j] for j in range(5)], len(pos))
    n = len(pos)
    cue = np.full(n, -1, dtype=np.int64)
    for i, c in enumerate(convs):
        if c is not None:
            sel = pos == i
            cue_id = str(systems[i].cue.cue_ball_id)
            if cue_id in c.ball_ids:
                cue[sel] = c.ball(cue_id)
            elif np.any(cols[0][sel] > 0):
                # from_system's message (it refuses a missing cue ball when V0 > 0)
                raise ValueError(f"system {i}: cue_ball_id {cue_id!r} is not a ball")
    cue[cols[0] == 0] = -1
    opts = dict(
        max_events=max_events, max_time=max_time, events=events, backend=backend,
        precision=precision,
    )
    # groups of systems on one table
    groups: dict[str, list[int]] = {}
    for i, c in enumerate(convs):
        if c is not None:
            groups.setdefault("" if table is not None else c.table, []).append(i)
    parts, bad = [], [(int(k), failed[int(p)]) for k, p in enumerate(pos) if int(p) in failed]
    for key, members in groups.items():
        local = np.full(len(systems), -1, dtype=np.int64)
        local[members] = np.arange(len(members))
        shots = np.flatnonzero(local[pos] >= 0)
        if len(shots) == 0:
            continue
        gconvs = [convs[i] for i in members]
        phys = [
            kisstime._physics((c.physics or None) if physics is None else physics)
            for c in gconvs
        ]
        tbl = table if table is not None else key
        try:
            ev, fin, oc, gbad = _run_group(
                gconvs, local[pos[shots]], cue[shots], [c[shots] for c in cols], tbl, phys,
                opts, report,
            )
        except ValueError as e:
            raise ValueError(_renumber(str(e), shots)) from None
        for arr in (ev, fin, oc):
            if arr is not None:
                arr["table"] = shots[arr["table"]]
        bad += [(int(shots[k]), _renumber(m, shots)) for k, m in gbad]
        parts.append((ev, fin, oc))

    def merged(i: int, like: np.ndarray | None) -> np.ndarray | None:
        arrs = [p[i] for p in parts if p[i] is not None]
        if not arrs:
            return None if like is None else like
        out = np.concatenate(arrs)
        return out[np.argsort(out["table"], kind="stable")]

    empty_fin = np.zeros(0, dtype=_FINAL_DTYPE)
    empty_oc = np.zeros(0, dtype=_OUTCOME_DTYPE)
    ev = merged(0, None)
    if events and ev is None:
        ev = np.zeros(0, dtype=_EVENT_DTYPE)
    fin, oc = merged(1, empty_fin), merged(2, empty_oc)
    if table is None:
        ids = [c.table_ids if c is not None else None for c in convs]
    else:
        shared = _ids_of_layout(table)
        ids = [shared if c is not None else None for c in convs]
    return BatchResult(convs, pos, ev if events else None, fin, oc, _status(n, bad), ids)


def _renumber(message: str, shots: np.ndarray) -> str:
    """A group's ``shot k: ...`` message with k the shot's number in the whole call."""
    head, sep, rest = message.partition(": ")
    if sep and head.startswith("shot ") and head[5:].isdigit():
        return f"shot {int(shots[int(head[5:])])}: {rest}"
    return message


def _dtype(spec: str) -> np.dtype:
    """A dtype of kisstime's outputs from ``"name:kind ..."`` (i: <i8, f: <f8)."""
    return np.dtype([(n, "<i8" if k == "i" else "<f8") for n, k in (x.split(":") for x in spec.split())])


# the dtypes of kisstime.simulate's outputs (for a batch where no shot was simulated)
_EVENT_DTYPE = _dtype(
    "table:i k:i t:f type:i agent_a:i agent_b:i ball:i state:i x:f y:f vx:f vy:f wx:f wy:f wz:f"
)
_FINAL_DTYPE = _dtype("table:i ball:i state:i x:f y:f vx:f vy:f wx:f wy:f wz:f pocket:i")
_OUTCOME_DTYPE = _dtype("table:i events:i t_end:f cut:i")


def _pool_number(bid: str) -> int:
    """A pooltool pool ball id as the game's number: ``"cue"`` 0, ``"1"`` to ``"15"``."""
    if bid == "cue":
        return 0
    if bid.isdigit() and 1 <= int(bid) <= 15:
        return int(bid)
    raise ValueError(f"ball {bid!r}: the planner takes pooltool's pool balls 'cue' and '1' to '15'")


def plan(
    balls: Any,
    table: Any = None,
    *,
    rules: str,
    hittable: Sequence[str] | None = None,
    noise: Any = "fastfiz",
    budget_s: float | None = 1.0,
    check: bool = True,
    **kwargs: Any,
):
    """Which shot to play, in pooltool's terms (``kisstime.plan`` on pooltool's objects).

    Args:
        balls: pooltool's ``{id: Ball}`` dict (``system.balls``), or a ``System`` (then
            ``table`` defaults to its table). Balls ``"cue"`` and ``"1"`` to ``"15"``, every
            one at rest; pocketed ones are left out. Their ``BallParams`` are the physics
            (with ``check``, they must agree, as :func:`from_system` asks).
        table: A pooltool ``Table`` (required with a dict of balls).
        rules: ``"8-ball"`` or ``"9-ball"``.
        hittable: 8-ball: the player's group as pooltool's ids (``("1", "2", ...)``, as its
            ``BallGroup.SOLIDS.balls``; those not on the table are left out, and with none
            on it the 8 is the ball on); ``None``: an open table.
        noise: A preset (``"fastfiz"``, ``"club"``, ``"casual"``, ``"none"``) or a dict of
            σ in pooltool's units: ``{"V0": 0.1, "phi": 0.1, "theta": 0.1, "a": 0.003,
            "b": 0.003}`` (m/s; degrees; fractions of the radius).
        budget_s: About this many seconds (or ``budget_s=None, budget_samples=N``).
        kwargs: The rest of ``kisstime.plan``'s (``budget_samples``, ``seed``, ``top``,
            ``noise_scale``, ``backend``, ``ball_in_hand`` or ``break_shot=True``: then
            ``.placement`` is where to put the cue ball, ``(x, y)`` in pooltool's table
            coordinates).

    Returns:
        The ``kisstime.Plan``: its ``.strike`` is a dict in pooltool's ``Cue`` conventions
        (``V0``, ``phi``, ``theta`` in degrees, ``a``, ``b`` as fractions of the ball
        radius), ready for ``system.cue.set_state(**plan.strike)``; the finalists'
        ``ball`` ids are pooltool's.
    """
    _require_pooltool()
    kisstime = _kisstime()
    if hasattr(balls, "balls") and hasattr(balls, "table"):
        system = balls
        balls, table = system.balls, table if table is not None else system.table
        physics = _physics_of(system, check)
    else:
        if table is None:
            raise ValueError("table: give pooltool's Table with a dict of balls")
        physics = _ball_params(balls, check)
    positions = {}
    for bid, ball in balls.items():
        if int(ball.state.s) == STATE_NAMES.index("pocketed"):
            continue
        rvw = np.asarray(ball.state.rvw, dtype=np.float64)
        x, y = _floats(rvw[0, :2], 2, f"ball {bid!r} position")
        if np.any(rvw[1] != 0) or np.any(rvw[2] != 0):
            raise ValueError(f"ball {bid!r} moves or spins: the planner plays from a position at rest")
        positions[_pool_number(str(bid))] = (x, y)
    # pooltool's groups name balls a position may lack: those on the table (none: the 8)
    numbers = None if hittable is None else [
        _pool_number(str(h)) for h in hittable if _pool_number(str(h)) in positions
    ]
    out = kisstime.plan(
        positions,
        rules=rules,
        hittable=numbers,
        table=table,
        physics=physics or None,
        noise=noise,
        budget_s=budget_s,
        **kwargs,
    )
    name = {0: "cue", **{n: str(n) for n in range(1, 16)}}
    for r in out.ranked:
        r["ball"] = name[int(r["ball"])]
    return out

