//! Decoding texture images within fixed limits, so a small hostile file (a PNG header that
//! claims 100000 × 100000 pixels) is refused instead of allocating gigabytes.

use image::{DynamicImage, ImageReader, Limits};
use std::io::Cursor;

/// Largest accepted texture side, in pixels.
pub const MAX_TEXTURE_SIDE: u32 = 16384;
/// Largest accepted texel count: 64 M texels, 768 MiB as linear RGB floats.
pub const MAX_TEXELS: u64 = 1 << 26;

/// Decodes a PNG or JPEG held in memory; the error says what was wrong, without a path.
pub fn decode(bytes: &[u8]) -> Result<DynamicImage, String> {
    let reader = || {
        ImageReader::new(Cursor::new(bytes))
            .with_guessed_format()
            .map_err(|e| e.to_string())
    };
    // The header alone first: refuse before the decoder allocates anything.
    check_size(reader()?.into_dimensions().map_err(|e| e.to_string())?)?;
    let mut limits = Limits::default();
    limits.max_image_width = Some(MAX_TEXTURE_SIDE);
    limits.max_image_height = Some(MAX_TEXTURE_SIDE);
    // 8-bit RGBA is the largest layout PNG and JPEG decode to here (16-bit PNGs are
    // rarer and still fit: the texel count is checked above).
    limits.max_alloc = Some(MAX_TEXELS * 8);
    let mut decoder = reader()?;
    decoder.limits(limits);
    decoder.decode().map_err(|e| e.to_string())
}

fn check_size((width, height): (u32, u32)) -> Result<(), String> {
    if width > MAX_TEXTURE_SIDE || height > MAX_TEXTURE_SIDE {
        return Err(format!(
            "{width} × {height} pixels: textures may be at most {MAX_TEXTURE_SIDE} pixels on a side"
        ));
    }
    if u64::from(width) * u64::from(height) > MAX_TEXELS {
        return Err(format!(
            "{width} × {height} pixels: textures may hold at most {MAX_TEXELS} pixels"
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn png(width: u32, height: u32) -> Vec<u8> {
        let mut bytes = Vec::new();
        image::RgbImage::new(width, height)
            .write_to(&mut Cursor::new(&mut bytes), image::ImageFormat::Png)
            .unwrap();
        bytes
    }

    #[test]
    fn small_images_decode() {
        let img = decode(&png(3, 2)).unwrap();
        assert_eq!((img.width(), img.height()), (3, 2));
    }

    /// CRC-32 (ISO-HDLC) as PNG chunks use it, bit by bit: only for patching test files.
    fn crc32(data: &[u8]) -> u32 {
        let mut crc = !0u32;
        for &b in data {
            crc ^= u32::from(b);
            for _ in 0..8 {
                crc = if crc & 1 == 1 {
                    (crc >> 1) ^ 0xEDB8_8320
                } else {
                    crc >> 1
                };
            }
        }
        !crc
    }

    #[test]
    fn a_header_claiming_a_huge_image_is_refused_before_decoding() {
        // A real 1×1 PNG whose IHDR (bytes 12..29: type, data, then its CRC) now claims
        // 100000 × 100000 pixels, with a valid checksum.
        let mut bytes = png(1, 1);
        bytes[16..20].copy_from_slice(&100_000u32.to_be_bytes());
        bytes[20..24].copy_from_slice(&100_000u32.to_be_bytes());
        let crc = crc32(&bytes[12..29]);
        bytes[29..33].copy_from_slice(&crc.to_be_bytes());
        let err = decode(&bytes).unwrap_err();
        assert!(
            err.contains("100000 × 100000 pixels: textures may be at most 16384"),
            "{err}"
        );
        let err = check_size((16384, 16384)).unwrap_err();
        assert!(err.contains("at most 67108864 pixels"), "{err}");
        assert!(check_size((8192, 8192)).is_ok());
    }

    #[test]
    fn garbage_is_an_error_not_a_panic() {
        assert!(decode(b"not an image at all").is_err());
        assert!(decode(&[]).is_err());
    }
}
