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

/// The words of a command line written as one string (split at spaces; no quoting).
pub(crate) fn words(line: &str) -> Vec<&str> {
    line.split_whitespace().collect()
}

/// A run's standard output, as text.
pub(crate) fn stdout(out: &Output) -> String {
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// A run's standard error, as text.
pub(crate) fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// Asserts that the run `what` exited with `code` and did not panic; returns its stderr.
#[track_caller]
pub(crate) fn expect_exit(out: &Output, code: i32, what: &str) -> String {
    let err = stderr(out);
    assert_eq!(
        out.status.code(),
        Some(code),
        "{what}: expected exit {code}, got {:?}; stderr:\n{err}",
        out.status
    );
    assert!(!err.contains("panicked"), "{what} panicked:\n{err}");
    err
}

/// Runs `prism ARGS` in `dir` and asserts its exit `code` and that it did not panic;
/// returns its stdout and stderr.
#[track_caller]
pub(crate) fn run(dir: &Path, args: &[&str], code: i32) -> (String, String) {
    let out = prism(dir, args);
    let err = expect_exit(&out, code, &format!("prism {args:?}"));
    (stdout(&out), err)
}
