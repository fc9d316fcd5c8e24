//! Rendering with the beam tracer (`integrator::beam`): its tile beams go to the thread
//! pool like the samplers' tiles, and their exact box-filtered pixels fill the film. No
//! sampler or reconstruction filter is involved; the image is a pure function of scene and
//! options, the same for every thread count.

use super::{Film, RenderError, TileDone};
use crate::integrator::beam::{BeamTracer, TileImage};
use crate::math::Color;
use crate::options::RenderOptions;
use crate::scene::PreparedScene;
use crate::stats::Stats;
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// A beam-traced image and what it took.
pub struct BeamRender {
    /// The image.
    pub film: Film,
    /// Per pixel, the area the view's fragments covered (1 up to rounding).
    pub coverage: Vec<f64>,
    /// Per pixel, a bound on its error from checker squares too small to cut out.
    pub bound: Vec<f64>,
    /// Counters summed over every tile (`Stats::beams` and the fragments among them).
    pub stats: Stats,
    /// The deepest beam of any tile's tree.
    pub deepest: u32,
    /// False when the render was cancelled; unrendered pixels are black.
    pub complete: bool,
    /// Wall-clock time.
    pub render_time: Duration,
}

impl BeamRender {
    /// The largest error bound of any pixel.
    pub fn error_bound(&self) -> f64 {
        self.bound.iter().copied().fold(0.0, f64::max)
    }
}

/// Renders `scene` with the beam tracer at the size, depth and weight settings of
/// `options`; `tolerance` bounds each pixel's error where a checker's squares are too many
/// to cut out (beside a horizon). `on_tile` and `cancel` work as for `render`.
pub fn render_beam(
    scene: &PreparedScene,
    options: &RenderOptions,
    tolerance: f64,
    on_tile: &(dyn Fn(TileDone) + Sync),
    cancel: &AtomicBool,
) -> Result<BeamRender, RenderError> {
    options.validate().map_err(RenderError::Options)?;
    if !(tolerance > 0.0 && tolerance.is_finite()) {
        return Err(RenderError::Options(format!(
            "the tolerance must be a positive number, got {tolerance}"
        )));
    }
    let tracer = BeamTracer::new(scene, options, tolerance)?;
    let tiles = tracer.tiles();
    let threads = super::requested_threads(options).clamp(1, tiles.len().max(1));
    let pool = super::thread_pool(threads)?;
    let start = Instant::now();
    type Traced = Option<Result<(TileImage, Stats), crate::integrator::beam::BeamError>>;
    let traced: Vec<Traced> = pool.install(|| {
        tiles
            .par_iter()
            .map(|&tile| {
                if cancel.load(Ordering::Relaxed) {
                    return None;
                }
                let mut stats = Stats::default();
                let result = tracer.trace_tile(tile, &mut stats);
                if let Ok(image) = &result {
                    on_tile(TileDone {
                        pixels: (image.width * image.height) as u64,
                        rays: stats.total_rays(),
                    });
                }
                Some(result.map(|image| (image, stats)))
            })
            .collect()
    });
    let (width, height) = (options.width, options.height);
    let n = width as usize * height as usize;
    let mut film = Film::new(width, height);
    let mut coverage = vec![0.0; n];
    let mut bound = vec![0.0; n];
    let mut stats = Stats::default();
    let mut deepest = 0;
    let mut complete = true;
    for t in traced {
        let Some(result) = t else {
            complete = false;
            continue;
        };
        let (image, tile_stats) = result?;
        stats += tile_stats;
        stats.beams += image.beams;
        stats.beam_fragments += image.fragments;
        stats.beam_pieces += image.pieces;
        deepest = deepest.max(image.deepest);
        for ly in 0..image.height {
            for lx in 0..image.width {
                let src = (ly * image.width + lx) as usize;
                let dst = (image.y0 + ly) as usize * width as usize + (image.x0 + lx) as usize;
                let c = image.colors[src];
                film.pixels[dst] = Color::new(c.x as f32, c.y as f32, c.z as f32);
                coverage[dst] = image.coverage[src];
                bound[dst] = image.bound[src];
            }
        }
    }
    film.transfer = options.transfer;
    Ok(BeamRender {
        film,
        coverage,
        bound,
        stats,
        deepest,
        complete,
        render_time: start.elapsed(),
    })
}
