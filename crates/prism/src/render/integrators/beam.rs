//! The beam tracer: whole tile beams of planar polygons, not rays, so it renders the
//! whole image its own way (`render::render_beam`).

use super::whitted::WhittedMethod;
use super::IntegratorMethod;
use crate::integrator::beam::DEFAULT_TOLERANCE;
use crate::integrator::CameraTracer;
use crate::options::RenderOptions;
use crate::render::{
    ray_counts, render_beam, RenderError, RenderResult, SamplerMethod, Tile, TileDone,
};
use crate::scene::PreparedScene;
use std::sync::atomic::AtomicBool;

/// The beam-tracing integrator.
pub(super) struct BeamMethod;

impl IntegratorMethod for BeamMethod {
    /// Callers that ask for radiance ray by ray (a progressive render) get the ray tracer
    /// the beam tracer agrees with.
    fn tracer<'a>(
        &self,
        scene: &'a PreparedScene<'a>,
        options: &RenderOptions,
    ) -> Box<dyn CameraTracer + 'a> {
        WhittedMethod.tracer(scene, options)
    }

    /// The beam tracer cuts the view into its own tile beams and renders them all.
    fn render(
        &self,
        scene: &PreparedScene,
        options: &RenderOptions,
        region: Tile,
        _sampler: &dyn SamplerMethod,
        on_tile: &(dyn Fn(TileDone) + Sync),
        cancel: &AtomicBool,
    ) -> Result<RenderResult, RenderError> {
        if region != Tile::full(options.width, options.height) {
            return Err(RenderError::Options(
                "the beam integrator renders whole images only, no region of one".into(),
            ));
        }
        let beam = render_beam(scene, options, DEFAULT_TOLERANCE, on_tile, cancel)?;
        Ok(RenderResult {
            film: beam.film,
            stats: beam.stats,
            complete: beam.complete,
            rows_reached: beam.complete.then_some(options.height),
            render_time: beam.render_time,
            rays: ray_counts(options.per_pixel_rays, options.width, options.height)?,
            light_buffers: Vec::new(),
            light_buffer_notes: Vec::new(),
        })
    }
}
