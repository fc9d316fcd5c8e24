//! Image textures from files: PNG and JPEG decoded within fixed limits (`decode`), then
//! turned into the engine's linear [`ImageTexture`].

mod decode;

pub use decode::{decode, MAX_TEXELS, MAX_TEXTURE_SIDE};

use crate::source::Reader;
use prism::shading::ImageTexture;
use std::path::Path;

/// Why an image texture named by a scene file could not be used.
#[derive(Debug, thiserror::Error)]
pub enum TextureError {
    /// The file could not be read or decoded; the message says which and why.
    #[error("cannot read image texture {path}: {message}")]
    Read {
        /// The texture file as the scene named it.
        path: String,
        /// What went wrong, without the path.
        message: String,
    },
}

/// Loads a PNG or JPEG, read through `reader`; 8-bit values are taken as sRGB-encoded.
pub fn load(path: &Path, reader: &mut Reader) -> Result<ImageTexture, TextureError> {
    read_image(path, reader).map(|img| from_srgb(&img))
}

/// Loads a PNG or JPEG of data (normals, heights), read through `reader`: 8-bit values
/// taken as they are, v/255.
pub fn load_data(path: &Path, reader: &mut Reader) -> Result<ImageTexture, TextureError> {
    read_image(path, reader).map(|img| from_linear(&img))
}

fn read_image(path: &Path, reader: &mut Reader) -> Result<image::DynamicImage, TextureError> {
    let read_error = |message: String| TextureError::Read {
        path: path.display().to_string(),
        message,
    };
    let bytes = reader.read(path).map_err(|e| read_error(e.to_string()))?;
    decode(&bytes).map_err(read_error)
}

/// Converts a decoded image whose 8-bit values are sRGB-encoded (as PNG and JPEG colour
/// images are) to linear texels.
pub fn from_srgb(img: &image::DynamicImage) -> ImageTexture {
    let rgb = img.to_rgb8();
    ImageTexture::from_srgb8(rgb.width() as usize, rgb.height() as usize, rgb.as_raw())
}

/// A decoded image of data rather than colour (a normal map): its 8-bit values taken as
/// they are, v/255, without the sRGB curve.
pub fn from_linear(img: &image::DynamicImage) -> ImageTexture {
    let rgb = img.to_rgb8();
    let texels = rgb
        .pixels()
        .map(|p| prism::math::Color::new(p[0] as f32, p[1] as f32, p[2] as f32) / 255.0)
        .collect();
    ImageTexture::from_texels(rgb.width() as usize, rgb.height() as usize, texels)
}
