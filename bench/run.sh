#!/usr/bin/env bash
# Runs the criterion benches (crates/prism-benches/benches/trace.rs) and prints a table of medians:
# time per iteration, throughput (Mrays/s for ray benches, Mprims/s for builds) and the
# speed-up of all threads over one, all from this one run, plus the machine and how much
# CPU other processes took meanwhile (on a shared machine, runs with much of it are noise).
#
# Usage: bench/run.sh [criterion filter and options…]   e.g. bench/run.sh primary_rays
# The full log goes to $CARGO_TARGET_DIR/bench-trace.log (default target/), the table to
# bench-summary.md beside it.
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
target=${CARGO_TARGET_DIR:-$root/target}
log=$target/bench-trace.log
summary=$target/bench-summary.md
cd "$root"
mkdir -p "$target"

machine() {
    local cpu
    cpu=$(grep -m1 'model name' /proc/cpuinfo 2>/dev/null | cut -d: -f2- | sed 's/^ *//')
    echo "machine: $(nproc) logical CPUs, ${cpu:-unknown CPU}"
}

# Busy and total CPU ticks of the whole machine, from /proc/stat.
cpu_ticks() {
    awk '/^cpu / { print $2 + $3 + $4 + $7 + $8 + $9, $2 + $3 + $4 + $5 + $6 + $7 + $8 + $9 }' /proc/stat
}

read -r busy0 _ < <(cpu_ticks)
start=$(date +%s%N)
cargo bench -p prism-benches --bench trace -- "$@" 2>&1 | tee "$log"
wall_ms=$(( ($(date +%s%N) - start) / 1000000 ))
read -r busy1 _ < <(cpu_ticks)
# CPU seconds this script's children used: the second line of bash's `times` (user,
# system), which must run in this shell, not in a command substitution's subshell.
times >"$target/bench-times.txt"
own_s=$(sed -n 2p "$target/bench-times.txt" | awk '{
    split($1, u, /[ms]/); split($2, s, /[ms]/); print u[1] * 60 + u[2] + s[1] * 60 + s[2] }')
others=$(awk -v b="$((busy1 - busy0))" -v hz="$(getconf CLK_TCK)" -v own="$own_s" \
    -v w="$wall_ms" 'BEGIN { o = b / hz - own; if (o < 0) o = 0; printf "%.2f", o / (w / 1000) }')

{
    echo "$(machine); other processes used $others cores on average during the run"
    echo
    grep '^context:' "$log" | sed 's/^context: /- /' || true
    echo
    python3 - "$target/criterion" "$log" <<'PY'
import json, os, re, sys

criterion_dir, log = sys.argv[1], sys.argv[2]
# Only the benchmarks this run measured, in the order it measured them.
ids = []
for line in open(log, encoding="utf-8", errors="replace"):
    m = re.match(r"Benchmarking (\S+): Analyzing", line)
    if m and m.group(1) not in ids:
        ids.append(m.group(1))

def unit(group):
    return "Mprims/s" if group.startswith("bvh_build") else "Mrays/s"

def fmt_time(ns):
    for scale, name in ((1e9, "s"), (1e6, "ms"), (1e3, "µs")):
        if ns >= scale:
            return f"{ns / scale:.3g} {name}"
    return f"{ns:.3g} ns"

rows, medians = [], {}
for bench_id in ids:
    new = os.path.join(criterion_dir, bench_id, "new")
    try:
        est = json.load(open(os.path.join(new, "estimates.json")))
        meta = json.load(open(os.path.join(new, "benchmark.json")))
    except OSError:
        continue
    med = est["median"]["point_estimate"]
    lo = est["median"]["confidence_interval"]["lower_bound"]
    hi = est["median"]["confidence_interval"]["upper_bound"]
    medians[bench_id] = med
    elements = (meta.get("throughput") or {}).get("Elements")
    rate = f"{elements / med * 1e3:.3f} {unit(bench_id)}" if elements else ""
    rows.append((bench_id, fmt_time(med), f"{fmt_time(lo)} – {fmt_time(hi)}", rate))

print("| benchmark | median | 95% CI of median | throughput at median |")
print("|---|---|---|---|")
for r in rows:
    print("| " + " | ".join(r) + " |")

speedups = []
for bench_id, med in medians.items():
    m = re.fullmatch(r"(.*)/(\d+)t", bench_id)
    if m and m.group(2) != "1" and f"{m.group(1)}/1t" in medians:
        speedups.append(f"- {m.group(1)}: {m.group(2)} threads are "
                        f"{medians[m.group(1) + '/1t'] / med:.2f}× one thread")
if speedups:
    print()
    print("\n".join(speedups))
PY
} | tee "$summary"
echo "(summary written to $summary)"
