//! Samplers as methods: what a render needs to know of a sampler (its pieces of work, its
//! passes over the pixels, the memory it takes, whether it can render a region) and how it
//! renders, behind one trait. The list below gives each `SamplerKind` its method; adding a
//! sampler is its name in `choices::SamplerKind`, its file here, and its line in the list.

mod adaptive;
mod corners;
mod pixel;

pub use pixel::PixelSamples;

use super::memory::{MemoryEstimate, SPLAT_SUM_BYTES};
use super::{Job, RenderError, Traced};
use crate::choices::SamplerKind;
use crate::options::RenderOptions;

/// How a sampler renders. The defaults are those of a per-pixel pattern rendered in
/// tiles: a sampler that shares samples between pixels overrides them.
pub trait SamplerMethod: Sync {
    /// The pieces of work the render's threads share: its tiles by default.
    fn pieces(&self, options: &RenderOptions) -> usize {
        let size = options.effective_tile_size();
        (options.width.div_ceil(size) as usize) * (options.height.div_ceil(size) as usize)
    }

    /// Passes over every pixel, for progress reports: one by default.
    fn passes(&self, _options: &RenderOptions) -> u64 {
        1
    }

    /// Films' worth of pixels it holds: one by default, written tile by tile.
    fn films(&self) -> u64 {
        1
    }

    /// Adds the buffers it needs beyond its films and the ray counts to `e`: by default
    /// the filter's sums, unless the filter is the one-pixel box.
    fn memory(&self, options: &RenderOptions, box_pixel: bool, e: &mut MemoryEstimate) {
        if !box_pixel {
            let pixels = options.width as u64 * options.height as u64;
            e.add("filter sums", pixels * SPLAT_SUM_BYTES);
        }
    }

    /// Whether it renders a region smaller than the image bit for bit as the whole
    /// image's pixels (true for per-pixel patterns).
    fn renders_regions(&self) -> bool {
        true
    }

    /// Renders `job`'s area with `options`' settings.
    fn render(&self, job: &Job, options: &RenderOptions) -> Result<Traced, RenderError>;
}

/// The method of each sampler: the one list of them.
pub fn sampler_method(kind: SamplerKind) -> &'static dyn SamplerMethod {
    match kind {
        SamplerKind::Centre => &pixel::PixelSampler(SamplerKind::Centre),
        SamplerKind::Grid => &pixel::PixelSampler(SamplerKind::Grid),
        SamplerKind::Corners => &corners::Corners,
        SamplerKind::Random => &pixel::PixelSampler(SamplerKind::Random),
        SamplerKind::Jittered => &pixel::PixelSampler(SamplerKind::Jittered),
        SamplerKind::Relaxed => &pixel::PixelSampler(SamplerKind::Relaxed),
        SamplerKind::Adaptive => &adaptive::Adaptive,
    }
}
