//! Traversal of a `VolumeBvh`, the same ordered stack walk as `Bvh`'s: test both children,
//! descend into the nearer, push the farther with its entry distance. The ray's per-volume
//! constants are prepared once, before the walk. Unlike `Bvh`, culling leaves a relative
//! slack (`CULL_SLACK`) for the rounding of the primitives' own hit distances.

use super::hierarchy::VolumeBvh;
use super::volume::Volume;
use crate::accel::Hit;
use crate::geometry::Geometry;
use crate::math::robust::next_up;
use crate::math::TraceRay;
use crate::stats::Stats;

/// Depth bound of the SAH build, hence of the stack.
const MAX_DEPTH: usize = 64;

pub use crate::accel::CULL_SLACK;

impl<V: Volume> VolumeBvh<V> {
    /// The ordered walk; `visit(item, limit, stats)` tests one leaf entry and returns its
    /// nearest hit before `limit` (for a sub-tree: its nearest, exact ties to the lowest
    /// primitive id). `any` stops at the first hit.
    #[inline(always)]
    pub(super) fn walk(
        &self,
        ray: &TraceRay,
        mut t_max: f32,
        stats: &mut Stats,
        any: bool,
        mut visit: impl FnMut(u32, f32, &mut Stats) -> Option<Hit>,
    ) -> Option<Hit> {
        if self.nodes.is_empty() {
            return None;
        }
        let prepared = V::prepare(ray);
        let hit =
            |i: usize, t_max: f32| self.nodes[i].volume.hit(&prepared, ray, t_max * CULL_SLACK);
        stats.node_visits += 1;
        hit(0, t_max)?;
        let mut best = None;
        let mut stack = [(0u32, 0.0f32); MAX_DEPTH];
        let mut sp = 0;
        let mut current = 0usize;
        loop {
            let node = &self.nodes[current];
            if node.is_leaf() {
                let range = node.first as usize..(node.first + node.count) as usize;
                for &item in &self.prims[range] {
                    // Exact ties go to the lower primitive id, as in the brute-force list:
                    // once something is hit, let ties at t_max through and decide here.
                    let limit = if best.is_some() {
                        next_up(t_max)
                    } else {
                        t_max
                    };
                    if let Some(h) = visit(item, limit, stats) {
                        let wins = h.t < t_max || best.is_none_or(|b: Hit| h.prim < b.prim);
                        if wins {
                            t_max = h.t;
                            best = Some(h);
                            if any {
                                return best;
                            }
                        }
                    }
                }
            } else {
                let (l, r) = (node.first as usize, node.first as usize + 1);
                stats.node_visits += 2;
                match (hit(l, t_max), hit(r, t_max)) {
                    (Some(tl), Some(tr)) => {
                        let (near, far) = if tl <= tr { (l, r) } else { (r, l) };
                        stack[sp] = (far as u32, tl.max(tr));
                        sp += 1;
                        current = near;
                        continue;
                    }
                    (Some(_), None) => {
                        current = l;
                        continue;
                    }
                    (None, Some(_)) => {
                        current = r;
                        continue;
                    }
                    (None, None) => {}
                }
            }
            loop {
                if sp == 0 {
                    return best;
                }
                sp -= 1;
                let (node, t_enter) = stack[sp];
                if t_enter <= t_max * CULL_SLACK {
                    current = node as usize;
                    break;
                }
            }
        }
    }

    /// The walk over primitives.
    #[inline(always)]
    pub(super) fn traverse(
        &self,
        geometry: &Geometry,
        ray: &TraceRay,
        t_max: f32,
        stats: &mut Stats,
        any: bool,
    ) -> Option<Hit> {
        self.walk(ray, t_max, stats, any, |prim, t_max, stats| {
            geometry
                .intersect_counted(prim, ray, t_max, stats)
                .map(|h| Hit {
                    t: h.t,
                    prim,
                    u: h.u,
                    v: h.v,
                })
        })
    }
}

crate::accel::accel_from_traverse!(impl<V: Volume> VolumeBvh<V>);
