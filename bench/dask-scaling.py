#!/usr/bin/env python3
"""Scaling of prism.distributed on this machine (docs/python.md): the same render on one
and on two local Dask workers, the overhead each tile costs (scheduling, transfer,
assembly) by tile size, the smallest tile whose overhead stays under 5 % of its work, and
from those figures a paper estimate for a 4K animation on a 100-machine cluster.

Every render uses one prism thread per tile and one task per worker, so a worker is one
core. Overhead per tile = (wall time on one worker - the sum of the tiles' render times as
the engine measured them on the worker) / tiles: scheduling, messages, the Python wrapper,
assembly, everything but tracing. Run with the package installed (python/test.sh makes
target/py-venv):

    target/py-venv/bin/python bench/dask-scaling.py [--quick]
"""

import argparse
import os
import statistics
import time

import numpy as np

import prism
import prism.distributed as dist
from distributed import Client, LocalCluster

SCENE = "builtin:sphereflake"


def local_seconds(settings, repeat):
    scene = prism.builtin(SCENE[len("builtin:") :])
    scene.render(**dict(settings, width=16, height=16))  # build the accelerator once
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        image, _ = scene.render(threads=1, **settings)
        times.append(time.perf_counter() - start)
    return statistics.median(times), image


def distributed_seconds(client, settings, tiles, repeat, reference):
    # One warm-up render ships the bundle and loads the scene on every worker.
    dist.render(SCENE, client, tile_edge=tiles, threads=1, **settings)
    times = []
    for _ in range(repeat):
        image, stats = dist.render(SCENE, client, tile_edge=tiles, threads=1, **settings)
        times.append((stats["wall_seconds"], sum(stats["tile_seconds"])))
        assert np.array_equal(image.view(np.uint32), reference.view(np.uint32))
    wall, traced = min(times)
    return wall, traced, stats["tiles"]


def cluster(workers):
    c = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=":0")
    return c, Client(c)


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--quick", action="store_true", help="a smaller image, one repetition")
    args = p.parse_args()
    size = (320, 240) if args.quick else (640, 480)
    repeat = 1 if args.quick else 2
    settings = {"width": size[0], "height": size[1], "spp": 16}
    pixels = size[0] * size[1]

    local, reference = local_seconds(settings, repeat)
    per_pixel = local / pixels
    print(f"scene {SCENE}, {size[0]}x{size[1]}, 16 spp, one thread: local render {local:.3f} s "
          f"({per_pixel * 1e6:.2f} us per pixel)")

    print(f"(wall times: the faster of {repeat} renders; load average {os.getloadavg()[0]:.1f})")
    print("\n| tile | tiles | 1 worker (s) | 2 workers (s) | speed-up | overhead per tile (ms) | overhead / tile work |")
    print("|---|---|---|---|---|---|---|")
    overheads = {}
    c1, client1 = cluster(1)
    c2, client2 = cluster(2)
    try:
        for tile in (16, 32, 64, 128):
            one, traced, count = distributed_seconds(client1, settings, tile, repeat, reference)
            two, _, _ = distributed_seconds(client2, settings, tile, repeat, reference)
            overhead = max(0.0, (one - traced) / count)
            work = local / count
            overheads[tile] = overhead
            print(f"| {tile} | {count} | {one:.3f} | {two:.3f} | {one / two:.2f} | "
                  f"{overhead * 1e3:.2f} | {overhead / work * 100:.1f} % |")
    finally:
        for client, c in ((client1, c1), (client2, c2)):
            client.close()
            c.close()

    # The overhead of a tile hardly grows with its pixels (scheduling and a few messages;
    # the pixels themselves are 12 bytes each); the median over the tile sizes is taken as
    # the cost of any tile.
    cost = statistics.median(overheads.values())
    edge = int(np.ceil(np.sqrt(20 * cost / per_pixel)))
    print(f"\noverhead per tile, median {cost * 1e3:.2f} ms: under 5 % of the work from "
          f"{20 * cost / per_pixel:.0f} pixels a tile, a square of {edge} px, at this scene's "
          f"{per_pixel * 1e6:.2f} us per pixel")

    # On paper: 4K frames, 10 s at 24 frames/s, on 100 machines of 32 cores (a task per
    # core), this scene's work per pixel and the overhead measured here.
    frames, machines, cores = 240, 100, 32
    w, h = 3840, 2160
    work = w * h * frames * per_pixel
    print(f"\n4K animation, {frames} frames, {machines} machines x {cores} cores, "
          f"{per_pixel * 1e6:.2f} us per pixel per core:")
    # Overhead spread over every core is the lower bound of the wall time; overhead paid
    # one task after another (a single scheduler) is the upper one.
    print("| tile | tasks | work per tile (s) | work (core-hours) | overhead (core-hours) | "
          "wall, overhead in parallel (s) | wall, overhead serial (s) |")
    print("|---|---|---|---|---|---|---|")
    for tile in (64, 128, 256, 512):
        tiles = -(-w // tile) * -(-h // tile) * frames
        over = tiles * cost
        low = (work + over) / (machines * cores)
        high = max(work / (machines * cores), over)
        print(f"| {tile} | {tiles} | {tile * tile * per_pixel:.3f} | {work / 3600:.1f} | "
              f"{over / 3600:.2f} | {low:.0f} | {high:.0f} |")

if __name__ == "__main__":
    main()
