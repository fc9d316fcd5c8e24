//! Integrators as methods: how a render turns camera rays into radiance (a tracer the
//! samplers call ray by ray or packet by packet) and, for an integrator that does not
//! trace rays one sample at a time, how it renders a whole image instead. The list below
//! gives each `IntegratorKind` its method; adding an integrator is its name in
//! `choices::IntegratorKind`, its file here, and its line in the list.

mod beam;
mod path;
mod whitted;

use super::{RenderError, RenderResult, SamplerMethod, Tile, TileDone};
use crate::choices::IntegratorKind;
use crate::integrator::CameraTracer;
use crate::options::RenderOptions;
use crate::scene::PreparedScene;
use std::sync::atomic::AtomicBool;

/// How an integrator renders.
pub trait IntegratorMethod: Sync {
    /// The tracer of camera rays over `scene` for `options`.
    fn tracer<'a>(
        &self,
        scene: &'a PreparedScene<'a>,
        options: &RenderOptions,
    ) -> Box<dyn CameraTracer + 'a>;

    /// Renders `region` of the image: by default the sampler's pieces over the thread
    /// pool, each camera ray traced by `tracer` (`render::render_tiled`). An integrator
    /// that works on whole beams or images overrides this.
    fn render(
        &self,
        scene: &PreparedScene,
        options: &RenderOptions,
        region: Tile,
        sampler: &dyn SamplerMethod,
        on_tile: &(dyn Fn(TileDone) + Sync),
        cancel: &AtomicBool,
    ) -> Result<RenderResult, RenderError> {
        let tracer = self.tracer(scene, options);
        super::render_tiled(scene, options, region, sampler, tracer, on_tile, cancel)
    }
}

/// The method of each integrator: the one list of them.
pub fn integrator_method(kind: IntegratorKind) -> &'static dyn IntegratorMethod {
    match kind {
        IntegratorKind::Whitted => &whitted::WhittedMethod,
        IntegratorKind::Path => &path::PathMethod,
        IntegratorKind::Beam => &beam::BeamMethod,
    }
}
