//! kd-tree: axis-aligned splitting planes chosen by the surface area heuristic
//! (`build.rs`), walked front to back with a stack of far children (`traverse.rs`).
//!
//! The build is clip-free: a primitive goes to every side its (padded) bounding box
//! touches, and split candidates are the box faces clamped to the node. Clipping the
//! primitives to the node would give tighter candidates on big triangles, but needs exact
//! polygon clipping per shape kind; the boxes keep the build shape-agnostic.

mod build;
mod traverse;

use crate::accel::AccelInfo;
use crate::math::Aabb;

pub use build::KdTreeOptions;

/// Depth the build never exceeds, so traversal can use a fixed stack.
const MAX_DEPTH: usize = 60;

/// Eight bytes. Interior: `bits = above << 2 | axis`, `data` the split position's bits, the
/// below child right after the node. Leaf: `bits = count << 2 | 3`, `data` the offset of
/// its primitive ids in `refs`.
#[derive(Clone, Copy, Debug)]
struct Node {
    bits: u32,
    data: u32,
}

const LEAF: u32 = 3;

impl Node {
    fn leaf(first: usize, count: usize) -> Node {
        Node {
            bits: (count as u32) << 2 | LEAF,
            data: first as u32,
        }
    }

    fn interior(axis: usize, split: f32) -> Node {
        Node {
            bits: axis as u32,
            data: split.to_bits(),
        }
    }

    fn is_leaf(&self) -> bool {
        self.bits & 3 == LEAF
    }

    fn axis(&self) -> usize {
        (self.bits & 3) as usize
    }

    fn split(&self) -> f32 {
        f32::from_bits(self.data)
    }

    /// Index of the above child (interior nodes).
    fn above(&self) -> usize {
        (self.bits >> 2) as usize
    }

    /// `(first, count)` of a leaf's primitive ids.
    fn prims(&self) -> (usize, usize) {
        (self.data as usize, (self.bits >> 2) as usize)
    }
}

/// A kd-tree: axis-aligned splitting planes chosen by the SAH, leaves listing the
/// primitives they overlap.
pub struct KdTree {
    bounds: Aabb,
    nodes: Vec<Node>,
    refs: Vec<u32>,
    primitives: usize,
    options: KdTreeOptions,
}

impl KdTree {
    /// Bytes of the nodes and reference lists.
    pub fn memory_bytes(&self) -> usize {
        self.nodes.len() * std::mem::size_of::<Node>() + self.refs.len() * 4
    }

    /// Shape statistics and the SAH cost of the built tree.
    pub fn info(&self) -> AccelInfo {
        let mut info = AccelInfo {
            method: format!(
                "kd-tree (SAH sweep, traversal {} : intersection {}, empty bonus {})",
                self.options.traversal_cost,
                self.options.intersection_cost,
                self.options.empty_bonus
            ),
            primitives: self.primitives,
            nodes: self.nodes.len(),
            memory_bytes: self.memory_bytes(),
            ..AccelInfo::default()
        };
        if self.nodes.is_empty() {
            return info;
        }
        let root_area = self.bounds.surface_area() as f64;
        let (mut cost, mut refs, mut non_empty) = (0.0, 0, 0);
        let mut stack = vec![(0usize, self.bounds, 1usize)];
        while let Some((i, b, depth)) = stack.pop() {
            let n = self.nodes[i];
            let share = b.surface_area() as f64 / root_area.max(f64::MIN_POSITIVE);
            info.depth = info.depth.max(depth);
            if n.is_leaf() {
                let count = n.prims().1;
                info.leaves += 1;
                info.max_leaf_size = info.max_leaf_size.max(count);
                refs += count;
                non_empty += (count > 0) as usize;
                cost += share * count as f64;
            } else {
                cost += share;
                let (mut lo, mut hi) = (b, b);
                lo.max[n.axis()] = n.split();
                hi.min[n.axis()] = n.split();
                stack.push((i + 1, lo, depth + 1));
                stack.push((n.above(), hi, depth + 1));
            }
        }
        info.mean_leaf_size = refs as f64 / non_empty.max(1) as f64;
        info.sah_cost = Some(cost);
        info
    }
}
