//! Integrators turn a camera ray into radiance. Whitted's recursive ray tracer is the one
//! prism is built around; the path tracer (`path.rs`) solves the rendering equation with
//! area lights (`emitters.rs`) and the lobes of `shading::Bsdf`, one path at a time or as a
//! wavefront of thousands (`wavefront.rs`); the beam tracer (`beam/`)
//! traces whole beams of planar polygons instead of rays.

mod area_lights;
pub mod beam;
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

/// What an integrator does with camera rays: radiance along one, or along a packet of
/// them (at most `accel::PACKET_MAX`) with exactly the values one at a time gives. The
/// renderer's samplers call it; `render::IntegratorMethod` makes one for a render.
pub trait CameraTracer: Sync {
    /// Radiance along a camera ray. `stream` holds the sample's random numbers, which a
    /// stochastic integrator draws.
    fn trace_camera_ray(&self, ray: &Ray, stream: &Stream, stats: &mut Stats) -> Color;

    /// Radiance along each of `rays` into `colors`, ray i with the random numbers of
    /// `streams[i]`; `rays_of[i]` gets the rays ray i spawned after itself. By default
    /// one ray at a time.
    fn trace_camera_packet(
        &self,
        rays: &[Ray],
        streams: &[Stream],
        colors: &mut [Color],
        rays_of: &mut [u32; PACKET_MAX],
        stats: &mut Stats,
    ) {
        for (i, (ray, stream)) in rays.iter().zip(streams).enumerate() {
            let before = stats.total_rays();
            colors[i] = self.trace_camera_ray(ray, stream, stats);
            rays_of[i] = (stats.total_rays() - before).saturating_sub(1) as u32;
        }
    }

    /// Whether `trace_camera_batch` keeps many paths in flight (a wavefront), so that a
    /// sampler should hand it a whole tile's samples at once rather than packets.
    fn traces_batches(&self) -> bool {
        false
    }

    /// Radiance of up to `count` camera samples. Sample i's ray and random numbers come
    /// from `sample(i)`, asked once each in order of i when the tracer has room for it;
    /// its radiance and the rays it spawned after its camera ray go to
    /// `done(i, color, rays)`, in any order. Every value is the one `trace_camera_ray`
    /// gives. A `sample` that answers None stops the batch (a cancelled render): it is
    /// asked no more, and the samples already begun finish. By default packets of
    /// `PACKET_MAX` consecutive samples.
    fn trace_camera_batch(
        &self,
        count: usize,
        sample: &mut dyn FnMut(usize) -> Option<(Ray, Stream)>,
        done: &mut dyn FnMut(usize, Color, u32),
        stats: &mut Stats,
    ) {
        let mut colors = [Color::ZERO; PACKET_MAX];
        for first in (0..count).step_by(PACKET_MAX) {
            let n = PACKET_MAX.min(count - first);
            let (rays, streams): (ArrayVec<Ray, PACKET_MAX>, ArrayVec<Stream, PACKET_MAX>) =
                (first..first + n).map_while(&mut *sample).unzip();
            let n = rays.len();
            let mut rays_of = [0u32; PACKET_MAX];
            self.trace_camera_packet(&rays, &streams, &mut colors[..n], &mut rays_of, stats);
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
    fn trace_camera_packet(
        &self,
        rays: &[Ray],
        _streams: &[Stream],
        colors: &mut [Color],
        rays_of: &mut [u32; PACKET_MAX],
        stats: &mut Stats,
    ) {
        let n = rays.len();
        let mut hits = [None; PACKET_MAX];
        self.camera_hits(rays, &mut hits[..n], stats);
        self.shade_camera_packet(rays, &hits[..n], &mut colors[..n], rays_of, stats);
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
    fn trace_camera_packet(
        &self,
        rays: &[Ray],
        streams: &[Stream],
        colors: &mut [Color],
        rays_of: &mut [u32; PACKET_MAX],
        stats: &mut Stats,
    ) {
        let n = rays.len();
        PathTracer::trace_camera_packet(self, rays, streams, &mut colors[..n], rays_of, stats)
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
