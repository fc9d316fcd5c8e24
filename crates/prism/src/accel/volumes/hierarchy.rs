//! A BVH whose nodes carry volumes of one kind: the topology is the binned-SAH tree of
//! `Bvh`, so every kind is compared on the same tree and only the volumes differ. Each
//! node's volume is fitted to the primitives below it (in parallel), or merged from its
//! children's where that is exact.

use super::volume::Volume;
use crate::accel::{AccelInfo, Bvh};
use crate::geometry::Geometry;
use crate::math::Aabb;
use rayon::prelude::*;

/// Interior nodes have `count == 0` and children at `first`, `first + 1`; leaves hold
/// `prims[first .. first + count]`, as in `Bvh`.
#[derive(Clone, Copy, Debug)]
pub(super) struct VolumeNode<V> {
    pub volume: V,
    pub first: u32,
    pub count: u32,
}

impl<V> VolumeNode<V> {
    #[inline(always)]
    pub(super) fn is_leaf(&self) -> bool {
        self.count > 0
    }
}

/// The binned-SAH tree of `Bvh` with a volume of kind `V` at every node.
pub struct VolumeBvh<V: Volume> {
    pub(super) nodes: Vec<VolumeNode<V>>,
    pub(super) prims: Vec<u32>,
    /// Each node's range in `prims`, for tests and tightness figures (traversal does not
    /// read it, so `memory_bytes` leaves it out).
    pub(super) ranges: Vec<(u32, u32)>,
    info: AccelInfo,
}

impl<V: Volume> VolumeBvh<V> {
    /// Fits volumes of kind `V` to the nodes of `bvh`; `name` names the kind in `info()`.
    pub fn from_bvh(geometry: &Geometry, bvh: &Bvh, name: &str) -> Self {
        let topology: Vec<(u32, u32, Aabb)> = bvh.topology().collect();
        let prims = bvh.leaf_order().to_vec();
        let n = topology.len();
        // Children come after their parent, so a reverse sweep sees them first.
        let mut ranges = vec![(0u32, 0u32); n];
        for i in (0..n).rev() {
            let (first, count, _) = topology[i];
            ranges[i] = if count > 0 {
                (first, first + count)
            } else {
                (ranges[first as usize].0, ranges[first as usize + 1].1)
            };
        }
        let fitted: Vec<Option<V>> = (0..n)
            .into_par_iter()
            .map(|i| {
                let (_, count, bounds) = topology[i];
                (count > 0 || !V::MERGES).then(|| {
                    let (a, b) = ranges[i];
                    V::fit(geometry, &prims[a as usize..b as usize], &bounds)
                })
            })
            .collect();
        let mut volumes: Vec<Option<V>> = fitted;
        for i in (0..n).rev() {
            if volumes[i].is_none() {
                let c = topology[i].0 as usize;
                let (a, b) = (volumes[c].expect("child"), volumes[c + 1].expect("child"));
                volumes[i] = Some(V::merge(&a, &b));
            }
        }
        let nodes: Vec<VolumeNode<V>> = topology
            .iter()
            .zip(volumes)
            .map(|(&(first, count, _), v)| VolumeNode {
                volume: v.expect("every node is fitted"),
                first,
                count,
            })
            .collect();
        let mut info = bvh.info();
        info.method = super::with_volume(&info.method, &format!("{name} volumes"));
        let mut this = VolumeBvh {
            nodes,
            prims,
            ranges,
            info,
        };
        this.info.memory_bytes = this.memory_bytes();
        this
    }

    /// Nodes and leaf order; the ranges kept for measurement are not counted.
    pub fn memory_bytes(&self) -> usize {
        self.nodes.len() * std::mem::size_of::<VolumeNode<V>>() + self.prims.len() * 4
    }

    /// The tree's figures, named with its volume kind.
    pub fn info(&self) -> AccelInfo {
        self.info.clone()
    }

    /// The volume of every node, in node order (for tests of containment and tightness).
    pub fn volumes(&self) -> impl Iterator<Item = &V> + '_ {
        self.nodes.iter().map(|n| &n.volume)
    }

    /// The primitives below node `i`.
    pub fn node_prims(&self, i: usize) -> &[u32] {
        let (a, b) = self.ranges[i];
        &self.prims[a as usize..b as usize]
    }
}
