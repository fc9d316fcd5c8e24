#!/usr/bin/env bash
# The adaptive-sampling goal (docs/sampling.md), end to end: on the checkerboard and the default
# scene (whitted), does the adaptive sampler at its default settings reach the RMSE of
# 16-spp jittered sampling with at most 35 % of its rays?
#
# Error: RMSE of linear RGB against a reference. The checkerboard's reference is exact
# (box-filtered area integrals, `prism reference`); whitted's is a jittered render with
# REF_SPP samples per pixel and a different seed (its own noise adds about the same
# amount to both errors compared). Rays: every ray traced (camera, shadow, shadow
# continuations through glass, reflected, refracted), from the renderer's statistics;
# camera rays are printed too. The ratio is adaptive's rays over jittered-16's.
#
# Usage: scripts/adaptive-goal.sh [OUT_DIR]   (env: REF_SPP, default 1024; REFERENCE=FILE
# to reuse a whitted reference; ADAPTIVE="--adaptive-depths 3 ..." to try other settings)
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-adaptive-goal}"
ref_spp="${REF_SPP:-1024}"
prism="${CARGO_TARGET_DIR:-target}/release/prism"
cargo build --release -q -p prism-cli
mkdir -p "$out"

# The adaptive sampler's defaults (threshold 0.1, depth 3, neighbourhood rule, jitter 1,
# texture 25 spp) unless ADAPTIVE says otherwise.
adaptive=(${ADAPTIVE:---adaptive-depths 3 --adaptive-thresholds 0.1})

sweep() {
    local name="$1"; shift
    "$prism" sweep --builtin "$name" -o "$out/$name" --samplers jittered,adaptive --spp 16 \
        "${adaptive[@]}" -q "$@" > /dev/null
}

report() {
    local name="$1" csv="$out/$1/sweep.csv"
    awk -F, -v scene="$name" '
        NR == 1 { next }
        $2 == "jittered" { jr = $11; jc = $10; je = $12 }
        $2 == "adaptive" { n++; ar[n] = $11; ac[n] = $10; ae[n] = $12; al[n] = $3 }
        END {
            printf "%s: jittered 16: RMSE %.5f, %.2f rays/px (%.2f camera)\n", scene, je, jr, jc
            for (i = 1; i <= n; i++) {
                ok = (ae[i] <= je && ar[i] / jr <= 0.35) ? "MET" : "NOT MET"
                printf "%s: %s: RMSE %.5f, %.2f rays/px (%.2f camera) = %.1f %% of the rays (%.1f %% of camera rays): goal %s\n", \
                    scene, al[i], ae[i], ar[i], ac[i], 100 * ar[i] / jr, 100 * ac[i] / jc, ok
            }
        }' "$csv"
}

sweep checkerboard
report checkerboard

reference="${REFERENCE:-$out/whitted-reference-$ref_spp.exr}"
if [ ! -e "$reference" ]; then
    echo "rendering the whitted reference, jittered $ref_spp spp (slow)…" >&2
    "$prism" render --builtin whitted --sampler jittered --spp "$ref_spp" --seed 99991 \
        -q -o "$reference"
fi
sweep whitted --reference "$reference"
report whitted
