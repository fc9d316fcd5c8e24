//! Whitted's recursive ray tracer, rendered in tiles by the sampler.

use super::IntegratorMethod;
use crate::integrator::{CameraTracer, Whitted};
use crate::options::RenderOptions;
use crate::scene::PreparedScene;

/// The Whitted integrator.
pub(super) struct WhittedMethod;

impl IntegratorMethod for WhittedMethod {
    fn tracer<'a>(
        &self,
        scene: &'a PreparedScene<'a>,
        options: &RenderOptions,
    ) -> Box<dyn CameraTracer + 'a> {
        Box::new(Whitted::new(scene, options))
    }
}
