//! Stack traversal of the 4-wide layout (the 8-wide one, where the CPU has AVX2, is in
//! `simd8.rs`): test a node's child boxes at once, descend into
//! the nearest hit, push the others farthest first.
//! Nearest-hit queries shrink `t_max` as hits are found, so far subtrees get culled.

use super::leaves::PACKED;
use super::wide::WideRay;
use super::{Bvh, Node, MAX_DEPTH};
use crate::accel::query::HitSearch;
use crate::accel::stack::TraversalStack;
use crate::accel::{Accel, AccelInfo, Hit, QueryMode};
use crate::geometry::{Geometry, PackRay, TrianglePack};
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

impl Accel for Bvh {
    #[inline(always)]
    fn query(
        &self,
        geometry: &Geometry,
        ray: &TraceRay,
        t_max: f32,
        mode: QueryMode,
        stats: &mut Stats,
    ) -> Option<Hit> {
        let root = self.nodes.first()?;
        // The root box first: a cheap way out for rays that miss the scene.
        stats.node_visits += 1;
        node_hit(root, ray, t_max)?;
        let mut search = HitSearch::new(t_max, mode);
        let leaf = LeafQuery {
            prims: &self.prims,
            packs: &self.packs,
            geometry,
            ray,
            pack_ray: PackRay::new(ray),
        };
        if root.is_leaf() {
            leaf.test(root.first, root.count, &mut search, stats);
            return search.best();
        }

        if !self.wide8.is_empty() {
            super::simd8::traverse(&self.wide8, ray, &mut search, stats, |c, n, s, st| {
                leaf.test(c, n, s, st)
            });
            return search.best();
        }

        let wide_ray = WideRay::new(ray);
        // Entry distances are compared against t_max with the same slack the box test
        // gives exits (`CULL_SLACK`): a hit's reported distance may be a little short.
        let slack = crate::accel::CULL_SLACK;
        // Deferred children: (child, primitive count or 0 for interior, entry distance).
        // A visit defers at most three, and the wide tree is no deeper than the binary one.
        let mut stack = TraversalStack::<(u32, u32, f32), { 3 * MAX_DEPTH }>::new();
        let (mut child, mut count) = (0u32, 0u32);
        loop {
            if count > 0 {
                if leaf.test(child, count, &mut search, stats) {
                    return search.best();
                }
            } else {
                let node = &self.wide[child as usize];
                stats.node_visits += u64::from(node.children());
                let t = node.hit(&wide_ray, search.t_max());
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
                        stack.push((node.child[k], node.count[k], t_enter));
                    }
                    let k = hits[0].1;
                    (child, count) = (node.child[k], node.count[k]);
                    continue;
                }
            }
            // Pop the next deferred child, skipping those whose entry lies beyond a hit
            // found since they were pushed.
            loop {
                let Some((c, n, t_enter)) = stack.pop() else {
                    return search.best();
                };
                if t_enter <= search.t_max() * slack {
                    (child, count) = (c, n);
                    break;
                }
            }
        }
    }

    fn info(&self) -> AccelInfo {
        self.info()
    }
}

/// Tests a leaf's primitives.
struct LeafQuery<'a> {
    prims: &'a [u32],
    packs: &'a [TrianglePack],
    geometry: &'a Geometry,
    ray: &'a TraceRay,
    pack_ray: PackRay,
}

impl LeafQuery<'_> {
    /// Tests a leaf: `packs[first .. first + n]` when `count` is `PACKED | n`, otherwise
    /// `prims[first .. first + count]`; true when the query is answered.
    #[inline(always)]
    fn test(&self, first: u32, count: u32, search: &mut HitSearch, stats: &mut Stats) -> bool {
        if count & PACKED != 0 {
            let packs = &self.packs[first as usize..(first + (count & !PACKED)) as usize];
            return packs
                .iter()
                .any(|pack| search.test_pack(pack, &self.pack_ray, self.ray, stats));
        }
        self.prims[first as usize..(first + count) as usize]
            .iter()
            .any(|&prim| search.test(self.geometry, self.ray, prim, stats))
    }
}
