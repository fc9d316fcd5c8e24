//! How the process meets signals. Ctrl-C (SIGINT) and SIGTERM, which `timeout`, systemd
//! and batch schedulers send, both stop a render at once (the tiles in flight are dropped
//! a row at a time) and still write the finished tiles; the exit code then says which one came (130 or 143).
//! The first says at once that the render is stopping. A second one stops at once, but only
//! once the first has been answered (`SECOND_SIGNAL_AFTER` later): `timeout -s INT` and a
//! terminal's Ctrl-C signal the process and its group, so one keypress can arrive twice a
//! few microseconds apart, and that must not discard the work. A closed standard output (`prism info … | head -1`) ends
//! the program quietly, as it does other Unix tools, and a file-size limit turns into a
//! write error instead of killing the process.

use std::sync::atomic::{AtomicBool, AtomicU8, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// How long after the first signal a second one counts as the user's second Ctrl-C.
const SECOND_SIGNAL_AFTER: Duration = Duration::from_millis(500);

/// What the first signal says at once.
const STOPPING: &str = "\nprism: stopping: keeping the finished tiles; Ctrl-C again discards them";

/// Set by the first SIGINT or SIGTERM; a render polls it between tiles.
#[derive(Clone)]
pub(crate) struct Interrupt {
    pub cancel: Arc<AtomicBool>,
    /// 128 + the signal's number once one came; 0 before.
    exit_code: Arc<AtomicU8>,
}

impl Interrupt {
    /// The exit code for an interrupted run: 130 after SIGINT, 143 after SIGTERM.
    pub(crate) fn exit_code(&self) -> u8 {
        match self.exit_code.load(Ordering::SeqCst) {
            0 => 130,
            code => code,
        }
    }

    /// What stopped the run, for the closing message.
    pub(crate) fn cause(&self) -> &'static str {
        if self.exit_code() == 143 {
            "terminated (SIGTERM)"
        } else {
            "interrupted"
        }
    }
}

/// Restores the usual Unix behaviour of signals that Rust programs change or that would
/// kill the process without a word. Call first thing in `main`.
#[cfg(unix)]
#[allow(unsafe_code)]
pub(crate) fn restore_unix_defaults() {
    // SAFETY: signal() with SIG_DFL / SIG_IGN installs no handler code; called before any
    // thread starts, so nothing races with the change.
    unsafe {
        // Rust ignores SIGPIPE, so every print to a closed pipe would panic. With the
        // default action the process ends silently, like `cat` and `grep`.
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
        // Past a file-size limit (ulimit -f) a write should fail with an error that names
        // the file, and the temporary file be removed, rather than the process die.
        libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
    }
}

#[cfg(not(unix))]
pub fn restore_unix_defaults() {}

/// Starts listening for SIGINT and SIGTERM. If that is impossible, the signals keep their
/// default action (the process ends at once), which is still safe: outputs are written
/// atomically.
pub(crate) fn listen() -> Interrupt {
    let interrupt = Interrupt {
        cancel: Arc::new(AtomicBool::new(false)),
        exit_code: Arc::new(AtomicU8::new(0)),
    };
    install(&interrupt);
    interrupt
}

#[cfg(unix)]
fn install(interrupt: &Interrupt) {
    use signal_hook::consts::{SIGINT, SIGTERM};
    use signal_hook::iterator::Signals;
    let Ok(mut signals) = Signals::new([SIGINT, SIGTERM]) else {
        return;
    };
    let interrupt = interrupt.clone();
    std::thread::spawn(move || {
        let mut first: Option<Instant> = None;
        for signal in signals.forever() {
            let code = 128 + signal as u8;
            match first {
                None => {
                    first = Some(Instant::now());
                    interrupt.exit_code.store(code, Ordering::SeqCst);
                    // Said before the render can see the flag: a render that stops at
                    // once would otherwise say what it writes before this.
                    eprintln!("{STOPPING}");
                    interrupt.cancel.store(true, Ordering::SeqCst);
                }
                // A second signal once the first was answered: the user does not want to
                // wait for the finished tiles to be written.
                Some(at) if at.elapsed() >= SECOND_SIGNAL_AFTER => {
                    // An output being written is half a file: it goes too.
                    prism_io::output::abandon_writes();
                    eprintln!("\nprism: stopped at once on a second signal; nothing written");
                    std::process::exit(code as i32);
                }
                // The same signal delivered twice (to the process and to its group).
                Some(_) => {}
            }
        }
    });
}

/// SIGINT and SIGTERM held for a command that runs until stopped (the viewer): listening
/// starts when this is made, before the command says it is ready, so that a signal sent
/// as soon as it has said so is not met by the default action. A process started in the
/// background by a script begins with SIGINT ignored; listening takes it back, so that
/// `kill -INT` stops it as Ctrl-C does.
pub(crate) struct StopSignals {
    #[cfg(unix)]
    signals: Option<signal_hook::iterator::Signals>,
    #[cfg(not(unix))]
    signals: Option<std::sync::mpsc::Receiver<()>>,
}

impl StopSignals {
    #[cfg(unix)]
    pub(crate) fn listen() -> Self {
        use signal_hook::consts::{SIGINT, SIGTERM};
        StopSignals {
            signals: signal_hook::iterator::Signals::new([SIGINT, SIGTERM]).ok(),
        }
    }

    #[cfg(not(unix))]
    pub(crate) fn listen() -> Self {
        let (send, receive) = std::sync::mpsc::channel();
        let set = ctrlc::set_handler(move || {
            let _ = send.send(());
        });
        StopSignals {
            signals: set.is_ok().then_some(receive),
        }
    }

    /// Blocks until a signal comes and returns the exit code it calls for (130 or 143);
    /// None if the signals could not be listened to (they then keep their default action,
    /// ending the process).
    #[cfg(unix)]
    pub(crate) fn wait(mut self) -> Option<u8> {
        let signal = self.signals.as_mut()?.forever().next()?;
        Some(128 + signal as u8)
    }

    #[cfg(not(unix))]
    pub(crate) fn wait(self) -> Option<u8> {
        self.signals?.recv().ok().map(|()| 130)
    }
}

#[cfg(not(unix))]
fn install(interrupt: &Interrupt) {
    let interrupt = interrupt.clone();
    let first = std::sync::Mutex::new(None::<Instant>);
    let _ = ctrlc::set_handler(move || {
        let mut first = first.lock().unwrap_or_else(|e| e.into_inner());
        match *first {
            None => {
                *first = Some(Instant::now());
                eprintln!("{STOPPING}");
                interrupt.cancel.store(true, Ordering::SeqCst);
            }
            Some(at) if at.elapsed() >= SECOND_SIGNAL_AFTER => {
                prism_io::output::abandon_writes();
                eprintln!("\nprism: stopped at once on a second Ctrl-C; nothing written");
                std::process::exit(130);
            }
            Some(_) => {}
        }
    });
}
