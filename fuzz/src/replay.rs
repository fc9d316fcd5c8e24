//! The main function of every target binary: AFL++'s persistent loop when built with the
//! `afl` feature (`cargo afl build`), otherwise a replayer that runs the target on the
//! files named on the command line, to reproduce and debug a finding without AFL.

use crate::targets::Target;

/// Runs `target` on AFL's inputs, or on each file given as an argument.
#[cfg(feature = "afl")]
pub fn run(target: Target) {
    afl::fuzz!(|data: &[u8]| {
        target(data);
    });
}

/// Runs `target` on AFL's inputs, or on each file given as an argument.
#[cfg(not(feature = "afl"))]
pub fn run(target: Target) {
    let files: Vec<_> = std::env::args_os().skip(1).collect();
    if files.is_empty() {
        eprintln!("usage: TARGET FILE…  (built without the `afl` feature, a target replays files)");
        std::process::exit(2);
    }
    for file in files {
        let data = std::fs::read(&file).unwrap_or_else(|e| {
            eprintln!("cannot read {}: {e}", file.to_string_lossy());
            std::process::exit(2);
        });
        let outcome = target(&data);
        println!(
            "{} ({} bytes): {outcome:?}",
            file.to_string_lossy(),
            data.len()
        );
    }
}
