#!/usr/bin/env bash
# Re-renders the golden images in crates/prism/tests/golden/ from the current code.
# Do this only on purpose, after a change that should alter the pictures, and look at
# every image before committing it.
set -euo pipefail
cd "$(dirname "$0")/.."
PRISM_BLESS=1 cargo test --release -p prism --test suites -- golden:: --nocapture
git status --short crates/prism/tests/golden/
