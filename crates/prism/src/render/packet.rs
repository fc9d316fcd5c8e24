//! Camera rays traced as packets: the rays through a run of neighbouring film positions
//! find their first hits together (`Whitted::camera_hits`), their shadow rays to each
//! light go as packets too, and each ray's tree is then shaded on its own
//! (`Whitted::shade_camera_packet`); the path tracer's paths go breadth first, a packet
//! per depth (`PathTracer::trace_camera_packet`). Every value is the one a single ray
//! gives. The per-pixel samplers trace blocks of pixels this way (`pixels.rs`), the corner
//! pattern runs of lattice points along a row (`lattice.rs`), a progressive render blocks
//! of pixels per sample index (`progressive.rs`).

use super::rays::{PixelRays, RayMark};
use super::Job;
use crate::accel::PACKET_MAX;
use crate::integrator::{Integrator, PathTracer, Whitted};
use crate::math::hash::Stream;
use crate::math::{Color, Ray, Vec2};
use crate::stats::Stats;
use arrayvec::ArrayVec;

/// Traces the camera rays through film positions `at` (at most `PACKET_MAX`) as one
/// packet: `colors[i]` is ray i's radiance, and `rays[i]` gains its rays and work, each
/// ray counted in its own slot and the packets' shared traversal split evenly.
pub(super) fn trace_packet(
    job: &Job,
    at: &[Vec2],
    colors: &mut [Color],
    rays: &mut [PixelRays],
    stats: &mut Stats,
) {
    let camera_rays: ArrayVec<Ray, PACKET_MAX> =
        at.iter().map(|p| job.camera.ray(p.x, p.y)).collect();
    // Keyed by the film position itself, as `Job::trace` keys a single ray's.
    let streams: ArrayVec<Stream, PACKET_MAX> = (at.iter())
        .map(|p| Stream::new(p.x.to_bits(), p.y.to_bits(), 0, job.seed))
        .collect();
    trace_camera_packet(&job.integrator, &camera_rays, &streams, colors, rays, stats);
}

/// Traces `camera_rays` (at most `PACKET_MAX`) as one packet with `integrator`, ray i
/// with the random numbers of `streams[i]` (which only the path tracer draws):
/// `colors[i]` is ray i's radiance, and `rays[i]` gains its rays and its even share of
/// the packets' traversal.
pub(super) fn trace_camera_packet(
    integrator: &Integrator,
    camera_rays: &[Ray],
    streams: &[Stream],
    colors: &mut [Color],
    rays: &mut [PixelRays],
    stats: &mut Stats,
) {
    match integrator {
        Integrator::Whitted(w) => trace_whitted_packet(w, camera_rays, colors, rays, stats),
        Integrator::Path(p) => trace_path_packet(p, camera_rays, streams, colors, rays, stats),
    }
}

/// The path tracer's part of `trace_camera_packet`.
fn trace_path_packet(
    path: &PathTracer,
    camera_rays: &[Ray],
    streams: &[Stream],
    colors: &mut [Color],
    rays: &mut [PixelRays],
    stats: &mut Stats,
) {
    let n = camera_rays.len();
    let before = RayMark::of(stats);
    let mut rays_of = [0u32; PACKET_MAX];
    path.trace_camera_packet(camera_rays, streams, &mut colors[..n], &mut rays_of, stats);
    share_work(before, &rays_of, rays, stats);
}

/// Gives each of a packet's rays its own rays (`rays_of`, after the camera ray) and an
/// even share of the traversal work done since `before`.
fn share_work(before: RayMark, rays_of: &[u32; PACKET_MAX], rays: &mut [PixelRays], stats: &Stats) {
    let n = rays.len();
    let shared = PixelRays::since(before, stats);
    for (i, r) in rays.iter_mut().enumerate() {
        let mut work = shared.share(i, n);
        work.total = 1 + rays_of[i];
        *r += work;
    }
}

/// The Whitted part of `trace_packet`, for callers that make their own camera rays (at
/// most `PACKET_MAX`): `colors[i]` is ray i's radiance, and `rays[i]` gains its rays and
/// its even share of the packets' traversal.
pub(super) fn trace_whitted_packet(
    whitted: &Whitted,
    camera_rays: &[Ray],
    colors: &mut [Color],
    rays: &mut [PixelRays],
    stats: &mut Stats,
) {
    let n = camera_rays.len();
    let mut hits = [None; PACKET_MAX];
    let before = RayMark::of(stats);
    whitted.camera_hits(camera_rays, &mut hits[..n], stats);
    let mut rays_of = [0u32; PACKET_MAX];
    whitted.shade_camera_packet(
        camera_rays,
        &hits[..n],
        &mut colors[..n],
        &mut rays_of,
        stats,
    );
    // Each ray counts in its own pixel; the traversal work is shared by the packet.
    share_work(before, &rays_of, &mut rays[..n], stats);
}
