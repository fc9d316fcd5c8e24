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
use crate::integrator::{CameraPacket, CameraTracer};
use crate::math::hash::Stream;
use crate::math::{Color, Ray, Vec2};
use crate::stats::Stats;
use arrayvec::ArrayVec;

/// Traces the camera rays through film positions `at` (at most `PACKET_MAX`) as one
/// packet: `colors[i]` is ray i's radiance, and `rays[i]` gains its rays and work, each
/// ray counted in its own slot and the packets' shared traversal split evenly (none
/// where `rays` is empty).
pub(super) fn trace_packet(
    job: &Job,
    at: &[Vec2],
    colors: &mut [Color],
    rays: &mut [PixelRays],
    stats: &mut Stats,
) {
    let camera_rays: ArrayVec<Ray, PACKET_MAX> =
        at.iter().map(|p| job.camera.ray(p.x, p.y)).collect();
    let streams: ArrayVec<Stream, PACKET_MAX> = at.iter().map(|p| job.stream(p.x, p.y)).collect();
    trace_camera_packet(&*job.tracer, &camera_rays, &streams, colors, rays, stats);
}

/// Traces `camera_rays` (at most `PACKET_MAX`) as one packet with `tracer`, ray i
/// with the random numbers of `streams[i]` (which only the path tracer draws):
/// `colors[i]` is ray i's radiance, and `rays[i]` gains its rays and its even share of
/// the packets' traversal. An empty `rays` keeps no counts (a render without per-pixel
/// ray counts), which spares the division of the packet's work among its rays.
pub(super) fn trace_camera_packet(
    tracer: &dyn CameraTracer,
    camera_rays: &[Ray],
    streams: &[Stream],
    colors: &mut [Color],
    rays: &mut [PixelRays],
    stats: &mut Stats,
) {
    let n = camera_rays.len();
    debug_assert!(rays.is_empty() || rays.len() >= n);
    let before = RayMark::of(stats);
    // Per ray, the rays of its tree or path after the camera ray.
    let mut rays_of = [0u32; PACKET_MAX];
    let packet = CameraPacket {
        rays: camera_rays,
        streams,
        colors: &mut colors[..n],
        rays_of: &mut rays_of,
    };
    tracer.trace_camera_packet(packet, stats);
    if rays.is_empty() {
        return;
    }
    // Each ray counts in its own pixel; the traversal work is shared by the packet.
    let shared = PixelRays::since(before, stats);
    for (i, r) in rays[..n].iter_mut().enumerate() {
        let mut work = shared.share(i, n);
        work.total = 1 + rays_of[i];
        *r += work;
    }
}
