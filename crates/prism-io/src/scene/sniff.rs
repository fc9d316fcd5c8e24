//! Saying what a file really is when its content does not match its extension. Downloads
//! go wrong in a few common ways: a web page saved under the model's name, a Git LFS
//! pointer checked out in place of a large file, a compressed archive or an image renamed.
//! A parser would report these as a syntax error on line 1; this names the real cause.

use std::io::Read;
use std::path::Path;

/// How many leading bytes identification reads.
const HEAD: usize = 4096;

/// What the first bytes of a file show it to be, when that is something other than a scene
/// or mesh: a sentence fragment such as "an HTML page".
pub(crate) fn identify(bytes: &[u8]) -> Option<&'static str> {
    let text = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    let start = text
        .iter()
        .position(|b| !b.is_ascii_whitespace())
        .unwrap_or(text.len());
    let lead = &text[start..text.len().min(start + 64)];
    let lower = lead.to_ascii_lowercase();
    if bytes.starts_with(b"version https://git-lfs.github.com/spec/") {
        return Some(
            "a Git LFS pointer, not the file itself (fetch it with `git lfs pull`, or download \
             the raw file)",
        );
    }
    if lower.starts_with(b"<!doctype html") || lower.starts_with(b"<html") {
        return Some("an HTML page (a web page saved in place of the file?)");
    }
    let magic: [(&[u8], &str); 7] = [
        (b"\x89PNG\r\n\x1a\n", "a PNG image"),
        (b"\xFF\xD8\xFF", "a JPEG image"),
        (b"PK\x03\x04", "a ZIP archive (unpack it first)"),
        (b"\x1F\x8B", "a gzip-compressed file (unpack it first)"),
        (b"%PDF", "a PDF document"),
        (b"glTF", "a binary glTF (.glb) file"),
        (b"ply", "a PLY mesh"),
    ];
    magic
        .iter()
        .find(|(m, _)| bytes.starts_with(m))
        .map(|&(_, what)| what)
}

/// Whether the bytes cannot be a text format: a NUL byte, or invalid UTF-8 together with
/// many control characters (Latin-1 comments in an OBJ file are still text).
pub(crate) fn is_binary(bytes: &[u8]) -> bool {
    if bytes.contains(&0) {
        return true;
    }
    let controls = bytes
        .iter()
        .filter(|&&b| b < 0x20 && !matches!(b, b'\n' | b'\r' | b'\t' | 0x0C))
        .count();
    std::str::from_utf8(bytes).is_err() && controls * 20 > bytes.len()
}

/// The file's first bytes (fewer if it is shorter); empty when it cannot be read, which the
/// loader then reports itself.
pub(crate) fn head(path: &Path) -> Vec<u8> {
    let mut out = Vec::with_capacity(HEAD);
    if let Ok(file) = std::fs::File::open(path) {
        let _ = file.take(HEAD as u64).read_to_end(&mut out);
    }
    out
}

/// The format a scene or mesh extension promises, for messages.
fn expected(ext: &str) -> Option<(&'static str, bool)> {
    // (what the extension means, whether it is a text format)
    Some(match ext {
        "toml" => ("a TOML scene", true),
        "nff" => ("an NFF scene", true),
        "gltf" => ("a glTF document", true),
        "glb" => ("a binary glTF (.glb) file", false),
        "obj" => ("an OBJ mesh", true),
        "ply" => ("a PLY mesh", false),
        _ => return None,
    })
}

/// An error message when the file at `path`, named with extension `ext`, is plainly not
/// what that extension says.
pub(crate) fn mismatch(path: &Path, ext: &str) -> Option<String> {
    let (promised, text) = expected(ext)?;
    let bytes = head(path);
    if bytes.is_empty() {
        return None;
    }
    let is = identify(&bytes);
    // glTF documents may be JSON or binary under either extension; the loader takes both.
    let fine = match (ext, is) {
        ("glb" | "gltf", Some("a binary glTF (.glb) file")) => true,
        ("ply", Some("a PLY mesh")) => true,
        (_, Some(_)) => false,
        ("glb", None) => first_non_blank(&bytes) == Some(b'{'),
        (_, None) => !(text && is_binary(&bytes)),
    };
    if fine {
        return None;
    }
    let what = match is {
        Some(what) => format!("this file is {what}"),
        None if ext == "glb" => format!(
            "this file does not start like a glTF file ('glTF' for binary, '{{' for JSON); its \
             first bytes are {}",
            hex(&bytes[..bytes.len().min(8)])
        ),
        None => "this file holds binary data (NUL or control bytes)".to_string(),
    };
    Some(format!("{what}, not {promised} as its extension says"))
}

fn first_non_blank(bytes: &[u8]) -> Option<u8> {
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    bytes.iter().copied().find(|b| !b.is_ascii_whitespace())
}

fn hex(bytes: &[u8]) -> String {
    bytes
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect::<Vec<_>>()
        .join(" ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn common_wrong_downloads_are_named() {
        let lfs = b"version https://git-lfs.github.com/spec/v1\noid sha256:4d7a\nsize 12345\n";
        assert!(identify(lfs).unwrap().contains("Git LFS pointer"));
        assert!(identify(b"\n  <!DOCTYPE html>\n<html>")
            .unwrap()
            .contains("HTML page"));
        assert!(identify(b"<HTML><body>").unwrap().contains("HTML page"));
        assert!(identify(b"PK\x03\x04rest").unwrap().contains("ZIP"));
        assert_eq!(identify(b"ply\nformat ascii 1.0\n"), Some("a PLY mesh"));
        assert_eq!(identify(b"# a comment\nv 0 0 0\n"), None);
    }

    #[test]
    fn text_with_latin1_is_not_binary_but_random_bytes_are() {
        assert!(!is_binary(b"# caf\xe9\nv 1 2 3\n"));
        assert!(is_binary(b"v 1 2 3\0"));
        let noise: Vec<u8> = (0..512u32)
            .map(|i| (i.wrapping_mul(2_654_435_761) >> 13) as u8)
            .collect();
        assert!(is_binary(&noise));
    }
}
