#!/usr/bin/env bash
# The live viewer's goals (docs/viewer.md), measured through its real WebSocket by a small
# client (crates/prism-serve/examples/viewer_bench.rs): frames per second at one sample per
# pixel per frame, the time from a camera move to the first frame that shows it (a preview
# when full frames are slow) and to the first full-resolution frame, and what each frame
# encoding would cost. How docs/viewer.md's figures were made.
#
# Usage: bench/serve.sh [SCENE [WIDTHxHEIGHT [SECONDS [KEY=VALUE ...]]]]   (default: whitted
# 640x360 10; settings as the scene file's keys, e.g. wavefront=false)
# PRISM_LOCK names a lock file held while measuring, so that no build that takes the same
# lock shares the cores with the measurement (default /tmp/prism-cargo.lock).
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
scene=${1:-whitted}
size=${2:-640x360}
seconds=${3:-10}
shift $(( $# < 3 ? $# : 3 ))
lock=${PRISM_LOCK:-/tmp/prism-cargo.lock}
cd "$root"

# Built first, so that no build runs while anything is timed.
flock "$lock" cargo build --release --quiet -p prism-serve --example viewer_bench
echo "load average before: $(cut -d' ' -f1-3 /proc/loadavg)"
flock "$lock" target/release/examples/viewer_bench "$scene" "$size" "$seconds" "$@"
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
