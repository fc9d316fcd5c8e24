//! Progressive hierarchical refinement (Hendrich, Meister & Bittner 2017): a fast
//! auxiliary LBVH (`lbvh.rs`, one primitive per leaf) is built first, and the tree is then
//! built top down over a *cut* of it rather than over primitives. A node's cut is the set
//! of auxiliary subtrees its primitives fall into; each is costed by its box and count, and
//! the node is split by a full SAH sweep over the cut's boxes on three axes. Before a node
//! is split its cut is refined: every auxiliary node whose surface area exceeds
//! `A_root / 2^(alpha·depth + delta)` is replaced by its children. `delta` sets the first
//! cut's size (about 2^delta subtrees on a surface mesh), `alpha` how fast the threshold
//! falls with depth: below 1 it falls slower than the nodes shrink, so cuts get smaller
//! going down and a split sorts a few hundred subtrees instead of a node's primitives.
//! Small nodes are refined down to their primitives, so the leaves are chosen by the SAH.
//!
//! Every choice depends on the node's cut alone, whose order the refinement fixes (sort
//! keys are unique: the centroid, then the member's place in the cut), so the tree does not depend on the
//! thread count; nodes over more than the parallel threshold build their children with
//! `rayon::join` and are stitched in serial order.

use super::lbvh;
use super::prim_ref::SimdBox;
use super::stitch::NodeBlock;
use super::BuildPrims;
use crate::accel::bvh::{Node, MAX_DEPTH};
use crate::math::Aabb;

/// Nodes of at most this many primitives refine their cut down to the primitives: the
/// SAH then chooses the bottom levels and the leaves among primitives rather than
/// following the auxiliary tree's Morton splits, for a sweep over a few dozen boxes.
const PRIMITIVE_CUT: u32 = 32;

/// `Item::node` of an item that is a single primitive rather than an auxiliary node.
const PRIMITIVE: u32 = u32::MAX;

pub(super) struct Phr {
    /// The paper's α: how fast the refinement threshold falls per level of the new tree.
    pub alpha: f32,
    /// The paper's δ: the first cut holds the auxiliary nodes of at most 2^-δ of the
    /// root's area.
    pub delta: f32,
    pub max_leaf_size: usize,
    pub traversal_cost: f32,
    pub parallel_threshold: usize,
}

/// A member of a cut: an auxiliary subtree (or one primitive), its box and its run of
/// the Morton order.
#[derive(Clone, Copy)]
struct Item {
    bounds: SimdBox,
    /// The auxiliary node, or `PRIMITIVE`.
    node: u32,
    /// Its primitives are `morton[lo..hi]`.
    lo: u32,
    hi: u32,
}

impl Item {
    fn count(&self) -> u32 {
        self.hi - self.lo
    }
}

/// The auxiliary tree as the refinement reads it.
struct Aux<'a> {
    nodes: Vec<Node>,
    /// Per auxiliary node, its run of the Morton order.
    runs: Vec<(u32, u32)>,
    /// Build positions in Morton order.
    morton: &'a [u32],
    prims: &'a BuildPrims,
}

impl Aux<'_> {
    fn item(&self, node: u32) -> Item {
        let n = &self.nodes[node as usize];
        let (lo, hi) = self.runs[node as usize];
        Item {
            bounds: SimdBox {
                min: n.min.into(),
                max: n.max.into(),
            },
            node,
            lo,
            hi,
        }
    }

    fn primitive(&self, position: u32) -> Item {
        let b = &self.prims.bounds[self.morton[position as usize] as usize];
        Item {
            bounds: SimdBox {
                min: b.min.into(),
                max: b.max.into(),
            },
            node: PRIMITIVE,
            lo: position,
            hi: position + 1,
        }
    }

    /// Pushes what replaces `item` in a refined cut: its children, or the primitives of
    /// an auxiliary leaf (more than one only where the LBVH hit its depth limit).
    fn expand(&self, item: &Item, out: &mut Vec<Item>) {
        let node = &self.nodes[item.node as usize];
        if node.is_leaf() {
            out.extend((item.lo..item.hi).map(|p| self.primitive(p)));
        } else {
            out.extend([self.item(node.first), self.item(node.first + 1)]);
        }
    }
}

/// Per-thread buffers of the SAH sweep.
#[derive(Default)]
struct Scratch {
    /// The cut's members in order on the axis being swept (`ordered_bits` of the centroid,
    /// then the member's place in the cut); the winning axis's order.
    sorted: Vec<u64>,
    best: Vec<u64>,
    right_area: Vec<f32>,
    right_count: Vec<u32>,
    /// Items waiting to be looked at by `refine`.
    stack: Vec<Item>,
}

impl Phr {
    /// Builds over all of `prims`, writing the leaf order into `order`.
    pub(super) fn build(&self, prims: &BuildPrims, order: &mut [u32]) -> Vec<Node> {
        let nodes = lbvh::build(
            prims,
            order,
            1,
            self.traversal_cost,
            self.parallel_threshold,
        );
        let morton = order.to_vec();
        let aux = Aux {
            runs: runs(&nodes),
            nodes,
            morton: &morton,
            prims,
        };
        let root = aux.item(0);
        let builder = Builder {
            phr: self,
            aux: &aux,
            root_area: f64::from(root.bounds.surface_area()),
            max_leaf_size: self.max_leaf_size.max(1) as u32,
        };
        let mut scratch = Scratch::default();
        let cut = builder.refine(vec![root], 1, &mut scratch);
        builder.block(cut, 0, 1, order).into_nodes()
    }
}

/// Each auxiliary node's run of the Morton order: children follow their parents in the
/// array, so one backward pass folds the runs up from the leaves.
fn runs(nodes: &[Node]) -> Vec<(u32, u32)> {
    let mut runs = vec![(0, 0); nodes.len()];
    for i in (0..nodes.len()).rev() {
        let n = &nodes[i];
        runs[i] = if n.is_leaf() {
            (n.first, n.first + n.count)
        } else {
            (runs[n.first as usize].0, runs[n.first as usize + 1].1)
        };
    }
    runs
}

struct Builder<'a> {
    phr: &'a Phr,
    aux: &'a Aux<'a>,
    root_area: f64,
    max_leaf_size: u32,
}

/// How a node is split: the cut's order along the chosen axis and where it parts, or a
/// leaf.
enum Decision {
    Leaf,
    Split {
        left: Vec<Item>,
        right: Vec<Item>,
        left_bounds: Aabb,
        right_bounds: Aabb,
    },
}

impl Decision {
    /// The split into `left` and `right`, each with the bounds of its items.
    fn split(left: Vec<Item>, right: Vec<Item>) -> Decision {
        let (left_bounds, right_bounds) = (cut_bounds(&left), cut_bounds(&right));
        Decision::Split {
            left,
            right,
            left_bounds,
            right_bounds,
        }
    }
}

impl Builder<'_> {
    /// The area above which an auxiliary node is refined in a cut for a node at `depth`
    /// (the root's is 1).
    fn threshold(&self, depth: usize) -> f64 {
        let levels = depth.saturating_sub(1) as f64;
        let exponent = f64::from(self.phr.alpha) * levels + f64::from(self.phr.delta);
        self.root_area * (-exponent).exp2()
    }

    /// The cut refined for a node at `depth`: auxiliary nodes above the threshold replaced
    /// by their children until none is; for a node of at most `PRIMITIVE_CUT` primitives,
    /// down to the primitives; and a cut of one subtree opened until it has two members,
    /// so that there is something to split.
    fn refine(&self, cut: Vec<Item>, depth: usize, scratch: &mut Scratch) -> Vec<Item> {
        let count: u32 = cut.iter().map(Item::count).sum();
        let threshold = if count <= PRIMITIVE_CUT {
            -1.0
        } else {
            self.threshold(depth)
        };
        let stack = &mut scratch.stack;
        stack.clear();
        stack.extend(cut.iter().rev());
        let mut out = Vec::with_capacity(cut.len() * 2);
        while let Some(item) = stack.pop() {
            let open = item.node != PRIMITIVE
                && (f64::from(item.bounds.surface_area()) > threshold
                    || (out.is_empty() && stack.is_empty() && item.count() > 1));
            if open {
                let from = stack.len();
                self.aux.expand(&item, stack);
                // Children were pushed in order; the stack pops the last first.
                stack[from..].reverse();
            } else {
                out.push(item);
            }
        }
        out
    }

    /// Where to split a node over `cut` (at least two members), whose box is `bounds`:
    /// the least SAH cost over the cut sorted by centroid on each axis, or a leaf where
    /// that costs no more and the node is small enough.
    fn decide(
        &self,
        cut: &[Item],
        count: u32,
        bounds: &Aabb,
        depth: usize,
        scratch: &mut Scratch,
    ) -> Decision {
        let prims = self.aux.prims;
        if depth >= MAX_DEPTH - 1 {
            return Decision::Leaf;
        }
        if self.must_balance(count, depth) {
            return self.halve(cut, count);
        }
        let m = cut.len();
        let parent_area = bounds.surface_area().max(f32::MIN_POSITIVE);
        let mut best: Option<(usize, f32)> = None;
        for axis in 0..3 {
            // Keys of the centroid's order-preserving bits and the member's place in the
            // cut: unique, so one order for any sort, and sorted as plain integers.
            let sorted = &mut scratch.sorted;
            sorted.clear();
            sorted.extend((cut.iter().enumerate()).map(|(i, it)| {
                let c = 0.5 * (it.bounds.min[axis] + it.bounds.max[axis]);
                u64::from(ordered_bits(c)) << 32 | i as u64
            }));
            sorted.sort_unstable();
            let (right_area, right_count) = (&mut scratch.right_area, &mut scratch.right_count);
            right_area.resize(m, 0.0);
            right_count.resize(m, 0);
            let (mut acc, mut n) = (SimdBox::EMPTY, 0);
            for k in (1..m).rev() {
                let it = &cut[sorted[k] as u32 as usize];
                acc = acc.union(&it.bounds);
                n += it.count();
                right_area[k] = acc.surface_area();
                right_count[k] = n;
            }
            let (mut acc, mut n) = (SimdBox::EMPTY, 0);
            let mut improved = false;
            for k in 1..m {
                let it = &cut[sorted[k - 1] as u32 as usize];
                acc = acc.union(&it.bounds);
                n += it.count();
                let cost = self.phr.traversal_cost
                    + (acc.surface_area() * prims.leaf_cost(n as usize)
                        + right_area[k] * prims.leaf_cost(right_count[k] as usize))
                        / parent_area;
                if best.is_none_or(|(_, c)| cost < c) {
                    best = Some((k, cost));
                    improved = true;
                }
            }
            if improved {
                std::mem::swap(&mut scratch.sorted, &mut scratch.best);
            }
        }
        let (k, cost) = best.expect("a cut of two or more has a split");
        if count <= self.max_leaf_size && cost >= prims.leaf_cost(count as usize) {
            return Decision::Leaf;
        }
        let order: Vec<u32> = scratch.best.iter().map(|&key| key as u32).collect();
        let side =
            |range: &[u32]| -> Vec<Item> { range.iter().map(|&i| cut[i as usize]).collect() };
        Decision::split(side(&order[..k]), side(&order[k..]))
    }

    /// Whether a node of `count` primitives at `depth` must be split by count to keep
    /// the tree within `MAX_DEPTH` (the SAH may peel off one subtree at a time).
    fn must_balance(&self, count: u32, depth: usize) -> bool {
        let (mut n, mut levels) = (count, 1);
        while n > self.max_leaf_size {
            n = n.div_ceil(2);
            levels += 1;
        }
        depth + levels + 2 >= MAX_DEPTH
    }

    /// A node of `count` primitives split into two halves of its primitives in Morton
    /// order (a leaf where it fits in one).
    fn halve(&self, cut: &[Item], count: u32) -> Decision {
        if count <= self.max_leaf_size {
            return Decision::Leaf;
        }
        let mut positions: Vec<u32> = cut.iter().flat_map(|it| it.lo..it.hi).collect();
        positions.sort_unstable();
        let mut left: Vec<Item> = positions.iter().map(|&p| self.aux.primitive(p)).collect();
        let right = left.split_off(positions.len() / 2);
        Decision::split(left, right)
    }

    /// The node over `cut` at `depth`, its primitives written into `out` (its slice of the
    /// leaf order, which starts at `offset`).
    fn block(&self, cut: Vec<Item>, offset: u32, depth: usize, out: &mut [u32]) -> NodeBlock {
        if out.len() <= self.phr.parallel_threshold {
            let mut nodes = Vec::with_capacity(out.len() / 2 + 1);
            nodes.push(Node::leaf(Aabb::EMPTY, 0, 0));
            let mut scratch = Scratch::default();
            self.write(&mut nodes, 0, cut, offset, depth, out, &mut scratch);
            return NodeBlock::Serial(nodes);
        }
        let bounds = cut_bounds(&cut);
        let count = out.len() as u32;
        let mut scratch = Scratch::default();
        match self.decide(&cut, count, &bounds, depth, &mut scratch) {
            Decision::Leaf => {
                self.gather(&cut, out);
                NodeBlock::leaf(Node::leaf(bounds, offset, out.len()))
            }
            Decision::Split { left, right, .. } => {
                let left = self.refine(left, depth + 1, &mut scratch);
                let right = self.refine(right, depth + 1, &mut scratch);
                let mid: u32 = left.iter().map(Item::count).sum();
                let (lo, hi) = out.split_at_mut(mid as usize);
                let (l, r) = rayon::join(
                    || self.block(left, offset, depth + 1, lo),
                    || self.block(right, offset + mid, depth + 1, hi),
                );
                NodeBlock::split(Node::interior(bounds, 0), l, r)
            }
        }
    }

    /// Fills `nodes[index]` with the subtree over `cut`, its descendants appended.
    #[allow(clippy::too_many_arguments)]
    fn write(
        &self,
        nodes: &mut Vec<Node>,
        index: usize,
        cut: Vec<Item>,
        offset: u32,
        depth: usize,
        out: &mut [u32],
        scratch: &mut Scratch,
    ) {
        let bounds = cut_bounds(&cut);
        self.write_within(nodes, index, cut, bounds, offset, depth, out, scratch);
    }

    /// `write` for a cut whose box the parent's sweep already knows.
    #[allow(clippy::too_many_arguments)]
    fn write_within(
        &self,
        nodes: &mut Vec<Node>,
        index: usize,
        cut: Vec<Item>,
        bounds: Aabb,
        offset: u32,
        depth: usize,
        out: &mut [u32],
        scratch: &mut Scratch,
    ) {
        let count = out.len() as u32;
        if cut.len() == 1 {
            // One primitive (a refined cut of more primitives has two members or more).
            self.gather(&cut, out);
            nodes[index] = Node::leaf(bounds, offset, out.len());
            return;
        }
        let Decision::Split {
            left,
            right,
            left_bounds,
            right_bounds,
        } = self.decide(&cut, count, &bounds, depth, scratch)
        else {
            self.gather(&cut, out);
            nodes[index] = Node::leaf(bounds, offset, out.len());
            return;
        };
        drop(cut);
        let first = nodes.len();
        nodes[index] = Node::interior(bounds, first as u32);
        let placeholder = Node::leaf(Aabb::EMPTY, 0, 0);
        nodes.extend([placeholder, placeholder]);
        let left = self.refine(left, depth + 1, scratch);
        let mid: u32 = left.iter().map(Item::count).sum();
        let (lo, hi) = out.split_at_mut(mid as usize);
        self.write_within(
            nodes,
            first,
            left,
            left_bounds,
            offset,
            depth + 1,
            lo,
            scratch,
        );
        let right = self.refine(right, depth + 1, scratch);
        self.write_within(
            nodes,
            first + 1,
            right,
            right_bounds,
            offset + mid,
            depth + 1,
            hi,
            scratch,
        );
    }

    /// Writes the primitives of the cut's members, member by member, into `out`.
    fn gather(&self, cut: &[Item], out: &mut [u32]) {
        let mut k = 0;
        for it in cut {
            let run = &self.aux.morton[it.lo as usize..it.hi as usize];
            out[k..k + run.len()].copy_from_slice(run);
            k += run.len();
        }
        debug_assert_eq!(k, out.len());
    }
}

fn cut_bounds(cut: &[Item]) -> Aabb {
    (cut.iter())
        .fold(SimdBox::EMPTY, |b, it| b.union(&it.bounds))
        .to_aabb()
}

/// The bits of `x` as an integer that orders as `f32::total_cmp` orders the floats.
fn ordered_bits(x: f32) -> u32 {
    let bits = x.to_bits();
    if bits >> 31 == 1 {
        !bits
    } else {
        bits | 1 << 31
    }
}
