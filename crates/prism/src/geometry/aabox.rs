//! Axis-aligned boxes as solid shapes (not to be confused with `Aabb`, the bounding volume).

use super::{ShapeHit, SurfacePoint};
use crate::math::robust::gamma;
use crate::math::{Aabb, Ray, TraceRay, Vec2, Vec3};

/// A solid axis-aligned box, for NFF-style blocks and walls that should stay exactly square.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AaBox {
    /// The corner with the smallest coordinates.
    pub min: Vec3,
    /// The corner with the largest coordinates.
    pub max: Vec3,
}

impl AaBox {
    /// The box spanned by two opposite corners, given in any order.
    pub fn new(a: Vec3, b: Vec3) -> Self {
        AaBox {
            min: a.min(b),
            max: a.max(b),
        }
    }

    /// Nearest face hit; `u` carries the face as `axis + 3·(max side)`.
    #[inline]
    pub fn intersect(&self, ray: &TraceRay, t_max: f32) -> Option<ShapeHit> {
        let o = ray.ray.origin;
        // Near and far planes by the sign of the direction, not by sorting the distances:
        // a ray lying in a face's plane gives NaN (0·∞) there, and sorting with min/max
        // would replace it by its ±∞ partner on both ends (see `Aabb::hit`).
        let negative = ray.inv_dir.cmplt(Vec3::ZERO);
        let near = (Vec3::select(negative, self.max, self.min) - o) * ray.inv_dir;
        let far = (Vec3::select(negative, self.min, self.max) - o) * ray.inv_dir;
        let (mut enter, mut enter_axis) = (f32::NEG_INFINITY, 0);
        let (mut exit, mut exit_axis) = (f32::INFINITY, 0);
        for a in 0..3 {
            // NaN (a ray lying in this slab's plane) never wins these comparisons, so the
            // slab does not constrain t: the box is closed.
            if near[a] > enter {
                enter = near[a];
                enter_axis = a;
            }
            if far[a] < exit {
                exit = far[a];
                exit_axis = a;
            }
        }
        if enter > exit {
            return None;
        }
        let (t, axis) = if enter > 0.0 {
            (enter, enter_axis)
        } else {
            (exit, exit_axis)
        };
        if !(t > 0.0 && t < t_max) {
            return None;
        }
        // Which side of the slab: the one the ray moves away from on entry, towards on exit.
        let max_side = if t == enter {
            negative.test(axis)
        } else {
            !negative.test(axis)
        };
        Some(ShapeHit {
            t,
            u: (axis + 3 * max_side as usize) as f32,
            v: 0.0,
        })
    }

    /// The point, normals and uv of a hit that `intersect` found, on the face it recorded.
    pub fn surface(&self, ray: &Ray, hit: &ShapeHit) -> SurfacePoint {
        let face = hit.u as usize;
        let (axis, max_side) = (face % 3, face >= 3);
        let mut p = ray.at(hit.t);
        let mut p_error = gamma(3) * (ray.origin.abs() + (hit.t * ray.dir).abs());
        // Snap onto the face: exact along the normal, which is all the offset needs.
        p[axis] = if max_side {
            self.max[axis]
        } else {
            self.min[axis]
        };
        p_error[axis] = 0.0;
        let p = p.clamp(self.min, self.max);
        let mut n = Vec3::ZERO;
        n[axis] = if max_side { 1.0 } else { -1.0 };
        let (a1, a2) = ((axis + 1) % 3, (axis + 2) % 3);
        let e = self.max - self.min;
        let uv = Vec2::new(
            (p[a1] - self.min[a1]) / e[a1].max(f32::MIN_POSITIVE),
            (p[a2] - self.min[a2]) / e[a2].max(f32::MIN_POSITIVE),
        );
        SurfacePoint::flat(p, p_error, n, uv)
    }

    /// The box as a bounding volume (its own extent).
    pub fn bounds(&self) -> Aabb {
        Aabb::new(self.min, self.max)
    }
}
