#!/usr/bin/env python3
"""Time pooltool's own ball-ball collision-time code on a `kisstime gen` workload file.

Run (from the repository root, after `cargo build --release`):

    target/release/kisstime gen --scenario midshot --tables 2000 -o /tmp/pt_midshot.csv
    /work/pooltool-venv/bin/python benches/pooltool_time.py /tmp/pt_midshot.csv \
        --kisstime target/release/kisstime

Install (pooltool's panda3d pin, 1.11.0.dev3702, is not on PyPI, hence --no-deps):

    python3 -m venv /work/pooltool-venv
    /work/pooltool-venv/bin/pip install --no-deps pooltool-billiards==0.6.0
    /work/pooltool-venv/bin/pip install -r benches/pooltool_requirements.txt

What it measures (pooltool 0.6.0, single thread, numba JIT compile excluded by a
warm-up call of every path; best and median of --reps runs; pairs = n(n-1)/2 per table
whatever the balls' states):

  pair-py     `pooltool.evolution.event_based.solve.ball_ball_collision_time` called
              from Python once per pair of every table, on every pair (no pre-filter):
              how pooltool's simulator calls it, one numba dispatch per pair.
  pair-njit   The same function called from a numba-compiled loop over all pairs:
              pooltool's per-pair arithmetic with no Python call overhead (a ceiling).
  fused       The next collision of each table in one numba loop: for every pair,
              the simulator's skip (either ball pocketed, or neither translating:
              `stationary`, `spinning`), else `ball_ball_collision_time`, and the
              table's minimum. The simulator's own step without its Python overhead,
              and the workload `kisstime bench`'s "next collision" times (pairs counted
              as above, skipped pairs included).
  batched     pooltool's vectorised quartic primitives: coefficients of all pairs
              (`solve.ball_ball_collision_coeffs`, in a numba loop), then
              `ptmath.roots.quartic.solve_many` and
              `ptmath.roots.core.get_real_positive_smallest_roots` on the whole array.
              pooltool 0.6.0's simulator does not use this route; it is the batched
              route its library offers.
  simulator   `pooltool.evolution.event_based.simulate.get_next_ball_ball_collision`
              on one `pooltool.System` per table with an empty `CollisionCache`: the
              simulator's own next-ball-ball-collision step (a Python loop over
              `itertools.combinations` with its pocketed / non-translating / overlap
              pre-filter, one `ball_ball_collision_time` call per remaining pair, then
              the min and an Event). Importing `simulate` pulls in pooltool's GUI
              modules, which import panda3d; panda3d, direct, simplepbr and gltf are
              replaced by inert stub modules (no rendering code runs in the timed path).
              Skip it with --no-simulator: then only the numeric submodules are
              imported (pooltool/__init__.py is bypassed) and no stub is installed.

Input columns: table,ball,state,x,y,vx,vy,wx,wy,wz (SI). Each ball becomes pooltool's
rvw = [[x, y, R], [vx, vy, 0], [wx, wy, wz]] with pooltool's state code
(stationary 0, spinning 1, sliding 2, rolling 3, pocketed 4) and pooltool's default
BallParams (R 0.028575, m 0.170097, u_s 0.2, u_r 0.01, g 9.81); mu is u_s for a sliding
ball and u_r otherwise, as the simulator passes it.

Side by side (--bench SCENARIO --seed K, with --kisstime BIN): the input must be
`BIN gen --scenario SCENARIO --tables N --balls B --seed K` byte for byte (checked); before
pooltool's paths, the same run times `BIN bench --scenario SCENARIO --tables N --balls B
--seed K --backend cpu --reps R --json` on the same tables, and after them prints
kisstime's next collision against `fused`, and its per pair against `pair-njit` and
`batched`:

    target/release/kisstime gen --scenario midshot --tables 20000 --seed 7 -o /tmp/m.csv
    /work/pooltool-venv/bin/python benches/pooltool_time.py /tmp/m.csv --no-simulator \
        --kisstime target/release/kisstime --bench midshot --seed 7 --reps 5

Sanity check (--kisstime BIN runs `BIN pairs FILE`, or --pairs-csv gives its output):
per-pair times are compared with kisstime's `t` (agreement: both inf, or
|a-b| <= 1e-9 * max(|a|,|b|)). Three pooltool answers are compared: raw (the function on
every pair), gated (what the simulator stores: inf for pocketed or both non-translating,
0 for overlapping, else the function's time), and gated+horizon (gated, with a time past
kisstime's `horizon`, the first motion-state change of the two balls, counted as inf:
pooltool's event loop would meet that transition first and recompute).
"""

from __future__ import annotations

import abc
import argparse
import csv
import importlib.abc
import importlib.machinery
import importlib.util
import math
import os
import statistics
import subprocess
import sys
import tempfile
import time
import types

import numpy as np

STATES = {"stationary": 0, "spinning": 1, "sliding": 2, "rolling": 3, "pocketed": 4}
STATE_NAMES = {v: k for k, v in STATES.items()}


# --------------------------------------------------------------------------- imports
def _skip_package_inits() -> None:
    """Import pooltool submodules without running pooltool/__init__.py (which imports
    the panda3d GUI) nor the __init__ of the subpackages on the way."""
    spec = importlib.util.find_spec("pooltool")
    if spec is None or spec.origin is None:
        sys.exit("pooltool is not installed: pip install --no-deps pooltool-billiards")
    root = os.path.dirname(spec.origin)
    for name, sub in [
        ("pooltool", ""),
        ("pooltool.physics", "physics"),
        ("pooltool.evolution", "evolution"),
        ("pooltool.evolution.event_based", os.path.join("evolution", "event_based")),
    ]:
        mod = types.ModuleType(name)
        mod.__path__ = [os.path.join(root, sub)]
        mod.__file__ = os.path.join(root, sub, "__init__.py")
        sys.modules[name] = mod


class _StubMeta(abc.ABCMeta):
    def __getattr__(cls, name):
        if name.startswith("__"):
            raise AttributeError(name)
        return _Stub()


class _Stub(metaclass=_StubMeta):
    def __init__(self, *args, **kwargs):
        pass

    def __getattr__(self, name):
        if name.startswith("__"):
            raise AttributeError(name)
        return _Stub()

    def __call__(self, *args, **kwargs):
        return _Stub()


class _StubModule(types.ModuleType):
    __path__: list[str] = []

    def __getattr__(self, name):
        if name.startswith("__"):
            raise AttributeError(name)
        return _Stub


class _StubFinder(importlib.abc.MetaPathFinder, importlib.abc.Loader):
    ROOTS = ("panda3d", "direct", "simplepbr", "gltf")

    def find_spec(self, fullname, path, target=None):
        if fullname.split(".")[0] in self.ROOTS:
            return importlib.machinery.ModuleSpec(fullname, self, is_package=True)
        return None

    def create_module(self, spec):
        return _StubModule(spec.name)

    def exec_module(self, module):
        pass


def _stub_panda3d() -> None:
    sys.meta_path.insert(0, _StubFinder())


# --------------------------------------------------------------------------- input
def load(path: str, R: float):
    """Returns (tables, rvw, s): tables = list of (table_id, ball_ids, start, n) over
    arrays rvw (N,3,3) and s (N,) sorted by table then ball id."""
    rows = []
    with open(path, newline="") as f:
        reader = csv.reader(f)
        header = next(reader)
        want = ["table", "ball", "state", "x", "y", "vx", "vy", "wx", "wy", "wz"]
        if [h.strip() for h in header] != want:
            sys.exit(f"{path}: header must be {','.join(want)}")
        for r in reader:
            if not r:
                continue
            rows.append(
                (int(r[0]), int(r[1]), STATES[r[2].strip()], *(float(x) for x in r[3:]))
            )
    rows.sort(key=lambda r: (r[0], r[1]))
    N = len(rows)
    rvw = np.zeros((N, 3, 3), dtype=np.float64)
    s = np.zeros(N, dtype=np.int64)
    tables = []
    for k, (t, b, st, x, y, vx, vy, wx, wy, wz) in enumerate(rows):
        rvw[k] = [[x, y, R], [vx, vy, 0.0], [wx, wy, wz]]
        s[k] = st
        if not tables or tables[-1][0] != t:
            tables.append([t, [], k, 0])
        tables[-1][1].append(b)
        tables[-1][3] += 1
    return [tuple(t) for t in tables], rvw, s


def pair_index(tables):
    """Flat arrays (ga, gb) of global ball indices for every pair i<j of every table,
    in kisstime's output order, plus (table_id, i, j) keys."""
    ga, gb, keys = [], [], []
    for tid, ids, start, n in tables:
        for a in range(n):
            for b in range(a + 1, n):
                ga.append(start + a)
                gb.append(start + b)
                keys.append((tid, ids[a], ids[b]))
    return np.array(ga, dtype=np.int64), np.array(gb, dtype=np.int64), keys


# --------------------------------------------------------------------------- timing
def timeit(fn, reps: int):
    fn()  # warm-up (JIT compile, caches)
    ts = []
    out = None
    for _ in range(reps):
        t0 = time.perf_counter()
        out = fn()
        ts.append(time.perf_counter() - t0)
    return min(ts), statistics.median(ts), out


def kisstime_bench(args, tables) -> dict:
    """Times `kisstime bench` on the tables of the input (checked to be `kisstime gen`'s
    for --bench and --seed); returns its CPU figures."""
    import json

    ns = {t[3] for t in tables}
    if len(ns) != 1:
        sys.exit("--bench: every table must have the same number of balls")
    (n,) = ns
    shape = ["--scenario", args.bench, "--tables", str(len(tables)), "--balls", str(n), "--seed", str(args.seed)]
    with tempfile.TemporaryDirectory() as d:
        regen = os.path.join(d, "gen.csv")
        subprocess.run([args.kisstime, "gen", *shape, "-o", regen], check=True)
        with open(regen, "rb") as f1, open(args.input, "rb") as f2:
            if f1.read() != f2.read():
                sys.exit(f"--bench: {args.input} is not `kisstime gen {' '.join(shape)}`")
    command = [args.kisstime, "bench", *shape, "--backend", "cpu", "--reps", str(args.reps), "--json"]
    out = subprocess.run(command, check=True, capture_output=True, text=True).stdout
    cpu = json.loads(out)["backends"][0]
    cpu["command"] = " ".join(command[1:-1])
    return cpu


def side_by_side(cpu: dict, npairs: int, rate: dict) -> None:
    """Prints kisstime's figures against pooltool's paths."""
    nxt, per = cpu["next_collisions_pairs_per_s"], cpu["pair_times_pairs_per_s"]
    print(f"\nside by side, the same {npairs} pairs: kisstime {cpu['command']} "
          f"({cpu['device']}, median; run before pooltool's paths)")
    print(f"  next collision: kisstime {nxt:.4g} pairs/s, pooltool fused {rate['fused']:.4g} (median): "
          f"{nxt / rate['fused']:.1f}x")
    print(f"  per pair:       kisstime {per:.4g} pairs/s, pooltool pair-njit {rate['pair-njit']:.4g}, "
          f"batched {rate['batched']:.4g} (medians): {per / rate['pair-njit']:.1f}x, {per / rate['batched']:.1f}x")


def main() -> None:
    ap = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    ap.add_argument("input", help="CSV from `kisstime gen` (table,ball,state,x,y,vx,vy,wx,wy,wz)")
    ap.add_argument("--reps", type=int, default=3, help="timed runs per path after one warm-up (default 3)")
    ap.add_argument("--kisstime", metavar="BIN", help="kisstime binary: run `BIN pairs INPUT` and compare")
    ap.add_argument("--pairs-csv", metavar="FILE", help="existing `kisstime pairs` output to compare with")
    ap.add_argument("--no-simulator", action="store_true", help="skip the simulator path (needs the panda3d stubs)")
    ap.add_argument("--bench", metavar="SCENARIO", help="with --kisstime and --seed: time `BIN bench` on the same tables (see above)")
    ap.add_argument("--seed", type=int, help="the seed the input was generated with (for --bench)")
    ap.add_argument("--examples", type=int, default=8, help="disagreements to print (default 8)")
    ap.add_argument("--radius", type=float, default=0.028575)
    ap.add_argument("--mu-s", type=float, default=0.2)
    ap.add_argument("--mu-r", type=float, default=0.01)
    ap.add_argument("--g", type=float, default=9.81)
    ap.add_argument("--mass", type=float, default=0.170097)
    args = ap.parse_args()
    if args.bench is not None and (args.kisstime is None or args.seed is None):
        sys.exit("--bench needs --kisstime BIN and --seed K")

    if args.no_simulator:
        _skip_package_inits()
    else:
        _stub_panda3d()
        import pooltool  # noqa: F401  (the full package, GUI modules on stubs)
    import numba

    import pooltool.constants as const
    import pooltool.evolution.event_based.solve as solve
    from pooltool.ptmath.roots import quartic
    from pooltool.ptmath.roots.core import get_real_positive_smallest_roots

    try:
        from importlib.metadata import version

        ptv = version("pooltool-billiards")
    except Exception:
        ptv = "?"
    print(f"pooltool-billiards {ptv}, numba {numba.__version__}, numpy {np.__version__}, python {sys.version.split()[0]}")

    R, g, m = args.radius, args.g, args.mass
    tables, rvw, s = load(args.input, R)
    # kisstime first, with no numba code compiled or run in this process yet
    kisstime_cpu = kisstime_bench(args, tables) if args.bench is not None else None
    mu = np.where(s == const.sliding, args.mu_s, args.mu_r).astype(np.float64)
    ga, gb, keys = pair_index(tables)
    npairs = len(ga)
    print(f"{args.input}: {len(tables)} tables, {len(s)} balls, {npairs} pairs; "
          + ", ".join(f"{STATE_NAMES[k]} {int((s == k).sum())}" for k in range(5) if (s == k).any()))

    bbtime = solve.ball_ball_collision_time
    bbcoeffs = solve.ball_ball_collision_coeffs

    # (a) per pair, from Python
    rv = [rvw[k] for k in range(len(s))]
    sl = [int(x) for x in s]
    ml = [float(x) for x in mu]
    pl = list(zip(ga.tolist(), gb.tolist()))

    def pair_py():
        out = np.empty(npairs)
        for k, (a, b) in enumerate(pl):
            out[k] = bbtime(rv[a], rv[b], sl[a], sl[b], ml[a], ml[b], m, m, g, g, R)
        return out

    # (a') per pair, numba loop
    @numba.njit(cache=False)
    def pair_njit_loop(rvw, s, mu, ga, gb, m, g, R):
        out = np.empty(ga.shape[0])
        for k in range(ga.shape[0]):
            a = ga[k]
            b = gb[k]
            out[k] = bbtime(rvw[a], rvw[b], s[a], s[b], mu[a], mu[b], m, m, g, g, R)
        return out

    def pair_njit():
        return pair_njit_loop(rvw, s, mu, ga, gb, m, g, R)

    # (a'') each table's next collision, the simulator's skip, one numba loop
    starts = np.array([t[2] for t in tables], dtype=np.int64)
    counts = np.array([t[3] for t in tables], dtype=np.int64)

    @numba.njit(cache=False)
    def fused_loop(rvw, s, mu, starts, counts, m, g, R, pocketed, still, spinning):
        out = np.empty(starts.shape[0])
        for t in range(starts.shape[0]):
            best = np.inf
            lo = starts[t]
            for a in range(lo, lo + counts[t]):
                for b in range(a + 1, lo + counts[t]):
                    if s[a] == pocketed or s[b] == pocketed:
                        continue
                    if (s[a] == still or s[a] == spinning) and (s[b] == still or s[b] == spinning):
                        continue
                    dt = bbtime(rvw[a], rvw[b], s[a], s[b], mu[a], mu[b], m, m, g, g, R)
                    if dt < best:
                        best = dt
            out[t] = best
        return out

    def fused():
        return fused_loop(rvw, s, mu, starts, counts, m, g, R,
                          const.pocketed, const.stationary, const.spinning)

    # (c) batched quartic primitives
    @numba.njit(cache=False)
    def coeffs_loop(rvw, s, mu, ga, gb, m, g, R):
        ps = np.empty((ga.shape[0], 5))
        for k in range(ga.shape[0]):
            a = ga[k]
            b = gb[k]
            c = bbcoeffs(rvw[a], rvw[b], s[a], s[b], mu[a], mu[b], m, m, g, g, R)
            ps[k, 0] = c[0]
            ps[k, 1] = c[1]
            ps[k, 2] = c[2]
            ps[k, 3] = c[3]
            ps[k, 4] = c[4]
        return ps

    def batched():
        ps = coeffs_loop(rvw, s, mu, ga, gb, m, g, R)
        return get_real_positive_smallest_roots(quartic.solve_many(ps))

    results = {}
    results_rate = {}
    paths = [("pair-py", pair_py), ("pair-njit", pair_njit), ("fused", fused), ("batched", batched)]

    # (b) the simulator's step
    if not args.no_simulator:
        import pooltool.evolution.event_based.simulate as sim
        from pooltool.evolution.event_based.cache import CollisionCache
        from pooltool.objects.ball.datatypes import Ball, BallState
        from pooltool.objects.ball.params import BallParams
        from pooltool.objects.cue.datatypes import Cue
        from pooltool.objects.table.datatypes import Table

        params = BallParams(m=m, R=R, u_s=args.mu_s, u_r=args.mu_r, g=g)
        table = Table.default()
        systems = []
        for tid, ids, start, n in tables:
            balls = {
                str(ids[a]): Ball(
                    id=str(ids[a]),
                    state=BallState(rvw=rvw[start + a].copy(), s=int(s[start + a]), t=0.0),
                    params=params,
                )
                for a in range(n)
            }
            systems.append(sim.System(cue=Cue(cue_ball_id=str(ids[0])), table=table, balls=balls))

        def simulator():
            return [sim.get_next_ball_ball_collision(sy, CollisionCache()) for sy in systems]

        paths.append(("simulator", simulator))

    print(f"\n{'path':<10} {'best s':>9} {'median s':>9} {'pairs/s (best)':>15} {'pairs/s (median)':>17}")
    for name, fn in paths:
        best, med, out = timeit(fn, args.reps)
        results[name] = out
        results_rate[name] = npairs / med
        print(f"{name:<10} {best:9.4f} {med:9.4f} {npairs / best:15.4g} {npairs / med:17.4g}")

    if kisstime_cpu is not None:
        side_by_side(kisstime_cpu, npairs, results_rate)

    raw = results["pair-njit"]
    for name in ("pair-py", "batched"):
        same = np.sum((results[name] == raw) | (np.isinf(results[name]) & np.isinf(raw)))
        print(f"check: {name} equals pair-njit on {same}/{npairs} pairs")

    # what the simulator stores per pair
    d = np.hypot(rvw[ga, 0, 0] - rvw[gb, 0, 0], rvw[ga, 0, 1] - rvw[gb, 0, 1])
    nontrans = np.isin(s, [const.stationary, const.spinning, const.pocketed])
    pocket = s == const.pocketed
    gated = raw.copy()
    gated[d < 2 * R] = 0.0
    gated[(nontrans[ga] & nontrans[gb]) | pocket[ga] | pocket[gb]] = np.inf

    if not args.no_simulator:
        ev = results["simulator"]
        agree = 0
        off = 0
        for tix, (tid, ids, start, n) in enumerate(tables):
            lo = off
            off += n * (n - 1) // 2
            tmin = gated[lo:off].min() if off > lo else np.inf
            if ev[tix].time == tmin or (np.isinf(ev[tix].time) and np.isinf(tmin)):
                agree += 1
        print(f"check: simulator's next-collision time equals min of gated pair times on {agree}/{len(tables)} tables")

    # ---------------------------------------------------------- compare with kisstime
    pairs_csv = args.pairs_csv
    tmp = None
    if pairs_csv is None and args.kisstime:
        tmp = tempfile.NamedTemporaryFile(suffix=".csv", delete=False)
        tmp.close()
        subprocess.run([args.kisstime, "pairs", args.input, "-o", tmp.name], check=True)
        pairs_csv = tmp.name
    if pairs_csv is None:
        return
    kt = {}
    with open(pairs_csv, newline="") as f:
        for r in csv.DictReader(f):
            kt[(int(r["table"]), int(r["i"]), int(r["j"]))] = (float(r["t"]), r["status"], float(r["horizon"]))
    if tmp is not None:
        os.unlink(tmp.name)
    kt_t = np.array([kt[k][0] for k in keys])
    kt_st = [kt[k][1] for k in keys]
    kt_h = np.array([kt[k][2] for k in keys])

    def agree(p):
        both_inf = np.isinf(p) & np.isinf(kt_t)
        fin = np.isfinite(p) & np.isfinite(kt_t)
        scale = np.maximum(np.abs(p), np.abs(kt_t))
        close = np.zeros_like(fin)
        close[fin] = np.abs(p[fin] - kt_t[fin]) <= 1e-9 * scale[fin]
        return both_inf | close

    horizon = gated.copy()
    horizon[horizon > kt_h] = np.inf
    print(f"\nagreement with kisstime pairs (|a-b| <= 1e-9 max(|a|,|b|), or both inf), {npairs} pairs:")
    for label, p in [("raw", raw), ("gated", gated), ("gated+horizon", horizon)]:
        ok = agree(p)
        fin = np.isfinite(p) & np.isfinite(kt_t) & (np.maximum(np.abs(p), np.abs(kt_t)) > 0)
        relmax = float(np.max(np.abs(p[fin] - kt_t[fin]) / np.maximum(np.abs(p[fin]), np.abs(kt_t[fin])))) if fin.any() else 0.0
        print(f"  {label:<14} {int(ok.sum()):>8} agree, {int((~ok).sum()):>7} differ; "
              f"{int(fin.sum())} both finite and non-zero, largest relative difference {relmax:.3g}")
        if (~ok).any():
            cats = {}
            for k in np.flatnonzero(~ok):
                if np.isinf(p[k]):
                    c = "pooltool inf, kisstime finite"
                elif np.isinf(kt_t[k]):
                    c = "pooltool " + ("0" if p[k] == 0 else "finite") + ", kisstime inf"
                else:
                    c = "both finite, different"
                cats[c] = cats.get(c, 0) + 1
            print("      " + "; ".join(f"{c}: {n}" for c, n in sorted(cats.items())))

    for label, p in [("raw", raw), ("gated", gated), ("gated+horizon", horizon)]:
        bad = np.flatnonzero(~agree(p))
        if not len(bad):
            continue
        print(f"\nexamples of {label} disagreements (at most 2 per kind, {args.examples} in all):")
        shown = 0
        seen: dict[tuple, int] = {}
        for k in bad:
            kind = (STATE_NAMES[int(s[ga[k]])], STATE_NAMES[int(s[gb[k]])],
                    bool(np.isinf(p[k])), bool(np.isinf(kt_t[k])), bool(p[k] == 0))
            if seen.get(kind, 0) >= 2:
                continue
            seen[kind] = seen.get(kind, 0) + 1
            tid, i, j = keys[k]
            print(f"  table {tid} pair ({i},{j}) {kind[0]}/{kind[1]}, gap |C|-2R {d[k] - 2 * R:.4g} m: "
                  f"pooltool {float(p[k])!r}; kisstime {float(kt_t[k])!r} {kt_st[k]}, horizon {float(kt_h[k])!r}")
            shown += 1
            if shown >= args.examples:
                break


if __name__ == "__main__":
    main()
