//! Whitted's adaptive supersampling, as POV-Ray's `+AM2` does it: trace the pixel's four
//! corners (shared with the neighbouring pixels); when their colours differ by more than a
//! threshold, trace the centre and the four edge midpoints and treat the four quarter
//! squares the same way, down to a depth limit. A square that does not split is worth the
//! mean of its corners.
//!
//! Every point lies on a lattice of 2^depth steps per pixel, so a point is named by integer
//! lattice coordinates and is traced once however many squares (of one pixel or of its
//! neighbours) use it. This file owns the geometry, the rule and where each point is traced;
//! `render::lattice` owns the passes that trace the points.
//!
//! The classic rule (`AdaptiveRule::Corners` without jitter) misses what falls between a
//! pixel's corners, and on a regular lattice a pattern finer than the pixels aliases into
//! broad bands where all corners agree. Two additions fix that while keeping the corners
//! shared (docs/sampling.md measures them):
//! - jitter: each point, the pixel corners too, is traced at a hashed position within its
//!   cell of the finest lattice (pixel corners within ±¼ pixel), turning aliasing into
//!   noise (POV-Ray's `Jitter` moves only the interior points, by a fraction of a cell);
//! - the neighbourhood rule: a pixel splits when any of the 16 corners around it (its own
//!   and its eight neighbours') differ, and a pixel whose 4×4 corners change colour more
//!   often than any single straight edge can make them (texture finer than the pixels) is
//!   textured.
//!
//! A textured pixel has no edge for the quadtree to find: subdividing it spends 4× the rays
//! per level on a nearly regular lattice, which aliases. So by default it takes n×n
//! jittered samples of its own instead (the stratified pass, `texture_n`), which turn the
//! pattern into noise at a fixed cost; with `texture_n` = 0 it is refined to depth − 1
//! everywhere and one level further where it differs, as before.

use crate::choices::{AdaptiveRule, AdaptiveSpec};
use crate::math::hash::uniform;
use crate::math::{Color, Vec2};
use crate::transfer::Transfer;

pub use crate::choices::sampler::{MAX_DEPTH, MAX_TEXTURE_N};

/// Hash dimensions of a lattice point's jitter.
const DIM_JITTER_X: u32 = 7;
const DIM_JITTER_Y: u32 = 8;

/// Mixed into the seed of the stratified pass, so that its points are not those of the
/// jittered sampler with the same seed (sweeps compare the two).
const TEXTURE_SEED_SALT: u64 = 0xA5A5_7E27_0000_0001;

/// The refinement rule and where it traces.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Refinement {
    /// A square splits when, in some channel, its corners' display-encoded (through
    /// `transfer`, clamped to [0, 1]) values span more than this.
    pub threshold: f32,
    /// How colours are shown, so that the threshold is a step on the screen.
    pub transfer: Transfer,
    /// Levels of splitting below the pixel; 0 traces the corners only.
    pub depth: u32,
    /// The rule that decides which squares split.
    pub rule: AdaptiveRule,
    /// 0: points exactly on the lattice; 1: anywhere in their cell (see the module notes).
    pub jitter: f32,
    /// Samples per axis of the stratified pass that textured pixels take (neighbourhood
    /// rule only); 0 refines them with the quadtree instead.
    pub texture_n: u32,
    /// Seed of the jitter and of the stratified pass.
    pub seed: u64,
}

impl Refinement {
    /// The refinement the adaptive sampler's settings ask for, judged through `transfer`,
    /// with its jitter and stratified pass seeded by `seed`.
    pub fn new(spec: &AdaptiveSpec, transfer: Transfer, seed: u64) -> Refinement {
        Refinement {
            threshold: spec.threshold,
            transfer,
            depth: spec.depth,
            rule: spec.rule,
            jitter: spec.jitter,
            texture_n: spec.texture_n(),
            seed,
        }
    }

    /// Lattice steps along a pixel side.
    pub fn steps(&self) -> u32 {
        1 << self.depth
    }

    /// Appends the offsets in (0, 1)² of the stratified pass's samples in pixel (px, py),
    /// in sample order: one jittered point in each of texture_n × texture_n strata.
    pub fn texture_offsets(&self, px: u32, py: u32, out: &mut Vec<Vec2>) {
        super::jittered::jittered(px, py, self.texture_n, self.seed ^ TEXTURE_SEED_SALT, out);
    }

    /// Where lattice point (x, y) is traced, in lattice units.
    #[inline]
    pub fn position(&self, x: u32, y: u32) -> (f32, f32) {
        if self.jitter == 0.0 {
            return (x as f32, y as f32);
        }
        let steps = self.steps();
        // `steps` is a power of two: a mask, not a division.
        let corner = (x | y) & (steps - 1) == 0;
        let span = self.jitter * if corner { 0.5 * steps as f32 } else { 1.0 };
        let jx = (uniform(x, y, 0, DIM_JITTER_X, self.seed) - 0.5) * span;
        let jy = (uniform(x, y, 0, DIM_JITTER_Y, self.seed) - 0.5) * span;
        (x as f32 + jx, y as f32 + jy)
    }

    /// Walks the quadtree of `root` down to `max_level`, reading point colours through
    /// `lookup` (None: not traced). Squares are visited parent first.
    pub fn walk(
        &self,
        root: Square,
        max_level: u32,
        lookup: &impl Fn(u32, u32) -> Option<Color>,
        visit: &mut impl FnMut(Square, Visit),
    ) {
        self.walk_square(root, max_level, lookup, visit);
    }

    /// What the rule says of a pixel from the corners around it, read display-encoded
    /// (`encode`) through `encoded`; None if one of the pixel's own corners is not traced.
    pub fn verdict(
        &self,
        pixel: &Square,
        encoded: &impl Fn(u32, u32) -> Option<Encoded>,
    ) -> Option<Verdict> {
        self.verdict_of_block(&neighbourhood_block(pixel, encoded))
    }

    /// `verdict` from the pixel's 4×4 block of corners (`neighbourhood_block`): row by row
    /// from the corner up and left of the pixel's own top-left one, None outside the image.
    /// A renderer judging every pixel reads the block from a dense array of corners, each
    /// encoded once, instead of through a lookup per corner.
    pub fn verdict_of_block(&self, block: &[Option<Encoded>; 16]) -> Option<Verdict> {
        let [Some(a), Some(b), Some(c), Some(d)] = [block[5], block[6], block[9], block[10]] else {
            return None;
        };
        let (busy, textured) = match self.rule {
            AdaptiveRule::Neighbourhood => self.neighbourhood(block),
            AdaptiveRule::Corners => (spread_encoded(&[a, b, c, d]) > self.threshold, false),
        };
        Some(Verdict { busy, textured })
    }

    fn walk_square(
        &self,
        square: Square,
        max_level: u32,
        lookup: &impl Fn(u32, u32) -> Option<Color>,
        visit: &mut impl FnMut(Square, Visit),
    ) {
        let corners = square.corners().map(|(x, y)| lookup(x, y));
        self.walk_known(square, corners, false, max_level, lookup, visit);
    }

    /// `walk_square` of a square whose corners' colours are known: a split square hands
    /// its quarters the colours it looked up for its new points, so that a walk looks up
    /// each point once instead of once per square that has it as a corner.
    fn walk_known(
        &self,
        square: Square,
        corners: [Option<Color>; 4],
        textured: bool,
        max_level: u32,
        lookup: &impl Fn(u32, u32) -> Option<Color>,
        visit: &mut impl FnMut(Square, Visit),
    ) {
        let [Some(a), Some(b), Some(c), Some(d)] = corners else {
            visit(square, Visit::Missing);
            return;
        };
        let corners = [a, b, c, d];
        let (busy, textured) = if square.level == 0 && self.rule == AdaptiveRule::Neighbourhood {
            let encoded = |x, y| lookup(x, y).map(|c| self.encode(c));
            self.neighbourhood(&neighbourhood_block(&square, &encoded))
        } else {
            (self.contrast(&corners) > self.threshold, textured)
        };
        if textured && self.texture_n > 0 && self.depth > 0 {
            visit(square, Visit::Stratified(corners));
            return;
        }
        // Texture is refined to depth − 1 regardless, and one level further where it differs.
        let split =
            square.level < self.depth && (busy || (textured && square.level + 1 < self.depth));
        if !split {
            visit(square, Visit::Leaf(corners));
            return;
        }
        let new = if square.level < max_level {
            square.new_points().map(|(x, y)| lookup(x, y))
        } else {
            [None; 5]
        };
        let [Some(m), Some(t), Some(l), Some(r), Some(u)] = new else {
            visit(square, Visit::Frontier(corners));
            return;
        };
        visit(square, Visit::Split);
        // Quarters in `children` order, corners in `corners` order; the new points are
        // centre, top, left, right and bottom (`new_points`).
        let quarters = [[a, t, l, m], [t, b, m, r], [l, m, c, u], [m, r, u, d]];
        for (child, corners) in square.children().into_iter().zip(quarters) {
            let corners = corners.map(Some);
            self.walk_known(child, corners, textured, max_level, lookup, visit);
        }
    }

    /// The neighbourhood rule for a pixel, from its 4×4 block of display-encoded corners
    /// (`neighbourhood_block`): whether they differ, and whether they change colour more
    /// often than one straight edge can make them. Encoded beforehand, since the 24
    /// comparisons below would otherwise encode each corner up to four times (the encoding,
    /// a power, dominates the rule's cost).
    fn neighbourhood(&self, block: &[Option<Encoded>; 16]) -> (bool, bool) {
        let busy = spread_encoded(block.iter().flatten()) > self.threshold;
        // No pair of the block can differ by more than the whole block spreads: no changes,
        // so no texture either (most pixels of most images end here).
        (busy, busy && self.textured(block))
    }

    /// The texture half of the neighbourhood rule: whether the block's corners change
    /// colour more often than one straight edge can make them.
    fn textured(&self, block: &[Option<Encoded>; 16]) -> bool {
        self.textured_by(|k| block[k])
    }

    /// `textured` of the block whose entry k is `corner(k)`: a renderer's block wholly
    /// inside the image has no absent corners to check for.
    #[inline]
    fn textured_by(&self, corner: impl Fn(usize) -> Option<Encoded>) -> bool {
        // The spread of two colours is their largest channel difference (bit for bit:
        // max − min is |a − b|; encoded values are never NaN, so "some channel differs by
        // more" is "the largest difference is more"); 24 pairs per pixel.
        let t = self.threshold;
        let differ = |i: usize, j: usize| match (corner(i), corner(j)) {
            (Some(a), Some(b)) => {
                let d = |k: usize| (a[k] - b[k]).abs();
                d(0) > t || d(1) > t || d(2) > t
            }
            _ => false,
        };
        let changes = (0..16)
            .map(|i| {
                let right = i % 4 < 3 && differ(i, i + 1);
                let down = i < 12 && differ(i, i + 4);
                right as usize + down as usize
            })
            .sum::<usize>();
        // A straight edge crosses each row and each column of the block at most once, so it
        // changes colour at most once per row and column (8 inside the image, fewer along
        // its borders, where the block is cut).
        let line =
            |a: usize, step: usize| (0..4).filter(|&k| corner(a + k * step).is_some()).count();
        let straight_edge_changes = (0..4)
            .map(|i| (line(i * 4, 1) >= 2) as usize + (line(i, 4) >= 2) as usize)
            .sum::<usize>();
        changes > straight_edge_changes
    }

    /// The verdicts of a row of pixels at once, from the corner lines above, at, below and
    /// two below its top edge (`lines[1]` and `lines[2]` are the row's own corners, W + 1
    /// of them; the others are None outside the image): what `verdict` says of each pixel.
    /// The neighbourhood rule's 4×4 blocks overlap by 12 corners from one pixel to the
    /// next, so the row's per-column extremes over the four lines are taken once
    /// (`extremes`: working memory) and each block's spread from four columns; only busy
    /// pixels then look at their block's changes.
    pub fn row_verdicts(
        &self,
        lines: [Option<&[Encoded]>; 4],
        extremes: &mut Vec<[Encoded; 2]>,
        out: &mut Vec<Verdict>,
    ) {
        out.clear();
        let (Some(top), Some(bottom)) = (lines[1], lines[2]) else {
            return;
        };
        let n = top.len();
        let width = n.saturating_sub(1);
        if self.rule == AdaptiveRule::Corners {
            out.extend((0..width).map(|x| Verdict {
                busy: spread_encoded(&[top[x], top[x + 1], bottom[x], bottom[x + 1]])
                    > self.threshold,
                textured: false,
            }));
            return;
        }
        extremes.clear();
        extremes.extend((0..n).map(|i| extremes_of(lines.iter().flatten().map(|l| &l[i]))));
        for x in 0..width {
            let columns = &extremes[x.saturating_sub(1)..(x + 3).min(n)];
            let lo = extremes_of(columns.iter().map(|e| &e[0]))[0];
            let hi = extremes_of(columns.iter().map(|e| &e[1]))[1];
            let busy = spread_of(lo, hi) > self.threshold;
            let textured = busy
                && match lines {
                    [Some(a), Some(b), Some(c), Some(d)] if x >= 1 && x + 3 <= n => {
                        let rows = [a, b, c, d].map(|l| &l[x - 1..x + 3]);
                        self.textured_by(|k| Some(rows[k / 4][k % 4]))
                    }
                    _ => self.textured_by(|k| {
                        let i = (x + k % 4).checked_sub(1).filter(|&i| i < n)?;
                        lines[k / 4].map(|l| l[i])
                    }),
                };
            out.push(Verdict { busy, textured });
        }
    }
}

/// The rule's judgement of a whole pixel, which depends on the pixel corners alone and so
/// holds for every pass once they are traced.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Verdict {
    /// The pixel splits (if the depth allows).
    pub busy: bool,
    /// The pixel is textured (neighbourhood rule only).
    pub textured: bool,
}

/// What a walk finds at a square.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Visit {
    /// A corner is not traced (the render was cancelled).
    Missing,
    /// The square does not split; its corners' colours.
    Leaf([Color; 4]),
    /// The square splits and the walk goes on into its quarters.
    Split,
    /// The square splits, but the walk stops here: it is at the level asked for, or its new
    /// points are not traced.
    Frontier([Color; 4]),
    /// The pixel is textured and takes the stratified pass instead of splitting; its
    /// corners' colours (worth their mean if the pass was not traced).
    Stratified([Color; 4]),
}

/// A square of the quadtree in lattice coordinates: top-left corner and side.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Square {
    /// Left edge, in lattice units.
    pub x: u32,
    /// Top edge, in lattice units.
    pub y: u32,
    /// Side length, in lattice units.
    pub size: u32,
    /// 0 for the pixel itself.
    pub level: u32,
}

impl Square {
    /// The whole pixel (px, py) on a lattice of `steps` per pixel.
    pub fn pixel(px: u32, py: u32, steps: u32) -> Square {
        Square {
            x: px * steps,
            y: py * steps,
            size: steps,
            level: 0,
        }
    }

    /// Top-left, top-right, bottom-left, bottom-right.
    pub fn corners(&self) -> [(u32, u32); 4] {
        let (x, y, s) = (self.x, self.y, self.size);
        [(x, y), (x + s, y), (x, y + s), (x + s, y + s)]
    }

    /// The points a split adds: centre, then the top, left, right and bottom midpoints.
    pub fn new_points(&self) -> [(u32, u32); 5] {
        let (x, y, s, h) = (self.x, self.y, self.size, self.size / 2);
        [
            (x + h, y + h),
            (x + h, y),
            (x, y + h),
            (x + s, y + h),
            (x + h, y + s),
        ]
    }

    /// The four quarters of the square, one level deeper.
    pub fn children(&self) -> [Square; 4] {
        let h = self.size / 2;
        let level = self.level + 1;
        let at = |x, y| Square {
            x,
            y,
            size: h,
            level,
        };
        [
            at(self.x, self.y),
            at(self.x + h, self.y),
            at(self.x, self.y + h),
            at(self.x + h, self.y + h),
        ]
    }
}

/// The 4×4 pixel corners around `pixel` (its own four are entries 5, 6, 9 and 10), row by
/// row, read through `encoded`; None left of or above the image (and wherever `encoded`
/// says so: right of or below it).
pub fn neighbourhood_block(
    pixel: &Square,
    encoded: &impl Fn(u32, u32) -> Option<Encoded>,
) -> [Option<Encoded>; 16] {
    let s = pixel.size as i64;
    let mut block = [None; 16];
    for dy in -1..=2i64 {
        for dx in -1..=2i64 {
            let (x, y) = (pixel.x as i64 + dx * s, pixel.y as i64 + dy * s);
            if x >= 0 && y >= 0 {
                block[((dy + 1) * 4 + dx + 1) as usize] = encoded(x as u32, y as u32);
            }
        }
    }
    block
}

/// A lattice point as `Refinement::refine` sees it: its colour and, if both its lattice
/// coordinates are even, its display-encoded colour. Only such points are corners of
/// squares that can still split (squares of side 2 and more), the only ones the rule
/// compares; the finest points never need the encoding.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Point {
    /// The radiance traced at the point.
    pub colour: Color,
    /// Meaningful where both coordinates are even (`Point::compared`).
    pub encoded: Encoded,
}

impl Point {
    /// Whether the rule ever compares lattice point (x, y), so that its `encoded` is needed.
    pub fn compared(x: u32, y: u32) -> bool {
        (x | y) & 1 == 0
    }
}

/// Where `Refinement::refine` gets the points a split adds: a renderer traces each the
/// first time any square asks for it and hands every later asker the same point.
pub trait PointSource {
    /// Lattice point (x, y), traced if this is the first time anyone asks for it.
    fn point(&mut self, x: u32, y: u32) -> Point;
}

/// What `Refinement::refine` did with a pixel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Refined {
    /// The pixel is textured and takes the stratified pass instead (nothing was visited).
    Stratified,
    /// The quadtree was walked to its leaves; this many squares split.
    Quadtree {
        /// Squares split (the statistics' `adaptive_splits`).
        splits: u64,
    },
}

impl Refinement {
    /// The whole refinement of one pixel in one walk, for a renderer that traces points on
    /// demand: squares are decided parent first, a split square's five new points come
    /// from `points`, and `leaf` receives every square that does not split with the mean
    /// of its corners, in the order `walk` visits them (the order the pixel's sum is taken
    /// in). `corners`: the pixel's own, in `Square::corners` order; `verdict`: the rule's
    /// judgement of the pixel (`verdict`). Decides exactly as `walk` at full depth when
    /// every point is traced (tested).
    pub fn refine(
        &self,
        pixel: Square,
        verdict: Verdict,
        corners: [Point; 4],
        points: &mut impl PointSource,
        leaf: &mut impl FnMut(Square, Color),
    ) -> Refined {
        debug_assert_eq!(pixel.level, 0);
        if self.stratified(&verdict) {
            return Refined::Stratified;
        }
        let mut splits = 0;
        let busy = Some(verdict.busy);
        self.refine_square(
            pixel,
            corners,
            busy,
            verdict.textured,
            points,
            leaf,
            &mut splits,
        );
        Refined::Quadtree { splits }
    }

    /// Whether a pixel so judged takes the stratified pass instead of the quadtree.
    pub fn stratified(&self, verdict: &Verdict) -> bool {
        verdict.textured && self.texture_n > 0 && self.depth > 0
    }

    /// Whether a pixel so judged is one leaf, its corners' mean: neither split nor given
    /// the stratified pass (what `refine` finds without asking for a point).
    pub fn quiet(&self, verdict: &Verdict) -> bool {
        !self.stratified(verdict) && !self.splits(0, verdict.textured, || verdict.busy)
    }

    /// Whether a square at `level` of a pixel (`textured` or not) splits; `busy`: whether
    /// its corners differ (the pixel's verdict at level 0), asked only if it matters.
    /// Texture is refined to depth − 1 regardless, and one level further where it differs.
    #[inline]
    fn splits(&self, level: u32, textured: bool, busy: impl FnOnce() -> bool) -> bool {
        level < self.depth && ((textured && level + 1 < self.depth) || busy())
    }

    /// `busy`: the pixel's verdict (level 0 only); below, the square's own contrast.
    #[allow(clippy::too_many_arguments)]
    fn refine_square(
        &self,
        square: Square,
        c: [Point; 4],
        busy: Option<bool>,
        textured: bool,
        points: &mut impl PointSource,
        leaf: &mut impl FnMut(Square, Color),
        splits: &mut u64,
    ) {
        let split = self.splits(square.level, textured, || {
            busy.unwrap_or_else(|| spread_encoded(&c.map(|p| p.encoded)) > self.threshold)
        });
        if !split {
            let mean = (c[0].colour + c[1].colour + c[2].colour + c[3].colour) * 0.25;
            leaf(square, mean);
            return;
        }
        *splits += 1;
        let [m, t, l, r, u] = square.new_points().map(|(x, y)| points.point(x, y));
        let [a, b, cc, d] = c;
        // As in `walk_known`: quarters in `children` order, corners in `corners` order.
        let quarters = [[a, t, l, m], [t, b, m, r], [l, m, cc, u], [m, r, u, d]];
        for (child, corners) in square.children().into_iter().zip(quarters) {
            self.refine_square(child, corners, None, textured, points, leaf, splits);
        }
    }
}

/// The largest per-channel spread of colours already display-encoded. Encoded values are
/// never NaN (`Transfer::encode` maps NaN to 0), so plain comparisons find the same
/// extremes as `f32::min` and `f32::max`, without their NaN handling.
#[inline]
fn spread_encoded<'c>(colours: impl IntoIterator<Item = &'c Encoded>) -> f32 {
    let [lo, hi] = extremes_of(colours);
    spread_of(lo, hi)
}

/// Per channel, the smallest and the largest of the encoded colours (∞ and −∞ for none).
#[inline]
fn extremes_of<'c>(colours: impl IntoIterator<Item = &'c Encoded>) -> [Encoded; 2] {
    let mut lo = [f32::INFINITY; 3];
    let mut hi = [f32::NEG_INFINITY; 3];
    for c in colours {
        for k in 0..3 {
            lo[k] = if c[k] < lo[k] { c[k] } else { lo[k] };
            hi[k] = if c[k] > hi[k] { c[k] } else { hi[k] };
        }
    }
    [lo, hi]
}

/// The largest channel spread between per-channel extremes (0 for no colours).
#[inline]
fn spread_of(lo: Encoded, hi: Encoded) -> f32 {
    (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f32::max)
}

/// A colour display-encoded: what the rule compares.
pub type Encoded = [f32; 3];

impl Refinement {
    /// A colour's channels display-encoded.
    pub fn encode(&self, c: Color) -> Encoded {
        c.to_array().map(|v| self.transfer.encode(v))
    }

    /// The largest per-channel spread of the corners, in display-encoded units.
    pub fn contrast(&self, corners: &[Color; 4]) -> f32 {
        spread_encoded(&corners.map(|c| self.encode(c)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn contrast_is_the_largest_channel_spread_on_screen() {
        let rule = |transfer| Refinement {
            threshold: 0.1,
            transfer,
            depth: 2,
            rule: AdaptiveRule::Corners,
            jitter: 0.0,
            texture_n: 0,
            seed: 0,
        };
        let srgb = rule(Transfer::Srgb);
        let black = Color::ZERO;
        let white = Color::ONE;
        assert_eq!(srgb.contrast(&[black; 4]), 0.0);
        assert!((srgb.contrast(&[black, black, black, white]) - 1.0).abs() < 1e-6);
        let grey = Color::splat(0.214_041_14); // sRGB 0.5
        let c = srgb.contrast(&[grey, black, grey, grey]);
        assert!((c - 0.5).abs() < 1e-4, "{c}");
        // Display-referred values are shown as they are.
        let display = rule(Transfer::Display);
        let c = display.contrast(&[grey, black, grey, grey]);
        assert!((c - 0.214_041_14).abs() < 1e-6, "{c}");
    }

    #[test]
    fn a_walk_splits_where_corners_differ_and_stops_at_the_depth() {
        let rule = Refinement {
            threshold: 0.1,
            transfer: Transfer::Srgb,
            depth: 2,
            rule: AdaptiveRule::Corners,
            jitter: 0.0,
            texture_n: 0,
            seed: 0,
        };
        // White left of x = 1 lattice step, black elsewhere: only squares touching x <= 1
        // see both colours.
        let lookup = |x: u32, _y: u32| Some(if x <= 1 { Color::ONE } else { Color::ZERO });
        let mut splits = 0;
        let mut leaves = 0;
        rule.walk(Square::pixel(0, 0, 4), 2, &lookup, &mut |sq, v| match v {
            Visit::Split => splits += 1,
            Visit::Leaf(_) => leaves += 1,
            Visit::Frontier(_) => panic!("depth-2 squares never split: {sq:?}"),
            Visit::Missing => panic!("all points exist"),
            Visit::Stratified(_) => panic!("the corners rule sees no texture"),
        });
        // The pixel and its two left quarters split; the quarters' 8 children are leaves,
        // plus the two right quarters.
        assert_eq!((splits, leaves), (3, 10));
    }

    #[test]
    fn a_textured_neighbourhood_takes_the_stratified_pass_or_splits_without_it() {
        // Corners alternating like a checker one pixel wide: 24 changes in the 4×4 block,
        // more than any straight edge makes.
        let lookup = |x: u32, y: u32| {
            Some(if (x / 4 + y / 4).is_multiple_of(2) {
                Color::ONE
            } else {
                Color::ZERO
            })
        };
        let visits = |texture_n| {
            let rule = Refinement {
                threshold: 0.1,
                transfer: Transfer::Srgb,
                depth: 2,
                rule: AdaptiveRule::Neighbourhood,
                jitter: 0.0,
                texture_n,
                seed: 0,
            };
            let mut seen = Vec::new();
            rule.walk(Square::pixel(1, 1, 4), 2, &lookup, &mut |_, v| seen.push(v));
            seen
        };
        assert!(matches!(visits(3)[..], [Visit::Stratified(_)]));
        assert!(visits(0).contains(&Visit::Split));
        // The corners rule never sees texture.
        let corners = Refinement {
            threshold: 0.1,
            transfer: Transfer::Srgb,
            depth: 2,
            rule: AdaptiveRule::Corners,
            jitter: 0.0,
            texture_n: 3,
            seed: 0,
        };
        corners.walk(Square::pixel(1, 1, 4), 2, &lookup, &mut |_, v| {
            assert!(!matches!(v, Visit::Stratified(_)))
        });
    }

    #[test]
    fn refine_decides_as_the_full_walk() {
        // A slanted edge, and a fine checker (texture) below y = 24 lattice steps.
        let lookup = |x: u32, y: u32| {
            let white = if y >= 24 {
                (x / 3 + y / 3).is_multiple_of(2)
            } else {
                2 * x + 3 * y < 70
            };
            Some(if white {
                Color::ONE
            } else {
                Color::splat(0.02)
            })
        };
        /// Looks points up and remembers which were asked for.
        struct Asked<'a, F> {
            lookup: &'a F,
            rule: &'a Refinement,
            asked: Vec<(u32, u32)>,
        }
        impl<F: Fn(u32, u32) -> Option<Color>> PointSource for Asked<'_, F> {
            fn point(&mut self, x: u32, y: u32) -> Point {
                self.asked.push((x, y));
                let colour = (self.lookup)(x, y).unwrap();
                let encoded = if Point::compared(x, y) {
                    self.rule.encode(colour)
                } else {
                    // Never compared: a wrong value would show.
                    [f32::NAN; 3]
                };
                Point { colour, encoded }
            }
        }
        for rule in AdaptiveRule::ALL {
            for texture_n in [0, 3] {
                let r = Refinement {
                    threshold: 0.1,
                    transfer: Transfer::Srgb,
                    depth: 3,
                    rule,
                    jitter: 0.0,
                    texture_n,
                    seed: 0,
                };
                let encoded = |x: u32, y: u32| lookup(x, y).map(|c| r.encode(c));
                let (mut splits, mut textured) = (0, 0);
                for (px, py) in [(0, 0), (1, 1), (2, 1), (1, 2), (3, 3), (0, 4)] {
                    let name = format!("{rule}, texture {texture_n}, pixel ({px}, {py})");
                    let pixel = Square::pixel(px, py, r.steps());
                    let verdict = r.verdict(&pixel, &encoded).unwrap();
                    textured += verdict.textured as usize;
                    // The full walk: leaves with their means, split squares' new points.
                    let (mut leaves, mut new, mut stratified) = (Vec::new(), Vec::new(), false);
                    r.walk(pixel, r.depth, &lookup, &mut |sq, v| match v {
                        Visit::Leaf(c) => leaves.push((sq, (c[0] + c[1] + c[2] + c[3]) * 0.25)),
                        Visit::Split => new.extend(sq.new_points()),
                        Visit::Stratified(_) => stratified = true,
                        Visit::Missing | Visit::Frontier(_) => panic!("{name}: {v:?}"),
                    });
                    let corners = pixel.corners().map(|(x, y)| {
                        let colour = lookup(x, y).unwrap();
                        Point {
                            colour,
                            encoded: r.encode(colour),
                        }
                    });
                    let mut source = Asked {
                        lookup: &lookup,
                        rule: &r,
                        asked: Vec::new(),
                    };
                    let mut found = Vec::new();
                    let outcome = r.refine(pixel, verdict, corners, &mut source, &mut |sq, m| {
                        found.push((sq, m))
                    });
                    if stratified {
                        assert_eq!(outcome, Refined::Stratified, "{name}");
                        assert!(found.is_empty() && source.asked.is_empty(), "{name}");
                        continue;
                    }
                    assert_eq!(found, leaves, "{name}");
                    assert_eq!(source.asked, new, "{name}: the points asked for");
                    assert_eq!(
                        outcome,
                        Refined::Quadtree {
                            splits: new.len() as u64 / 5
                        },
                        "{name}"
                    );
                    splits += new.len() / 5;
                }
                // The cases above are not vacuous.
                assert!(splits > 6, "{rule}: {splits} splits");
                assert_eq!(textured > 0, rule == AdaptiveRule::Neighbourhood, "{rule}");
            }
        }
    }

    #[test]
    fn row_verdicts_are_the_verdicts_of_each_pixel() {
        // Corners of a 7×5-pixel image: an edge, a checker patch (texture) and noise.
        let (w, h) = (7usize, 5usize);
        let colour = |i: usize, j: usize| -> Encoded {
            let v = if j >= 3 && i < 4 {
                ((i + j) % 2) as f32
            } else if i + 2 * j < 7 {
                0.9
            } else {
                0.1 + 0.07 * ((i * 7 + j * 3) % 5) as f32
            };
            [v, 0.5 * v, 0.2]
        };
        let lines: Vec<Vec<Encoded>> = (0..=h)
            .map(|j| (0..=w).map(|i| colour(i, j)).collect())
            .collect();
        for rule in AdaptiveRule::ALL {
            let r = Refinement {
                threshold: 0.1,
                transfer: Transfer::Display,
                depth: 2,
                rule,
                jitter: 0.0,
                texture_n: 3,
                seed: 0,
            };
            let steps = r.steps();
            let encoded = |x: u32, y: u32| {
                let (i, j) = ((x / steps) as usize, (y / steps) as usize);
                (i <= w && j <= h).then(|| lines[j][i])
            };
            let (mut extremes, mut row) = (Vec::new(), Vec::new());
            let (mut busy, mut textured) = (0, 0);
            for y in 0..h {
                let line = |d: i64| {
                    let j = y as i64 + d;
                    (0..=h as i64).contains(&j).then(|| &lines[j as usize][..])
                };
                r.row_verdicts(
                    [line(-1), line(0), line(1), line(2)],
                    &mut extremes,
                    &mut row,
                );
                assert_eq!(row.len(), w);
                for (x, v) in row.iter().enumerate() {
                    let pixel = Square::pixel(x as u32, y as u32, steps);
                    assert_eq!(Some(*v), r.verdict(&pixel, &encoded), "{rule} ({x}, {y})");
                    busy += v.busy as usize;
                    textured += v.textured as usize;
                }
            }
            assert!(busy > 5, "{rule}: {busy} busy");
            assert_eq!(textured > 0, rule == AdaptiveRule::Neighbourhood, "{rule}");
        }
    }

    #[test]
    fn stratified_offsets_put_one_point_in_each_stratum_inside_the_pixel() {
        let rule = Refinement {
            threshold: 0.1,
            transfer: Transfer::Srgb,
            depth: 3,
            rule: AdaptiveRule::Neighbourhood,
            jitter: 1.0,
            texture_n: 5,
            seed: 7,
        };
        let mut out = Vec::new();
        rule.texture_offsets(12, 34, &mut out);
        assert_eq!(out.len(), 25);
        let mut seen = [false; 25];
        for o in &out {
            assert!(o.x > 0.0 && o.x < 1.0 && o.y > 0.0 && o.y < 1.0, "{o}");
            seen[(o.y * 5.0) as usize * 5 + (o.x * 5.0) as usize] = true;
        }
        assert!(seen.iter().all(|&s| s));
    }
}
