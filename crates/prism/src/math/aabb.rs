//! Axis-aligned bounding boxes: the bounding volume of the BVH and the grid.

use super::robust::gamma;
use glam::Vec3;

/// An axis-aligned bounding box; the empty box (`Default`) has `min > max`, so any union with it is
/// the other box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// The corner with the smallest coordinates.
    pub min: Vec3,
    /// The corner with the largest coordinates.
    pub max: Vec3,
}

impl Default for Aabb {
    fn default() -> Self {
        Self::EMPTY
    }
}

impl Aabb {
    /// The identity of `union`: contains nothing.
    pub const EMPTY: Aabb = Aabb {
        min: Vec3::splat(f32::INFINITY),
        max: Vec3::splat(f32::NEG_INFINITY),
    };

    /// The box spanned by two opposite corners, given in any order.
    pub fn new(a: Vec3, b: Vec3) -> Self {
        Aabb {
            min: a.min(b),
            max: a.max(b),
        }
    }

    /// The box of a single point (zero extent).
    pub fn from_point(p: Vec3) -> Self {
        Aabb { min: p, max: p }
    }

    /// The smallest box holding every point; empty for no points.
    pub fn from_points(points: impl IntoIterator<Item = Vec3>) -> Self {
        points
            .into_iter()
            .fold(Aabb::EMPTY, |b, p| b.union_point(p))
    }

    /// Whether the box holds no point at all (`min > max` on some axis).
    pub fn is_empty(&self) -> bool {
        self.min.x > self.max.x || self.min.y > self.max.y || self.min.z > self.max.z
    }

    /// The smallest box holding both boxes.
    pub fn union(&self, o: &Aabb) -> Aabb {
        Aabb {
            min: self.min.min(o.min),
            max: self.max.max(o.max),
        }
    }

    /// The smallest box holding this box and `p`.
    pub fn union_point(&self, p: Vec3) -> Aabb {
        Aabb {
            min: self.min.min(p),
            max: self.max.max(p),
        }
    }

    /// Size along each axis.
    pub fn extent(&self) -> Vec3 {
        self.max - self.min
    }

    /// The centre point.
    pub fn center(&self) -> Vec3 {
        0.5 * (self.min + self.max)
    }

    /// The axis (0, 1, 2) along which the box is longest.
    pub fn longest_axis(&self) -> usize {
        let e = self.extent();
        if e.x >= e.y && e.x >= e.z {
            0
        } else if e.y >= e.z {
            1
        } else {
            2
        }
    }

    /// Volume (0 for an empty or flat box).
    pub fn volume(&self) -> f32 {
        if self.is_empty() {
            return 0.0;
        }
        let e = self.extent();
        e.x * e.y * e.z
    }

    /// Surface area, the probability weight of the surface area heuristic (0 for an empty box).
    pub fn surface_area(&self) -> f32 {
        if self.is_empty() {
            return 0.0;
        }
        let e = self.extent();
        2.0 * (e.x * e.y + e.y * e.z + e.z * e.x)
    }

    /// Whether `p` lies inside or on the boundary.
    pub fn contains(&self, p: Vec3) -> bool {
        p.cmpge(self.min).all() && p.cmple(self.max).all()
    }

    /// Slab test against `[0, t_max]`. Returns the entry distance on a hit.
    ///
    /// The far distance is widened by 2γ₃ (pbrt's bound on the rounding of the slab
    /// arithmetic) so a ray that touches a box edge is never lost to rounding, at any scale.
    ///
    /// Each slab's near and far planes are picked by the sign of the direction rather than by
    /// comparing the two distances. A ray lying in a slab's plane then makes 0·∞ = NaN on
    /// exactly one side, which the NaN-ignoring `f32::max`/`min` reductions drop, so that
    /// slab does not constrain t: the box is closed and the ray touches it. (Sorting the pair
    /// with `min`/`max` would drop the NaN too early and keep the ±∞ partner as both ends,
    /// missing the box.) An empty box has near > far on every axis and is never hit.
    #[inline(always)]
    pub fn hit(&self, origin: Vec3, inv_dir: Vec3, t_max: f32) -> Option<f32> {
        self.span(origin, inv_dir, t_max)
            .map(|(t_enter, _)| t_enter)
    }

    /// The slab test of `hit`, returning the span `[t_enter, t_exit]` of the ray inside
    /// the box (the exit widened as `hit` says): what a walk through cells needs.
    #[inline(always)]
    pub fn span(&self, origin: Vec3, inv_dir: Vec3, t_max: f32) -> Option<(f32, f32)> {
        let negative = inv_dir.cmplt(Vec3::ZERO);
        let near_plane = Vec3::select(negative, self.max, self.min);
        let far_plane = Vec3::select(negative, self.min, self.max);
        let near = (near_plane - origin) * inv_dir;
        let far = (far_plane - origin) * inv_dir;
        let t_enter = near.x.max(near.y).max(near.z).max(0.0);
        let t_exit = far.x.min(far.y).min(far.z).min(t_max) * (1.0 + 2.0 * gamma(3));
        (t_enter <= t_exit).then_some((t_enter, t_exit))
    }
}
