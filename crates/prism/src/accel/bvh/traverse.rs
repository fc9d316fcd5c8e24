//! Stack traversal: test both children's boxes, descend into the nearer, push the farther.
//! Nearest-hit queries shrink `t_max` as hits are found, so far subtrees get culled.

use super::pair::PairRay;
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
        let root = self.nodes.first()?;
        stats.node_visits += 1;
        node_hit(root, ray, t_max)?;
        let mut best = None;
        if root.is_leaf() {
            let leaf = LeafQuery { geometry, ray, any };
            leaf.test(
                &self.prims,
                root.first,
                root.count,
                &mut t_max,
                &mut best,
                stats,
            );
            return best;
        }

        let leaf = LeafQuery { geometry, ray, any };
        let pair_ray = PairRay::new(ray);
        // Entry distances are compared against t_max with the same slack the box test
        // gives exits, so a child pushed before a hit is not culled by rounding.
        let slack = 1.0 + 2.0 * gamma(3);
        // Deferred children: (child, primitive count or 0 for interior, entry distance).
        let mut stack = [(0u32, 0u32, 0.0f32); MAX_DEPTH];
        let mut sp = 0;
        let (mut child, mut count) = (0u32, 0u32);
        loop {
            if count > 0 {
                if leaf.test(&self.prims, child, count, &mut t_max, &mut best, stats) {
                    return best;
                }
            } else {
                let pair = &self.pairs[child as usize];
                stats.node_visits += 2;
                match pair.hit(&pair_ray, t_max) {
                    [Some(ta), Some(tb)] => {
                        // Visit the nearer child now, the farther one later.
                        let (near, far, t_far) = if tb < ta { (1, 0, ta) } else { (0, 1, tb) };
                        stack[sp] = (pair.child[far], pair.count[far], t_far);
                        sp += 1;
                        (child, count) = (pair.child[near], pair.count[near]);
                        continue;
                    }
                    [Some(_), None] => {
                        (child, count) = (pair.child[0], pair.count[0]);
                        continue;
                    }
                    [None, Some(_)] => {
                        (child, count) = (pair.child[1], pair.count[1]);
                        continue;
                    }
                    [None, None] => {}
                }
            }
            // Pop the next deferred child, skipping those whose entry lies beyond a hit
            // found since they were pushed.
            loop {
                if sp == 0 {
                    return best;
                }
                sp -= 1;
                let (c, n, t_enter) = stack[sp];
                if t_enter <= t_max * slack {
                    (child, count) = (c, n);
                    break;
                }
            }
        }
    }
}

/// What a leaf's primitives are tested for.
struct LeafQuery<'a> {
    geometry: &'a Geometry,
    ray: &'a TraceRay,
    /// Stop at the first hit.
    any: bool,
}

impl LeafQuery<'_> {
    /// Tests `prims[first .. first + count]`, shrinking `t_max` to each hit; true when an
    /// any-hit query may stop.
    #[inline(always)]
    fn test(
        &self,
        prims: &[u32],
        first: u32,
        count: u32,
        t_max: &mut f32,
        best: &mut Option<Hit>,
        stats: &mut Stats,
    ) -> bool {
        for &prim in &prims[first as usize..(first + count) as usize] {
            // Exact ties go to the lower primitive id, as in the brute-force list, so the
            // answer does not depend on the order leaves are visited in.
            let limit = match best {
                Some(b) if prim < b.prim => next_up(*t_max),
                _ => *t_max,
            };
            if let Some(h) = self
                .geometry
                .intersect_counted(prim, self.ray, limit, stats)
            {
                *t_max = h.t;
                *best = Some(Hit {
                    t: h.t,
                    prim,
                    u: h.u,
                    v: h.v,
                });
                if self.any {
                    return true;
                }
            }
        }
        false
    }
}

crate::accel::accel_from_traverse!(Bvh);
