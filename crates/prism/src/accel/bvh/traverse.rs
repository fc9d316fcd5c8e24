//! Stack traversal: test both children's boxes, descend into the nearer, push the farther.
//! Nearest-hit queries shrink `t_max` as hits are found, so far subtrees get culled.

use super::{Bvh, Node, MAX_DEPTH};
use crate::accel::Hit;
use crate::geometry::Geometry;
use crate::math::robust::{gamma, next_up};
use crate::math::{Aabb, TraceRay};
use crate::stats::Stats;

#[inline(always)]
fn node_hit(node: &Node, ray: &TraceRay, t_max: f32) -> Option<f32> {
    Aabb {
        min: node.min,
        max: node.max,
    }
    .hit(ray.ray.origin, ray.inv_dir, t_max)
}

impl Bvh {
    /// Shared traversal; `any` stops at the first hit.
    #[inline(always)]
    fn traverse(
        &self,
        geometry: &Geometry,
        ray: &TraceRay,
        mut t_max: f32,
        stats: &mut Stats,
        any: bool,
    ) -> Option<Hit> {
        if self.nodes.is_empty() {
            return None;
        }
        stats.node_visits += 1;
        node_hit(&self.nodes[0], ray, t_max)?;
        let mut best = None;
        let mut stack = [(0u32, 0.0f32); MAX_DEPTH];
        let mut sp = 0;
        let mut current = 0usize;
        loop {
            let node = &self.nodes[current];
            if node.is_leaf() {
                let range = node.first as usize..(node.first + node.count) as usize;
                for &prim in &self.prims[range] {
                    // Exact ties go to the lower primitive id, as in the brute-force list,
                    // so the answer (and the image) does not depend on how the tree was
                    // built: a lower id is tested against a bound one ulp farther.
                    let lower = best.is_some_and(|b: Hit| prim < b.prim);
                    let bound = if lower { next_up(t_max) } else { t_max };
                    if let Some(h) = geometry.intersect_counted(prim, ray, bound, stats) {
                        t_max = h.t;
                        best = Some(Hit {
                            t: h.t,
                            prim,
                            u: h.u,
                            v: h.v,
                        });
                        if any {
                            return best;
                        }
                    }
                }
            } else {
                let (l, r) = (node.first as usize, node.first as usize + 1);
                stats.node_visits += 2;
                let hl = node_hit(&self.nodes[l], ray, t_max);
                let hr = node_hit(&self.nodes[r], ray, t_max);
                match (hl, hr) {
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
            // Pop the next far child, skipping those whose entry lies beyond a hit found
            // since they were pushed.
            loop {
                if sp == 0 {
                    return best;
                }
                sp -= 1;
                let (node, t_enter) = stack[sp];
                if t_enter <= t_max * (1.0 + 2.0 * gamma(3)) {
                    current = node as usize;
                    break;
                }
            }
        }
    }
}

crate::accel::accel_from_traverse!(Bvh);
