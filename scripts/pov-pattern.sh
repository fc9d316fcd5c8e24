#!/usr/bin/env bash
# The adaptive sampler's defaults against POV-Ray's +AM2 pattern (`--preset pov`:
# corners rule, no jitter, no stratified pass) at equal error. Each is swept over
# thresholds 0.05-0.3 and depths 1-3; scripts/equal-error.py then reads each family's
# error-against-rays front and says how many rays the other family needs to reach each
# point's RMSE and FLIP (log-log interpolation along the front).
#
# Scenes: the checkerboard (exact reference), whitted at 320×240 and, when ../shared
# holds them, SPD gears and balls at 256×256 (references: 256-spp jittered renders).
#
# Usage: scripts/pov-pattern.sh [OUT_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-pov-pattern}"
prism="${CARGO_TARGET_DIR:-target}/release/prism"
cargo build --release -q -p prism-cli
mkdir -p "$out"
common=(--samplers adaptive --adaptive-depths 1,2,3 --adaptive-thresholds 0.05,0.1,0.2,0.3
        --adaptive-variants neighbourhood:1:25,corners:0:0 -q)
"$prism" sweep --builtin checkerboard -W 320 -H 180 -o "$out/checker" "${common[@]}"
"$prism" sweep --builtin whitted -W 320 -H 240 --reference-spp 256 -o "$out/whitted" "${common[@]}"
scenes=(checker whitted)
for s in gears balls; do
    f="../shared/scenes/spd/$s.nff"
    if [ -f "$f" ]; then
        "$prism" sweep "$f" -W 256 -H 256 --reference-spp 256 -o "$out/$s" "${common[@]}"
        scenes+=("$s")
    else
        echo "skipping $s: $f not found"
    fi
done
for s in "${scenes[@]}"; do
    python3 scripts/equal-error.py "$out/$s/sweep.csv"
done
