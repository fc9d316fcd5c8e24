"""Every Python block of README.md and docs/*.md runs as written: saved as a script and run
with `python file.py`, as a reader would, from a folder where the repository's scenes are
at hand."""

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
FENCE = re.compile(r"```python\n(.*?)```", re.S)


def blocks():
    for doc in [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]:
        for i, match in enumerate(FENCE.finditer(doc.read_text(encoding="utf-8"))):
            yield pytest.param(match.group(1), id=f"{doc.name}-{i + 1}")


@pytest.mark.parametrize("code", list(blocks()))
def test_documented_python_runs_as_written(code, tmp_path):
    (tmp_path / "scenes").symlink_to(ROOT / "scenes")
    script = tmp_path / "example.py"
    script.write_text(code, encoding="utf-8")
    run = subprocess.run(
        [sys.executable, str(script)],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=600,
        env={**os.environ, "PYTHONPATH": ""},
    )
    assert run.returncode == 0, f"{code}\n---\n{run.stdout}\n{run.stderr}"


def test_there_are_blocks_to_run():
    assert len(list(blocks())) >= 3
