//! The path tracer, rendered in tiles by the sampler.

use super::IntegratorMethod;
use crate::integrator::{CameraTracer, PathTracer};
use crate::options::RenderOptions;
use crate::scene::PreparedScene;

/// The path-tracing integrator.
pub(super) struct PathMethod;

impl IntegratorMethod for PathMethod {
    fn tracer<'a>(
        &self,
        scene: &'a PreparedScene<'a>,
        options: &RenderOptions,
    ) -> Box<dyn CameraTracer + 'a> {
        Box::new(PathTracer::new(scene, options))
    }
}
