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
source bench/embree/prelude.sh
txt=$out/embree.txt
csv=$out/embree.csv
rm -f "$csv"
results_header "prism against Embree 3" | tee "$txt"

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
