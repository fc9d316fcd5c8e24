#!/usr/bin/env bash
# Runs `prism bench` over the full matrix: every built-in scene (the bad cases included),
# the SPD scenes when ../shared/scenes/spd exists, and the default methods, one thread.
# Writes bench/results/accel.{csv,json,svg} and the printed table to accel.txt.
# Usage: bench/accel-bench.sh [prism binary] [extra prism bench arguments…]
set -euo pipefail
cd "$(dirname "$0")/.."
prism=${1:-${CARGO_TARGET_DIR:-target}/release/prism}
shift || true
spd=../shared/scenes/spd
extra=()
if [[ -d $spd ]]; then extra+=(--spd "$spd"); fi
out=bench/results
mkdir -p "$out"
"$prism" bench "${extra[@]}" --threads 1 \
    --csv "$out/accel.csv" --json "$out/accel.json" --chart "$out/accel.svg" "$@" \
    | tee "$out/accel.txt"
