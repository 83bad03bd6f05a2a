#!/usr/bin/env python3
"""Soak: N tables of random valid shots streamed through `kisstime simulate` to `.npy`,
the process's resident memory sampled over time (issue 31, "Soak and faults").

What it does:
  1. writes N tables of random valid shots as the CLI's own input formats, in table order:
     the balls as a structured `.npy` (`kisstime.io.npy`'s BALL_DTYPE: table, ball, state,
     x, y, vx, vy, wx, wy, wz) and one strike a table as a structured `.npy` (table, ball,
     V0, phi, theta, a, b). Each table has --balls balls at rest on a jittered grid of the
     9-ft table's playing surface (never touching, clear of the cushions and pockets); the
     cue ball (id 0) is struck with V0 in [0.5, 3] m/s, phi in [0, 360), theta in [0, 15]
     degrees, (a, b) inside the disc of radius 0.5. Generated a million tables at a time
     (numpy memmaps), so the generator's memory is flat too;
  2. runs `kisstime simulate IN --strikes STRIKES --final FINAL.npy --outcomes OUT.npy`
     (and `-o EVENTS.npy` with --events), sampling VmRSS and VmHWM from /proc/PID/status
     every --interval seconds;
  3. checks the exit status and the outputs' shapes (one outcome row a table, one final
     row a ball), and prints the samples and a summary (also as JSON with --json).

Usage (from the repository root; a release build is much faster):
  cargo build --release --bin kisstime
  python3 tools/soak/soak.py --tables 100000
  python3 tools/soak/soak.py --tables 1000000
  python3 tools/soak/soak.py --tables 10000000          # by hand: ~1 GB of input
  python3 tools/soak/soak.py --tables 100000 --csv      # CSV input instead of .npy

Needs numpy. Results are recorded in FUZZING.md ("Soak and faults").
"""

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BALL_DTYPE = [("table", "<i8"), ("ball", "<i8"), ("state", "<i8"), ("x", "<f8"),
              ("y", "<f8"), ("vx", "<f8"), ("vy", "<f8"), ("wx", "<f8"), ("wy", "<f8"),
              ("wz", "<f8")]
STRIKE_DTYPE = [("table", "<i8"), ("ball", "<i8"), ("V0", "<f8"), ("phi", "<f8"),
                ("theta", "<f8"), ("a", "<f8"), ("b", "<f8")]
# the 9-ft table's playing surface (pooltool's frame), the ball radius
WIDTH, LENGTH, R = 1.2700, 2.5400, 0.028575
GEN_CHUNK = 1_000_000


def binary(path):
    if path:
        return path
    for kind in ("release", "debug"):
        p = os.path.join(ROOT, "target", kind, "kisstime")
        if os.path.exists(p):
            return p
    sys.exit("soak.py: no kisstime binary; cargo build --release --bin kisstime")


def grid(balls):
    """Cell centres of a grid with at least `balls` cells, clear of cushions and pockets."""
    cols = 3
    rows = -(-balls // cols) + 1
    xs = np.linspace(0.25, WIDTH - 0.25, cols)
    ys = np.linspace(0.35, LENGTH - 0.35, rows)
    cells = np.array([(x, y) for y in ys for x in xs])
    jitter = min(xs[1] - xs[0], ys[1] - ys[0]) / 2 - 2 * R
    return cells, jitter


def generate(n, balls, seed, ball_path, strike_path):
    cells, jitter = grid(balls)
    rng = np.random.default_rng(seed)
    b_out = np.lib.format.open_memmap(ball_path, mode="w+", dtype=BALL_DTYPE,
                                      shape=(n * balls,))
    s_out = np.lib.format.open_memmap(strike_path, mode="w+", dtype=STRIKE_DTYPE, shape=(n,))
    for start in range(0, n, GEN_CHUNK):
        m = min(GEN_CHUNK, n - start)
        tables = np.arange(start, start + m, dtype=np.int64)
        # each table: `balls` distinct cells, jittered
        pick = np.argsort(rng.random((m, len(cells))), axis=1)[:, :balls]
        xy = cells[pick] + rng.uniform(-jitter, jitter, (m, balls, 2))
        rows = b_out[start * balls:(start + m) * balls]
        rows["table"] = np.repeat(tables, balls)
        rows["ball"] = np.tile(np.arange(balls, dtype=np.int64), m)
        rows["state"] = 0
        rows["x"] = xy[:, :, 0].ravel()
        rows["y"] = xy[:, :, 1].ravel()
        for f in ("vx", "vy", "wx", "wy", "wz"):
            rows[f] = 0.0
        s = s_out[start:start + m]
        s["table"] = tables
        s["ball"] = 0
        s["V0"] = rng.uniform(0.5, 3.0, m)
        s["phi"] = rng.uniform(0.0, 360.0, m)
        s["theta"] = rng.uniform(0.0, 15.0, m)
        rad = 0.5 * np.sqrt(rng.random(m))
        ang = rng.uniform(0, 2 * np.pi, m)
        s["a"] = rad * np.cos(ang)
        s["b"] = rad * np.sin(ang)
    b_out.flush()
    s_out.flush()
    del b_out, s_out


def to_csv(npy_path, csv_path, header, fmt):
    a = np.load(npy_path, mmap_mode="r")
    with open(csv_path, "w") as f:
        f.write(header + "\n")
        for start in range(0, len(a), GEN_CHUNK):
            part = a[start:start + GEN_CHUNK]
            cols = [part[name] for name in a.dtype.names]
            np.savetxt(f, np.column_stack(cols).astype(object), fmt=fmt, delimiter=",")


def status(pid):
    """VmRSS and VmHWM of `pid` in bytes (None once it is gone)."""
    try:
        with open(f"/proc/{pid}/status") as f:
            text = f.read()
    except OSError:
        return None
    got = {}
    for line in text.splitlines():
        key, _, value = line.partition(":")
        if key in ("VmRSS", "VmHWM"):
            got[key] = int(value.split()[0]) * 1024
    return got.get("VmRSS"), got.get("VmHWM")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--tables", type=int, default=100_000)
    ap.add_argument("--balls", type=int, default=3)
    ap.add_argument("--seed", type=int, default=31)
    ap.add_argument("--csv", action="store_true", help="CSV input and strikes")
    ap.add_argument("--events", action="store_true", help="also -o events.npy")
    ap.add_argument("--bin", help="the kisstime binary (default: target/release, else debug)")
    ap.add_argument("--dir", help="work folder (default: a temporary one, removed)")
    ap.add_argument("--interval", type=float, default=0.2, help="RSS sampling period, s")
    ap.add_argument("--threads", type=int)
    ap.add_argument("--json", help="write the summary here")
    ap.add_argument("--extra", nargs=argparse.REMAINDER, default=[],
                    help="more arguments for kisstime simulate")
    args = ap.parse_args()
    exe = binary(args.bin)
    work = args.dir or tempfile.mkdtemp(prefix="kisstime-soak-")
    os.makedirs(work, exist_ok=True)
    try:
        n, balls = args.tables, args.balls
        ball_path = os.path.join(work, "balls.npy")
        strike_path = os.path.join(work, "strikes.npy")
        t0 = time.time()
        generate(n, balls, args.seed, ball_path, strike_path)
        if args.csv:
            to_csv(ball_path, os.path.join(work, "balls.csv"),
                   "table,ball,state,x,y,vx,vy,wx,wy,wz",
                   ["%d", "%d", "%d"] + ["%.17g"] * 7)
            to_csv(strike_path, os.path.join(work, "strikes.csv"),
                   "table,ball,V0,phi,theta,a,b", ["%d", "%d"] + ["%.17g"] * 5)
            # the state column as the CSV's words
            ball_path = os.path.join(work, "balls.csv")
            text_fix(ball_path)
            strike_path = os.path.join(work, "strikes.csv")
        gen_s = time.time() - t0
        in_bytes = os.path.getsize(ball_path) + os.path.getsize(strike_path)
        final = os.path.join(work, "final.npy")
        outcomes = os.path.join(work, "outcomes.npy")
        cmd = [exe, "simulate", ball_path, "--strikes", strike_path, "--final", final,
               "--outcomes", outcomes]
        if args.events:
            cmd += ["-o", os.path.join(work, "events.npy")]
        if args.threads:
            cmd += ["--threads", str(args.threads)]
        cmd += args.extra
        print(f"soak: {n} tables of {balls} balls ({in_bytes / 2**20:.0f} MiB of input, "
              f"generated in {gen_s:.1f} s); {' '.join(cmd)}", flush=True)
        samples = []
        start = time.time()
        proc = subprocess.Popen(cmd, stderr=subprocess.PIPE, text=True)
        while proc.poll() is None:
            got = status(proc.pid)
            if got and got[0]:
                samples.append((time.time() - start, got[0], got[1]))
            time.sleep(args.interval)
        wall = time.time() - start
        err = proc.stderr.read()
        code = proc.returncode
        print(err.strip())
        result = {"tables": n, "balls_per_table": balls, "input_bytes": in_bytes,
                  "format": "csv" if args.csv else "npy", "exit": code, "wall_s": wall,
                  "tables_per_s": n / wall if wall else None,
                  "binary": exe, "cpus": os.cpu_count(),
                  "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())}
        if samples:
            rss = [s[1] for s in samples]
            result["rss_peak_mib"] = max(rss) / 2**20
            result["hwm_mib"] = max(s[2] for s in samples) / 2**20
            # RSS at each tenth of the run
            tenth = []
            for k in range(1, 11):
                t = wall * k / 10
                before = [s for s in samples if s[0] <= t]
                tenth.append(round(before[-1][1] / 2**20, 1) if before else None)
            result["rss_by_tenth_mib"] = tenth
        if code == 0:
            oc = np.load(outcomes, mmap_mode="r")
            fin = np.load(final, mmap_mode="r")
            result["outcome_rows"] = len(oc)
            result["final_rows"] = len(fin)
            result["output_bytes"] = os.path.getsize(outcomes) + os.path.getsize(final)
            ok = len(oc) == n and len(fin) == n * balls
            result["outputs_ok"] = bool(ok)
        print("soak: " + json.dumps(result, indent=1))
        if args.json:
            with open(args.json, "w") as f:
                json.dump(result, f, indent=1)
        return 0 if code == 0 and result.get("outputs_ok") else 1
    finally:
        if not args.dir:
            shutil.rmtree(work, ignore_errors=True)


def text_fix(path):
    """The CSV input's state column as a word (the generator writes code 0: stationary)."""
    tmp = path + ".tmp"
    with open(path) as src, open(tmp, "w") as dst:
        dst.write(src.readline())
        for line in src:
            t, b, _, rest = line.split(",", 3)
            dst.write(f"{t},{b},stationary,{rest}")
    os.replace(tmp, path)


if __name__ == "__main__":
    sys.exit(main())
