"""The Python package's overhead on `next_collisions` (issue 15): the same 10,000 tables
of 16 balls (`midshot`, seed 42; 1.2 M pairs) timed from Python and from Rust.

    python python/benches/overhead.py [PATH/TO/kisstime]

Rust: `kisstime bench --tables 10000 --backend cpu --reps R`, whose next-collision figure
is the median of R calls of the library's `next_collisions` on a built batch. Python: the
median of R calls of `kisstime.next_collisions` on a `kisstime.Batch` (converted once,
as a Rust caller holds its batch), and on the arrays themselves (converted every call).
The two are run alternately, three rounds, to share the machine's load.
"""

import re
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

import kisstime

EXE = sys.argv[1] if len(sys.argv) > 1 else "target/release/kisstime"
REPS = 15


def rust_ms() -> float:
    out = subprocess.run(
        [EXE, "bench", "--tables", "10000", "--backend", "cpu", "--reps", str(REPS)],
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    rate = float(re.search(r"cpu f64\s+[\d.]+ M pairs/s\s+([\d.]+) M pairs/s", out).group(1))
    return 1.2e6 / (rate * 1e6) * 1e3


def py_ms(x) -> float:
    kisstime.next_collisions(x)
    ts = []
    for _ in range(REPS):
        t = time.perf_counter()
        kisstime.next_collisions(x)
        ts.append(time.perf_counter() - t)
    return statistics.median(ts) * 1e3


with tempfile.TemporaryDirectory() as d:
    path = f"{d}/mid.npy"
    subprocess.run([EXE, "gen", "--tables", "10000", "--seed", "42", "-o", path], check=True)
    balls = np.load(path)
batch = kisstime.Batch(balls)
for round_ in range(3):
    r = rust_ms()
    b = py_ms(batch)
    a = py_ms(balls)
    print(
        f"round {round_}: Rust {r:.2f} ms; Python on a Batch {b:.2f} ms ({100 * (b / r - 1):+.1f} %); "
        f"Python on the arrays {a:.2f} ms ({100 * (a / r - 1):+.1f} %)"
    )
