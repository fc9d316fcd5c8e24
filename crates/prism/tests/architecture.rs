//! ARCHITECTURE.md is the map of the code, so it must stay true: every source module and
//! every test file is named in it, and every module imports only the modules that its
//! documented dependency order puts before it.

use std::collections::BTreeSet;
use std::fs;
use std::path::Path;

fn architecture() -> String {
    fs::read_to_string("../../ARCHITECTURE.md").expect("ARCHITECTURE.md beside the workspace")
}

/// The `.rs` files (and folders) below `dir`, as paths relative to it.
fn entries(dir: &Path, prefix: &str, out: &mut Vec<(String, bool)>) {
    let mut list: Vec<_> = fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .collect();
    list.sort();
    for path in list {
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        if path.is_dir() {
            out.push((format!("{prefix}{name}"), true));
            entries(&path, &format!("{prefix}{name}/"), out);
        } else if name.ends_with(".rs") {
            out.push((format!("{prefix}{name}"), false));
        }
    }
}

/// Whether the document names `stem` in backticks, alone or as `stem.rs` / `stem/`, or as
/// the last part of a backticked path (`integrator/shadow.rs`).
fn named(doc: &str, stem: &str) -> bool {
    doc.split('`').skip(1).step_by(2).any(|code| {
        let last = code.trim_end_matches('/').rsplit('/').next().unwrap_or("");
        last == stem || last == format!("{stem}.rs")
    })
}

fn unnamed(dir: &str) -> Vec<String> {
    let doc = architecture();
    let mut files = Vec::new();
    entries(Path::new(dir), "", &mut files);
    files
        .into_iter()
        .filter(|(path, _)| !path.ends_with("mod.rs") && path != "lib.rs")
        .filter(|(path, _)| !path.starts_with("data"))
        .filter(|(path, _)| {
            let stem = path.rsplit('/').next().unwrap().trim_end_matches(".rs");
            !named(&doc, stem)
        })
        .map(|(path, is_dir)| if is_dir { format!("{path}/") } else { path })
        .collect()
}

#[test]
fn every_engine_module_is_named() {
    let missing = unnamed("src");
    assert!(
        missing.is_empty(),
        "ARCHITECTURE.md does not name these modules of crates/prism/src: {missing:?}"
    );
}

#[test]
fn every_test_example_and_bench_file_is_named() {
    let mut missing = Vec::new();
    for dir in [
        "tests",
        "examples",
        "benches",
        "../prism-cli/src",
        "../prism-cli/tests",
    ] {
        missing.extend(unnamed(dir).into_iter().map(|m| format!("{dir}: {m}")));
    }
    assert!(
        missing.is_empty(),
        "ARCHITECTURE.md does not name these files: {missing:?}"
    );
}

#[test]
fn the_concept_table_points_at_files_that_exist() {
    let doc = architecture();
    let table = doc
        .split("## The lecture's concepts, file by file")
        .nth(1)
        .and_then(|rest| rest.split("\n## ").next())
        .expect("ARCHITECTURE.md opens with the concept table");
    let mut checked = 0;
    for row in table
        .lines()
        .filter(|l| l.starts_with("| ") && !l.starts_with("| concept"))
    {
        let cells: Vec<&str> = row.split('|').map(str::trim).collect();
        let (concept, place) = (cells[1], cells[2]);
        if place.starts_with("not yet") {
            continue;
        }
        // The first backticked path of the row, relative to crates/prism/src.
        let first = place
            .split('`')
            .nth(1)
            .unwrap_or_else(|| panic!("{concept}: no file named"));
        assert!(
            Path::new("src").join(first).exists(),
            "{concept}: src/{first} does not exist"
        );
        checked += 1;
    }
    assert!(checked >= 15, "only {checked} concepts point at files");
    for concept in ["ray packets", "beam tracing", "path tracing"] {
        assert!(
            table
                .lines()
                .any(|l| l.starts_with(&format!("| {concept} | not yet"))),
            "the concept table should say honestly that {concept} is not there yet"
        );
    }
}

/// The dependency order as ARCHITECTURE.md writes it: levels separated by `←`, modules on
/// one level by `/`.
fn documented_order() -> Vec<Vec<String>> {
    let doc = architecture();
    let line = doc
        .lines()
        .find(|l| l.trim_start().starts_with("`math` ←"))
        .expect("the dependency order line");
    line.split('←')
        .map(|level| {
            level
                .split('/')
                .map(|m| m.trim().trim_matches('`').to_string())
                .collect()
        })
        .collect()
}

/// The `crate::X` modules that the files of module `module` mention.
fn imports_of(module: &str) -> BTreeSet<String> {
    let mut files = Vec::new();
    let dir = Path::new("src").join(module);
    if dir.is_dir() {
        entries(&dir, "", &mut files);
        files.retain(|(_, is_dir)| !is_dir);
        files = files
            .into_iter()
            .map(|(p, d)| (format!("{module}/{p}"), d))
            .collect();
    } else {
        files.push((format!("{module}.rs"), false));
    }
    let mut out = BTreeSet::new();
    for (path, _) in files {
        let text = fs::read_to_string(Path::new("src").join(&path)).unwrap();
        for part in text.split("crate::").skip(1) {
            let name: String = part
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                .collect();
            if !name.is_empty() && name != module {
                out.insert(name);
            }
        }
    }
    out
}

#[test]
fn modules_import_only_what_the_order_puts_before_them() {
    let order = documented_order();
    assert!(order.len() >= 8, "{order:?}");
    // Outside the order by design (see ARCHITECTURE.md): the settings everyone reads, and
    // the macros every module may use.
    let free = ["options", "preset", "kinds"];
    let level = |m: &str| order.iter().position(|l| l.iter().any(|x| x == m));
    let mut wrong = Vec::new();
    for (i, modules) in order.iter().enumerate() {
        for module in modules {
            for import in imports_of(module) {
                if free.contains(&import.as_str()) {
                    continue;
                }
                match level(&import) {
                    Some(j) if j < i => {}
                    _ => wrong.push(format!("{module} imports {import}")),
                }
            }
        }
    }
    assert!(
        wrong.is_empty(),
        "imports against ARCHITECTURE.md's dependency order: {wrong:?}"
    );
}
