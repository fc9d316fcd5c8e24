#!/usr/bin/env python3
"""How close `bvh:build=auto` comes to the best builder's total time (build + trace) on
each scene of a `prism bench` CSV with every builder, at 1 and 64 passes of the bench's
camera and shadow rays. The model's rows repeat crates/prism/src/accel/bvh/build/auto.rs
(build ns per primitive, trace time relative to binned SAH's tree; binned's ns per ray),
for the scenes whose primitives are all triangles and for the others.
Usage: bench/bvh-auto-check.py bench/results/bvh-auto-check.csv"""
import csv
import sys

TRIANGLE_SCENES = {"stadium", "slivers", "shards", "teapot", "gears", "stanford-bunny"}
MODEL = {
    True: ([("bvh:build=lbvh", 290, 1.27), ("bvh", 303, 1.0), ("bvh:reinsert", 380, 1.021)], 192),
    False: ([("bvh:build=lbvh", 226, 0.926), ("bvh", 427, 1.0), ("bvh:reinsert", 743, 0.956)], 118),
}


def pass_ms(r):
    return (int(r["primary_rays"]) / float(r["primary_mrays_per_s"])
            + int(r["shadow_rays"]) / float(r["shadow_mrays_per_s"])) / 1e3


def short(m):
    return "binned" if m == "bvh" else m.replace("bvh:build=", "").replace("bvh:", "binned,")


scenes = {}
for row in csv.DictReader(open(sys.argv[1])):
    scenes.setdefault(row["scene"], {})[row["method"]] = row
print("| scene | passes | auto picks | best | auto / best | binned / best |")
print("|---|---:|---|---|---:|---:|")
for passes in (1, 64):
    for scene, runs in scenes.items():
        binned = runs["bvh"]
        n = int(binned["primitives"])
        rays = passes * (int(binned["primary_rays"]) + int(binned["shadow_rays"]))
        rows, ns_per_ray = MODEL[scene in TRIANGLE_SCENES]
        pick = min(rows, key=lambda c: n * c[1] + rays * ns_per_ray * c[2])[0]
        total = {m: float(r["build_ms"]) + passes * pass_ms(r) for m, r in runs.items()}
        best = min(total, key=total.get)
        print(f"| {scene} | {passes} | {short(pick)} | {short(best)} | "
              f"{total[pick] / total[best]:.2f} | {total['bvh'] / total[best]:.2f} |")
