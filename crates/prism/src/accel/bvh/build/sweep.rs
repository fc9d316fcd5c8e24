//! Full-sweep SAH splits (as in pbrt and Wald's survey): on each axis the primitives are
//! sorted by centroid and every split between neighbours is costed exactly, with the
//! right-hand boxes accumulated in one backward pass. O(n log n) per node. A leaf costs a
//! step per test block (`BuildPrims::leaf_cost`), as in the binned builder, so that the
//! exact sweep and the binned one weigh the same triangle packs.

use super::prim_ref::PrimRef;
use super::topdown::{Split, SplitRule};
use super::BuildPrims;
use crate::math::Aabb;
use rayon::slice::ParallelSliceMut;

pub(super) struct FullSweepSah {
    pub max_leaf_size: usize,
    pub traversal_cost: f32,
    /// Nodes bigger than this sort on all threads (the order does not depend on it).
    pub parallel_threshold: usize,
}

/// Per-thread buffers: the candidate order on the axis being swept, the best so far, and
/// the area of everything right of each split.
#[derive(Default)]
pub(super) struct Buffers {
    sorted: Vec<(f32, u32)>,
    best: Vec<(f32, u32)>,
    right_area: Vec<f32>,
}

impl SplitRule for FullSweepSah {
    type Scratch = Buffers;

    fn scratch(&self) -> Buffers {
        Buffers::default()
    }

    fn split(
        &self,
        prims: &BuildPrims,
        buffers: &mut Buffers,
        order: &mut [PrimRef],
        bounds: &Aabb,
        centroid_bounds: &Aabb,
    ) -> Option<Split> {
        let n = order.len();
        let parent_area = bounds.surface_area().max(f32::MIN_POSITIVE);
        // (split index, cost); the order sorted on the winning axis stays in `best`.
        let mut best: Option<(usize, f32)> = None;
        for axis in 0..3 {
            let extent = centroid_bounds.max[axis] - centroid_bounds.min[axis];
            if extent.is_nan() || extent <= 0.0 {
                continue;
            }
            let sorted = &mut buffers.sorted;
            sorted.clear();
            sorted.extend(order.iter().map(|r| (r.centroid()[axis], r.index())));
            // Keys are unique (ties broken by position), so any sort gives the same order.
            let by_key = |a: &(f32, u32), b: &(f32, u32)| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1));
            if n > self.parallel_threshold {
                sorted.par_sort_unstable_by(by_key);
            } else {
                sorted.sort_unstable_by(by_key);
            }
            let right_area = &mut buffers.right_area;
            right_area.resize(n, 0.0);
            let mut acc = Aabb::EMPTY;
            for k in (1..n).rev() {
                acc = acc.union(&prims.bounds[sorted[k].1 as usize]);
                right_area[k] = acc.surface_area();
            }
            let mut acc = Aabb::EMPTY;
            let mut improved = false;
            for k in 1..n {
                acc = acc.union(&prims.bounds[sorted[k - 1].1 as usize]);
                let cost = self.traversal_cost
                    + (acc.surface_area() * prims.leaf_cost(k)
                        + right_area[k] * prims.leaf_cost(n - k))
                        / parent_area;
                if best.is_none_or(|(_, c)| cost < c) {
                    best = Some((k, cost));
                    improved = true;
                }
            }
            if improved {
                std::mem::swap(&mut buffers.sorted, &mut buffers.best);
            }
        }
        match best {
            Some((k, cost)) => {
                if n <= self.max_leaf_size && cost >= prims.leaf_cost(n) {
                    return None;
                }
                for (slot, &(_, i)) in order.iter_mut().zip(&buffers.best) {
                    *slot = PrimRef::new(i, &prims.bounds[i as usize]);
                }
                Some(Split::at(k))
            }
            // All centroids coincide: halve the list if it is too big for a leaf.
            None if n <= self.max_leaf_size => None,
            None => Some(Split::at(n / 2)),
        }
    }
}
