//! Buffer data: each glTF buffer's bytes, from a file beside the scene, a data: URI, or
//! (for a .glb's first buffer without a uri) the BIN chunk.

use super::uri::{self, Source};
use crate::source::Reader;
use gltf::json::Root;
use std::borrow::Cow;
use std::path::Path;

/// Loads every buffer, cut to its declared `byteLength`; files are read through `reader`.
pub(super) fn load<'a>(
    root: &Root,
    glb_bin: Option<&'a [u8]>,
    base_dir: &Path,
    reader: &mut Reader,
) -> Result<Vec<Cow<'a, [u8]>>, String> {
    root.buffers
        .iter()
        .enumerate()
        .map(|(index, buffer)| {
            let declared = buffer.byte_length.0;
            let (data, origin): (Cow<'a, [u8]>, String) =
                match &buffer.uri {
                    Some(u) => (read(u, base_dir, &format!("buffer {index}"), reader)?, {
                        format!("'{}'", uri::shorten(u))
                    }),
                    None if index == 0 => match glb_bin {
                        Some(bin) => (Cow::Borrowed(bin), "the GLB's BIN chunk".into()),
                        None => return Err(
                            "buffer 0 has no uri and the file has no GLB BIN chunk: expected a \
                             uri (a file name or data: URI), or a .glb file with binary data"
                                .into(),
                        ),
                    },
                    None => {
                        return Err(format!(
                            "buffer {index} has no uri; only the first buffer of a .glb file may \
                         omit it"
                        ))
                    }
                };
            if (data.len() as u64) < declared {
                // A short buffer is most often not the buffer at all: say what it is.
                let is = crate::scene::sniff::identify(&data)
                    .map_or(String::new(), |what| format!("; it is {what}"));
                return Err(format!(
                    "buffer {index} ({origin}) has {} bytes but its byteLength is {declared}{is}",
                    data.len()
                ));
            }
            Ok(match data {
                Cow::Borrowed(b) => Cow::Borrowed(&b[..declared as usize]),
                Cow::Owned(mut v) => {
                    v.truncate(declared as usize);
                    Cow::Owned(v)
                }
            })
        })
        .collect()
}

/// Reads the bytes a uri names (a file through `reader`); `what` ("buffer 2", "image 0")
/// starts error messages.
pub(super) fn read<'a>(
    u: &str,
    base_dir: &Path,
    what: &str,
    reader: &mut Reader,
) -> Result<Cow<'a, [u8]>, String> {
    match uri::resolve(u, base_dir).map_err(|e| format!("{what}: {e}"))? {
        Source::Inline(bytes) => Ok(Cow::Owned(bytes)),
        Source::File(file) => reader
            .read_regular_file(&file)
            .map(Cow::Owned)
            .map_err(|e| {
                format!(
                    "{what}: cannot read '{}' ({}): {e}",
                    uri::shorten(u),
                    file.display()
                )
            }),
    }
}

/// The bytes of buffer view `view`, checked to lie inside its buffer.
pub(super) fn view<'b>(
    root: &Root,
    buffers: &'b [Cow<'_, [u8]>],
    view: usize,
) -> Result<&'b [u8], String> {
    let v = root.buffer_views.get(view).ok_or_else(|| {
        format!(
            "bufferView {view} does not exist (the file has {})",
            root.buffer_views.len()
        )
    })?;
    let index = v.buffer.value();
    let buffer = buffers.get(index).ok_or_else(|| {
        format!("bufferView {view} refers to buffer {index}, which does not exist")
    })?;
    let start = v.byte_offset.map_or(0, |o| o.0);
    let len = v.byte_length.0;
    start
        .checked_add(len)
        .and_then(|end| buffer.get(usize::try_from(start).ok()?..usize::try_from(end).ok()?))
        .ok_or_else(|| {
            format!(
                "bufferView {view} spans bytes {start}..{} of buffer {index}, which has {} bytes",
                start as u128 + len as u128,
                buffer.len()
            )
        })
}
