"""prism from Python, end to end: render a scene, move its camera, change a material,
compare two sampling settings, and render the same image on a local Dask cluster, which
must be identical bit for bit. Run from the repository's root:

    python python/examples/render_and_compare.py [OUTPUT_FOLDER]
"""

import sys
from pathlib import Path

import numpy as np

import prism
import prism.distributed


def main(out):
    out.mkdir(parents=True, exist_ok=True)
    scene = prism.load("scenes/whitted.toml")
    image, stats = scene.render(width=320, height=240, spp=4)
    prism.write(out / "whitted.exr", image)
    print(f"whitted: {stats['total_rays']} rays in {stats['render_seconds']:.2f} s")

    # A camera move and a parameter change, then the picture again.
    camera = scene.camera
    scene.set_camera(fov=camera["fov"] * 0.7)
    glass = [m["name"] for m in scene.materials if m["transmit"] != [0.0, 0.0, 0.0]]
    for name in glass:
        scene.set_material(name, ior=1.1)
    prism.write(out / "whitted-closer.png", scene.render(width=320, height=240, spp=4)[0])
    scene.set_camera(**camera)

    # One sample per pixel against sixteen, measured as `prism compare` does.
    board = prism.builtin("checkerboard")
    reference, _ = board.render(width=320, height=180, spp=64, sampler="jittered")
    for spp in (1, 16):
        test, _ = board.render(width=320, height=180, spp=spp, sampler="jittered")
        c = prism.compare(reference, test)
        print(f"checkerboard at {spp:2} spp: PSNR {c['psnr']:.1f} dB, FLIP {c['flip']:.4f}")

    # The same render, tile by tile, on two local worker processes.
    tiled, dstats = prism.distributed.render(
        "scenes/whitted.toml", width=320, height=240, spp=4, tile_edge=64, workers=2
    )
    same = np.array_equal(tiled.view(np.uint32), image.view(np.uint32))
    print(f"dask: {dstats['tiles']} tiles on {dstats['workers']} workers, identical: {same}")
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main(Path(sys.argv[1] if len(sys.argv) > 1 else "python-example")))
