//! The adaptive sampler: the pixel corners' lattice refined where it differs (Whitted;
//! POV-Ray's +AM2), traced in passes over rows of the whole image.

use super::SamplerMethod;
use crate::options::RenderOptions;
use crate::render::memory::{
    MemoryEstimate, CORNER_BYTES, EDGE_POINT_BYTES, ENCODED_CORNER_BYTES, SPLAT_SUM_BYTES,
};
use crate::render::{lattice, Job, RenderError, Traced};
use crate::sampling::Refinement;

/// The adaptive sampler.
pub(super) struct Adaptive;

impl SamplerMethod for Adaptive {
    /// Rows, and the bottom corners' row.
    fn pieces(&self, options: &RenderOptions) -> usize {
        options.height as usize + 1
    }

    fn passes(&self, options: &RenderOptions) -> u64 {
        lattice::passes(Some(options.adaptive.depth))
    }

    fn memory(&self, options: &RenderOptions, box_pixel: bool, e: &mut MemoryEstimate) {
        let pixels = options.width as u64 * options.height as u64;
        let corners = (options.width as u64 + 1) * (options.height as u64 + 1);
        e.add(
            "sample lattice",
            corners * (CORNER_BYTES + ENCODED_CORNER_BYTES) + pixels * EDGE_POINT_BYTES,
        );
        // Under the pixel box each pixel is its own samples' mean: no sums.
        if !box_pixel {
            e.add("filter sums", pixels * SPLAT_SUM_BYTES);
        }
    }

    /// It assembles the film once more from its lattice.
    fn films(&self) -> u64 {
        2
    }

    fn renders_regions(&self) -> bool {
        false
    }

    fn render(&self, job: &Job, options: &RenderOptions) -> Result<Traced, RenderError> {
        let rule = Refinement::new(&options.adaptive, options.transfer, options.seed);
        lattice::render_adaptive(job, &rule)
    }
}
