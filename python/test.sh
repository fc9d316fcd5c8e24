#!/usr/bin/env bash
# The Python package's test command (README, .ci/run): builds prism's release CLI (the
# suites hold the package's arrays to its PFM output), creates a virtual environment in
# target/py-venv with maturin, NumPy, Dask and pytest, installs the package from python/
# (`pip install ./python`, a release build in the workspace's target folder), and runs the
# suites. Needs Python 3.8 or newer with venv and pip ($PYTHON, default python3).
set -euo pipefail
cd "$(dirname "$0")/.."

python=${PYTHON:-python3}
venv=target/py-venv
cargo build --release -p prism-cli --quiet
if [ ! -x "$venv/bin/python" ]; then
  "$python" -m venv "$venv"
fi
# The build backend runs the venv's maturin by name.
export PATH="$PWD/$venv/bin:$PATH"
"$venv/bin/python" -m pip install --quiet maturin numpy dask distributed pytest
# Without build isolation the build uses the maturin installed above rather than
# fetching its own; the native module lands in the venv's site-packages.
"$venv/bin/python" -m pip install --quiet --no-build-isolation --force-reinstall --no-deps ./python
# From the repository's root, so that python/prism (the sources, without the native
# module) does not hide the installed package.
exec "$venv/bin/python" -m pytest -q -p no:cacheprovider python/tests "$@"
