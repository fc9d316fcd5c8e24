//! Traversal of a `VolumeBvh`, the same ordered stack walk as `Bvh`'s: test both children,
//! descend into the nearer, push the farther with its entry distance. The ray's per-volume
//! constants are prepared once, before the walk. Unlike `Bvh`, culling leaves a relative
//! slack (`CULL_SLACK`) for the rounding of the primitives' own hit distances.

use super::hierarchy::VolumeBvh;
use super::volume::Volume;
use crate::accel::query::HitSearch;
use crate::accel::stack::TraversalStack;
use crate::accel::{Accel, AccelInfo, Hit, QueryMode, RayQuery};
use crate::math::TraceRay;
use crate::stats::Stats;

/// Depth bound of the SAH build, hence of the stack.
const MAX_DEPTH: usize = 64;

pub use crate::accel::CULL_SLACK;

impl<V: Volume> VolumeBvh<V> {
    /// The ordered walk; `visit(item, search, stats)` tests one leaf entry (a primitive,
    /// or for `ObjectHulls` a whole object) into `search` and returns true when the query
    /// is answered.
    #[inline(always)]
    pub(super) fn walk(
        &self,
        ray: &TraceRay,
        t_max: f32,
        mode: QueryMode,
        stats: &mut Stats,
        mut visit: impl FnMut(u32, &mut HitSearch, &mut Stats) -> bool,
    ) -> Option<Hit> {
        if self.nodes.is_empty() {
            return None;
        }
        let prepared = V::prepare(ray);
        let hit =
            |i: usize, t_max: f32| self.nodes[i].volume.hit(&prepared, ray, t_max * CULL_SLACK);
        stats.node_visits += 1;
        hit(0, t_max)?;
        let mut search = HitSearch::new(t_max, mode);
        // Far children still to search, with the distance where the ray enters them.
        let mut stack = TraversalStack::<(u32, f32), MAX_DEPTH>::new();
        let mut current = 0usize;
        loop {
            let node = &self.nodes[current];
            if node.is_leaf() {
                let range = node.first as usize..(node.first + node.count) as usize;
                for &item in &self.prims[range] {
                    if visit(item, &mut search, stats) {
                        return search.best();
                    }
                }
            } else {
                let (l, r) = (node.first as usize, node.first as usize + 1);
                stats.node_visits += 2;
                match (hit(l, search.t_max()), hit(r, search.t_max())) {
                    (Some(tl), Some(tr)) => {
                        let (near, far) = if tl <= tr { (l, r) } else { (r, l) };
                        stack.push((far as u32, tl.max(tr)));
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
                let Some((node, t_enter)) = stack.pop() else {
                    return search.best();
                };
                if t_enter <= search.t_max() * CULL_SLACK {
                    current = node as usize;
                    break;
                }
            }
        }
    }
}

impl<V: Volume> Accel for VolumeBvh<V> {
    #[inline(always)]
    fn query(&self, query: &RayQuery, stats: &mut Stats) -> Option<Hit> {
        self.walk(
            query.ray,
            query.t_max,
            query.mode,
            stats,
            |prim, search, stats| search.test(query.geometry, query.ray, prim, stats),
        )
    }

    fn info(&self) -> AccelInfo {
        self.info()
    }
}
