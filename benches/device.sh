#!/usr/bin/env bash
# The GPU benchmarks for a lent device machine (issues 16, 17 and 26), as one prepared run:
# - kernels: `kisstime bench` on the GPU, `midshot` and `worst`, each reporting per-pair
#   and next-collision pairs/s end to end, the phase split (host packing and upload,
#   kernel, readback and unpacking) and the agreement with the CPU f64 reference, plus
#   one CPU run for scale;
# - sim: `kisstime bench --sim` on the GPU event loop, ordinary shots and breaks: shots/s
#   and events/s end to end and kernel-only, the phases (pack, upload, kernel and the
#   passes on the device's clock where it has timestamps, readback, unpack, and the host
#   work hidden behind the device's), and (for ordinary shots up to SIM_CPU_MAX tables, where the CPU runs beside
#   it) the tables whose events differ from the CPU's;
# - study: `kisstime shots` (the built-in study) on the GPU and on the CPU: samples/s end
#   to end and the GPU's phases (`--verbose`), and on the GPU again with each sample's strike
#   drawn on the host and shipped (KISSTIME_GPU_DRAWS=0: what the device's draws gain);
# - first, where the binary's directory holds `pipeline_stats` (examples/pipeline_stats.rs),
#   the driver's own statistics of the compiled event loop (registers, spills, workgroup
#   memory, where it reports them) for each thread count, row split and tables a workgroup, to
#   $OUT/pipeline_stats.txt and the output.
# PARTS (default "kernels sim study") chooses the parts; SIZES, KERNEL_SCENARIOS, KERNEL_PRECISIONS,
# SIM_SIZES, BREAK_SIZES, SIM_PRECISIONS, ONE_CHUNK_SIZES (ordinary shots again in one chunk, with no
# host work beside the device's; default the largest of SIM_SIZES), ROW_SERIAL_SIZES (ordinary shots
# and breaks again with each ball-table row filled on one thread, KISSTIME_GPU_ROW_THREADS=1: what
# splitting a row's items over the threads gains; default the smallest of SIM_SIZES),
# EXACT_OFF_SIZES (ordinary shots again with the CPU beside, the event loop compiled from
# the WGSL as wgpu does, which the driver may contract, KISSTIME_GPU_EXACT=0: what the
# exact SPIR-V costs, and how many tables part from the CPU's bits without it; default the
# smallest of SIM_SIZES), GROUPED_SIZES (ordinary shots and breaks again for each THREADS:TABLES of
# GROUPED, default "16:1 16:2 16:4 32:2": a table's threads, KISSTIME_EVENT_LOOP_THREADS, and
# tables a workgroup, KISSTIME_GPU_TABLES_PER_GROUP: what occupancy gains; default the smallest
# of SIM_SIZES) and STUDY_SAMPLES their sizes. The sim table's `differ` column is
# events/moved/not-identical against the CPU (the last 0 on a device with IEEE f64). Prints one table per part at
# the end; the raw JSON goes to $OUT/bench.jsonl, $OUT/sim.jsonl and $OUT/study.jsonl.
# Each run has its own timeout (150 s), so the whole stays within one 10-minute call.
#
# Here (x86-64, this checkout): build the binary and fetch the Vulkan loader, once:
#   cargo build --release && mkdir -p .dev && cp target/release/kisstime .dev/
#   cargo build --release --example pipeline_stats && cp target/release/examples/pipeline_stats .dev/
#   echo /.dev/ >> .git/info/exclude; echo /.gl/ >> .git/info/exclude
#   (the `device` tool's README gives the apt-get download line for .gl/)
# Then, with the `device` tool: run `bash benches/device.sh .dev/kisstime`, carry [".dev", ".gl"].
# Locally (lavapipe), smaller:
#   SIZES=2000 SIM_SIZES=2000 STUDY_SAMPLES=2000 bash benches/device.sh target/release/kisstime
set -uo pipefail
BIN="${1:-.dev/kisstime}"
OUT="${OUT:-$(mktemp -d)}"
SIZES="${SIZES:-100000 1000000}"
KERNEL_PRECISIONS="${KERNEL_PRECISIONS:-f32 f64}"
KERNEL_SCENARIOS="${KERNEL_SCENARIOS:-midshot worst}"
SIM_SIZES="${SIM_SIZES:-100000 1000000}"
SIM_PRECISIONS="${SIM_PRECISIONS:-f64}"
BREAK_SIZES="${BREAK_SIZES:-${SIM_SIZES%% *}}"
SIM_CPU_MAX="${SIM_CPU_MAX:-100000}"
STUDY_SAMPLES="${STUDY_SAMPLES:-1000000}"
ONE_CHUNK_SIZES="${ONE_CHUNK_SIZES:-${SIM_SIZES##* }}"
ROW_SERIAL_SIZES="${ROW_SERIAL_SIZES:-${SIM_SIZES%% *}}"
EXACT_OFF_SIZES="${EXACT_OFF_SIZES:-${SIM_SIZES%% *}}"
GROUPED_SIZES="${GROUPED_SIZES:-${SIM_SIZES%% *}}"
GROUPED="${GROUPED:-16:1 16:2 16:4 32:2}"
PARTS="${PARTS:-kernels sim study}"
mkdir -p "$OUT"
if compgen -G ".gl/*.deb" > /dev/null; then
  for f in .gl/*.deb; do dpkg -x "$f" /; done
  ldconfig
fi
ICD=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
if [ -z "${VK_DRIVER_FILES:-}" ] && [ -f "$ICD" ]; then export VK_DRIVER_FILES="$ICD"; fi
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-$(mktemp -d)}"
command -v nvidia-smi > /dev/null && nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader
echo "binary: $BIN; cores: $(nproc); sizes: $SIZES"
STATS_BIN="$(dirname "$BIN")/pipeline_stats"
if [ -x "$STATS_BIN" ]; then
  timeout 120 "$STATS_BIN" > "$OUT/pipeline_stats.txt" 2>&1 || echo "FAIL pipeline_stats (exit $?)"
  cat "$OUT/pipeline_stats.txt"
fi
: > "$OUT/bench.jsonl"
: > "$OUT/sim.jsonl"
: > "$OUT/sim_one_chunk.jsonl"
: > "$OUT/sim_row_serial.jsonl"
: > "$OUT/sim_exact_off.jsonl"
: > "$OUT/sim_grouped.jsonl"
: > "$OUT/study.jsonl"
run() { # output file, label, then kisstime bench arguments
  local file="$1" label="$2"; shift 2
  local start=$SECONDS
  if timeout 150 "$BIN" bench "$@" --json >> "$file" 2>> "$OUT/stderr.txt"; then
    echo "ok   $label ($((SECONDS - start)) s)"
  else
    echo "FAIL $label (exit $?, $((SECONDS - start)) s; see stderr.txt)"
  fi
}
if [[ " $PARTS " == *" kernels "* ]]; then
  for n in $SIZES; do
    for scenario in $KERNEL_SCENARIOS; do
      for precision in $KERNEL_PRECISIONS; do
        run "$OUT/bench.jsonl" "gpu $precision $scenario $n" --scenario "$scenario" --tables "$n" --backend gpu --precision "$precision" --reps 3
      done
    done
  done
  run "$OUT/bench.jsonl" "cpu f64 midshot 100000" --scenario midshot --tables 100000 --backend cpu --reps 3
fi
if [[ " $PARTS " == *" sim "* ]]; then
  for workload in ordinary breaks; do
    sizes="$SIM_SIZES"
    if [ "$workload" = breaks ]; then sizes="$BREAK_SIZES"; fi
    for n in $sizes; do
      for precision in $SIM_PRECISIONS; do
        # the CPU beside the GPU only where it is quick: ordinary shots up to SIM_CPU_MAX
        backend=gpu
        if [ "$workload" = ordinary ] && [ "$n" -le "$SIM_CPU_MAX" ]; then backend=all; fi
        run "$OUT/sim.jsonl" "sim $backend $precision $workload $n" --sim "$workload" --tables "$n" --backend "$backend" --precision "$precision" --reps 1
      done
    done
  done
  # the same ordinary shots in one chunk, with no host work beside the device's: what the
  # overlap gains (KISSTIME_GPU_PIPELINE_CHUNKS=1)
  for n in $ONE_CHUNK_SIZES; do
    KISSTIME_GPU_PIPELINE_CHUNKS=1 run "$OUT/sim_one_chunk.jsonl" "sim gpu f64 ordinary $n, one chunk" \
      --sim ordinary --tables "$n" --backend gpu --precision f64 --reps 1
  done
  # ordinary shots and breaks with each ball-table row on one thread (as before the rows'
  # items were split over the workgroup's threads): what the split gains
  for n in $ROW_SERIAL_SIZES; do
    for workload in ordinary breaks; do
      KISSTIME_GPU_ROW_THREADS=1 run "$OUT/sim_row_serial.jsonl" "sim gpu f64 $workload $n, rows on one thread" \
        --sim "$workload" --tables "$n" --backend gpu --precision f64 --reps 1
    done
  done
  # ordinary shots from the WGSL as wgpu compiles it (the driver may contract), the CPU
  # beside: what the exact SPIR-V costs, and the tables that part from the CPU's bits
  for n in $EXACT_OFF_SIZES; do
    KISSTIME_GPU_EXACT=0 run "$OUT/sim_exact_off.jsonl" "sim all f64 ordinary $n, contraction allowed" \
      --sim ordinary --tables "$n" --backend all --precision f64 --reps 1
  done
  # ordinary shots and breaks at other thread counts and several tables a workgroup: what
  # occupancy gains (the same answers at every count)
  for n in $GROUPED_SIZES; do
    for g in $GROUPED; do
      for workload in ordinary breaks; do
        : > "$OUT/grouped_one.json"
        KISSTIME_EVENT_LOOP_THREADS="${g%%:*}" KISSTIME_GPU_TABLES_PER_GROUP="${g##*:}" \
          run "$OUT/grouped_one.json" "sim gpu f64 $workload $n, ${g%%:*} threads x ${g##*:} tables a workgroup" \
          --sim "$workload" --tables "$n" --backend gpu --precision f64 --reps 1
        # the JSON does not name the knobs: its workload tagged with them
        sed "s/\"workload\": \"$workload\"/\"workload\": \"$workload [${g%%:*}x${g##*:}]\"/" \
          "$OUT/grouped_one.json" >> "$OUT/sim_grouped.jsonl"
      done
    done
  done
fi
if [[ " $PARTS " == *" study "* ]]; then
  for n in $STUDY_SAMPLES; do
    for backend in gpu cpu; do
      start=$SECONDS
      if timeout 150 "$BIN" shots --samples "$n" --backend "$backend" --precision f64 --json --verbose \
          >> "$OUT/study.jsonl" 2>> "$OUT/study_stderr.txt"; then
        echo "ok   study $backend f64 $n ($((SECONDS - start)) s)"
      else
        echo "FAIL study $backend f64 $n (exit $?, $((SECONDS - start)) s; see study_stderr.txt)"
      fi
    done
    # the same GPU study with each sample's strike drawn and struck on the host and shipped
    # (KISSTIME_GPU_DRAWS=0): what the device's own draws gain
    start=$SECONDS
    if KISSTIME_GPU_DRAWS=0 timeout 150 "$BIN" shots --samples "$n" --backend gpu --precision f64 --json --verbose \
        >> "$OUT/study_host_draws.jsonl" 2>> "$OUT/study_host_draws_stderr.txt"; then
      echo "ok   study gpu f64 $n, strikes drawn on the host ($((SECONDS - start)) s)"
    else
      echo "FAIL study gpu f64 $n, strikes drawn on the host (exit $?, $((SECONDS - start)) s)"
    fi
  done
  grep -h "GPU phases\|samples of" "$OUT/study_stderr.txt"
  echo "strikes drawn on the host (KISSTIME_GPU_DRAWS=0):"
  grep -h "GPU phases\|samples of" "$OUT/study_host_draws_stderr.txt"
fi
# one table of everything that ran (the JSON objects follow one another in the file)
python3 - "$OUT/bench.jsonl" "$OUT/sim.jsonl" "$OUT/study.jsonl" "$OUT/sim_one_chunk.jsonl" "$OUT/sim_row_serial.jsonl" "$OUT/sim_exact_off.jsonl" "$OUT/sim_grouped.jsonl" <<'PY' || cat "$OUT"/*.jsonl
import json, sys
def objects(path):
    text, dec, at, out = open(path).read(), json.JSONDecoder(), 0, []
    while True:
        while at < len(text) and text[at].isspace():
            at += 1
        if at >= len(text):
            return out
        obj, at = dec.raw_decode(text, at)
        out.append(obj)
rows, sims, studies = objects(sys.argv[1]), objects(sys.argv[2]), objects(sys.argv[3])
one_chunk = objects(sys.argv[4])
for r in one_chunk:
    r["workload"] += " (1 chunk)"
row_serial = objects(sys.argv[5])
for r in row_serial:
    r["workload"] += " (rows on 1 thread)"
exact_off = objects(sys.argv[6])
for r in exact_off:
    r["workload"] += " (contraction allowed)"
grouped = objects(sys.argv[7])
for r in grouped:
    w, _, g = r["workload"].partition(" [")
    r["workload"] = w + " (" + g.rstrip("]") + ")"
sims += one_chunk + row_serial + exact_off + grouped
g = lambda v: "-" if v is None else f"{v / 1e6:,.0f} M"
k = lambda s: "-" if not s else f"{s['kernel_s'] * 1e3:.2f}/{(s['upload_s'] + s['kernel_s'] + s['readback_s']) * 1e3:.2f} ms"
print(f"{'scenario':<8} {'tables':>8} {'backend':<8} {'pairs/s':>10} {'next/s':>10} "
      f"{'pairs kernel/all':>18} {'next kernel/all':>18} {'outside tier':>12} device")
for r in rows:
    for b in r["backends"]:
        a = b.get("agreement") or {}
        print(f"{r['scenario']:<8} {r['tables']:>8} {b['backend'] + ' ' + b['precision']:<8} "
              f"{g(b['pair_times_pairs_per_s']):>10} {g(b['next_collisions_pairs_per_s']):>10} "
              f"{k(b['pair_times_gpu_split']):>18} {k(b['next_collisions_gpu_split']):>18} "
              f"{a.get('pairs_outside_tier', '-'):>12} {b['device']}")
if sims:
    print()
    print(f"{'workload':<9} {'tables':>8} {'backend':<8} {'shots/s':>12} {'events/s':>12} "
          f"{'kernel shots/s':>15} {'ev/shot':>8} {'cut':>4} {'differ':>10} device")
    for r in sims:
        for b in r["backends"]:
            d = b.get("tables_differ")
            if d is not None:
                d = list(d) + [b.get("tables_not_identical")]
            print(f"{r['workload']:<9} {r['tables']:>8} {b['backend'] + ' ' + b['precision']:<8} "
                  f"{b['shots_per_s']:>12,.0f} {b['events_per_s']:>12,.0f} "
                  f"{b.get('kernel_shots_per_s') or 0:>15,.0f} {b['events_per_shot']:>8.1f} "
                  f"{b['cut']:>4} {'-' if d is None else f'{d[0]}/{d[1]}/{d[2]}':>10} {b['device']}"
                  f"{' (exact)' if b.get('exact') else ''}")
            sp = b.get("gpu_split")
            if sp:
                print("          phases: " + ", ".join(
                    f"{name} {(sp.get(name + '_s') or 0) * 1e3:.1f} ms"
                    for name in ("pack", "upload", "kernel", "kernel_device", "kernel_tail",
                                 "readback", "unpack", "overlapped"))
                    + f" ({sp.get('tail_dispatches', 0)} tail dispatches of {b.get('dispatches')})")
# each change against its predecessor, where both ran: the row split (rows on one thread),
# the host work beside the device's (one chunk)
def gpu_of(r):
    return next((b for b in r["backends"] if b["backend"] == "gpu"), None)
base = {(r["workload"], r["tables"]): gpu_of(r) for r in sims if "(" not in r["workload"]}
def compare(what, workload, tables, old, new):
    """One change: old (before it) against new (with it), kernel and end to end."""
    if not (new and old and new.get("gpu_split") and old.get("gpu_split")):
        return
    kn, ko = new["gpu_split"]["kernel_s"], old["gpu_split"]["kernel_s"]
    print(f"{what}, {workload} {tables}: kernel {ko * 1e3:,.0f} -> "
          f"{kn * 1e3:,.0f} ms (x{ko / kn if kn else 0:.2f}), end to end "
          f"{old['shots_per_s']:,.0f} -> {new['shots_per_s']:,.0f} shots/s "
          f"(x{new['shots_per_s'] / old['shots_per_s'] if old['shots_per_s'] else 0:.2f})")
for tag, what in ((" (rows on 1 thread)", "row split"), (" (1 chunk)", "four chunks"),
                  (" (contraction allowed)", "exact SPIR-V")):
    for r in sims:
        if not r["workload"].endswith(tag):
            continue
        new, old = base.get((r["workload"][: -len(tag)], r["tables"])), gpu_of(r)
        if not (new and old and new.get("gpu_split") and old.get("gpu_split")):
            continue
        compare(what, r["workload"][: -len(tag)], r["tables"], old, new)
# threads x tables a workgroup against the default (64 threads, one table)
for r in sims:
    w, _, g = r["workload"].partition(" (")
    if not (g.endswith(")") and "x" in g and g[0].isdigit()):
        continue
    compare(f"{g[:-1]} a workgroup", w, r["tables"], base.get((w, r["tables"])), gpu_of(r))
if studies:
    print()
    print(f"{'samples':>8} {'seconds':>8} {'samples/s':>12}  backend")
    for r in studies:
        n = r.get("samples") or r.get("n") or 0
        secs = r.get("seconds") or 0
        print(f"{n:>8} {secs:>8.2f} {(n / secs if secs else 0):>12,.0f}  {r.get('backend')}")
PY
