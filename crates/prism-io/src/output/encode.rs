//! Encoders from film to file bytes, one function per format.

use super::to_rgb8;
use prism::render::Film;
use std::io::Cursor;

pub(super) fn png(film: &Film) -> Result<Vec<u8>, String> {
    png_rgb8(&to_rgb8(film), film.width, film.height)
}

/// PNG of 8-bit RGB rows from the top.
pub(super) fn png_rgb8(data: &[u8], width: u32, height: u32) -> Result<Vec<u8>, String> {
    use image::ImageEncoder;
    let mut out = Vec::new();
    image::codecs::png::PngEncoder::new(&mut out)
        .write_image(data, width, height, image::ExtendedColorType::Rgb8)
        .map_err(|e| e.to_string())?;
    Ok(out)
}

/// OpenEXR, linear RGB. Compressed chunk by chunk on this thread: exr's parallel writer
/// stores chunks in the order its threads finish them, so the same pixels would give files
/// with different bytes from run to run.
pub(super) fn exr(film: &Film, half: bool) -> Result<Vec<u8>, String> {
    use exr::prelude::*;
    let film = film.displayed_linear();
    let (w, h) = (film.width as usize, film.height as usize);
    let mut out = Cursor::new(Vec::new());
    let pixel = |x: usize, y: usize| film.pixels[y * w + x];
    let result = if half {
        let channels = SpecificChannels::rgb(|Vec2(x, y)| {
            let c = pixel(x, y);
            (f16::from_f32(c.x), f16::from_f32(c.y), f16::from_f32(c.z))
        });
        Image::from_channels((w, h), channels)
            .write()
            .non_parallel()
            .to_buffered(&mut out)
    } else {
        let channels = SpecificChannels::rgb(|Vec2(x, y)| {
            let c = pixel(x, y);
            (c.x, c.y, c.z)
        });
        Image::from_channels((w, h), channels)
            .write()
            .non_parallel()
            .to_buffered(&mut out)
    };
    result.map_err(|e| e.to_string())?;
    Ok(out.into_inner())
}

/// Portable float map: a text header, then little-endian f32 RGB rows from the bottom up.
pub(super) fn pfm(film: &Film) -> Vec<u8> {
    let film = film.displayed_linear();
    let mut out = format!("PF\n{} {}\n-1.0\n", film.width, film.height).into_bytes();
    let w = film.width as usize;
    for row in film.pixels.chunks(w.max(1)).rev() {
        for c in row {
            for v in [c.x, c.y, c.z] {
                out.extend_from_slice(&v.to_le_bytes());
            }
        }
    }
    out
}
