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
    /// A stage's queries in the order they go to the accelerator (`sort_by_key`).
    order: Vec<u64>,
    /// `sort_by_key`'s scratch: the entries between its passes and its key counts.
    sorting: Sorting,
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

    /// Every path's next hit. The rays go to the accelerator grouped by depth, in queue
    /// order within a depth: the camera rays of neighbouring pixels in runs of
    /// `PACKET_MAX` as packets, the bounce rays one by one (`coherent`).
    fn find_hits(&self, queue: &[Lane], stages: &mut Stages, stats: &mut Stats) {
        let s = self.paths.scene;
        let Stages {
            hits,
            order,
            sorting,
            ..
        } = stages;
        hits.clear();
        hits.resize(queue.len(), None);
        sort_by_key(queue.iter().map(|l| l.depth), order, sorting);
        stats.primary_rays += queue.iter().filter(|l| l.depth == 1).count() as u64;
        for run in runs(order) {
            let rays: ArrayVec<Ray, PACKET_MAX> =
                run.iter().map(|&k| queue[index(k)].path.ray).collect();
            let mut found = [None; PACKET_MAX];
            let found = &mut found[..run.len()];
            if coherent((run[0] >> 32) as u32) {
                s.intersector.intersect_packet(
                    &s.scene.geometry,
                    &rays,
                    f32::INFINITY,
                    found,
                    stats,
                );
            } else {
                for (r, f) in rays.iter().zip(found.iter_mut()) {
                    *f = s
                        .intersector
                        .intersect(&s.scene.geometry, r, f32::INFINITY, stats);
                }
            }
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

    /// Whether each light sample's shadow ray is blocked. The rays go grouped by their
    /// vertex's depth and their place among its samples (which light): the shadow rays
    /// of neighbouring first hits to one light in runs of `PACKET_MAX` as packets, the
    /// deeper vertices' one by one (`coherent`).
    fn answer_shadow_rays(&self, queue: &[Lane], stages: &mut Stages, stats: &mut Stats) {
        let s = self.paths.scene;
        let Stages {
            lights,
            spans,
            order,
            sorting,
            ..
        } = stages;
        let keys = queue.iter().zip(spans.iter()).flat_map(|(lane, span)| {
            (0..span.len()).map(move |slot| lane.depth << 16 | (slot as u32).min(0xffff))
        });
        sort_by_key(keys, order, sorting);
        for run in runs(order) {
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
            if coherent((run[0] >> 48) as u32) {
                stats.shadow_query(c as u64, |stats| {
                    s.intersector.occluded_packet(
                        &s.scene.geometry,
                        &rays,
                        &t_max,
                        &mut blocked[..c],
                        stats,
                    )
                });
            } else {
                for ((ray, &t), b) in rays.iter().zip(&t_max).zip(&mut blocked[..c]) {
                    *b = stats.shadow_query(1, |stats| {
                        s.intersector.occluded(&s.scene.geometry, ray, t, stats)
                    });
                }
            }
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

/// The indices of `keys` in order of key, in index order within a key, into `order` as
/// key << 32 | index. The keys are small (a depth, a depth and a light's place), so a
/// counting sort, stable, on each 16-bit half of the key that is not all zero (least
/// significant first) puts them in order in a pass or two over the queue, where a
/// comparison sort took 4 % of a `cornell-light` render's instructions and mispredicted
/// its branches. A half whose largest value is above the entries' count is left to
/// `sort_unstable` of the whole (a scene with thousands of delta lights), which gives the
/// same order, as the entries are distinct.
fn sort_by_key(keys: impl Iterator<Item = u32>, order: &mut Vec<u64>, sorting: &mut Sorting) {
    order.clear();
    order.extend(
        keys.enumerate()
            .map(|(i, key)| u64::from(key) << 32 | i as u64),
    );
    let Sorting { spare, counts } = sorting;
    for shift in [32, 48] {
        let digit = |entry: u64| (entry >> shift & 0xffff) as usize;
        let largest = order.iter().map(|&e| digit(e)).max().unwrap_or(0);
        if largest == 0 {
            continue;
        }
        if largest > order.len() {
            order.sort_unstable();
            return;
        }
        counts.clear();
        counts.resize(largest + 1, 0);
        for &e in order.iter() {
            counts[digit(e)] += 1;
        }
        let mut start = 0;
        for c in counts.iter_mut() {
            let n = *c;
            *c = start;
            start += n;
        }
        spare.clear();
        spare.resize(order.len(), 0);
        for &e in order.iter() {
            let at = &mut counts[digit(e)];
            spare[*at as usize] = e;
            *at += 1;
        }
        std::mem::swap(order, spare);
    }
}

/// `sort_by_key`'s buffers, kept between its calls.
#[derive(Default)]
struct Sorting {
    spare: Vec<u64>,
    counts: Vec<u32>,
}

/// The index an entry of `sort_by_key`'s order stands for.
#[inline]
fn index(entry: u64) -> usize {
    (entry & 0xffff_ffff) as usize
}

/// `order` cut into runs of one key, each cut into pieces of at most `PACKET_MAX`.
fn runs(order: &[u64]) -> impl Iterator<Item = &[u64]> {
    order
        .chunk_by(|a, b| a >> 32 == b >> 32)
        .flat_map(|run| run.chunks(PACKET_MAX))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The counting sort gives the comparison sort's order: depths alone, depths with
    /// light places (both halves of the key), and keys too large to count.
    #[test]
    fn sort_by_key_is_the_comparison_sorts_order() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = move |below: u32| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state % u64::from(below)) as u32
        };
        let mut sorting = Sorting::default();
        let mut order = Vec::new();
        for (len, make) in [(1024, 0u32), (1000, 1), (700, 2), (300, 3), (0, 0)] {
            let keys: Vec<u32> = (0..len)
                .map(|_| match make {
                    0 => 1 + next(6),
                    1 => (1 + next(6)) << 16 | next(3),
                    2 => next(2) << 16 | next(2),
                    _ => 1 + next(100_000),
                })
                .collect();
            sort_by_key(keys.iter().copied(), &mut order, &mut sorting);
            let mut expected: Vec<u64> = keys
                .iter()
                .enumerate()
                .map(|(i, &k)| u64::from(k) << 32 | i as u64)
                .collect();
            expected.sort_unstable();
            assert_eq!(order, expected, "keys of kind {make}");
        }
    }
}
