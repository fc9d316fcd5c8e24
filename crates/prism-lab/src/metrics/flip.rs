//! LDR-FLIP (Andersson, Nilsson, Akenine-Möller, Oskarsson, Åström and Fairchild, "FLIP: A
//! Difference Evaluator for Alternating Images", HPG 2020): the perceived difference, per
//! pixel in [0, 1], between two images flipped back and forth on a screen seen from a
//! given number of pixels per degree of visual angle.
//!
//! Written from the paper's description. The colour pipeline: both images, as displayed
//! (linear values clamped to [0, 1]), go to the opponent space YyCxCz, are filtered by
//! contrast sensitivity functions (sums of Gaussians), go back to linear RGB and then to
//! CIELAB with the Hunt adjustment; their HyAB distance is raised to qc = 0.7 and mapped to
//! [0, 1]. The feature pipeline: edges and points (first and second Gaussian derivatives,
//! σ = ½·0.082° in pixels) of the luminance; their largest difference, raised to qf = 0.5,
//! sharpens the colour error: FLIP = ΔE_c^(1 − ΔE_f).

use super::convolve::{gaussian, Plane};
use prism::math::Color;
use std::f32::consts::PI;

/// Pixels per degree for a 0.7 m wide, 3840-pixel monitor seen from 0.7 m (the paper's
/// default observer).
pub const DEFAULT_PPD: f32 = 67.0;

const QC: f32 = 0.7;
const QF: f32 = 0.5;
const PC: f32 = 0.4;
const PT: f32 = 0.95;
/// Width in degrees of the features the edge and point detectors look for.
const FEATURE_WIDTH: f32 = 0.082;

/// Contrast sensitivity per opponent channel as (a, b) terms of Gaussians a·√(π/b)·
/// exp(−π²x²/b), x in degrees: achromatic, red–green, blue–yellow.
const CSF: [&[(f32, f32)]; 3] = [
    &[(1.0, 0.0047)],
    &[(1.0, 0.0053)],
    &[(34.1, 0.04), (13.5, 0.025)],
];
/// The widest b, which sets every channel's kernel radius.
const CSF_B_MAX: f32 = 0.04;

/// XYZ of linear-RGB white (D65): the reference white.
const WHITE: [f32; 3] = [0.950_470_6, 1.0, 1.088_830_1];

fn rgb_to_xyz(c: [f32; 3]) -> [f32; 3] {
    let [r, g, b] = c;
    [
        0.412_456_4 * r + 0.357_576_1 * g + 0.180_437_5 * b,
        0.212_672_9 * r + 0.715_152_2 * g + 0.072_175 * b,
        0.019_333_9 * r + 0.119_192 * g + 0.950_304_1 * b,
    ]
}

fn xyz_to_rgb(c: [f32; 3]) -> [f32; 3] {
    let [x, y, z] = c;
    [
        3.240_454_2 * x - 1.537_138_5 * y - 0.498_531_4 * z,
        -0.969_266 * x + 1.876_010_8 * y + 0.041_556 * z,
        0.055_643_4 * x - 0.204_025_9 * y + 1.057_225_2 * z,
    ]
}

fn xyz_to_ycxcz(c: [f32; 3]) -> [f32; 3] {
    let [x, y, z] = [c[0] / WHITE[0], c[1] / WHITE[1], c[2] / WHITE[2]];
    [116.0 * y - 16.0, 500.0 * (x - y), 200.0 * (y - z)]
}

fn ycxcz_to_xyz(c: [f32; 3]) -> [f32; 3] {
    let y = (c[0] + 16.0) / 116.0;
    let x = c[1] / 500.0 + y;
    let z = y - c[2] / 200.0;
    [x * WHITE[0], y * WHITE[1], z * WHITE[2]]
}

/// CIELAB with the Hunt adjustment (a and b scaled by 0.01·L), from linear RGB.
fn hunt_lab(rgb: [f32; 3]) -> [f32; 3] {
    let xyz = rgb_to_xyz(rgb);
    let f = |t: f32| {
        let d = 6.0f32 / 29.0;
        if t > d * d * d {
            t.cbrt()
        } else {
            t / (3.0 * d * d) + 4.0 / 29.0
        }
    };
    let (fx, fy, fz) = (
        f(xyz[0] / WHITE[0]),
        f(xyz[1] / WHITE[1]),
        f(xyz[2] / WHITE[2]),
    );
    let l = 116.0 * fy - 16.0;
    [
        l,
        0.01 * l * 500.0 * (fx - fy),
        0.01 * l * 200.0 * (fy - fz),
    ]
}

fn hyab(a: [f32; 3], b: [f32; 3]) -> f32 {
    (a[0] - b[0]).abs() + ((a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// The FLIP error of every pixel of `test` against `reference` (same size, linear RGB),
/// for a viewer at `ppd` pixels per degree.
pub fn flip_map(
    reference: &[Color],
    test: &[Color],
    width: usize,
    height: usize,
    ppd: f32,
) -> Plane {
    let display = |img: &[Color]| -> Vec<[f32; 3]> {
        img.iter()
            .map(|c| {
                c.to_array()
                    .map(|v| if v.is_nan() { 0.0 } else { v.clamp(0.0, 1.0) })
            })
            .collect()
    };
    let (r, t) = (display(reference), display(test));
    let colour_r = filtered_lab(&r, width, height, ppd);
    let colour_t = filtered_lab(&t, width, height, ppd);
    let (edges_r, points_r) = features(&r, width, height, ppd);
    let (edges_t, points_t) = features(&t, width, height, ppd);

    let cmax = hyab(hunt_lab([0.0, 1.0, 0.0]), hunt_lab([0.0, 0.0, 1.0])).powf(QC);
    let values = (0..width * height)
        .map(|i| {
            let e = hyab(colour_r[i], colour_t[i]).powf(QC);
            let colour = if e < PC * cmax {
                PT / (PC * cmax) * e
            } else {
                PT + (e - PC * cmax) / (cmax - PC * cmax) * (1.0 - PT)
            };
            let feature = (std::f32::consts::FRAC_1_SQRT_2
                * (edges_r.values[i] - edges_t.values[i])
                    .abs()
                    .max((points_r.values[i] - points_t.values[i]).abs()))
            .min(1.0)
            .powf(QF);
            colour.powf(1.0 - feature)
        })
        .collect();
    Plane::new(width, height, values)
}

/// The image through the contrast sensitivity filters, as Hunt-adjusted CIELAB.
fn filtered_lab(rgb: &[[f32; 3]], width: usize, height: usize, ppd: f32) -> Vec<[f32; 3]> {
    let opponent: Vec<[f32; 3]> = rgb.iter().map(|&c| xyz_to_ycxcz(rgb_to_xyz(c))).collect();
    let radius = (3.0 * (CSF_B_MAX / (2.0 * PI * PI)).sqrt() * ppd).ceil() as usize;
    let channels: Vec<Plane> = (0..3)
        .map(|ch| {
            let plane = Plane::new(width, height, opponent.iter().map(|c| c[ch]).collect());
            csf_filter(&plane, CSF[ch], radius, ppd)
        })
        .collect();
    (0..width * height)
        .map(|i| {
            let ycxcz = [
                channels[0].values[i],
                channels[1].values[i],
                channels[2].values[i],
            ];
            hunt_lab(xyz_to_rgb(ycxcz_to_xyz(ycxcz)).map(|v| v.clamp(0.0, 1.0)))
        })
        .collect()
}

/// Convolution with Σ a·√(π/b)·exp(−π²r²/b), normalised to sum to one over the window.
/// Each Gaussian term is separable; the terms are filtered apart and added.
fn csf_filter(plane: &Plane, terms: &[(f32, f32)], radius: usize, ppd: f32) -> Plane {
    let kernels: Vec<(f32, Vec<f32>)> = terms
        .iter()
        .map(|&(a, b)| {
            let k: Vec<f32> = (0..=2 * radius)
                .map(|i| {
                    let x = (i as f32 - radius as f32) / ppd;
                    (-PI * PI * x * x / b).exp()
                })
                .collect();
            (a * (PI / b).sqrt(), k)
        })
        .collect();
    let total: f32 = kernels
        .iter()
        .map(|(amp, k)| amp * k.iter().sum::<f32>().powi(2))
        .sum();
    let mut out = Plane::new(plane.width, plane.height, vec![0.0; plane.values.len()]);
    for (amp, k) in &kernels {
        let filtered = plane.convolve(k, k);
        let w = amp / total;
        for (o, v) in out.values.iter_mut().zip(filtered.values) {
            *o += w * v;
        }
    }
    out
}

/// Edge and point strengths of the luminance: magnitudes of the Gaussian's first and
/// second derivatives, each kernel scaled so its positive weights sum to 1 and its
/// negative weights to −1.
fn features(rgb: &[[f32; 3]], width: usize, height: usize, ppd: f32) -> (Plane, Plane) {
    let luminance = Plane::new(
        width,
        height,
        rgb.iter().map(|&c| rgb_to_xyz(c)[1]).collect(),
    );
    let sigma = 0.5 * FEATURE_WIDTH * ppd;
    let radius = (3.0 * sigma).ceil() as usize;
    let g = gaussian(sigma, radius);
    let xs = (0..=2 * radius).map(|i| i as f32 - radius as f32);
    let shape = |x: f32| (-x * x / (2.0 * sigma * sigma)).exp();
    let first = balanced(xs.clone().map(|x| -x * shape(x)).collect());
    let second = balanced(
        xs.map(|x| (x * x / (sigma * sigma) - 1.0) * shape(x))
            .collect(),
    );
    let magnitude = |d: &[f32]| {
        let gx = luminance.convolve(d, &g);
        let gy = luminance.convolve(&g, d);
        gx.zip(&gy, |a, b| (a * a + b * b).sqrt())
    };
    (magnitude(&first), magnitude(&second))
}

/// Scales the positive weights to sum 1 and the negative ones to sum −1.
fn balanced(k: Vec<f32>) -> Vec<f32> {
    let pos: f32 = k.iter().filter(|&&v| v > 0.0).sum();
    let neg: f32 = -k.iter().filter(|&&v| v < 0.0).sum::<f32>();
    k.into_iter()
        .map(|v| if v > 0.0 { v / pos } else { v / neg })
        .collect()
}
