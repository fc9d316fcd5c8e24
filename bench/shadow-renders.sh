#!/usr/bin/env bash
# Whole renders with each shadow method, side by side: every SPD scene (with --preset spd,
# when ../shared/scenes/spd exists) and the built-ins cornell and sphereflake, rendered with
# one render thread by each method of METHODS in turns, ROUNDS times (default 3); medians of
# process CPU time (user + system), each method's speed relative to the first, and whether
# every method's image is byte-identical to the first's. How docs/shadows.md's "Whole
# renders" table was made.
#
# Usage: bench/shadow-renders.sh [output file]
# METHODS: the `--shadows` values, separated by spaces (default "any-hit cache light-buffer
# both"). PRISM_LOCK names a lock file that serialises each timed render with other builds
# and benchmarks on a shared machine (default /tmp/prism-cargo.lock).
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
out=${1:-/dev/stdout}
rounds=${ROUNDS:-3}
lock=${PRISM_LOCK:-/tmp/prism-cargo.lock}
read -r -a methods <<<"${METHODS:-any-hit cache light-buffer both}"
cd "$root"

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# Built first, so that no build runs while anything is timed.
flock "$lock" cargo build --release --quiet -p prism-cli
cp "${CARGO_TARGET_DIR:-target}/release/prism" "$work/prism"

# cpu and median.
source "$root/bench/renders-common.sh"

scenes=()
if [[ -d ../shared/scenes/spd ]]; then
    for f in ../shared/scenes/spd/*.nff; do scenes+=("$f"); done
fi
scenes+=(builtin:cornell builtin:sphereflake)

{
    echo "# whole renders by shadow method: $(git rev-parse --short HEAD)$(git diff --quiet HEAD || echo " with uncommitted changes"), 1 render thread, CPU s, median of $rounds in turns; (x) = speed relative to ${methods[0]}"
    printf '%-12s' scene
    for m in "${methods[@]}"; do printf ' %18s' "$m"; done
    printf '  %s\n' images
    for s in "${scenes[@]}"; do
        if [[ $s == builtin:* ]]; then
            name=${s#builtin:}
            args=(render -b "$name" --threads 1)
        else
            name=$(basename "$s" .nff)
            args=(render "$s" --preset spd --threads 1)
        fi
        declare -A times=()
        for _ in $(seq "$rounds"); do
            for k in "${!methods[@]}"; do
                t=$(flock "$lock" bash -c "$(declare -f cpu); work=$work; cpu $work/prism ${args[*]} --shadows ${methods[$k]} -o $work/$k.png")
                times[$k]="${times[$k]:-} $t"
            done
        done
        printf '%-12s' "$name"
        first=""
        same=identical
        for k in "${!methods[@]}"; do
            # shellcheck disable=SC2086
            m=$(median ${times[$k]})
            [[ -z $first ]] && first=$m
            ratio=$(awk -v a="$first" -v b="$m" 'BEGIN { if (b > 0) printf "%.2f", a / b; else print "-" }')
            printf ' %11.2f (%4s)' "$m" "$ratio"
            cmp -s "$work/0.png" "$work/$k.png" || same=DIFFERENT
        done
        printf '  %s\n' "$same"
        unset times
    done
} | tee "$out"
