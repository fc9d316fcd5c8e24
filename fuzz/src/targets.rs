//! The fuzz target bodies: bytes in, a parser run, and the scene it returns (if any)
//! checked and traced. A panic anywhere is a finding.

use crate::exercise::{self, Outcome};
use std::path::Path;

/// A folder that does not exist: files a scene names relative to itself (textures, glTF
/// buffers) are never found, so a run depends on the input alone.
const BASE: &str = "/nonexistent/prism-fuzz";

/// Text formats see the bytes as UTF-8 with bad sequences replaced, so that every input
/// reaches the parser; the loaders reject non-UTF-8 files before parsing.
fn text(data: &[u8]) -> std::borrow::Cow<'_, str> {
    String::from_utf8_lossy(data)
}

/// NFF text (`prism::scene::nff::parse`).
pub fn nff(data: &[u8]) -> Outcome {
    let text = text(data);
    let path = format!("{BASE}/input.nff");
    exercise::outcome(prism::scene::nff::parse(&text, &path), Some(&text))
}

/// TOML scene text (`prism::scene::parse_toml`).
pub fn toml(data: &[u8]) -> Outcome {
    let text = text(data);
    let path = Path::new(BASE).join("input.toml");
    exercise::outcome(prism::scene::parse_toml(&text, &path), Some(&text))
}

/// glTF JSON (`prism::scene::parse_gltf`); the corpus holds .gltf documents.
pub fn gltf(data: &[u8]) -> Outcome {
    let path = Path::new(BASE).join("input.gltf");
    exercise::outcome(prism::scene::parse_gltf(data, &path), None)
}

/// Binary glTF containers, the same entry point as `gltf` with a corpus of .glb files
/// (their headers, chunk lengths and BIN data are what the fuzzer mutates).
pub fn glb(data: &[u8]) -> Outcome {
    let path = Path::new(BASE).join("input.glb");
    exercise::outcome(prism::scene::parse_gltf(data, &path), None)
}

pub type Target = fn(&[u8]) -> Outcome;

/// Every target by name: the binaries, the corpus folders and the tests use these names.
pub const ALL: &[(&str, Target)] = &[("nff", nff), ("toml", toml), ("gltf", gltf), ("glb", glb)];
