//! The path tracer, rendered in tiles by the sampler: as a wavefront of paths (the
//! default) or one path, or one packet of paths, at a time (`wavefront` off).

use super::IntegratorMethod;
use crate::integrator::{CameraTracer, PathTracer, WavefrontPathTracer};
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
        if options.wavefront {
            Box::new(WavefrontPathTracer::new(scene, options))
        } else {
            Box::new(PathTracer::new(scene, options))
        }
    }
}
