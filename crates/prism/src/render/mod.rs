//! Rendering: the image is cut into square tiles that a rayon pool renders in any order.
//! Each pixel depends only on (scene, options, pixel), and tiles are written back by
//! position, so the image and the statistics are identical for every thread count.

mod film;

pub use film::Film;

use crate::camera::CameraError;
use crate::integrator::Whitted;
use crate::options::RenderOptions;
use crate::scene::PreparedScene;
use crate::stats::Stats;
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// A rectangle of pixels `[x0, x1) × [y0, y1)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Tile {
    pub x0: u32,
    pub y0: u32,
    pub x1: u32,
    pub y1: u32,
}

impl Tile {
    pub fn pixel_count(&self) -> u64 {
        (self.x1 - self.x0) as u64 * (self.y1 - self.y0) as u64
    }
}

/// Tiles in row-major order covering a width × height image.
pub fn tiles(width: u32, height: u32, size: u32) -> Vec<Tile> {
    let mut out = Vec::new();
    for y0 in (0..height).step_by(size as usize) {
        for x0 in (0..width).step_by(size as usize) {
            out.push(Tile {
                x0,
                y0,
                x1: (x0 + size).min(width),
                y1: (y0 + size).min(height),
            });
        }
    }
    out
}

/// What a finished tile reports to a progress display.
#[derive(Clone, Copy, Debug)]
pub struct TileDone {
    pub pixels: u64,
    pub rays: u64,
}

pub struct RenderResult {
    pub film: Film,
    pub stats: Stats,
    /// False when the render was cancelled; unrendered tiles are black.
    pub complete: bool,
    pub render_time: Duration,
}

#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    #[error("invalid options: {0}")]
    Options(String),
    #[error(transparent)]
    Camera(#[from] CameraError),
    #[error("cannot start {threads} worker threads: {message}")]
    Threads { threads: usize, message: String },
}

/// Renders `scene` with `options`. `on_tile` is called (from worker threads) after each
/// tile; setting `cancel` stops the render after the tiles in flight.
pub fn render(
    scene: &PreparedScene,
    options: &RenderOptions,
    on_tile: &(dyn Fn(TileDone) + Sync),
    cancel: &AtomicBool,
) -> Result<RenderResult, RenderError> {
    options.validate().map_err(RenderError::Options)?;
    let camera = scene.scene.camera.setup(options.width, options.height)?;
    let integrator = Whitted::new(scene, options);
    let n = options.samples;
    let inv_n = 1.0 / n as f32;
    let sample_weight = 1.0 / (n * n) as f32;
    let tile_list = tiles(options.width, options.height, options.tile_size);

    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(options.threads)
        .build()
        .map_err(|e| RenderError::Threads {
            threads: options.threads,
            message: e.to_string(),
        })?;

    let start = Instant::now();
    let results: Vec<Option<(Vec<crate::math::Color>, Stats)>> = pool.install(|| {
        tile_list
            .par_iter()
            .map(|tile| {
                if cancel.load(Ordering::Relaxed) {
                    return None;
                }
                let mut stats = Stats::default();
                let mut pixels = Vec::with_capacity(tile.pixel_count() as usize);
                for y in tile.y0..tile.y1 {
                    for x in tile.x0..tile.x1 {
                        let mut sum = crate::math::Color::ZERO;
                        for j in 0..n {
                            for i in 0..n {
                                let fx = x as f32 + (i as f32 + 0.5) * inv_n;
                                let fy = y as f32 + (j as f32 + 0.5) * inv_n;
                                let ray = camera.ray(fx, fy);
                                sum += integrator.trace_camera_ray(&ray, &mut stats);
                            }
                        }
                        pixels.push(sum * sample_weight);
                    }
                }
                on_tile(TileDone {
                    pixels: tile.pixel_count(),
                    rays: stats.total_rays(),
                });
                Some((pixels, stats))
            })
            .collect()
    });
    let render_time = start.elapsed();

    let mut film = Film::new(options.width, options.height);
    let mut stats = Stats::default();
    let mut complete = true;
    for (tile, result) in tile_list.iter().zip(results) {
        let Some((pixels, tile_stats)) = result else {
            complete = false;
            continue;
        };
        stats += tile_stats;
        let mut it = pixels.into_iter();
        for y in tile.y0..tile.y1 {
            for x in tile.x0..tile.x1 {
                film.set(x, y, it.next().unwrap_or_default());
            }
        }
    }
    Ok(RenderResult {
        film,
        stats,
        complete,
        render_time,
    })
}
