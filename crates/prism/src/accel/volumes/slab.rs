//! Slab arithmetic shared by every volume bounded by planes (k-DOPs, OBBs, hulls), made
//! conservative without absolute epsilons.
//!
//! A slab is `lo ≤ n·x ≤ hi`. The ray meets it for `t` between `(lo − n·o)/(n·d)` and
//! `(hi − n·o)/(n·d)`. Three things round: `n·o` (absolute error at most γ·|n|·|o|, added
//! to the numerators), `n·d` (relative error e/|n·d|, applied to the final distances as a
//! relative widening), and the stored bounds (widened outward at build time by
//! `pad_outward`). A direction so close to parallel that `n·d` could have the wrong sign, or
//! be off by more than 2⁻¹⁰ of itself, simply does not constrain the ray: looser, never lost.

use crate::math::robust::gamma;
use glam::Vec3;

/// Relative error of `n·d` above which a slab is ignored for this ray.
const MAX_RELATIVE: f32 = 1.0 / 1024.0;

/// Roundings allowed for, in γₙ, on both sides: the ray's `n·o`, and the primitives' own
/// tests, whose hit distances err by a few γ of the vertices' distance from the origin
/// (more for thin triangles, whose barycentrics are ill-conditioned). Generous on purpose:
/// at γ₆₄ ≈ 4·10⁻⁶ of the coordinates, the padding costs no measurable tightness.
pub(super) const ROUNDINGS: u32 = 64;

/// One direction prepared for one ray: `n·o`, its error bound, and `1/(n·d)` (0 for an
/// ignored direction, whose error bound is then infinite so that both ends become NaN,
/// which the min/max reductions drop).
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct SlabAxis {
    pub origin: f32,
    pub error: f32,
    pub inv: f32,
}

impl SlabAxis {
    /// Prepares direction `n` for the ray (origin `o`, direction `d`); the second value is
    /// the relative error of `1/(n·d)`, to be applied to the distances.
    #[inline(always)]
    pub(super) fn new(n: Vec3, o: Vec3, d: Vec3) -> (SlabAxis, f32) {
        let origin = n.dot(o);
        let error = gamma(ROUNDINGS) * n.abs().dot(o.abs());
        let dn = n.dot(d);
        let e = gamma(3) * n.abs().dot(d.abs());
        if e == 0.0 {
            // n·d is exact (zero, when the ray lies parallel to the slab's planes): the
            // same closed-slab semantics as `Aabb::hit`.
            return (
                SlabAxis {
                    origin,
                    error,
                    inv: 1.0 / dn,
                },
                0.0,
            );
        }
        let margin = dn.abs() - e;
        if margin > 0.0 && e <= MAX_RELATIVE * margin {
            (
                SlabAxis {
                    origin,
                    error,
                    inv: 1.0 / dn,
                },
                e / margin,
            )
        } else {
            (
                SlabAxis {
                    origin,
                    error: f32::INFINITY,
                    inv: 0.0,
                },
                0.0,
            )
        }
    }

    /// Entry and exit distances of the slab `[lo, hi]` (either may be NaN: no constraint).
    #[inline(always)]
    pub(super) fn clip(&self, lo: f32, hi: f32) -> (f32, f32) {
        let a = (lo - self.origin - self.error) * self.inv;
        let b = (hi - self.origin + self.error) * self.inv;
        if self.inv < 0.0 {
            (b, a)
        } else {
            (a, b)
        }
    }
}

/// Combines the clipped interval `[enter, exit]` (before clamping) with `[0, t_max]`,
/// widened by `relative` (the largest relative error of the directions) plus the rounding
/// of the divisions. Returns the entry distance on a hit.
#[inline(always)]
pub(super) fn finish(enter: f32, exit: f32, t_max: f32, relative: f32) -> Option<f32> {
    let widen = relative + gamma(4);
    let t_enter = (enter * (1.0 - widen)).max(0.0);
    let t_exit = exit.min(t_max) * (1.0 + widen);
    // An infinite entry (a ray parallel to a slab, outside it) never arrives, even when
    // t_max is infinite too.
    (t_enter <= t_exit && t_enter < f32::INFINITY).then_some(t_enter)
}

/// Rounds an f64 slab `[lo, hi]` outward to f32 and widens it by γ·`scale`, where `scale`
/// bounds `|n|·|x|` over the contents: a primitive's own intersection test perturbs it by
/// a few ulps of its coordinates, and the volume must contain the perturbed shape too.
pub(super) fn pad_outward(lo: f64, hi: f64, scale: f64) -> (f32, f32) {
    let pad = gamma(ROUNDINGS) as f64 * scale;
    (round_down(lo - pad), round_up(hi + pad))
}

pub(super) fn round_up(x: f64) -> f32 {
    let y = x as f32;
    if (y as f64) < x {
        crate::math::robust::next_up(y)
    } else {
        y
    }
}

pub(super) fn round_down(x: f64) -> f32 {
    let y = x as f32;
    if (y as f64) > x {
        crate::math::robust::next_down(y)
    } else {
        y
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn outward_rounding_brackets_the_value() {
        for x in [0.1f64, -0.1, 1e-30, 3.0, -7e20] {
            assert!((round_down(x) as f64) <= x && (round_up(x) as f64) >= x);
        }
    }

    #[test]
    fn parallel_rays_inside_a_slab_are_unconstrained_and_outside_miss() {
        let n = Vec3::new(1.0, 1.0, 0.0);
        let (axis, rel) = SlabAxis::new(n, Vec3::new(0.5, 0.0, 0.0), Vec3::Z);
        assert_eq!(rel, 0.0);
        let (a, b) = axis.clip(0.0, 1.0);
        assert!(finish(a, b, f32::INFINITY, rel).is_some());
        let (a, b) = axis.clip(2.0, 3.0);
        assert!(finish(a, b, f32::INFINITY, rel).is_none());
    }

    #[test]
    fn directions_whose_dot_may_have_the_wrong_sign_do_not_constrain() {
        // n·d rounds to zero but the terms do not: the true sign is unknown.
        let d = Vec3::new(0.5, -0.5, 0.5f32.sqrt());
        let (axis, _) = SlabAxis::new(Vec3::new(1.0, 1.0, 0.0), Vec3::ZERO, d);
        let (a, b) = axis.clip(5.0, 6.0);
        assert!(a.is_nan() && b.is_nan());
    }
}
