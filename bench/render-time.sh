#!/usr/bin/env bash
# Wall time of the whole `prism render` command (start-up, scene, BVH build, render, PNG
# write) on the default scene, or on whatever scene the extra arguments select, followed by
# prism's own --stats-json split of that time. Uses hyperfine when it is installed (as root
# with apt-get it installs the Debian package; set PRISM_NO_INSTALL=1 to prevent that), and
# a loop of timed runs otherwise.
#
# Usage: bench/render-time.sh [prism render options…]   e.g. bench/render-time.sh -b sphereflake
# RUNS (default 10) sets the number of timed runs.
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
target=${CARGO_TARGET_DIR:-$root/target}
runs=${RUNS:-10}
cd "$root"
cargo build --release -p prism-cli
bin=$target/release/prism

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cmd=("$bin" render --quiet --output "$work/prism.png" "$@")

if ! command -v hyperfine >/dev/null && [ -z "${PRISM_NO_INSTALL:-}" ] \
    && [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
    echo "installing hyperfine (apt-get; PRISM_NO_INSTALL=1 skips this)…" >&2
    apt-get install -y -qq hyperfine >/dev/null 2>&1 \
        || { apt-get update -qq >/dev/null 2>&1 && apt-get install -y -qq hyperfine >/dev/null 2>&1; } \
        || echo "could not install hyperfine; timing with a loop instead" >&2
fi

echo "$(nproc) logical CPUs, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//'), load average $(cut -d' ' -f1-3 /proc/loadavg)"
if command -v hyperfine >/dev/null; then
    hyperfine --warmup 2 --runs "$runs" --export-json "$work/hyperfine.json" \
        "$(printf '%q ' "${cmd[@]}")"
    # hyperfine leads with the mean; on a shared machine the median is the steadier figure.
    python3 - "$work/hyperfine.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))["results"][0]
print(f"wall time over {len(r['times'])} runs: median {r['median'] * 1e3:.0f} ms, "
      f"min {r['min'] * 1e3:.0f} ms, max {r['max'] * 1e3:.0f} ms")
PY
else
    times=()
    "${cmd[@]}" # warm-up: page cache, CPU frequency
    for _ in $(seq "$runs"); do
        start=$(date +%s%N)
        "${cmd[@]}"
        times+=($(( ($(date +%s%N) - start) / 1000000 )))
    done
    printf '%s\n' "${times[@]}" | sort -n | awk -v n="$runs" '
        { t[NR] = $1 }
        END { printf "wall time over %d runs: median %d ms, min %d ms, max %d ms\n",
              n, (n % 2) ? t[(n + 1) / 2] : (t[n / 2] + t[n / 2 + 1]) / 2, t[1], t[n] }'
fi

# prism's own account of one run: where the time goes and how much work it was.
"${cmd[@]}" --stats-json "$work/stats.json"
python3 - "$work/stats.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
t, r = s["times_ms"], s["rays"]
total = max(r["total"], 1)
print(f"one run, {s['scene']} {s['options']['width']}x{s['options']['height']}, "
      f"{s['options']['threads'] or 'all'} threads: load {t['load']:.1f} ms, "
      f"build {t['build']:.1f} ms, render {t['render']:.1f} ms")
print(f"  {s['accelerator']}")
print(f"  {r['total']} rays ({r['primary']} primary), {r['per_second'] / 1e6:.2f} Mrays/s, "
      f"{s['primitive_tests'] / total:.2f} primitive tests/ray, "
      f"{s['node_visits'] / total:.2f} node visits/ray")
PY
