"""Rendering across the workers of a Dask cluster (`dask.distributed`).

    import prism.distributed
    image, stats = prism.distributed.render("scenes/whitted.toml", width=1920, height=1080,
                                            spp=16, tile_edge=128)

The image is cut into square tiles `tile_edge` pixels on a side (tile_edge=128: tiles of
128 × 128 pixels); each tile is a Dask task that renders
that region with `Scene.render(region=...)`, and the client assembles them. prism renders
every pixel as a pure function of scene, settings and position, so the result is
bit-identical to one local render whatever the tile size and however many workers took
part, and a tile rendered twice (after a worker died) gives the same pixels.

The scene travels as a `SceneBundle` (its file and every file it reads), which a worker
plugin hands to each worker once, and to any worker that joins later; or as a path every
worker can open (`shared=True`). A tile that fails for a
reason in the scene or the settings comes back as a value, not an exception, so Dask does
not retry it: the render stops and raises that error once. A worker that dies costs only
its tiles in flight, which the scheduler gives to another worker.

From a shell: `python -m prism.distributed SCENE --scheduler tcp://HOST:8786 -o OUT.exr`
(without --scheduler, a local cluster of --workers processes), with a progress bar over
the tiles.
"""

import argparse
import collections
import os
import sys
import threading
import time
import warnings

import numpy as np
from distributed.diagnostics.plugin import WorkerPlugin

from . import ImageError, PrismError, RenderError, SceneError, write
from .bundle import SceneBundle
from .progress import TileBar

__all__ = ["render", "tile_grid", "SceneBundle", "main"]

#: The edge in pixels of the square tiles, one Dask task each, unless told otherwise.
TILE_EDGE = 64

#: Tiles this process has started rendering, as a worker (the fault tests count them).
attempts = 0

_ERRORS = {
    "SceneError": SceneError,
    "RenderError": RenderError,
    "ImageError": ImageError,
    "PrismError": PrismError,
    "ValueError": ValueError,
}


def tile_grid(width, height, size):
    """The regions (x0, y0, x1, y1) of `size`-pixel square tiles covering the image,
    row by row."""
    if size < 1:
        raise ValueError(f"tile_edge must be at least 1 pixel, got {size}")
    return [
        (x0, y0, min(x0 + size, width), min(y0 + size, height))
        for y0 in range(0, height, size)
        for x0 in range(0, width, size)
    ]


# --- on the workers ---------------------------------------------------------------------

_scenes = collections.OrderedDict()
_scenes_lock = threading.Lock()
#: Scenes (with their accelerators) a worker process keeps: the frames of an animation
#: and a few renders at once.
_SCENES_KEPT = 4


def _scene(bundle, camera, materials):
    """The bundle's scene with the overrides applied, loaded once per worker process and
    kept, with its accelerator, for the next tiles."""
    key = (bundle.digest, repr(camera), repr(materials))
    with _scenes_lock:
        if key in _scenes:
            _scenes.move_to_end(key)
            return _scenes[key]
        scene = bundle.load()
        if camera:
            scene.set_camera(**camera)
        for name, change in (materials or {}).items():
            scene.set_material(name, **change)
        _scenes[key] = scene
        while len(_scenes) > _SCENES_KEPT:
            _scenes.popitem(last=False)
        return scene


def _threads_per_task():
    """prism's threads for one tile: this machine's cores shared among the tasks its
    worker runs at once (a worker of one thread on an 8-core machine renders with 8)."""
    try:
        cores = len(os.sched_getaffinity(0))
    except AttributeError:
        cores = os.cpu_count() or 1
    try:
        from distributed import get_worker

        slots = get_worker().state.nthreads
    except (ImportError, ValueError, AttributeError):
        slots = 1
    return max(1, cores // max(1, slots))


def _render_tile(digest, settings, camera, materials, frame, region):
    """One task: renders `region` of the scene of the bundle `digest`; returns ("ok",
    frame, region, pixels, stats) or, for an error of the scene or the settings, ("error",
    frame, region, kind, message)."""
    global attempts
    attempts += 1
    bundle = _installed.get(digest)
    if bundle is None:
        return ("error", frame, region, "PrismError", "the scene did not reach this worker")
    try:
        scene = _scene(bundle, camera, materials)
        options = dict(settings)
        if options.get("threads") is None:
            options["threads"] = _threads_per_task()
        image, stats = scene.render(region=region, **options)
        return ("ok", frame, region, np.array(image), stats)
    except (PrismError, ValueError) as e:
        # Deterministic: another attempt would fail the same way, so it is an answer.
        return ("error", frame, region, type(e).__name__, str(e))


# --- on the client ----------------------------------------------------------------------


class _BundlePlugin(WorkerPlugin):
    """Hands a `SceneBundle` to every worker of a cluster: those running now and those
    that join later (a worker the nanny restarts after a crash among them), once each."""

    def __init__(self, bundle):
        self.bundle = bundle
        self.name = f"prism-scene-{bundle.digest}"

    def setup(self, worker):
        _installed[self.bundle.digest] = self.bundle


#: The bundles this worker process received, by digest.
_installed = {}

#: (id of a client, digest) of the bundles already given to a client's cluster, which keeps
#: its plugins while it runs: the next render of the same scene ships nothing.
_registered = {}
_registered_lock = threading.Lock()


def _ship(client, bundle):
    """Gives `bundle` to every worker of `client`'s cluster, unless it has it already."""
    with _registered_lock:
        for key in [k for k, c in _registered.items() if c.status in ("closed", "closing")]:
            del _registered[key]
        key = (id(client), bundle.digest)
        if key not in _registered:
            client.register_plugin(_BundlePlugin(bundle))
            _registered[key] = client


def _add_counters(total, counters):
    for k, v in counters.items():
        if isinstance(v, list):
            total[k] = [a + b for a, b in zip(total.get(k, [0] * len(v)), v)]
        else:
            total[k] = total.get(k, 0) + v


def render(
    scene,
    client=None,
    *,
    tile_edge=None,
    tiles=None,
    frames=None,
    materials=None,
    shared=False,
    workers=2,
    progress=None,
    **settings,
):
    """Renders `scene` (a file, "builtin:NAME" or a `SceneBundle`) on Dask; returns (image, stats), or
    with `frames` (a list of camera overrides, dicts as `Scene.set_camera` takes) a list of
    images, one per frame, and the stats.

    client: a `distributed.Client`; None starts a `LocalCluster` of `workers` processes
    of one thread each, closed at the end. tile_edge: the edge of a tile in pixels
    (default 64: tiles of 64 × 64 pixels, however many that makes); tiles= is its deprecated
    old name, the same edge, not a count of tiles. materials:
    {name: {coefficient: value}} overrides, as `Scene.set_material` takes them. shared:
    the workers open the scene at its path (a shared file system) instead of receiving
    its files. progress: called as progress(done, total) after each tile. Every other
    keyword is a `Scene.render` setting (width, height, spp, sampler, accel, seed, ...);
    threads defaults to the worker machine's cores divided among its worker's threads.

    stats: the engine's counters summed over the tiles ("counters", "total_rays"),
    "tiles", "frames", "workers", "wall_seconds", "tile_seconds" (each tile's render
    time on its worker), "shipped_bytes".
    """
    from distributed import Client, LocalCluster, as_completed

    if tiles is not None:
        if tile_edge is not None:
            raise ValueError("tiles= and tile_edge= name the same edge: give tile_edge= only")
        warnings.warn(
            "tiles= is deprecated: use tile_edge=, the same edge of a tile in pixels",
            DeprecationWarning,
            stacklevel=2,
        )
        tile_edge = tiles
    if tile_edge is None:
        tile_edge = TILE_EDGE
    for reserved in ("region",):
        if reserved in settings:
            raise ValueError(f"{reserved}= is chosen per tile by prism.distributed")
    bundle = scene if isinstance(scene, SceneBundle) else SceneBundle.of(scene, shared=shared)
    width = settings.get("width") or bundle.size[0]
    height = settings.get("height") or bundle.size[1]
    settings = dict(settings, width=width, height=height)
    regions = tile_grid(width, height, int(tile_edge))
    cameras = [None] if frames is None else list(frames)

    own = None
    if client is None:
        cluster = LocalCluster(
            n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=":0"
        )
        own = Client(cluster)
        client = own
    start = time.perf_counter()
    try:
        _ship(client, bundle)
        futures = [
            client.submit(
                _render_tile,
                bundle.digest,
                settings,
                camera,
                materials,
                frame,
                region,
                pure=False,
                retries=0,
            )
            for frame, camera in enumerate(cameras)
            for region in regions
        ]
        images = [np.empty((height, width, 3), dtype=np.float32) for _ in cameras]
        counters = {}
        total_rays = 0
        tile_seconds = []
        done = 0
        for future in as_completed(futures):
            answer = future.result()
            if answer[0] == "error":
                _, frame, region, kind, message = answer
                client.cancel(futures)
                raise _ERRORS.get(kind, PrismError)(message)
            _, frame, (x0, y0, x1, y1), pixels, stats = answer
            images[frame][y0:y1, x0:x1] = pixels
            _add_counters(counters, stats["counters"])
            total_rays += stats["total_rays"]
            tile_seconds.append(stats["render_seconds"])
            done += 1
            if progress is not None:
                progress(done, len(futures))
        stats = {
            "counters": counters,
            "total_rays": total_rays,
            "tiles": len(futures),
            "frames": len(cameras),
            "workers": len(client.scheduler_info().get("workers", {})),
            "wall_seconds": time.perf_counter() - start,
            "tile_seconds": tile_seconds,
            "shipped_bytes": bundle.bytes,
        }
        return (images if frames is not None else images[0]), stats
    finally:
        if own is not None:
            cluster = own.cluster
            own.close()
            cluster.close()


# --- the command line -------------------------------------------------------------------


def _arguments():
    p = argparse.ArgumentParser(
        prog="python -m prism.distributed",
        description="Render a prism scene on a Dask cluster, tile by tile; the image is "
        "bit-identical to a local render.",
    )
    p.add_argument("scene", help="scene file (.toml, .nff, .gltf, .glb, .obj, .ply) or builtin:NAME")
    p.add_argument("-o", "--output", default="prism.exr", help="image file: .exr, .pfm or .png")
    p.add_argument("--scheduler", help="address of a running scheduler, e.g. tcp://HOST:8786")
    p.add_argument("--workers", type=int, default=2, help="local worker processes without --scheduler")
    p.add_argument(
        "--tile-edge",
        type=int,
        help=f"edge of a tile in pixels (default {TILE_EDGE}: {TILE_EDGE} × {TILE_EDGE}-pixel tiles)",
    )
    # The old name of --tile-edge, which read as a count of tiles.
    p.add_argument("--tiles", type=int, help=argparse.SUPPRESS)
    p.add_argument("--shared", action="store_true", help="workers open the scene at its path")
    p.add_argument("-W", "--width", type=int)
    p.add_argument("-H", "--height", type=int)
    p.add_argument("--spp", type=int, help="samples per pixel, a square number")
    p.add_argument("--sampler")
    p.add_argument("--filter")
    p.add_argument("--accel")
    p.add_argument("--integrator")
    p.add_argument("--seed", type=int)
    p.add_argument("-d", "--depth", type=int)
    p.add_argument("-t", "--threads", type=int, help="prism threads per tile (default: the cores per task)")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress bar")
    return p


def main(argv=None):
    args = _arguments().parse_args(argv)
    if args.tiles is not None:
        if args.tile_edge is not None:
            print("prism.distributed: error: --tiles is --tile-edge's old name: give --tile-edge only",
                  file=sys.stderr)
            return 2
        print("prism.distributed: warning: --tiles is deprecated: use --tile-edge, the same edge "
              "of a tile in pixels", file=sys.stderr)
        args.tile_edge = args.tiles
    settings = {
        k: getattr(args, k)
        for k in ("width", "height", "spp", "sampler", "filter", "accel", "integrator", "seed", "depth", "threads")
        if getattr(args, k) is not None
    }
    client = None
    if args.scheduler:
        from distributed import Client

        client = Client(args.scheduler)
    bar = None if args.quiet else TileBar()
    try:
        image, stats = render(
            args.scene,
            client,
            tile_edge=args.tile_edge,
            shared=args.shared,
            workers=args.workers,
            progress=None if bar is None else bar.update,
            **settings,
        )
    except (PrismError, ValueError, OSError) as e:
        if bar is not None:
            bar.close()
        print(f"prism.distributed: error: {e}", file=sys.stderr)
        return 1
    finally:
        if client is not None:
            client.close()
    if bar is not None:
        bar.close()
    write(args.output, image)
    if not args.quiet:
        h, w = image.shape[:2]
        print(
            f"prism.distributed: wrote {args.output} ({w}×{h}, {stats['tiles']} tiles on "
            f"{stats['workers']} workers, {stats['wall_seconds']:.2f} s)",
            file=sys.stderr,
        )
    return 0


if __name__ == "__main__":
    # Run as prism.distributed, not __main__, so that the tasks sent to workers name
    # functions the workers can import.
    from prism.distributed import main as _main

    sys.exit(_main())
