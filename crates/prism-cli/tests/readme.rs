//! The README's "Using it" examples run as written, from a copy of the repository's
//! scenes, and the first screen's two commands are still the ones a newcomer needs.

mod common;

use std::fs;
use std::path::Path;

fn readme() -> String {
    fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("../../README.md")).unwrap()
}

/// The shell lines of the first ```sh block after `heading`, comments removed.
fn examples(text: &str, heading: &str) -> Vec<String> {
    let section = &text[text.find(heading).expect("the heading is there")..];
    let start = section.find("```sh\n").expect("a sh block") + 6;
    let end = start + section[start..].find("```").expect("the block ends");
    section[start..end]
        .lines()
        .map(|l| l.split("  #").next().unwrap_or("").trim().to_string())
        .filter(|l| !l.is_empty())
        .collect()
}

/// Splits a command line into words, honouring double quotes.
fn words(line: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut word = String::new();
    let mut quoted = false;
    let mut any = false;
    for c in line.chars() {
        match c {
            '"' => {
                quoted = !quoted;
                any = true;
            }
            c if c.is_whitespace() && !quoted => {
                if any {
                    out.push(std::mem::take(&mut word));
                    any = false;
                }
            }
            c => {
                word.push(c);
                any = true;
            }
        }
    }
    if any {
        out.push(word);
    }
    out
}

fn copy_dir(from: &Path, to: &Path) {
    fs::create_dir_all(to).unwrap();
    for entry in fs::read_dir(from).unwrap() {
        let entry = entry.unwrap();
        let target = to.join(entry.file_name());
        if entry.file_type().unwrap().is_dir() {
            copy_dir(&entry.path(), &target);
        } else {
            fs::copy(entry.path(), &target).unwrap();
        }
    }
}

#[test]
fn the_first_screen_gives_the_render_and_test_commands() {
    let text = readme();
    let first_screen: String = text.lines().take(24).collect::<Vec<_>>().join("\n");
    assert!(
        first_screen.contains("cargo run --release -- render"),
        "{first_screen}"
    );
    assert!(
        first_screen.contains("cargo test --release"),
        "{first_screen}"
    );
    let ci =
        fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("../../.ci/run")).unwrap();
    assert!(
        ci.contains("cargo test --release"),
        ".ci/run calls the README's test command"
    );
    assert!(
        first_screen.contains("python/test.sh") && ci.contains("\npython/test.sh"),
        ".ci/run calls the README's Python test command"
    );
}

#[test]
fn every_using_it_example_runs_as_written() {
    let dir = common::work_dir("readme", "examples");
    copy_dir(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes"),
        &dir.join("scenes"),
    );
    let lines = examples(&readme(), "## Using it");
    assert!(lines.len() >= 10, "the block has the examples: {lines:?}");
    for line in &lines {
        let w = words(line);
        assert_eq!(w[0], "prism", "an example runs prism: {line}");
        let args: Vec<&str> = w[1..].iter().map(String::as_str).collect();
        let out = common::prism(&dir, &args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            out.status.success(),
            "README example `{line}` failed ({:?}):\n{err}",
            out.status
        );
        assert!(!err.contains("warning"), "`{line}` warns:\n{err}");
    }
}

#[test]
fn words_split_like_a_shell() {
    assert_eq!(
        words(r#"prism bench --methods "bvh;grid" -o x"#),
        ["prism", "bench", "--methods", "bvh;grid", "-o", "x"]
    );
}
