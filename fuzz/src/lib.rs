//! Fuzz targets for prism's scene parsers: one function per input format, each taking the
//! raw bytes AFL++ generates. The binaries in src/bin hand them to AFL (feature `afl`) or
//! replay files with them; `cargo test` runs them over the committed corpora.

/// fuzz/data, the folder inputs are parsed as if they were in (see `targets`).
const DATA: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/data");

mod exercise;
mod replay;
pub mod targets;

pub use exercise::Outcome;
pub use replay::run;
