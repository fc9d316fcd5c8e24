#!/usr/bin/env bash
# prism against Embree 3, side by side in one process per mesh. Installs Debian's
# libembree-dev when it is missing (as root), builds bench/embree, runs the four
# meshes, and writes bench/results/embree.{txt,csv,md} and the tables in
# docs/performance.md (between the embree-bench markers).
# Usage: bench/embree/run.sh [embree-bench run options, e.g. --repeats 3]
# MESHES="bunny blob" limits the meshes, PASSES=N sets the processes per mesh (3); PRISM_LOCK names the lock that serialises builds
# and benchmarks on a shared machine (each mesh takes it for its own run only).
set -euo pipefail
cd "$(dirname "$0")/../.."
lock=${PRISM_LOCK:-/tmp/prism-cargo.lock}

if [[ ! -e /usr/include/embree3/rtcore.h ]]; then
    if [[ $(id -u) == 0 ]]; then
        apt-get update && apt-get install -y libembree-dev
    else
        echo "run.sh: Embree 3 is missing; install it with: apt-get install libembree-dev" >&2
        exit 1
    fi
fi

(cd bench/embree && flock "$lock" cargo build --release --quiet)
bin=bench/embree/target/release/embree-bench
out=bench/results
mkdir -p "$out"
txt=$out/embree.txt
csv=$out/embree.csv
rm -f "$csv"

{
    echo "# prism against Embree 3 ($(date -u '+%Y-%m-%d %H:%M UTC'), prism $(git rev-parse --short HEAD))"
    echo "machine: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) logical CPUs, shared with other work (noisy)"
    echo "Embree $(dpkg-query -W -f '${Version}' libembree3-3 2>/dev/null || echo '?'), $(rustc --version)"
    echo "CPU: avx2 $(grep -qw avx2 /proc/cpuinfo && echo yes || echo no), avx512f $(grep -qw avx512f /proc/cpuinfo && echo yes || echo no)"
    echo
} | tee "$txt"

# Each mesh runs in PASSES separate processes (one pass over all meshes after another):
# prism's throughput moves by up to 30 % from one process to the next (Embree's by ~5 %),
# so the tables give the median over processes and the spread.
for pass in $(seq "${PASSES:-3}"); do
    echo "# pass $pass" | tee -a "$txt"
    for mesh in ${MESHES:-bunny blob sphereflake soup}; do
        flock "$lock" "$bin" run --mesh "$mesh" --csv "$csv" "$@" | tee -a "$txt"
    done
done

"$bin" report "$csv" >"$out/embree.md"

# Replace what lies between the markers in docs/performance.md with the new tables.
doc=docs/performance.md
begin='<!-- embree-bench:begin (bench/embree/run.sh writes this part) -->'
end='<!-- embree-bench:end -->'
if grep -qF "$begin" "$doc"; then
    {
        sed "/^${begin//\//\\/}\$/q" "$doc"
        head -4 "$txt" | sed 's/^# //; s/$/  /'
        echo
        cat "$out/embree.md"
        sed -n "/^${end//\//\\/}\$/,\$p" "$doc"
    } >"$doc.new"
    mv "$doc.new" "$doc"
else
    echo "run.sh: $doc has no embree-bench markers; tables are in $out/embree.md" >&2
fi
