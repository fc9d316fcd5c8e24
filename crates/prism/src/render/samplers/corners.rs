//! The corner pattern: each pixel's centre and its four corners, the corners shared with
//! the neighbouring pixels, traced in passes over rows of the whole image.

use super::SamplerMethod;
use crate::options::RenderOptions;
use crate::render::memory::{MemoryEstimate, CENTRE_BYTES, CORNER_BYTES, SPLAT_SUM_BYTES};
use crate::render::{lattice, Job, RenderError, Traced};

/// The corner sampler.
pub(super) struct Corners;

impl SamplerMethod for Corners {
    /// Rows, and the bottom corners' row.
    fn pieces(&self, options: &RenderOptions) -> usize {
        options.height as usize + 1
    }

    fn passes(&self, _options: &RenderOptions) -> u64 {
        lattice::passes(None)
    }

    fn memory(&self, options: &RenderOptions, _box_pixel: bool, e: &mut MemoryEstimate) {
        let pixels = options.width as u64 * options.height as u64;
        let corners = (options.width as u64 + 1) * (options.height as u64 + 1);
        e.add(
            "sample lattice",
            corners * CORNER_BYTES + pixels * CENTRE_BYTES,
        );
        e.add("filter sums", pixels * SPLAT_SUM_BYTES);
    }

    /// It assembles the film once more from its lattice.
    fn films(&self) -> u64 {
        2
    }

    fn renders_regions(&self) -> bool {
        false
    }

    fn render(&self, job: &Job, _options: &RenderOptions) -> Result<Traced, RenderError> {
        lattice::render_corners(job)
    }
}
