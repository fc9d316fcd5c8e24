//! Where a pixel's camera rays go. Per-pixel patterns (centre, grid, random, jittered,
//! relaxed) give each pixel its own samples; lattice patterns (corners, adaptive) put
//! samples on pixel corners and edges that neighbouring pixels share. Every random number
//! comes from `math::hash`, a function of (pixel, sample index, dimension, seed).
//!
//! Filters and the film, which turn samples into pixels, live in `render`.

pub mod adaptive;
mod grid;
mod jittered;
mod random;
pub mod relaxed;
mod voronoi;

pub use crate::choices::{AdaptiveRule, AdaptiveSpec, SamplerKind};
pub use adaptive::Refinement;
pub use relaxed::RelaxedTile;

use crate::math::Vec2;
use crate::options::RenderOptions;

/// A pattern whose samples each belong to one pixel.
#[derive(Clone, Debug)]
pub enum PixelPattern {
    /// An n × n grid of sample points in each pixel.
    Grid {
        /// Points per axis.
        n: u32,
    },
    /// `count` uniformly random points per pixel.
    Random {
        /// Points per pixel.
        count: u32,
        /// Seed of the hash that places them.
        seed: u64,
    },
    /// One random point in each cell of an n × n grid.
    Jittered {
        /// Cells per axis.
        n: u32,
        /// Seed of the hash that places the points in their cells.
        seed: u64,
    },
    /// Blue-noise points from a tile relaxed by Lloyd's method.
    Relaxed(RelaxedTile),
}

impl PixelPattern {
    /// The per-pixel pattern of sampler `kind` with `n` samples per axis (where it takes
    /// a count), or None for a kind whose samples pixels share.
    pub fn new(kind: SamplerKind, n: u32, seed: u64) -> Option<PixelPattern> {
        Some(match kind {
            SamplerKind::Centre => PixelPattern::Grid { n: 1 },
            SamplerKind::Grid => PixelPattern::Grid { n },
            SamplerKind::Random => PixelPattern::Random { count: n * n, seed },
            SamplerKind::Jittered => PixelPattern::Jittered { n, seed },
            SamplerKind::Relaxed => PixelPattern::Relaxed(RelaxedTile::new(n, seed)),
            SamplerKind::Corners | SamplerKind::Adaptive => return None,
        })
    }

    /// Samples per pixel.
    pub fn count(&self) -> u32 {
        match self {
            PixelPattern::Grid { n } | PixelPattern::Jittered { n, .. } => n * n,
            PixelPattern::Random { count, .. } => *count,
            PixelPattern::Relaxed(tile) => tile.per_pixel(),
        }
    }

    /// Appends the offsets in (0, 1)² of pixel (px, py)'s samples, in sample order.
    pub fn offsets(&self, px: u32, py: u32, out: &mut Vec<Vec2>) {
        match self {
            PixelPattern::Grid { n } => grid::grid(*n, out),
            PixelPattern::Random { count, seed } => random::random(px, py, *count, *seed, out),
            PixelPattern::Jittered { n, seed } => jittered::jittered(px, py, *n, *seed, out),
            PixelPattern::Relaxed(tile) => tile.offsets(px, py, out),
        }
    }
}

/// The largest n with n² ≤ `count`: samples per axis of a square count.
pub fn floor_sqrt(count: u32) -> u32 {
    count.isqrt()
}

/// A sampler ready for one render.
#[derive(Clone, Debug)]
pub enum Sampler {
    /// Samples that belong to one pixel each.
    Pixel(PixelPattern),
    /// Pixel centres plus the (W+1)×(H+1) shared corners.
    Corners,
    /// The adaptive refinement of the pixel corners' lattice.
    Adaptive(Refinement),
}

impl Sampler {
    /// Builds the sampler the options ask for (relaxed sampling relaxes its tile here).
    pub fn new(options: &RenderOptions) -> Sampler {
        match options.sampler {
            SamplerKind::Corners => Sampler::Corners,
            SamplerKind::Adaptive => Sampler::Adaptive(Refinement::new(
                &options.adaptive,
                options.transfer,
                options.seed,
            )),
            kind => Sampler::Pixel(
                PixelPattern::new(kind, options.samples, options.seed)
                    .expect("every other kind is a per-pixel pattern"),
            ),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::floor_sqrt;

    #[test]
    fn floor_sqrt_is_exact_up_to_the_largest_count() {
        for (count, root) in [
            (0, 0),
            (1, 1),
            (3, 1),
            (4, 2),
            (24, 4),
            (25, 5),
            (65535 * 65535, 65535),
            (65535 * 65535 + 1, 65535),
            (u32::MAX, 65535),
        ] {
            assert_eq!(floor_sqrt(count), root, "{count}");
        }
    }
}
