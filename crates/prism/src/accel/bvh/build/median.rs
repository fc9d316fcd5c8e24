//! Object median splits: halve the primitives by centroid along the longest axis of their
//! centroid bounds. Cheap and balanced, but blind to surface area.

use super::prim_ref::PrimRef;
use super::topdown::{Split, SplitRule};
use super::BuildPrims;
use crate::math::Aabb;

pub(super) struct ObjectMedian {
    pub max_leaf_size: usize,
}

impl SplitRule for ObjectMedian {
    type Scratch = ();

    fn scratch(&self) {}

    fn split(
        &self,
        _: &BuildPrims,
        _: &mut (),
        order: &mut [PrimRef],
        _bounds: &Aabb,
        centroid_bounds: &Aabb,
    ) -> Option<Split> {
        if order.len() <= self.max_leaf_size {
            return None;
        }
        let axis = centroid_bounds.longest_axis();
        let mid = order.len() / 2;
        // Ties broken by position, so equal centroids still split deterministically.
        order.select_nth_unstable_by(mid, |a, b| {
            let (ca, cb) = (a.centroid()[axis], b.centroid()[axis]);
            ca.total_cmp(&cb).then(a.index().cmp(&b.index()))
        });
        Some(Split::at(mid))
    }
}
