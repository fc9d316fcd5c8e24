#!/usr/bin/env bash
# prism's BVH builders beside Embree 3's build qualities, on embree-bench's four meshes:
# prism's default (binned SAH) tree and its SBVH, PLOC and PHR trees against Embree
# MEDIUM and HIGH, built in turns (both cores where the builder is parallel) and traced in
# turns (camera and incoherent rays, single rays, 1 thread, process CPU time, medians).
# Writes bench/results/embree-builders.{txt,csv,md}; docs/acceleration.md has the reading.
# Usage: bench/embree/builders.sh [embree-bench run options, e.g. --repeats 3]
# MESHES="bunny blob" limits the meshes, PASSES=N sets the processes per mesh (1),
# BUILDERS the builders (sbvh,ploc,phr); PRISM_LOCK as in run.sh.
set -euo pipefail
cd "$(dirname "$0")/../.."
source bench/embree/prelude.sh
txt=$out/embree-builders.txt
csv=$out/embree-builders.csv
rm -f "$csv"
results_header "prism's builders beside Embree 3" | tee "$txt"
for pass in $(seq "${PASSES:-1}"); do
    echo "# pass $pass" | tee -a "$txt"
    for mesh in ${MESHES:-bunny blob sphereflake soup}; do
        echo "load average before $mesh: $(cut -d' ' -f1-3 /proc/loadavg)" | tee -a "$txt"
        flock "$lock" "$bin" run --mesh "$mesh" --csv "$csv" --threads 1 \
            --rays primary,incoherent --builders "${BUILDERS:-sbvh,ploc,phr}" "$@" | tee -a "$txt"
    done
done
"$bin" report "$csv" >"$out/embree-builders.md"
