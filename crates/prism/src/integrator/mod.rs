//! Integrators turn a camera ray into radiance. Whitted's recursive ray tracer is the one
//! prism is built around; the path tracer (`path.rs`) solves the rendering equation with
//! area lights (`emitters.rs`) and the lobes of `shading::Bsdf`; the beam tracer (`beam/`)
//! traces whole beams of planar polygons instead of rays.

pub mod beam;
mod emitters;
mod light_buffer;
mod path;
mod shadow;
mod whitted;

pub use emitters::{EmitterSample, Emitters};
pub use light_buffer::{BufferParams, LightBuffer, LightBufferInfo};
pub use path::{PathTracer, Strategy, RR_DEPTH};
pub use shadow::{begin_piece, ShadowMethod, ShadowSpec, Shadows};
pub use whitted::Whitted;

use crate::math::hash::Stream;
use crate::math::{Color, Ray};
use crate::options::{IntegratorKind, RenderOptions};
use crate::scene::PreparedScene;
use crate::stats::Stats;

/// The integrator of one render, chosen by `RenderOptions::integrator`.
pub enum Integrator<'a> {
    /// Whitted ray tracing.
    Whitted(Whitted<'a>),
    /// Path tracing.
    Path(PathTracer<'a>),
}

impl<'a> Integrator<'a> {
    /// The integrator `options` ask for, over `scene`.
    pub fn new(scene: &'a PreparedScene<'a>, options: &RenderOptions) -> Self {
        match options.integrator {
            IntegratorKind::Whitted => Integrator::Whitted(Whitted::new(scene, options)),
            IntegratorKind::Path => Integrator::Path(PathTracer::new(scene, options)),
            // The beam tracer renders whole tiles (`render::render` hands it the film);
            // callers that ask for radiance ray by ray get the ray tracer it agrees with.
            IntegratorKind::Beam => Integrator::Whitted(Whitted::new(scene, options)),
        }
    }

    /// Radiance along a camera ray. `stream` holds the sample's random numbers, which
    /// only the path tracer draws.
    #[inline]
    pub fn trace_camera_ray(&self, ray: &Ray, stream: &Stream, stats: &mut Stats) -> Color {
        match self {
            Integrator::Whitted(w) => w.trace_camera_ray(ray, stats),
            Integrator::Path(p) => p.trace_camera_ray(ray, stream, stats),
        }
    }

    /// The shadow-ray machinery of the Whitted integrator (light buffers and why some
    /// lights have none), for reports; None for the path tracer.
    pub fn shadows(&self) -> Option<&Shadows<'a>> {
        match self {
            Integrator::Whitted(w) => Some(w.shadows()),
            Integrator::Path(_) => None,
        }
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
