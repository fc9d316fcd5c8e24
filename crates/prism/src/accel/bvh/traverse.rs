//! The stack walk every layout and packets share (the 4-wide layout's and the 8-wide one's,
//! `simd8.rs`, for one ray and for packets): test a node's child boxes at once, descend
//! into the nearest hit, push the others farthest first.
//! Nearest-hit queries shrink `t_max` as hits are found, so far subtrees get culled.

use super::leaves::PACKED;
use super::wide::LeafSlots;
use super::MAX_DEPTH;
use crate::accel::query::HitSearch;
use crate::accel::stack::TraversalStack;
use crate::geometry::{Geometry, PackRay, TrianglePack};
use crate::math::TraceRay;
use crate::stats::Stats;

/// What the shared walk culls against: the distance beyond which no hit is wanted any more
/// (one ray's best hit so far, or the farthest of a packet's), and which rays go on into a
/// child (`Rays`: nothing for one ray, a bit per ray for a packet).
pub(super) trait CullBound {
    /// What travels with each child: the rays that enter it.
    type Rays: Copy;
    /// Whether the walk defers the children a visit enters by a branch per lane and goes
    /// on with the top of its stack where it can (see `walk`): for one ray, whose walk
    /// waits on each box test; a packet's visits are long enough to hide that wait, and
    /// their shadow packets ran up to 8 % slower so.
    const BY_BRANCHES: bool;
    fn t_max(&self) -> f32;
    /// The rays the walk starts with.
    fn all_rays(&self) -> Self::Rays;
    /// The rays of `rays` that still need a child deferred with entry bound `t_enter`, or
    /// None when none does.
    fn resume(&self, rays: Self::Rays, t_enter: f32) -> Option<Self::Rays>;
}

impl CullBound for HitSearch {
    type Rays = ();
    const BY_BRANCHES: bool = true;
    #[inline(always)]
    fn t_max(&self) -> f32 {
        HitSearch::t_max(self)
    }
    #[inline(always)]
    fn all_rays(&self) {}
    #[inline(always)]
    fn resume(&self, (): (), t_enter: f32) -> Option<()> {
        // Entry distances are compared against t_max with the same slack the box test
        // gives exits (`CULL_SLACK`): a hit's reported distance may be a little short.
        (t_enter <= HitSearch::t_max(self) * crate::accel::CULL_SLACK).then_some(())
    }
}

/// What one visit of a wide node found.
pub(super) struct Visit<R> {
    /// Children in use (what the statistics count as node visits).
    pub children: u32,
    /// The children entered before the bound, a bit per lane.
    pub hit: u32,
    /// Their entry distances (meaningful in the lanes of `hit`).
    pub entries: [f32; 8],
    /// The rays that enter each of them.
    pub rays: [R; 8],
}

/// The stack walk both wide layouts and packets share, from `root` (the tree's node 0, or
/// an entry node made of some of its subtrees, `subtree.rs`): visit a node (`visit`, the
/// layout's SIMD box test, with the rays that reached it), descend into the nearest child
/// hit, push the others farthest first (ties keep lane order; without `ORDERED`, the
/// lowest lane entered first: for one ray, every lane is pushed by a branch of its own and
/// the walk goes on with the top, `CullBound::BY_BRANCHES`), hand leaves to `leaf` with
/// their entry distance and rays (true when the query is answered), and skip deferred
/// children that `search` no longer needs (`CullBound::resume`). `#[inline(always)]` so
/// that the 8-wide callers' AVX2 compilation reaches the whole walk.
///
/// `ORDERED` is for nearest-hit queries, whose bound shrinks with each hit and culls what
/// lies beyond it; an any-hit query stops at its first hit wherever it lies, so ordering
/// its children only costs time (Embree's occlusion walk does not sort either). A
/// parameter of the compiled walk, not a run-time test: a test in the loop cost the
/// nearest-hit packets about a fifth of their speed on the 1M-triangle soup.
#[inline(always)]
pub(super) fn walk<N: LeafSlots, S: CullBound, const ORDERED: bool>(
    nodes: &[N],
    root: &N,
    visit: impl Fn(&N, &S, S::Rays) -> Visit<S::Rays>,
    search: &mut S,
    stats: &mut Stats,
    mut leaf: impl FnMut(u32, u32, f32, S::Rays, &mut S, &mut Stats) -> bool,
) {
    // Deferred children: (child, primitive count or 0 for interior, entry distance, rays).
    // A visit defers at most eight and goes on with one of them (seven net), and a wide
    // tree is no deeper than the binary one.
    let mut stack = TraversalStack::<(u32, u32, f32, S::Rays), { 7 * MAX_DEPTH + 1 }>::new();
    let (mut child, mut count, mut enter, mut rays) = (0u32, 0u32, 0.0f32, search.all_rays());
    let mut at_root = true;
    loop {
        if count > 0 {
            if leaf(child, count, enter, rays, search, stats) {
                return;
            }
        } else {
            let node = if at_root {
                at_root = false;
                root
            } else {
                &nodes[child as usize]
            };
            let Visit {
                children,
                hit: mut mask,
                entries: t,
                rays: r,
            } = visit(node, search, rays);
            stats.node_visits += u64::from(children);
            let (children, counts) = node.children_and_counts();
            if S::BY_BRANCHES && mask != 0 && (!ORDERED || mask & (mask - 1) == 0) {
                // (One ray.) One child, or no order wanted: every lane entered is deferred by a
                // branch of its own, the lowest on top, and the walk goes on with the top.
                // So the next node's index is read from this node alone once the branches
                // are predicted, and its load can start while the box test that decides
                // them is still running; taking the lane from the mask (its trailing
                // zeros) made every step wait for the box test. Shadow rays 1.1-1.35x
                // faster, nearest-hit rays 2-24 % (docs/journal/performance.md, twenty-third step).
                for k in (0..children.len()).rev() {
                    if mask >> k & 1 == 1 {
                        stack.push((children[k], counts[k], t[k], r[k]));
                    }
                }
            } else if mask != 0 {
                let first = mask.trailing_zeros() as usize;
                mask &= mask - 1;
                if mask == 0 || !ORDERED {
                    // (Packets.) One child, or no order wanted: the first lane now, the
                    // others deferred as they come.
                    while mask != 0 {
                        let k = mask.trailing_zeros() as usize;
                        mask &= mask - 1;
                        stack.push((children[k], counts[k], t[k], r[k]));
                    }
                    (child, count, enter, rays) =
                        (children[first], counts[first], t[first], r[first]);
                    continue;
                }
                // Two or more: order them nearest first (ties keep lane order).
                let mut hits = [(0.0f32, 0usize); 8];
                hits[0] = (t[first], first);
                let mut n = 1;
                while mask != 0 {
                    let k = mask.trailing_zeros() as usize;
                    mask &= mask - 1;
                    let mut j = n;
                    while j > 0 && hits[j - 1].0 > t[k] {
                        hits[j] = hits[j - 1];
                        j -= 1;
                    }
                    hits[j] = (t[k], k);
                    n += 1;
                }
                // Farthest first onto the stack, so the nearer ones come off first.
                for &(t_enter, k) in hits[1..n].iter().rev() {
                    stack.push((children[k], counts[k], t_enter, r[k]));
                }
                let (t_enter, k) = hits[0];
                (child, count, enter, rays) = (children[k], counts[k], t_enter, r[k]);
                continue;
            }
        }
        loop {
            let Some((c, n, t_enter, deferred)) = stack.pop() else {
                return;
            };
            if let Some(still) = search.resume(deferred, t_enter) {
                (child, count, enter, rays) = (c, n, t_enter, still);
                break;
            }
        }
    }
}

/// Tests a leaf's primitives.
pub(super) struct LeafQuery<'a> {
    pub(super) prims: &'a [u32],
    pub(super) packs: &'a [TrianglePack],
    pub(super) geometry: &'a Geometry,
    pub(super) ray: &'a TraceRay,
    pub(super) pack_ray: &'a PackRay,
}

impl LeafQuery<'_> {
    /// Tests a leaf: `packs[first .. first + n]` when `count` is `PACKED | n`, otherwise
    /// `prims[first .. first + count]`; true when the query is answered.
    #[inline(always)]
    pub(super) fn test(
        &self,
        first: u32,
        count: u32,
        search: &mut HitSearch,
        stats: &mut Stats,
    ) -> bool {
        if count & PACKED != 0 {
            let packs = &self.packs[first as usize..(first + (count & !PACKED)) as usize];
            // A plain loop, inlined into the walk (`Iterator::any` stayed a call, and the
            // walk's ray constants were reloaded from the stack after each leaf).
            for pack in packs {
                if search.test_pack(pack, self.pack_ray, self.ray, stats) {
                    return true;
                }
            }
            return false;
        }
        self.prims[first as usize..(first + count) as usize]
            .iter()
            .any(|&prim| search.test(self.geometry, self.ray, prim, stats))
    }
}
