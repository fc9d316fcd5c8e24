#!/usr/bin/env bash
# Whole renders of this checkout against another git revision, side by side: process CPU
# time (user + system) of each `prism render` with one render thread, the two binaries taken
# in turns ROUNDS times (default 3), medians, and whether the two images are byte-identical.
# Scenes: the SPD files (with --preset spd) when ../shared/scenes/spd exists, and the
# built-ins whitted, cornell, sphereflake and torusknot. How the whole-render
# tables of docs/performance.md and docs/journal/performance.md were made.
#
# Usage: bench/render-vs.sh REVISION [output file]   e.g. bench/render-vs.sh 29d38f2
# PRISM_LOCK names a lock file that serialises each timed render with other builds and
# benchmarks on a shared machine (default /tmp/prism-cargo.lock). PRISM_OLD_BINARY names a
# prism binary already built at REVISION, which then is not built again. SHADOWS, when set,
# is passed to every render as `--shadows` (e.g. SHADOWS=both).
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
rev=${1:?usage: bench/render-vs.sh REVISION [output file]}
out=${2:-/dev/stdout}
rounds=${ROUNDS:-3}
lock=${PRISM_LOCK:-/tmp/prism-cargo.lock}
shadows=()
if [[ -n ${SHADOWS:-} ]]; then
    shadows=(--shadows "$SHADOWS")
fi
cd "$root"

work=$(mktemp -d)
cleanup() {
    git worktree remove --force "$work/old" >/dev/null 2>&1 || true
    rm -rf "$work"
}
trap cleanup EXIT

# Both binaries, built first so that no build runs while anything is timed.
if [[ -n ${PRISM_OLD_BINARY:-} ]]; then
    cp "$PRISM_OLD_BINARY" "$work/prism-old"
else
    git worktree add --detach "$work/old" "$rev" >/dev/null
    (cd "$work/old" && flock "$lock" cargo build --release --quiet -p prism-cli)
    cp "$work/old/target/release/prism" "$work/prism-old"
fi
flock "$lock" cargo build --release --quiet -p prism-cli
cp "${CARGO_TARGET_DIR:-target}/release/prism" "$work/prism-new"

# cpu and median.
source "$root/bench/renders-common.sh"

scenes=()
if [[ -d ../shared/scenes/spd ]]; then
    for f in ../shared/scenes/spd/*.nff; do scenes+=("$f"); done
fi
scenes+=(builtin:whitted builtin:cornell builtin:sphereflake builtin:torusknot)

{
    echo "# whole renders: $(git rev-parse --short HEAD)$(git diff --quiet HEAD || echo " with uncommitted changes") against $rev, 1 render thread, CPU s, median of $rounds in turns${SHADOWS:+, --shadows $SHADOWS}"
    printf '%-14s %8s %8s %7s  %s\n' scene before after speedup image
    for s in "${scenes[@]}"; do
        if [[ $s == builtin:* ]]; then
            name=${s#builtin:}
            args=(render -b "$name" --threads 1 "${shadows[@]}")
        else
            name=$(basename "$s" .nff)
            args=(render "$s" --preset spd --threads 1 "${shadows[@]}")
        fi
        old=() new=()
        for _ in $(seq "$rounds"); do
            old+=("$(flock "$lock" bash -c "$(declare -f cpu); work=$work; cpu $work/prism-old ${args[*]} -o $work/old.png")")
            new+=("$(flock "$lock" bash -c "$(declare -f cpu); work=$work; cpu $work/prism-new ${args[*]} -o $work/new.png")")
        done
        o=$(median "${old[@]}") n=$(median "${new[@]}")
        same=$(cmp -s "$work/old.png" "$work/new.png" && echo identical || echo DIFFERENT)
        speedup=$(awk -v o="$o" -v n="$n" 'BEGIN { if (n > 0) printf "%.2f", o / n; else print "-" }')
        printf '%-14s %8.2f %8.2f %7s  %s\n' "$name" "$o" "$n" "$speedup" "$same"
    done
} | tee "$out"
