//! Every target over its committed corpus (fuzz/corpus/<target>/), without AFL: keeps the
//! targets compiling and the seeds (and any findings added to them) passing.

use std::path::Path;

#[test]
fn every_target_survives_its_corpus() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("corpus");
    for &(name, target) in prism_fuzz::targets::ALL {
        let dir = root.join(name);
        let mut files: Vec<_> = std::fs::read_dir(&dir)
            .unwrap_or_else(|e| panic!("corpus {}: {e}", dir.display()))
            .map(|entry| entry.expect("corpus entry").path())
            .collect();
        files.sort();
        assert!(!files.is_empty(), "corpus {} is empty", dir.display());
        for file in files {
            let data = std::fs::read(&file).expect("corpus file");
            eprintln!("{name}: {}", file.display());
            let _ = target(&data);
        }
    }
}

#[test]
fn every_target_survives_trivial_inputs() {
    for &(_, target) in prism_fuzz::targets::ALL {
        for data in [&b""[..], b"\0", b"glTF", b"\xff\xfe", b"{}", b"[[objects]]"] {
            let _ = target(data);
        }
    }
}
