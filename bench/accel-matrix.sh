#!/usr/bin/env bash
# Renders each scene with each acceleration method (`prism render --stats-json`) and prints
# a markdown table: build ms, memory, node visits and primitive tests per ray, render ms.
# Usage: bench/accel-matrix.sh [prism binary]   (PRISM_SIZE=WxH overrides every scene's size)
set -euo pipefail
cd "$(dirname "$0")/.."
prism=${1:-${CARGO_TARGET_DIR:-target}/release/prism}
spd=../shared/scenes/spd
scenes=(builtin:sphereflake builtin:torusknot builtin:cornell "$spd/gears.nff" "$spd/tree.nff" "$spd/rings.nff")
methods=(bvh grid kdtree octree)
size=()
if [[ -n ${PRISM_SIZE:-} ]]; then size=(-W "${PRISM_SIZE%x*}" -H "${PRISM_SIZE#*x}"); fi
out=$(mktemp -d)
for scene in "${scenes[@]}"; do
    for m in "${methods[@]}"; do
        name=$(basename "$scene" .nff); name=${name#builtin:}
        if [[ $scene == builtin:* ]]; then src=(-b "${scene#builtin:}"); else src=("$scene"); fi
        "$prism" render "${src[@]}" "${size[@]}" --accel "$m" -q -o "$out/img.png" \
            --stats-json "$out/$name.$m.json"
    done
done
python3 - "$out" "${scenes[@]}" <<'PY'
import json, re, sys, os
out, scenes = sys.argv[1], sys.argv[2:]
print("| scene | prims | method | build ms | memory MiB | nodes/ray | tests/ray | render ms | Mrays/s |")
print("|---|---:|---|---:|---:|---:|---:|---:|---:|")
for s in scenes:
    name = os.path.basename(s).removesuffix(".nff").removeprefix("builtin:")
    for m in ["bvh", "grid", "kdtree", "octree"]:
        d = json.load(open(f"{out}/{name}.{m}.json"))
        rays = d["rays"]["total"]
        mib = float(re.search(r"([0-9.]+) MiB", d["accelerator"]).group(1))
        t = d["times_ms"]
        print(f"| {name} | {d['primitives']} | {m} | {t['build']:.0f} | {mib:.1f} | "
              f"{d['node_visits']/rays:.1f} | {d['primitive_tests']/rays:.1f} | "
              f"{t['render']:.0f} | {d['rays']['per_second']/1e6:.2f} |")
PY
