//! Binned SAH splits (Wald 2007): centroids are sorted into a few bins per axis, and the
//! split between bins with the lowest surface-area cost wins, unless a leaf is cheaper.
//! One pass bins all three axes; the bins also give each side's bounds, so a child never
//! passes over its primitives just to bound them.

use super::topdown::{Split, SplitRule, PARALLEL_PASS};
use super::BuildPrims;
use crate::accel::bvh::BvhOptions;
use crate::math::{Aabb, Vec3};
use rayon::prelude::*;

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

/// Scratch space of the SAH sweep: the bins of all three axes (axis-major), and the
/// right-to-left sweep's running areas and counts for one axis.
pub(super) struct Sweep {
    bins: Vec<Bin>,
    right_area: Vec<f32>,
    right_count: Vec<u32>,
}

#[derive(Clone, Copy)]
struct Bin {
    bounds: Aabb,
    centroids: Aabb,
    count: u32,
}

impl Bin {
    const EMPTY: Bin = Bin {
        bounds: Aabb::EMPTY,
        centroids: Aabb::EMPTY,
        count: 0,
    };

    fn merge(&self, other: &Bin) -> Bin {
        Bin {
            bounds: self.bounds.union(&other.bounds),
            centroids: self.centroids.union(&other.centroids),
            count: self.count + other.count,
        }
    }
}

/// How centroids map to bins on the three axes: the one rule both binning and
/// partitioning follow, so each side of a split is exactly the union of its bins.
#[derive(Clone, Copy)]
struct Binning {
    lo: Vec3,
    /// Bins per unit length; 0 on an axis whose centroids all coincide.
    scale: Vec3,
    bins: usize,
}

impl Binning {
    #[inline(always)]
    fn bin(&self, c: Vec3, axis: usize) -> usize {
        // `as` saturates (NaN to 0), and the clamp keeps the maximum in the last bin.
        (((c[axis] - self.lo[axis]) * self.scale[axis]) as usize).min(self.bins - 1)
    }

    /// Adds primitives `order` to `bins` (three axes' worth, axis-major), reading each
    /// primitive once.
    fn fill(&self, prims: &BuildPrims, order: &[u32], bins: &mut [Bin]) {
        let nb = self.bins;
        for &i in order {
            let (c, b) = (prims.centroids[i as usize], &prims.bounds[i as usize]);
            for axis in 0..3 {
                let bin = &mut bins[axis * nb + self.bin(c, axis)];
                bin.count += 1;
                bin.bounds = bin.bounds.union(b);
                bin.centroids = bin.centroids.union_point(c);
            }
        }
    }
}

impl SplitRule for BinnedSah {
    type Scratch = Sweep;

    fn scratch(&self) -> Sweep {
        Sweep {
            bins: vec![Bin::EMPTY; 3 * self.bins],
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
    ) -> Option<Split> {
        let n = order.len();
        // Small nodes take as many bins as primitives: more could not separate them better,
        // and clearing unused bins would cost more than binning.
        let nb = self.bins.min(n.max(4));
        let extent = centroid_bounds.max - centroid_bounds.min;
        let scale = Vec3::select(extent.cmpgt(Vec3::ZERO), nb as f32 / extent, Vec3::ZERO);
        let binning = Binning {
            lo: centroid_bounds.min,
            scale,
            bins: nb,
        };
        let bins = &mut sweep.bins[..3 * nb];
        self.fill_bins(prims, &binning, order, bins);
        match self.best_split(sweep, nb, bounds, scale, prims) {
            Some((axis, k, cost)) => {
                if n <= self.max_leaf_size && cost >= prims.leaf_cost(n) {
                    return None;
                }
                let mid = partition(order, |&i| {
                    binning.bin(prims.centroids[i as usize], axis) <= k
                });
                let bins = &sweep.bins[axis * nb..][..nb];
                let side = |bins: &[Bin]| {
                    let all = bins.iter().fold(Bin::EMPTY, |a, b| a.merge(b));
                    (all.bounds, all.centroids)
                };
                debug_assert!(mid > 0 && mid < n);
                Some(Split {
                    mid,
                    sides: Some([side(&bins[..=k]), side(&bins[k + 1..])]),
                })
            }
            // All centroids coincide: SAH cannot separate them, so split the list in half
            // (if it is too big for a leaf) to keep leaves bounded.
            None if n <= self.max_leaf_size => None,
            None => Some(Split::at(n / 2)),
        }
    }
}

impl BinnedSah {
    /// Bins `order` on all three axes, in parallel chunks for the nodes near the top.
    fn fill_bins(&self, prims: &BuildPrims, binning: &Binning, order: &[u32], bins: &mut [Bin]) {
        bins.fill(Bin::EMPTY);
        if order.len() < PARALLEL_PASS {
            binning.fill(prims, order, bins);
            return;
        }
        // Unions and counts are exact, so how rayon merges the chunks cannot change them.
        let merged = order
            .par_chunks(PARALLEL_PASS / 2)
            .map(|chunk| {
                let mut local = vec![Bin::EMPTY; bins.len()];
                binning.fill(prims, chunk, &mut local);
                local
            })
            .reduce(
                || vec![Bin::EMPTY; bins.len()],
                |a, b| a.iter().zip(&b).map(|(x, y)| x.merge(y)).collect(),
            );
        bins.copy_from_slice(&merged);
    }

    /// The cheapest binned split as (axis, last bin on the left, SAH cost in units of one
    /// primitive test), or `None` when all centroids coincide.
    fn best_split(
        &self,
        sweep: &mut Sweep,
        nb: usize,
        bounds: &Aabb,
        scale: Vec3,
        prims: &BuildPrims,
    ) -> Option<(usize, usize, f32)> {
        let mut best: Option<(usize, usize, f32)> = None;
        let parent_area = bounds.surface_area().max(f32::MIN_POSITIVE);
        let Sweep {
            bins,
            right_area,
            right_count,
        } = sweep;
        for axis in 0..3 {
            if scale[axis] <= 0.0 {
                continue;
            }
            let bins = &bins[axis * nb..][..nb];
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
                    + (acc.surface_area() * prims.leaf_cost(count as usize)
                        + right_area[k + 1] * prims.leaf_cost(right_count[k + 1] as usize))
                        / parent_area;
                if best.is_none_or(|(_, _, c)| cost < c) {
                    best = Some((axis, k, cost));
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
