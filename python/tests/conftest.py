"""Shared fixtures: the repository's paths, the release CLI whose output the package's
arrays are held to, and an independent PFM reader (so the comparison does not go through
the code under test)."""

import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
SCENES = ROOT / "scenes"


def cli_binary():
    """target/release/prism (or $PRISM_BIN). The gate builds it with `cargo test
    --release` before the Python suites run; without it the comparison cannot be made,
    which is a failure, not a skip."""
    path = Path(os.environ.get("PRISM_BIN", ROOT / "target" / "release" / "prism"))
    if not path.is_file():
        pytest.fail(f"{path} is missing: build it with `cargo build --release` first")
    return path


def read_pfm(path):
    """A colour PFM as an (H, W, 3) float32 array, top row first."""
    data = Path(path).read_bytes()
    header = []
    at = 0
    while len(header) < 3:
        end = data.index(b"\n", at)
        header.append(data[at:end].decode())
        at = end + 1
    assert header[0] == "PF", header
    w, h = (int(v) for v in header[1].split())
    dtype = "<f4" if float(header[2]) < 0 else ">f4"
    pixels = np.frombuffer(data[at:], dtype=dtype).reshape(h, w, 3)
    return np.ascontiguousarray(pixels[::-1]).astype(np.float32)


@pytest.fixture
def cli_render(tmp_path):
    """Runs `prism render ARGS -o x.pfm` and returns the image it wrote."""

    def run(*args):
        out = tmp_path / "cli.pfm"
        subprocess.run(
            [str(cli_binary()), "render", *map(str, args), "-q", "-o", str(out)],
            check=True,
            capture_output=True,
        )
        return read_pfm(out)

    return run


def same_bits(a, b):
    """Whether two float32 images are bit for bit equal (NaN and -0.0 included)."""
    a = np.ascontiguousarray(a, dtype=np.float32)
    b = np.ascontiguousarray(b, dtype=np.float32)
    return a.shape == b.shape and np.array_equal(a.view(np.uint32), b.view(np.uint32))
