//! A `prism` run whose standard error is a terminal, so that it draws its progress bar:
//! the signal tests wait for the bar, which shows once the render has started and
//! listens for Ctrl-C, instead of sleeping a fixed time.
#![cfg(unix)]

use std::fs;
use std::io::Read;
use std::process::{Command, Stdio};

/// A render whose standard error is a terminal (so that it draws its progress bar),
/// started in `dir`; the bar's output arrives on the returned channel.
pub(crate) struct OnTerminal {
    pub(crate) child: std::process::Child,
    output: std::sync::mpsc::Receiver<String>,
    /// Everything the terminal has shown so far.
    pub(crate) seen: String,
}

impl OnTerminal {
    #[allow(unsafe_code)]
    pub(crate) fn spawn(dir: &std::path::Path, args: &[&str]) -> OnTerminal {
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
        let child = Command::new(super::bin())
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

    /// Waits until the progress bar shows work done (a share above 0 %), so that a signal
    /// finds finished tiles to write; false if the program ended first.
    pub(crate) fn wait_for_work_done(&mut self) -> bool {
        let done = |seen: &str| {
            seen.split('%').any(|before| {
                let digits: String = before
                    .chars()
                    .rev()
                    .take_while(char::is_ascii_digit)
                    .collect();
                digits.parse::<u32>().is_ok_and(|p| p > 0)
            })
        };
        while !done(&self.seen) {
            match self.output.recv() {
                Ok(more) => self.seen.push_str(&more),
                Err(_) => return false,
            }
        }
        true
    }

    /// Waits until the terminal has shown `text`; false if the program ended first.
    pub(crate) fn wait_for(&mut self, text: &str) -> bool {
        while !self.seen.contains(text) {
            match self.output.recv() {
                Ok(more) => self.seen.push_str(&more),
                Err(_) => return false,
            }
        }
        true
    }

    pub(crate) fn signal(&self, name: &str) {
        let ok = Command::new("kill")
            .args([&format!("-{name}"), &self.child.id().to_string()])
            .status()
            .unwrap()
            .success();
        assert!(ok, "kill -{name}");
    }

    /// Sends SIGINT and waits for the program to end as interrupted (exit code 130);
    /// returns everything the terminal showed.
    #[track_caller]
    pub(crate) fn interrupt(self) -> String {
        self.signal("INT");
        let (code, seen) = self.finish();
        assert_eq!(code, Some(130), "{seen}");
        seen
    }

    /// The exit code and everything the terminal showed.
    pub(crate) fn finish(mut self) -> (Option<i32>, String) {
        let code = self.child.wait().unwrap().code();
        while let Ok(more) = self.output.recv() {
            self.seen.push_str(&more);
        }
        (code, self.seen)
    }
}
