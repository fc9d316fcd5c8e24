//! The URIs a glTF file uses for buffers and images: `data:` URIs with base64 payloads,
//! and relative file paths (percent-encoded, resolved against the glTF file's folder).
//! Other schemes (http:, file:, …) are refused: a scene file should not reach the network.

use std::path::{Path, PathBuf};

/// Where a URI's bytes come from.
pub(super) enum Source {
    /// The decoded payload of a `data:` URI.
    Inline(Vec<u8>),
    File(PathBuf),
}

/// Resolves `uri` against `base_dir`, decoding it if it is a `data:` URI.
pub(super) fn resolve(uri: &str, base_dir: &Path) -> Result<Source, String> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let (header, payload) = rest
            .split_once(',')
            .ok_or("a data: URI needs a ',' before its payload")?;
        if !header.ends_with(";base64") {
            return Err(format!(
                "data: URI with header '{header}': prism reads only base64 data URIs \
                 (data:<type>;base64,<payload>)"
            ));
        }
        return decode_base64(payload)
            .map(Source::Inline)
            .map_err(|e| format!("data: URI: {e}"));
    }
    if let Some(scheme) = scheme(uri) {
        return Err(format!(
            "URI '{}' uses the scheme '{scheme}:'; prism reads relative file paths and data: \
             URIs only",
            shorten(uri)
        ));
    }
    Ok(Source::File(base_dir.join(percent_decode(uri)?)))
}

/// The URI's scheme (RFC 3986: a letter, then letters, digits, '+', '-', '.', then ':'),
/// if it has one.
fn scheme(uri: &str) -> Option<&str> {
    let (head, _) = uri.split_once(':')?;
    let mut chars = head.chars();
    let first = chars.next()?;
    (first.is_ascii_alphabetic()
        && chars.all(|c| c.is_ascii_alphanumeric() || matches!(c, '+' | '-' | '.')))
    .then_some(head)
}

/// Long data URIs would flood an error message; keep their start.
pub(super) fn shorten(uri: &str) -> String {
    const KEEP: usize = 60;
    match uri.char_indices().nth(KEEP) {
        Some((end, _)) => format!("{}…", &uri[..end]),
        None => uri.to_string(),
    }
}

fn percent_decode(uri: &str) -> Result<String, String> {
    let bytes = uri.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let hex = bytes
                .get(i + 1..i + 3)
                .and_then(|h| std::str::from_utf8(h).ok())
                .and_then(|h| u8::from_str_radix(h, 16).ok())
                .ok_or_else(|| {
                    format!(
                        "URI '{}': '%' at byte {i} must be followed by two hex digits",
                        shorten(uri)
                    )
                })?;
            out.push(hex);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    String::from_utf8(out)
        .map_err(|_| format!("URI '{}' decodes to a path that is not UTF-8", shorten(uri)))
}

fn base64_value(c: u8) -> Option<u32> {
    match c {
        b'A'..=b'Z' => Some((c - b'A') as u32),
        b'a'..=b'z' => Some((c - b'a') as u32 + 26),
        b'0'..=b'9' => Some((c - b'0') as u32 + 52),
        b'+' | b'-' => Some(62),
        b'/' | b'_' => Some(63),
        _ => None,
    }
}

/// Decodes base64 (standard or URL-safe alphabet, padding optional).
pub(super) fn decode_base64(text: &str) -> Result<Vec<u8>, String> {
    let data = text.trim_end_matches('=').as_bytes();
    if text.len() - data.len() > 2 {
        return Err("base64 payload ends in more than two '=' padding characters".into());
    }
    let mut out = Vec::with_capacity(data.len() / 4 * 3 + 2);
    for (chunk_index, chunk) in data.chunks(4).enumerate() {
        let mut word = 0u32;
        for (k, &c) in chunk.iter().enumerate() {
            let v = base64_value(c).ok_or_else(|| {
                format!(
                    "character {:?} at position {} is not base64",
                    c as char,
                    chunk_index * 4 + k
                )
            })?;
            word |= v << (18 - 6 * k);
        }
        let bytes = word.to_be_bytes();
        match chunk.len() {
            4 => out.extend_from_slice(&bytes[1..4]),
            3 => out.extend_from_slice(&bytes[1..3]),
            2 => out.push(bytes[1]),
            _ => return Err("base64 payload has a stray final character".into()),
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base64_round_trips_known_values() {
        assert_eq!(decode_base64("").unwrap(), b"");
        assert_eq!(decode_base64("Zg==").unwrap(), b"f");
        assert_eq!(decode_base64("Zm8=").unwrap(), b"fo");
        assert_eq!(decode_base64("Zm9v").unwrap(), b"foo");
        assert_eq!(decode_base64("Zm9vYmFy").unwrap(), b"foobar");
        assert_eq!(decode_base64("Zm9vYg").unwrap(), b"foob");
        assert_eq!(decode_base64("//79").unwrap(), [0xff, 0xfe, 0xfd]);
        assert!(decode_base64("Zm9v!").is_err());
        assert!(decode_base64("Z").is_err());
        assert!(decode_base64("Zg===").is_err());
    }

    #[test]
    fn uris_resolve_to_files_or_bytes() {
        let base = Path::new("/scenes");
        match resolve("my%20mesh.bin", base).unwrap() {
            Source::File(p) => assert_eq!(p, Path::new("/scenes/my mesh.bin")),
            Source::Inline(_) => panic!("expected a file"),
        }
        match resolve("data:application/octet-stream;base64,Zm9v", base).unwrap() {
            Source::Inline(b) => assert_eq!(b, b"foo"),
            Source::File(_) => panic!("expected inline data"),
        }
        assert!(resolve("https://example.com/a.bin", base)
            .err()
            .unwrap()
            .contains("scheme 'https:'"));
        assert!(resolve("data:text/plain,hello", base).is_err());
        assert!(resolve("bad%2", base).is_err());
    }
}
