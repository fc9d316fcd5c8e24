//! How the process meets signals. Ctrl-C (SIGINT) and SIGTERM, which `timeout`, systemd
//! and batch schedulers send, both stop a render after the tiles in flight so that the
//! finished part is still written; the exit code then says which one came (130 or 143).
//! A second one stops at once. A closed standard output (`prism info … | head -1`) ends
//! the program quietly, as it does other Unix tools, and a file-size limit turns into a
//! write error instead of killing the process.

use std::sync::atomic::{AtomicBool, AtomicU8, Ordering};
use std::sync::Arc;

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
        for signal in signals.forever() {
            let code = 128 + signal as u8;
            if interrupt.cancel.swap(true, Ordering::SeqCst) {
                // A second signal: the user does not want to wait for the tiles in flight.
                eprintln!("\nprism: stopped at once on a second signal; nothing written");
                std::process::exit(code as i32);
            }
            interrupt.exit_code.store(code, Ordering::SeqCst);
        }
    });
}

#[cfg(not(unix))]
fn install(interrupt: &Interrupt) {
    let interrupt = interrupt.clone();
    let _ = ctrlc::set_handler(move || {
        if interrupt.cancel.swap(true, Ordering::SeqCst) {
            eprintln!("\nprism: stopped at once on a second Ctrl-C; nothing written");
            std::process::exit(130);
        }
    });
}
