//! Adaptive octree: a cell holding more than a few primitives is cut into eight equal
//! octants, down to a depth limit (`build.rs`); rays visit the octants they cross in order
//! along the ray (`traverse.rs`).

mod build;
mod traverse;

use crate::accel::AccelInfo;
use crate::math::Aabb;

pub use build::OctreeOptions;

/// Depth the build never exceeds, so traversal can use a fixed stack.
const MAX_DEPTH: usize = 20;

/// Eight bytes. Interior nodes (`count == INTERIOR`) have their eight children at
/// `first .. first + 8`, child `c` being the octant on the high side of axis k where bit k
/// of c is set. Leaves hold `refs[first .. first + count]`.
#[derive(Clone, Copy, Debug)]
struct Node {
    first: u32,
    count: u32,
}

const INTERIOR: u32 = u32::MAX;

impl Node {
    fn is_leaf(&self) -> bool {
        self.count != INTERIOR
    }
}

/// Octant `child` of `bounds`.
fn octant(bounds: &Aabb, child: usize) -> Aabb {
    let mid = bounds.center();
    let mut b = *bounds;
    for k in 0..3 {
        if child >> k & 1 == 1 {
            b.min[k] = mid[k];
        } else {
            b.max[k] = mid[k];
        }
    }
    b
}

/// An adaptive octree: cells split into eight equal octants while they hold many
/// primitives.
pub struct Octree {
    bounds: Aabb,
    nodes: Vec<Node>,
    refs: Vec<u32>,
    primitives: usize,
    options: OctreeOptions,
}

impl Octree {
    /// Bytes of the nodes and reference lists.
    pub fn memory_bytes(&self) -> usize {
        self.nodes.len() * std::mem::size_of::<Node>() + self.refs.len() * 4
    }

    /// Shape statistics of the built tree.
    pub fn info(&self) -> AccelInfo {
        let mut info = AccelInfo {
            method: format!(
                "octree (leaves up to {} primitives, depth ≤ {})",
                self.options.max_leaf_size, self.options.max_depth
            ),
            primitives: self.primitives,
            nodes: self.nodes.len(),
            memory_bytes: self.memory_bytes(),
            ..AccelInfo::default()
        };
        if self.nodes.is_empty() {
            return info;
        }
        let (mut refs, mut non_empty) = (0, 0);
        let mut stack = vec![(0usize, 1usize)];
        while let Some((i, depth)) = stack.pop() {
            let n = self.nodes[i];
            info.depth = info.depth.max(depth);
            if n.is_leaf() {
                info.leaves += 1;
                info.max_leaf_size = info.max_leaf_size.max(n.count as usize);
                refs += n.count as usize;
                non_empty += (n.count > 0) as usize;
            } else {
                stack.extend((0..8).map(|c| (n.first as usize + c, depth + 1)));
            }
        }
        info.mean_leaf_size = refs as f64 / non_empty.max(1) as f64;
        info
    }
}
