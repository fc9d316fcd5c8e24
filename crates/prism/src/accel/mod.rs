//! Acceleration structures. Every one answers the same two questions, nearest hit and any
//! hit, over the bounded primitives of a `Geometry`; the brute-force list is the oracle the
//! tests hold the others to.

mod brute;
pub mod bvh;
mod cells;
pub mod grid;
mod info;
pub mod kdtree;
mod mailbox;
pub mod octree;
mod params;
mod query;
mod spec;
mod stack;
pub mod volumes;

pub use crate::choices::{
    help_text, markdown, method_doc, parse_params, Accepts, Key, KeyDoc, Keyed, MethodDoc, Value,
};
pub use brute::{BruteForce, BruteForceOptions};
pub use bvh::{Avx512, Bvh, BvhBuilder, BvhOptions, NodeWidth, RayOrigins};
pub use grid::{Grid, GridOptions};
pub use info::AccelInfo;
pub use kdtree::{KdTree, KdTreeOptions};
pub use octree::{Octree, OctreeOptions};
pub use params::Method;
pub(crate) use query::HitSearch;
pub use query::{Hit, PacketQuery, QueryMode, RayQuery};
pub use spec::{AccelKind, AccelSpec};

use crate::geometry::Geometry;
use crate::math::{Ray, TraceRay};
use crate::stats::Stats;
use rayon::prelude::*;

/// An acceleration structure: answers ray queries over the bounded primitives it was
/// built on. A method implements `query` (and `info`); `intersect` and `occluded` are the
/// two modes of it that the renderer asks for. Implementations mark `query`
/// `#[inline(always)]` so each mode compiles to its own specialised walk.
pub trait Accel: Send + Sync {
    /// Hits with `0 < t < t_max`: the nearest (exact ties to the lower primitive id, see
    /// `HitSearch`) or, for `QueryMode::Any`, whichever is found first.
    fn query(&self, query: &RayQuery, stats: &mut Stats) -> Option<Hit>;

    /// What was built: node counts, depth, leaf sizes, SAH cost, memory.
    fn info(&self) -> AccelInfo;

    /// Answers a packet of rays (at most `PACKET_MAX`): `answers[i]` is exactly what
    /// `query` gives ray i. A method that can walk coherent rays together (the BVH) does
    /// so; the others answer one ray at a time.
    fn query_packet(&self, packet: &PacketQuery, answers: &mut [Option<Hit>], stats: &mut Stats) {
        let PacketQuery { geometry, mode, .. } = *packet;
        let bounds = packet.rays.iter().zip(packet.t_max);
        for ((ray, &t_max), answer) in bounds.zip(answers.iter_mut()) {
            let ray = &TraceRay::new(*ray);
            *answer = self.query(&RayQuery::new(geometry, ray, t_max, mode), stats);
        }
    }

    /// Nearest hit with `0 < t < t_max`. Its own entry point, so that a call through
    /// `dyn Accel` reaches a walk specialised for the mode.
    fn intersect(
        &self,
        geometry: &Geometry,
        ray: &TraceRay,
        t_max: f32,
        stats: &mut Stats,
    ) -> Option<Hit> {
        let mode = QueryMode::Nearest;
        self.query(&RayQuery::new(geometry, ray, t_max, mode), stats)
    }

    /// Whether anything is hit with `0 < t < t_max`; may stop at the first hit found.
    fn occluded(&self, geometry: &Geometry, ray: &TraceRay, t_max: f32, stats: &mut Stats) -> bool {
        let mode = QueryMode::Any;
        self.query(&RayQuery::new(geometry, ray, t_max, mode), stats)
            .is_some()
    }

    /// A one-line description for `--stats` and `prism info`.
    fn describe(&self) -> String {
        self.info().to_string()
    }

    /// The method as a BVH of boxes, for structures that start its walk below the root
    /// (the light buffer's cells); None for every other method.
    fn as_bvh(&self) -> Option<&Bvh> {
        None
    }
}

/// Most rays in one packet (`Accel::query_packet`): an 8 × 8 block of camera rays.
pub const PACKET_MAX: usize = 64;

/// How much farther than the best hit so far a hierarchy still looks (a factor on t).
/// A primitive's reported distance can be off from its exact intersection by far more than
/// a box test rounds: a thin triangle's barycentrics are ill-conditioned, and a sphere's or
/// cylinder's quadratic loses digits near its silhouette. So the point at a reported
/// distance can lie just outside a box or volume that holds the primitive, and a node
/// culled at exactly that distance can hold a hit nearer than the one that culled it (the
/// SPD rings, where cylinders meet spheres, showed it). 2⁻¹³ covers the 10⁻⁴-relative
/// errors the tests provoke; 2⁻¹⁰ cost ~15 % more primitive tests on closed meshes.
pub const CULL_SLACK: f32 = 1.0 + 1.0 / 8192.0;

/// The whole scene's ray queries: an accelerator over bounded primitives plus a plain list
/// of unbounded ones (planes), which no bounding structure can hold.
pub struct SceneIntersector {
    /// The accelerator over the bounded primitives.
    pub accel: Box<dyn Accel>,
    unbounded: Vec<u32>,
}

impl SceneIntersector {
    /// Builds the method `spec` names over the bounded primitives of `geometry` and keeps
    /// the unbounded ones (planes) aside.
    pub fn build(geometry: &Geometry, spec: &AccelSpec) -> Self {
        // The whole build is one job on rayon's pool: its parallel steps then start from a
        // worker, not from a caller outside the pool that sleeps until each step is done
        // and is woken for the next (a wake-up each way per step, on a small mesh).
        rayon::scope(|_| {
            // In parallel and without computing boxes: on the 100k-triangle blob the serial
            // pass that asked each primitive for its box took a millisecond, while every
            // other step of the build uses both cores.
            let n = geometry.primitives.len() as u32;
            let is_bounded = |i: u32| geometry.primitives[i as usize].shape.is_bounded();
            // Most scenes have no plane: then every id is bounded, and a parallel range
            // writes them without the partition's pieces gathered and joined.
            let (bounded, unbounded): (Vec<u32>, Vec<u32>) =
                if (0..n).into_par_iter().all(is_bounded) {
                    ((0..n).into_par_iter().collect(), Vec::new())
                } else {
                    (0..n).into_par_iter().partition(|&i| is_bounded(i))
                };
            SceneIntersector {
                accel: spec.build(geometry, bounded),
                unbounded,
            }
        })
    }

    /// The unbounded primitives (planes), which every query tests beside the accelerator.
    pub(crate) fn unbounded(&self) -> &[u32] {
        &self.unbounded
    }

    /// The nearest hit along `ray` with `0 < t < t_max`, planes included (see
    /// `HitSearch::test_unbounded` for how a plane ties with an object).
    pub fn intersect(
        &self,
        geometry: &Geometry,
        ray: &Ray,
        t_max: f32,
        stats: &mut Stats,
    ) -> Option<Hit> {
        let tr = TraceRay::new(*ray);
        let found = self.accel.intersect(geometry, &tr, t_max, stats);
        self.nearest_with_planes(geometry, &tr, t_max, found, stats)
    }

    /// `found`, the nearest hit the accelerator (or a part of it) found before `t_max`,
    /// against the planes: a plane's hit where it is strictly nearer.
    #[inline(always)]
    pub(crate) fn nearest_with_planes(
        &self,
        geometry: &Geometry,
        tr: &TraceRay,
        t_max: f32,
        found: Option<Hit>,
        stats: &mut Stats,
    ) -> Option<Hit> {
        // No plane: the accelerator's hit stands as found (the search below would keep it).
        if self.unbounded.is_empty() {
            return found;
        }
        let mut search = HitSearch::new(t_max, QueryMode::Nearest);
        if let Some(hit) = found {
            search.offer(hit);
        }
        for &prim in &self.unbounded {
            search.test_unbounded(geometry, tr, prim, stats);
        }
        search.best()
    }

    /// The first plane, in order, that blocks `tr` before `t_max`: any-hit queries test the
    /// planes before the accelerator (a few tests that may spare the walk).
    #[inline(always)]
    pub(crate) fn plane_blocker(
        &self,
        geometry: &Geometry,
        tr: &TraceRay,
        t_max: f32,
        stats: &mut Stats,
    ) -> Option<Hit> {
        let mut planes = HitSearch::new(t_max, QueryMode::Any);
        for &prim in &self.unbounded {
            if planes.test_unbounded(geometry, tr, prim, stats) {
                return planes.best();
            }
        }
        None
    }

    /// The nearest hits of a packet of rays (at most `PACKET_MAX`), each with
    /// `0 < t < t_max`: `answers[i]` is exactly `intersect(rays[i])`, but coherent rays
    /// walk the accelerator together (`Accel::query_packet`).
    pub fn intersect_packet(
        &self,
        geometry: &Geometry,
        rays: &[Ray],
        t_max: f32,
        answers: &mut [Option<Hit>],
        stats: &mut Stats,
    ) {
        let bounds = [t_max; PACKET_MAX];
        let t_max = &bounds[..rays.len()];
        let packet = PacketQuery::new(geometry, rays, t_max, QueryMode::Nearest);
        self.query_packet(&packet, answers, stats);
    }

    /// The answers of a packet query (at most `PACKET_MAX` rays), planes included: answer
    /// i is exactly the single-ray query's, `intersect(rays[i], t_max[i])` for the nearest
    /// hit, `any_hit(rays[i], t_max[i])` for any hit (a plane's hit where a plane blocks,
    /// as it is tested first), but coherent rays walk the accelerator together
    /// (`Accel::query_packet`).
    pub fn query_packet(
        &self,
        packet: &PacketQuery,
        answers: &mut [Option<Hit>],
        stats: &mut Stats,
    ) {
        let answers = &mut answers[..packet.rays.len()];
        self.accel.query_packet(packet, answers, stats);
        self.add_planes(packet, answers, stats);
    }

    /// The planes added to `answers`, a packet query's answers from the accelerator (or a
    /// part of it): a nearer plane's hit for the nearest hit, a blocking plane's for any
    /// hit, as the single-ray queries offer them.
    pub(crate) fn add_planes(
        &self,
        packet: &PacketQuery,
        answers: &mut [Option<Hit>],
        stats: &mut Stats,
    ) {
        // The accelerator's answers are final unless a plane may come nearer or block.
        if self.unbounded.is_empty() {
            return;
        }
        let geometry = packet.geometry;
        for ((ray, answer), &t_max) in packet.rays.iter().zip(answers).zip(packet.t_max) {
            let tr = TraceRay::new(*ray);
            match packet.mode {
                QueryMode::Nearest => {
                    *answer = self.nearest_with_planes(geometry, &tr, t_max, *answer, stats);
                }
                QueryMode::Any => {
                    if let Some(plane) = self.plane_blocker(geometry, &tr, t_max, stats) {
                        *answer = Some(plane);
                    }
                }
            }
        }
    }

    /// The first blocker an any-hit query finds, planes first (a few tests that may spare
    /// the walk); the shadow cache remembers it.
    pub fn any_hit(
        &self,
        geometry: &Geometry,
        ray: &Ray,
        t_max: f32,
        stats: &mut Stats,
    ) -> Option<Hit> {
        let ray = &TraceRay::new(*ray);
        self.plane_blocker(geometry, ray, t_max, stats).or_else(|| {
            let mode = QueryMode::Any;
            self.accel
                .query(&RayQuery::new(geometry, ray, t_max, mode), stats)
        })
    }

    /// For a packet of rays (at most `PACKET_MAX`), whether anything, planes included, is
    /// hit along ray i with `0 < t < t_max[i]`: `blocked[i]` is exactly `occluded(rays[i])`,
    /// but coherent rays walk the accelerator together (`Accel::query_packet`).
    pub fn occluded_packet(
        &self,
        geometry: &Geometry,
        rays: &[Ray],
        t_max: &[f32],
        blocked: &mut [bool],
        stats: &mut Stats,
    ) {
        let n = rays.len();
        let mut answers = [None; PACKET_MAX];
        let mode = QueryMode::Any;
        let packet = PacketQuery::new(geometry, rays, &t_max[..n], mode);
        self.accel.query_packet(&packet, &mut answers[..n], stats);
        for (i, ray) in rays.iter().enumerate() {
            blocked[i] = answers[i].is_some()
                || (!self.unbounded.is_empty()
                    && (self.plane_blocker(geometry, &TraceRay::new(*ray), t_max[i], stats))
                        .is_some());
        }
    }

    /// Whether anything, planes included, is hit along `ray` with `0 < t < t_max`.
    pub fn occluded(&self, geometry: &Geometry, ray: &Ray, t_max: f32, stats: &mut Stats) -> bool {
        self.any_hit(geometry, ray, t_max, stats).is_some()
    }
}
