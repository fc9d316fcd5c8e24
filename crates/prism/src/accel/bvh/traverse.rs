//! Stack traversal of the 4-wide layout: test a node's child boxes at once, descend into
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
use glam::Vec4;

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
                let hit = t.cmplt(Vec4::INFINITY).bitmask();
                if hit != 0 {
                    // The children hit, nearest first, sorted without branches.
                    let keys = order_keys(t);
                    let n = hit.count_ones() as usize;
                    // Farthest first onto the stack, so the nearer ones come off first.
                    for &key in keys[1..n].iter().rev() {
                        let k = (key & 3) as usize;
                        stack.push((node.child[k], node.count[k], entry_bound(key)));
                    }
                    let k = (keys[0] & 3) as usize;
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

/// Sort keys for four children's entry distances, ascending: each distance's bits with the
/// lane in the two lowest. Entry distances are never negative (the box test starts from
/// +0), so their bits order as the numbers do; overwriting two bits merges distances
/// within four ulps, which then go in lane order. Lanes the ray misses (+∞) sort last.
#[inline(always)]
fn order_keys(t: Vec4) -> [u32; 4] {
    let key = |k: usize| (t[k].to_bits() & !3) | k as u32;
    let [mut a, mut b, mut c, mut d] = [key(0), key(1), key(2), key(3)];
    // A sorting network of five compare-exchanges (min/max, no branches).
    let exchange = |x: &mut u32, y: &mut u32| (*x, *y) = ((*x).min(*y), (*x).max(*y));
    exchange(&mut a, &mut b);
    exchange(&mut c, &mut d);
    exchange(&mut a, &mut c);
    exchange(&mut b, &mut d);
    exchange(&mut b, &mut c);
    [a, b, c, d]
}

/// A lower bound on the entry distance a sort key was made from (the lane bits cleared),
/// which is what the culling of deferred children may compare safely.
#[inline(always)]
fn entry_bound(key: u32) -> f32 {
    f32::from_bits(key & !3)
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
