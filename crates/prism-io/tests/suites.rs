//! prism-io's test suites, built as one test binary: each suite is a file beside this one,
//! declared here as a module, so that the suites share one compilation and one link instead
//! of one each (ARCHITECTURE.md, "How to add a test suite"). `cargo test --release -p
//! prism-io --test suites -- NAME::` runs the suite of NAME.rs alone.

// The helpers every suite shares live beside the engine's tests (ARCHITECTURE.md).
#[path = "../../prism/tests/common/mod.rs"]
mod common;

// Every suite runs under the counting allocator, so that the parser suites can bound the
// bytes a hostile file makes them allocate (common/work.rs); the count is per thread.
#[global_allocator]
static COUNTING: common::work::Counting = common::work::Counting;

mod fuzz_corpora;
mod fuzz_regressions;
mod gltf;
mod nff;
mod obj;
mod ply;
mod scene_toml;
mod spd;
