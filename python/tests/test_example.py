"""The example of docs/python.md runs as written and finds the Dask render identical."""

import subprocess
import sys

from conftest import ROOT


def test_the_example_runs(tmp_path):
    run = subprocess.run(
        [sys.executable, "python/examples/render_and_compare.py", str(tmp_path)],
        cwd=ROOT, capture_output=True, text=True, timeout=600,
    )
    assert run.returncode == 0, run.stdout + run.stderr
    assert "identical: True" in run.stdout
    assert (tmp_path / "whitted.exr").is_file() and (tmp_path / "whitted-closer.png").is_file()
