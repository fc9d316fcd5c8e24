//! Rendering with a per-pixel pattern: tiles over the thread pool, every pixel tracing its
//! own samples. With the one-pixel box filter a pixel is the plain mean of its samples,
//! summed in sample order (the renderer's original arithmetic, bit for bit); any other
//! filter splats the samples into a buffer with a margin, merged exactly into the film.
//!
//! With packets on, a tile is traced in blocks of `PACKET_EDGE` × `PACKET_EDGE` pixels:
//! the camera rays of a block's pixels for one sample index find their first hits as one
//! packet, then each is shaded on its own. Every sample's value is the one a single ray
//! gives, and pixels still sum their samples in sample order, so the image is the same.
//! Tiles are whole blocks (`RenderOptions::effective_tile_size`), so the blocks, and the
//! statistics, do not depend on the tile size.

use super::packet::trace_packet;
use super::rays::{PixelRays, RayMark};
use super::splat::{FilmSums, SplatBuffer};
use super::{tiles, Film, Job, PixelSamples, RenderError, Tile, TileDone, Traced};
use crate::accel::PACKET_MAX;
use crate::integrator::CameraBatch;
use crate::math::{Color, Vec2};
use crate::options::PACKET_EDGE;
use crate::stats::Stats;
use rayon::iter::{ParallelBridge, ParallelIterator};
use std::sync::Mutex;

pub(super) fn render(
    job: &Job,
    pattern: &dyn PixelSamples,
    tile_size: u32,
) -> Result<Traced, RenderError> {
    let (width, height) = (job.width, job.height);
    let area = job.area;
    let local = job.filter.is_pixel_box();
    // A wider filter spreads the samples of pixels around the area into it, so those are
    // traced too. Tiles stay on the whole image's grid, clipped, so the packets' blocks
    // are the ones a whole render traces.
    let traced = if local {
        area
    } else {
        area.grown(job.filter.radius.ceil() as u32, width, height)
    };
    let tile_list: Vec<Tile> = tiles(width, height, tile_size)
        .iter()
        .filter_map(|t| t.intersection(&traced))
        .collect();
    let (aw, ah) = (area.width(), area.height());
    // Only a filter wider than the pixel needs the traced area's sums; the box filter's
    // pixels go straight into the film.
    let (mut out, sums) = if local {
        (Traced::try_new(job, aw, ah, Film::try_new(aw, ah)?)?, None)
    } else {
        let sums = Mutex::new(FilmSums::try_new(traced)?);
        (
            Traced::try_new(job, aw, ah, Film::unallocated(aw, ah))?,
            Some(sums),
        )
    };
    let count = pattern.count();
    let mean_weight = 1.0 / count as f32;

    // Each tile's pixels go into the output as soon as it is done (a tile at a time under
    // the lock), rather than every tile's being kept until the last is: on a large image
    // those copies doubled the memory a render writes for the first time, and fresh pages
    // cost a page fault each (about 1.6 µs per 4 KiB on a virtual machine).
    let merged = Mutex::new(&mut out);
    let merge = || merged.lock().unwrap_or_else(|e| e.into_inner());
    let unfinished = || merge().complete = false;
    // The bottom of the lowest finished tile: rows below it hold no work.
    let reached = std::sync::atomic::AtomicU32::new(0);
    // Tiles are handed out in row-major order (not split in halves as a parallel slice
    // is), so that a cancelled render has finished a band of rows from the top.
    tile_list.iter().par_bridge().for_each(|tile| {
        if job.cancelled() {
            unfinished();
            return;
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
        if job.packets {
            let traced = if job.tracer.traces_batches() {
                trace_batch(job, pattern, tile, &mut buffer, &mut stats)
            } else {
                trace_packets(job, pattern, tile, &mut buffer, &mut stats)
            };
            let Some((m, r)) = traced else {
                unfinished();
                return;
            };
            (means, rays) = (m, r);
            if !local {
                means.clear();
            }
            for m in &mut means {
                *m *= mean_weight;
            }
        } else {
            for y in tile.y0..tile.y1 {
                // A row at a time, so that a cancel answers at once even in large tiles.
                if job.cancelled() {
                    unfinished();
                    return;
                }
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
        }
        if let (Some(b), Some(sums)) = (&buffer, &sums) {
            sums.lock().unwrap_or_else(|e| e.into_inner()).merge(b);
        }
        reached.fetch_max(tile.y1, std::sync::atomic::Ordering::Relaxed);
        (job.on_tile)(TileDone {
            pixels: tile.pixel_count(),
            rays: stats.total_rays(),
        });
        let mut out = merge();
        out.stats += stats;
        let mut means = means.into_iter();
        let mut rays = rays.iter();
        for y in tile.y0..tile.y1 {
            for x in tile.x0..tile.x1 {
                let mean = if local { means.next() } else { None };
                let ray = rays.next();
                // Pixels of the filter's margin were traced for their samples only.
                if x < area.x0 || x >= area.x1 || y < area.y0 || y >= area.y1 {
                    continue;
                }
                let (ax, ay) = (x - area.x0, y - area.y0);
                if let Some(m) = mean {
                    out.film.set(ax, ay, m);
                }
                if let Some(&r) = ray {
                    out.rays.add(ax, ay, r);
                }
            }
        }
    });
    out.rows_reached = Some(job.rows_reached(area, reached.into_inner()));
    if let Some(sums) = sums {
        out.film = sums
            .into_inner()
            .unwrap_or_else(|e| e.into_inner())
            .into_film(area)?;
    }
    Ok(out)
}

/// Traces `tile` block by block with packets of camera rays; returns per pixel (row-major
/// in the tile) the sum of its samples in sample order (unused when `buffer` takes the
/// samples) and its rays, the packets' shared traversal split evenly among their pixels
/// (no rays when the render keeps no per-pixel counts). None when the render was
/// cancelled before the tile was done.
fn trace_packets(
    job: &Job,
    pattern: &dyn PixelSamples,
    tile: &Tile,
    buffer: &mut Option<SplatBuffer>,
    stats: &mut Stats,
) -> Option<(Vec<Color>, Vec<PixelRays>)> {
    let width = (tile.x1 - tile.x0) as usize;
    let pixels = tile.pixel_count() as usize;
    let mut sums = vec![Color::ZERO; pixels];
    // Counted only where they are kept: sharing each packet's work among its pixels
    // took a few percent of a whole render of a small scene.
    let recorded = job.per_pixel_rays;
    let mut rays = vec![PixelRays::default(); if recorded { pixels } else { 0 }];
    let count = pattern.count() as usize;
    let edge = PACKET_EDGE as usize;
    let mut offsets: Vec<Vec2> = Vec::with_capacity(count);
    // Per block pixel: its position, its samples' offsets and colours.
    let mut block: Vec<(u32, u32)> = Vec::with_capacity(PACKET_MAX);
    let mut block_offsets: Vec<Vec2> = Vec::with_capacity(PACKET_MAX * count);
    let mut colors: Vec<Color> = vec![Color::ZERO; PACKET_MAX * count];
    for by in (tile.y0..tile.y1).step_by(edge) {
        // A row of blocks at a time, so that a cancel answers at once even in large tiles.
        if job.cancelled() {
            return None;
        }
        for bx in (tile.x0..tile.x1).step_by(edge) {
            block.clear();
            block_offsets.clear();
            for y in by..(by + PACKET_EDGE).min(tile.y1) {
                for x in bx..(bx + PACKET_EDGE).min(tile.x1) {
                    block.push((x, y));
                    offsets.clear();
                    pattern.offsets(x, y, &mut offsets);
                    block_offsets.extend_from_slice(&offsets);
                }
            }
            let n = block.len();
            let local = |x: u32, y: u32| (y - tile.y0) as usize * width + (x - tile.x0) as usize;
            let mut at = [Vec2::ZERO; PACKET_MAX];
            let mut shaded = [Color::ZERO; PACKET_MAX];
            let mut work = [PixelRays::default(); PACKET_MAX];
            let work = if recorded { &mut work[..n] } else { &mut [] };
            for s in 0..count {
                for (i, &(x, y)) in block.iter().enumerate() {
                    let o = block_offsets[i * count + s];
                    at[i] = Vec2::new(x as f32 + o.x, y as f32 + o.y);
                }
                work.fill(PixelRays::default());
                trace_packet(job, &at[..n], &mut shaded, work, stats);
                for (i, &c) in shaded[..n].iter().enumerate() {
                    colors[i * count + s] = c;
                }
                for (&(x, y), &w) in block.iter().zip(work.iter()) {
                    rays[local(x, y)] += w;
                }
            }
            let traced = Samples::new(&block, &block_offsets, &colors, count);
            traced.add(job, buffer, &mut sums, local);
        }
    }
    Some((sums, rays))
}

/// Samples at most in one batch of `trace_batch` (but whole blocks): about 2 MiB of
/// positions, colours and order per thread however large the tile or the sample count,
/// and far more than the wavefront's queue holds, so that it stays full.
const BATCH_SAMPLES: usize = 1 << 16;

/// Traces `tile`'s samples as batches (`CameraTracer::trace_camera_batch`) of whole
/// blocks, at most `BATCH_SAMPLES` samples unless one block has more, in the packets'
/// order: block by block, sample index by sample index, so that the camera rays the
/// batch takes together are a packet's. Returns what `trace_packets` returns; a batch's
/// traversal work is shared evenly among its samples. None when the render was cancelled
/// before the tile was done.
fn trace_batch(
    job: &Job,
    pattern: &dyn PixelSamples,
    tile: &Tile,
    buffer: &mut Option<SplatBuffer>,
    stats: &mut Stats,
) -> Option<(Vec<Color>, Vec<PixelRays>)> {
    let width = (tile.x1 - tile.x0) as usize;
    let pixels = tile.pixel_count() as usize;
    let count = pattern.count() as usize;
    let edge = PACKET_EDGE as usize;
    let local = |x: u32, y: u32| (y - tile.y0) as usize * width + (x - tile.x0) as usize;
    let blocks: Vec<(u32, u32)> = (tile.y0..tile.y1)
        .step_by(edge)
        .flat_map(|by| (tile.x0..tile.x1).step_by(edge).map(move |bx| (bx, by)))
        .collect();
    let per_batch = (BATCH_SAMPLES / (PACKET_MAX * count)).max(1);
    let mut sums = vec![Color::ZERO; pixels];
    let mut rays = vec![PixelRays::default(); pixels];
    let mut one: Vec<Vec2> = Vec::with_capacity(count);
    for batch in blocks.chunks(per_batch) {
        // The batch's pixels in block order with their samples' offsets; per sample of
        // the batch, its pixel (in `at`) and its index in the pixel.
        let mut at: Vec<(u32, u32)> = Vec::with_capacity(batch.len() * PACKET_MAX);
        let mut offsets: Vec<Vec2> = Vec::with_capacity(batch.len() * PACKET_MAX * count);
        let mut order: Vec<(u32, u32)> = Vec::with_capacity(batch.len() * PACKET_MAX * count);
        for &(bx, by) in batch {
            let first = at.len();
            for y in by..(by + PACKET_EDGE).min(tile.y1) {
                for x in bx..(bx + PACKET_EDGE).min(tile.x1) {
                    at.push((x, y));
                    one.clear();
                    pattern.offsets(x, y, &mut one);
                    offsets.extend_from_slice(&one);
                }
            }
            for s in 0..count as u32 {
                order.extend((first..at.len()).map(|p| (p as u32, s)));
            }
        }
        let position = |i: usize| {
            let (p, s) = order[i];
            let (x, y) = at[p as usize];
            let o = offsets[p as usize * count + s as usize];
            Vec2::new(x as f32 + o.x, y as f32 + o.y)
        };
        let mut colors = vec![Color::ZERO; at.len() * count];
        let before = RayMark::of(stats);
        let mut cancelled = false;
        let batch = CameraBatch {
            count: order.len(),
            sample: &mut |i| {
                // Asked at every sample, so that a cancel answers at once in any tile.
                if job.cancelled() {
                    cancelled = true;
                    return None;
                }
                let film = position(i);
                Some((job.camera.ray(film.x, film.y), job.stream(film.x, film.y)))
            },
            done: &mut |i, color, spawned| {
                let (p, s) = order[i];
                colors[p as usize * count + s as usize] = color;
                let (x, y) = at[p as usize];
                let r = &mut rays[local(x, y)];
                r.camera += 1;
                r.total += 1 + spawned;
            },
        };
        job.tracer.trace_camera_batch(batch, stats);
        if cancelled {
            return None;
        }
        let shared = PixelRays::since(before, stats);
        let n = order.len();
        for (i, &(p, _)) in order.iter().enumerate() {
            let mut work = shared.share(i, n);
            (work.camera, work.total) = (0, 0);
            let (x, y) = at[p as usize];
            rays[local(x, y)] += work;
        }
        // In the packets' order of blocks, as `trace_packets` adds them, so that a wide
        // filter's sums are the same too.
        Samples::new(&at, &offsets, &colors, count).add(job, buffer, &mut sums, local);
    }
    Some((sums, rays))
}

/// The traced samples of some pixels: pixel p's `count` samples at
/// `offsets[p * count..][..count]` came out as `colors[p * count..][..count]`.
struct Samples<'a> {
    pixels: &'a [(u32, u32)],
    offsets: &'a [Vec2],
    colors: &'a [Color],
    count: usize,
}

impl<'a> Samples<'a> {
    fn new(
        pixels: &'a [(u32, u32)],
        offsets: &'a [Vec2],
        colors: &'a [Color],
        count: usize,
    ) -> Self {
        Samples {
            pixels,
            offsets,
            colors,
            count,
        }
    }

    /// Adds each pixel's samples in sample order, as the single-ray path sums them: to its
    /// sum in `sums` (at `local(x, y)`), or with a wide filter into the splat buffer pixel
    /// by pixel in the order of `pixels`.
    fn add(
        &self,
        job: &Job,
        buffer: &mut Option<SplatBuffer>,
        sums: &mut [Color],
        local: impl Fn(u32, u32) -> usize,
    ) {
        let count = self.count;
        for (p, &(x, y)) in self.pixels.iter().enumerate() {
            let samples = &self.colors[p * count..(p + 1) * count];
            match buffer {
                Some(b) => {
                    for (s, &c) in samples.iter().enumerate() {
                        b.add(&job.filter, x, y, self.offsets[p * count + s], 1.0, c);
                    }
                }
                None => {
                    let sum = &mut sums[local(x, y)];
                    for &c in samples {
                        *sum += c;
                    }
                }
            }
        }
    }
}
