//! The binary glTF container (.glb): a 12-byte header, then a JSON chunk and an optional
//! BIN chunk. Split here, with every length checked, rather than by the gltf crate, whose
//! header arithmetic underflows on a header that claims fewer than 12 bytes.

const MAGIC: &[u8; 4] = b"glTF";
const HEADER_LEN: usize = 12;
const CHUNK_HEADER_LEN: usize = 8;
const CHUNK_JSON: u32 = 0x4E4F_534A;
const CHUNK_BIN: u32 = 0x004E_4942;

/// The chunks of a GLB file, borrowed from its bytes.
#[derive(Debug)]
pub(super) struct Glb<'a> {
    pub json: &'a [u8],
    /// The first BIN chunk: the data of buffer 0 when that buffer has no `uri`.
    pub bin: Option<&'a [u8]>,
}

/// Whether the bytes start like a GLB file (whatever the file's extension says).
pub(super) fn is_glb(bytes: &[u8]) -> bool {
    bytes.starts_with(MAGIC)
}

fn read_u32(bytes: &[u8], at: usize) -> Option<u32> {
    let word = bytes.get(at..at.checked_add(4)?)?;
    Some(u32::from_le_bytes([word[0], word[1], word[2], word[3]]))
}

/// Splits a GLB file into its chunks. Chunks of unknown type are skipped, as the
/// specification asks.
pub(super) fn split(bytes: &[u8]) -> Result<Glb<'_>, String> {
    if bytes.len() < HEADER_LEN || !is_glb(bytes) {
        return Err(format!(
            "expected a 12-byte GLB header starting with 'glTF', the file has {} bytes",
            bytes.len()
        ));
    }
    let version = read_u32(bytes, 4).unwrap_or(0);
    if version != 2 {
        return Err(format!(
            "GLB version {version} is not supported: expected version 2 (glTF 2.0)"
        ));
    }
    let declared = read_u32(bytes, 8).unwrap_or(0) as usize;
    if declared > bytes.len() {
        return Err(format!(
            "the GLB header declares {declared} bytes but the file has only {}: the file is \
             truncated",
            bytes.len()
        ));
    }
    if declared < HEADER_LEN + CHUNK_HEADER_LEN {
        return Err(format!(
            "the GLB header declares {declared} bytes, too few for a header and a JSON chunk"
        ));
    }
    let body = &bytes[..declared];

    let mut json = None;
    let mut bin = None;
    let mut at = HEADER_LEN;
    let mut chunk_number = 0;
    while at < body.len() {
        let (Some(length), Some(kind)) = (read_u32(body, at), read_u32(body, at + 4)) else {
            return Err(format!(
                "chunk {chunk_number} at byte {at}: expected an 8-byte chunk header, the file \
                 ends after {} bytes: the file is truncated",
                body.len() - at
            ));
        };
        let start = at + CHUNK_HEADER_LEN;
        let end = start
            .checked_add(length as usize)
            .filter(|&end| end <= body.len())
            .ok_or_else(|| {
                format!(
                    "chunk {chunk_number} at byte {at} declares {length} bytes but only {} \
                     follow: the file is truncated",
                    body.len() - start
                )
            })?;
        let data = &body[start..end];
        match (chunk_number, kind) {
            (0, CHUNK_JSON) => json = Some(data),
            (0, _) => {
                return Err(format!(
                    "the first chunk has type 0x{kind:08x}: expected the JSON chunk (0x{CHUNK_JSON:08x})"
                ))
            }
            (_, CHUNK_JSON) => return Err("the GLB file has a second JSON chunk".into()),
            (_, CHUNK_BIN) if bin.is_none() => bin = Some(data),
            _ => {}
        }
        // Chunks are padded to 4 bytes; the declared length includes the padding.
        at = end;
        chunk_number += 1;
    }
    let json = json.ok_or("the GLB file has no JSON chunk")?;
    // The JSON chunk is padded with spaces; some exporters pad with zeros instead.
    let end = json.iter().rposition(|&b| b != 0).map_or(0, |i| i + 1);
    Ok(Glb {
        json: &json[..end],
        bin,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn glb(chunks: &[(u32, &[u8])]) -> Vec<u8> {
        let mut out = b"glTF".to_vec();
        out.extend(2u32.to_le_bytes());
        out.extend(0u32.to_le_bytes());
        for (kind, data) in chunks {
            out.extend((data.len() as u32).to_le_bytes());
            out.extend(kind.to_le_bytes());
            out.extend(*data);
        }
        let len = out.len() as u32;
        out[8..12].copy_from_slice(&len.to_le_bytes());
        out
    }

    #[test]
    fn splits_json_and_bin_and_skips_unknown_chunks() {
        let bytes = glb(&[
            (CHUNK_JSON, b"{}\0\0"),
            (0x1234, b"xxxx"),
            (CHUNK_BIN, b"abcd"),
        ]);
        let g = split(&bytes).unwrap();
        assert_eq!(g.json, b"{}");
        assert_eq!(g.bin, Some(&b"abcd"[..]));
    }

    #[test]
    fn truncation_and_bad_headers_are_errors() {
        let bytes = glb(&[(CHUNK_JSON, b"{}  "), (CHUNK_BIN, b"abcd")]);
        for cut in 0..bytes.len() {
            assert!(split(&bytes[..cut]).is_err(), "cut at {cut}");
        }
        let mut tiny = bytes.clone();
        tiny[8..12].copy_from_slice(&3u32.to_le_bytes());
        assert!(split(&tiny).unwrap_err().contains("too few"));
        let mut v1 = bytes.clone();
        v1[4] = 1;
        assert!(split(&v1).unwrap_err().contains("version 1"));
        let bin_first = glb(&[(CHUNK_BIN, b"abcd")]);
        assert!(split(&bin_first).unwrap_err().contains("JSON chunk"));
    }
}
