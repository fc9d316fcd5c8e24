//! Every shell block of README.md and docs/*.md runs as written, from a copy of the
//! repository's scenes (one work folder per file, the blocks in order), except the blocks
//! marked `<!-- not run: REASON -->` on the line before the fence (servers, builds,
//! benchmarks, minutes of work); and the first screen's two commands are still the ones
//! a newcomer needs. The Python blocks are run by python/tests/test_docs.py.

use crate::common;

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
    // The tiers the README's "Tests" section gives (wrapped across its lines) are the
    // commands .ci/run runs.
    let words = text.split_whitespace().collect::<Vec<_>>().join(" ");
    for tier in [
        "cargo test --release -- --ignored long_tier",
        "cargo test --release -p prism-serve --features browser --test browser",
    ] {
        assert!(
            words.contains(&format!("`{tier}`")),
            "the README gives {tier}"
        );
        assert!(ci.contains(&format!("\n{tier}\n")), ".ci/run runs {tier}");
    }
}

/// A fenced shell block of a Markdown file: where it starts, its command lines (comments
/// and blank lines removed), and the reason it is not run, if it is marked so.
struct ShellBlock {
    line: usize,
    commands: Vec<String>,
    not_run: Option<String>,
}

const NOT_RUN: &str = "<!-- not run:";

/// The ```sh (or bash, shell) blocks of `text`. A block without a language that starts
/// with a prism command is reported as an error, so that no example escapes the test.
fn shell_blocks(text: &str) -> Result<Vec<ShellBlock>, String> {
    let lines: Vec<&str> = text.lines().collect();
    let mut blocks = Vec::new();
    let mut i = 0;
    while i < lines.len() {
        let Some(lang) = lines[i].trim_start().strip_prefix("```") else {
            i += 1;
            continue;
        };
        let start = i;
        let end = (i + 1..lines.len())
            .find(|&j| lines[j].trim_start().starts_with("```"))
            .ok_or(format!("line {}: the block does not end", start + 1))?;
        let commands: Vec<String> = lines[start + 1..end]
            .iter()
            .map(|l| l.split("  #").next().unwrap_or("").trim().to_string())
            .filter(|l| !l.is_empty() && !l.starts_with('#'))
            .collect();
        let shell = matches!(lang.trim(), "sh" | "bash" | "shell");
        if lang.trim().is_empty() && commands.iter().any(|c| c.starts_with("prism ")) {
            return Err(format!(
                "line {}: a block of prism commands without a language; mark it ```sh",
                start + 1
            ));
        }
        if shell {
            let not_run = start
                .checked_sub(1)
                .and_then(|p| lines[p].trim().strip_prefix(NOT_RUN))
                .map(|r| r.trim_end_matches("-->").trim().to_string());
            if not_run.as_deref() == Some("") {
                return Err(format!("line {}: `not run` needs a reason", start + 1));
            }
            blocks.push(ShellBlock {
                line: start + 1,
                commands,
                not_run,
            });
        }
        i = end + 1;
    }
    Ok(blocks)
}

/// README.md and every docs/*.md (not the journal), by name.
fn documents() -> Vec<(String, String)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut files = vec![("README.md".to_string(), readme())];
    let mut docs: Vec<_> = fs::read_dir(root.join("docs"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .collect();
    docs.sort();
    for path in docs {
        let name = format!("docs/{}", path.file_name().unwrap().to_string_lossy());
        files.push((name, fs::read_to_string(&path).unwrap()));
    }
    files
}

#[test]
fn every_shell_block_of_the_docs_runs_as_written() {
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    let using_it = examples(&readme(), "## Using it");
    assert!(using_it.len() >= 10, "the README's examples: {using_it:?}");
    let mut ran = 0;
    for (name, text) in documents() {
        let blocks = shell_blocks(&text).unwrap_or_else(|e| panic!("{name}: {e}"));
        let dir = common::work_dir("readme", &name.replace(['/', '.'], "-"));
        copy_dir(&scenes, &dir.join("scenes"));
        for block in blocks.iter().filter(|b| b.not_run.is_none()) {
            for line in &block.commands {
                let w = words(line);
                assert_eq!(
                    w[0], "prism",
                    "{name}:{}: `{line}` is not a prism command: mark the block \
                     `{NOT_RUN} REASON -->` or run it elsewhere",
                    block.line
                );
                let args: Vec<&str> = w[1..].iter().map(String::as_str).collect();
                let out = common::prism(&dir, &args);
                let err = String::from_utf8_lossy(&out.stderr);
                assert!(
                    out.status.success(),
                    "{name}:{}: `{line}` failed ({:?}):\n{err}",
                    block.line,
                    out.status
                );
                assert!(!err.contains("warning"), "`{line}` warns:\n{err}");
                ran += 1;
            }
        }
        let _ = fs::remove_dir_all(&dir);
    }
    assert!(ran > using_it.len(), "the docs' blocks ran too: {ran}");
}

#[test]
fn blocks_are_found_and_marks_need_a_reason() {
    let text = "a\n```sh\nprism list  # all\n\n```\n<!-- not run: a server -->\n```sh\n\
                prism serve\n```\n```toml\nx = 1\n```\n";
    let blocks = shell_blocks(text).unwrap();
    assert_eq!(blocks.len(), 2);
    assert_eq!(
        (blocks[0].line, &blocks[0].commands[..]),
        (2, &["prism list".to_string()][..])
    );
    assert_eq!(blocks[1].not_run.as_deref(), Some("a server"));
    assert!(shell_blocks("<!-- not run: -->\n```sh\nprism\n```\n").is_err());
    assert!(shell_blocks("```\nprism render\n```\n").is_err());
    assert!(shell_blocks("```sh\nprism render\n").is_err());
}

#[test]
fn words_split_like_a_shell() {
    assert_eq!(
        words(r#"prism bench --methods "bvh;grid" -o x"#),
        ["prism", "bench", "--methods", "bvh;grid", "-o", "x"]
    );
}
