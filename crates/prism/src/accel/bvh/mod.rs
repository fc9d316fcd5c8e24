//! Bounding volume hierarchy over axis-aligned boxes: a binned SAH build (`build.rs`) into
//! a flat array of 32-byte nodes, and a stack traversal that visits the nearer child first
//! (`traverse.rs`).

mod build;
mod traverse;

use crate::math::Vec3;

pub use build::BvhOptions;

/// A node is 32 bytes, two to a cache line. Interior nodes have `count == 0` and their
/// children at `first` and `first + 1`; leaves hold `prims[first .. first + count]`.
#[derive(Clone, Copy, Debug)]
#[repr(C)]
struct Node {
    min: Vec3,
    first: u32,
    max: Vec3,
    count: u32,
}

impl Node {
    fn is_leaf(&self) -> bool {
        self.count > 0
    }
}

pub struct Bvh {
    nodes: Vec<Node>,
    /// Primitive indices (into `Geometry::primitives`) in leaf order.
    prims: Vec<u32>,
}

/// Depth the build never exceeds, so traversal can use a fixed stack.
const MAX_DEPTH: usize = 64;

impl Bvh {
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    pub fn primitive_count(&self) -> usize {
        self.prims.len()
    }

    /// Depth of the deepest leaf (the root alone has depth 1).
    pub fn depth(&self) -> usize {
        fn walk(nodes: &[Node], i: usize) -> usize {
            let n = &nodes[i];
            if n.is_leaf() || nodes.is_empty() {
                1
            } else {
                1 + walk(nodes, n.first as usize).max(walk(nodes, n.first as usize + 1))
            }
        }
        if self.nodes.is_empty() {
            0
        } else {
            walk(&self.nodes, 0)
        }
    }

    pub fn memory_bytes(&self) -> usize {
        self.nodes.len() * std::mem::size_of::<Node>() + self.prims.len() * 4
    }
}
