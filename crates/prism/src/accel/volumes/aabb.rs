//! The axis-aligned box as a node volume: the baseline the others are measured against,
//! tested exactly as `Bvh` tests it.

use super::volume::Volume;
use crate::geometry::Geometry;
use crate::math::{Aabb, TraceRay, Vec3};

impl Volume for Aabb {
    type Ray = ();

    #[inline(always)]
    fn prepare(_ray: &TraceRay) {}

    #[inline(always)]
    fn hit(&self, _: &(), trace: &TraceRay, t_max: f32) -> Option<f32> {
        Aabb::hit(self, trace.ray.origin, trace.inv_dir, t_max)
    }

    fn contains(&self, p: Vec3) -> bool {
        Aabb::contains(self, p)
    }

    fn fit(_geometry: &Geometry, _prims: &[u32], bounds: &Aabb) -> Self {
        *bounds
    }

    const MERGES: bool = true;

    fn merge(a: &Self, b: &Self) -> Self {
        a.union(b)
    }
}
