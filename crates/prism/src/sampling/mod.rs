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

pub use adaptive::{AdaptiveRule, Refinement};
pub use relaxed::RelaxedTile;

use crate::math::Vec2;
use crate::options::RenderOptions;
use serde::{Deserialize, Serialize};

/// The sampling pattern, as `--sampler` and the scene file's `sampler` name it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SamplerKind {
    /// One ray through the pixel centre.
    #[serde(alias = "center")]
    Centre,
    /// n×n subpixel centres.
    #[default]
    Grid,
    /// The centre and the four corners, corners shared with the neighbours.
    Corners,
    /// n² uniform random points.
    Random,
    /// n×n strata with one random point each.
    Jittered,
    /// Jittered points relaxed toward blue noise.
    Relaxed,
    /// Corner rays refined where they differ (Whitted; POV-Ray's +AM2).
    Adaptive,
}

named_kinds! {
    SamplerKind, "sampler" {
        Centre => "centre",
        Grid => "grid",
        Corners => "corners",
        Random => "random",
        Jittered => "jittered",
        Relaxed => "relaxed",
        Adaptive => "adaptive",
    }
    aliases { "center" => "centre" }
}

impl SamplerKind {
    /// Whether the pattern takes `samples` (n per axis, n² per pixel); the others choose
    /// their own count.
    pub fn uses_sample_count(self) -> bool {
        matches!(
            self,
            SamplerKind::Grid | SamplerKind::Random | SamplerKind::Jittered | SamplerKind::Relaxed
        )
    }
}

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
        let n = options.samples;
        let seed = options.seed;
        match options.sampler {
            SamplerKind::Centre => Sampler::Pixel(PixelPattern::Grid { n: 1 }),
            SamplerKind::Grid => Sampler::Pixel(PixelPattern::Grid { n }),
            SamplerKind::Random => Sampler::Pixel(PixelPattern::Random { count: n * n, seed }),
            SamplerKind::Jittered => Sampler::Pixel(PixelPattern::Jittered { n, seed }),
            SamplerKind::Relaxed => {
                Sampler::Pixel(PixelPattern::Relaxed(RelaxedTile::new(n, seed)))
            }
            SamplerKind::Corners => Sampler::Corners,
            SamplerKind::Adaptive => Sampler::Adaptive(Refinement {
                threshold: options.adaptive_threshold,
                transfer: options.transfer,
                depth: options.adaptive_depth,
                rule: options.adaptive_rule,
                jitter: options.adaptive_jitter,
                texture_n: floor_sqrt(options.adaptive_texture_spp),
                seed,
            }),
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
