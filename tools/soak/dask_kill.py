#!/usr/bin/env python3
"""Dask workers killed mid-study (issue 31, "Soak and faults"): a shot study on a local
`distributed` cluster of 3 worker processes (under nannies, one thread each), 2 of them
SIGKILLed while it runs, the result compared with the single-process study.

What it does:
  1. the single-process study: `kisstime.shot_study(samples=N)` (the built-in study);
  2. a LocalCluster of 3 workers; `kisstime.dask.shot_study(client, samples=N,
     chunk=C)` in the main thread while a second thread waits until the workers hold
     --after finished chunks and then SIGKILLs the 2 workers holding the most (their
     finished chunks are lost with them), one right after the other. The nannies start new
     workers, and the scheduler re-runs the lost chunks on the survivor and on them;
  3. compares the two studies: the summary (repr: exact floats), the per-sample rows bit
     for bit, the potted balls; prints what happened (chunks held by each killed worker,
     how often chunk tasks ran, the workers' pids before and after, wall times).

Usage (from the repository root, with the package installed: pip install ./python):
  python3 tools/soak/dask_kill.py [--samples 200000] [--chunk 2500]

Exits non-zero when the studies differ. Results recorded in FUZZING.md.
"""

import argparse
import json
import logging
import os
import signal
import sys
import threading
import time

import distributed

import kisstime
import kisstime.dask


def held_by_worker(dask_scheduler):
    """On the scheduler: each worker's (chunks held, chunks running, pid)."""
    out = {}
    for address, ws in dask_scheduler.workers.items():
        held = [ts for ts in ws.has_what if str(ts.key).startswith("kisstime-chunk-")]
        running = [ts for ts in ws.processing if str(ts.key).startswith("kisstime-chunk-")]
        out[address] = (len(held), len(running), ws.pid)
    return out


def chunk_states(dask_scheduler):
    prefix = dask_scheduler.task_prefixes.get("kisstime-chunk")
    return {} if prefix is None else dict(prefix.state_counts)


def worker_pids(dask_scheduler):
    return sorted(ws.pid for ws in dask_scheduler.workers.values())


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--samples", type=int, default=200_000)
    ap.add_argument("--chunk", type=int, default=2_500)
    ap.add_argument("--after", type=int, default=4, help="finished chunks before the kills")
    ap.add_argument("--json")
    args = ap.parse_args()
    result = {"samples": args.samples, "chunk": args.chunk, "workers": 3, "killed": 2,
              "cpus": os.cpu_count(),
              "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())}
    start = time.time()
    want = kisstime.shot_study(samples=args.samples)
    result["single_process_s"] = round(time.time() - start, 2)

    cluster = distributed.LocalCluster(
        n_workers=3, threads_per_worker=1, processes=True, dashboard_address=None,
        scheduler_kwargs={"dashboard_address": ":0"}, silence_logs=logging.ERROR)
    client = distributed.Client(cluster)
    client.wait_for_workers(3, timeout=60)
    result["pids_before"] = client.run_on_scheduler(worker_pids)
    kills, errors = [], []
    done = threading.Event()

    def killer():
        try:
            while not done.is_set():
                counts = client.run_on_scheduler(held_by_worker)
                held = sorted(((h, pid, a) for a, (h, _, pid) in counts.items()), reverse=True)
                if sum(h for h, _, _ in held) >= args.after:
                    for h, pid, address in held[:2]:
                        os.kill(pid, signal.SIGKILL)
                        kills.append({"pid": pid, "address": address, "chunks_held": h,
                                      "at_s": round(time.time() - t0, 2)})
                    result["held_at_kill"] = {a: c for a, c in counts.items()}
                    return
                time.sleep(0.005)
        except BaseException as exc:  # noqa: BLE001 - reported below
            errors.append(repr(exc))

    t0 = time.time()
    thread = threading.Thread(target=killer, daemon=True)
    thread.start()
    try:
        got = kisstime.dask.shot_study(client, samples=args.samples, chunk=args.chunk)
    finally:
        done.set()
        thread.join(timeout=30)
    result["dask_s"] = round(time.time() - t0, 2)
    result["kills"] = kills
    result["errors"] = errors
    result["chunks"] = -(-args.samples // args.chunk)
    result["chunk_task_states"] = client.run_on_scheduler(chunk_states)
    time.sleep(2)
    result["pids_after"] = client.run_on_scheduler(worker_pids)
    same = (repr(got.summary) == repr(want.summary)
            and got.samples.tobytes() == want.samples.tobytes()
            and list(got.potted) == list(want.potted))
    result["equal_to_single_process"] = same
    result["killed_mid_run"] = len(kills) == 2 and (
        sum(c[0] for c in result.get("held_at_kill", {}).values()) < result["chunks"])
    client.close()
    cluster.close()
    print(json.dumps(result, indent=1))
    if args.json:
        with open(args.json, "w") as f:
            json.dump(result, f, indent=1)
    return 0 if same and result["killed_mid_run"] and not errors else 1


if __name__ == "__main__":
    sys.exit(main())
