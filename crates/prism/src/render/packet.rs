//! Camera rays traced as packets: the rays through a run of neighbouring film positions
//! find their first hits together (`Whitted::camera_hits`), their shadow rays to each
//! light go as packets too, and each ray's tree is then shaded on its own
//! (`Whitted::shade_camera_packet`). Every value is the one a single ray gives. The
//! per-pixel samplers trace blocks of pixels this way (`pixels.rs`), the corner pattern
//! runs of lattice points along a row (`lattice.rs`).

use super::rays::{PixelRays, RayMark};
use super::Job;
use crate::accel::PACKET_MAX;
use crate::integrator::Whitted;
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
    // `Job::packets` is set only for the Whitted integrator.
    let Some(whitted) = job.integrator.whitted() else {
        for ((p, c), r) in at.iter().zip(colors.iter_mut()).zip(rays.iter_mut()) {
            let before = *stats;
            *c = job.trace(p.x, p.y, stats);
            *r += PixelRays::between(&before, stats);
        }
        return;
    };
    let camera_rays: ArrayVec<Ray, PACKET_MAX> =
        at.iter().map(|p| job.camera.ray(p.x, p.y)).collect();
    trace_whitted_packet(whitted, &camera_rays, colors, rays, stats);
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
    let shared = PixelRays::since(before, stats);
    for (i, r) in rays[..n].iter_mut().enumerate() {
        let mut work = shared.share(i, n);
        work.total = 1 + rays_of[i];
        *r += work;
    }
}
