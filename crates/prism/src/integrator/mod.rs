//! Integrators turn a camera ray into radiance. Whitted's recursive ray tracer is the one
//! prism is built around; the path tracer (`path.rs`) solves the rendering equation with
//! area lights (`emitters.rs`) and the lobes of `shading::Bsdf`, one path at a time or as a
//! wavefront of thousands (`wavefront.rs`); the beam tracer (`beam/`)
//! traces whole beams of planar polygons instead of rays.

mod area_lights;
pub mod beam;
mod diffuse_lanes;
mod emitters;
mod light_buffer;
mod path;
mod shadow;
mod stage_clock;
mod wavefront;
mod whitted;

pub use crate::choices::Strategy;
pub use emitters::{EmitterSample, Emitters};
pub use light_buffer::{BufferParams, LightBuffer, LightBufferInfo};
pub use path::{PathTracer, RR_DEPTH};
pub use shadow::{begin_piece, ShadowMethod, ShadowSpec, Shadows};
pub use wavefront::WavefrontPathTracer;
pub use whitted::Whitted;

use crate::accel::PACKET_MAX;
use crate::math::hash::Stream;
use crate::math::{Color, Ray};
use crate::stats::Stats;
use arrayvec::ArrayVec;

/// A packet of camera rays (at most `accel::PACKET_MAX`) for
/// `CameraTracer::trace_camera_packet`, and where its answers go.
pub struct CameraPacket<'a> {
    /// The camera rays.
    pub rays: &'a [Ray],
    /// Ray i's random numbers, which a stochastic integrator draws.
    pub streams: &'a [Stream],
    /// Radiance along ray i (at least as many slots as rays).
    pub colors: &'a mut [Color],
    /// Gains the rays ray i spawned after itself.
    pub rays_of: &'a mut [u32; PACKET_MAX],
}

/// A batch of camera samples for `CameraTracer::trace_camera_batch`: how many, where each
/// comes from and where its answer goes.
pub struct CameraBatch<'a> {
    /// Samples in the batch.
    pub count: usize,
    /// Sample i's ray and random numbers, asked once each in order of i when the tracer
    /// has room for it; None stops the batch (a cancelled render): it is asked no more,
    /// and the samples already begun finish.
    pub sample: &'a mut dyn FnMut(usize) -> Option<(Ray, Stream)>,
    /// Takes sample i's radiance and the rays it spawned after its camera ray, in any
    /// order of i.
    pub done: &'a mut dyn FnMut(usize, Color, u32),
}

/// What an integrator does with camera rays: radiance along one, or along a packet of
/// them (at most `accel::PACKET_MAX`) with exactly the values one at a time gives. The
/// renderer's samplers call it; `render::IntegratorMethod` makes one for a render.
pub trait CameraTracer: Sync {
    /// Radiance along a camera ray. `stream` holds the sample's random numbers, which a
    /// stochastic integrator draws.
    fn trace_camera_ray(&self, ray: &Ray, stream: &Stream, stats: &mut Stats) -> Color;

    /// Radiance along each of the packet's rays, with the values one at a time gives. By
    /// default one ray at a time.
    fn trace_camera_packet(&self, packet: CameraPacket<'_>, stats: &mut Stats) {
        for (i, (ray, stream)) in packet.rays.iter().zip(packet.streams).enumerate() {
            let before = stats.total_rays();
            packet.colors[i] = self.trace_camera_ray(ray, stream, stats);
            packet.rays_of[i] = (stats.total_rays() - before).saturating_sub(1) as u32;
        }
    }

    /// Whether `trace_camera_batch` keeps many paths in flight (a wavefront), so that a
    /// sampler should hand it a whole tile's samples at once rather than packets.
    fn traces_batches(&self) -> bool {
        false
    }

    /// Radiance of the batch's samples, each value the one `trace_camera_ray` gives. By
    /// default packets of `PACKET_MAX` consecutive samples.
    fn trace_camera_batch(&self, batch: CameraBatch<'_>, stats: &mut Stats) {
        let (count, sample, done) = (batch.count, batch.sample, batch.done);
        let mut colors = [Color::ZERO; PACKET_MAX];
        for first in (0..count).step_by(PACKET_MAX) {
            let n = PACKET_MAX.min(count - first);
            let (rays, streams): (ArrayVec<Ray, PACKET_MAX>, ArrayVec<Stream, PACKET_MAX>) =
                (first..first + n).map_while(&mut *sample).unzip();
            let n = rays.len();
            let mut rays_of = [0u32; PACKET_MAX];
            let packet = CameraPacket {
                rays: &rays,
                streams: &streams,
                colors: &mut colors[..n],
                rays_of: &mut rays_of,
            };
            self.trace_camera_packet(packet, stats);
            for i in 0..n {
                done(first + i, colors[i], rays_of[i]);
            }
            if n < PACKET_MAX.min(count - first) {
                return;
            }
        }
    }

    /// The shadow-ray machinery (light buffers and why some lights have none), for
    /// reports; None for an integrator without it.
    fn shadows(&self) -> Option<&Shadows<'_>> {
        None
    }
}

impl CameraTracer for Whitted<'_> {
    #[inline]
    fn trace_camera_ray(&self, ray: &Ray, _stream: &Stream, stats: &mut Stats) -> Color {
        Whitted::trace_camera_ray(self, ray, stats)
    }

    /// The first hits as one packet, then each ray's tree shaded on its own with its
    /// shadow rays in packets.
    fn trace_camera_packet(&self, packet: CameraPacket<'_>, stats: &mut Stats) {
        let (rays, n) = (packet.rays, packet.rays.len());
        let mut hits = [None; PACKET_MAX];
        self.camera_hits(rays, &mut hits[..n], stats);
        let colors = &mut packet.colors[..n];
        self.shade_camera_packet(rays, &hits[..n], colors, packet.rays_of, stats);
    }

    fn shadows(&self) -> Option<&Shadows<'_>> {
        Some(Whitted::shadows(self))
    }
}

impl CameraTracer for PathTracer<'_> {
    #[inline]
    fn trace_camera_ray(&self, ray: &Ray, stream: &Stream, stats: &mut Stats) -> Color {
        PathTracer::trace_camera_ray(self, ray, stream, stats)
    }

    /// The packet's paths breadth first, a packet per depth.
    fn trace_camera_packet(&self, packet: CameraPacket<'_>, stats: &mut Stats) {
        PathTracer::trace_camera_packet(self, packet, stats)
    }
}

/// Whether a secondary ray (or beam) of weight `w` in a parent of weight `weight` is
/// traced: the ray tracer's depth control, which the beam tracer applies per fragment.
/// Under SPD's rules, whenever the material has the term at all (`present`); otherwise
/// when it can change some channel of the pixel by `min_weight`. A child the static limit
/// would trace but this drops is counted as pruned.
pub(crate) fn spawns(
    (spd_rules, min_weight): (bool, f32),
    present: bool,
    w: crate::math::Color,
    weight: crate::math::Color,
    stats: &mut crate::stats::Stats,
) -> bool {
    if spd_rules {
        return present;
    }
    if w.max_element() <= 0.0 {
        return false;
    }
    if changes_pixel(min_weight, weight, w) {
        true
    } else {
        stats.pruned_rays += 1;
        false
    }
}

/// Whether a term worth `w` (per unit of radiance) to a ray of weight `weight` in its pixel
/// could change some channel of the pixel by `min_weight`: the one rule of adaptive depth
/// control (`spawns`) and of adaptive shadow testing (the Whitted integrator's faint
/// lights).
#[inline]
pub(crate) fn changes_pixel(
    min_weight: f32,
    weight: crate::math::Color,
    w: crate::math::Color,
) -> bool {
    (weight * w).max_element() >= min_weight
}
