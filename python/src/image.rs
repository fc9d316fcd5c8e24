//! Images between Python and prism-io / prism-lab: NumPy's (H, W, 3) float32 arrays cross
//! as bytes of little-endian f32 RGB, row-major from the top (the package makes them
//! contiguous first), and become a linear `Film` here.

use crate::errors::{bad_argument, image_error};
use prism::math::Color;
use prism::render::Film;
use pyo3::prelude::*;
use pyo3::types::{PyByteArray, PyDict};
use std::path::PathBuf;

/// A linear film from `width` × `height` f32 RGB triples in `data`.
fn film(data: &[u8], width: u32, height: u32) -> PyResult<Film> {
    let expected = width as usize * height as usize * 12;
    if data.len() != expected || width == 0 || height == 0 {
        return Err(bad_argument(format!(
            "an image of {width}×{height} RGB float32 pixels takes {expected} bytes, got {}",
            data.len()
        )));
    }
    let value = |i: usize| f32::from_le_bytes([data[i], data[i + 1], data[i + 2], data[i + 3]]);
    let mut film = Film::new(width, height);
    for (i, p) in film.pixels.iter_mut().enumerate() {
        *p = Color::new(value(i * 12), value(i * 12 + 4), value(i * 12 + 8));
    }
    Ok(film)
}

/// Writes the image to `path` in the format its extension names (PNG, EXR, PFM),
/// atomically; `half` writes EXR as 16-bit floats.
#[pyfunction]
#[pyo3(signature = (path, data, width, height, half=false))]
pub(crate) fn write(
    py: Python<'_>,
    path: PathBuf,
    data: &[u8],
    width: u32,
    height: u32,
    half: bool,
) -> PyResult<()> {
    use prism_io::output::{write_image_as, ImageFormat};
    let film = film(data, width, height)?;
    let format = match ImageFormat::from_path(&path).map_err(image_error)? {
        ImageFormat::Exr { .. } => ImageFormat::Exr { half },
        other if half => {
            return Err(bad_argument(format!(
                "half=True applies to EXR only, not {other:?} ({})",
                path.display()
            )))
        }
        other => other,
    };
    py.allow_threads(|| write_image_as(&path, &film, format))
        .map_err(image_error)
}

/// Reads an image (PNG, JPEG, EXR, PFM) as linear light: (bytearray, width, height).
#[pyfunction]
pub(crate) fn read(py: Python<'_>, path: PathBuf) -> PyResult<(Bound<'_, PyByteArray>, u32, u32)> {
    let film = py
        .allow_threads(|| prism_io::output::read_image(&path))
        .map_err(image_error)?;
    let film = film.displayed_linear();
    let mut bytes = Vec::with_capacity(film.pixels.len() * 12);
    for c in &film.pixels {
        for v in [c.x, c.y, c.z] {
            bytes.extend_from_slice(&v.to_le_bytes());
        }
    }
    Ok((PyByteArray::new(py, &bytes), film.width, film.height))
}

/// How far `test` is from `reference` (each as bytes, width, height): RMSE, PSNR, SSIM
/// and FLIP for a viewer at `ppd` pixels per degree, as `prism compare` reports them.
#[pyfunction]
#[pyo3(signature = (reference, test, ppd=prism_lab::metrics::flip::DEFAULT_PPD))]
pub(crate) fn compare<'py>(
    py: Python<'py>,
    reference: (Vec<u8>, u32, u32),
    test: (Vec<u8>, u32, u32),
    ppd: f32,
) -> PyResult<Bound<'py, PyDict>> {
    if !(ppd > 0.0 && ppd.is_finite()) {
        return Err(bad_argument(format!(
            "ppd must be a positive number, got {ppd}"
        )));
    }
    let a = film(&reference.0, reference.1, reference.2)?;
    let b = film(&test.0, test.1, test.2)?;
    let c = py
        .allow_threads(|| prism_lab::metrics::compare(&a, &b, None, ppd))
        .map_err(image_error)?;
    let out = PyDict::new(py);
    out.set_item("rmse", c.rmse)?;
    out.set_item("psnr", c.psnr)?;
    out.set_item("ssim", c.ssim)?;
    out.set_item("flip", c.flip)?;
    out.set_item("flip_max", c.flip_max)?;
    out.set_item("pixels", c.pixels)?;
    Ok(out)
}
