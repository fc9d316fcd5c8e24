//! The fuzz corpora (fuzz/corpus/TARGET) replayed through the fuzz targets' own bodies, so
//! that `cargo test` (and with it `.ci/run`) runs every seed as AFL++ would, without AFL:
//! no input may panic, a parsed scene must validate and trace a few pixels, and a refused
//! one must say what is wrong and where (line and column from 1, within the text). Each
//! seed is also replayed cut short at a few lengths, which the parsers must refuse (or
//! accept) in the same way.
//!
//! The target bodies are fuzz/src/targets.rs and exercise.rs themselves, compiled into this
//! suite with `#[path]`: one copy, which the fuzz crate (outside the workspace, it needs
//! AFL) and this suite both build.

#[allow(unreachable_pub, dead_code)] // the fuzz crate's public API, seen from a test
#[path = "../../../fuzz/src/exercise.rs"]
mod exercise;
#[allow(unreachable_pub, dead_code)]
#[path = "../../../fuzz/src/targets.rs"]
mod targets;

use exercise::Outcome;
use std::path::Path;

/// fuzz/data, the folder the targets parse their inputs as if they were in.
const DATA: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fuzz/data");

/// Every corpus file of a target, sorted, with its bytes.
fn corpus(target: &str) -> Vec<(String, Vec<u8>)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fuzz/corpus")
        .join(target);
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    files
        .into_iter()
        .map(|p| {
            let name = p.file_name().unwrap().to_string_lossy().to_string();
            (name, std::fs::read(&p).unwrap())
        })
        .collect()
}

/// An error message must be a sentence about the input, naming the file it was parsed as.
fn assert_clear(target: &str, what: &str, outcome: &Outcome) {
    if let Outcome::Rejected(message) = outcome {
        assert!(
            message.contains("input.") && message.len() > "input.xyz: ".len() + 8,
            "{target} {what}: the error should name the file and say what is wrong: {message}"
        );
    }
}

#[test]
fn every_seed_of_every_target_replays_cleanly() {
    let mut seeds = 0;
    for &(target, body) in targets::ALL {
        let files = corpus(target);
        assert!(!files.is_empty(), "fuzz/corpus/{target} holds no seeds");
        for (name, bytes) in files {
            let outcome = body(&bytes);
            assert_clear(target, &name, &outcome);
            seeds += 1;
        }
    }
    // 23 seeds are committed today; fewer means a corpus folder went missing.
    assert!(seeds >= 20, "only {seeds} seeds replayed");
}

#[test]
fn seeds_cut_short_are_refused_clearly_or_parsed() {
    let mut refused = 0;
    for &(target, body) in targets::ALL {
        for (name, bytes) in corpus(target) {
            for cut in [
                1,
                4,
                3 * bytes.len() / 8,
                bytes.len() / 2,
                7 * bytes.len() / 8,
            ] {
                let cut = cut.min(bytes.len().saturating_sub(1));
                let outcome = body(&bytes[..cut]);
                assert_clear(target, &format!("{name} cut at {cut} bytes"), &outcome);
                refused += usize::from(matches!(outcome, Outcome::Rejected(_)));
            }
        }
    }
    // Most truncations break a file; if none were refused, the targets stopped checking.
    assert!(refused >= 30, "only {refused} truncated seeds were refused");
}
