//! Floating-point error bounds and the scale-free offset of secondary-ray origins.
//!
//! A hit point computed in f32 lies near, not on, the surface. Rather than nudging it by a
//! fixed epsilon (which fails on either a millimetre or a kilometre scene), every shape
//! returns a conservative bound on the error of its hit point, in the manner of pbrt's
//! `pError`, and the new ray starts just outside that error box along the normal. Both the
//! bound and the offset scale with the coordinates, so the same scene works at any scale.

use glam::Vec3;

/// γₙ = nε / (1 − nε), the bound on the relative error of n chained f32 operations.
#[inline(always)]
pub const fn gamma(n: u32) -> f32 {
    let e = f32::EPSILON * 0.5 * n as f32;
    e / (1.0 - e)
}

/// Next representable float towards +infinity (or -infinity with `next_down`).
#[inline]
pub fn next_up(x: f32) -> f32 {
    if x.is_infinite() && x > 0.0 {
        return x;
    }
    if x == 0.0 {
        return f32::from_bits(1);
    }
    let bits = x.to_bits();
    f32::from_bits(if x > 0.0 { bits + 1 } else { bits - 1 })
}

/// The largest float below `x` (the mirror of `next_up`).
#[inline]
pub fn next_down(x: f32) -> f32 {
    -next_up(-x)
}

/// Moves `p` (with per-axis error bound `p_error`) off the surface with normal `n`, to the
/// side `towards` points to. The result is guaranteed to be on that side of the true surface
/// point, so a ray leaving from it cannot re-hit the surface at t ≈ 0.
#[inline(always)]
pub fn offset_ray_origin(p: Vec3, p_error: Vec3, n: Vec3, towards: Vec3) -> Vec3 {
    let d = n.abs().dot(p_error);
    let side = if towards.dot(n) < 0.0 { -n } else { n };
    let mut po = p + d * side;
    // Round away from p so the rounding of the addition cannot undo the offset; a zero
    // error bound (a face lying in a coordinate plane) still moves by one ulp.
    for i in 0..3 {
        if side[i] > 0.0 {
            po[i] = next_up(po[i]);
        } else if side[i] < 0.0 {
            po[i] = next_down(po[i]);
        }
    }
    po
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn next_up_and_down_step_one_ulp() {
        assert_eq!(next_up(1.0), 1.0 + f32::EPSILON);
        assert_eq!(next_down(1.0), 1.0 - f32::EPSILON / 2.0);
        assert_eq!(next_up(-1.0), -1.0 + f32::EPSILON / 2.0);
        assert_eq!(next_up(0.0), f32::from_bits(1));
        assert_eq!(next_up(-0.0), f32::from_bits(1));
        assert_eq!(next_down(0.0), -f32::from_bits(1));
        assert_eq!(next_up(f32::INFINITY), f32::INFINITY);
        assert_eq!(next_up(f32::MAX), f32::INFINITY);
        assert_eq!(next_down(f32::NEG_INFINITY), f32::NEG_INFINITY);
    }

    #[test]
    fn gamma_matches_its_definition() {
        let e = f64::from(f32::EPSILON) / 2.0;
        for n in [1u32, 3, 7] {
            let expected = n as f64 * e / (1.0 - n as f64 * e);
            assert!((gamma(n) as f64 - expected).abs() <= 1e-6 * expected);
        }
        assert!(gamma(3) < gamma(5));
    }

    #[test]
    fn offset_lands_strictly_on_the_requested_side() {
        // A point on the plane z = c with no error still moves by at least one ulp, and a
        // point with error moves past its error box, towards either side.
        for c in [1e-3f32, 1.0, 7.5, 1e3] {
            let p = Vec3::new(0.25 * c, -0.5 * c, c);
            for err in [0.0, gamma(7) * c] {
                let p_error = Vec3::splat(err);
                let up = offset_ray_origin(p, p_error, Vec3::Z, Vec3::new(0.3, 0.1, 0.9));
                let down = offset_ray_origin(p, p_error, Vec3::Z, Vec3::new(0.3, 0.1, -0.9));
                assert!(up.z > c + err, "scale {c}, error {err}: {} above", up.z);
                assert!(down.z < c - err, "scale {c}, error {err}: {} below", down.z);
            }
        }
    }
}
