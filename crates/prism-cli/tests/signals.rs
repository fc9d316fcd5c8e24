//! Ctrl-C as `timeout -s INT` and a terminal deliver it: to the process and its group, so
//! one keypress can arrive twice within microseconds. The render says at once that it is
//! stopping, counts the pair as one, and still writes the rows its finished tiles reached.
//! A Ctrl-C answers within a tile, at any size: it stops the tiles in flight and writes
//! only what was reached, rather than a full-size image of black.

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
    assert!(rest.contains("prism: wrote out.pfm"), "{rest}");
    let bytes = fs::read(dir.join("out.pfm")).unwrap();
    assert!(bytes.starts_with(b"PF\n1200 "), "the image's full width");
    let _ = fs::remove_dir_all(&dir);
}

/// A render whose standard error is a terminal (so that it draws its progress bar),
/// started in `dir`; the bar's output arrives on the returned channel.
struct OnTerminal {
    child: std::process::Child,
    output: std::sync::mpsc::Receiver<String>,
    seen: String,
}

impl OnTerminal {
    #[allow(unsafe_code)]
    fn spawn(dir: &std::path::Path, args: &[&str]) -> OnTerminal {
        use std::os::fd::{FromRawFd, OwnedFd};
        let (mut leader, mut follower) = (0, 0);
        let size = libc::winsize {
            ws_row: 24,
            ws_col: 100,
            ws_xpixel: 0,
            ws_ypixel: 0,
        };
        // SAFETY: openpty writes two new descriptors into the integers it is given, which
        // become owned here and nowhere else.
        let opened = unsafe {
            libc::openpty(
                &mut leader,
                &mut follower,
                std::ptr::null_mut(),
                std::ptr::null(),
                &size,
            )
        };
        assert_eq!(opened, 0, "openpty");
        let (leader, follower) =
            unsafe { (OwnedFd::from_raw_fd(leader), OwnedFd::from_raw_fd(follower)) };
        let child = Command::new(common::bin())
            .args(args)
            .current_dir(dir)
            .stdout(Stdio::null())
            .stderr(Stdio::from(follower))
            .spawn()
            .unwrap();
        let (send, output) = std::sync::mpsc::channel();
        let mut leader = fs::File::from(leader);
        std::thread::spawn(move || {
            let mut buffer = [0u8; 4096];
            // Ends with an error once the child has exited and the terminal is closed.
            while let Ok(n @ 1..) = leader.read(&mut buffer) {
                if send
                    .send(String::from_utf8_lossy(&buffer[..n]).into_owned())
                    .is_err()
                {
                    break;
                }
            }
        });
        OnTerminal {
            child,
            output,
            seen: String::new(),
        }
    }

    /// Waits until the terminal has shown `text`; false if the program ended first.
    fn wait_for(&mut self, text: &str) -> bool {
        while !self.seen.contains(text) {
            match self.output.recv() {
                Ok(more) => self.seen.push_str(&more),
                Err(_) => return false,
            }
        }
        true
    }

    fn signal(&self, name: &str) {
        let ok = Command::new("kill")
            .args([&format!("-{name}"), &self.child.id().to_string()])
            .status()
            .unwrap()
            .success();
        assert!(ok, "kill -{name}");
    }

    /// The exit code and everything the terminal showed.
    fn finish(mut self) -> (Option<i32>, String) {
        let code = self.child.wait().unwrap().code();
        while let Ok(more) = self.output.recv() {
            self.seen.push_str(&more);
        }
        (code, self.seen)
    }
}

#[test]
fn ctrl_c_stops_inside_a_large_tile() {
    // One tile of the whole image on one thread, with packets and without: the tile takes
    // far longer than a Ctrl-C may wait, so the render stops inside it, with no tile
    // finished and nothing written.
    for (name, packets) in [("packets", None), ("single-rays", Some("--no-packets"))] {
        let dir = common::work_dir("signals", &format!("large-tile-{name}"));
        let mut args = vec![
            "render",
            "-b",
            "sphereflake",
            "-W",
            "2048",
            "-H",
            "2048",
            "--spp",
            "64",
            "--tile-size",
            "2048",
            "--threads",
            "1",
            "-o",
            "out.png",
        ];
        args.extend(packets);
        let mut render = OnTerminal::spawn(&dir, &args);
        assert!(render.wait_for("%"), "no progress bar: {}", render.seen);
        render.signal("INT");
        let (code, seen) = render.finish();
        assert_eq!(code, Some(130), "{seen}");
        assert!(
            seen.contains("stopping: finishing the tiles in flight"),
            "{seen}"
        );
        assert!(
            seen.contains("no tile was finished: the image is not written"),
            "{seen}"
        );
        assert!(!dir.join("out.png").exists(), "{seen}");
        let _ = fs::remove_dir_all(&dir);
    }
}

#[test]
fn ctrl_c_at_the_start_of_a_huge_render_writes_only_the_rows_reached() {
    let dir = common::work_dir("signals", "huge");
    let mut render = OnTerminal::spawn(
        &dir,
        &[
            "render",
            "-W",
            "20000",
            "-H",
            "20000",
            "--threads",
            "2",
            "-o",
            "out.png",
        ],
    );
    assert!(render.wait_for("%"), "no progress bar: {}", render.seen);
    render.signal("INT");
    let (code, seen) = render.finish();
    assert_eq!(code, Some(130), "{seen}");
    assert!(
        seen.contains("stopping: finishing the tiles in flight"),
        "{seen}"
    );
    // What is written is said before it is written, and is a band from the top.
    match seen.find("writing the ") {
        Some(at) => {
            assert!(seen[at..].contains("rows of 20000"), "{seen}");
            let (width, height) = image::image_dimensions(dir.join("out.png")).unwrap();
            assert_eq!(width, 20000);
            assert!(height < 20000, "only the rows reached, not {height}");
            assert!(seen.contains("prism: wrote out.png"), "{seen}");
        }
        None => {
            assert!(seen.contains("no tile was finished"), "{seen}");
            assert!(!dir.join("out.png").exists());
        }
    }
    let _ = fs::remove_dir_all(&dir);
}

/// `prism serve` started as a script starts it, in the background of a shell without job
/// control (which starts it with SIGINT ignored), ends on SIGINT and on SIGTERM, saying so.
#[test]
fn serve_started_in_the_background_stops_on_sigint_and_sigterm() {
    for (signal, code, said) in [
        ("INT", 130, "prism: interrupted: stopping the viewer"),
        (
            "TERM",
            143,
            "prism: terminated (SIGTERM): stopping the viewer",
        ),
    ] {
        let dir = common::work_dir("signals", &format!("serve-{signal}"));
        // The shell prints the server's process id, waits for it and prints its exit code.
        let script = "\"$0\" serve -b cornell --port 0 -W 64 -H 36 2>err.txt & \
                      echo \"pid $!\"; wait $!; echo \"exit $?\"";
        let mut shell = Command::new("sh")
            .args(["-c", script])
            .arg(common::bin())
            .current_dir(&dir)
            .stdout(Stdio::piped())
            .spawn()
            .unwrap();
        let mut stdout = BufReader::new(shell.stdout.take().unwrap());
        let mut lines = Vec::new();
        // Wait for the pid, then for the address the server prints once it listens.
        while !lines
            .iter()
            .any(|l: &String| l.starts_with("prism: viewing"))
        {
            let mut line = String::new();
            assert!(stdout.read_line(&mut line).unwrap() > 0, "{lines:?}");
            lines.push(line);
        }
        let pid = lines
            .iter()
            .find_map(|l| l.strip_prefix("pid "))
            .unwrap()
            .trim()
            .to_string();
        let ok = Command::new("kill")
            .args([&format!("-{signal}"), &pid])
            .status()
            .unwrap()
            .success();
        assert!(ok, "kill -{signal} {pid}");
        let mut rest = String::new();
        stdout.read_to_string(&mut rest).unwrap();
        shell.wait().unwrap();
        assert_eq!(rest.trim(), format!("exit {code}"), "{lines:?}");
        let err = fs::read_to_string(dir.join("err.txt")).unwrap();
        assert!(err.contains(said), "{err}");
        let _ = fs::remove_dir_all(&dir);
    }
}
