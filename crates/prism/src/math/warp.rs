//! Warps of uniform numbers in (0, 1)² onto the domains a path tracer samples: the
//! cosine-weighted hemisphere, a cosine-power lobe, the sphere and the triangle. Each
//! comes with the density it samples, so estimators divide by exactly what they drew.

use super::lanes::{sincos, FloatLanes};
use glam::Vec3;
use std::f32::consts::{FRAC_1_PI, PI};

/// A direction about +z with density cos θ / π (Malley's method: a uniform point on the
/// disc lifted to the hemisphere), so the cosine of the rendering equation cancels.
#[inline]
pub fn cosine_hemisphere(u1: f32, u2: f32) -> Vec3 {
    let [x, y, z] = cosine_hemisphere_lanes(u1, u2);
    Vec3::new(x, y, z)
}

/// `cosine_hemisphere` lane by lane, with `lanes::sincos`: one lane is the scalar warp.
#[inline(always)]
pub(crate) fn cosine_hemisphere_lanes<L: FloatLanes>(u1: L, u2: L) -> [L; 3] {
    let r = u1.sqrt();
    let phi = L::splat(2.0 * PI) * u2;
    let z = (L::splat(1.0) - u1).max(L::splat(0.0)).sqrt();
    let (sin, cos) = sincos(phi);
    [r * cos, r * sin, z]
}

/// `cosine_hemisphere` about the unit normal `n` (in `Frame::from_z(n)`'s axes), made unit
/// again, lane by lane: exactly `Frame::from_z(n).to_world(cosine_hemisphere(u1,
/// u2)).normalize()`'s operations in its order, so that the diffuse lobe's direction in
/// lanes (the wavefront's) and in the scalar `Bsdf::sample` are the same bits.
#[inline(always)]
pub(crate) fn cosine_direction<L: FloatLanes>(n: [L; 3], u1: L, u2: L) -> [L; 3] {
    let [lx, ly, lz] = cosine_hemisphere_lanes(u1, u2);
    let [nx, ny, nz] = n;
    // Frame::from_z (Duff et al. 2017).
    let sign = L::splat(1.0).copysign(nz);
    let a = L::splat(-1.0) / (sign + nz);
    let b = nx * ny * a;
    let x = [
        L::splat(1.0) + sign * nx * nx * a,
        sign * b,
        sign.neg() * nx,
    ];
    let y = [b, sign + ny * ny * a, ny.neg()];
    // Frame::to_world, then Vec3::normalize (a multiplication by 1 / length).
    let w = [
        lx * x[0] + ly * y[0] + lz * nx,
        lx * x[1] + ly * y[1] + lz * ny,
        lx * x[2] + ly * y[2] + lz * nz,
    ];
    let inv = L::splat(1.0) / (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt();
    [w[0] * inv, w[1] * inv, w[2] * inv]
}

/// The density of `cosine_hemisphere` for a direction with cosine `cos` to +z.
#[inline]
pub fn cosine_hemisphere_pdf(cos: f32) -> f32 {
    cos.max(0.0) * FRAC_1_PI
}

/// A direction about +z with density (n + 1)/(2π)·cosⁿα, α its angle to +z: the
/// normalised Phong lobe (Lafortune and Willems 1994), n = 0 the uniform hemisphere.
#[inline]
pub fn cosine_power(u1: f32, u2: f32, n: f32) -> Vec3 {
    let cos = u1.powf(1.0 / (n + 1.0));
    let sin = (1.0 - cos * cos).max(0.0).sqrt();
    let phi = 2.0 * PI * u2;
    Vec3::new(sin * phi.cos(), sin * phi.sin(), cos)
}

/// The density of `cosine_power` for a direction at cosine `cos` to the lobe's axis.
#[inline]
pub fn cosine_power_pdf(cos: f32, n: f32) -> f32 {
    if cos <= 0.0 {
        return 0.0;
    }
    (n + 1.0) * (0.5 * FRAC_1_PI) * cos.powf(n)
}

/// A uniform direction on the unit sphere (density 1/(4π)): z uniform in [−1, 1]
/// (Archimedes' hat-box theorem).
#[inline]
pub fn uniform_sphere(u1: f32, u2: f32) -> Vec3 {
    let z = 1.0 - 2.0 * u1;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u2;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// Barycentric weights (b1, b2) of a uniform point in a triangle: the square folded by
/// the square root so that equal areas of the square map to equal areas of the triangle.
#[inline]
pub fn uniform_triangle(u1: f32, u2: f32) -> (f32, f32) {
    let s = u1.sqrt();
    (s * (1.0 - u2), s * u2)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn warped_directions_are_unit_and_on_their_side() {
        for i in 1..64 {
            for j in 1..64 {
                let (u1, u2) = (i as f32 / 64.0, j as f32 / 64.0);
                for d in [cosine_hemisphere(u1, u2), cosine_power(u1, u2, 20.0)] {
                    assert!((d.length() - 1.0).abs() < 1e-5);
                    assert!(d.z >= 0.0);
                }
                assert!((uniform_sphere(u1, u2).length() - 1.0).abs() < 1e-5);
                let (b1, b2) = uniform_triangle(u1, u2);
                assert!(b1 >= 0.0 && b2 >= 0.0 && b1 + b2 <= 1.0);
            }
        }
    }

    #[test]
    fn the_lobe_densities_integrate_to_one() {
        // Midpoint rule over θ on the hemisphere: ∫ p 2π sinθ dθ.
        let steps = 100_000;
        for n in [0.0, 1.0, 10.0, 100.0] {
            let (mut cosine, mut power) = (0.0f64, 0.0f64);
            for k in 0..steps {
                let theta = (k as f64 + 0.5) / steps as f64 * std::f64::consts::FRAC_PI_2;
                let w = 2.0 * std::f64::consts::PI * theta.sin() * std::f64::consts::FRAC_PI_2
                    / steps as f64;
                let c = theta.cos() as f32;
                cosine += cosine_hemisphere_pdf(c) as f64 * w;
                power += cosine_power_pdf(c, n) as f64 * w;
            }
            assert!((cosine - 1.0).abs() < 1e-3, "{cosine}");
            assert!((power - 1.0).abs() < 1e-3, "n = {n}: {power}");
        }
    }
}
