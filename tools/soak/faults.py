#!/usr/bin/env python3
"""Faults of `kisstime simulate` (issue 31, "Soak and faults"): signals halfway through a
long run, a disk that fills up, a full device.

  1. SIGINT and SIGTERM sent halfway through `simulate IN --strikes S -o out.npy --final
     final.npy` (halfway by the wall time of a complete run of the same input): expected
     exit status 130, a message "interrupted after X of Y tables" with 0 < X < Y, the
     file that was at out.npy before the run left as it was, final.npy not created, no
     temporary file (.kisstime-*) left in the folder;
  2. the disk filling up: the outputs on a tmpfs of 2 MiB (`mount -t tmpfs -o size=2m`;
     needs root, else skipped with the reason), once with --final (written as it comes)
     and once with -o events.npy (spooled, written at the end), a previous file there:
     expected a non-zero exit, an error naming the output path and "No space left", the
     previous file intact, no temporary file left;
  3. `-o /dev/full`, `--final /dev/full`, `--outcomes /dev/full` and standard output on
     /dev/full: a non-zero exit and an error naming /dev/full (standard output).

Usage (from the repository root):
  python3 tools/soak/faults.py [--tables 300000] [--bin target/release/kisstime]

Needs numpy (the input is generated as tools/soak/soak.py does). Exits non-zero when an
expectation fails; the results are recorded in FUZZING.md ("Soak and faults").
"""

import argparse
import glob
import json
import os
import re
import signal
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import soak  # noqa: E402

PREVIOUS = b"the previous run's output\n"


def temporaries(folder):
    return sorted(os.path.basename(p) for p in glob.glob(os.path.join(folder, ".kisstime-*")))


def run_signal(exe, balls, strikes, folder, sig, delay):
    out = os.path.join(folder, "out.npy")
    final = os.path.join(folder, "final.npy")
    with open(out, "wb") as f:
        f.write(PREVIOUS)
    cmd = [exe, "simulate", balls, "--strikes", strikes, "-o", out, "--final", final]
    proc = subprocess.Popen(cmd, stderr=subprocess.PIPE, text=True)
    time.sleep(delay)
    proc.send_signal(sig)
    _, err = proc.communicate()
    m = re.search(r"interrupted after (\d+) of (\d+) tables", err)
    got = {
        "signal": signal.Signals(sig).name,
        "after_s": round(delay, 2),
        "exit": proc.returncode,
        "message": err.strip(),
        "previous_intact": open(out, "rb").read() == PREVIOUS,
        "final_created": os.path.exists(final),
        "temporaries": temporaries(folder),
    }
    got["ok"] = (proc.returncode == 130 and m is not None and 0 < int(m[1]) < int(m[2])
                 and got["previous_intact"] and not got["final_created"]
                 and not got["temporaries"])
    return got


def run_full(exe, args, folder, previous, expect_path):
    if previous:
        with open(previous, "wb") as f:
            f.write(PREVIOUS)
    proc = subprocess.run([exe, "simulate"] + args, stderr=subprocess.PIPE,
                          stdout=subprocess.DEVNULL if expect_path != "standard output"
                          else open("/dev/full", "wb"), text=True)
    err = proc.stderr.strip()
    got = {"args": " ".join(args), "exit": proc.returncode, "message": err}
    ok = proc.returncode not in (0, None) and expect_path in err and "No space left" in err
    if previous:
        got["previous_intact"] = open(previous, "rb").read() == PREVIOUS
        ok = ok and got["previous_intact"]
    if folder:
        got["temporaries"] = temporaries(folder)
        ok = ok and not got["temporaries"]
    got["ok"] = ok
    return got


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--tables", type=int, default=300_000)
    ap.add_argument("--balls", type=int, default=6)
    ap.add_argument("--bin")
    ap.add_argument("--json", help="write the results here")
    args = ap.parse_args()
    exe = soak.binary(args.bin)
    results = {"binary": exe, "tables": args.tables, "cpus": os.cpu_count(),
               "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())}
    with tempfile.TemporaryDirectory(prefix="kisstime-faults-") as work:
        balls = os.path.join(work, "balls.npy")
        strikes = os.path.join(work, "strikes.npy")
        soak.generate(args.tables, args.balls, 7, balls, strikes)
        out_dir = os.path.join(work, "out")
        os.mkdir(out_dir)
        # a complete run: how long "halfway" is
        start = time.time()
        done = subprocess.run([exe, "simulate", balls, "--strikes", strikes, "-o",
                               os.path.join(out_dir, "out.npy"), "--final",
                               os.path.join(out_dir, "final.npy")],
                              stderr=subprocess.PIPE, text=True)
        full_s = time.time() - start
        results["complete_run"] = {"exit": done.returncode, "wall_s": round(full_s, 2),
                                   "message": done.stderr.strip()}
        for name in os.listdir(out_dir):
            os.remove(os.path.join(out_dir, name))
        results["signals"] = [run_signal(exe, balls, strikes, out_dir, sig, full_s / 2)
                              for sig in (signal.SIGINT, signal.SIGTERM)]
        # a small disk
        small = os.path.join(work, "small")
        os.mkdir(small)
        mounted = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=2m", "tmpfs", small],
                                 stderr=subprocess.PIPE, text=True)
        if mounted.returncode != 0:
            results["disk_full"] = {"skipped": f"mount failed: {mounted.stderr.strip()}"}
        else:
            try:
                prev = os.path.join(small, "final.npy")
                runs = [run_full(exe, [balls, "--strikes", strikes, "--final", prev], small,
                                 prev, prev)]
                prev = os.path.join(small, "events.npy")
                runs.append(run_full(exe, [balls, "--strikes", strikes, "-o", prev,
                                           "--outcomes", os.path.join(work, "oc.npy")],
                                     small, prev, prev))
                results["disk_full"] = runs
            finally:
                subprocess.run(["umount", small])
        results["dev_full"] = [
            run_full(exe, [balls, "--strikes", strikes, flag, "/dev/full"], None, None,
                     "/dev/full")
            for flag in ("-o", "--final", "--outcomes")
        ] + [run_full(exe, [balls, "--strikes", strikes], None, None, "standard output")]
    checks = results["signals"] + results["dev_full"] + (
        results["disk_full"] if isinstance(results["disk_full"], list) else [])
    results["all_ok"] = all(c["ok"] for c in checks)
    print(json.dumps(results, indent=1))
    if args.json:
        with open(args.json, "w") as f:
            json.dump(results, f, indent=1)
    return 0 if results["all_ok"] else 1


if __name__ == "__main__":
    sys.exit(main())
