//! The fuzz target bodies: bytes in, a parser run, and the scene it returns (if any)
//! checked and traced. A panic anywhere is a finding.

use super::exercise::{self, Outcome};
use prism_io::scene::mesh_file::Materials;
use std::path::Path;

/// The folder the inputs are parsed as if they were in: fuzz/data, which holds a material
/// library (`lib.mtl`) and an image (`card.png`) for inputs to name, and nothing else, so a
/// run depends on the input alone. The module that declares these targets says where it is
/// (`super::DATA`, beside `super::exercise`): this crate's root, and prism-io's
/// `fuzz_corpora` suite, a module of that crate's test binary, which replays the corpora
/// through these same bodies.
const BASE: &str = super::DATA;

/// Text formats see the bytes as UTF-8 with bad sequences replaced, so that every input
/// reaches the parser; the loaders reject non-UTF-8 files before parsing.
fn text(data: &[u8]) -> std::borrow::Cow<'_, str> {
    String::from_utf8_lossy(data)
}

/// NFF text (`prism_io::scene::nff::parse`).
pub fn nff(data: &[u8]) -> Outcome {
    let text = text(data);
    let path = format!("{BASE}/input.nff");
    exercise::outcome(prism_io::scene::nff::parse(&text, &path), Some(&text))
}

/// TOML scene text (`prism_io::scene::parse_toml`).
pub fn toml(data: &[u8]) -> Outcome {
    let text = text(data);
    let path = Path::new(BASE).join("input.toml");
    exercise::outcome(prism_io::scene::parse_toml(&text, &path), Some(&text))
}

/// glTF JSON (`prism_io::scene::parse_gltf`); the corpus holds .gltf documents.
pub fn gltf(data: &[u8]) -> Outcome {
    let path = Path::new(BASE).join("input.gltf");
    exercise::outcome(prism_io::scene::parse_gltf(data, &path), None)
}

/// Binary glTF containers, the same entry point as `gltf` with a corpus of .glb files
/// (their headers, chunk lengths and BIN data are what the fuzzer mutates).
pub fn glb(data: &[u8]) -> Outcome {
    let path = Path::new(BASE).join("input.glb");
    exercise::outcome(prism_io::scene::parse_gltf(data, &path), None)
}

/// Wavefront OBJ text (`prism_io::scene::obj::parse`), made a scene as `prism_io::scene::load`
/// makes one (`mesh_scene`). `mtllib` names files, which the base folder does not hold.
pub fn obj(data: &[u8]) -> Outcome {
    let text = text(data);
    let path = Path::new(BASE).join("input.obj");
    let file = prism_io::scene::obj::parse(&text, &path, Materials::Read);
    let outcome = exercise::outcome(
        file.and_then(|f| prism_io::scene::mesh_scene(f, &path)),
        Some(&text),
    );
    tobj_agrees(outcome)
}

/// prism checks OBJ and MTL text itself before tobj reads it, so that every error has a
/// line and column; tobj refusing text those checks passed is a gap in them.
fn tobj_agrees(outcome: Outcome) -> Outcome {
    if let Outcome::Rejected(message) = &outcome {
        assert!(
            !message.contains("(tobj) failed"),
            "prism's checks passed text that tobj refuses: {message}"
        );
    }
    outcome
}

/// MTL material library text (`prism_io::scene::obj::parse_mtl`).
pub fn mtl(data: &[u8]) -> Outcome {
    let text = text(data);
    let path = Path::new(BASE).join("input.mtl");
    match prism_io::scene::obj::parse_mtl(&text, &path) {
        Ok(materials) => Outcome::Materials(materials.len()),
        Err(e) => tobj_agrees(exercise::outcome(Err(e), Some(&text))),
    }
}

/// PLY files, ASCII or binary (`prism_io::scene::ply::parse`), made a scene like `obj`.
pub fn ply(data: &[u8]) -> Outcome {
    let path = Path::new(BASE).join("input.ply");
    let file = prism_io::scene::ply::parse(data, &path.display().to_string());
    exercise::outcome(
        file.and_then(|f| prism_io::scene::mesh_scene(f, &path)),
        None,
    )
}

pub type Target = fn(&[u8]) -> Outcome;

/// Every target by name: the binaries, the corpus folders and the tests use these names.
pub const ALL: &[(&str, Target)] = &[
    ("nff", nff),
    ("toml", toml),
    ("gltf", gltf),
    ("glb", glb),
    ("obj", obj),
    ("mtl", mtl),
    ("ply", ply),
];
