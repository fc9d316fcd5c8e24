//! Image error metrics, for measuring sampling error against a reference: RMSE and PSNR of
//! the linear values, SSIM of the displayed luma, and LDR-FLIP of the displayed colours.
//! A display-referred film is first turned into the linear light it shows
//! (`Film::displayed_linear`), so it compares with its own PNG read back.
//! Each metric can be restricted to a mask of pixels (such as the checkerboard's far field).

mod convolve;
pub mod flip;
mod ssim;

pub use convolve::Plane;

use prism::render::Film;
use prism::transfer::Transfer;
use serde::Serialize;

/// How far one image is from another.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Comparison {
    /// Root mean square difference of the linear RGB values.
    pub rmse: f64,
    /// 20·log10(1 / RMSE): peak signal-to-noise ratio for a peak of 1, in dB (infinite for
    /// identical images).
    pub psnr: f64,
    /// Mean structural similarity of the displayed luma (1 for identical images).
    pub ssim: f64,
    /// Mean LDR-FLIP error (0 for identical images, 1 at most).
    pub flip: f64,
    /// The largest per-pixel FLIP error.
    pub flip_max: f64,
    /// Pixels compared.
    pub pixels: usize,
}

/// Why two images cannot be compared.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum CompareError {
    /// Their sizes differ: width × height of each.
    #[error("the images differ in size: {0}×{1} and {2}×{3}")]
    Size(u32, u32, u32, u32),
    /// The mask leaves no pixel to compare.
    #[error("the mask selects no pixels")]
    EmptyMask,
}

/// Compares `test` with `reference` over the pixels `mask` selects (all when None), FLIP
/// for a viewer at `ppd` pixels per degree.
pub fn compare(
    reference: &Film,
    test: &Film,
    mask: Option<&[bool]>,
    ppd: f32,
) -> Result<Comparison, CompareError> {
    check_sizes(reference, test)?;
    let selected = |i: usize| mask.is_none_or(|m| m.get(i).copied().unwrap_or(false));
    let pixels = (0..reference.pixels.len()).filter(|&i| selected(i)).count();
    if pixels == 0 {
        return Err(CompareError::EmptyMask);
    }
    let rmse = rmse(reference, test, mask)?;
    let psnr = if rmse == 0.0 {
        f64::INFINITY
    } else {
        -20.0 * rmse.log10()
    };
    let ssim = ssim_map(reference, test)?;
    let flip = flip_map(reference, test, ppd)?;
    let mean = |p: &Plane| {
        p.values
            .iter()
            .enumerate()
            .filter(|(i, _)| selected(*i))
            .map(|(_, &v)| v as f64)
            .sum::<f64>()
            / pixels as f64
    };
    let flip_max = flip
        .values
        .iter()
        .enumerate()
        .filter(|(i, _)| selected(*i))
        .map(|(_, &v)| v as f64)
        .fold(0.0, f64::max);
    Ok(Comparison {
        rmse,
        psnr,
        ssim: mean(&ssim),
        flip: mean(&flip),
        flip_max,
        pixels,
    })
}

fn check_sizes(a: &Film, b: &Film) -> Result<(), CompareError> {
    if (a.width, a.height) != (b.width, b.height) {
        return Err(CompareError::Size(a.width, a.height, b.width, b.height));
    }
    Ok(())
}

/// Root mean square difference of the linear RGB values over the masked pixels.
pub fn rmse(a: &Film, b: &Film, mask: Option<&[bool]>) -> Result<f64, CompareError> {
    check_sizes(a, b)?;
    let (a, b) = (a.displayed_linear(), b.displayed_linear());
    let (mut sum, mut n) = (0.0f64, 0usize);
    for (i, (p, q)) in a.pixels.iter().zip(&b.pixels).enumerate() {
        if mask.is_some_and(|m| !m.get(i).copied().unwrap_or(false)) {
            continue;
        }
        let d = *p - *q;
        sum += (d.x as f64).powi(2) + (d.y as f64).powi(2) + (d.z as f64).powi(2);
        n += 3;
    }
    if n == 0 {
        return Err(CompareError::EmptyMask);
    }
    Ok((sum / n as f64).sqrt())
}

/// Per-pixel SSIM.
pub fn ssim_map(a: &Film, b: &Film) -> Result<Plane, CompareError> {
    check_sizes(a, b)?;
    let (a, b) = (a.displayed_linear(), b.displayed_linear());
    Ok(ssim::ssim_map(&luma(&a), &luma(&b)))
}

/// Per-pixel LDR-FLIP error of `test` against `reference`.
pub fn flip_map(reference: &Film, test: &Film, ppd: f32) -> Result<Plane, CompareError> {
    check_sizes(reference, test)?;
    let (reference, test) = (reference.displayed_linear(), test.displayed_linear());
    Ok(flip::flip_map(
        &reference.pixels,
        &test.pixels,
        reference.width as usize,
        reference.height as usize,
        ppd,
    ))
}

/// Rec. 709 luma of the display-encoded (8-bit sRGB) image, in [0, 1].
fn luma(film: &Film) -> Plane {
    let values = film
        .pixels
        .iter()
        .map(|c| {
            let e = c
                .to_array()
                .map(|v| Transfer::Srgb.encode8(v) as f32 / 255.0);
            0.2126 * e[0] + 0.7152 * e[1] + 0.0722 * e[2]
        })
        .collect();
    Plane::new(film.width as usize, film.height as usize, values)
}

#[cfg(test)]
mod tests {
    use super::*;
    use prism::math::Color;

    fn film(w: u32, h: u32, f: impl Fn(u32, u32) -> Color) -> Film {
        let mut film = Film::new(w, h);
        for y in 0..h {
            for x in 0..w {
                film.set(x, y, f(x, y));
            }
        }
        film
    }

    #[test]
    fn identical_images_have_no_error() {
        let a = film(20, 12, |x, y| {
            Color::new(x as f32 / 20.0, y as f32 / 12.0, 0.3)
        });
        let c = compare(&a, &a, None, DEFAULT_PPD_FOR_TESTS).unwrap();
        assert_eq!(c.rmse, 0.0);
        assert!(c.psnr.is_infinite());
        assert!((c.ssim - 1.0).abs() < 1e-6, "{}", c.ssim);
        assert!(c.flip < 1e-6 && c.flip_max < 1e-6, "{c:?}");
    }

    const DEFAULT_PPD_FOR_TESTS: f32 = flip::DEFAULT_PPD;

    #[test]
    fn rmse_and_psnr_of_a_constant_offset() {
        let a = film(8, 8, |_, _| Color::splat(0.5));
        let b = film(8, 8, |_, _| Color::splat(0.6));
        let c = compare(&a, &b, None, DEFAULT_PPD_FOR_TESTS).unwrap();
        assert!((c.rmse - 0.1).abs() < 1e-6);
        assert!((c.psnr - 20.0).abs() < 1e-4);
    }

    #[test]
    fn black_against_white_is_the_largest_flip_error() {
        let a = film(16, 16, |_, _| Color::ZERO);
        let b = film(16, 16, |_, _| Color::ONE);
        let c = compare(&a, &b, None, DEFAULT_PPD_FOR_TESTS).unwrap();
        assert!(c.flip > 0.9, "{c:?}");
        assert!(c.ssim < 0.1, "{c:?}");
    }

    #[test]
    fn a_small_change_is_a_small_flip_error_and_grows_with_the_change() {
        let base = film(32, 32, |x, y| {
            Color::splat(if (x / 4 + y / 4) % 2 == 0 { 0.8 } else { 0.2 })
        });
        let shifted = |d: f32| film(32, 32, |x, y| base.get(x, y) + Color::splat(d));
        let small = compare(&base, &shifted(0.005), None, DEFAULT_PPD_FOR_TESTS).unwrap();
        let large = compare(&base, &shifted(0.1), None, DEFAULT_PPD_FOR_TESTS).unwrap();
        assert!(small.flip < 0.05, "{small:?}");
        assert!(large.flip > 2.0 * small.flip, "{small:?} {large:?}");
    }

    #[test]
    fn masks_select_pixels_and_sizes_must_match() {
        let a = film(4, 1, |x, _| Color::splat(x as f32));
        let b = film(4, 1, |_, _| Color::ZERO);
        let mask = [true, false, false, false];
        assert_eq!(rmse(&a, &b, Some(&mask)).unwrap(), 0.0);
        assert_eq!(
            compare(&a, &b, Some(&[false; 4]), 67.0).unwrap_err(),
            CompareError::EmptyMask
        );
        let c = film(3, 1, |_, _| Color::ZERO);
        assert!(matches!(
            compare(&a, &c, None, 67.0),
            Err(CompareError::Size(..))
        ));
    }
}
