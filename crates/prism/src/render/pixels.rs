//! Rendering with a per-pixel pattern: tiles over the thread pool, every pixel tracing its
//! own samples. With the one-pixel box filter a pixel is the plain mean of its samples,
//! summed in sample order (the renderer's original arithmetic, bit for bit); any other
//! filter splats the samples into a buffer with a margin, merged exactly into the film.

use super::rays::PixelRays;
use super::splat::{FilmSums, SplatBuffer};
use super::{tiles, Film, Job, RenderError, TileDone, Traced};
use crate::math::{Color, Vec2};
use crate::sampling::PixelPattern;
use crate::stats::Stats;
use rayon::prelude::*;
use std::sync::Mutex;

/// What one tile sends back: its pixels' means (box filter only), statistics and rays.
struct TileResult {
    means: Vec<Color>,
    stats: Stats,
    rays: Vec<PixelRays>,
}

pub(super) fn render(
    job: &Job,
    pattern: &PixelPattern,
    tile_size: u32,
) -> Result<Traced, RenderError> {
    let (width, height) = (job.width, job.height);
    let tile_list = tiles(width, height, tile_size);
    let local = job.filter.is_pixel_box();
    // Only a filter wider than the pixel needs the whole image's sums; the box filter's
    // pixels go straight into the film.
    let (mut out, sums) = if local {
        (
            Traced::try_new(width, height, Film::try_new(width, height)?)?,
            None,
        )
    } else {
        let sums = Mutex::new(FilmSums::try_new(width, height)?);
        (
            Traced::try_new(width, height, Film::unallocated(width, height))?,
            Some(sums),
        )
    };
    let count = pattern.count();
    let mean_weight = 1.0 / count as f32;

    let results: Vec<Option<TileResult>> = tile_list
        .par_iter()
        .map(|tile| {
            if job.cancelled() {
                return None;
            }
            crate::integrator::begin_piece();
            let mut stats = Stats::default();
            let mut means = Vec::new();
            let mut rays = Vec::with_capacity(tile.pixel_count() as usize);
            let mut buffer = (!local).then(|| {
                SplatBuffer::around(
                    &job.filter,
                    (width, height),
                    tile.x0,
                    tile.y0,
                    tile.x1,
                    tile.y1,
                )
            });
            let mut offsets: Vec<Vec2> = Vec::with_capacity(count as usize);
            for y in tile.y0..tile.y1 {
                for x in tile.x0..tile.x1 {
                    let before = stats;
                    offsets.clear();
                    pattern.offsets(x, y, &mut offsets);
                    let mut sum = Color::ZERO;
                    for &o in &offsets {
                        let c = job.trace(x as f32 + o.x, y as f32 + o.y, &mut stats);
                        match &mut buffer {
                            Some(b) => b.add(&job.filter, x, y, o, 1.0, c),
                            None => sum += c,
                        }
                    }
                    if local {
                        means.push(sum * mean_weight);
                    }
                    rays.push(PixelRays::between(&before, &stats));
                }
            }
            if let (Some(b), Some(sums)) = (&buffer, &sums) {
                sums.lock().unwrap_or_else(|e| e.into_inner()).merge(b);
            }
            (job.on_tile)(TileDone {
                pixels: tile.pixel_count(),
                rays: stats.total_rays(),
            });
            Some(TileResult { means, stats, rays })
        })
        .collect();

    let mut film = match sums {
        None => std::mem::replace(&mut out.film, Film::unallocated(width, height)),
        Some(sums) => sums
            .into_inner()
            .unwrap_or_else(|e| e.into_inner())
            .into_film()?,
    };
    for (tile, result) in tile_list.iter().zip(results) {
        let Some(r) = result else {
            out.complete = false;
            continue;
        };
        out.stats += r.stats;
        let mut means = r.means.into_iter();
        let mut rays = r.rays.iter();
        for y in tile.y0..tile.y1 {
            for x in tile.x0..tile.x1 {
                if local {
                    film.set(x, y, means.next().unwrap_or_default());
                }
                if let Some(&r) = rays.next() {
                    out.rays.add(x, y, r);
                }
            }
        }
    }
    out.film = film;
    Ok(out)
}
