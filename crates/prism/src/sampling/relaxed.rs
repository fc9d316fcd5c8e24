//! Relaxed sampling: jittered points moved by a few steps of Lloyd relaxation toward a
//! blue-noise layout, with every point kept in its own pixel.
//!
//! The relaxation runs once per render over a tile of K×K pixels that wraps around (a
//! torus), so points repel each other across pixel borders and across the tile's edges: the
//! per-pixel sets join without seams and the tile repeats without gaps or clumps. Each
//! step moves every point to the centroid of its Voronoi cell, or, when that lies beyond
//! its pixel, to the centroid of the part of the cell inside the pixel; so every pixel
//! keeps exactly n×n points. To hide the K-pixel period, each K×K block of
//! the image shows the tile shifted by whole pixels and mirrored or transposed, chosen by
//! the hash of the block.

use super::jittered::jittered;
use super::voronoi::Cell;
use crate::math::hash::{hash, inside_unit};
use crate::math::Vec2;
use glam::DVec2;
use rayon::prelude::*;

/// About this many points are relaxed, whatever the sample count: the tile is as large
/// as that allows, between `MIN_SIDE` and `MAX_SIDE` pixels.
const TILE_POINTS: u32 = 8192;
const MIN_SIDE: u32 = 4;
const MAX_SIDE: u32 = 64;
/// Lloyd steps. Few on purpose: full convergence crystallises into hexagonal patches, which
/// alias like a grid; a few steps remove the clumps of jittering and keep the randomness.
pub const LLOYD_STEPS: u32 = 2;
/// Hash dimension choosing each block's shift and symmetry.
const DIM_BLOCK: u32 = 6;
/// Keeps the tile's jitter apart from the jittered pattern's numbers for the same seed.
const TILE_SALT: u64 = 0x5EED_0F7E_1A8E_D000;

/// A tile of blue-noise points, relaxed once by Lloyd's method and laid over the image with a shift
/// and a symmetry per block, so no repetition shows.
#[derive(Clone, Debug)]
pub struct RelaxedTile {
    /// Points per pixel (n×n).
    per_pixel: u32,
    /// Tile side K in pixels.
    side: u32,
    /// Offsets in (0, 1)² of the tile's pixels, row-major, `per_pixel` each.
    offsets: Vec<Vec2>,
    seed: u64,
}

impl RelaxedTile {
    /// Relaxes n×n points per pixel over a tile; a pure function of `n` and `seed`.
    pub fn new(n: u32, seed: u64) -> Self {
        let per_pixel = n * n;
        let side = ((TILE_POINTS / per_pixel) as f64)
            .sqrt()
            .floor()
            .clamp(MIN_SIDE as f64, MAX_SIDE as f64) as u32;
        let mut positions = Vec::with_capacity((side * side * per_pixel) as usize);
        let mut pixel = Vec::new();
        for ty in 0..side {
            for tx in 0..side {
                pixel.clear();
                jittered(tx, ty, n, seed ^ TILE_SALT, &mut pixel);
                positions.extend(
                    pixel
                        .iter()
                        .map(|o| DVec2::new(tx as f64 + o.x as f64, ty as f64 + o.y as f64)),
                );
            }
        }
        let mut relax = Relaxation::new(side, per_pixel);
        for _ in 0..LLOYD_STEPS {
            positions = relax.step(&positions);
        }
        let offsets = positions
            .iter()
            .map(|p| {
                Vec2::new(
                    inside_unit(p.x.fract() as f32),
                    inside_unit(p.y.fract() as f32),
                )
            })
            .collect();
        RelaxedTile {
            per_pixel,
            side,
            offsets,
            seed,
        }
    }

    /// Points per pixel.
    pub fn per_pixel(&self) -> u32 {
        self.per_pixel
    }

    /// Tile side in pixels.
    pub fn side(&self) -> u32 {
        self.side
    }

    /// The tile's points in tile coordinates (pixels), as relaxed: for tests and figures.
    pub fn tile_points(&self) -> Vec<Vec2> {
        let n = self.per_pixel as usize;
        self.offsets
            .iter()
            .enumerate()
            .map(|(i, o)| {
                let p = (i / n) as u32;
                Vec2::new((p % self.side) as f32 + o.x, (p / self.side) as f32 + o.y)
            })
            .collect()
    }

    /// The offsets of the tile's own pixel (tx, ty), as relaxed.
    pub fn tile_pixel(&self, tx: u32, ty: u32) -> &[Vec2] {
        let start = ((ty * self.side + tx) * self.per_pixel) as usize;
        &self.offsets[start..start + self.per_pixel as usize]
    }

    /// Appends pixel (px, py)'s offsets: the tile pixel its block maps it to, with the
    /// block's mirror or transposition applied to the offsets.
    pub fn offsets(&self, px: u32, py: u32, out: &mut Vec<Vec2>) {
        let k = self.side;
        let h = hash(px / k, py / k, 0, DIM_BLOCK, self.seed);
        let (sx, sy) = ((h % k as u64) as u32, ((h >> 16) % k as u64) as u32);
        let (flip_x, flip_y, transpose) = (h >> 32 & 1 == 1, h >> 33 & 1 == 1, h >> 34 & 1 == 1);
        // Destination pixel -> source pixel: shift, transpose, then mirror.
        let (mut lx, mut ly) = ((px % k + sx) % k, (py % k + sy) % k);
        if transpose {
            std::mem::swap(&mut lx, &mut ly);
        }
        if flip_x {
            lx = k - 1 - lx;
        }
        if flip_y {
            ly = k - 1 - ly;
        }
        let start = ((ly * k + lx) * self.per_pixel) as usize;
        // Source offset -> destination offset: the inverse map, mirror then transpose.
        for o in &self.offsets[start..start + self.per_pixel as usize] {
            let mut o = *o;
            if flip_x {
                o.x = inside_unit(1.0 - o.x);
            }
            if flip_y {
                o.y = inside_unit(1.0 - o.y);
            }
            if transpose {
                o = Vec2::new(o.y, o.x);
            }
            out.push(o);
        }
    }
}

/// One Lloyd step over the torus, with a bucket grid of about one point per bucket to find
/// neighbours nearest first.
struct Relaxation {
    side: u32,
    per_pixel: u32,
    /// Buckets per pixel along each axis.
    per_axis: u32,
    bucket_start: Vec<u32>,
    bucket_points: Vec<u32>,
}

impl Relaxation {
    fn new(side: u32, per_pixel: u32) -> Self {
        Relaxation {
            side,
            per_pixel,
            per_axis: (per_pixel as f64).sqrt().ceil() as u32,
            bucket_start: Vec::new(),
            bucket_points: Vec::new(),
        }
    }

    fn buckets(&self) -> u32 {
        self.side * self.per_axis
    }

    fn bucket_of(&self, p: DVec2) -> (u32, u32) {
        let b = self.buckets();
        let f = self.per_axis as f64;
        (((p.x * f) as u32).min(b - 1), ((p.y * f) as u32).min(b - 1))
    }

    fn step(&mut self, positions: &[DVec2]) -> Vec<DVec2> {
        self.fill_buckets(positions);
        let this = &*self;
        positions
            .par_iter()
            .enumerate()
            .map_init(Cell::default, |cell, (i, &p)| {
                this.centroid(positions, i, p, cell)
            })
            .collect()
    }

    /// Counting sort of the points into buckets.
    fn fill_buckets(&mut self, positions: &[DVec2]) {
        let b = self.buckets() as usize;
        let index = |s: &Self, p: DVec2| {
            let (x, y) = s.bucket_of(p);
            y as usize * b + x as usize
        };
        let mut count = vec![0u32; b * b + 1];
        for &p in positions {
            count[index(self, p) + 1] += 1;
        }
        for i in 1..count.len() {
            count[i] += count[i - 1];
        }
        let mut fill = count.clone();
        let mut points = vec![0u32; positions.len()];
        for (i, &p) in positions.iter().enumerate() {
            let k = index(self, p);
            points[fill[k] as usize] = i as u32;
            fill[k] += 1;
        }
        self.bucket_start = count;
        self.bucket_points = points;
    }

    /// Point `i`'s new position: the centroid of its Voronoi cell, kept in its pixel. The
    /// cell is not cut to the pixel: that would push every point away from the borders and
    /// print the pixel grid into the pattern.
    fn centroid(&self, positions: &[DVec2], i: usize, p: DVec2, cell: &mut Cell) -> DVec2 {
        let pixel = (i as u32 / self.per_pixel) as usize;
        let k = self.side as usize;
        let origin = DVec2::new((pixel % k) as f64, (pixel / k) as f64);
        // No Voronoi cell reaches farther than the pixel's diagonal from its point.
        cell.rect(DVec2::splat(-2.0), DVec2::splat(2.0));
        let b = self.buckets() as i64;
        let period = self.side as f64;
        let (bx, by) = self.bucket_of(p);
        let max_ring = (b - 1) / 2;
        for ring in 0..=max_ring {
            for dy in -ring..=ring {
                for dx in -ring..=ring {
                    if dx.abs().max(dy.abs()) != ring {
                        continue;
                    }
                    let x = (bx as i64 + dx).rem_euclid(b) as usize;
                    let y = (by as i64 + dy).rem_euclid(b) as usize;
                    let bucket = y * b as usize + x;
                    let (s, e) = (self.bucket_start[bucket], self.bucket_start[bucket + 1]);
                    for &j in &self.bucket_points[s as usize..e as usize] {
                        if j as usize == i {
                            continue;
                        }
                        let mut d = positions[j as usize] - p;
                        d -= (d / period).round() * period;
                        cell.clip_to_bisector(d);
                    }
                }
            }
            // Points beyond this ring are at least `ring` buckets away.
            if 2.0 * cell.radius() <= ring as f64 / self.per_axis as f64 {
                break;
            }
        }
        let Some(c) = cell.centroid() else {
            return p;
        };
        let (lo, hi) = (origin - p, origin + DVec2::ONE - p);
        if c.cmpgt(lo).all() && c.cmplt(hi).all() {
            return p + c;
        }
        // The centroid lies beyond the pixel: take the centroid of the part of the cell
        // inside it. Clamping instead would pile points up on the borders, and cutting
        // every cell to its pixel would push all points away from them.
        for q in [
            DVec2::new(2.0 * hi.x, 0.0),
            DVec2::new(2.0 * lo.x, 0.0),
            DVec2::new(0.0, 2.0 * hi.y),
            DVec2::new(0.0, 2.0 * lo.y),
        ] {
            cell.clip_to_bisector(q);
        }
        cell.centroid().map_or(p, |c| p + c)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_pixel_keeps_its_points_inside() {
        let tile = RelaxedTile::new(3, 1);
        assert_eq!(tile.offsets.len() as u32, tile.side * tile.side * 9);
        assert!(tile
            .offsets
            .iter()
            .all(|o| o.x > 0.0 && o.x < 1.0 && o.y > 0.0 && o.y < 1.0));
    }

    #[test]
    fn a_pure_function_of_count_and_seed() {
        let a = RelaxedTile::new(2, 5);
        let b = RelaxedTile::new(2, 5);
        let c = RelaxedTile::new(2, 6);
        assert_eq!(a.offsets, b.offsets);
        assert_ne!(a.offsets, c.offsets);
    }
}
