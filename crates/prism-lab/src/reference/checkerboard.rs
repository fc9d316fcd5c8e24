//! The exact box-filtered image of a checkered plane lit by ambient light alone (the
//! built-in `checkerboard`): every pixel is the area average over the pixel of the
//! radiance the pinhole camera sees, the sky where rays miss the plane.
//!
//! The integral is analytic when the camera's right vector lies in the plane and along one
//! of the checker's axes (no roll, and a yaw that is a multiple of 90° relative to the
//! squares; the built-in camera). Then a film row y sees a line of the plane at one depth,
//! and along it the checker is a square wave in the across-coordinate s, whose integral is
//! the closed form G(s) below. The row integral W(y) is piecewise affine in y, with breaks
//! where the depth coordinate or the pixel's two side edges cross a square's border, so the
//! trapezoid rule over the breaks is exact.
//!
//! Towards the horizon the breaks become infinitely many. Within Δ rows of the horizon the
//! row integral is replaced by its mean, half the row; along any row the checker's integral
//! differs from that by at most half a square, i.e. by c·|g(y)|/(2·|h·sA|) in film units,
//! which vanishes at the horizon. Integrating that bound over the band gives each pixel's
//! error bound; Δ is chosen so that the bound stays below the requested tolerance. All
//! arithmetic is in f64.

use glam::DVec3;
use prism::camera::CameraError;
use prism::geometry::Shape;
use prism::math::{Color, Frame};
use prism::render::Film;
use prism::scene::Scene;
use prism::shading::{CheckerSpace, Texture};
use rayon::prelude::*;

/// Largest error of any pixel's value (per channel, in the scene's linear units) when no
/// tolerance is given: a fortieth of a step of an 8-bit image near black, and far below the
/// sampling errors the reference is used to measure. The cost grows as 1/√tolerance, in
/// the pixels beside the horizon only.
pub const DEFAULT_TOLERANCE: f64 = 1e-4;

/// Guard against runaway work: breaks per pixel.
const MAX_BREAKS: f64 = 5e7;

/// The exact image of a checkerboard scene, with what each pixel covers and how exact it is.
#[derive(Clone, Debug)]
pub struct CheckerReference {
    /// The reference image.
    pub film: Film,
    /// Checker squares a pixel spans, along the row or in depth, whichever is more
    /// (infinite where the pixel reaches the horizon; 0 for pure sky).
    pub squares: Vec<f32>,
    /// The largest error bound of any pixel (per channel).
    pub error_bound: f64,
}

impl CheckerReference {
    /// Pixels whose squares are smaller than half a pixel: the checker's period (two
    /// squares) is shorter than a pixel, beyond what one sample per pixel can resolve.
    pub fn far_field(&self) -> Vec<bool> {
        self.squares.iter().map(|&s| s >= 2.0).collect()
    }
}

/// Why no reference could be computed.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum ReferenceError {
    /// The scene is not one this reference can compute.
    #[error("no exact reference for this scene: {0}")]
    Unsupported(String),
    /// The scene's camera makes no rays.
    #[error(transparent)]
    Camera(#[from] CameraError),
    /// The tolerance asked for is not positive.
    #[error("the tolerance must be a positive number, got {0}")]
    Tolerance(f64),
}

/// The reference image of `scene` at `width` × `height`, each pixel within `tolerance` of
/// the exact area average.
pub fn checkerboard(
    scene: &Scene,
    width: u32,
    height: u32,
    tolerance: f64,
) -> Result<CheckerReference, ReferenceError> {
    if !(tolerance > 0.0 && tolerance.is_finite()) {
        return Err(ReferenceError::Tolerance(tolerance));
    }
    let setup = Setup::new(scene, width, height, tolerance)?;
    // Per pixel, not per row: the rows beside the horizon cost far more than the others.
    let pixels: Vec<Result<PixelValue, ReferenceError>> = (0..width * height)
        .into_par_iter()
        .map(|i| setup.pixel((i % width) as f64, (i / width) as f64))
        .collect();
    let mut film = Film::new(width, height);
    let mut squares = Vec::with_capacity(pixels.len());
    let mut error_bound: f64 = 0.0;
    for (p, slot) in pixels.into_iter().zip(film.pixels.iter_mut()) {
        let p = p?;
        *slot = p.value;
        squares.push(p.squares as f32);
        error_bound = error_bound.max(p.bound);
    }
    Ok(CheckerReference {
        film,
        squares,
        error_bound,
    })
}

struct PixelValue {
    value: Color,
    squares: f64,
    bound: f64,
}

/// The scene reduced to the numbers of the closed form. Film row y, column x: the ray
/// direction's plane-normal component is g(y) = g0 + g1·y; the hit is t = h/g(y) along it;
/// the across-coordinate (in squares) is s(x, y) = (α0 + h·(kA0 + kA1·y + (x − W/2)·sA)/g)/c
/// and the depth coordinate β(y)/c = (β0 + h·(kB0 + kB1·y)/g)/c.
struct Setup {
    g0: f64,
    g1: f64,
    h: f64,
    s_a: f64,
    k_a: [f64; 2],
    alpha0: f64,
    k_b: [f64; 2],
    beta0: f64,
    c: f64,
    half_width: f64,
    white: DVec3,
    black: DVec3,
    sky: DVec3,
    /// Half-width Δ of the band beside the horizon where rows take their mean.
    band: f64,
    /// Bound per unit of ∫|g|dy over the band: largest colour difference · c/(2|h·sA|).
    bound_scale: f64,
}

fn unsupported(why: &str) -> ReferenceError {
    ReferenceError::Unsupported(why.to_string())
}

impl Setup {
    fn new(scene: &Scene, width: u32, height: u32, tolerance: f64) -> Result<Self, ReferenceError> {
        scene.camera.validate()?;
        let [prim] = scene.geometry.primitives.as_slice() else {
            return Err(unsupported(
                "the scene must hold exactly one shape, a plane",
            ));
        };
        let Shape::Plane(plane) = &prim.shape else {
            return Err(unsupported("the scene's shape is not a plane"));
        };
        let material = scene
            .materials
            .get(prim.material as usize)
            .ok_or_else(|| unsupported("the plane has no material"))?;
        let Texture::Checker(checker) = &material.color else {
            return Err(unsupported("the plane's colour is not a checker texture"));
        };
        if checker.space != CheckerSpace::Uv {
            return Err(unsupported("the checker must be in uv space"));
        }
        if !scene.lights.is_empty() && (material.diffuse > 0.0 || material.specular > 0.0) {
            return Err(unsupported(
                "the plane must be lit by ambient light alone (lights with kd or ks > 0)",
            ));
        }
        if material.reflect > 0.0 || material.is_transmissive() {
            return Err(unsupported("the plane must neither reflect nor transmit"));
        }
        let d = |v: prism::math::Vec3| DVec3::new(v.x as f64, v.y as f64, v.z as f64);
        let frame = Frame::from_z(plane.normal());
        let (n, ex, ey, p0) = (d(frame.z), d(frame.x), d(frame.y), d(plane.point));

        // The camera exactly as `Camera::setup` builds it, in f64.
        let cam = &scene.camera;
        let eye = d(cam.eye);
        let forward = (d(cam.look_at) - eye).normalize();
        let right = forward.cross(d(cam.up)).normalize();
        let up = right.cross(forward);
        let pixel = 2.0 * ((cam.fov_degrees as f64).to_radians() * 0.5).tan()
            / width.min(height).max(1) as f64;
        let (half_w, half_h) = (width as f64 * 0.5, height as f64 * 0.5);

        let flat = 1e-9;
        if right.dot(n).abs() > flat {
            return Err(unsupported(
                "the camera's right vector must lie in the plane (no roll)",
            ));
        }
        // `across` runs along film rows, `depth` across them.
        let (across, depth) = if right.dot(ey).abs() <= flat {
            (ex, ey)
        } else if right.dot(ex).abs() <= flat {
            (ey, ex)
        } else {
            return Err(unsupported(
                "the camera's right vector must run along one of the checker's axes",
            ));
        };

        // Direction at (x, y): forward + (x − W/2)·pixel·right + (H/2 − y)·pixel·up.
        let comp = |axis: DVec3| {
            // (constant, per-y) parts of the direction's component along `axis`.
            let u = pixel * up.dot(axis);
            [forward.dot(axis) + half_h * u, -u]
        };
        let [g0, g1] = comp(n);
        let h = n.dot(p0 - eye);
        let s_a = pixel * right.dot(across);
        let k_a = comp(across);
        let k_b = comp(depth);
        let c = checker.size as f64;
        let ka = material.ambient as f64;
        let ia = d(scene.ambient);
        let white = ka * ia * d(checker.a);
        let black = ka * ia * d(checker.b);
        let largest = (white - black).abs().max_element();
        let bound_scale = largest * c / (2.0 * (h * s_a).abs());
        // ∫ over the band of |g| = |g1|·Δ²/2, so the band's bound is bound_scale·|g1|·Δ²/2.
        let band = if g1 == 0.0 || bound_scale == 0.0 {
            0.0
        } else {
            (2.0 * tolerance / (bound_scale * g1.abs())).sqrt()
        };
        Ok(Setup {
            g0,
            g1,
            h,
            s_a,
            k_a,
            alpha0: across.dot(eye - p0),
            k_b,
            beta0: depth.dot(eye - p0),
            c,
            half_width: half_w,
            white,
            black,
            sky: d(scene.background),
            band,
            bound_scale,
        })
    }

    fn g(&self, y: f64) -> f64 {
        self.g0 + self.g1 * y
    }

    /// Across-coordinate in squares at film (x, y).
    fn s(&self, x: f64, y: f64) -> f64 {
        let k = self.k_a[0] + self.k_a[1] * y + (x - self.half_width) * self.s_a;
        (self.alpha0 + self.h * k / self.g(y)) / self.c
    }

    /// Depth coordinate in squares at film row y.
    fn depth(&self, y: f64) -> f64 {
        (self.beta0 + self.h * (self.k_b[0] + self.k_b[1] * y) / self.g(y)) / self.c
    }

    /// Length of film row y, between x0 and x0 + 1, that sees white squares.
    fn white_in_row(&self, x0: f64, y: f64, parity: i64) -> f64 {
        let (s0, s1) = (self.s(x0, y), self.s(x0 + 1.0, y));
        let g = |s: f64| if parity == 0 { even(s) } else { s - even(s) };
        // |ds/dx| = |h·sA/(c·g)|: film length per square is its inverse.
        let per_square = self.c * self.g(y).abs() / (self.h * self.s_a).abs();
        per_square * (g(s1) - g(s0)).abs()
    }

    /// The visible part of rows [y0, y1]: hit points in front of the eye.
    fn visible(&self, y0: f64, y1: f64) -> Option<(f64, f64)> {
        let sees = |y: f64| {
            let g = self.g(y);
            g != 0.0 && g.signum() == self.h.signum()
        };
        if self.g1 == 0.0 {
            return sees(0.5 * (y0 + y1)).then_some((y0, y1));
        }
        let horizon = -self.g0 / self.g1;
        let (lo, hi) = if sees(horizon + 1.0) {
            (y0.max(horizon), y1)
        } else {
            (y0, y1.min(horizon))
        };
        (lo < hi).then_some((lo, hi))
    }

    fn pixel(&self, x0: f64, y0: f64) -> Result<PixelValue, ReferenceError> {
        let sky_only = PixelValue {
            value: to_color(self.sky),
            squares: 0.0,
            bound: 0.0,
        };
        if self.h == 0.0 {
            return Ok(sky_only);
        }
        let Some((lo, hi)) = self.visible(y0, y0 + 1.0) else {
            return Ok(sky_only);
        };
        let seen = hi - lo;
        // Split off the band beside the horizon.
        let (mut exact, mut band_len, mut bound) = ((lo, hi), 0.0, 0.0);
        if self.g1 != 0.0 && self.band > 0.0 {
            let horizon = -self.g0 / self.g1;
            let (near, far) = if lo >= horizon {
                (lo - horizon, hi - horizon)
            } else {
                (horizon - hi, horizon - lo)
            };
            let band_far = far.min(self.band);
            if near < self.band {
                band_len = band_far - near;
                bound =
                    self.bound_scale * self.g1.abs() * (band_far * band_far - near * near) / 2.0;
                exact = if lo >= horizon {
                    (horizon + band_far, hi)
                } else {
                    (lo, horizon - band_far)
                };
            }
        }
        let mut white = 0.5 * band_len;
        let mut squares: f64 = if band_len > 0.0 { f64::INFINITY } else { 0.0 };
        if exact.1 > exact.0 {
            let (ya, yb) = exact;
            white += self.white_exact(x0, ya, yb)?;
            let across = (self.s(x0 + 1.0, ya) - self.s(x0, ya))
                .abs()
                .max((self.s(x0 + 1.0, yb) - self.s(x0, yb)).abs());
            squares = squares
                .max(across)
                .max((self.depth(yb) - self.depth(ya)).abs());
        }
        let value = self.sky * (1.0 - seen) + self.black * seen + (self.white - self.black) * white;
        Ok(PixelValue {
            value: to_color(value),
            squares,
            bound,
        })
    }

    /// ∫ white length dy over rows [ya, yb] (all visible, clear of the horizon): exact.
    fn white_exact(&self, x0: f64, ya: f64, yb: f64) -> Result<f64, ReferenceError> {
        let mut breaks = vec![ya];
        let c = self.c;
        // Depth crossings, then the two side edges' across crossings.
        self.crossings(
            [self.h * self.k_b[0] / c, self.h * self.k_b[1] / c],
            self.beta0 / c,
            ya,
            yb,
            &mut breaks,
        )?;
        for x in [x0, x0 + 1.0] {
            let k0 = self.k_a[0] + (x - self.half_width) * self.s_a;
            self.crossings(
                [self.h * k0 / c, self.h * self.k_a[1] / c],
                self.alpha0 / c,
                ya,
                yb,
                &mut breaks,
            )?;
        }
        breaks.push(yb);
        breaks.sort_by(f64::total_cmp);
        let mut total = 0.0;
        for pair in breaks.windows(2) {
            let (a, b) = (pair[0], pair[1]);
            if b <= a {
                continue;
            }
            let parity = (self.depth(0.5 * (a + b)).floor() as i64).rem_euclid(2);
            total += 0.5
                * (b - a)
                * (self.white_in_row(x0, a, parity) + self.white_in_row(x0, b, parity));
        }
        Ok(total)
    }

    /// Rows in (ya, yb) where (p0 + p1·y)/g(y) + q crosses an integer, appended to `out`.
    fn crossings(
        &self,
        p: [f64; 2],
        q: f64,
        ya: f64,
        yb: f64,
        out: &mut Vec<f64>,
    ) -> Result<(), ReferenceError> {
        let f = |y: f64| (p[0] + p[1] * y) / self.g(y) + q;
        let (fa, fb) = (f(ya), f(yb));
        let (lo, hi) = (fa.min(fb), fa.max(fb));
        if !(hi - lo).is_finite() || hi - lo > MAX_BREAKS {
            return Err(unsupported(
                "a pixel spans too many squares for the exact integral; give a larger tolerance",
            ));
        }
        let first = lo.floor() as i64 + 1;
        let last = hi.ceil() as i64 - 1;
        // f is monotonic between ya and yb: visit the integers in the order y increases, so
        // each family is one ascending run and sorting the breaks is a cheap merge.
        let row = |n: i64| {
            let m = n as f64 - q;
            let y = (m * self.g0 - p[0]) / (p[1] - m * self.g1);
            y.is_finite().then(|| y.clamp(ya, yb))
        };
        if fa <= fb {
            out.extend((first..=last).filter_map(row));
        } else {
            out.extend((first..=last).rev().filter_map(row));
        }
        Ok(())
    }
}

/// ∫₀ˢ [⌊σ⌋ even] dσ, for any real s (negative s gives minus the measure on [s, 0]).
fn even(s: f64) -> f64 {
    let n = (s * 0.5).floor();
    n + (s - 2.0 * n).min(1.0)
}

fn to_color(v: DVec3) -> Color {
    Color::new(v.x as f32, v.y as f32, v.z as f32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_even_measure_is_an_antiderivative_of_the_square_wave() {
        for i in -400..400 {
            let s = i as f64 * 0.0137;
            let ds = 1e-6;
            let slope = (even(s + ds) - even(s)) / ds;
            let expected = if (s.floor() as i64).rem_euclid(2) == 0 {
                1.0
            } else {
                0.0
            };
            // Away from the integers the slope is the indicator.
            if (s - s.round()).abs() > 1e-5 {
                assert!((slope - expected).abs() < 1e-6, "s {s}: slope {slope}");
            }
        }
        assert_eq!(even(0.0), 0.0);
        assert_eq!(even(2.0), 1.0);
        assert_eq!(even(3.5), 2.0);
        assert_eq!(even(-1.5), -0.5);
    }
}
