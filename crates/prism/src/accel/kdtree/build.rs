//! SAH kd-tree build with a sorted event sweep per node and axis, O(n log² n) overall.
//!
//! At each node and axis the primitives' box faces, clamped to the node, are sorted; a
//! sweep over them counts for every candidate plane how many primitives reach below and
//! above it, and prices the split as `traversal + intersection·(P_below·n_below +
//! P_above·n_above)` with P the children's share of the node's surface area. A split that
//! cuts off empty space gets the empty-space bonus (its cost scaled by `1 − bonus`), which
//! makes the tree wrap objects tightly. A node stays a leaf when no split beats testing its
//! primitives, except that a few unpromising splits in a row are tolerated (pbrt's
//! "bad refines"), since a better split often follows one that looked worse.

use super::{KdTree, Node, MAX_DEPTH};
use crate::accel::cells::padded_bounds;
use crate::accel::Accel;
use crate::accel::Method;
use crate::choices::{Key, Keyed};
use crate::field_key;
use crate::geometry::Geometry;
use crate::math::Aabb;

/// The SAH costs and depth limit of the kd-tree build; also the `kdtree:` keys.
#[derive(Clone, Debug, PartialEq)]
pub struct KdTreeOptions {
    /// Cost of one traversal step, relative to...
    pub traversal_cost: f32,
    /// ...the cost of one primitive test.
    pub intersection_cost: f32,
    /// Discount (0..1) for splits that leave one side empty.
    pub empty_bonus: f32,
    /// Depth limit; 0 picks `8 + 1.3·log₂ n` (pbrt's rule), never more than 60.
    pub max_depth: usize,
}

impl Default for KdTreeOptions {
    fn default() -> Self {
        KdTreeOptions {
            traversal_cost: 1.0,
            intersection_cost: 1.5,
            empty_bonus: 0.2,
            max_depth: 0,
        }
    }
}

impl Keyed for KdTreeOptions {
    const NAME: &'static str = "kdtree";
    const SUMMARY: &'static str = "kd-tree, SAH event-sweep build";
    const KEYS: &'static [Key<Self>] = &[
        field_key!("trav" => traversal_cost, number 0.0..=1000.0, "cost of a traversal step"),
        field_key!("isect" => intersection_cost, number 0.001..=1000.0, "cost of a primitive test"),
        field_key!("empty-bonus" => empty_bonus, number 0.0..=1.0,
            "discount for splits that leave one side empty"),
        field_key!("depth" => max_depth, int 0..=60, "depth limit (0 = 8 + 1.3·log₂ n)"),
    ];
}

impl Method for KdTreeOptions {
    fn build(&self, geometry: &Geometry, prims: Vec<u32>) -> Box<dyn Accel> {
        Box::new(KdTree::build(geometry, prims, self))
    }
}

struct Builder<'a> {
    boxes: &'a [Aabb],
    prims: &'a [u32],
    options: &'a KdTreeOptions,
    max_depth: usize,
}

/// Nodes with more references than this build their two children in parallel.
const PARALLEL_REFERENCES: usize = 50_000;

/// A tree or subtree in its own arrays: above-child indices and leaf offsets are relative to
/// its first node and first reference.
#[derive(Default)]
struct Subtree {
    nodes: Vec<Node>,
    refs: Vec<u32>,
}

impl Subtree {
    /// Appends `other` after the nodes and references already here, shifting its indices.
    fn append(&mut self, other: Subtree) {
        let (node_offset, ref_offset) = (self.nodes.len() as u32, self.refs.len() as u32);
        self.nodes.extend(other.nodes.into_iter().map(|n| {
            if n.is_leaf() {
                Node {
                    bits: n.bits,
                    data: n.data + ref_offset,
                }
            } else {
                Node {
                    bits: n.bits + (node_offset << 2),
                    data: n.data,
                }
            }
        }));
        self.refs.extend(other.refs);
    }
}

struct Split {
    axis: usize,
    position: f32,
    cost: f32,
}

/// A node's child: its cell and the items reaching into it.
type Side = (Aabb, Vec<u32>);

impl KdTree {
    /// Builds the tree over `prims` (indices into `geometry.primitives`).
    pub fn build(geometry: &Geometry, prims: Vec<u32>, options: &KdTreeOptions) -> KdTree {
        let (boxes, bounds) = padded_bounds(geometry, &prims);
        let n = prims.len();
        let max_depth = if options.max_depth == 0 {
            (8.0 + 1.3 * (n.max(1) as f32).log2()).round() as usize
        } else {
            options.max_depth
        }
        .clamp(1, MAX_DEPTH - 1);
        let b = Builder {
            boxes: &boxes,
            prims: &prims,
            options,
            max_depth,
        };
        let mut tree = Subtree::default();
        if n > 0 {
            b.node(&mut tree, bounds, (0..n as u32).collect(), 1, 0);
        }
        KdTree {
            bounds,
            nodes: tree.nodes,
            refs: tree.refs,
            primitives: n,
            options: options.clone(),
        }
    }
}

impl Builder<'_> {
    /// Builds the subtree over `items` (indices into `boxes`) at the end of `out` and
    /// returns its root's index. Big subtrees build their children on two threads; the
    /// result is the same tree as a serial build.
    fn node(
        &self,
        out: &mut Subtree,
        bounds: Aabb,
        items: Vec<u32>,
        depth: usize,
        bad_refines: u32,
    ) -> usize {
        let index = out.nodes.len();
        let (split, bad_refines) = self.choose_split(&bounds, &items, depth, bad_refines);
        let Some(split) = split else {
            out.nodes.push(Node::leaf(out.refs.len(), items.len()));
            out.refs
                .extend(items.iter().map(|&i| self.prims[i as usize]));
            return index;
        };
        let (below, above) = self.partition(&bounds, items, &split);
        out.nodes.push(Node::interior(split.axis, split.position));
        let above_index = if below.1.len() + above.1.len() > PARALLEL_REFERENCES {
            let subtree = |(b, items): Side| {
                let mut t = Subtree::default();
                self.node(&mut t, b, items, depth + 1, bad_refines);
                t
            };
            let (lo, hi) = rayon::join(|| subtree(below), || subtree(above));
            out.append(lo);
            let above_index = out.nodes.len();
            out.append(hi);
            above_index
        } else {
            self.node(out, below.0, below.1, depth + 1, bad_refines);
            self.node(out, above.0, above.1, depth + 1, bad_refines)
        };
        out.nodes[index].bits |= (above_index as u32) << 2;
        index
    }

    /// The split to make, if any, and the updated count of unpromising splits in a row.
    fn choose_split(
        &self,
        bounds: &Aabb,
        items: &[u32],
        depth: usize,
        bad_refines: u32,
    ) -> (Option<Split>, u32) {
        let n = items.len();
        let leaf_cost = self.options.intersection_cost * n as f32;
        let split = if n > 1 && depth < self.max_depth {
            self.best_split(bounds, items)
        } else {
            None
        };
        let bad_refines = bad_refines + split.as_ref().is_some_and(|s| s.cost >= leaf_cost) as u32;
        let split = split.filter(|s| bad_refines < 3 && !(s.cost > 4.0 * leaf_cost && n < 16));
        (split, bad_refines)
    }

    /// The two children's cells and items.
    fn partition(&self, bounds: &Aabb, items: Vec<u32>, split: &Split) -> (Side, Side) {
        let (axis, p) = (split.axis, split.position);
        // A box goes to each side it reaches into; one that merely touches the plane stays
        // on its own side (the padding already keeps it clear of the other), and a box
        // flat in the plane goes to both.
        let below: Vec<u32> = items
            .iter()
            .copied()
            .filter(|&i| {
                let b = &self.boxes[i as usize];
                b.min[axis] < p || b.max[axis] <= p
            })
            .collect();
        let above: Vec<u32> = items
            .into_iter()
            .filter(|&i| {
                let b = &self.boxes[i as usize];
                b.max[axis] > p || b.min[axis] >= p
            })
            .collect();
        let (mut lo, mut hi) = (*bounds, *bounds);
        lo.max[axis] = p;
        hi.min[axis] = p;
        ((lo, below), (hi, above))
    }

    fn best_split(&self, bounds: &Aabb, items: &[u32]) -> Option<Split> {
        let n = items.len();
        let o = self.options;
        let inv_area = 1.0 / bounds.surface_area();
        let extent = bounds.extent();
        let mut best: Option<Split> = None;
        let mut starts = Vec::with_capacity(n);
        let mut ends = Vec::with_capacity(n);
        let mut candidates = Vec::with_capacity(2 * n);
        for axis in 0..3 {
            let (lo, hi) = (bounds.min[axis], bounds.max[axis]);
            starts.clear();
            ends.clear();
            for &i in items {
                let b = &self.boxes[i as usize];
                starts.push(b.min[axis].max(lo));
                ends.push(b.max[axis].min(hi));
            }
            starts.sort_unstable_by(f32::total_cmp);
            ends.sort_unstable_by(f32::total_cmp);
            let (a1, a2) = ((axis + 1) % 3, (axis + 2) % 3);
            let cap = extent[a1] * extent[a2];
            let ring = extent[a1] + extent[a2];
            merge_inside(&starts, &ends, lo, hi, &mut candidates);
            // Walk the candidates in increasing order: `below` counts the boxes with
            // min < p, `ended` those with max <= p; the rest reach above p. (Boxes flat in
            // the plane, which go to both sides, are counted on one only: a heuristic.)
            let (mut below, mut ended) = (0, 0);
            for &p in &candidates {
                while below < n && starts[below] < p {
                    below += 1;
                }
                while ended < n && ends[ended] <= p {
                    ended += 1;
                }
                let above = n - ended;
                let area = |len: f32| 2.0 * (cap + len * ring);
                let p_below = area(p - lo) * inv_area;
                let p_above = area(hi - p) * inv_area;
                let mut cost = o.traversal_cost
                    + o.intersection_cost * (p_below * below as f32 + p_above * above as f32);
                if below == 0 || above == 0 {
                    cost *= 1.0 - o.empty_bonus;
                }
                if best.as_ref().is_none_or(|b| cost < b.cost) {
                    best = Some(Split {
                        axis,
                        position: p,
                        cost,
                    });
                }
            }
        }
        best
    }
}

/// The distinct values of two sorted lists that lie strictly between `lo` and `hi`, in
/// increasing order, into `out`: a linear merge, cheaper than sorting them again.
fn merge_inside(a: &[f32], b: &[f32], lo: f32, hi: f32, out: &mut Vec<f32>) {
    out.clear();
    let (mut i, mut j) = (0, 0);
    while i < a.len() || j < b.len() {
        let take_a = j == b.len() || (i < a.len() && a[i] <= b[j]);
        let p = if take_a { a[i] } else { b[j] };
        if take_a {
            i += 1;
        } else {
            j += 1;
        }
        if p > lo && p < hi && out.last() != Some(&p) {
            out.push(p);
        }
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn merge_inside_keeps_distinct_interior_values_in_order() {
        let mut out = Vec::new();
        super::merge_inside(
            &[0.0, 1.0, 2.0, 2.0, 5.0],
            &[1.0, 3.0, 4.0, 6.0],
            0.0,
            6.0,
            &mut out,
        );
        assert_eq!(out, [1.0, 2.0, 3.0, 4.0, 5.0]);
    }
}
