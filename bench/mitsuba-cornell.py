#!/usr/bin/env python3
"""prism's path tracer against Mitsuba 3's on the same Cornell box.

Writes the built-ins cornell-light and cornell-light-glass as a Mitsuba scene (the same
published geometry, RGB reflectances, light and camera as
crates/prism/src/scene/builtin/cornell_light.rs), renders both with both renderers at the
same size, paths per pixel and maximum depth, and reports

- paths per CPU-second of each (process CPU time, user + system, all threads; Mitsuba's
  JIT compilation is kept out by a warm-up render first),
- the mean of each image and the difference of the means in standard errors (the pixel
  differences' spread measures the noise),
- `prism compare` of prism's image against Mitsuba's (RMSE, PSNR, SSIM, FLIP).

Usage (Mitsuba in a venv; its llvm variants need Debian's libllvm19, which the script
installs with apt-get when it is missing and points Dr.Jit at; an older libLLVM, which
Dr.Jit would otherwise pick up, fails in its code generator):
    python3 -m venv /tmp/mi && /tmp/mi/bin/pip install mitsuba numpy
    /tmp/mi/bin/python bench/mitsuba-cornell.py [--spp 256] [--threads 2]
        [--variant llvm_ad_rgb] [--size 512] [--depth 6] [--out DIR]
        [--prism-args '--wavefront false']
Run it from the repository root after `cargo build --release -p prism-cli`.

    /tmp/mi/bin/python bench/mitsuba-cornell.py --write-reference crates/prism/tests/data \
        --size 64 --spp 16384
writes Mitsuba's images alone (NAME-mitsuba.exr), the references that
crates/prism/tests/path_tracing.rs holds prism's path tracer to.
"""

import argparse
import os
import resource
import subprocess
import sys
import time

import numpy as np

WHITE = [0.73, 0.73, 0.73]
RED = [0.63, 0.065, 0.05]
GREEN = [0.14, 0.45, 0.09]
LIGHT_RADIANCE = [17.0, 12.0, 4.0]
LIGHT_REFLECTANCE = [0.78, 0.78, 0.78]

FLOOR = [[552.8, 0, 0], [0, 0, 0], [0, 0, 559.2], [549.6, 0, 559.2]]
CEILING = [[556, 548.8, 0], [556, 548.8, 559.2], [0, 548.8, 559.2], [0, 548.8, 0]]
BACK = [[549.6, 0, 559.2], [0, 0, 559.2], [0, 548.8, 559.2], [556, 548.8, 559.2]]
RIGHT_GREEN = [[0, 0, 559.2], [0, 0, 0], [0, 548.8, 0], [0, 548.8, 559.2]]
LEFT_RED = [[552.8, 0, 0], [549.6, 0, 559.2], [556, 548.8, 559.2], [556, 548.8, 0]]
LIGHT = [[343, 548.7, 227], [343, 548.7, 332], [213, 548.7, 332], [213, 548.7, 227]]
SHORT_BLOCK = [
    [[130, 165, 65], [82, 165, 225], [240, 165, 272], [290, 165, 114]],
    [[290, 0, 114], [290, 165, 114], [240, 165, 272], [240, 0, 272]],
    [[130, 0, 65], [130, 165, 65], [290, 165, 114], [290, 0, 114]],
    [[82, 0, 225], [82, 165, 225], [130, 165, 65], [130, 0, 65]],
    [[240, 0, 272], [240, 165, 272], [82, 165, 225], [82, 0, 225]],
]
TALL_BLOCK = [
    [[423, 330, 247], [265, 330, 296], [314, 330, 456], [472, 330, 406]],
    [[423, 0, 247], [423, 330, 247], [472, 330, 406], [472, 0, 406]],
    [[472, 0, 406], [472, 330, 406], [314, 330, 456], [314, 0, 456]],
    [[314, 0, 456], [314, 330, 456], [265, 330, 296], [265, 0, 296]],
    [[265, 0, 296], [265, 330, 296], [423, 330, 247], [423, 0, 247]],
]


def write_obj(path, quads):
    """Quads as OBJ triangles (a b c, a c d), counter-clockwise as in the data."""
    with open(path, "w") as f:
        for q in quads:
            for p in q:
                f.write("v %g %g %g\n" % tuple(p))
        for i in range(len(quads)):
            a = 4 * i + 1
            f.write("f %d %d %d\nf %d %d %d\n" % (a, a + 1, a + 2, a, a + 2, a + 3))


def diffuse(rgb):
    return {"type": "diffuse", "reflectance": {"type": "rgb", "value": rgb}}


def mitsuba_scene(mi, variant_name, work, size, spp, depth):
    def obj(name, quads, bsdf, **extra):
        path = os.path.join(work, name + ".obj")
        write_obj(path, quads)
        d = {"type": "obj", "filename": path, "face_normals": True, "bsdf": bsdf}
        d.update(extra)
        return d

    scene = {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": depth, "rr_depth": 3},
        "sensor": {
            "type": "perspective",
            "fov": 2.0 * np.degrees(np.arctan(12.5 / 35.0)),
            "fov_axis": "x",
            "to_world": mi.ScalarTransform4f().look_at(
                origin=[278, 273, -800], target=[278, 273, 0], up=[0, 1, 0]
            ),
            "sampler": {"type": "independent", "sample_count": spp},
            "film": {
                "type": "hdrfilm",
                "width": size,
                "height": size,
                "rfilter": {"type": "box"},
                "pixel_format": "rgb",
            },
        },
        "white": obj("white", [FLOOR, CEILING, BACK], diffuse(WHITE)),
        "green": obj("green", [RIGHT_GREEN], diffuse(GREEN)),
        "red": obj("red", [LEFT_RED], diffuse(RED)),
        "light": obj(
            "light",
            [LIGHT],
            diffuse(LIGHT_REFLECTANCE),
            emitter={"type": "area", "radiance": {"type": "rgb", "value": LIGHT_RADIANCE}},
        ),
    }
    if variant_name == "cornell-light":
        scene["blocks"] = obj("blocks", SHORT_BLOCK + TALL_BLOCK, diffuse(WHITE))
    else:
        scene["mirror"] = {
            "type": "sphere",
            "center": [368, 100, 351],
            "radius": 100,
            "bsdf": {"type": "conductor", "material": "none"},
        }
        scene["glass"] = {
            "type": "sphere",
            "center": [186, 90, 169],
            "radius": 90,
            "bsdf": {"type": "dielectric", "int_ior": 1.5, "ext_ior": 1.0},
        }
    return scene


def cpu_seconds():
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


def child_cpu_seconds():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def read_exr(mi, path):
    return np.array(mi.Bitmap(path).convert(mi.Bitmap.PixelFormat.RGB,
                                            mi.Struct.Type.Float32, False))


LIBLLVM19 = "/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1"


def use_libllvm19():
    """Points Dr.Jit at Debian's libLLVM 19 (installing libllvm19 when it is missing),
    unless DRJIT_LIBLLVM_PATH already names a library."""
    if os.environ.get("DRJIT_LIBLLVM_PATH"):
        return
    if not os.path.exists(LIBLLVM19):
        sudo = [] if os.geteuid() == 0 else ["sudo", "-n"]
        install = sudo + ["apt-get", "install", "-y", "-qq", "libllvm19"]
        if subprocess.run(install, stdout=subprocess.DEVNULL).returncode != 0:
            subprocess.run(sudo + ["apt-get", "update", "-qq"], check=True)
            subprocess.run(install, stdout=subprocess.DEVNULL, check=True)
    os.environ["DRJIT_LIBLLVM_PATH"] = LIBLLVM19


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--spp", type=int, default=256, help="paths per pixel (a square for prism)")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--variant", default="llvm_ad_rgb")
    ap.add_argument("--size", type=int, default=512)
    ap.add_argument("--depth", type=int, default=6)
    ap.add_argument("--out", default="/tmp/prism-mitsuba")
    ap.add_argument("--prism", default="target/release/prism")
    ap.add_argument("--prism-args", default="",
                    help="more arguments for prism render, e.g. '--wavefront false'")
    ap.add_argument("--scenes", default="cornell-light,cornell-light-glass")
    ap.add_argument("--write-reference", metavar="DIR",
                    help="only render Mitsuba's images into DIR")
    args = ap.parse_args()
    n = int(round(args.spp ** 0.5))
    if n * n != args.spp:
        sys.exit("--spp must be a square: prism takes n×n samples per pixel")

    if args.variant.startswith("llvm"):
        use_libllvm19()
    import mitsuba as mi
    import drjit as dr

    mi.set_variant(args.variant)
    dr.set_thread_count(args.threads)
    os.makedirs(args.out, exist_ok=True)
    if args.write_reference:
        for name in args.scenes.split(","):
            scene = mi.load_dict(mitsuba_scene(mi, name, args.out, args.size, args.spp,
                                               args.depth))
            path = os.path.join(args.write_reference, f"{name}-mitsuba.exr")
            mi.Bitmap(mi.render(scene, spp=args.spp)).write(path)
            print("wrote", path)
        return
    paths = args.size * args.size * args.spp
    print(f"# {args.size}², {args.spp} paths per pixel, max depth {args.depth}, "
          f"{args.threads} threads; Mitsuba {mi.__version__} {args.variant}")
    print("| scene | renderer | CPU s | wall s | M paths per CPU-second | image mean |")
    print("|---|---|---|---|---|---|")
    reports = []
    for name in args.scenes.split(","):
        # prism
        prism_exr = os.path.join(args.out, f"{name}-prism.exr")
        c0, w0 = child_cpu_seconds(), time.time()
        subprocess.run([args.prism, "render", "--builtin", name, "--integrator", "path",
                        "-W", str(args.size), "-H", str(args.size), "--depth", str(args.depth),
                        "--samples", str(n), "--sampler", "jittered",
                        "--threads", str(args.threads), "-q",
                        "-o", prism_exr] + args.prism_args.split(), check=True)
        prism_cpu, prism_wall = child_cpu_seconds() - c0, time.time() - w0

        # Mitsuba: a one-path-per-pixel warm-up compiles the kernels first.
        scene = mi.load_dict(mitsuba_scene(mi, name, args.out, args.size, args.spp, args.depth))
        dr.eval(mi.render(scene, spp=1))
        dr.sync_thread()
        c0, w0 = cpu_seconds(), time.time()
        image = mi.render(scene, spp=args.spp)
        dr.eval(image)
        dr.sync_thread()
        mi_cpu, mi_wall = cpu_seconds() - c0, time.time() - w0
        mi_exr = os.path.join(args.out, f"{name}-mitsuba.exr")
        mi.Bitmap(image).write(mi_exr)

        a = read_exr(mi, prism_exr)
        b = read_exr(mi, mi_exr)
        for label, img, cpu, wall in [("prism", a, prism_cpu, prism_wall),
                                      ("Mitsuba", b, mi_cpu, mi_wall)]:
            print(f"| {name} | {label} | {cpu:.2f} | {wall:.2f} | "
                  f"{paths / cpu / 1e6:.2f} | {img.mean():.5f} |")
        # The light itself fills about 1 % of the picture at radiance 17 and dominates the
        # mean; its outline is where the two cameras' rounding differs most. The
        # comparison of light transport keeps the pixels both see below radiance 1.
        lit = ((a.max(axis=2) < 1.0) & (b.max(axis=2) < 1.0)).ravel()
        d = (a - b).mean(axis=2).ravel()[lit]
        z = d.mean() / (d.std(ddof=1) / np.sqrt(d.size))
        ma = a.mean(axis=2).ravel()[lit].mean()
        mb = b.mean(axis=2).ravel()[lit].mean()
        compare = subprocess.run([args.prism, "compare", prism_exr, mi_exr],
                                 capture_output=True, text=True)
        reports.append((name, ma, mb, z, compare.stdout.strip() or compare.stderr.strip()))
    print()
    for name, ma, mb, z, compare in reports:
        print(f"{name}: mean of the pixels below 1: prism {ma:.5f}, Mitsuba {mb:.5f}, "
              f"difference {100 * (ma - mb) / mb:+.2f} % = {z:+.2f} standard errors")
        print("  prism compare prism.exr mitsuba.exr: " + " ".join(compare.split()))


if __name__ == "__main__":
    main()
