//! Rendering with lattice patterns, whose samples neighbouring pixels share: `corners`
//! (every pixel corner plus every centre) and `adaptive` (corners refined where they
//! differ). Points sit on a lattice of 2^depth steps per pixel; each is owned by the one
//! pixel whose half-open square holds it, traced exactly once and its rays counted in
//! that pixel, so the ray counts do not depend on how the work is cut up.
//!
//! The work runs in passes over pixel rows, each pass reading only what earlier passes
//! stored. The corners pattern: the corners, the centres, the reconstruction. The adaptive
//! pattern: the (W+1)×(H+1) corners, then one refinement pass in two halves, the even rows
//! and then the odd ones. A pixel's quadtree is decided by the points of its own closed
//! square alone (and its verdict, by the corners around it), so the refinement pass walks
//! each pixel once, to its leaves, tracing each point the first time the pixel needs it,
//! and takes the pixel's value from the leaves at once. Only points on a pixel's edges are
//! shared, with one neighbour each: along a row, a pixel hands the points it traced on its
//! right edge to the next pixel; between rows, an even row records the points it traced on
//! its top and bottom edges, and the odd rows, which run after all even rows, read them.
//! Two rows that share an edge never run at the same time, so every point is still traced
//! once, for any thread count. A point traced for the neighbour that owns it counts in
//! the owner's rays, so the density view is the same as if every pixel traced its own.

use super::memory::try_filled;
use super::packet::trace_packet;
use super::rays::{PixelRays, RayMark};
use super::splat::{FilmSums, SplatBuffer};
use super::{Film, Job, RenderError, Tile, TileDone, Traced};
use crate::accel::PACKET_MAX;
use crate::math::{Color, Vec2};
use crate::sampling::adaptive::{
    Encoded, Point, PointSource, Refined, Refinement, Square, Verdict,
};
use crate::stats::Stats;
use rayon::prelude::*;
use std::sync::Mutex;

/// Progress passes of each pattern, for the progress total.
pub(super) fn passes(depth: Option<u32>) -> u64 {
    match depth {
        None => 3,
        Some(_) => 2,
    }
}

/// The (W+1)×(H+1) pixel corners, dense, and which rows of them were traced (a cancelled
/// render leaves some out).
struct Corners {
    width: u32,
    colours: Vec<Color>,
    traced: Vec<bool>,
}

impl Corners {
    fn try_new(width: u32, height: u32) -> Result<Self, RenderError> {
        let n = (width as usize + 1) * (height as usize + 1);
        Ok(Corners {
            width,
            colours: try_filled(n, Color::ZERO, "sample lattice")?,
            traced: try_filled(height as usize + 1, false, "sample lattice")?,
        })
    }

    fn index(&self, i: u32, j: u32) -> usize {
        j as usize * (self.width as usize + 1) + i as usize
    }

    /// Corner (i, j), in pixels, if its row was traced.
    fn get(&self, i: u32, j: u32) -> Option<Color> {
        self.traced[j as usize].then(|| self.colours[self.index(i, j)])
    }

    /// Whether every corner was traced.
    fn complete(&self) -> bool {
        self.traced.iter().all(|&t| t)
    }

    /// The rows of corners from the top traced without a gap: where a cancelled pass
    /// stopped, since rows are handed out from the top.
    fn rows_reached(&self) -> u32 {
        self.traced.iter().take_while(|&&t| t).count() as u32
    }
}

/// One row's output of a tracing pass.
struct RowTrace<T> {
    values: T,
    stats: Stats,
    rays: Vec<PixelRays>,
}

pub(super) fn render_corners(job: &Job) -> Result<Traced, RenderError> {
    let (w, h) = (job.width, job.height);
    let mut out = Traced::try_new(job, w, h, Film::unallocated(w, h))?;
    let mut corners = Corners::try_new(w, h)?;
    let mut centres = try_filled(w as usize * h as usize, None, "sample lattice")?;
    if trace_corners(job, &mut corners, 1, |x, y| (x as f32, y as f32), &mut out) {
        trace_centres(job, &mut centres, &mut out);
    } else {
        // Pixel row y holds corner row y's samples (and the centres none): the rows
        // above the first corner row not traced.
        out.rows_reached = Some(job.rows_reached(Tile::full(w, h), corners.rows_reached()));
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
                if let Some(c) = corners.get(i, j) {
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
    let steps = rule.steps();
    let mut out = Traced::try_new(job, w, h, Film::unallocated(w, h))?;
    let mut corners = Corners::try_new(w, h)?;
    let refine = trace_corners(
        job,
        &mut corners,
        steps,
        |x, y| rule.position(x, y),
        &mut out,
    );
    if !refine {
        // A pixel without its refinement is its four corners' mean, so it needs the
        // corner rows above and below it.
        let bottom = corners.rows_reached().saturating_sub(1);
        out.rows_reached = Some(job.rows_reached(Tile::full(w, h), bottom));
    }
    // Each corner encoded once: a pixel's verdict compares 16 of them, its walk 4.
    let mut encoded = try_filled(corners.colours.len(), [0.0; 3], "sample lattice")?;
    let row = w as usize + 1;
    (encoded.par_chunks_mut(row))
        .zip(corners.colours.par_chunks(row))
        .for_each(|(e, c)| {
            for (e, &c) in e.iter_mut().zip(c) {
                *e = rule.encode(c);
            }
        });
    let wide = !job.filter.covers_one_pixel();
    let pass = Refine {
        job,
        rule,
        corners: &corners,
        encoded: &encoded,
        steps,
        wide,
        refine,
    };
    let mut film = if wide {
        Film::unallocated(w, h)
    } else {
        Film::try_new(w, h)?
    };
    let sums = if wide {
        Some(FilmSums::try_new(Tile::full(w, h))?)
    } else {
        None
    };
    let merge = Mutex::new(Merge {
        out: &mut out,
        pixels: &mut film.pixels,
        sums,
    });
    let new_scratch = || Scratch::new(steps);
    // The even rows, which record the points they trace on their top and bottom edges…
    let even: Vec<Option<EdgePoints>> = (0..h.div_ceil(2))
        .into_par_iter()
        .map_init(new_scratch, |scratch, k| {
            pass.row(2 * k, None, scratch, &merge)
        })
        .collect::<Result<_, _>>()?;
    // …and the odd rows, which read them.
    let none = EdgePoints::default();
    let recorded = |k: usize| even.get(k).and_then(Option::as_ref).unwrap_or(&none);
    (0..h / 2)
        .into_par_iter()
        .map_init(new_scratch, |scratch, k| {
            let (above, below) = (recorded(k as usize), recorded(k as usize + 1));
            let shared = (&above.bottom[..], &below.top[..]);
            pass.row(2 * k + 1, Some(shared), scratch, &merge)
        })
        .collect::<Result<Vec<_>, _>>()?;
    let sums = merge.into_inner().unwrap_or_else(|e| e.into_inner()).sums;
    out.film = match sums {
        Some(sums) => sums.into_film(Tile::full(w, h))?,
        None => film,
    };
    Ok(out)
}

/// Where finished rows go: the statistics and ray counts, and the pixels (pixel box) or the
/// filter sums (wider filters), which any order of rows leaves the same.
struct Merge<'a> {
    out: &'a mut Traced,
    pixels: &'a mut [Color],
    sums: Option<FilmSums>,
}

/// Points an even row traced on its edges, for the odd rows next to it: (lattice x,
/// colour), in order of x.
#[derive(Default)]
struct EdgePoints {
    top: Vec<EdgePoint>,
    bottom: Vec<EdgePoint>,
}

/// A point on a horizontal pixel edge: (lattice x, colour).
type EdgePoint = (u32, Color);

/// A row's working memory, kept from row to row by each worker: the grid of one pixel's
/// lattice points and the row's per-pixel buffers.
struct Scratch {
    grid: Grid,
    /// Points the previous pixel traced on its right edge, by local y (`carry_mask`).
    carry: Vec<Point>,
    offsets: Vec<Vec2>,
    rays: Vec<PixelRays>,
    /// Rays traced for the row below (points on the bottom edges, which it owns).
    below: Vec<PixelRays>,
    colours: Vec<Color>,
    verdicts: Vec<Verdict>,
    extremes: Vec<[Encoded; 2]>,
}

impl Scratch {
    fn new(steps: u32) -> Self {
        Scratch {
            grid: Grid::new(steps),
            carry: vec![Point::default(); steps as usize + 1],
            offsets: Vec::new(),
            rays: Vec::new(),
            below: Vec::new(),
            colours: Vec::new(),
            verdicts: Vec::new(),
            extremes: Vec::new(),
        }
    }
}

/// The lattice points of the pixel being refined, dense over its closed square
/// ((steps + 1)² of them) and reused from pixel to pixel: an entry holds a point of the
/// current pixel only if stamped with its number, so moving on clears nothing.
struct Grid {
    side: u32,
    points: Vec<Point>,
    stamp: Vec<u32>,
    current: u32,
}

impl Grid {
    fn new(steps: u32) -> Self {
        let n = (steps as usize + 1) * (steps as usize + 1);
        Grid {
            side: steps + 1,
            points: vec![Point::default(); n],
            stamp: vec![0; n],
            current: 0,
        }
    }

    /// Forgets every point: the grid is for the next pixel.
    fn next_pixel(&mut self) {
        if self.current == u32::MAX {
            self.stamp.fill(0);
            self.current = 0;
        }
        self.current += 1;
    }

    fn index(&self, i: u32, j: u32) -> usize {
        (j * self.side + i) as usize
    }

    fn set(&mut self, i: u32, j: u32, p: Point) {
        let k = self.index(i, j);
        self.points[k] = p;
        self.stamp[k] = self.current;
    }

    fn get(&self, i: u32, j: u32) -> Option<Point> {
        let k = self.index(i, j);
        (self.stamp[k] == self.current).then(|| self.points[k])
    }
}

/// The refinement pass's shared inputs.
struct Refine<'a> {
    job: &'a Job<'a>,
    rule: &'a Refinement,
    corners: &'a Corners,
    encoded: &'a [Encoded],
    steps: u32,
    /// The filter reaches beyond the pixel: samples are splatted, not averaged.
    wide: bool,
    /// False when the corners pass was cancelled: pixels are their corners' mean.
    refine: bool,
}

/// Where a pixel's samples go: its own weighted mean (pixel box), or a splat buffer.
enum Leaves<'b> {
    Mean { sum: [f64; 3], total: f64 },
    Splat(&'b mut SplatBuffer),
}

impl<'b> Leaves<'b> {
    fn new(buffer: &'b mut Option<SplatBuffer>) -> Self {
        match buffer {
            Some(b) => Leaves::Splat(b),
            None => Leaves::Mean {
                sum: [0.0; 3],
                total: 0.0,
            },
        }
    }

    fn add(&mut self, job: &Job, x: u32, y: u32, offset: Vec2, weight: f32, c: Color) {
        match self {
            Leaves::Mean { sum, total } => {
                let weight = weight as f64;
                for (s, v) in sum.iter_mut().zip(c.to_array()) {
                    *s += weight * v as f64;
                }
                *total += weight;
            }
            Leaves::Splat(buffer) => buffer.add(&job.filter, x, y, offset, weight, c),
        }
    }

    /// A square that does not split: worth the mean of its corners over its area, at its
    /// centre.
    fn square(&mut self, job: &Job, steps: u32, x: u32, y: u32, sq: Square, mean: Color) {
        let side = sq.size as f32 / steps as f32;
        let offset = match self {
            Leaves::Mean { .. } => Vec2::ZERO,
            Leaves::Splat(_) => {
                let (s, half) = (steps as f32, sq.size as f32 * 0.5);
                Vec2::new(
                    (sq.x as f32 + half - (x * steps) as f32) / s,
                    (sq.y as f32 + half - (y * steps) as f32) / s,
                )
            }
        };
        self.add(job, x, y, offset, side * side, mean);
    }

    /// The pixel's value under the pixel box: the weighted mean, black without samples.
    fn mean(&self) -> Color {
        match self {
            Leaves::Mean { sum, total } if *total != 0.0 => {
                Color::from_array(sum.map(|s| (s / total) as f32))
            }
            _ => Color::ZERO,
        }
    }
}

impl Refine<'_> {
    /// The corner points of pixel (x, y) (its corners' rows traced).
    fn corner_points(&self, x: u32, y: u32) -> [Point; 4] {
        let (top, bottom) = (self.corners.index(x, y), self.corners.index(x, y + 1));
        let point = |k: usize| Point {
            colour: self.corners.colours[k],
            encoded: self.encoded[k],
        };
        [point(top), point(top + 1), point(bottom), point(bottom + 1)]
    }

    /// Refines row y and merges it: `shared` is None for an even row, which returns the
    /// points it traced on its top and bottom edges; for an odd row, the points the even
    /// rows above and below traced on its top and bottom edges.
    fn row(
        &self,
        y: u32,
        shared: Option<(&[EdgePoint], &[EdgePoint])>,
        scratch: &mut Scratch,
        merge: &Mutex<Merge>,
    ) -> Result<Option<EdgePoints>, RenderError> {
        let job = self.job;
        let (w, h, steps) = (job.width, job.height, self.steps);
        let traced = self.refine && !job.cancelled();
        let mut buffer = self
            .wide
            .then(|| SplatBuffer::around(&job.filter, (w, h), 0, y, w, y + 1));
        scratch.colours.clear();
        if !traced {
            // Cancelled: each pixel is worth its corners' mean, where they were traced.
            for x in 0..w {
                let mut leaves = Leaves::new(&mut buffer);
                let c = [(x, y), (x + 1, y), (x, y + 1), (x + 1, y + 1)]
                    .map(|(i, j)| self.corners.get(i, j));
                if let [Some(a), Some(b), Some(c), Some(d)] = c {
                    let pixel = Square::pixel(x, y, steps);
                    leaves.square(job, steps, x, y, pixel, (a + b + c + d) * 0.25);
                }
                scratch.colours.push(leaves.mean());
            }
            let mut m = merge.lock().unwrap_or_else(|e| e.into_inner());
            m.out.complete = false;
            m.finish_row(y, &scratch.colours, buffer.as_ref());
            return Ok(None);
        }
        crate::integrator::begin_piece();
        let mut stats = Stats::default();
        scratch.rays.clear();
        scratch.rays.resize(w as usize, PixelRays::default());
        scratch.below.clear();
        scratch.below.resize(w as usize, PixelRays::default());
        let record = shared.is_none();
        let mut edges = EdgePoints::default();
        let (above, under) = shared.unwrap_or((&[], &[]));
        let (mut above_at, mut under_at) = (0, 0);
        let mut carry_mask = 0u64;
        self.verdicts(y, &mut scratch.extremes, &mut scratch.verdicts);
        for x in 0..w {
            let mut leaves = Leaves::new(&mut buffer);
            let pixel = Square::pixel(x, y, steps);
            let verdict = scratch.verdicts[x as usize];
            if self.rule.quiet(&verdict) {
                // Most pixels: one leaf, traced nothing (what `refine` would find). Under the
                // pixel box its value is its mean as it is: the one-sample weighted mean
                // 1·v / 1 in f64 returns v exactly.
                let (top, bottom) = (self.corners.index(x, y), self.corners.index(x, y + 1));
                let c = &self.corners.colours;
                let mean = (c[top] + c[top + 1] + c[bottom] + c[bottom + 1]) * 0.25;
                scratch.colours.push(match leaves {
                    Leaves::Mean { .. } => mean,
                    Leaves::Splat(_) => {
                        leaves.square(job, steps, x, y, pixel, mean);
                        Color::ZERO
                    }
                });
                carry_mask = 0;
                continue;
            }
            let corners = self.corner_points(x, y);
            if self.rule.stratified(&verdict) {
                // The stratified pass: the pixel's own samples, each worth an equal share.
                stats.adaptive_stratified += 1;
                scratch.offsets.clear();
                self.rule.texture_offsets(x, y, &mut scratch.offsets);
                let weight = 1.0 / scratch.offsets.len() as f32;
                let mark = RayMark::of(&stats);
                for &o in &scratch.offsets {
                    let c = job.trace(x as f32 + o.x, y as f32 + o.y, &mut stats);
                    leaves.add(job, x, y, o, weight, c);
                }
                scratch.rays[x as usize] += PixelRays::since(mark, &stats);
                scratch.colours.push(leaves.mean());
                carry_mask = 0;
                continue;
            }
            let (ox, oy) = (x * steps, y * steps);
            let grid = &mut scratch.grid;
            grid.next_pixel();
            for (&(i, j), &p) in [(0, 0), (steps, 0), (0, steps), (steps, steps)]
                .iter()
                .zip(&corners)
            {
                grid.set(i, j, p);
            }
            for j in bits(carry_mask) {
                grid.set(0, j, scratch.carry[j as usize]);
            }
            // Points the even rows traced on this odd row's top and bottom edges.
            for (list, at, j) in [(above, &mut above_at, 0), (under, &mut under_at, steps)] {
                while let Some(&(lx, colour)) = list.get(*at).filter(|e| e.0 < ox + steps) {
                    *at += 1;
                    if lx < ox {
                        // A point of a pixel that took the stratified pass.
                        continue;
                    }
                    let encoded = self.encode_if_compared(lx, oy + j, colour);
                    grid.set(lx - ox, j, Point { colour, encoded });
                }
            }
            let run = RayMark::of(&stats);
            let mut tracer = Tracer {
                grid,
                job,
                rule: self.rule,
                stats: &mut stats,
                origin: (ox, oy),
                steps,
                last_column: x + 1 == w,
                last_row: y + 1 == h,
                own: PixelRays::default(),
                run,
                right: PixelRays::default(),
                below: PixelRays::default(),
                masks: [0; 3],
            };
            let outcome =
                self.rule
                    .refine(pixel, verdict, corners, &mut tracer, &mut |sq, mean| {
                        leaves.square(job, steps, x, y, sq, mean)
                    });
            tracer.end_run();
            let Tracer {
                own,
                right,
                below,
                masks: [right_mask, top_mask, bottom_mask],
                ..
            } = tracer;
            if let Refined::Quadtree { splits } = outcome {
                stats.adaptive_splits += splits;
            }
            scratch.rays[x as usize] += own;
            if x + 1 < w {
                scratch.rays[x as usize + 1] += right;
            }
            scratch.below[x as usize] += below;
            scratch.colours.push(leaves.mean());
            let grid = &scratch.grid;
            for j in bits(right_mask) {
                scratch.carry[j as usize] = grid.get(steps, j).unwrap_or_default();
            }
            carry_mask = right_mask;
            if record {
                for (list, mask, j, wanted) in [
                    (&mut edges.top, top_mask, 0, y > 0),
                    (&mut edges.bottom, bottom_mask, steps, y + 1 < h),
                ] {
                    if !wanted || mask == 0 {
                        continue;
                    }
                    list.try_reserve(mask.count_ones() as usize).map_err(|_| {
                        RenderError::OutOfMemory {
                            what: "sample lattice",
                            bytes: (list.len() as u64 + 64) * 16,
                        }
                    })?;
                    for i in bits(mask) {
                        list.push((ox + i, grid.get(i, j).unwrap_or_default().colour));
                    }
                }
            }
        }
        (job.on_tile)(TileDone {
            pixels: w as u64,
            rays: stats.total_rays(),
        });
        let mut m = merge.lock().unwrap_or_else(|e| e.into_inner());
        m.out.stats += stats;
        // Most pixels trace nothing in this pass (and most trace nothing for the row below).
        let rows = [(y, &scratch.rays), (y + 1, &scratch.below)];
        for (j, rays) in rows.into_iter().filter(|&(j, _)| j < h) {
            for (x, &r) in rays.iter().enumerate() {
                if r != PixelRays::default() {
                    m.out.rays.add(x as u32, j, r);
                }
            }
        }
        m.finish_row(y, &scratch.colours, buffer.as_ref());
        Ok(record.then_some(edges))
    }

    /// The verdicts of row y's pixels (its corners traced), into `out`.
    fn verdicts(&self, y: u32, extremes: &mut Vec<[Encoded; 2]>, out: &mut Vec<Verdict>) {
        let (n, h) = (self.job.width as usize + 1, self.job.height);
        let lines = [-1i64, 0, 1, 2].map(|d| {
            let j = y as i64 + d;
            (0..=h as i64)
                .contains(&j)
                .then(|| &self.encoded[j as usize * n..][..n])
        });
        self.rule.row_verdicts(lines, extremes, out);
    }

    /// A point's `Point::encoded`, computed only where the rule will compare it.
    fn encode_if_compared(&self, x: u32, y: u32, colour: Color) -> Encoded {
        if Point::compared(x, y) {
            self.rule.encode(colour)
        } else {
            Encoded::default()
        }
    }
}

impl Merge<'_> {
    /// Row y's pixels (pixel box) or its splat buffer (wider filters).
    fn finish_row(&mut self, y: u32, colours: &[Color], buffer: Option<&SplatBuffer>) {
        match (&mut self.sums, buffer) {
            (Some(sums), Some(buffer)) => sums.merge(buffer),
            _ => {
                let start = y as usize * colours.len();
                self.pixels[start..start + colours.len()].copy_from_slice(colours);
            }
        }
    }
}

/// The set bits of `mask`, lowest first.
fn bits(mut mask: u64) -> impl Iterator<Item = u32> {
    std::iter::from_fn(move || {
        (mask != 0).then(|| {
            let i = mask.trailing_zeros();
            mask &= mask - 1;
            i
        })
    })
}

/// One pixel's walk traces through this: a point already in the grid is looked up, any
/// other is traced, stored and its rays counted in the pixel that owns it (the right
/// neighbour for the right edge, the pixel below for the bottom edge, the pixel itself for
/// the rest; the last column and row own their outer edges).
struct Tracer<'a, 'j> {
    grid: &'a mut Grid,
    job: &'a Job<'j>,
    rule: &'a Refinement,
    stats: &'a mut Stats,
    /// The pixel's top-left lattice point.
    origin: (u32, u32),
    steps: u32,
    last_column: bool,
    last_row: bool,
    /// Rays of the pixel's own points, up to the start of the current run (`run`).
    own: PixelRays,
    run: RayMark,
    right: PixelRays,
    below: PixelRays,
    /// Points traced on the right, top and bottom edges, by local coordinate along it.
    masks: [u64; 3],
}

impl Tracer<'_, '_> {
    /// Counts the current run of the pixel's own rays (at the end of the pixel).
    fn end_run(&mut self) {
        self.own += PixelRays::since(self.run, self.stats);
        self.run = RayMark::of(self.stats);
    }
}

impl PointSource for Tracer<'_, '_> {
    fn point(&mut self, x: u32, y: u32) -> Point {
        let (i, j) = (x - self.origin.0, y - self.origin.1);
        if let Some(p) = self.grid.get(i, j) {
            return p;
        }
        let s = self.steps as f32;
        let (fx, fy) = self.rule.position(x, y);
        let steps = self.steps;
        if i == steps {
            self.masks[0] |= 1 << j;
        } else if j == 0 {
            self.masks[1] |= 1 << i;
        } else if j == steps {
            self.masks[2] |= 1 << i;
        }
        let neighbour = if i == steps && !self.last_column {
            Some(&mut self.right)
        } else if j == steps && !self.last_row {
            Some(&mut self.below)
        } else {
            None
        };
        let colour = match neighbour {
            // The pixel's own points are counted together (`Tracer::own`); a neighbour's
            // ends the pixel's current run of rays.
            Some(rays) => {
                self.own += PixelRays::since(self.run, self.stats);
                let mark = RayMark::of(self.stats);
                let colour = self.job.trace(fx / s, fy / s, self.stats);
                *rays += PixelRays::since(mark, self.stats);
                self.run = RayMark::of(self.stats);
                colour
            }
            None => self.job.trace(fx / s, fy / s, self.stats),
        };
        let encoded = if Point::compared(x, y) {
            self.rule.encode(colour)
        } else {
            Encoded::default()
        };
        let p = Point { colour, encoded };
        self.grid.set(i, j, p);
        p
    }
}

/// Traces the (W+1)×(H+1) pixel corners, each at `position` (lattice units, `steps` per
/// pixel) of its lattice coordinates; false if cancelled.
fn trace_corners(
    job: &Job,
    corners: &mut Corners,
    steps: u32,
    position: impl Fn(u32, u32) -> (f32, f32) + Sync,
    out: &mut Traced,
) -> bool {
    let (w, h) = (job.width, job.height);
    let s = steps as f32;
    // Rows are merged as they finish, so that their buffers are reused, not all held.
    let merge = Mutex::new((&mut corners.traced, out));
    // Rows are handed out from the top (not split in halves as a parallel slice is), so
    // that a cancelled pass has traced a band of rows from the top.
    (corners.colours)
        .chunks_mut(w as usize + 1)
        .enumerate()
        .par_bridge()
        .for_each_init(Vec::new, |rays, (j, values)| {
            if job.cancelled() {
                return;
            }
            crate::integrator::begin_piece();
            let j = j as u32;
            let mut stats = Stats::default();
            rays.clear();
            rays.resize(w as usize, PixelRays::default());
            if job.packets {
                // Runs of corners along the row, one packet each.
                let mut at = [Vec2::ZERO; PACKET_MAX];
                let mut work = [PixelRays::default(); PACKET_MAX];
                for (run, chunk) in values.chunks_mut(PACKET_MAX).enumerate() {
                    let first = (run * PACKET_MAX) as u32;
                    for (k, p) in at[..chunk.len()].iter_mut().enumerate() {
                        let (fx, fy) = position((first + k as u32) * steps, j * steps);
                        *p = Vec2::new(fx / s, fy / s);
                    }
                    work.fill(PixelRays::default());
                    trace_packet(job, &at[..chunk.len()], chunk, &mut work, &mut stats);
                    for (k, r) in work[..chunk.len()].iter().enumerate() {
                        rays[(first + k as u32).min(w - 1) as usize] += *r;
                    }
                }
            } else {
                for (i, value) in (0..=w).zip(values) {
                    let mark = RayMark::of(&stats);
                    let (fx, fy) = position(i * steps, j * steps);
                    *value = job.trace(fx / s, fy / s, &mut stats);
                    rays[i.min(w - 1) as usize] += PixelRays::since(mark, &stats);
                }
            }
            (job.on_tile)(TileDone {
                pixels: if j < h { w as u64 } else { 0 },
                rays: stats.total_rays(),
            });
            let mut m = merge.lock().unwrap_or_else(|e| e.into_inner());
            m.0[j as usize] = true;
            m.1.add_row(j.min(h - 1), stats, rays);
        });
    let out = merge.into_inner().unwrap_or_else(|e| e.into_inner()).1;
    let complete = corners.complete();
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
            if job.packets {
                values.resize(w as usize, Color::ZERO);
                rays.resize(w as usize, PixelRays::default());
                let mut at = [Vec2::ZERO; PACKET_MAX];
                for (run, (chunk, work)) in values
                    .chunks_mut(PACKET_MAX)
                    .zip(rays.chunks_mut(PACKET_MAX))
                    .enumerate()
                {
                    let first = run * PACKET_MAX;
                    for (k, p) in at[..chunk.len()].iter_mut().enumerate() {
                        *p = Vec2::new((first + k) as f32 + 0.5, y as f32 + 0.5);
                    }
                    trace_packet(job, &at[..chunk.len()], chunk, work, &mut stats);
                }
            } else {
                for x in 0..w {
                    let before = stats;
                    values.push(job.trace(x as f32 + 0.5, y as f32 + 0.5, &mut stats));
                    rays.push(PixelRays::between(&before, &stats));
                }
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

/// The reconstruction pass: `splat` adds pixel (x, y)'s samples to a buffer covering its
/// row and the filter's reach; buffers merge exactly into the film.
fn reconstruct(
    job: &Job,
    splat: impl Fn(&mut SplatBuffer, u32, u32) + Sync,
) -> Result<Film, RenderError> {
    let (w, h) = (job.width, job.height);
    let sums = Mutex::new(FilmSums::try_new(Tile::full(w, h))?);
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
        .into_film(Tile::full(w, h))
}
