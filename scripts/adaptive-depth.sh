#!/usr/bin/env bash
# Measures adaptive depth control and adaptive shadow testing: every scene rendered with
# min_weight 0 (the static depth limit, every light tested) and with the default 1/255,
# then the rays each traced, the branches and shadow rays the threshold left out, and the
# FLIP difference between the two images. Prints a Markdown table (docs/sampling.md).
# Usage: scripts/adaptive-depth.sh [SPD_DIR]   (default ../shared/scenes/spd)
set -euo pipefail
cd "$(dirname "$0")/.."
spd="${1:-../shared/scenes/spd}"
prism="${CARGO_TARGET_DIR:-target}/release/prism"
cargo build --release -q -p prism-cli
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

total() { awk '$1 == "total" { print $2 }' "$1"; }
pruned() { awk '$1 == "pruned" && $2 ~ /^[0-9]+$/ { print $2 }' "$1"; }
pruned_shadow() { awk '$1 == "pruned" && $2 == "shadow" { print $3 }' "$1"; }

echo "| scene | rays, min_weight 0 | rays, 1/255 | saved | pruned branches | pruned shadow rays | mean FLIP | max FLIP |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|"
run() {
    local name="$1"; shift
    "$prism" render "$@" -q --min-weight 0 -o "$work/static.exr" --stats > "$work/static.txt"
    "$prism" render "$@" -q -o "$work/adaptive.exr" --stats > "$work/adaptive.txt"
    local a b
    a=$(total "$work/static.txt"); b=$(total "$work/adaptive.txt")
    "$prism" compare "$work/static.exr" "$work/adaptive.exr" --json > "$work/cmp.json"
    local mean max
    mean=$(sed -n 's/.*"flip_mean": \([0-9.e-]*\).*/\1/p' "$work/cmp.json")
    max=$(sed -n 's/.*"flip_max": \([0-9.e-]*\).*/\1/p' "$work/cmp.json")
    printf "| %s | %d | %d | %.1f%% | %d | %d | %.5f | %.4f |\n" "$name" "$a" "$b" \
        "$(echo "100 * ($a - $b) / $a" | bc -l)" "$(pruned "$work/adaptive.txt")" \
        "$(pruned_shadow "$work/adaptive.txt")" "$mean" "$max"
}
run "whitted 640×480" --builtin whitted
run "cornell 512×512" --builtin cornell -W 512 -H 512
run "sphereflake 512×512" --builtin sphereflake -W 512 -H 512
for f in "$spd"/*.nff; do
    [ -e "$f" ] || continue
    run "$(basename "$f" .nff) (SPD)" "$f"
done
