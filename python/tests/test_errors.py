"""What prism refuses reaches Python as an exception carrying prism's message: scene
files by file:line:col, bad arguments as ValueError; nothing panics."""

import numpy as np
import pytest

import prism


def test_a_missing_file_is_a_scene_error_naming_it(tmp_path):
    missing = tmp_path / "nowhere.toml"
    with pytest.raises(prism.SceneError, match=r"cannot read .*nowhere\.toml"):
        prism.load(missing)


def test_a_malformed_scene_names_file_line_and_column(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text('[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, "x"]\n')
    with pytest.raises(prism.SceneError) as caught:
        prism.load(bad)
    assert f"{bad}:3:" in str(caught.value)
    assert isinstance(caught.value, prism.PrismError)


def test_an_unknown_extension_and_a_directory_are_refused(tmp_path):
    odd = tmp_path / "scene.xyz"
    odd.write_text("nothing")
    with pytest.raises(prism.SceneError, match="unknown scene format"):
        prism.load(odd)
    with pytest.raises(prism.SceneError, match="directory"):
        prism.load(tmp_path)


def test_an_unknown_builtin_lists_the_known_ones():
    with pytest.raises(ValueError, match="no built-in scene named 'nope'.*whitted"):
        prism.builtin("nope")


@pytest.mark.parametrize(
    "settings,message",
    [
        ({"spp": 3}, "square number"),
        ({"spp": 0}, "square number"),
        ({"width": 0}, "width=0: expected a whole number from 1 to 65536"),
        ({"sampler": "wobbly"}, "sampler"),
        ({"accel": "bvh:leaf=banana"}, "accel"),
        ({"integrator": "photon"}, "integrator"),
        ({"depth": 0}, "depth=0: expected a whole number from 1 to 256"),
        ({"max_depth": 0}, "max_depth=0: expected a whole number from 1 to 256"),
        ({"threads": 100000}, "threads"),
        ({"tile": 0}, "tile=0"),
        ({"region": (0, 0, 100, 10)}, "outside"),
        ({"region": (5, 5, 5, 9)}, "empty"),
        ({"sampler": "adaptive", "region": (0, 0, 4, 4)}, "whole image"),
        ({"sampler": "corners", "spp": 4}, "own sample count"),
    ],
)
@pytest.mark.filterwarnings("ignore:tile= is deprecated")
def test_bad_settings_raise_value_error(settings, message):
    scene = prism.builtin("whitted")
    settings = {"width": 20, "height": 10, **settings}
    with pytest.raises(ValueError, match=message):
        scene.render(**settings)


def test_wrong_types_raise_type_error():
    scene = prism.builtin("whitted")
    with pytest.raises(TypeError):
        scene.render(width="wide")


@pytest.mark.parametrize(
    "keyword,value,accepted",
    [
        ("width", -1, "from 1 to 65536"),
        ("width", 2**40, "from 1 to 65536"),
        ("height", -1, "from 1 to 65536"),
        ("spp", -4, "square number from 1 to 4096"),
        ("spp", 2**70, "square number from 1 to 4096"),
        ("seed", -1, "from 0 to 18446744073709551615"),
        ("seed", 2**64, "from 0 to 18446744073709551615"),
        ("threads", -2, "from 0 to 1024"),
        ("threads", 2**65, "from 0 to 1024"),
        ("tile", -16, "from 1 to 4294967295"),
        ("depth", -1, "from 1 to 256"),
        ("depth", 2**33, "from 1 to 256"),
        ("tile_size", -16, "from 1 to 4294967295"),
        ("adaptive_depth", -1, "from 0 to"),
    ],
)
@pytest.mark.filterwarnings("ignore:tile= is deprecated")
def test_negative_or_too_large_numbers_raise_value_error_naming_keyword_and_range(
    keyword, value, accepted
):
    scene = prism.builtin("whitted")
    with pytest.raises(ValueError) as caught:
        scene.render(**{keyword: value})
    message = str(caught.value)
    assert message.startswith(f"{keyword}={value}:"), message
    assert accepted in message, message


def test_bad_overrides_raise_value_error():
    scene = prism.builtin("whitted")
    camera = scene.camera
    with pytest.raises(ValueError, match="coincide"):
        scene.set_camera(eye=camera["look_at"])
    with pytest.raises(ValueError, match="field of view"):
        scene.set_camera(fov=180)
    with pytest.raises(ValueError, match="finite"):
        scene.set_camera(eye=[float("nan"), 0, 0])
    assert scene.camera == camera, "a refused change leaves the camera as it was"
    with pytest.raises(ValueError, match="no material named 'chrome'"):
        scene.set_material("chrome", reflect=1.0)
    name = scene.materials[0]["name"]
    with pytest.raises(ValueError, match="reflect"):
        scene.set_material(name, reflect=2.0)


@pytest.mark.parametrize(
    "change,message",
    [
        ({"diffuse": -1.0}, "diffuse must be a finite number of at least 0 (no upper bound)"),
        ({"shininess": float("inf")}, "shininess must be a finite number of at least 0"),
        ({"ior": 0.0}, "ior must be a finite number greater than 0 (no upper bound)"),
        ({"reflect": 2.0}, "reflect must be between 0 and 1"),
    ],
)
def test_material_ranges_say_no_upper_bound_rather_than_print_the_largest_float(
    change, message
):
    scene = prism.builtin("whitted")
    with pytest.raises(ValueError) as caught:
        scene.set_material(scene.materials[0]["name"], **change)
    assert message in str(caught.value)
    assert "340282" not in str(caught.value) and "e-38" not in str(caught.value)


def test_image_errors(tmp_path):
    image = np.zeros((4, 5, 3), dtype=np.float32)
    with pytest.raises(prism.ImageError):
        prism.write(tmp_path / "x.bmp", image)
    with pytest.raises(prism.ImageError):
        prism.write(tmp_path / "no" / "such" / "dir" / "x.exr", image)
    with pytest.raises(ValueError, match=r"shape \(height, width, 3\)"):
        prism.write(tmp_path / "x.exr", np.zeros((4, 5)))
    with pytest.raises(ValueError, match="EXR"):
        prism.write(tmp_path / "x.png", image, half=True)
    with pytest.raises(prism.ImageError, match="differ in size"):
        prism.compare(image, np.zeros((5, 4, 3)))
    with pytest.raises(prism.ImageError):
        prism.read(tmp_path / "missing.exr")
    with pytest.raises(ValueError, match="scene"):
        prism.bench(["not-a-scene"])


def test_render_errors_name_the_python_keyword_not_the_command_line_flag():
    # The beam tracer refuses curved shapes and says which integrator to use instead.
    scene = prism.builtin("whitted")
    with pytest.raises(prism.RenderError) as caught:
        scene.render(width=8, height=6, integrator="beam")
    message = str(caught.value)
    assert 'integrator="whitted"' in message, message
    assert "--integrator" not in message, message
