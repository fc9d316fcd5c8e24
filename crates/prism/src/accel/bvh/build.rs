//! Binned SAH construction (Wald 2007): at every node, centroids are sorted into a few
//! bins per axis, and the split between bins with the lowest surface-area cost wins, unless
//! a leaf is cheaper.

use super::{Bvh, Node, MAX_DEPTH};
use crate::geometry::Geometry;
use crate::math::{Aabb, Vec3};

#[derive(Clone, Debug, PartialEq)]
pub struct BvhOptions {
    /// Bins per axis for the SAH sweep.
    pub bins: usize,
    /// Leaves never hold more primitives than this (unless they cannot be split).
    pub max_leaf_size: usize,
    /// Cost of a node visit relative to one primitive test.
    pub traversal_cost: f32,
}

impl Default for BvhOptions {
    fn default() -> Self {
        BvhOptions {
            bins: 16,
            max_leaf_size: 8,
            traversal_cost: 1.0,
        }
    }
}

struct Builder<'a> {
    options: &'a BvhOptions,
    bounds: Vec<Aabb>,
    centroids: Vec<Vec3>,
    nodes: Vec<Node>,
    /// Per-node sweep buffers, reused so a node costs no heap allocations.
    sweep: Sweep,
}

/// Scratch space of the SAH sweep, `options.bins` entries each.
struct Sweep {
    bins: Vec<Bin>,
    right_area: Vec<f32>,
    right_count: Vec<u32>,
}

#[derive(Clone, Copy)]
struct Bin {
    bounds: Aabb,
    count: u32,
}

impl Bin {
    const EMPTY: Bin = Bin {
        bounds: Aabb::EMPTY,
        count: 0,
    };
}

impl Bvh {
    /// Builds over `prims`, which must all be bounded.
    pub fn build(geometry: &Geometry, prims: Vec<u32>, options: &BvhOptions) -> Bvh {
        let bounds: Vec<Aabb> = prims
            .iter()
            .map(|&p| geometry.bounds(p).expect("BVH primitives must be bounded"))
            .collect();
        Bvh::build_over_bounds(prims, bounds, options)
    }

    /// Builds over items known only by their boxes (`bounds[i]` bounds `prims[i]`), for
    /// hierarchies whose leaves are not single primitives.
    pub(crate) fn build_over_bounds(
        mut prims: Vec<u32>,
        bounds: Vec<Aabb>,
        options: &BvhOptions,
    ) -> Bvh {
        let centroids = bounds.iter().map(Aabb::center).collect();
        let mut builder = Builder {
            options,
            bounds,
            centroids,
            nodes: Vec::with_capacity(2 * prims.len().max(1)),
            sweep: Sweep {
                bins: vec![Bin::EMPTY; options.bins],
                right_area: vec![0.0; options.bins],
                right_count: vec![0; options.bins],
            },
        };
        // Work on positions 0..n into the local arrays; map back to primitive ids at the end.
        let mut order: Vec<u32> = (0..prims.len() as u32).collect();
        if !order.is_empty() {
            builder.nodes.push(Node {
                min: Vec3::ZERO,
                first: 0,
                max: Vec3::ZERO,
                count: 0,
            });
            builder.subdivide(0, &mut order, 0, 1);
        }
        prims = order.iter().map(|&i| prims[i as usize]).collect();
        Bvh::from_tree(builder.nodes, prims)
    }
}

impl Builder<'_> {
    /// Fills node `index` for `order` (whose first element sits at `offset` in the final
    /// primitive array).
    fn subdivide(&mut self, index: usize, order: &mut [u32], offset: u32, depth: usize) {
        let bounds = order
            .iter()
            .fold(Aabb::EMPTY, |b, &i| b.union(&self.bounds[i as usize]));
        let centroid_bounds = order.iter().fold(Aabb::EMPTY, |b, &i| {
            b.union_point(self.centroids[i as usize])
        });
        self.nodes[index].min = bounds.min;
        self.nodes[index].max = bounds.max;

        let n = order.len();
        let make_leaf = |nodes: &mut Vec<Node>| {
            nodes[index].first = offset;
            nodes[index].count = n as u32;
        };
        if n == 1 || depth >= MAX_DEPTH - 1 {
            return make_leaf(&mut self.nodes);
        }

        let split = self.best_split(order, &bounds, &centroid_bounds);
        let mid = match split {
            Some((axis, pos, cost)) => {
                if n <= self.options.max_leaf_size && cost >= n as f32 {
                    return make_leaf(&mut self.nodes);
                }
                let mid = partition(order, |&i| self.centroids[i as usize][axis] < pos);
                if mid == 0 || mid == n {
                    n / 2
                } else {
                    mid
                }
            }
            // All centroids coincide: SAH cannot separate them, so split the list in half
            // (if it is too big for a leaf) to keep leaves bounded.
            None if n <= self.options.max_leaf_size => return make_leaf(&mut self.nodes),
            None => n / 2,
        };

        let left = self.nodes.len();
        let empty = Node {
            min: Vec3::ZERO,
            first: 0,
            max: Vec3::ZERO,
            count: 0,
        };
        self.nodes.push(empty);
        self.nodes.push(empty);
        self.nodes[index].first = left as u32;
        self.nodes[index].count = 0;
        let (lo, hi) = order.split_at_mut(mid);
        self.subdivide(left, lo, offset, depth + 1);
        self.subdivide(left + 1, hi, offset + mid as u32, depth + 1);
    }

    /// The cheapest binned split as (axis, centroid position, SAH cost in units of one
    /// primitive test), or `None` when all centroids coincide.
    fn best_split(
        &mut self,
        order: &[u32],
        bounds: &Aabb,
        centroid_bounds: &Aabb,
    ) -> Option<(usize, f32, f32)> {
        let nb = self.options.bins;
        let mut best: Option<(usize, f32, f32)> = None;
        let parent_area = bounds.surface_area().max(f32::MIN_POSITIVE);
        let Sweep {
            bins,
            right_area,
            right_count,
        } = &mut self.sweep;
        for axis in 0..3 {
            let lo = centroid_bounds.min[axis];
            let extent = centroid_bounds.max[axis] - lo;
            if extent.is_nan() || extent <= 0.0 {
                continue;
            }
            let scale = nb as f32 / extent;
            bins.fill(Bin::EMPTY);
            for &i in order {
                let b = (((self.centroids[i as usize][axis] - lo) * scale) as usize).min(nb - 1);
                bins[b].count += 1;
                bins[b].bounds = bins[b].bounds.union(&self.bounds[i as usize]);
            }
            // Sweep from the right, then from the left, evaluating the split after bin k.
            let (mut acc, mut count) = (Aabb::EMPTY, 0);
            for k in (1..nb).rev() {
                acc = acc.union(&bins[k].bounds);
                count += bins[k].count;
                right_area[k] = acc.surface_area();
                right_count[k] = count;
            }
            let (mut acc, mut count) = (Aabb::EMPTY, 0);
            for k in 0..nb - 1 {
                acc = acc.union(&bins[k].bounds);
                count += bins[k].count;
                if count == 0 || right_count[k + 1] == 0 {
                    continue;
                }
                let cost = self.options.traversal_cost
                    + (acc.surface_area() * count as f32
                        + right_area[k + 1] * right_count[k + 1] as f32)
                        / parent_area;
                if best.is_none_or(|(_, _, c)| cost < c) {
                    best = Some((axis, lo + (k + 1) as f32 / scale, cost));
                }
            }
        }
        best
    }
}

/// In-place partition; returns the number of elements for which `pred` holds (now first).
fn partition<T>(items: &mut [T], pred: impl Fn(&T) -> bool) -> usize {
    let mut first = 0;
    for i in 0..items.len() {
        if pred(&items[i]) {
            items.swap(first, i);
            first += 1;
        }
    }
    first
}
