//! The top-down recursion shared by the median, binned SAH and full-sweep SAH builders: a
//! node's bounds, a split rule that partitions its primitives (or declines, for a leaf),
//! and subtrees above a size threshold built in parallel with `rayon::join`. Subtrees are
//! stitched in serial build order, so the tree is the same for any thread count.

use super::prim_ref::{PrimRef, SimdBox};
use super::stitch::NodeBlock;
use super::{inside_share, BuildPrims};
use crate::accel::bvh::{Node, MAX_DEPTH};
use crate::math::Aabb;
use rayon::prelude::*;

/// Nodes over at least this many primitives fold their bounds (and the binned builder its
/// bins) in parallel chunks: the top of the tree, where one node's pass over a million
/// primitives would otherwise leave every other core idle.
pub(super) const PARALLEL_PASS: usize = 1 << 15;

/// How one builder splits a node.
pub(super) trait SplitRule: Sync {
    /// Per-thread working memory, reused across the nodes of a serial subtree.
    type Scratch: Send;

    fn scratch(&self) -> Self::Scratch;

    /// `None` makes `refs` a leaf; `Some(split)`, with `0 < split.mid < refs.len()`,
    /// splits it into `refs[..mid]` and `refs[mid..]` after reordering it. Only called on
    /// two or more primitives.
    fn split(
        &self,
        prims: &BuildPrims,
        scratch: &mut Self::Scratch,
        refs: &mut [PrimRef],
        bounds: &Aabb,
        centroid_bounds: &Aabb,
    ) -> Option<Split>;

    /// For rules that split small nodes tentatively (rays from inside the scene): the
    /// traversal cost and the largest leaf. A subtree over at most that many primitives
    /// is then collapsed back into a leaf where the leaf costs no more, with its
    /// children's costs weighted by `inside_share`.
    fn collapse(&self) -> Option<(f32, usize)> {
        None
    }
}

/// Where a rule splits a node's primitives.
pub(super) struct Split {
    pub mid: usize,
    /// The two sides' (bounds, centroid bounds), when the rule knows them already (the
    /// binned builder has them from its bins), so the children need not fold them again.
    pub sides: Option<[Extent; 2]>,
}

impl Split {
    /// A split whose sides' bounds the recursion computes.
    pub(super) fn at(mid: usize) -> Split {
        Split { mid, sides: None }
    }
}

/// A node's bounds and the bounds of its primitives' centroids.
pub(super) type Extent = (Aabb, Aabb);

/// Builds the tree over `refs`, reordering them into leaf order.
pub(super) fn build<R: SplitRule>(
    rule: &R,
    prims: &BuildPrims,
    refs: &mut [PrimRef],
    parallel_threshold: usize,
) -> Vec<Node> {
    let top = TopDown {
        rule,
        prims,
        parallel_threshold,
    };
    top.block(refs, 0, 1, None).into_nodes()
}

struct TopDown<'a, R> {
    rule: &'a R,
    prims: &'a BuildPrims,
    parallel_threshold: usize,
}

impl<R: SplitRule> TopDown<'_, R> {
    /// The bounds of a node at `depth` over `refs` (`extent` when the parent knows it),
    /// and where to split it (`None`: leaf).
    fn decide(
        &self,
        scratch: &mut R::Scratch,
        refs: &mut [PrimRef],
        depth: usize,
        extent: Option<Extent>,
    ) -> (Aabb, Option<Split>) {
        let (bounds, centroid_bounds) = extent.unwrap_or_else(|| extent_of(refs));
        if refs.len() == 1 || depth >= MAX_DEPTH - 1 {
            return (bounds, None);
        }
        let split = self
            .rule
            .split(self.prims, scratch, refs, &bounds, &centroid_bounds);
        debug_assert!(split
            .as_ref()
            .is_none_or(|s| s.mid > 0 && s.mid < refs.len()));
        (bounds, split)
    }

    /// The subtree over `refs`, whose first primitive sits at `offset` in leaf order.
    fn block(
        &self,
        refs: &mut [PrimRef],
        offset: u32,
        depth: usize,
        extent: Option<Extent>,
    ) -> NodeBlock {
        // A subtree that may be collapsed into a leaf is built serially whatever the
        // threshold, so that the tree does not depend on it.
        let collapsible = self.rule.collapse().map_or(0, |(_, max_leaf)| max_leaf);
        if refs.len() <= self.parallel_threshold.max(collapsible) {
            let mut serial = Serial {
                top: self,
                scratch: self.rule.scratch(),
                nodes: Self::first_node(refs.len()),
            };
            serial.subdivide(0, refs, offset, depth, extent);
            return NodeBlock::Serial(serial.nodes);
        }
        let n = refs.len();
        let (bounds, split) = self.decide(&mut self.rule.scratch(), refs, depth, extent);
        let Some(Split { mid, sides }) = split else {
            return NodeBlock::leaf(Node::leaf(bounds, offset, n));
        };
        let [lo_extent, hi_extent] = sides.map_or([None, None], |s| s.map(Some));
        let (lo, hi) = refs.split_at_mut(mid);
        let (left, right) = rayon::join(
            || self.block(lo, offset, depth + 1, lo_extent),
            || self.block(hi, offset + mid as u32, depth + 1, hi_extent),
        );
        NodeBlock::split(Node::interior(bounds, 0), left, right)
    }
}

/// The bounds and centroid bounds of `refs`, in one pass (in parallel chunks for big
/// nodes: unions are exact, so the chunks' order of merging cannot change the result).
pub(super) fn extent_of(refs: &[PrimRef]) -> Extent {
    let fold = |chunk: &[PrimRef]| {
        let (mut b, mut c) = (SimdBox::EMPTY, SimdBox::EMPTY);
        for r in chunk {
            b.grow(r.min(), r.max());
            c.grow_point(r.centroid());
        }
        (b, c)
    };
    let (b, c) = if refs.len() < PARALLEL_PASS {
        fold(refs)
    } else {
        refs.par_chunks(PARALLEL_PASS / 2).map(fold).reduce(
            || (SimdBox::EMPTY, SimdBox::EMPTY),
            |(a, b), (c, d)| (a.union(&c), b.union(&d)),
        )
    };
    (b.to_aabb(), c.to_aabb())
}

/// A subtree built on one thread, depth first into one vector.
struct Serial<'a, 'b, R: SplitRule> {
    top: &'a TopDown<'b, R>,
    scratch: R::Scratch,
    nodes: Vec<Node>,
}

impl<R: SplitRule> TopDown<'_, R> {
    /// A placeholder root in a vector with room for the nodes of a tree over `n`
    /// primitives in leaves of about four (more grow it). Room for the worst case, 2n,
    /// made each subtree's vector a fresh mapping of the OS (glibc maps requests over
    /// 128 KiB), whose pages fault in one by one in every build (docs/journal/performance.md,
    /// the seventh step).
    fn first_node(n: usize) -> Vec<Node> {
        let mut nodes = Vec::with_capacity(n / 2 + 1);
        nodes.push(Node::leaf(Aabb::EMPTY, 0, 0));
        nodes
    }
}

impl<R: SplitRule> Serial<'_, '_, R> {
    /// Builds the subtree over `refs` at `index`; returns its box and, for rules that
    /// collapse (`SplitRule::collapse`), its cost for a ray that entered it (others ignore
    /// the cost).
    fn subdivide(
        &mut self,
        index: usize,
        refs: &mut [PrimRef],
        offset: u32,
        depth: usize,
        extent: Option<Extent>,
    ) -> (Aabb, f32) {
        let n = refs.len();
        let (bounds, split) = self.top.decide(&mut self.scratch, refs, depth, extent);
        let collapse = self.top.rule.collapse();
        let leaf_cost = self.top.prims.leaf_cost(n);
        let Some(Split { mid, sides }) = split else {
            self.nodes[index] = Node::leaf(bounds, offset, n);
            return (bounds, leaf_cost);
        };
        let left = self.nodes.len();
        self.nodes[index] = Node::interior(bounds, left as u32);
        let placeholder = Node::leaf(Aabb::EMPTY, 0, 0);
        self.nodes.extend([placeholder, placeholder]);
        let [lo_extent, hi_extent] = sides.map_or([None, None], |s| s.map(Some));
        let (lo, hi) = refs.split_at_mut(mid);
        let (lo_box, lo_cost) = self.subdivide(left, lo, offset, depth + 1, lo_extent);
        let hi_start = offset + mid as u32;
        let (hi_box, hi_cost) = self.subdivide(left + 1, hi, hi_start, depth + 1, hi_extent);
        let Some((traversal, max_leaf)) = collapse else {
            return (bounds, 0.0);
        };
        let (area, volume) = (
            bounds.surface_area().max(f32::MIN_POSITIVE),
            bounds.volume(),
        );
        let share = |b: &Aabb| inside_share(b.surface_area(), b.volume(), area, volume);
        let cost = traversal + share(&lo_box) * lo_cost + share(&hi_box) * hi_cost;
        if n <= max_leaf && leaf_cost <= cost {
            // The subtree was built last, so its nodes are the vector's tail.
            self.nodes.truncate(left);
            self.nodes[index] = Node::leaf(bounds, offset, n);
            return (bounds, leaf_cost);
        }
        (bounds, cost)
    }
}
