//! The path tracer as a wavefront (Laine, Karras & Aila 2013, "Megakernels considered
//! harmful"; pbrt-v4's wavefront integrator; Mitsuba 3's vectorised variants): a queue of
//! thousands of paths per thread, each bounce a sequence of stages over the whole queue
//! rather than one path carried through all of its bounces.
//!
//! A round of the queue: refill it with new camera samples (so that it stays full while
//! paths die), find every path's next hit, let each arrive (emission, the BSDF), draw the
//! light samples, answer all their shadow rays, let each leave (unblocked light, the BSDF's
//! direction, Russian roulette), then retire the ended paths and close the gaps, keeping
//! the living in order. The ray queries of a stage go to the accelerator in runs of
//! `PACKET_MAX` in queue order: new camera rays arrive together, so they walk as packets.
//!
//! Each path goes through exactly the operations `PathTracer::trace_camera_ray` performs,
//! in the same order, with its own random numbers: every sample's value is the one-path
//! tracer's bit for bit, whatever the queue's size, and the image with it.

use super::diffuse_lanes::DiffuseBlock;
use super::path::{LightQuery, Path, Vertex};
use super::stage_clock::StageClock;
use super::{CameraBatch, CameraPacket, CameraTracer, PathTracer};
use crate::accel::{Hit, PACKET_MAX};
use crate::math::hash::Stream;
use crate::math::{Color, Ray};
use crate::options::RenderOptions;
use crate::scene::PreparedScene;
use crate::shading::BsdfSample;
use crate::stats::Stats;
use arrayvec::ArrayVec;
use std::ops::Range;

/// The stages' places in `StageTimes::NAMES`.
const CAMERA: usize = 0;
const TRACE: usize = 1;
const SHADE: usize = 2;
const SHADOW: usize = 3;
const LEAVE: usize = 4;

/// Paths in flight per thread. A path's state with its vertex is about 200 bytes, so the
/// queue and its stages' arrays stay within a core's L2 cache; fewer paths leave the
/// camera rays' packets and the stages' loops short.
pub(super) const WAVEFRONT_PATHS: usize = 1024;

/// The path tracer advancing a queue of paths a bounce at a time.
pub struct WavefrontPathTracer<'a> {
    paths: PathTracer<'a>,
    capacity: usize,
}

/// A path in the queue: its state, its random numbers, the sample it answers, the depth
/// its ray is at and the rays it has cast after its camera ray.
struct Lane {
    path: Path,
    stream: Stream,
    sample: usize,
    depth: u32,
    rays: u32,
}

/// The per-stage arrays of a round, kept between rounds so that a render allocates them
/// once per batch.
#[derive(Default)]
struct Stages {
    hits: Vec<Option<Hit>>,
    vertices: Vec<Option<Vertex>>,
    lights: Vec<LightQuery>,
    spans: Vec<Range<usize>>,
    /// A stage's queries that go as packets, in the order they go (`index` of each).
    order: Vec<u64>,
    /// Each path's BSDF sample in the leave stage.
    samples: Vec<Option<BsdfSample>>,
    /// The leave stage's diffuse bounces waiting for their lanes.
    diffuse: Box<DiffuseBlock>,
}

impl<'a> WavefrontPathTracer<'a> {
    /// The wavefront path tracer for `scene` with the depth and strategy of `options`.
    pub fn new(scene: &'a PreparedScene<'a>, options: &RenderOptions) -> Self {
        Self::with_capacity(scene, options, WAVEFRONT_PATHS)
    }

    /// The same with `capacity` paths in flight (at least one): a test's handle on the
    /// queue's size, which changes nothing in the image.
    pub fn with_capacity(
        scene: &'a PreparedScene<'a>,
        options: &RenderOptions,
        capacity: usize,
    ) -> Self {
        WavefrontPathTracer {
            paths: PathTracer::new(scene, options),
            capacity: capacity.max(1),
        }
    }

    /// Every path's next hit. The camera rays (depth 1: the places refilled this round)
    /// go to the accelerator in runs of `PACKET_MAX` in queue order as packets, so that
    /// neighbouring pixels' rays walk the tree together; the bounce rays one by one in
    /// queue order (`coherent`). A ray's hit does not depend on the order of the queries,
    /// so nothing is sorted: a sort by depth took 4 % of a `cornell-light` render's
    /// instructions, a counting sort still 2 % of its time.
    fn find_hits(&self, queue: &[Lane], stages: &mut Stages, stats: &mut Stats) {
        let s = self.paths.scene;
        let geometry = &s.scene.geometry;
        let Stages { hits, order, .. } = stages;
        hits.clear();
        order.clear();
        for (i, lane) in queue.iter().enumerate() {
            if coherent(lane.depth) {
                hits.push(None);
                order.push(i as u64);
            } else {
                let ray = &lane.path.ray;
                hits.push(s.intersector.intersect(geometry, ray, f32::INFINITY, stats));
            }
        }
        stats.primary_rays += queue.iter().filter(|l| l.depth == 1).count() as u64;
        for run in order.chunks(PACKET_MAX) {
            let rays: ArrayVec<Ray, PACKET_MAX> =
                run.iter().map(|&k| queue[index(k)].path.ray).collect();
            let mut found = [None; PACKET_MAX];
            let found = &mut found[..run.len()];
            s.intersector
                .intersect_packet(geometry, &rays, f32::INFINITY, found, stats);
            for (&k, &h) in run.iter().zip(found.iter()) {
                hits[index(k)] = h;
            }
        }
    }

    /// Every path arrives at its hit, and the paths that go on draw their light samples.
    fn arrive(&self, queue: &mut [Lane], stages: &mut Stages, stats: &mut Stats) {
        let Stages {
            hits,
            vertices,
            lights,
            spans,
            ..
        } = stages;
        vertices.clear();
        lights.clear();
        spans.clear();
        for (lane, &hit) in queue.iter_mut().zip(hits.iter()) {
            let vertex = self.paths.arrive(&mut lane.path, hit, lane.depth, stats);
            let first = lights.len();
            if let Some(v) = &vertex {
                self.paths
                    .light_queries(v, lane.depth, &lane.stream, lights);
                lane.rays += (lights.len() - first) as u32;
            }
            spans.push(first..lights.len());
            vertices.push(vertex);
        }
    }

    /// Whether each light sample's shadow ray is blocked. The shadow rays of the first
    /// hits (`coherent`) go by their place among their vertex's samples (which light),
    /// in queue order within a place, in runs of `PACKET_MAX` as packets: neighbouring
    /// first hits' rays to one light walk the tree together. The deeper vertices' go one
    /// by one in queue order.
    fn answer_shadow_rays(&self, queue: &[Lane], stages: &mut Stages, stats: &mut Stats) {
        let s = self.paths.scene;
        let geometry = &s.scene.geometry;
        let Stages {
            lights,
            spans,
            order,
            ..
        } = stages;
        order.clear();
        let mut places = 0;
        for (lane, span) in queue.iter().zip(spans.iter()) {
            if coherent(lane.depth) {
                places = places.max(span.len());
                order.extend(
                    span.clone()
                        .zip(0u64..)
                        .map(|(k, place)| place << 32 | k as u64),
                );
            } else {
                for q in &mut lights[span.clone()] {
                    let ray = Ray::new(q.origin, q.dir);
                    q.blocked = stats.shadow_query(1, |stats| {
                        s.intersector.occluded(geometry, &ray, q.t_max, stats)
                    });
                }
            }
        }
        if places > 1 {
            // By place, in queue order within one (the entries are distinct).
            order.sort_unstable();
        }
        let runs = order
            .chunk_by(|a, b| a >> 32 == b >> 32)
            .flat_map(|run| run.chunks(PACKET_MAX));
        for run in runs {
            let c = run.len();
            let rays: ArrayVec<Ray, PACKET_MAX> = run
                .iter()
                .map(|&k| {
                    let q = &lights[index(k)];
                    Ray::new(q.origin, q.dir)
                })
                .collect();
            let t_max: ArrayVec<f32, PACKET_MAX> =
                run.iter().map(|&k| lights[index(k)].t_max).collect();
            let mut blocked = [false; PACKET_MAX];
            stats.shadow_query(c as u64, |stats| {
                s.intersector
                    .occluded_packet(geometry, &rays, &t_max, &mut blocked[..c], stats)
            });
            for (&k, &b) in run.iter().zip(&blocked[..c]) {
                lights[index(k)].blocked = b;
            }
        }
    }

    /// Every path leaves its vertex or ends; the ended ones hand their radiance to `done`
    /// and the living close ranks in queue order. The light samples' light is added and
    /// the BSDFs sampled first, the diffuse bounces in lanes (`diffuse_lanes.rs`), then
    /// every path scatters or ends.
    fn leave(
        &self,
        queue: &mut Vec<Lane>,
        stages: &mut Stages,
        done: &mut dyn FnMut(usize, Color, u32),
        stats: &mut Stats,
    ) {
        let Stages {
            vertices,
            lights,
            spans,
            samples,
            diffuse,
            ..
        } = stages;
        samples.clear();
        for (i, lane) in queue.iter_mut().enumerate() {
            let Some(v) = &vertices[i] else {
                samples.push(None);
                continue;
            };
            PathTracer::add_light(&mut lane.path, v, &lights[spans[i].clone()]);
            let [u_lobe, u1, u2] = PathTracer::bsdf_numbers(lane.depth, &lane.stream);
            match v.bsdf.diffuse_only() {
                Some(lobe) if u_lobe < lobe.p_diffuse => {
                    samples.push(None);
                    if diffuse.push(i, &lobe, u1, u2) {
                        diffuse.run(samples);
                    }
                }
                _ => samples.push(v.bsdf.sample(u_lobe, u1, u2)),
            }
        }
        diffuse.run(samples);
        let mut alive = 0;
        for i in 0..queue.len() {
            let lane = &mut queue[i];
            let goes_on = match &vertices[i] {
                Some(v) => PathTracer::scatter(
                    &mut lane.path,
                    v,
                    samples[i],
                    lane.depth,
                    &lane.stream,
                    stats,
                ),
                None => false,
            };
            if goes_on {
                lane.depth += 1;
                lane.rays += 1;
                queue.swap(alive, i);
                alive += 1;
            } else {
                done(lane.sample, lane.path.finish(), lane.rays);
            }
        }
        queue.truncate(alive);
    }
}

impl CameraTracer for WavefrontPathTracer<'_> {
    #[inline]
    fn trace_camera_ray(&self, ray: &Ray, stream: &Stream, stats: &mut Stats) -> Color {
        self.paths.trace_camera_ray(ray, stream, stats)
    }

    fn trace_camera_packet(&self, packet: CameraPacket<'_>, stats: &mut Stats) {
        self.paths.trace_camera_packet(packet, stats)
    }

    fn traces_batches(&self) -> bool {
        true
    }

    fn trace_camera_batch(&self, batch: CameraBatch<'_>, stats: &mut Stats) {
        let (count, sample, done) = (batch.count, batch.sample, batch.done);
        let capacity = self.capacity.min(count);
        let mut queue: Vec<Lane> = Vec::with_capacity(capacity);
        let mut stages = Stages::default();
        let mut next = 0;
        let mut clock = StageClock::start();
        // Adds the thread's CPU time since the last lap to `stage`.
        let mut lap = |stage: usize, stats: &mut Stats| stats.stages.ns[stage] += clock.lap();
        loop {
            while queue.len() < capacity && next < count {
                let Some((ray, stream)) = sample(next) else {
                    // Stopped: no more samples, the ones begun finish.
                    next = count;
                    break;
                };
                queue.push(Lane {
                    path: Path::new(ray),
                    stream,
                    sample: next,
                    depth: 1,
                    rays: 0,
                });
                next += 1;
            }
            lap(CAMERA, stats);
            if queue.is_empty() {
                break;
            }
            self.find_hits(&queue, &mut stages, stats);
            lap(TRACE, stats);
            self.arrive(&mut queue, &mut stages, stats);
            lap(SHADE, stats);
            self.answer_shadow_rays(&queue, &mut stages, stats);
            lap(SHADOW, stats);
            self.leave(&mut queue, &mut stages, done, stats);
            lap(LEAVE, stats);
        }
    }
}

/// Whether rays at a path's `depth` are coherent enough to walk the tree as packets: the
/// camera rays of neighbouring pixels and their first hits' shadow rays (depth one) are,
/// the rays after a bounce point every way. Walked as packets of one depth, the deeper
/// rays cost the sphereflake 24 % more instructions than one by one, mixed depths more
/// still (docs/path-tracing.md).
#[inline]
fn coherent(depth: u32) -> bool {
    depth <= 1
}

/// The index an entry of a stage's `order` stands for: its low 32 bits (the shadow stage
/// keeps the light sample's place at its vertex above them).
#[inline]
fn index(entry: u64) -> usize {
    (entry & 0xffff_ffff) as usize
}
