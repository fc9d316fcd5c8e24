//! Binned SAH splits (Wald 2007): centroids are sorted into a few bins per axis, and the
//! split between bins with the lowest surface-area cost wins, unless a leaf is cheaper.

use super::topdown::SplitRule;
use super::BuildPrims;
use crate::accel::bvh::BvhOptions;
use crate::math::Aabb;

pub(super) struct BinnedSah {
    bins: usize,
    max_leaf_size: usize,
    traversal_cost: f32,
}

impl BinnedSah {
    pub(super) fn new(options: &BvhOptions) -> Self {
        BinnedSah {
            bins: options.bins.max(2),
            max_leaf_size: options.max_leaf_size.max(1),
            traversal_cost: options.traversal_cost,
        }
    }
}

/// Scratch space of the SAH sweep, one entry per bin each.
pub(super) struct Sweep {
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

impl SplitRule for BinnedSah {
    type Scratch = Sweep;

    fn scratch(&self) -> Sweep {
        Sweep {
            bins: vec![Bin::EMPTY; self.bins],
            right_area: vec![0.0; self.bins],
            right_count: vec![0; self.bins],
        }
    }

    fn split(
        &self,
        prims: &BuildPrims,
        sweep: &mut Sweep,
        order: &mut [u32],
        bounds: &Aabb,
        centroid_bounds: &Aabb,
    ) -> Option<usize> {
        let n = order.len();
        match self.best_split(prims, sweep, order, bounds, centroid_bounds) {
            Some((axis, pos, cost)) => {
                if n <= self.max_leaf_size && cost >= n as f32 {
                    return None;
                }
                let mid = partition(order, |&i| prims.centroids[i as usize][axis] < pos);
                // Rounding can put every centroid on one side of the plane.
                Some(if mid == 0 || mid == n { n / 2 } else { mid })
            }
            // All centroids coincide: SAH cannot separate them, so split the list in half
            // (if it is too big for a leaf) to keep leaves bounded.
            None if n <= self.max_leaf_size => None,
            None => Some(n / 2),
        }
    }
}

impl BinnedSah {
    /// The cheapest binned split as (axis, centroid position, SAH cost in units of one
    /// primitive test), or `None` when all centroids coincide.
    fn best_split(
        &self,
        prims: &BuildPrims,
        sweep: &mut Sweep,
        order: &[u32],
        bounds: &Aabb,
        centroid_bounds: &Aabb,
    ) -> Option<(usize, f32, f32)> {
        let nb = self.bins;
        let mut best: Option<(usize, f32, f32)> = None;
        let parent_area = bounds.surface_area().max(f32::MIN_POSITIVE);
        let Sweep {
            bins,
            right_area,
            right_count,
        } = sweep;
        for axis in 0..3 {
            let lo = centroid_bounds.min[axis];
            let extent = centroid_bounds.max[axis] - lo;
            if extent.is_nan() || extent <= 0.0 {
                continue;
            }
            let scale = nb as f32 / extent;
            bins.fill(Bin::EMPTY);
            for &i in order {
                let b = (((prims.centroids[i as usize][axis] - lo) * scale) as usize).min(nb - 1);
                bins[b].count += 1;
                bins[b].bounds = bins[b].bounds.union(&prims.bounds[i as usize]);
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
                let cost = self.traversal_cost
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
