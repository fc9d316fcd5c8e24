//! Rendering with lattice patterns, whose samples neighbouring pixels share: `corners`
//! (every pixel corner plus every centre) and `adaptive` (corners refined where they
//! differ). Points sit on a lattice of 2^depth steps per pixel; each is owned, traced and
//! stored by the one pixel whose half-open square holds it, so every point is traced
//! exactly once and the ray counts do not depend on how the work is cut up.
//!
//! The work runs in passes over pixel rows, each pass reading only what earlier passes
//! stored: the corners; then, per level, the points of the squares that split at that
//! level (a pixel also traces the midpoints on its left and top edges when the neighbour
//! across the edge splits there; a textured pixel traces its stratified samples, which
//! are its own, in the first of these passes); then the reconstruction, which splats each
//! pixel's samples through the filter.
//!
//! No decision is made twice: each pixel's verdict is judged once, after the corners pass,
//! and each refinement pass walks each pixel once, from the squares that split in the pass
//! before, storing what it finds for the pixel's right and bottom neighbours too.

use super::memory::try_filled;
use super::rays::PixelRays;
use super::splat::{FilmSums, SplatBuffer};
use super::{Film, Job, RenderError, TileDone, Traced};
use crate::math::{Color, Vec2};
use crate::sampling::adaptive::{Refinement, Square, Verdict, Visit};
use crate::stats::Stats;
use rayon::prelude::*;
use std::sync::Mutex;

/// Progress passes of each pattern, for the progress total.
pub(super) fn passes(depth: Option<u32>) -> u64 {
    match depth {
        None => 3,
        Some(d) => d as u64 + 2,
    }
}

/// Traced lattice points: the pixel corners densely, finer points per owning pixel.
struct Lattice {
    width: u32,
    height: u32,
    steps: u32,
    /// log2 of `steps` (a power of two): lookups, which every walk makes for every square,
    /// shift and mask instead of dividing.
    shift: u32,
    /// (W+1)×(H+1) corners; None where the render was cancelled first.
    corners: Vec<Option<Color>>,
    /// Per pixel, its finer points sorted by local key.
    points: Vec<PixelPoints>,
    /// Per pixel, the colours of its stratified samples in sample order (textured pixels).
    stratified: Vec<Vec<Color>>,
}

impl Lattice {
    fn try_new(width: u32, height: u32, steps: u32) -> Result<Self, RenderError> {
        debug_assert!(steps.is_power_of_two());
        let pixels = width as usize * height as usize;
        let corners = (width as usize + 1) * (height as usize + 1);
        Ok(Lattice {
            width,
            height,
            steps,
            shift: steps.trailing_zeros(),
            corners: try_filled(corners, None, "sample lattice")?,
            points: try_filled(pixels, Vec::new(), "sample lattice")?,
            stratified: try_filled(pixels, Vec::new(), "sample lattice")?,
        })
    }

    /// The pixel that traces and stores lattice point (x, y): the one whose half-open
    /// square holds it; the last column and row also own the image's right and bottom edges.
    fn owner(&self, x: u32, y: u32) -> (u32, u32) {
        (
            (x >> self.shift).min(self.width - 1),
            (y >> self.shift).min(self.height - 1),
        )
    }

    fn local_key(&self, x: u32, y: u32, owner: (u32, u32)) -> u32 {
        (y - owner.1 * self.steps) << 16 | (x - owner.0 * self.steps)
    }

    fn lookup(&self, x: u32, y: u32) -> Option<Color> {
        let (s, shift) = (self.steps, self.shift);
        if x > self.width * s || y > self.height * s {
            return None;
        }
        if (x | y) & (s - 1) == 0 {
            return self.corners[((y >> shift) * (self.width + 1) + (x >> shift)) as usize];
        }
        let owner = self.owner(x, y);
        let key = self.local_key(x, y, owner);
        let list = &self.points[(owner.1 * self.width + owner.0) as usize];
        list.binary_search_by_key(&key, |&(k, _)| k)
            .ok()
            .map(|i| list[i].1)
    }

    /// Offset of lattice point (x, y) within pixel (px, py), in pixels.
    fn offset(&self, x: f32, y: f32, px: u32, py: u32) -> Vec2 {
        let s = self.steps as f32;
        Vec2::new(
            (x - (px * self.steps) as f32) / s,
            (y - (py * self.steps) as f32) / s,
        )
    }
}

/// The points one pixel traced in a pass: (local key, colour).
type PixelPoints = Vec<(u32, Color)>;

/// What one row traced in a refinement pass, flat (one allocation per row, not two per
/// pixel): pixel x's lattice points are `points[point_start[x]..point_start[x + 1]]`, its
/// stratified samples `samples[sample_start[x]..sample_start[x + 1]]`.
#[derive(Default)]
struct RowRefinement {
    points: PixelPoints,
    point_start: Vec<u32>,
    samples: Vec<Color>,
    sample_start: Vec<u32>,
}

/// One row's output of a tracing pass.
struct RowTrace<T> {
    values: T,
    stats: Stats,
    rays: Vec<PixelRays>,
}

pub(super) fn render_corners(job: &Job) -> Result<Traced, RenderError> {
    let (w, h) = (job.width, job.height);
    let mut out = Traced::try_new(w, h, Film::unallocated(w, h))?;
    let mut lattice = Lattice::try_new(w, h, 1)?;
    let mut centres = try_filled(w as usize * h as usize, None, "sample lattice")?;
    if trace_corners(job, &mut lattice, |x, y| (x as f32, y as f32), &mut out) {
        trace_centres(job, &mut centres, &mut out);
    }
    let film = reconstruct(job, |buffer, x, y| {
        if let Some(c) = centres[(y * job.width + x) as usize] {
            buffer.add(&job.filter, x, y, Vec2::splat(0.5), 1.0, c);
        }
        // The corners this pixel owns: its top-left one, and along the image's right and
        // bottom edges the ones beyond.
        let xs = if x + 1 == job.width { x..=x + 1 } else { x..=x };
        for j in if y + 1 == job.height {
            y..=y + 1
        } else {
            y..=y
        } {
            for i in xs.clone() {
                if let Some(c) = lattice.lookup(i, j) {
                    let o = Vec2::new((i - x) as f32, (j - y) as f32);
                    buffer.add(&job.filter, x, y, o, 1.0, c);
                }
            }
        }
    });
    out.film = film?;
    Ok(out)
}

pub(super) fn render_adaptive(job: &Job, rule: &Refinement) -> Result<Traced, RenderError> {
    let (w, h) = (job.width, job.height);
    let mut out = Traced::try_new(w, h, Film::unallocated(w, h))?;
    let mut lattice = Lattice::try_new(w, h, rule.steps())?;
    let complete = trace_corners(job, &mut lattice, |x, y| rule.position(x, y), &mut out);
    // The corners never change after their pass, so neither do the pixels' verdicts.
    let judged = Judged::new(job, rule, &lattice);
    if complete {
        let mut frontiers = Vec::new();
        for level in 0..rule.depth {
            frontiers = find_frontiers(&judged, &lattice, level, &frontiers);
            if !refine(job, &judged, &mut lattice, level, &frontiers, &mut out) {
                break;
            }
        }
    }
    let steps = rule.steps();
    // Pixel (x, y)'s samples: (offset in the pixel, weight, colour) in walk order.
    let samples = |x: u32, y: u32, add: &mut dyn FnMut(Vec2, f32, Color)| {
        let lookup = |lx: u32, ly: u32| lattice.lookup(lx, ly);
        let stratified = &lattice.stratified[(y * job.width + x) as usize];
        let mut offsets = Vec::new();
        judged.walk(x, y, rule.depth, &lookup, &mut |sq, visit| {
            let c = match visit {
                Visit::Stratified(_) if !stratified.is_empty() => {
                    // Each sample stands for its stratum: an equal share of the pixel.
                    offsets.clear();
                    rule.texture_offsets(x, y, &mut offsets);
                    let weight = 1.0 / stratified.len() as f32;
                    for (&o, &c) in offsets.iter().zip(stratified) {
                        add(o, weight, c);
                    }
                    return;
                }
                Visit::Leaf(c) | Visit::Frontier(c) | Visit::Stratified(c) => c,
                Visit::Split | Visit::Missing => return,
            };
            // A square that does not split (or whose split or stratified pass was never
            // traced) is worth the mean of its corners over its area.
            let mean = (c[0] + c[1] + c[2] + c[3]) * 0.25;
            let half = sq.size as f32 * 0.5;
            let o = lattice.offset(sq.x as f32 + half, sq.y as f32 + half, x, y);
            let side = sq.size as f32 / steps as f32;
            add(o, side * side, mean);
        });
    };
    let film = if job.filter.covers_one_pixel() {
        own_pixels(job, samples)
    } else {
        reconstruct(job, |buffer, x, y| {
            samples(x, y, &mut |o, weight, c| {
                buffer.add(&job.filter, x, y, o, weight, c)
            })
        })?
    };
    out.film = film;
    Ok(out)
}

/// The refinement rule with every pixel's verdict judged once, after the corners pass: the
/// neighbourhood rule reads 16 corners per pixel, and the passes walk each pixel again.
struct Judged<'a> {
    rule: &'a Refinement,
    width: u32,
    /// Per pixel; None where one of its corners was not traced.
    verdicts: Vec<Option<Verdict>>,
}

impl<'a> Judged<'a> {
    fn new(job: &Job, rule: &'a Refinement, lattice: &Lattice) -> Self {
        let (w, steps) = (job.width, lattice.steps);
        // Each corner encoded once: a pixel's verdict compares 16 of them.
        let encoded: Vec<_> = (lattice.corners.par_iter())
            .map(|c| c.map(|c| rule.encode(c)))
            .collect();
        let shift = lattice.shift;
        let lookup = |x: u32, y: u32| {
            // Only pixel corners are asked for: multiples of `steps`, a power of two.
            let (i, j) = (x >> shift, y >> shift);
            if i > w || j > job.height {
                return None;
            }
            encoded[(j * (w + 1) + i) as usize]
        };
        let rows: Vec<Vec<Option<Verdict>>> = (0..job.height)
            .into_par_iter()
            .map(|y| {
                (0..w)
                    .map(|x| rule.verdict(&Square::pixel(x, y, steps), &lookup))
                    .collect()
            })
            .collect();
        Judged {
            rule,
            width: w,
            verdicts: rows.concat(),
        }
    }

    /// Whether pixel (x, y) is textured (false where not judged).
    fn textured(&self, x: u32, y: u32) -> bool {
        self.verdicts[(y * self.width + x) as usize].is_some_and(|v| v.textured)
    }

    /// `Refinement::walk` of pixel (x, y).
    fn walk(
        &self,
        x: u32,
        y: u32,
        max_level: u32,
        lookup: &impl Fn(u32, u32) -> Option<Color>,
        visit: &mut impl FnMut(Square, Visit),
    ) {
        let pixel = Square::pixel(x, y, self.rule.steps());
        match self.verdicts[(y * self.width + x) as usize] {
            Some(verdict) => self
                .rule
                .walk_judged(pixel, verdict, max_level, lookup, visit),
            None => self.rule.walk(pixel, max_level, lookup, visit),
        }
    }
}

/// What one row's walks find at a refinement pass's level: per pixel, the squares that
/// split there (the pass traces their new points) and whether the pixel takes the
/// stratified pass. One list per row, not per pixel: a pass over a large image would
/// otherwise allocate (and the kernel zero) a vector per pixel.
#[derive(Default)]
struct RowFrontier {
    splits: Vec<Square>,
    /// Pixel x's splits are `splits[start[x]..start[x + 1]]`.
    start: Vec<u32>,
    stratified: Vec<bool>,
}

impl RowFrontier {
    fn splits(&self, x: u32) -> &[Square] {
        &self.splits[self.start[x as usize] as usize..self.start[x as usize + 1] as usize]
    }

    fn stratified(&self, x: u32) -> bool {
        self.stratified[x as usize]
    }
}

/// Per row and pixel, the squares that split at `level`, found once per pass (a pixel's
/// pass also needs its left and top neighbours'). Below the pixel only the quarters of
/// the squares that split one level up (`above`, from the pass before, whose points are
/// all traced) are new: the levels above would be walked to the same decisions.
fn find_frontiers(
    judged: &Judged,
    lattice: &Lattice,
    level: u32,
    above: &[RowFrontier],
) -> Vec<RowFrontier> {
    let lookup = |x: u32, y: u32| lattice.lookup(x, y);
    (0..lattice.height)
        .into_par_iter()
        .map(|y| {
            let w = lattice.width as usize;
            let mut row = RowFrontier {
                splits: Vec::new(),
                start: Vec::with_capacity(w + 1),
                stratified: Vec::with_capacity(w),
            };
            for x in 0..lattice.width {
                row.start.push(row.splits.len() as u32);
                let mut stratified = false;
                let mut visit = |sq: Square, v| {
                    if matches!(v, Visit::Frontier(_)) && sq.level == level {
                        row.splits.push(sq);
                    }
                    stratified |= matches!(v, Visit::Stratified(_));
                };
                if level == 0 {
                    judged.walk(x, y, level, &lookup, &mut visit);
                } else {
                    let textured = judged.textured(x, y);
                    for parent in above[y as usize].splits(x) {
                        for child in parent.children() {
                            judged
                                .rule
                                .walk_below(child, textured, level, &lookup, &mut visit);
                        }
                    }
                }
                row.stratified.push(stratified);
            }
            row.start.push(row.splits.len() as u32);
            row
        })
        .collect()
}

/// Traces the (W+1)×(H+1) pixel corners, each at `position` (lattice units) of its
/// lattice coordinates; false if cancelled.
fn trace_corners(
    job: &Job,
    lattice: &mut Lattice,
    position: impl Fn(u32, u32) -> (f32, f32) + Sync,
    out: &mut Traced,
) -> bool {
    let (w, h) = (job.width, job.height);
    let steps = lattice.steps;
    let s = steps as f32;
    let rows: Vec<Option<RowTrace<Vec<Color>>>> = (0..=h)
        .into_par_iter()
        .map(|j| {
            if job.cancelled() {
                return None;
            }
            crate::integrator::begin_piece();
            let mut stats = Stats::default();
            let mut values = Vec::with_capacity(w as usize + 1);
            let mut rays = vec![PixelRays::default(); w as usize];
            for i in 0..=w {
                let before = stats;
                let (fx, fy) = position(i * steps, j * steps);
                values.push(job.trace(fx / s, fy / s, &mut stats));
                rays[i.min(w - 1) as usize] += PixelRays::between(&before, &stats);
            }
            (job.on_tile)(TileDone {
                pixels: if j < h { w as u64 } else { 0 },
                rays: stats.total_rays(),
            });
            Some(RowTrace {
                values,
                stats,
                rays,
            })
        })
        .collect();
    let mut complete = true;
    for (j, row) in rows.into_iter().enumerate() {
        let Some(row) = row else {
            complete = false;
            continue;
        };
        let start = j * (w as usize + 1);
        for (slot, c) in lattice.corners[start..].iter_mut().zip(row.values) {
            *slot = Some(c);
        }
        out.add_row(j.min(h as usize - 1) as u32, row.stats, &row.rays);
    }
    out.complete &= complete;
    complete
}

/// Traces every pixel centre (the corners pattern's own samples).
fn trace_centres(job: &Job, centres: &mut [Option<Color>], out: &mut Traced) {
    let w = job.width;
    let rows: Vec<Option<RowTrace<Vec<Color>>>> = (0..job.height)
        .into_par_iter()
        .map(|y| {
            if job.cancelled() {
                return None;
            }
            crate::integrator::begin_piece();
            let mut stats = Stats::default();
            let mut values = Vec::with_capacity(w as usize);
            let mut rays = Vec::with_capacity(w as usize);
            for x in 0..w {
                let before = stats;
                values.push(job.trace(x as f32 + 0.5, y as f32 + 0.5, &mut stats));
                rays.push(PixelRays::between(&before, &stats));
            }
            (job.on_tile)(TileDone {
                pixels: w as u64,
                rays: stats.total_rays(),
            });
            Some(RowTrace {
                values,
                stats,
                rays,
            })
        })
        .collect();
    for (y, row) in rows.into_iter().enumerate() {
        let Some(row) = row else {
            out.complete = false;
            continue;
        };
        let start = y * w as usize;
        for (slot, c) in centres[start..start + w as usize]
            .iter_mut()
            .zip(row.values)
        {
            *slot = Some(c);
        }
        out.add_row(y as u32, row.stats, &row.rays);
    }
}

/// One refinement pass: traces the new points of every square that splits at `level`
/// (`frontiers`) and, in the first pass, the samples of every textured pixel; false if
/// cancelled.
fn refine(
    job: &Job,
    judged: &Judged,
    lattice: &mut Lattice,
    level: u32,
    frontiers: &[RowFrontier],
    out: &mut Traced,
) -> bool {
    let rule = judged.rule;
    let (w, steps) = (job.width, lattice.steps);
    let shared = &*lattice;
    let rows: Vec<Option<RowTrace<RowRefinement>>> = (0..job.height)
        .into_par_iter()
        .map(|y| {
            if job.cancelled() {
                return None;
            }
            crate::integrator::begin_piece();
            let mut stats = Stats::default();
            let mut values = RowRefinement::default();
            let mut rays = Vec::with_capacity(w as usize);
            let mut wanted: Vec<(u32, u32)> = Vec::new();
            let mut offsets: Vec<Vec2> = Vec::new();
            for x in 0..w {
                wanted.clear();
                let own = frontiers[y as usize].splits(x);
                for sq in own {
                    wanted.extend(sq.new_points());
                }
                stats.adaptive_splits += own.len() as u64;
                // Midpoints on this pixel's left and top edges are its own; the neighbour
                // across the edge may be the one that needs them.
                if x > 0 {
                    for sq in frontiers[y as usize].splits(x - 1) {
                        if sq.x + sq.size == x * steps {
                            wanted.push(sq.new_points()[3]);
                        }
                    }
                }
                if y > 0 {
                    for sq in frontiers[y as usize - 1].splits(x) {
                        if sq.y + sq.size == y * steps {
                            wanted.push(sq.new_points()[4]);
                        }
                    }
                }
                wanted.retain(|&(px, py)| shared.owner(px, py) == (x, y));
                wanted.sort_unstable();
                wanted.dedup();
                let before = stats;
                let s = steps as f32;
                values.point_start.push(values.points.len() as u32);
                for &(px, py) in &wanted {
                    let (fx, fy) = rule.position(px, py);
                    let c = job.trace(fx / s, fy / s, &mut stats);
                    values.points.push((shared.local_key(px, py, (x, y)), c));
                }
                offsets.clear();
                if frontiers[y as usize].stratified(x) && level == 0 {
                    stats.adaptive_stratified += 1;
                    rule.texture_offsets(x, y, &mut offsets);
                }
                values.sample_start.push(values.samples.len() as u32);
                for o in &offsets {
                    let c = job.trace(x as f32 + o.x, y as f32 + o.y, &mut stats);
                    values.samples.push(c);
                }
                rays.push(PixelRays::between(&before, &stats));
            }
            (job.on_tile)(TileDone {
                pixels: w as u64,
                rays: stats.total_rays(),
            });
            Some(RowTrace {
                values,
                stats,
                rays,
            })
        })
        .collect();
    let mut complete = true;
    for (y, row) in rows.into_iter().enumerate() {
        let Some(row) = row else {
            complete = false;
            continue;
        };
        let RowRefinement {
            points,
            mut point_start,
            samples,
            mut sample_start,
        } = row.values;
        point_start.push(points.len() as u32);
        sample_start.push(samples.len() as u32);
        for x in 0..w as usize {
            let i = y * w as usize + x;
            let new = &points[point_start[x] as usize..point_start[x + 1] as usize];
            if !new.is_empty() {
                let list = &mut lattice.points[i];
                list.extend_from_slice(new);
                list.sort_unstable_by_key(|&(k, _)| k);
            }
            let own = &samples[sample_start[x] as usize..sample_start[x + 1] as usize];
            if !own.is_empty() {
                lattice.stratified[i] = own.to_vec();
            }
        }
        out.add_row(y as u32, row.stats, &row.rays);
    }
    out.complete &= complete;
    complete
}

/// The reconstruction pass when every sample counts in its own pixel only (the box of
/// radius ½, the default): each pixel is the weighted mean of its samples, summed in the
/// order `samples` gives them, which is fixed, so the image does not depend on the
/// threads either; no fixed-point sums and no image-sized buffers are needed.
fn own_pixels(
    job: &Job,
    samples: impl Fn(u32, u32, &mut dyn FnMut(Vec2, f32, Color)) + Sync,
) -> super::Film {
    let w = job.width;
    let rows: Vec<Vec<Color>> = (0..job.height)
        .into_par_iter()
        .map(|y| {
            let row = (0..w)
                .map(|x| {
                    let (mut sum, mut total) = ([0.0f64; 3], 0.0f64);
                    samples(x, y, &mut |_, weight, c| {
                        let weight = weight as f64;
                        for (s, v) in sum.iter_mut().zip(c.to_array()) {
                            *s += weight * v as f64;
                        }
                        total += weight;
                    });
                    if total == 0.0 {
                        return Color::ZERO;
                    }
                    Color::from_array(sum.map(|s| (s / total) as f32))
                })
                .collect();
            (job.on_tile)(TileDone {
                pixels: w as u64,
                rays: 0,
            });
            row
        })
        .collect();
    let mut film = super::Film::new(w, job.height);
    film.pixels = rows.concat();
    film
}

/// The reconstruction pass: `splat` adds pixel (x, y)'s samples to a buffer covering its
/// row and the filter's reach; buffers merge exactly into the film.
fn reconstruct(
    job: &Job,
    splat: impl Fn(&mut SplatBuffer, u32, u32) + Sync,
) -> Result<Film, RenderError> {
    let (w, h) = (job.width, job.height);
    let sums = Mutex::new(FilmSums::try_new(w, h)?);
    (0..h).into_par_iter().for_each(|y| {
        let mut buffer = SplatBuffer::around(&job.filter, (w, h), 0, y, w, y + 1);
        for x in 0..w {
            splat(&mut buffer, x, y);
        }
        sums.lock()
            .unwrap_or_else(|e| e.into_inner())
            .merge(&buffer);
        (job.on_tile)(TileDone {
            pixels: w as u64,
            rays: 0,
        });
    });
    sums.into_inner()
        .unwrap_or_else(|e| e.into_inner())
        .into_film()
}
