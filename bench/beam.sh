#!/bin/sh
# Beam tracing against jittered supersampling: prints the Markdown table of
# docs/beam-tracing.md and writes its plot. Run from the repository's root.
set -eu
cargo run --release -p prism --example beam_vs_supersampling -- docs/images/beam-vs-supersampling.svg
