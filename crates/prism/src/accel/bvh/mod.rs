//! Bounding volume hierarchy over axis-aligned boxes: several builders (`build/`) into a
//! flat array of 32-byte nodes, an optional reinsertion pass (`reinsert.rs`), a stack
//! traversal that visits the nearer child first (`traverse.rs`), and the queries of
//! `Accel` over it (`accel.rs`).

mod accel;
mod build;
mod leaves;
mod options;
mod packet;
mod reinsert;
mod simd8;
mod subtree;
mod traverse;
mod wide;

use crate::accel::AccelInfo;
use crate::math::{Aabb, Vec3};
use wide::{Wide8Node, WideNode};

pub use options::{Avx512, BvhBuilder, BvhOptions, NodeWidth, RayOrigins};
pub use subtree::{Entry, EntryNodes, Subtree};

/// A node is 32 bytes, two to a cache line. Interior nodes have `count == 0` and their
/// children at `first` and `first + 1`; leaves hold `prims[first .. first + count]`.
#[derive(Clone, Copy, Debug, PartialEq)]
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

    fn leaf(bounds: Aabb, first: u32, count: usize) -> Node {
        Node {
            min: bounds.min,
            first,
            max: bounds.max,
            count: count as u32,
        }
    }

    fn interior(bounds: Aabb, first: u32) -> Node {
        Node {
            min: bounds.min,
            first,
            max: bounds.max,
            count: 0,
        }
    }

    fn bounds(&self) -> Aabb {
        Aabb {
            min: self.min,
            max: self.max,
        }
    }

    /// The same node with its children `shift` places further on (leaves unchanged).
    fn relocated(self, shift: u32) -> Node {
        if self.is_leaf() {
            self
        } else {
            Node {
                first: self.first + shift,
                ..self
            }
        }
    }
}

/// Two trees are equal when their nodes and primitive orders are (how the tests check that
/// a parallel build is the serial one).
#[derive(PartialEq)]
pub struct Bvh {
    /// The tree as built: binary nodes, the root at 0.
    nodes: Vec<Node>,
    /// The same tree as traversed: 4-wide nodes (`wide.rs`).
    /// Empty when `wide8` is used.
    wide: Vec<WideNode>,
    /// The same tree as 8-wide nodes (`wide.rs`, traversed by `simd8.rs`): built instead of
    /// `wide` when the CPU has AVX2 (`NodeWidth::Auto`), otherwise empty.
    wide8: Vec<Wide8Node>,
    /// Whether packets walk `wide8` with the AVX-512 kernels (`BvhOptions::avx512`, and
    /// only where the CPU has them).
    packet_avx512: bool,
    /// Leaves of triangles only, their vertices in leaf order (`leaves.rs`); empty until
    /// `Bvh::build` packs them (a tree over boxes alone has none).
    packs: Vec<crate::geometry::TrianglePack>,
    /// Primitive indices (into `Geometry::primitives`) in leaf order.
    prims: Vec<u32>,
    builder: BvhBuilder,
    reinserted: bool,
    /// Whether triangles were split into several references before the build.
    presplit: bool,
    /// Whether `prims` may hold an id more than once (pre-split or spatial splits).
    duplicates: bool,
    /// Whether the binned SAH expected rays from inside the scene (`RayOrigins::Inside`).
    inside: bool,
    /// What `build=auto` chose and why (`build/auto.rs`), for `info`.
    auto: Option<String>,
}

/// Depth the build never exceeds, so traversal can use a fixed stack.
const MAX_DEPTH: usize = 64;

impl Bvh {
    /// Takes a built tree (root at 0, interior nodes' children at `first`, `first + 1`)
    /// and derives the traversal layout.
    fn from_tree(nodes: Vec<Node>, prims: Vec<u32>, options: &BvhOptions) -> Bvh {
        let (wide, wide8) = if options.width == NodeWidth::Auto && simd8::available() {
            (Vec::new(), Wide8Node::from_tree(&nodes))
        } else {
            (WideNode::from_tree(&nodes), Vec::new())
        };
        let packet_avx512 =
            !wide8.is_empty() && options.avx512 == Avx512::Auto && simd8::avx512_available();
        Bvh {
            nodes,
            wide,
            wide8,
            packet_avx512,
            packs: Vec::new(),
            prims,
            builder: options.builder,
            reinserted: options.reinsert,
            presplit: options.presplit > 0.0,
            duplicates: options.presplit > 0.0 || options.builder.clips_triangles(),
            inside: options.for_rays_from_inside(),
            auto: None,
        }
    }

    /// Nodes of the binary tree as built.
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Primitive references in the leaves (more than the primitives when pre-split).
    pub fn primitive_count(&self) -> usize {
        self.prims.len()
    }

    fn distinct_primitives(&self) -> usize {
        if !self.duplicates {
            return self.prims.len();
        }
        let mut ids = self.prims.clone();
        ids.sort_unstable();
        ids.dedup();
        ids.len()
    }

    /// Depth of the deepest leaf (the root alone has depth 1).
    pub fn depth(&self) -> usize {
        self.info().depth
    }

    /// Shape statistics and the SAH cost of the built tree.
    pub fn info(&self) -> AccelInfo {
        let mut info = AccelInfo {
            method: format!(
                "bvh ({}{}{}{}{})",
                self.builder.description(),
                if self.inside {
                    " for rays from inside"
                } else {
                    ""
                },
                if self.presplit { " + pre-split" } else { "" },
                if self.reinserted {
                    " + reinsertion"
                } else {
                    ""
                },
                (self.auto.as_ref()).map_or(String::new(), |why| format!("; {why}"))
            ),
            primitives: self.distinct_primitives(),
            nodes: self.nodes.len(),
            memory_bytes: self.memory_bytes(),
            ..AccelInfo::default()
        };
        if self.nodes.is_empty() {
            return info;
        }
        let area = |n: &Node| Aabb::new(n.min, n.max).surface_area() as f64;
        let root_area = area(&self.nodes[0]).max(f64::MIN_POSITIVE);
        let (mut cost, mut leaf_prims) = (0.0, 0);
        // Iterative walk with depths; recursion could be as deep as MAX_DEPTH anyway.
        let mut stack = vec![(0usize, 1usize)];
        while let Some((i, depth)) = stack.pop() {
            let n = &self.nodes[i];
            let share = area(n) / root_area;
            info.depth = info.depth.max(depth);
            if n.is_leaf() {
                info.leaves += 1;
                info.max_leaf_size = info.max_leaf_size.max(n.count as usize);
                leaf_prims += n.count as usize;
                cost += share * n.count as f64;
            } else {
                cost += share;
                stack.push((n.first as usize, depth + 1));
                stack.push((n.first as usize + 1, depth + 1));
            }
        }
        info.mean_leaf_size = leaf_prims as f64 / info.leaves.max(1) as f64;
        info.sah_cost = Some(cost);
        info
    }

    /// The tree's topology for hierarchies that reuse it with other volumes: per node,
    /// `(first, count)` as in `Node` (children at `first`, `first + 1` when `count == 0`),
    /// and the node's box.
    pub(crate) fn topology(&self) -> impl Iterator<Item = (u32, u32, Aabb)> + '_ {
        self.nodes
            .iter()
            .map(|n| (n.first, n.count, Aabb::new(n.min, n.max)))
    }

    /// Primitive indices in leaf order: a leaf holds `leaf_order()[first .. first + count]`.
    pub(crate) fn leaf_order(&self) -> &[u32] {
        &self.prims
    }

    /// Both layouts of the tree, the triangle packs and the primitive list.
    pub fn memory_bytes(&self) -> usize {
        self.nodes.len() * std::mem::size_of::<Node>()
            + self.wide.len() * std::mem::size_of::<WideNode>()
            + self.wide8.len() * std::mem::size_of::<Wide8Node>()
            + self.packs.len() * std::mem::size_of::<crate::geometry::TrianglePack>()
            + self.prims.len() * 4
    }
}
