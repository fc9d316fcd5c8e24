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
use crate::geometry::Geometry;
use crate::math::Aabb;

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

struct Builder<'a> {
    boxes: &'a [Aabb],
    prims: &'a [u32],
    options: &'a KdTreeOptions,
    max_depth: usize,
    nodes: Vec<Node>,
    refs: Vec<u32>,
}

struct Split {
    axis: usize,
    position: f32,
    cost: f32,
}

impl KdTree {
    pub fn build(geometry: &Geometry, prims: Vec<u32>, options: &KdTreeOptions) -> KdTree {
        let (boxes, bounds) = padded_bounds(geometry, &prims);
        let n = prims.len();
        let max_depth = if options.max_depth == 0 {
            (8.0 + 1.3 * (n.max(1) as f32).log2()).round() as usize
        } else {
            options.max_depth
        }
        .clamp(1, MAX_DEPTH - 1);
        let mut b = Builder {
            boxes: &boxes,
            prims: &prims,
            options,
            max_depth,
            nodes: Vec::new(),
            refs: Vec::new(),
        };
        if n > 0 {
            b.node(bounds, (0..n as u32).collect(), 1, 0);
        }
        KdTree {
            bounds,
            nodes: b.nodes,
            refs: b.refs,
            primitives: n,
            options: options.clone(),
        }
    }
}

impl Builder<'_> {
    /// Builds the subtree over `items` (indices into `boxes`) and returns its node index.
    fn node(&mut self, bounds: Aabb, items: Vec<u32>, depth: usize, bad_refines: u32) -> usize {
        let index = self.nodes.len();
        let n = items.len();
        let leaf_cost = self.options.intersection_cost * n as f32;
        let split = if n > 1 && depth < self.max_depth {
            self.best_split(&bounds, &items)
        } else {
            None
        };
        let bad_refines = bad_refines + split.as_ref().is_some_and(|s| s.cost >= leaf_cost) as u32;
        let split = split.filter(|s| bad_refines < 3 && !(s.cost > 4.0 * leaf_cost && n < 16));
        let Some(split) = split else {
            self.nodes.push(Node::leaf(self.refs.len(), n));
            self.refs
                .extend(items.iter().map(|&i| self.prims[i as usize]));
            return index;
        };
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
        let (mut lo, mut hi) = (bounds, bounds);
        lo.max[axis] = p;
        hi.min[axis] = p;
        self.nodes.push(Node::interior(axis, p));
        self.node(lo, below, depth + 1, bad_refines);
        let above_index = self.node(hi, above, depth + 1, bad_refines);
        self.nodes[index].bits |= (above_index as u32) << 2;
        index
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
