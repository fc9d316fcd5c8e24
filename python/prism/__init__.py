"""prism, a deterministic CPU ray tracer, from Python.

    import prism
    scene = prism.load("scenes/whitted.toml")      # or prism.builtin("cornell")
    image, stats = scene.render(width=320, height=240, spp=4)
    prism.write("whitted.exr", image)

`image` is a NumPy float32 array of shape (height, width, 3) holding linear RGB, exactly
the values `prism render -o x.pfm` writes. Renders are bit-identical for any thread count
and tile size, which `prism.distributed` relies on to cut a render into tiles for Dask.
Errors raise `prism.PrismError` (subclasses `SceneError`, `RenderError`, `ImageError`)
with prism's own message, a scene file's mistakes as file:line:col; bad arguments raise
`ValueError`. A render releases the GIL and stops on Ctrl-C with `KeyboardInterrupt`.
"""

import json as _json
import operator as _operator
import os as _os
import warnings as _warnings

import numpy as _np

from . import _prism
from ._prism import ImageError, PrismError, RenderError, SceneError

__all__ = [
    "Scene",
    "load",
    "builtin",
    "builtins",
    "write",
    "read",
    "compare",
    "bench",
    "settings",
    "PrismError",
    "SceneError",
    "RenderError",
    "ImageError",
]

__version__ = _prism.__version__


def _array(pixels, width, height):
    """The native side's bytes of little-endian f32 RGB as an (H, W, 3) array, no copy."""
    return _np.frombuffer(pixels, dtype="<f4").reshape(height, width, 3)


def _image_bytes(image, name):
    """An (H, W, 3) array-like as (bytes, width, height) for the native side."""
    a = _np.asarray(image)
    if a.ndim != 3 or a.shape[2] != 3:
        raise ValueError(f"{name}: an image is an array of shape (height, width, 3), got {a.shape}")
    if not _np.issubdtype(a.dtype, _np.number):
        raise ValueError(f"{name}: an image holds numbers, got dtype {a.dtype}")
    a = _np.ascontiguousarray(a, dtype="<f4")
    return a.tobytes(), a.shape[1], a.shape[0]


class Scene:
    """A scene to render: from `load(path)` or `builtin(name)`.

    `render(...)` returns `(image, stats)`. Settings left out keep the scene's own (its
    file's [render] table, or the built-in's), as on the command line.
    """

    __slots__ = ("_native",)

    def __init__(self, native):
        self._native = native

    @property
    def name(self):
        """The scene's file, or builtin:NAME."""
        return self._native.name

    @property
    def size(self):
        """The (width, height) the scene asks for."""
        return self._native.size

    @property
    def warnings(self):
        """What the loader warned about (missing MTL files, features not rendered)."""
        return self._native.warnings

    @property
    def camera(self):
        """The camera as a dict: eye, look_at, up (three numbers each) and fov (degrees)."""
        return self._native.camera

    def set_camera(self, *, eye=None, look_at=None, up=None, fov=None):
        """Moves the camera; what is not given stays. Raises ValueError for a camera that
        cannot make rays (eye on the look-at point, up along the view, fov outside 0..180)."""
        self._native.set_camera(eye=eye, look_at=look_at, up=up, fov=fov)

    @property
    def materials(self):
        """The materials as dicts: name, color (when solid), ambient, diffuse, specular,
        shininess, reflect, transmit, ior, emission."""
        return self._native.materials

    def set_material(self, name, **changes):
        """Changes the coefficients of material `name` (keywords as in `materials`)."""
        self._native.set_material(name, **changes)

    def info(self):
        """(primitives, lights, materials), by count."""
        return self._native.info()

    def render(
        self,
        *,
        width=None,
        height=None,
        spp=None,
        sampler=None,
        filter=None,
        accel=None,
        integrator=None,
        shadows=None,
        seed=None,
        threads=None,
        tile=None,
        depth=None,
        packets=None,
        region=None,
        **settings,
    ):
        """Renders the scene; returns (image, stats).

        width, height: image size in pixels. spp: samples per pixel, a square number
        (n × n). sampler, filter, accel, integrator, shadows: names as the command line
        takes them (e.g. accel="bvh:build=sweep", integrator="path"). seed: the seed of
        every random decision. threads: worker threads, 0 = every core. tile_size: the
        edge in pixels of the square tiles the threads take (tile_size=16: tiles of
        16 × 16 pixels, not 16 tiles); tile= is its deprecated old name, the same edge
        in pixels. depth: ray-tree depth limit. packets: trace camera
        rays in packets (the image is the same either way). region: (x0, y0, x1, y1) to
        render only that rectangle, whose pixels are bit for bit the whole image's. Any
        other keyword is a setting of `settings()` by its key, as the scene file's
        [render] table writes it (e.g. adaptive_depth=2, min_weight=0, filter_radius=1.5).

        image: float32 array (rows, columns, 3) of linear RGB. stats: a dict with the
        engine's counters ("counters"), "total_rays", "render_seconds",
        "build_seconds", "threads" and the settings in words.
        """
        if tile is not None:
            if "tile_size" in settings:
                raise ValueError("tile= and tile_size= name the same setting: give tile_size= only")
            _warnings.warn(
                "tile= is deprecated: use tile_size=, the same tile edge in pixels",
                DeprecationWarning,
                stacklevel=2,
            )
        pixels, w, h, stats = self._native.render(
            width=_whole("width", width),
            height=_whole("height", height),
            spp=_samples_per_pixel(spp),
            sampler=sampler,
            filter=filter,
            accel=accel,
            integrator=integrator,
            shadows=shadows,
            seed=_whole("seed", seed),
            threads=_whole("threads", threads),
            tile=_whole("tile", tile, "tile_size"),
            depth=_whole("depth", depth, "max_depth"),
            packets=packets,
            region=None if region is None else tuple(int(v) for v in region),
            settings=[
                (key, _setting_text(_whole(key, value))) for key, value in settings.items()
            ],
        )
        return _array(pixels, w, h), _json.loads(stats)

    def __repr__(self):
        return repr(self._native)


def _integer_ranges():
    """{key: (lowest, highest)} of the whole-number settings, from the settings table."""
    return {key: (lo, hi) for key, lo, hi in _prism.integer_ranges()}


_RANGES = _integer_ranges()


def _whole(keyword, value, key=None):
    """`value` of the keyword `keyword` (the setting `key`, the keyword itself by default)
    checked against the setting's range: a negative or too large whole number raises
    ValueError naming the keyword and the range, rather than the native side's
    OverflowError. Values that are not whole numbers pass unchanged, for the native side
    to refuse by type."""
    if value is None or isinstance(value, bool):
        return value
    bounds = _RANGES.get(key or keyword)
    if bounds is None:
        return value
    try:
        number = _operator.index(value)
    except TypeError:
        return value
    lo, hi = bounds
    if not lo <= number <= hi:
        raise ValueError(f"{keyword}={number}: expected a whole number from {lo} to {hi}")
    return number


def _samples_per_pixel(spp):
    """`spp` checked against its range, 1 to the largest square of samples per axis (the
    native side checks that it is a square)."""
    if spp is None or isinstance(spp, bool):
        return spp
    try:
        number = _operator.index(spp)
    except TypeError:
        return spp
    hi = _RANGES["samples"][1] ** 2
    if not 1 <= number <= hi:
        raise ValueError(
            f"spp={number}: samples per pixel must be a square number from 1 to {hi} "
            "(n × n samples)"
        )
    return number


def _setting_text(value):
    """A setting's value as the settings table reads it: booleans as true/false."""
    if isinstance(value, bool):
        return "true" if value else "false"
    return str(value)


def settings():
    """Every render setting as a dict: key, type, default (as text) and help. Each key is a
    keyword of `Scene.render` and of the scene file's [render] table."""
    return [
        {"key": key, "type": kind, "default": default, "help": help_text}
        for key, kind, default, help_text in _prism.settings()
    ]


def load(path):
    """Loads a scene file (.toml, .nff, .gltf, .glb, .obj, .ply). Raises SceneError with
    the file, line and column of a mistake."""
    return Scene(_prism.load(_os.fspath(path)))


def builtin(name):
    """A built-in scene by name (see `builtins()`; also "sphereflake:N")."""
    return Scene(_prism.builtin(name))


def builtins():
    """The built-in scenes as (name, description) pairs."""
    return _prism.builtins()


def write(path, image, *, half=False):
    """Writes an (H, W, 3) image of linear RGB to `path`, in the format its extension
    names: .png (8-bit sRGB), .exr (32-bit float, or 16-bit with half=True), .pfm. The file
    is written under a temporary name and renamed."""
    data, w, h = _image_bytes(image, "write")
    _prism.write(_os.fspath(path), data, w, h, half)


def read(path):
    """Reads an image (.png, .jpg, .exr, .pfm) as an (H, W, 3) float32 array of linear RGB."""
    pixels, w, h = _prism.read(_os.fspath(path))
    return _array(pixels, w, h)


def _image_or_file(x, name):
    if isinstance(x, (str, bytes, _os.PathLike)):
        return _image_bytes(read(x), name)
    return _image_bytes(x, name)


def compare(reference, test, *, ppd=67.0):
    """How far `test` is from `reference` (arrays or image files): a dict of rmse, psnr
    (dB), ssim, flip (mean), flip_max and pixels, as `prism compare` reports them."""
    return _prism.compare(
        _image_or_file(reference, "reference"), _image_or_file(test, "test"), ppd
    )


def bench(scenes, methods=("bvh", "grid", "kdtree", "octree"), *, size=32, repeat=1, threads=1):
    """The acceleration benchmark of `prism bench`: every method in `methods` (as
    `accel=` takes them) on every scene in `scenes` (built-in names or files), on one
    camera ray per pixel of an image `size` pixels along its longer side plus the shadow
    rays of their hits. Returns one dict per (scene, method): build_ms, nodes,
    memory_bytes, primary/shadow rays, Mrays/s, nodes and tests per ray, and
    matches_reference (its hits equal the reference BVH's)."""
    if isinstance(scenes, str):
        scenes = [scenes]
    if isinstance(methods, str):
        methods = [methods]
    return _prism.bench(list(scenes), list(methods), size, repeat, threads)
