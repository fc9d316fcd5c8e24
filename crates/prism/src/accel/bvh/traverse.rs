//! Stack traversal of the 4-wide layout: test a node's child boxes at once, descend into
//! the nearest hit, push the others farthest first.
//! Nearest-hit queries shrink `t_max` as hits are found, so far subtrees get culled.

use super::wide::WideRay;
use super::{Bvh, Node, MAX_DEPTH};
use crate::accel::Hit;
use crate::geometry::Geometry;
use crate::math::robust::next_up;
use crate::math::{Aabb, TraceRay};
use crate::stats::Stats;
use std::mem::MaybeUninit;

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
        // The root box first: a cheap way out for rays that miss the scene.
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
        let wide_ray = WideRay::new(ray);
        // Entry distances are compared against t_max with the same slack the box test
        // gives exits (`CULL_SLACK`): a hit's reported distance may be a little short.
        let slack = crate::accel::CULL_SLACK;
        // Deferred children: (child, primitive count or 0 for interior, entry distance).
        // A visit defers at most three, and the wide tree is no deeper than the binary one.
        let mut stack = DeferredStack::new();
        let mut sp = 0;
        let (mut child, mut count) = (0u32, 0u32);
        loop {
            if count > 0 {
                if leaf.test(&self.prims, child, count, &mut t_max, &mut best, stats) {
                    return best;
                }
            } else {
                let node = &self.wide[child as usize];
                stats.node_visits += u64::from(node.children());
                let t = node.hit(&wide_ray, t_max);
                // The children hit, nearest first (ties keep lane order).
                let mut hits = [(0.0f32, 0usize); 4];
                let mut n = 0;
                for k in 0..4 {
                    if t[k] < f32::INFINITY {
                        let mut j = n;
                        while j > 0 && hits[j - 1].0 > t[k] {
                            hits[j] = hits[j - 1];
                            j -= 1;
                        }
                        hits[j] = (t[k], k);
                        n += 1;
                    }
                }
                if n > 0 {
                    // Farthest first onto the stack, so the nearer ones come off first.
                    for &(t_enter, k) in hits[1..n].iter().rev() {
                        stack.push(sp, (node.child[k], node.count[k], t_enter));
                        sp += 1;
                    }
                    let k = hits[0].1;
                    (child, count) = (node.child[k], node.count[k]);
                    continue;
                }
            }
            // Pop the next deferred child, skipping those whose entry lies beyond a hit
            // found since they were pushed.
            loop {
                if sp == 0 {
                    return best;
                }
                sp -= 1;
                let (c, n, t_enter) = stack.get(sp);
                if t_enter <= t_max * slack {
                    (child, count) = (c, n);
                    break;
                }
            }
        }
    }
}

/// The traversal stack. Left uninitialised: zeroing its 2 KiB for every ray costs as much
/// as a whole traversal of a small scene.
struct DeferredStack([MaybeUninit<(u32, u32, f32)>; 3 * MAX_DEPTH]);

impl DeferredStack {
    #[inline(always)]
    fn new() -> Self {
        DeferredStack([MaybeUninit::uninit(); 3 * MAX_DEPTH])
    }

    /// Writes slot `i` (the caller keeps the top-of-stack count).
    #[inline(always)]
    fn push(&mut self, i: usize, entry: (u32, u32, f32)) {
        self.0[i] = MaybeUninit::new(entry);
    }

    /// Reads slot `i`, which must have been written by `push`.
    #[inline(always)]
    fn get(&self, i: usize) -> (u32, u32, f32) {
        // SAFETY: the traversal only reads slots below its stack pointer, each written by
        // `push` since this stack was made (`i` is bounds-checked by the indexing).
        unsafe { self.0[i].assume_init() }
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
