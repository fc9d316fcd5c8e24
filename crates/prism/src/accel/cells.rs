//! What the spatial subdivisions (grid, kd-tree, octree) share: primitive bounds padded so
//! that rounding cannot hide a primitive from a cell it touches, the ray's parameter span
//! through a box, and the cell-by-cell search for the nearest hit.

use super::mailbox::Mailbox;
use super::query::{HitSearch, RayQuery};
use crate::geometry::Geometry;
use crate::math::{Aabb, TraceRay, Vec3};
use crate::stats::Stats;

/// Relative padding of reference bounds, in units of the scene's coordinate magnitude.
/// It must exceed the rounding of cell boundaries, of the ray's t at a cell face and of a
/// primitive's own hit t (a few ulps each); 2⁻¹⁸ ≈ 4·10⁻⁶ leaves a wide margin and makes
/// cells only that much fuller. Being relative to the scene, it works at every scale.
const PAD: f32 = 1.0 / (1u32 << 18) as f32;

/// Bounds of each primitive in `prims`, padded by `PAD` times the scene's magnitude, and the
/// union of them all (the root cell).
///
/// Why pad: a subdivision puts a primitive in the cells its box overlaps and a ray only
/// tests what lies in the cells it walks, so a hit point that rounding places just outside
/// the primitive's cells would be lost. With the padding every primitive sits in all cells
/// within `PAD·magnitude` of it, which covers all those rounding errors.
pub(crate) fn padded_bounds(geometry: &Geometry, prims: &[u32]) -> (Vec<Aabb>, Aabb) {
    let raw: Vec<Aabb> = prims
        .iter()
        .map(|&p| geometry.bounds(p).unwrap_or(Aabb::EMPTY))
        .collect();
    let world = raw.iter().fold(Aabb::EMPTY, |a, b| a.union(b));
    if world.is_empty() {
        return (raw, world);
    }
    let magnitude = world
        .min
        .abs()
        .max(world.max.abs())
        .max_element()
        .max(world.extent().max_element());
    let pad = Vec3::splat(PAD * magnitude);
    let padded: Vec<Aabb> = raw
        .iter()
        .map(|b| Aabb {
            min: b.min - pad,
            max: b.max + pad,
        })
        .collect();
    let world = Aabb {
        min: world.min - pad,
        max: world.max + pad,
    };
    (padded, world)
}

/// The span `[t_enter, t_exit]` of the ray inside `bounds`, clipped to `[0, t_max]`
/// (`Aabb::span`).
#[inline(always)]
fn ray_span(bounds: &Aabb, ray: &TraceRay, t_max: f32) -> Option<(f32, f32)> {
    bounds.span(ray.ray.origin, ray.inv_dir, t_max)
}

/// Where the ray crosses the plane `x[axis] = position`, or infinity if it runs parallel
/// to it (including directions so small that their reciprocal overflows).
#[inline(always)]
pub(crate) fn plane_crossing(ray: &TraceRay, axis: usize, position: f32) -> f32 {
    let inv = ray.inv_dir[axis];
    if inv.is_finite() {
        (position - ray.ray.origin[axis]) * inv
    } else {
        f32::INFINITY
    }
}

/// The state of one nearest- or any-hit query as it walks cells front to back: the shared
/// `HitSearch` plus a mailbox.
///
/// Hits are kept even when they lie beyond the cell being searched (the primitive reaches
/// into later cells): the mailbox stops those primitives from being tested again, so the
/// hit must not be forgotten. The walk ends once the best hit lies no farther than the
/// current cell's exit, because everything not yet tested lies beyond that exit. That is
/// the classic "a hit only counts inside its cell" rule, without dropping hits.
pub(crate) struct CellSearch {
    pub(crate) hits: HitSearch,
    mailbox: Mailbox,
}

impl CellSearch {
    /// The search for `query`, made where the walk keeps it: returned inside `enter`'s
    /// answer it would be copied on every ray (its mailbox is 256 bytes; a memcpy per ray
    /// cost the kd-tree 5 % of a Whitted render).
    #[inline(always)]
    pub(crate) fn new(query: &RayQuery) -> Self {
        CellSearch {
            hits: HitSearch::new(query.t_max, query.mode),
            mailbox: Mailbox::new(),
        }
    }

    /// The start of a walk through cells: the span `[t_enter, t_exit]` of the ray in the
    /// structure's `bounds`; `None` where the structure is `empty` or the ray misses it.
    /// Entering counts as the root's visit, a miss included.
    #[inline(always)]
    pub(crate) fn enter(
        query: &RayQuery,
        empty: bool,
        bounds: &Aabb,
        stats: &mut Stats,
    ) -> Option<(f32, f32)> {
        if empty {
            return None;
        }
        stats.node_visits += 1;
        ray_span(bounds, query.ray, query.t_max)
    }

    /// Tests the cell's primitives; returns true when the query is answered, i.e. for an
    /// any-hit query a hit was found, or for a nearest-hit query the best hit lies before
    /// `t_exit`, the ray's exit from this cell.
    #[inline(always)]
    pub(crate) fn search_cell(
        &mut self,
        geometry: &Geometry,
        ray: &TraceRay,
        prims: &[u32],
        t_exit: f32,
        stats: &mut Stats,
    ) -> bool {
        for &prim in prims {
            if self.mailbox.first_visit(prim) && self.hits.test(geometry, ray, prim, stats) {
                return true;
            }
        }
        self.hits.settled_by(t_exit)
    }
}
