#!/usr/bin/env python3
"""Where Mitsuba 3's path-tracing speed on the Cornell box comes from, against prism's.

Two measurements, both on the built-in cornell-light as bench/mitsuba-cornell.py writes it
for Mitsuba (the same published geometry, reflectances, light and camera):

1. Nanoseconds of process CPU time per path at maximum depths 1, 2, 3 and 6 for Mitsuba's
   vectorised `llvm_ad_rgb` variant (a wavefront of paths in SIMD lanes, rays through
   Embree), its `scalar_rgb` variant (one path at a time, one ray at a time through
   Embree, as prism traces) and prism's `--integrator path`. The steps between depths say
   what a path vertex costs (its light sample's shadow ray, its bounce ray, its shading).
   prism's wavefront reports its stages (camera, trace, shade, shadow, leave) in ns per
   path (`--stats-json`), printed beside Mitsuba's whole path and its rays' share (its
   measured ns per ray, part 2, times prism's rays per path).
2. The same 4,194,304 rays (uniform points on the floor, cosine-distributed directions,
   as the bounce rays of a path's first vertex on the floor) through Mitsuba's
   `ray_intersect_preliminary` (llvm) and, from the same file, through Embree 3 and prism
   in `bench/embree` (`embree-bench run --mesh cornell --ray-file`), so the ray queries
   are compared apart from the shading.

Usage (Mitsuba in a venv, as for bench/mitsuba-cornell.py; bench/embree needs Debian's
libembree-dev, which bench/embree/run.sh installs):
    python3 -m venv /tmp/mi && /tmp/mi/bin/pip install mitsuba numpy
    cargo build --release -p prism-cli && (cd bench/embree && cargo build --release)
    /tmp/mi/bin/python bench/mitsuba-anatomy.py [--spp 64] [--threads 2] [--out DIR]
Run it from the repository root.
"""

import argparse
import importlib.util
import json
import os
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
DEPTHS = [1, 2, 3, 6]
RAYS = 1 << 22


def load_cornell_script():
    """bench/mitsuba-cornell.py as a module: its Mitsuba scene and its CPU clocks."""
    spec = importlib.util.spec_from_file_location(
        "mitsuba_cornell", os.path.join(HERE, "mitsuba-cornell.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def mitsuba_per_path(mi, dr, mc, variant, size, spp, out):
    """ns of CPU per path at each depth (after a warm-up render that compiles kernels)."""
    mi.set_variant(variant)
    result = {}
    for depth in DEPTHS:
        scene = mi.load_dict(mc.mitsuba_scene(mi, "cornell-light", out, size, spp, depth))
        dr.eval(mi.render(scene, spp=1))
        dr.sync_thread()
        c0 = mc.cpu_seconds()
        image = mi.render(scene, spp=spp)
        dr.eval(image)
        dr.sync_thread()
        result[depth] = (mc.cpu_seconds() - c0) / (size * size * spp) * 1e9
    return result


def prism_per_path(mc, prism, size, spp, threads, out, stages):
    """ns of CPU per path at each depth; `stages[depth]` gets the wavefront's stages (ns
    per path, from `--stats-json`) and the rays per path."""
    n = int(round(spp ** 0.5))
    result = {}
    for depth in DEPTHS:
        stats = os.path.join(out, f"prism-depth{depth}.json")
        c0 = mc.child_cpu_seconds()
        subprocess.run([prism, "render", "--builtin", "cornell-light", "--integrator", "path",
                        "-W", str(size), "-H", str(size), "--depth", str(depth),
                        "--samples", str(n), "--sampler", "jittered",
                        "--threads", str(threads), "-q", "--stats-json", stats,
                        "-o", os.path.join(out, f"prism-depth{depth}.exr")], check=True)
        result[depth] = (mc.child_cpu_seconds() - c0) / (size * size * n * n) * 1e9
        with open(stats) as f:
            report = json.load(f)
        paths = report["rays"]["primary"]
        stages[depth] = dict(report.get("wavefront_stage_ns_per_path") or {})
        stages[depth]["rays"] = report["rays"]["total"] / paths
        stages[depth]["shadow rays"] = report["rays"]["shadow"] / paths
    return result


def print_stages(stages, per_path, mitsuba_ns_per_ray):
    """prism's wavefront stages in ns per path at each depth, beside what Mitsuba's
    vectorised variant spends in all: its whole path, and its rays' share at its measured
    cost per ray (the floor rays below) times prism's rays per path."""
    names = ["camera", "trace", "shade", "shadow", "leave"]
    print("\n# prism's wavefront stages (ns of the render threads' CPU time per path) beside "
          "Mitsuba llvm_ad_rgb")
    print("| depth | " + " | ".join(names) + " | rays per path | Mitsuba llvm: whole path | "
          "Mitsuba llvm: its rays at its ns per ray |")
    print("|---:|" + "---:|" * (len(names) + 3))
    for depth in DEPTHS:
        st = stages[depth]
        cells = [f"{st.get(k, float('nan')):.0f}" for k in names]
        rays = st["rays"]
        print(f"| {depth} | " + " | ".join(cells) + f" | {rays:.2f} | "
              f"{per_path[depth]:.0f} | {rays * mitsuba_ns_per_ray:.0f} |")


def floor_rays():
    """Origins uniform on the floor (5 mm in from its edges, 0.01 mm above it), directions
    cosine-distributed about +y; a fixed seed."""
    rng = np.random.default_rng(1)
    u1, u2 = rng.random(RAYS), rng.random(RAYS)
    r, phi = np.sqrt(u1), 2 * np.pi * u2
    d = np.stack([r * np.cos(phi), np.sqrt(1 - u1), r * np.sin(phi)], 1).astype(np.float32)
    o = np.stack([rng.random(RAYS) * 540 + 5, np.full(RAYS, 0.01),
                  rng.random(RAYS) * 540 + 5], 1).astype(np.float32)
    return o, d


def mitsuba_rays(mi, dr, mc, o, d, out, rounds=5):
    """ns of CPU per ray of `ray_intersect_preliminary` (llvm), median of `rounds`, and
    the hits."""
    mi.set_variant("llvm_ad_rgb")
    scene = mi.load_dict(mc.mitsuba_scene(mi, "cornell-light", out, 64, 1, 6))
    times, hits = [], 0
    for _ in range(rounds + 1):
        ray = mi.Ray3f(mi.Point3f(o[:, 0], o[:, 1], o[:, 2]),
                       mi.Vector3f(d[:, 0], d[:, 1], d[:, 2]))
        dr.eval(ray)
        dr.sync_thread()
        c0 = mc.cpu_seconds()
        found = scene.ray_intersect_preliminary(ray)
        dr.eval(found.t)
        dr.sync_thread()
        times.append((mc.cpu_seconds() - c0) / RAYS * 1e9)
        hits = int(np.isfinite(np.array(found.t)).sum())
    return float(np.median(times[1:])), hits  # the first compiles the kernel


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--spp", type=int, default=64, help="paths per pixel (a square for prism)")
    ap.add_argument("--size", type=int, default=512)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--out", default="/tmp/prism-mitsuba-anatomy")
    ap.add_argument("--prism", default="target/release/prism")
    ap.add_argument("--embree-bench", default="bench/embree/target/release/embree-bench")
    args = ap.parse_args()
    if int(round(args.spp ** 0.5)) ** 2 != args.spp:
        sys.exit("--spp must be a square: prism takes n×n samples per pixel")
    for path in (args.prism, args.embree_bench):
        if not os.path.exists(path):
            sys.exit(f"{path} is missing: build it first (see the usage above)")

    mc = load_cornell_script()
    mc.use_libllvm19()
    import mitsuba as mi
    import drjit as dr

    dr.set_thread_count(args.threads)
    os.makedirs(args.out, exist_ok=True)
    print(f"# cornell-light, {args.size}², {args.spp} paths per pixel, {args.threads} threads, "
          f"Mitsuba {mi.__version__}; ns of process CPU time per path")
    stages = {}
    rows = {
        "Mitsuba llvm_ad_rgb": mitsuba_per_path(mi, dr, mc, "llvm_ad_rgb", args.size,
                                                args.spp, args.out),
        "Mitsuba scalar_rgb": mitsuba_per_path(mi, dr, mc, "scalar_rgb", args.size,
                                               args.spp, args.out),
        "prism": prism_per_path(mc, args.prism, args.size, args.spp, args.threads, args.out,
                                stages),
    }
    print("| renderer | " + " | ".join(f"depth {d}" for d in DEPTHS) + " |")
    print("|---|" + "---:|" * len(DEPTHS))
    for name, per_depth in rows.items():
        print(f"| {name} | " + " | ".join(f"{per_depth[d]:.0f}" for d in DEPTHS) + " |")

    o, d = floor_rays()
    ns, hits = mitsuba_rays(mi, dr, mc, o, d, args.out)
    print_stages(stages, rows["Mitsuba llvm_ad_rgb"], ns)
    ray_file = os.path.join(args.out, "floor-rays.bin")
    np.concatenate([o, d], 1).astype("<f4").tofile(ray_file)
    print(f"\n# {RAYS} rays from the floor: Mitsuba llvm ray_intersect_preliminary "
          f"{ns:.1f} ns of CPU per ray ({args.threads} threads), {hits} hits; "
          f"Embree 3 and prism on the same rays (embree-bench, Mrays/s of CPU time):")
    sys.stdout.flush()
    subprocess.run([args.embree_bench, "run", "--mesh", "cornell", "--ray-file", ray_file,
                    "--repeats", "5", "--builds", "1", "--threads", "1"], check=True)


if __name__ == "__main__":
    main()
