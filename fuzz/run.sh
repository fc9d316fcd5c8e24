#!/usr/bin/env bash
# Builds one fuzz target with AFL++ instrumentation and fuzzes it for a while.
#   fuzz/run.sh TARGET SECONDS [extra afl-fuzz options…]
# TARGET is one of src/bin/*.rs (nff, toml, gltf, glb, …). Seeds come from corpus/TARGET,
# the dictionary (if any) from dict/; findings land in $FUZZ_OUT/TARGET (default
# fuzz/out/TARGET, not committed): crashes/ and hangs/ hold the inputs to fix.
# Installs cargo-afl and builds AFL++ on first use (needs a C compiler and make).
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
target=${1:?usage: run.sh TARGET SECONDS [afl-fuzz options]}
seconds=${2:?usage: run.sh TARGET SECONDS [afl-fuzz options]}
shift 2
[[ -f "$here/src/bin/$target.rs" ]] || { echo "run.sh: no target '$target' in src/bin" >&2; exit 2; }
[[ -d "$here/corpus/$target" ]] || { echo "run.sh: no seed corpus corpus/$target" >&2; exit 2; }

if ! cargo afl --version >/dev/null 2>&1; then
    cargo install --locked cargo-afl
fi
# `config --build` fails when AFL++ is already built for this toolchain: that is fine.
cargo afl config --build >/dev/null 2>&1 || true

export CARGO_TARGET_DIR=${CARGO_TARGET_DIR:-$here/target}
cd "$here"
cargo afl build --release --features afl --bin "$target"

out=${FUZZ_OUT:-$here/out}/$target
mkdir -p "$out"
dict=()
case $target in
    glb) [[ -f dict/gltf.dict ]] && dict=(-x dict/gltf.dict) ;;
    *) [[ -f dict/$target.dict ]] && dict=(-x "dict/$target.dict") ;;
esac
# -V: stop after SECONDS; -m: memory limit (MB) so an input that allocates hugely is a
# crash; -t: a run slower than this (ms) is a hang. A second run resumes (-i -).
input=(-i "corpus/$target")
[[ -d "$out/default/queue" ]] && input=(-i -)
AFL_SKIP_CPUFREQ=1 AFL_NO_UI=1 AFL_I_DONT_CARE_ABOUT_MISSING_CRASHES=1 \
    cargo afl fuzz "${input[@]}" -o "$out" -m 1024 -t 1000 -V "$seconds" "${dict[@]}" "$@" \
    -- "$CARGO_TARGET_DIR/release/$target"
echo "findings: $(ls "$out/default/crashes" 2>/dev/null | grep -vc README || true) crashes," \
    "$(ls "$out/default/hangs" 2>/dev/null | wc -l) hangs in $out/default"
