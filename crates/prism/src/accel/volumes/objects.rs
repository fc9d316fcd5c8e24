//! Convex hulls as per-object bounds. Primitives are grouped into objects (the triangles of
//! one mesh are one object; every other primitive is its own); an object with many
//! primitives gets its own SAH sub-tree and a convex hull a ray must hit before the
//! sub-tree is entered. A top-level SAH tree over boxes holds the objects and the loose
//! primitives.
//!
//! The hull is tested once per object per ray; it pays when many rays pass near a complex
//! object's box without touching the object (concave or slanted shapes), and costs a
//! Cyrus–Beck clip against all its faces when they do.

use super::hierarchy::VolumeBvh;
use super::hull::convex_hull;
use super::kdop::DIRECTIONS;
use super::measure;
use super::polytope::{hit_polytope, store_planes, Plane};
use super::volume::magnitude;
use super::VolumeAccel;
use crate::accel::{Accel, AccelInfo, Bvh, BvhOptions, Hit, RayQuery};
use crate::geometry::{Geometry, Shape};
use crate::math::Aabb;
use crate::stats::Stats;
use glam::DVec3;
use std::collections::HashMap;

/// Objects with at least this many primitives get a hull and a sub-tree.
pub const HULL_MIN_PRIMITIVES: usize = 64;

/// Items of the top-level tree with this bit set are objects, the rest primitives.
const OBJECT_BIT: u32 = 1 << 31;

struct Object {
    tree: VolumeBvh<Aabb>,
    /// The hull's planes: `planes[range]`.
    planes: std::ops::Range<usize>,
    bounds: Aabb,
}

/// Boxes everywhere, plus a convex hull around each object of many primitives, which a
/// ray must hit before that object's own sub-tree is entered.
pub struct ObjectHulls {
    top: VolumeBvh<Aabb>,
    objects: Vec<Object>,
    planes: Vec<Plane>,
    primitives: usize,
}

impl ObjectHulls {
    /// Groups `prims` by object (mesh), builds hulls and sub-trees for the big ones and a
    /// top-level tree over them and the rest.
    pub fn build(geometry: &Geometry, prims: Vec<u32>, options: &BvhOptions) -> Self {
        let primitives = prims.len();
        let mut by_mesh: HashMap<u32, Vec<u32>> = HashMap::new();
        let mut loose = Vec::new();
        for p in prims {
            match geometry.primitives[p as usize].shape {
                Shape::Triangle { mesh, .. } => by_mesh.entry(mesh).or_default().push(p),
                _ => loose.push(p),
            }
        }
        let mut meshes: Vec<(u32, Vec<u32>)> = by_mesh.into_iter().collect();
        meshes.sort_by_key(|m| m.0);
        let (mut objects, mut planes) = (Vec::new(), Vec::new());
        for (_, tris) in meshes {
            if tris.len() < HULL_MIN_PRIMITIVES {
                loose.extend(tris);
                continue;
            }
            let bounds = measure::prims_bounds(geometry, &tris);
            let hull = object_planes(geometry, &tris, &bounds);
            let first = planes.len();
            planes.extend(hull);
            let bvh = Bvh::build(geometry, tris, options);
            objects.push(Object {
                tree: VolumeBvh::from_bvh(geometry, &bvh, "aabb"),
                planes: first..planes.len(),
                bounds,
            });
        }
        // Top level: loose primitives by id, objects by OBJECT_BIT | index. Box volumes
        // are fitted from the items' boxes alone, so the item ids never reach `fit`.
        let mut items: Vec<u32> = loose.clone();
        let mut boxes: Vec<Aabb> = loose
            .iter()
            .map(|&p| {
                geometry
                    .bounds(p)
                    .expect("accelerated primitives are bounded")
            })
            .collect();
        for (i, o) in objects.iter().enumerate() {
            items.push(OBJECT_BIT | i as u32);
            boxes.push(o.bounds);
        }
        let top_bvh = Bvh::build_over_bounds(items, boxes, options);
        ObjectHulls {
            top: VolumeBvh::from_bvh(geometry, &top_bvh, "aabb"),
            objects,
            planes,
            primitives,
        }
    }

    /// Bytes of the top tree, the hull planes and the objects' sub-trees.
    pub fn memory_bytes(&self) -> usize {
        self.top.memory_bytes()
            + self.planes.len() * std::mem::size_of::<Plane>()
            + self
                .objects
                .iter()
                .map(|o| o.tree.memory_bytes() + std::mem::size_of::<Object>())
                .sum::<usize>()
    }

    /// Number of objects with a hull, and their total face count.
    pub fn hull_stats(&self) -> (usize, usize) {
        (self.objects.len(), self.planes.len())
    }
}

/// The hull planes of one object's triangles; the 26-DOP's planes when the vertices span
/// no volume (a flat or degenerate mesh), which bound it just as conservatively.
fn object_planes(geometry: &Geometry, tris: &[u32], bounds: &Aabb) -> Vec<Plane> {
    let mut points: Vec<DVec3> = Vec::with_capacity(tris.len() * 3);
    for &t in tris {
        if let Shape::Triangle { mesh, index } = geometry.primitives[t as usize].shape {
            points.extend(
                geometry.meshes[mesh as usize]
                    .vertices(index)
                    .map(|v| v.as_dvec3()),
            );
        }
    }
    points.sort_by(|a, b| {
        a.x.total_cmp(&b.x)
            .then(a.y.total_cmp(&b.y))
            .then(a.z.total_cmp(&b.z))
    });
    points.dedup();
    let faces = match convex_hull(&points) {
        Some(h) => h.faces(&points),
        None => DIRECTIONS
            .iter()
            .flat_map(|n| [n.as_dvec3().normalize(), -n.as_dvec3().normalize()])
            .map(|normal| super::hull::HalfSpace {
                normal,
                offset: 0.0,
            })
            .collect(),
    };
    // A triangle's support is its vertices', so the deduplicated points give the same
    // maximum as the triangles, a third of the work without the per-triangle lookups.
    let support_all = |n: DVec3| points.iter().map(|p| p.dot(n)).fold(f64::MIN, f64::max);
    store_planes(&faces, support_all, magnitude(bounds))
}

impl Accel for ObjectHulls {
    #[inline(always)]
    fn query(&self, query: &RayQuery, stats: &mut Stats) -> Option<Hit> {
        let ray = query.ray;
        self.top.walk(
            ray,
            query.t_max,
            query.mode,
            stats,
            |item, search, stats| {
                if item & OBJECT_BIT == 0 {
                    return search.test(query.geometry, ray, item, stats);
                }
                let object = &self.objects[(item & !OBJECT_BIT) as usize];
                stats.node_visits += 1;
                let planes = &self.planes[object.planes.clone()];
                let limit = search.nested_limit();
                if hit_polytope(planes, ray, limit * super::CULL_SLACK).is_none() {
                    return false;
                }
                let inner = RayQuery::new(query.geometry, ray, limit, query.mode);
                match object.tree.query(&inner, stats) {
                    Some(hit) => search.offer(hit),
                    None => false,
                }
            },
        )
    }

    fn info(&self) -> AccelInfo {
        self.info()
    }
}

impl ObjectHulls {
    /// The top-level tree's figures with the objects' sub-trees added in.
    fn info(&self) -> AccelInfo {
        let mut info = self.top.info();
        let top_depth = info.depth;
        let (hulls, faces) = self.hull_stats();
        info.method = super::with_volume(
            &info.method,
            &format!(
                "hull volumes: {hulls} objects of ≥ {HULL_MIN_PRIMITIVES} primitives, \
                 {faces} faces"
            ),
        );
        info.primitives = self.primitives;
        for o in &self.objects {
            let sub = o.tree.info();
            info.nodes += sub.nodes;
            info.leaves += sub.leaves;
            info.max_leaf_size = info.max_leaf_size.max(sub.max_leaf_size);
            // A sub-tree hangs below a top-level leaf.
            info.depth = info.depth.max(top_depth + sub.depth);
        }
        info.sah_cost = None;
        info.memory_bytes = self.memory_bytes();
        info
    }
}

impl VolumeAccel for ObjectHulls {
    fn accel(&self) -> &dyn Accel {
        self
    }

    /// Hulls against their objects' boxes (the per-node boxes below are plain boxes).
    fn tightness(&self, _geometry: &Geometry, nodes: usize, lines: u32) -> f64 {
        let (mut on_hull, mut on_box) = (0u64, 0u64);
        for (i, o) in self.objects.iter().take(nodes.max(1)).enumerate() {
            let planes = &self.planes[o.planes.clone()];
            let (h, b) = measure::crossings_with(
                |ray| hit_polytope(planes, ray, f32::INFINITY).is_some(),
                &o.bounds,
                lines,
                i as u64,
            );
            on_hull += h;
            on_box += b;
        }
        // NaN when no object is big enough for a hull: there is nothing to measure.
        on_hull as f64 / on_box as f64
    }
}
