"""prism.distributed on a LocalCluster of two worker processes: the assembled image is bit
for bit a local render for any tile size and worker count, scenes reach workers with
their files, a killed worker costs only its tiles, and a scene error fails the render
once. One cluster serves the module; `client.restart()` is not needed between tests
since every task is independent."""

import os
import shutil
import signal
import subprocess
import sys

import numpy as np
import pytest
from conftest import ROOT, SCENES, read_pfm, same_bits

import prism
import prism.distributed as dist

distributed = pytest.importorskip("distributed")


@pytest.fixture(scope="module")
def client():
    cluster = distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0"
    )
    c = distributed.Client(cluster)
    yield c
    c.close()
    cluster.close()


def local(scene, **settings):
    s = prism.builtin(scene[len("builtin:") :]) if scene.startswith("builtin:") else prism.load(scene)
    return s.render(**settings)[0]


@pytest.mark.parametrize("tiles", [7, 32, 200])
def test_tiles_assemble_into_the_local_render(client, tiles):
    settings = {"width": 90, "height": 50, "spp": 4, "filter": "mitchell"}
    image, stats = dist.render("builtin:whitted", client, tile_edge=tiles, **settings)
    assert stats["tiles"] == len(dist.tile_grid(90, 50, tiles))
    assert stats["workers"] == 2
    assert same_bits(image, local("builtin:whitted", **settings))


def test_a_scene_with_meshes_and_textures_reaches_workers_as_a_bundle(client, tmp_path):
    # A copy outside the repository, removed before the render: the workers can only
    # have it from the bundle.
    copy = tmp_path / "copy"
    shutil.copytree(SCENES, copy)
    scene = copy / "mesh-room.toml"
    settings = {"width": 64, "height": 48, "spp": 4}
    expected = local(str(scene), **settings)
    bundle = dist.SceneBundle.of(scene)
    assert sorted(bundle.files) == [
        "mesh-room.toml",
        "meshes/gems.mtl",
        "meshes/gems.obj",
        "meshes/torus.ply",
        "textures/testcard.png",
    ]
    shutil.rmtree(copy)
    image, stats = dist.render(bundle_scene(bundle), client, tile_edge=16, **settings)
    assert stats["shipped_bytes"] == bundle.bytes > 0
    assert same_bits(image, expected)


def bundle_scene(bundle):
    """render() takes a bundle where it takes a path (the path may be gone)."""
    return bundle


def test_one_worker_and_two_give_the_same_image(tmp_path):
    settings = {"width": 48, "height": 32, "spp": 4, "integrator": "path"}
    one, _ = dist.render("builtin:cornell-light", tile_edge=16, workers=1, **settings)
    assert same_bits(one, local("builtin:cornell-light", **settings))


def test_frames_follow_their_cameras(client):
    scene = prism.builtin("whitted")
    camera = scene.camera
    frames = [{"fov": camera["fov"]}, {"fov": camera["fov"] * 0.6}]
    images, stats = dist.render("builtin:whitted", client, tile_edge=24, frames=frames, width=40, height=30)
    assert stats["frames"] == 2 and len(images) == 2
    for image, frame in zip(images, frames):
        scene.set_camera(**frame)
        assert same_bits(image, scene.render(width=40, height=30)[0])


def test_material_overrides_reach_the_workers(client):
    scene = prism.builtin("whitted")
    name = scene.materials[0]["name"]
    change = {name: {"color": [0.1, 0.8, 0.2]}}
    image, _ = dist.render("builtin:whitted", client, tile_edge=16, materials=change, width=32, height=24)
    scene.set_material(name, **change[name])
    assert same_bits(image, scene.render(width=32, height=24)[0])


def test_a_killed_worker_costs_only_its_tiles(client):
    settings = {"width": 96, "height": 96, "spp": 16, "threads": 1}
    expected = local("builtin:sphereflake", **settings)
    pids = client.run(os.getpid)
    victim = sorted(pids.values())[0]
    killed = []

    def kill_after_some_tiles(done, total):
        if done == 4 and not killed:
            os.kill(victim, signal.SIGKILL)
            killed.append(victim)

    image, stats = dist.render(
        "builtin:sphereflake", client, tile_edge=12, progress=kill_after_some_tiles, **settings
    )
    assert killed, "the worker was killed during the render"
    assert stats["tiles"] == 64
    assert same_bits(image, expected)
    client.wait_for_workers(2, timeout=60)
    assert victim not in client.run(os.getpid).values(), "the nanny started a new worker"


def test_a_scene_error_fails_the_render_once(client, tmp_path):
    # A bundle whose scene file is broken: the client's own check is bypassed, so every
    # tile meets the error on its worker.
    broken = dist.SceneBundle(
        scene="broken.toml",
        files={"broken.toml": b'[camera]\neye = [0, 0, 5]\nlook_at = "up"\n'},
        digest="broken-scene-test",
        size=(32, 32),
    )
    before = sum(client.run(lambda: __import__("prism.distributed").distributed.attempts).values())
    with pytest.raises(prism.SceneError, match=r"broken\.toml:3:"):
        dist.render(broken, client, tile_edge=8)
    client.wait_for_workers(2, timeout=60)
    after = sum(client.run(lambda: __import__("prism.distributed").distributed.attempts).values())
    # 16 tiles; each tried at most once (no retries of a deterministic error), and the
    # render stopped at the first answer.
    assert 1 <= after - before <= 16


def test_bad_settings_fail_once_with_value_error(client):
    with pytest.raises(ValueError, match="whole image"):
        dist.render("builtin:whitted", client, tile_edge=8, width=16, height=16, sampler="adaptive")


def test_tile_edge_names_the_edge_and_tiles_is_its_deprecated_old_name(client):
    # tile_edge=16 on 40 × 30: tiles of 16 × 16 pixels, 3 × 2 of them, not 16 tiles.
    settings = {"width": 40, "height": 30}
    image, stats = dist.render("builtin:whitted", client, tile_edge=16, **settings)
    assert stats["tiles"] == 6
    with pytest.warns(DeprecationWarning, match="tile_edge="):
        old, old_stats = dist.render("builtin:whitted", client, tiles=16, **settings)
    assert old_stats["tiles"] == 6 and same_bits(old, image)
    with pytest.raises(ValueError, match="give tile_edge= only"):
        dist.render("builtin:whitted", client, tiles=16, tile_edge=16, **settings)
    with pytest.raises(ValueError, match="tile_edge must be at least 1 pixel"):
        dist.render("builtin:whitted", client, tile_edge=0, **settings)


def test_an_unknown_scene_fails_on_the_client():
    with pytest.raises(prism.SceneError, match="cannot read"):
        dist.SceneBundle.of("no/such/scene.toml")
    with pytest.raises(ValueError, match="no built-in"):
        dist.SceneBundle.of("builtin:nope")


def test_the_command_line_writes_the_image(tmp_path):
    out = tmp_path / "flake.pfm"
    run = subprocess.run(
        [sys.executable, "-m", "prism.distributed", "builtin:sphereflake:1", "-W", "40", "-H", "30",
         "--tile-edge", "16", "--workers", "2", "-o", str(out)],
        capture_output=True, text=True, timeout=300,
    )
    assert run.returncode == 0, run.stderr
    assert "6 tiles on 2 workers" in run.stderr
    assert same_bits(read_pfm(out), local("builtin:sphereflake:1", width=40, height=30))
    bad = subprocess.run(
        [sys.executable, "-m", "prism.distributed", str(tmp_path / "missing.toml"), "-o", str(out)],
        capture_output=True, text=True, timeout=300,
    )
    assert bad.returncode == 1 and "cannot read" in bad.stderr
    old = subprocess.run(
        [sys.executable, "-m", "prism.distributed", "builtin:sphereflake:1", "-W", "40", "-H", "30",
         "--tiles", "16", "--workers", "2", "-q", "-o", str(out)],
        capture_output=True, text=True, timeout=300,
    )
    assert old.returncode == 0 and "--tiles is deprecated: use --tile-edge" in old.stderr, old.stderr
