//! The top-down recursion shared by the median, binned SAH and full-sweep SAH builders: a
//! node's bounds, a split rule that partitions its primitives (or declines, for a leaf),
//! and subtrees above a size threshold built in parallel with `rayon::join`. Subtrees are
//! stitched in serial build order, so the tree is the same for any thread count.

use super::stitch::NodeBlock;
use super::BuildPrims;
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

    /// `None` makes `order` a leaf; `Some(split)`, with `0 < split.mid < order.len()`,
    /// splits it into `order[..mid]` and `order[mid..]` after reordering it. Only called on
    /// two or more primitives.
    fn split(
        &self,
        prims: &BuildPrims,
        scratch: &mut Self::Scratch,
        order: &mut [u32],
        bounds: &Aabb,
        centroid_bounds: &Aabb,
    ) -> Option<Split>;
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

/// Builds the tree over `order` (positions into `prims`), reordering it into leaf order.
pub(super) fn build<R: SplitRule>(
    rule: &R,
    prims: &BuildPrims,
    order: &mut [u32],
    parallel_threshold: usize,
) -> Vec<Node> {
    let top = TopDown {
        rule,
        prims,
        parallel_threshold,
    };
    top.block(order, 0, 1, None).into_nodes()
}

struct TopDown<'a, R> {
    rule: &'a R,
    prims: &'a BuildPrims,
    parallel_threshold: usize,
}

impl<R: SplitRule> TopDown<'_, R> {
    /// The bounds of a node at `depth` over `order` (`extent` when the parent knows it),
    /// and where to split it (`None`: leaf).
    fn decide(
        &self,
        scratch: &mut R::Scratch,
        order: &mut [u32],
        depth: usize,
        extent: Option<Extent>,
    ) -> (Aabb, Option<Split>) {
        let (bounds, centroid_bounds) = extent.unwrap_or_else(|| self.extent(order));
        if order.len() == 1 || depth >= MAX_DEPTH - 1 {
            return (bounds, None);
        }
        let split = self
            .rule
            .split(self.prims, scratch, order, &bounds, &centroid_bounds);
        debug_assert!(split
            .as_ref()
            .is_none_or(|s| s.mid > 0 && s.mid < order.len()));
        (bounds, split)
    }

    /// The bounds and centroid bounds of `order`, in one pass.
    fn extent(&self, order: &[u32]) -> Extent {
        let fold = |chunk: &[u32]| {
            chunk.iter().fold((Aabb::EMPTY, Aabb::EMPTY), |(b, c), &i| {
                (
                    b.union(&self.prims.bounds[i as usize]),
                    c.union_point(self.prims.centroids[i as usize]),
                )
            })
        };
        if order.len() < PARALLEL_PASS {
            return fold(order);
        }
        // Unions are exact, so the chunks' order of merging cannot change the result.
        order.par_chunks(PARALLEL_PASS / 2).map(fold).reduce(
            || (Aabb::EMPTY, Aabb::EMPTY),
            |(a, b), (c, d)| (a.union(&c), b.union(&d)),
        )
    }

    /// The subtree over `order`, whose first primitive sits at `offset` in leaf order.
    fn block(
        &self,
        order: &mut [u32],
        offset: u32,
        depth: usize,
        extent: Option<Extent>,
    ) -> NodeBlock {
        if order.len() <= self.parallel_threshold {
            let mut serial = Serial {
                top: self,
                scratch: self.rule.scratch(),
                nodes: Self::first_node(order.len()),
            };
            serial.subdivide(0, order, offset, depth, extent);
            return NodeBlock::Serial(serial.nodes);
        }
        let n = order.len();
        let (bounds, split) = self.decide(&mut self.rule.scratch(), order, depth, extent);
        let Some(Split { mid, sides }) = split else {
            return NodeBlock::leaf(Node::leaf(bounds, offset, n));
        };
        let [lo_extent, hi_extent] = sides.map_or([None, None], |s| s.map(Some));
        let (lo, hi) = order.split_at_mut(mid);
        let (left, right) = rayon::join(
            || self.block(lo, offset, depth + 1, lo_extent),
            || self.block(hi, offset + mid as u32, depth + 1, hi_extent),
        );
        NodeBlock::split(Node::interior(bounds, 0), left, right)
    }
}

/// A subtree built on one thread, depth first into one vector.
struct Serial<'a, 'b, R: SplitRule> {
    top: &'a TopDown<'b, R>,
    scratch: R::Scratch,
    nodes: Vec<Node>,
}

impl<R: SplitRule> TopDown<'_, R> {
    /// A placeholder root in a vector big enough for a tree over `n` primitives.
    fn first_node(n: usize) -> Vec<Node> {
        let mut nodes = Vec::with_capacity(2 * n);
        nodes.push(Node::leaf(Aabb::EMPTY, 0, 0));
        nodes
    }
}

impl<R: SplitRule> Serial<'_, '_, R> {
    fn subdivide(
        &mut self,
        index: usize,
        order: &mut [u32],
        offset: u32,
        depth: usize,
        extent: Option<Extent>,
    ) {
        let (bounds, split) = self.top.decide(&mut self.scratch, order, depth, extent);
        let Some(Split { mid, sides }) = split else {
            self.nodes[index] = Node::leaf(bounds, offset, order.len());
            return;
        };
        let left = self.nodes.len();
        self.nodes[index] = Node::interior(bounds, left as u32);
        let placeholder = Node::leaf(Aabb::EMPTY, 0, 0);
        self.nodes.extend([placeholder, placeholder]);
        let [lo_extent, hi_extent] = sides.map_or([None, None], |s| s.map(Some));
        let (lo, hi) = order.split_at_mut(mid);
        self.subdivide(left, lo, offset, depth + 1, lo_extent);
        self.subdivide(left + 1, hi, offset + mid as u32, depth + 1, hi_extent);
    }
}
