//! Texture images: found through `textures[i].source`, read from a file, a data: URI or a
//! buffer view, and decoded by the `image` crate (PNG and JPEG). Each image is decoded at
//! most once however many materials use it.

use super::{buffers, uri};
use crate::source::Reader;
use gltf::json::Root;
use image::DynamicImage;
use std::borrow::Cow;
use std::collections::HashMap;
use std::path::Path;
use std::rc::Rc;

pub(super) struct Images<'a> {
    root: &'a Root,
    buffers: &'a [Cow<'a, [u8]>],
    base_dir: &'a Path,
    /// Reads the image files.
    reader: &'a mut Reader,
    decoded: HashMap<usize, Rc<DynamicImage>>,
}

impl<'a> Images<'a> {
    pub(super) fn new(
        root: &'a Root,
        buffers: &'a [Cow<'a, [u8]>],
        base_dir: &'a Path,
        reader: &'a mut Reader,
    ) -> Self {
        Images {
            root,
            buffers,
            base_dir,
            reader,
            decoded: HashMap::new(),
        }
    }

    /// The image of texture `texture`.
    pub(super) fn texture(&mut self, texture: usize) -> Result<Rc<DynamicImage>, String> {
        let t = self.root.textures.get(texture).ok_or_else(|| {
            format!(
                "texture {texture} does not exist (the file has {})",
                self.root.textures.len()
            )
        })?;
        let source = t.source.value();
        if let Some(img) = self.decoded.get(&source) {
            return Ok(img.clone());
        }
        let img = Rc::new(
            self.decode(source)
                .map_err(|e| format!("texture {texture}: {e}"))?,
        );
        self.decoded.insert(source, img.clone());
        Ok(img)
    }

    /// The file texture `texture`'s image names, where it names one that is not there (a
    /// model downloaded without its textures): its colour texture is then left out with a
    /// warning rather than failing the load.
    pub(super) fn missing_file(&self, texture: usize) -> Option<std::path::PathBuf> {
        let t = self.root.textures.get(texture)?;
        let uri = self.root.images.get(t.source.value())?.uri.as_ref()?;
        match super::uri::resolve(uri, self.base_dir) {
            Ok(super::uri::Source::File(path)) if !path.exists() => Some(path),
            _ => None,
        }
    }

    fn decode(&mut self, index: usize) -> Result<DynamicImage, String> {
        let image = self.root.images.get(index).ok_or_else(|| {
            format!(
                "image {index} does not exist (the file has {})",
                self.root.images.len()
            )
        })?;
        let what = format!("image {index}");
        let (bytes, origin): (Cow<[u8]>, String) = match (&image.uri, image.buffer_view) {
            (Some(u), _) => (
                buffers::read(u, self.base_dir, &what, self.reader)?,
                format!("'{}'", uri::shorten(u)),
            ),
            (None, Some(view)) => (
                Cow::Borrowed(
                    buffers::view(self.root, self.buffers, view.value())
                        .map_err(|e| format!("{what}: {e}"))?,
                ),
                format!("bufferView {}", view.value()),
            ),
            (None, None) => return Err(format!("{what} has neither a uri nor a bufferView")),
        };
        crate::texture::decode(&bytes).map_err(|e| {
            format!("cannot decode {what} ({origin}): {e}; prism reads PNG and JPEG images")
        })
    }
}
