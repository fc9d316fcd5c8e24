//! The command line's test suites, built as one test binary: each suite is a file beside
//! this one, declared here as a module, so that the suites share one compilation and one
//! link instead of one each (ARCHITECTURE.md, "How to add a test suite"). `cargo test
//! --release -p prism-cli --test suites -- NAME::` runs the suite of NAME.rs alone.

mod common;

mod bench;
mod cli;
mod commands;
mod front_door;
mod readme;
#[cfg(unix)]
mod signals;
