//! The one interface every node bounding volume implements: how it is fitted to the
//! primitives below a node, what a ray precomputes once before traversal, and the ray test.

use crate::geometry::Geometry;
use crate::math::{Aabb, TraceRay, Vec3};

/// A node bounding volume: fitted conservatively, tested robustly.
pub trait Volume: Copy + Send + Sync + std::fmt::Debug + 'static {
    /// Constants a ray computes once per traversal, not once per node.
    type Ray: Copy;

    /// The per-ray constants for `ray`, once per traversal.
    fn prepare(ray: &TraceRay) -> Self::Ray;

    /// Entry distance (≥ 0, possibly underestimated, never over) if the ray may meet the
    /// volume within `[0, t_max]`. Never misses a volume whose contents the ray hits.
    fn hit(&self, ray: &Self::Ray, trace: &TraceRay, t_max: f32) -> Option<f32>;

    /// Whether `p` lies inside (boundary and padding included), decided in f64.
    fn contains(&self, p: Vec3) -> bool;

    /// A volume containing every primitive of `prims`, whose boxes' union is `bounds`.
    fn fit(geometry: &Geometry, prims: &[u32], bounds: &Aabb) -> Self;

    /// Whether `merge` of the children's volumes is as tight as fitting a node afresh
    /// (true of boxes and k-DOPs, whose slabs are maxima of support functions).
    const MERGES: bool = false;

    /// A volume containing both (only called when `MERGES`).
    fn merge(a: &Self, _b: &Self) -> Self {
        *a
    }
}

/// The largest coordinate magnitude in `bounds`: what the rounding of the primitives' own
/// intersection tests scales with.
pub(super) fn magnitude(bounds: &Aabb) -> f64 {
    bounds.min.abs().max(bounds.max.abs()).max_element() as f64
}
