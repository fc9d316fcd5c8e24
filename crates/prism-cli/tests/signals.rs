//! Ctrl-C as `timeout -s INT` and a terminal deliver it: to the process and its group, so
//! one keypress can arrive twice within microseconds. The render says at once that it is
//! stopping, counts the pair as one, and still writes the finished tiles.

#![cfg(unix)]

mod common;

use std::fs;
use std::io::{BufRead, BufReader, Read};
use std::process::{Command, Stdio};

#[test]
fn two_signals_at_once_are_one_ctrl_c_and_the_work_is_written() {
    let dir = common::work_dir("signals", "double-int");
    let mut child = Command::new(common::bin())
        .args(["render", "-b", "sphereflake", "-W", "1200", "-H", "1200"])
        .args(["--spp", "64", "--threads", "1", "-o", "out.pfm"])
        .current_dir(&dir)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Wait until the render has started: prism says which threads it renders with, or
    // else give it a moment (the signal is handled whenever it comes).
    std::thread::sleep(std::time::Duration::from_millis(800));
    // Two SIGINTs back to back, as `timeout` sends one to the process and one to the group.
    let pid = child.id().to_string();
    let ok = Command::new("sh")
        .args(["-c", &format!("kill -INT {pid}; kill -INT {pid}")])
        .status()
        .unwrap()
        .success();
    assert!(ok);
    let mut stderr = BufReader::new(child.stderr.take().unwrap());
    let mut first = String::new();
    // The first thing it says after the signal (skipping any note before it).
    while stderr.read_line(&mut first).unwrap() > 0 && !first.contains("stopping") {}
    assert!(
        first.contains("stopping: finishing the tiles in flight; Ctrl-C again discards"),
        "{first}"
    );
    let mut rest = String::new();
    stderr.read_to_string(&mut rest).unwrap();
    let code = child.wait().unwrap().code();
    assert_eq!(code, Some(130), "{first}{rest}");
    assert!(!rest.contains("stopped at once"), "{rest}");
    assert!(
        rest.contains("wrote the finished tiles to out.pfm"),
        "{rest}"
    );
    let bytes = fs::read(dir.join("out.pfm")).unwrap();
    assert!(bytes.starts_with(b"PF\n1200 1200\n"), "a whole-size image");
    let _ = fs::remove_dir_all(&dir);
}
