#!/usr/bin/env bash
# Path tracing throughput: samples (paths) per CPU-second of `prism render --integrator path`
# on the built-in Cornell boxes (cornell-light, cornell-light-glass) at 512², max depth 6,
# on 1 and 2 render threads. CPU time is the process's user + system time, so a figure
# on 2 threads shows what parallelism costs, not what it gains in wall time. Each
# configuration runs ROUNDS times (default 3); the median is reported. How the
# "Throughput" table of docs/path-tracing.md was made.
#
# Usage: bench/path-tracing.sh [output file]; SAMPLES=n renders n×n paths per pixel
# (default 4). PRISM_LOCK names a lock file that serialises each timed render with builds
# on a shared machine (default /tmp/prism-cargo.lock).
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
out=${1:-/dev/stdout}
rounds=${ROUNDS:-3}
n=${SAMPLES:-4}
lock=${PRISM_LOCK:-/tmp/prism-cargo.lock}
cd "$root"
flock "$lock" cargo build --release --quiet -p prism-cli
prism="${CARGO_TARGET_DIR:-target}/release/prism"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

median() { sort -g | awk '{ v[NR] = $1 } END { print v[int((NR + 1) / 2)] }'; }

{
    echo "| scene | threads | paths per pixel | CPU s (median of $rounds) | wall s | M paths per CPU-second |"
    echo "|---|---|---|---|---|---|"
    for scene in cornell-light cornell-light-glass; do
        for threads in 1 2; do
            : >"$work/cpu"
            : >"$work/wall"
            for _ in $(seq "$rounds"); do
                flock "$lock" /usr/bin/time -f "%U %S %e" -o "$work/time" \
                    "$prism" render --builtin "$scene" --integrator path -W 512 -H 512 \
                    --depth 6 --samples "$n" --threads "$threads" -q -o "$work/x.png"
                awk '{ print $1 + $2 }' "$work/time" >>"$work/cpu"
                awk '{ print $3 }' "$work/time" >>"$work/wall"
            done
            cpu=$(median <"$work/cpu")
            wall=$(median <"$work/wall")
            paths=$((512 * 512 * n * n))
            rate=$(awk -v p="$paths" -v c="$cpu" 'BEGIN { printf "%.2f", p / c / 1e6 }')
            echo "| $scene | $threads | $((n * n)) | $cpu | $wall | $rate |"
        done
    done
} | tee "$out"
