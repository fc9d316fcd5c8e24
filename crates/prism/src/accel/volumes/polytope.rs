//! A convex polytope as a ray volume: a set of half-spaces `n·x ≤ w`, clipped against the
//! ray one plane at a time (Cyrus–Beck): planes the ray runs towards bound its exit, planes
//! it runs away from bound its entry. Fitted from a convex hull's faces with offsets taken
//! from the contents' support functions, so rounding in the hull cannot cut anything off.

use super::hull::HalfSpace;
use super::slab::{finish, round_up, SlabAxis, ROUNDINGS};
use crate::math::robust::gamma;
use crate::math::{TraceRay, Vec3};
use glam::DVec3;
use rayon::prelude::*;

#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Plane {
    pub normal: Vec3,
    pub offset: f32,
}

/// Stores `planes` in f32 for contents whose support function is `support` and whose
/// coordinates are at most `magnitude`: each offset is recomputed for the rounded normal
/// and padded like every other volume's slabs.
pub(super) fn store_planes(
    planes: &[HalfSpace],
    support: impl Fn(DVec3) -> f64 + Sync,
    magnitude: f64,
) -> Vec<Plane> {
    // In parallel: a hull of a big mesh has thousands of faces, each a pass over its points.
    planes
        .par_iter()
        .map(|p| {
            let normal = p.normal.as_vec3();
            let n = normal.as_dvec3();
            let pad = gamma(ROUNDINGS) as f64 * magnitude * n.abs().element_sum();
            Plane {
                normal,
                offset: round_up(support(n) + pad),
            }
        })
        .collect()
}

/// Entry distance if the ray may meet the polytope `planes` within `[0, t_max]`.
#[inline]
pub(super) fn hit_polytope(planes: &[Plane], ray: &TraceRay, t_max: f32) -> Option<f32> {
    let (o, d) = (ray.ray.origin, ray.ray.dir);
    // The widest any finished interval can be widened: early exits must allow for it.
    let most = 1.0 / 1024.0 + gamma(4);
    let (mut enter, mut exit, mut relative) = (0.0f32, t_max, 0.0f32);
    for p in planes {
        let (axis, r) = SlabAxis::new(p.normal, o, d);
        if axis.inv == 0.0 {
            // Too close to parallel to tell: no constraint.
            continue;
        }
        let num = p.offset - axis.origin + axis.error;
        if axis.inv.is_infinite() {
            // Exactly parallel: inside the plane's half-space or never.
            if num < 0.0 {
                return None;
            }
            continue;
        }
        let t = num * axis.inv;
        if axis.inv > 0.0 {
            exit = exit.min(t);
        } else {
            enter = enter.max(t);
        }
        relative = relative.max(r);
        if enter * (1.0 - most) > exit * (1.0 + most) {
            return None;
        }
    }
    finish(enter, exit, t_max, relative)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Ray;

    fn unit_cube() -> Vec<Plane> {
        [Vec3::X, Vec3::Y, Vec3::Z, -Vec3::X, -Vec3::Y, -Vec3::Z]
            .map(|n| Plane {
                normal: n,
                offset: 1.0,
            })
            .to_vec()
    }

    #[test]
    fn clips_a_cube_like_a_slab_test() {
        let cube = unit_cube();
        let ray = TraceRay::new(Ray::new(Vec3::new(-3.0, 0.5, 0.2), Vec3::X));
        let t = hit_polytope(&cube, &ray, f32::INFINITY).unwrap();
        // Entry before 2 by the padding for the origin's rounding, a few 10⁻⁶ of |o|.
        assert!(t <= 2.0 && t > 2.0 - 1e-4, "{t}");
        assert!(hit_polytope(&cube, &ray, 1.5).is_none());
        let away = TraceRay::new(Ray::new(Vec3::new(-3.0, 0.5, 0.2), -Vec3::X));
        assert!(hit_polytope(&cube, &away, f32::INFINITY).is_none());
        let beside = TraceRay::new(Ray::new(Vec3::new(-3.0, 1.5, 0.2), Vec3::X));
        assert!(hit_polytope(&cube, &beside, f32::INFINITY).is_none());
        let inside = TraceRay::new(Ray::new(Vec3::ZERO, Vec3::new(0.6, 0.0, 0.8)));
        assert_eq!(hit_polytope(&cube, &inside, f32::INFINITY), Some(0.0));
    }
}
