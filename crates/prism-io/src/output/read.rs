//! Reading images back, for comparing renders: PNG and JPEG (8- or 16-bit, taken as
//! sRGB-encoded), OpenEXR and PFM (linear floats). Every format becomes a linear film.

use prism::math::Color;
use prism::render::Film;
use prism::transfer::srgb_decode;
use std::path::Path;

/// Why an image could not be read back.
#[derive(Debug, thiserror::Error)]
#[error("cannot read image {path}: {message}")]
pub struct ReadError {
    /// The file.
    pub path: String,
    /// What went wrong.
    pub message: String,
}

/// Reads the image at `path`; the extension picks the format.
pub fn read_image(path: &Path) -> Result<Film, ReadError> {
    let err = |message: String| ReadError {
        path: path.display().to_string(),
        message,
    };
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default();
    match ext.as_str() {
        "exr" => read_exr(path).map_err(err),
        "pfm" => {
            let bytes = std::fs::read(path).map_err(|e| err(e.to_string()))?;
            parse_pfm(&bytes).map_err(err)
        }
        "png" | "jpg" | "jpeg" => read_display(path).map_err(err),
        "" => Err(err(
            "no file extension; expected .png, .jpg, .exr or .pfm".into()
        )),
        other => Err(err(format!(
            "unknown image format '.{other}'; expected .png, .jpg, .exr or .pfm"
        ))),
    }
}

fn read_display(path: &Path) -> Result<Film, String> {
    let img = image::open(path).map_err(|e| e.to_string())?.to_rgb32f();
    let (w, h) = img.dimensions();
    let mut film = Film::new(w, h);
    for (p, q) in film.pixels.iter_mut().zip(img.pixels()) {
        *p = Color::new(srgb_decode(q[0]), srgb_decode(q[1]), srgb_decode(q[2]));
    }
    Ok(film)
}

fn read_exr(path: &Path) -> Result<Film, String> {
    use exr::prelude::*;
    let image = read_first_rgba_layer_from_file(
        path,
        |size, _| Film::new(size.width() as u32, size.height() as u32),
        |film: &mut Film, pos, (r, g, b, _a): (f32, f32, f32, f32)| {
            film.set(pos.x() as u32, pos.y() as u32, Color::new(r, g, b));
        },
    )
    .map_err(|e| e.to_string())?;
    Ok(image.layer_data.channel_data.pixels)
}

/// Portable float map: `PF` (colour) or `Pf` (grey), `width height`, a scale whose sign
/// gives the byte order (negative: little-endian), then rows from the bottom.
pub fn parse_pfm(bytes: &[u8]) -> Result<Film, String> {
    let mut fields = Vec::new();
    let mut pos = 0;
    // Four whitespace-separated header fields, then exactly one whitespace byte.
    while fields.len() < 4 {
        while pos < bytes.len() && bytes[pos].is_ascii_whitespace() {
            pos += 1;
        }
        let start = pos;
        while pos < bytes.len() && !bytes[pos].is_ascii_whitespace() {
            pos += 1;
        }
        if start == pos {
            return Err("truncated PFM header".into());
        }
        fields.push(String::from_utf8_lossy(&bytes[start..pos]).into_owned());
    }
    pos += 1;
    let channels = match fields[0].as_str() {
        "PF" => 3,
        "Pf" => 1,
        m => return Err(format!("not a PFM file (magic '{m}', expected PF or Pf)")),
    };
    let dim = |s: &str| {
        s.parse::<u32>()
            .ok()
            .filter(|&d| d > 0 && d <= 65536)
            .ok_or_else(|| format!("bad PFM size '{s}'"))
    };
    let (w, h) = (dim(&fields[1])?, dim(&fields[2])?);
    let scale: f32 = fields[3]
        .parse()
        .map_err(|_| format!("bad PFM scale '{}'", fields[3]))?;
    let need = w as usize * h as usize * channels * 4;
    let data = bytes.get(pos..pos + need).ok_or_else(|| {
        format!(
            "PFM data too short: {} bytes for {w}×{h}×{channels}, expected {need}",
            bytes.len().saturating_sub(pos)
        )
    })?;
    let value = |i: usize| {
        let b: [u8; 4] = data[i * 4..i * 4 + 4].try_into().expect("four bytes");
        if scale < 0.0 {
            f32::from_le_bytes(b)
        } else {
            f32::from_be_bytes(b)
        }
    };
    let mut film = Film::new(w, h);
    for y in 0..h {
        for x in 0..w {
            let i = ((h - 1 - y) as usize * w as usize + x as usize) * channels;
            let c = if channels == 3 {
                Color::new(value(i), value(i + 1), value(i + 2))
            } else {
                Color::splat(value(i))
            };
            film.set(x, y, c);
        }
    }
    Ok(film)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pfm_round_trips_through_the_encoder() {
        let mut film = Film::new(3, 2);
        for (i, p) in film.pixels.iter_mut().enumerate() {
            *p = Color::new(i as f32, 0.5 * i as f32, -1.0);
        }
        let back = parse_pfm(&super::super::encode::pfm(&film)).unwrap();
        assert_eq!(back, film);
    }

    #[test]
    fn bad_pfm_says_what_is_wrong() {
        assert!(parse_pfm(b"P6\n1 1\n255\n").unwrap_err().contains("magic"));
        assert!(parse_pfm(b"PF\n2 2\n-1\n\0\0")
            .unwrap_err()
            .contains("too short"));
        assert!(parse_pfm(b"PF\n").unwrap_err().contains("truncated"));
    }
}
