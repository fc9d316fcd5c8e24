//! What every command-line test needs: a fresh working directory per test and a way to run
//! the built `prism` binary in it.
#![allow(dead_code)]

pub(crate) mod terminal;

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A fresh, empty directory `SUITE-TEST` under cargo's per-target scratch folder.
pub(crate) fn work_dir(suite: &str, test: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("{suite}-{test}"));
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).unwrap();
    dir
}

/// The binary under test: the one cargo built, or another one named by `PRISM_BIN` (to run
/// the suite against an older build for a before/after comparison).
pub(crate) fn bin() -> std::ffi::OsString {
    std::env::var_os("PRISM_BIN").unwrap_or_else(|| env!("CARGO_BIN_EXE_prism").into())
}

/// Runs `prism ARGS` in `dir`.
pub(crate) fn prism(dir: &Path, args: &[&str]) -> Output {
    Command::new(bin())
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the prism binary runs")
}
