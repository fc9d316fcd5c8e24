//! The per-pixel patterns (centre, grid, random, jittered, relaxed): every sample belongs
//! to one pixel, so tiles render independently and any region renders on its own.

use super::SamplerMethod;
use crate::choices::SamplerKind;
use crate::math::Vec2;
use crate::options::RenderOptions;
use crate::render::{Job, RenderError, Traced};
use crate::sampling::PixelPattern;

/// Where a per-pixel sampler puts a pixel's samples: what a new per-pixel pattern
/// implements to render through `Job::render_pixels`.
pub trait PixelSamples: Sync {
    /// Samples per pixel.
    fn count(&self) -> u32;

    /// Appends the offsets in (0, 1)² of pixel (px, py)'s samples, in sample order.
    fn offsets(&self, px: u32, py: u32, out: &mut Vec<Vec2>);
}

impl PixelSamples for PixelPattern {
    fn count(&self) -> u32 {
        PixelPattern::count(self)
    }

    fn offsets(&self, px: u32, py: u32, out: &mut Vec<Vec2>) {
        PixelPattern::offsets(self, px, py, out)
    }
}

/// A per-pixel pattern of the library, named by its kind.
pub(super) struct PixelSampler(pub SamplerKind);

impl SamplerMethod for PixelSampler {
    fn render(&self, job: &Job, options: &RenderOptions) -> Result<Traced, RenderError> {
        let pattern = PixelPattern::new(self.0, options.samples, options.seed)
            .expect("the list gives per-pixel kinds only");
        job.render_pixels(&pattern)
    }
}
