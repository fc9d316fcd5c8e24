//! Octree construction: split a cell into octants while it holds more than
//! `max_leaf_size` primitives, the depth limit allows, and the split is likely to pay.

use super::{octant, Node, Octree, INTERIOR, MAX_DEPTH};
use crate::accel::cells::padded_bounds;
use crate::accel::Accel;
use crate::accel::Method;
use crate::choices::{Key, Keyed};
use crate::field_key;
use crate::geometry::Geometry;
use crate::math::Aabb;

/// When a cell splits and how deep; also the `octree:` keys.
#[derive(Clone, Debug, PartialEq)]
pub struct OctreeOptions {
    /// A cell with more primitives than this is subdivided.
    pub max_leaf_size: usize,
    /// Depth limit (the root has depth 1), at most 20.
    pub max_depth: usize,
}

impl Default for OctreeOptions {
    fn default() -> Self {
        OctreeOptions {
            max_leaf_size: 8,
            max_depth: 12,
        }
    }
}

impl Keyed for OctreeOptions {
    const NAME: &'static str = "octree";
    const SUMMARY: &'static str = "adaptive octree";
    const KEYS: &'static [Key<Self>] = &[
        field_key!("leaf" => max_leaf_size, int 1..=1024,
            "a cell with more primitives is subdivided"),
        field_key!("depth" => max_depth, int 1..=20, "depth limit, the root being 1"),
    ];
}

impl Method for OctreeOptions {
    fn build(&self, geometry: &Geometry, prims: Vec<u32>) -> Box<dyn Accel> {
        Box::new(Octree::build(geometry, prims, self))
    }
}

/// Whether two closed boxes share at least a point.
fn overlaps(a: &Aabb, b: &Aabb) -> bool {
    a.min.cmple(b.max).all() && b.min.cmple(a.max).all()
}

struct Builder<'a> {
    boxes: &'a [Aabb],
    prims: &'a [u32],
    options: &'a OctreeOptions,
    nodes: Vec<Node>,
    refs: Vec<u32>,
}

impl Octree {
    /// Builds the tree over `prims` (indices into `geometry.primitives`).
    pub fn build(geometry: &Geometry, prims: Vec<u32>, options: &OctreeOptions) -> Octree {
        let (boxes, bounds) = padded_bounds(geometry, &prims);
        let options = OctreeOptions {
            max_leaf_size: options.max_leaf_size.max(1),
            max_depth: options.max_depth.clamp(1, MAX_DEPTH),
        };
        let mut b = Builder {
            boxes: &boxes,
            prims: &prims,
            options: &options,
            nodes: Vec::new(),
            refs: Vec::new(),
        };
        if !prims.is_empty() {
            b.nodes.push(Node { first: 0, count: 0 });
            b.fill(0, &bounds, (0..prims.len() as u32).collect(), 1);
        }
        let (nodes, refs) = (b.nodes, b.refs);
        Octree {
            bounds,
            nodes,
            refs,
            primitives: prims.len(),
            options,
        }
    }
}

impl Builder<'_> {
    /// Makes node `index`, covering `bounds`, a leaf over `items` or an interior node.
    fn fill(&mut self, index: usize, bounds: &Aabb, items: Vec<u32>, depth: usize) {
        let n = items.len();
        if n > self.options.max_leaf_size && depth < self.options.max_depth {
            // A primitive goes to every octant its padded box touches (closed boxes): the
            // padding keeps rounding at the octant faces from hiding it.
            let children: Vec<(Aabb, Vec<u32>)> = (0..8)
                .map(|c| {
                    let b = octant(bounds, c);
                    let inside = items
                        .iter()
                        .copied()
                        .filter(|&i| overlaps(&self.boxes[i as usize], &b))
                        .collect();
                    (b, inside)
                })
                .collect();
            // A ray crossing the cell passes through two octants on average (each has a
            // quarter of its surface area), so at 4n references in all a cut would no
            // longer pay. Stopping at 3n keeps copies of big primitives from multiplying
            // level after level (at 4n the gears scene took 226 MiB, at 2n its leaves
            // stayed huge), and stops at coincident primitives.
            let references: usize = children.iter().map(|(_, c)| c.len()).sum();
            if references < 3 * n {
                let first = self.nodes.len();
                self.nodes[index] = Node {
                    first: first as u32,
                    count: INTERIOR,
                };
                self.nodes
                    .extend(std::iter::repeat_n(Node { first: 0, count: 0 }, 8));
                for (c, (b, inside)) in children.into_iter().enumerate() {
                    self.fill(first + c, &b, inside, depth + 1);
                }
                return;
            }
        }
        self.nodes[index] = Node {
            first: self.refs.len() as u32,
            count: n as u32,
        };
        self.refs
            .extend(items.iter().map(|&i| self.prims[i as usize]));
    }
}
