#!/usr/bin/env bash
# Runs one fuzz target on one core until 10 million executions or SECONDS_MAX seconds.
# Usage: fuzz/run.sh <target> [seconds, default 3600]   (from the repository root or fuzz/)
# The nightly toolchain is used if installed; otherwise stable with RUSTC_BOOTSTRAP=1.
set -euo pipefail
cd "$(dirname "$0")"
target=$1
secs=${2:-3600}
if rustup run nightly rustc --version >/dev/null 2>&1; then
    cargo=(cargo +nightly)
else
    export RUSTC_BOOTSTRAP=1
    cargo=(cargo)
fi
mkdir -p "corpus/$target" "seeds/$target"
# one thread for the Rayon pool the batch driver uses
export RAYON_NUM_THREADS=1
exec "${cargo[@]}" fuzz run --sanitizer none --debug-assertions "$target" \
    "corpus/$target" "seeds/$target" -- \
    -runs=10000000 -max_total_time="$secs" -max_len=4096 -timeout=10 \
    -rss_limit_mb=4096 -print_final_stats=1
