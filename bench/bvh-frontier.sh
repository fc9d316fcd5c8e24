#!/usr/bin/env bash
# The BVH builders' build-against-trace chart: `prism bench` with every builder, with and
# without reinsertion, traced with camera, shadow and incoherent rays, on the built-ins
# (the 1M-triangle knot apart: see below), the SPD scenes teapot, gears, lattice and tree and the Stanford bunny when ../shared holds them;
# one thread, process CPU time, the methods timed in turns, 128 px. Writes
# bench/results/bvh-frontier.{txt,csv,svg}.
# Then the million-triangle builds alone on both cores (wall time, builders in turns):
# bench/results/bvh-frontier-1m.txt.
# Usage: bench/bvh-frontier.sh [prism binary]
set -euo pipefail
cd "$(dirname "$0")/.."
prism=${1:-${CARGO_TARGET_DIR:-target}/release/prism}
out=bench/results
mkdir -p "$out"
methods="bvh;bvh:build=sweep;bvh:build=median;bvh:build=lbvh;bvh:build=ploc;bvh:build=sbvh"
methods+=";bvh:build=phr;bvh:reinsert;bvh:build=lbvh,reinsert;bvh:build=ploc,reinsert"
methods+=";bvh:build=sbvh,reinsert;bvh:build=phr,reinsert"
scenes=sphereflake,stadium,slivers,shards,pearls
spd=../shared/scenes/spd
if [[ -d $spd ]]; then scenes+=,$spd/teapot.nff,$spd/gears.nff,$spd/lattice.nff,$spd/tree.nff; fi
if [[ -f ../shared/meshes/stanford-bunny.obj ]]; then
    scenes+=,../shared/meshes/stanford-bunny.obj
fi
"$prism" bench -q --threads 1 --repeat 3 --size 128 --scenes "$scenes" --methods "$methods" \
    --csv "$out/bvh-frontier.csv" \
    --frontier "$out/bvh-frontier.svg" | tee "$out/bvh-frontier.txt"
"$prism" bench --threads 2 --repeat 3 --size 128 --scenes torusknot \
    --methods "bvh;bvh:build=lbvh;bvh:build=ploc;bvh:build=ploc,radius=8;bvh:build=phr" \
    | tee "$out/bvh-frontier-1m.txt"
