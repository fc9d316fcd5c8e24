//! SSIM, the structural similarity index (Wang, Bovik, Sheikh and Simoncelli 2004), on the
//! luma of the display-encoded images with their 11×11 Gaussian window (σ = 1.5) and
//! constants K1 = 0.01, K2 = 0.03 for a dynamic range of 1.

use super::convolve::{gaussian, Plane};

const C1: f32 = 0.01 * 0.01;
const C2: f32 = 0.03 * 0.03;

/// The SSIM of every pixel (1 where the images agree), from two luma planes.
pub(super) fn ssim_map(a: &Plane, b: &Plane) -> Plane {
    let k = gaussian(1.5, 5);
    let blur = |p: &Plane| p.convolve(&k, &k);
    let (mu_a, mu_b) = (blur(a), blur(b));
    let aa = blur(&a.zip(a, |x, y| x * y));
    let bb = blur(&b.zip(b, |x, y| x * y));
    let ab = blur(&a.zip(b, |x, y| x * y));
    let mut out = Vec::with_capacity(a.values.len());
    for i in 0..a.values.len() {
        let (ma, mb) = (mu_a.values[i], mu_b.values[i]);
        let va = aa.values[i] - ma * ma;
        let vb = bb.values[i] - mb * mb;
        let cov = ab.values[i] - ma * mb;
        out.push(
            ((2.0 * ma * mb + C1) * (2.0 * cov + C2)) / ((ma * ma + mb * mb + C1) * (va + vb + C2)),
        );
    }
    Plane::new(a.width, a.height, out)
}
