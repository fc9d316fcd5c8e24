//! Node bounding volumes beyond the axis-aligned box: bounding spheres, OBBs, 14- and
//! 26-DOPs on the binned-SAH tree of `Bvh`, and convex hulls as per-object bounds, each
//! switchable (`NodeVolume`) so that tightness and test cost can be compared on one tree.
//!
//! Every volume is fitted conservatively from exact support functions in f64 (`support`),
//! stored rounded outward with relative padding, and tested with error bounds computed
//! from the ray and the volume (`slab`): a ray never misses a volume whose contents it
//! hits, at any scale.

mod aabb;
mod hierarchy;
pub mod hull;
pub mod kdop;
mod measure;
pub mod obb;
mod objects;
mod pca;
mod polytope;
mod slab;
pub mod sphere;
mod support;
mod traverse;
mod volume;

pub use hierarchy::VolumeBvh;
pub use kdop::{Dop, Dop14, Dop26};
pub use obb::Obb;
pub use objects::{ObjectHulls, HULL_MIN_PRIMITIVES};
pub use sphere::BoundingSphere;
pub use traverse::CULL_SLACK;
pub use volume::Volume;

use crate::accel::{Accel, AccelInfo, Bvh, BvhOptions, Hit, RayQuery};
use crate::geometry::Geometry;
use crate::math::{Aabb, TraceRay};
use crate::stats::Stats;

/// Which volume the nodes carry.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum NodeVolume {
    /// Axis-aligned boxes: the plain BVH.
    Aabb,
    /// Bounding spheres.
    Sphere,
    /// Oriented boxes, axes from the principal components of the node's points.
    Obb,
    /// 14-DOPs: seven slab directions.
    Dop14,
    /// 26-DOPs: thirteen slab directions.
    Dop26,
    /// Boxes, plus a convex hull around each object of many primitives.
    Hull,
}

named_kinds! {
    NodeVolume, "node volume" {
        Aabb => "aabb",
        Sphere => "sphere",
        Obb => "obb",
        Dop14 => "dop14",
        Dop26 => "dop26",
        Hull => "hull",
    }
}

/// An accelerator built with one node volume, which can also say how tight its volumes are.
pub trait VolumeAccel: Send + Sync {
    /// The accelerator itself.
    fn accel(&self) -> &dyn Accel;

    /// The mean chance that a random line meeting a node's box also meets its volume
    /// (the surface-area ratio, for convex volumes), over up to `nodes` nodes spread
    /// through the tree, `lines` lines each; NaN when there is nothing to measure.
    fn tightness(&self, geometry: &Geometry, nodes: usize, lines: u32) -> f64;
}

impl<V: Volume> VolumeAccel for VolumeBvh<V> {
    fn accel(&self) -> &dyn Accel {
        self
    }

    fn tightness(&self, geometry: &Geometry, nodes: usize, lines: u32) -> f64 {
        let n = self.nodes.len();
        let step = n.div_ceil(nodes.max(1)).max(1);
        let (mut hit_volume, mut hit_box) = (0u64, 0u64);
        for i in (0..n).step_by(step) {
            let bounds: Aabb = measure::prims_bounds(geometry, self.node_prims(i));
            let (v, b) = measure::crossings(&self.nodes[i].volume, &bounds, lines, i as u64);
            hit_volume += v;
            hit_box += b;
        }
        hit_volume as f64 / hit_box.max(1) as f64
    }
}

/// Builds the SAH tree over `prims` and fits volumes of kind `volume` to it.
pub fn build(
    geometry: &Geometry,
    prims: Vec<u32>,
    options: &BvhOptions,
    volume: NodeVolume,
) -> Box<dyn Accel> {
    Box::new(build_measurable(geometry, prims, options, volume))
}

/// `build`, keeping access to the tightness measurement.
pub fn build_measurable(
    geometry: &Geometry,
    prims: Vec<u32>,
    options: &BvhOptions,
    volume: NodeVolume,
) -> Box<dyn VolumeAccel> {
    fn fitted<V: Volume>(
        geometry: &Geometry,
        prims: Vec<u32>,
        options: &BvhOptions,
        volume: NodeVolume,
    ) -> Box<dyn VolumeAccel> {
        let bvh = Bvh::build(geometry, prims, options);
        Box::new(VolumeBvh::<V>::from_bvh(geometry, &bvh, volume.name()))
    }
    match volume {
        NodeVolume::Aabb => fitted::<Aabb>(geometry, prims, options, volume),
        NodeVolume::Sphere => fitted::<BoundingSphere>(geometry, prims, options, volume),
        NodeVolume::Obb => fitted::<Obb>(geometry, prims, options, volume),
        NodeVolume::Dop14 => fitted::<Dop14>(geometry, prims, options, volume),
        NodeVolume::Dop26 => fitted::<Dop26>(geometry, prims, options, volume),
        NodeVolume::Hull => Box::new(ObjectHulls::build(geometry, prims, options)),
    }
}

impl Accel for Box<dyn VolumeAccel> {
    fn query(&self, query: &RayQuery, stats: &mut Stats) -> Option<Hit> {
        self.accel().query(query, stats)
    }

    // The two modes forwarded as well, so they reach the walks specialised for them.
    fn intersect(
        &self,
        geometry: &Geometry,
        ray: &TraceRay,
        t_max: f32,
        stats: &mut Stats,
    ) -> Option<Hit> {
        self.accel().intersect(geometry, ray, t_max, stats)
    }

    fn occluded(&self, geometry: &Geometry, ray: &TraceRay, t_max: f32, stats: &mut Stats) -> bool {
        self.accel().occluded(geometry, ray, t_max, stats)
    }

    fn info(&self) -> AccelInfo {
        self.accel().info()
    }
}

/// The BVH's own description ("bvh (full-sweep SAH + reinsertion)") with the volume kind
/// added inside the brackets, so the builder and its options stay named.
fn with_volume(method: &str, volumes: &str) -> String {
    match method.strip_suffix(')') {
        Some(open) => format!("{open}, {volumes})"),
        None => format!("{method} ({volumes})"),
    }
}
