//! ARCHITECTURE.md is the map of the code, so it must stay true: every source module of
//! every crate is named in that crate's section, every test, example and bench file is
//! named, every module imports only the modules that its crate's documented dependency
//! order puts before it, and every crate depends only on the crates its order puts before
//! it. Beside the map, every file in a crate's tests/ must be part of a test binary, since
//! a file that no binary declares would silently never run. The checks run from
//! crates/prism, the first crate, but cover the whole workspace.

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

/// The crates of the workspace, in their dependency order, with their folders; each has a
/// section of ARCHITECTURE.md whose heading names its `FOLDER/src`.
const CRATE_DIRS: [(&str, &str); 6] = [
    ("prism", "crates/prism"),
    ("prism-io", "crates/prism-io"),
    ("prism-lab", "crates/prism-lab"),
    ("prism-serve", "crates/prism-serve"),
    ("prism-python", "python"),
    ("prism-cli", "crates/prism-cli"),
];

/// The crates' names, in their dependency order.
const CRATES: [&str; 6] = [
    "prism",
    "prism-io",
    "prism-lab",
    "prism-serve",
    "prism-python",
    "prism-cli",
];

/// The section of ARCHITECTURE.md whose `## ` heading contains `marker`.
fn section(doc: &str, marker: &str) -> String {
    doc.split("\n## ")
        .find(|s| s.lines().next().is_some_and(|h| h.contains(marker)))
        .unwrap_or_else(|| panic!("ARCHITECTURE.md has no section headed with {marker}"))
        .to_string()
}

/// The files (and folders) below `dir` that `doc` does not name.
fn unnamed(doc: &str, dir: &str) -> Vec<String> {
    let mut files = Vec::new();
    entries(Path::new(dir), "", &mut files);
    files
        .into_iter()
        .filter(|(path, _)| !path.ends_with("mod.rs") && path != "lib.rs")
        .filter(|(path, _)| !path.starts_with("data"))
        .filter(|(path, _)| {
            let stem = path.rsplit('/').next().unwrap().trim_end_matches(".rs");
            !named(doc, stem)
        })
        .map(|(path, is_dir)| if is_dir { format!("{path}/") } else { path })
        .collect()
}

/// The folder of crate `name`, from the workspace's root (`crates/NAME`, or `python`).
fn folder(name: &str) -> &'static str {
    CRATE_DIRS
        .iter()
        .find(|(n, _)| *n == name)
        .unwrap_or_else(|| panic!("{name} is not a crate of the workspace"))
        .1
}

/// `FOLDER/sub` of crate `name` as a path from crates/prism, where the tests run.
fn crate_dir(name: &str, sub: &str) -> String {
    format!("../../{}/{sub}", folder(name))
}

#[test]
fn every_module_is_named_in_its_crates_section() {
    let doc = architecture();
    let mut missing = Vec::new();
    for name in CRATES {
        let part = section(&doc, &format!("`{}/src`", folder(name)));
        let dir = crate_dir(name, "src");
        missing.extend(
            unnamed(&part, &dir)
                .into_iter()
                .map(|m| format!("{dir}: {m}")),
        );
    }
    assert!(
        missing.is_empty(),
        "ARCHITECTURE.md does not name these modules in their crate's section: {missing:?}"
    );
}

/// The folders of the workspace's members, as paths from crates/prism: the crates of
/// `CRATE_DIRS` and those that hold only tests or benches (crates/prism-benches).
fn member_dirs() -> Vec<String> {
    let manifest = fs::read_to_string("../../Cargo.toml").expect("the workspace's Cargo.toml");
    let list = manifest
        .split("\nmembers = [")
        .nth(1)
        .and_then(|rest| rest.split(']').next())
        .expect("the workspace's Cargo.toml lists its members");
    list.split(',')
        .map(|m| m.trim().trim_matches('"'))
        .filter(|m| !m.is_empty())
        .map(|m| format!("../../{m}"))
        .collect()
}

#[test]
fn every_test_example_and_bench_file_is_named() {
    let doc = architecture();
    let mut missing = Vec::new();
    let members = member_dirs();
    for (_, dir) in CRATE_DIRS {
        assert!(
            members.contains(&format!("../../{dir}")),
            "the workspace's members {members:?} leave out {dir}"
        );
    }
    for member in members {
        for sub in ["tests", "examples", "benches"] {
            let dir = format!("{member}/{sub}");
            if Path::new(&dir).is_dir() {
                missing.extend(
                    unnamed(&doc, &dir)
                        .into_iter()
                        .map(|m| format!("{dir}: {m}")),
                );
            }
        }
    }
    assert!(
        missing.is_empty(),
        "ARCHITECTURE.md does not name these files: {missing:?}"
    );
}

/// The `[[test]]` targets of a member's Cargo.toml: their root files, from the member's
/// folder (`path`, or cargo's default `tests/NAME.rs`).
fn test_roots(manifest: &str) -> Vec<String> {
    manifest
        .split("\n[[test]]")
        .skip(1)
        .map(|target| target.split("\n[").next().unwrap_or(""))
        .map(|target| {
            let value = |key: &str| {
                target.lines().find_map(|l| {
                    let (k, v) = l.split_once('=')?;
                    (k.trim() == key).then(|| v.trim().trim_matches('"').to_string())
                })
            };
            value("path").unwrap_or_else(|| format!("tests/{}.rs", value("name").unwrap()))
        })
        .collect()
}

/// The modules a test root declares from files (`mod NAME;` on a line of its own).
fn declared_modules(root: &str) -> BTreeSet<String> {
    root.lines()
        .filter_map(|l| l.trim().strip_prefix("mod ")?.strip_suffix(';'))
        .map(|name| name.trim().to_string())
        .collect()
}

#[test]
fn every_test_file_is_part_of_a_test_binary() {
    let mut orphans = Vec::new();
    let mut merged = 0;
    for member in member_dirs() {
        let dir = Path::new(&member).join("tests");
        let manifest = fs::read_to_string(Path::new(&member).join("Cargo.toml")).unwrap();
        // Without `autotests = false`, cargo makes every tests/*.rs a test binary.
        if !dir.is_dir() || !manifest.contains("\nautotests = false") {
            continue;
        }
        merged += 1;
        let roots = test_roots(&manifest);
        let mut declared = BTreeSet::new();
        for root in &roots {
            let text = fs::read_to_string(Path::new(&member).join(root))
                .unwrap_or_else(|e| panic!("{member}/{root}, a [[test]] of Cargo.toml: {e}"));
            declared.extend(declared_modules(&text));
        }
        let mut files: Vec<_> = fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().to_string())
            .filter(|name| name.ends_with(".rs"))
            .collect();
        files.sort();
        for file in files {
            let stem = file.trim_end_matches(".rs");
            let is_root = roots.iter().any(|r| *r == format!("tests/{file}"));
            if !is_root && !declared.contains(stem) {
                let root = roots.first().map_or("a [[test]] root", String::as_str);
                let folder = member.trim_start_matches("../../");
                orphans.push(format!(
                    "{folder}/tests/{file} is in no test binary, so its tests never run: \
                     declare it with `mod {stem};` in {folder}/{root}"
                ));
            }
        }
    }
    assert!(
        merged >= 4,
        "the engine, prism-io, prism-lab and the CLI build their suites as one binary each"
    );
    assert!(
        orphans.is_empty(),
        "{} (ARCHITECTURE.md, \"How to add a test suite\")",
        orphans.join("; ")
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
        // The first backticked path of the row, relative to crates/, so naming its crate.
        let first = place
            .split('`')
            .nth(1)
            .unwrap_or_else(|| panic!("{concept}: no file named"));
        assert!(
            CRATES
                .iter()
                .any(|c| first.starts_with(&format!("{c}/src/"))),
            "{concept}: {first} should start with the crate, as in prism/src/…"
        );
        assert!(
            Path::new("..").join(first).exists(),
            "{concept}: crates/{first} does not exist"
        );
        checked += 1;
    }
    assert!(checked >= 15, "only {checked} concepts point at files");
    // The lecture items the table must name, built or (honestly) "not yet".
    for concept in ["ray packets", "beam tracing", "path tracing"] {
        assert!(
            table
                .lines()
                .any(|l| l.starts_with(&format!("| {concept} |"))),
            "the concept table has no row for {concept} (a file, or \"not yet\")"
        );
    }
}

/// A dependency order as ARCHITECTURE.md writes it, on the line that starts with
/// `label:`: levels separated by `←`, names on one level by `/`.
fn documented_order(label: &str) -> Vec<Vec<String>> {
    let doc = architecture();
    let line = doc
        .lines()
        .find_map(|l| l.trim_start().strip_prefix(&format!("{label}: ")))
        .unwrap_or_else(|| panic!("ARCHITECTURE.md has no dependency order line `{label}:`"));
    line.split('←')
        .map(|level| {
            level
                .split('/')
                .map(|m| m.trim().trim_matches('`').to_string())
                .collect()
        })
        .collect()
}

/// The `crate::X` modules that the files of module `module` of the crate whose sources
/// are in `src` mention.
fn imports_of(src: &Path, module: &str) -> BTreeSet<String> {
    let mut files = Vec::new();
    let dir = src.join(module);
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
        let text = fs::read_to_string(src.join(&path))
            .unwrap_or_else(|e| panic!("{}: {e}", src.join(&path).display()));
        for part in text.split("crate::").skip(1) {
            let name: String = part
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                .collect();
            // Only modules count: `$crate::some_macro!` names no module.
            if !name.is_empty() && name != module && is_module(src, &name) {
                out.insert(name);
            }
        }
    }
    out
}

/// Whether `name` is a top module of the crate whose sources are in `src`.
fn is_module(src: &Path, name: &str) -> bool {
    src.join(name).is_dir() || src.join(format!("{name}.rs")).is_file()
}

/// The top modules of a crate: the folders and files beside its lib.rs.
fn top_modules(src: &Path) -> BTreeSet<String> {
    fs::read_dir(src)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().to_string())
        .filter(|n| n != "lib.rs" && n != "main.rs")
        .map(|n| n.trim_end_matches(".rs").to_string())
        .collect()
}

#[test]
fn modules_import_only_what_the_order_puts_before_them() {
    let mut wrong = Vec::new();
    for name in CRATES {
        let order = documented_order(name);
        let src = Path::new(&crate_dir(name, "src")).to_path_buf();
        let level = |m: &str| order.iter().position(|l| l.iter().any(|x| x == m));
        for module in top_modules(&src) {
            if level(&module).is_none() {
                wrong.push(format!("{name}: {module} is not in the order"));
            }
        }
        for (i, modules) in order.iter().enumerate() {
            for module in modules {
                for import in imports_of(&src, module) {
                    match level(&import) {
                        Some(j) if j < i => {}
                        _ => wrong.push(format!("{name}: {module} imports {import}")),
                    }
                }
            }
        }
    }
    assert!(
        documented_order("prism").len() >= 8,
        "{:?}",
        documented_order("prism")
    );
    assert!(
        wrong.is_empty(),
        "imports against ARCHITECTURE.md's dependency order: {wrong:?}"
    );
}

/// The workspace crates a crate's Cargo.toml lists under `[dependencies]` (not the
/// dev-dependencies: test fixtures may come from any crate).
fn crate_dependencies(name: &str) -> Vec<String> {
    let manifest = fs::read_to_string(crate_dir(name, "Cargo.toml")).unwrap();
    let deps = manifest
        .split("\n[dependencies]")
        .nth(1)
        .and_then(|rest| rest.split("\n[").next())
        .unwrap_or("");
    deps.lines()
        .filter_map(|l| l.split_once(" = { path = "))
        .map(|(dep, _)| dep.trim().to_string())
        .collect()
}

#[test]
fn crates_depend_only_on_crates_before_them() {
    let order = documented_order("crates");
    let level = |m: &str| order.iter().position(|l| l.iter().any(|x| x == m));
    let mut wrong = Vec::new();
    for name in CRATES {
        let i = level(name).unwrap_or_else(|| panic!("{name} is not in the crate order"));
        for dep in crate_dependencies(name) {
            match level(&dep) {
                Some(j) if j < i => {}
                _ => wrong.push(format!("{name} depends on {dep}")),
            }
        }
    }
    assert!(
        crate_dependencies("prism-cli").len() == 4,
        "the CLI should build on all four libraries"
    );
    assert!(
        wrong.is_empty(),
        "crate dependencies against ARCHITECTURE.md's order: {wrong:?}"
    );
}
