"""prism from Python: arrays equal the command line's PFM output bit for bit, settings
and overrides reach the engine, regions hold the whole image's pixels."""

import numpy as np
import pytest
from conftest import SCENES, same_bits

import prism

# (scene or builtin, Python settings, the same on the command line)
CASES = [
    ("builtin:whitted", {"width": 64, "height": 48}, ["-W", 64, "-H", 48]),
    (
        SCENES / "whitted.toml",
        {"width": 80, "height": 60, "spp": 4, "sampler": "jittered", "seed": 7},
        ["-W", 80, "-H", 60, "--spp", 4, "--sampler", "jittered", "--seed", 7],
    ),
    (
        SCENES / "mesh-room.toml",
        {"width": 72, "height": 40, "filter": "mitchell", "spp": 4, "threads": 1, "tile_size": 5},
        ["-W", 72, "-H", 40, "--filter", "mitchell", "--spp", 4],
    ),
    (
        "builtin:cornell-light",
        {"width": 40, "height": 40, "spp": 4, "integrator": "path", "accel": "kdtree"},
        ["-W", 40, "-H", 40, "--spp", 4, "--integrator", "path", "--accel", "kdtree"],
    ),
    (SCENES / "pyramid.nff", {"width": 50, "height": 50}, ["-W", 50, "-H", 50]),
    (SCENES / "spheres.gltf", {"width": 64, "height": 36, "sampler": "adaptive"}, ["-W", 64, "-H", 36, "--sampler", "adaptive"]),
]


def scene_of(name):
    name = str(name)
    if name.startswith("builtin:"):
        return prism.builtin(name[len("builtin:") :]), ["--builtin", name[len("builtin:") :]]
    return prism.load(name), [name]


@pytest.mark.parametrize("name,settings,flags", CASES, ids=[str(c[0]).split("/")[-1] for c in CASES])
def test_arrays_equal_the_clis_pfm_bit_for_bit(cli_render, name, settings, flags):
    scene, source = scene_of(name)
    image, stats = scene.render(**settings)
    assert image.dtype == np.float32
    assert image.shape == (settings["height"], settings["width"], 3)
    assert stats["complete"] and stats["total_rays"] > 0
    expected = cli_render(*source, *flags)
    assert image.any(), "a black image proves nothing"
    assert same_bits(image, expected)


def test_regions_hold_the_whole_images_pixels():
    scene = prism.builtin("whitted")
    whole, _ = scene.render(width=50, height=30, spp=4, filter="gaussian")
    out = np.zeros_like(whole)
    for y0 in range(0, 30, 13):
        for x0 in range(0, 50, 13):
            region = (x0, y0, min(x0 + 13, 50), min(y0 + 13, 30))
            part, stats = scene.render(width=50, height=30, spp=4, filter="gaussian", region=region)
            assert stats["region"] == list(region)
            out[region[1] : region[3], region[0] : region[2]] = part
    assert same_bits(out, whole)


def test_threads_and_tiles_do_not_change_the_image():
    scene = prism.builtin("sphereflake:2")
    a, sa = scene.render(width=48, height=32, spp=4, threads=1, tile_size=64)
    b, sb = scene.render(width=48, height=32, spp=4, threads=2, tile_size=3)
    assert same_bits(a, b)
    assert sa["counters"] == sb["counters"]


def test_the_camera_and_materials_can_be_changed():
    scene = prism.builtin("whitted")
    before, _ = scene.render(width=40, height=30)
    camera = scene.camera
    assert set(camera) == {"eye", "look_at", "up", "fov"}
    scene.set_camera(fov=camera["fov"] / 2)
    zoomed, _ = scene.render(width=40, height=30)
    assert not same_bits(before, zoomed)
    scene.set_camera(fov=camera["fov"])
    assert same_bits(scene.render(width=40, height=30)[0], before)

    names = [m["name"] for m in scene.materials]
    assert names, "the built-in has named materials"
    scene.set_material(names[0], color=[0.0, 0.0, 1.0], reflect=0.0)
    recoloured, _ = scene.render(width=40, height=30)
    assert not same_bits(before, recoloured)
    assert scene.materials[0]["color"] == [0.0, 0.0, 1.0]


def test_write_and_read_round_trip(tmp_path):
    image, _ = prism.builtin("cornell").render(width=32, height=24)
    for ext in ("pfm", "exr"):
        path = tmp_path / f"x.{ext}"
        prism.write(path, image)
        assert same_bits(prism.read(path), image), ext
    prism.write(tmp_path / "x.png", image)
    png = prism.read(tmp_path / "x.png")
    assert png.shape == image.shape and np.abs(png - np.clip(image, 0, 1)).max() < 0.01


def test_compare_measures_what_prism_compare_does(tmp_path):
    scene = prism.builtin("checkerboard")
    a, _ = scene.render(width=48, height=32, spp=16, sampler="jittered")
    b, _ = scene.render(width=48, height=32)
    same = prism.compare(a, a)
    assert same["rmse"] == 0.0 and same["psnr"] == float("inf") and same["flip"] == 0.0
    differ = prism.compare(a, b)
    assert 0 < differ["rmse"] < 1 and differ["ssim"] < 1 and differ["pixels"] == 48 * 32
    prism.write(tmp_path / "a.exr", a)
    assert prism.compare(tmp_path / "a.exr", b) == differ


def test_bench_returns_records_that_match_the_reference():
    records = prism.bench(["cornell", "sphereflake:1"], ["bvh", "grid"], size=16)
    assert [(r["scene"], r["method"]) for r in records] == [
        ("cornell", "bvh"),
        ("cornell", "grid"),
        ("sphereflake:1", "bvh"),
        ("sphereflake:1", "grid"),
    ]
    for r in records:
        assert r["matches_reference"], r
        assert r["primary_rays"] > 0 and r["nodes"] > 0 and r["primary_mrays_per_s"] > 0


def _value(setting):
    """A setting's default as the Python value a user would pass."""
    text = setting["default"]
    return {
        "integer": int,
        "number": float,
        "boolean": lambda t: t == "true",
    }.get(setting["type"], str)(text)


def test_every_setting_of_the_table_is_a_render_keyword():
    """The settings table is the one list: each key renders as a keyword, a setting reaches
    the engine, and a key the table lacks is refused."""
    keys = [s["key"] for s in prism.settings()]
    assert keys[:3] == ["width", "height", "samples"], keys
    assert {"adaptive_depth", "min_weight", "tile_size", "spd_rules"} <= set(keys)
    scene = prism.builtin("whitted")
    base, _ = scene.render(width=12, height=9)
    for setting in prism.settings():
        if setting["key"] in ("width", "height"):
            continue
        image, _ = scene.render(width=12, height=9, **{setting["key"]: _value(setting)})
        assert image.shape == (9, 12, 3), setting["key"]
    deeper, _ = scene.render(width=12, height=9, max_depth=1)
    assert not same_bits(deeper, base), "max_depth reaches the engine"
    with pytest.raises(ValueError, match="unknown setting 'colour'"):
        scene.render(width=12, height=9, colour=1)
    with pytest.raises(ValueError, match="adaptive_depth"):
        scene.render(width=12, height=9, adaptive_depth=9)


def test_tile_size_is_the_tile_edge_and_tile_its_deprecated_alias():
    scene = prism.builtin("whitted")
    settings = {"width": 40, "height": 24, "threads": 2, "packets": False}
    by_key, _ = scene.render(tile_size=7, **settings)
    with pytest.warns(DeprecationWarning, match="tile_size="):
        by_alias, _ = scene.render(tile=7, **settings)
    assert same_bits(by_key, by_alias)
    with pytest.raises(ValueError, match="tile_size= only"):
        scene.render(tile=7, tile_size=7, **settings)
