//! Where a pixel's camera rays go: the sampler's name (`--sampler`, the scene file's
//! `sampler`) and the adaptive sampler's five settings as one value (their keys, ranges
//! and help are rows of the settings table, `options::settings`). The patterns themselves
//! live in `sampling`, the passes that trace them in `render`.

use serde::{Deserialize, Serialize};

/// Largest accepted adaptive depth: 64×64 squares per pixel.
pub const MAX_DEPTH: u32 = 6;
/// Largest accepted samples per axis of the stratified pass: 32×32 per textured pixel.
pub const MAX_TEXTURE_N: u32 = 32;
/// The adaptive sampler's default split threshold: a tenth of the display range.
pub const DEFAULT_ADAPTIVE_THRESHOLD: f32 = 0.1;
/// The adaptive sampler's default levels of splitting below the pixel.
pub const DEFAULT_ADAPTIVE_DEPTH: u32 = 3;
/// Samples of the stratified pass in a textured pixel: with threshold 0.1 and depth 3,
/// the setting that reaches 16-spp jittered error with under a third of its rays on the
/// checkerboard and the default scene (docs/sampling.md).
pub const DEFAULT_ADAPTIVE_TEXTURE_SPP: u32 = 25;

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

/// When a pixel splits.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum AdaptiveRule {
    /// Only its own four corners decide (POV-Ray's +AM2).
    Corners,
    /// The corners of its 3×3 neighbourhood decide, and texture forces refinement.
    #[default]
    Neighbourhood,
}

named_kinds! {
    AdaptiveRule, "adaptive rule" {
        Corners => "corners",
        Neighbourhood => "neighbourhood",
    }
    aliases { "neighborhood" => "neighbourhood" }
}

/// The adaptive sampler's settings, as the scene file's `adaptive_*` keys and the
/// command line's `--adaptive-*` flags set them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AdaptiveSpec {
    /// A square splits when, in some channel, its corners' display-encoded (sRGB) values
    /// span more than this (0 to 1).
    pub threshold: f32,
    /// Levels of splitting below the pixel (0 to 6); d allows 2^d × 2^d squares per pixel.
    pub depth: u32,
    /// What decides that a pixel splits (its own corners, as POV-Ray, or its
    /// neighbourhood's).
    pub rule: AdaptiveRule,
    /// 0 traces points exactly on the lattice (POV-Ray's +AM2 without jitter); 1 anywhere
    /// in their lattice cell (pixel corners within ±¼ pixel).
    pub jitter: f32,
    /// Samples (a square number) that a textured pixel, one whose neighbourhood shows
    /// detail finer than the pixels, takes in a stratified (jittered) pass instead of being
    /// subdivided; 0 subdivides it like any other pixel. Only the neighbourhood rule
    /// detects texture.
    pub texture_spp: u32,
}

impl Default for AdaptiveSpec {
    fn default() -> Self {
        AdaptiveSpec {
            threshold: DEFAULT_ADAPTIVE_THRESHOLD,
            depth: DEFAULT_ADAPTIVE_DEPTH,
            rule: AdaptiveRule::Neighbourhood,
            jitter: 1.0,
            texture_spp: DEFAULT_ADAPTIVE_TEXTURE_SPP,
        }
    }
}

impl AdaptiveSpec {
    /// Samples per axis of the stratified pass.
    pub fn texture_n(&self) -> u32 {
        self.texture_spp.isqrt()
    }

    /// Checks ranges; the messages name the settings as the scene file spells them
    /// (`adaptive_depth`, …), which the command line's flags follow.
    pub fn validate(&self) -> Result<(), String> {
        if !(0.0..=1.0).contains(&self.threshold) {
            return Err(format!(
                "adaptive_threshold must be between 0 and 1, got {}",
                self.threshold
            ));
        }
        if !(0.0..=1.0).contains(&self.jitter) {
            return Err(format!(
                "adaptive_jitter must be between 0 and 1, got {}",
                self.jitter
            ));
        }
        if self.depth > MAX_DEPTH {
            return Err(format!(
                "adaptive_depth must be between 0 and {MAX_DEPTH}, got {}",
                self.depth
            ));
        }
        let n = self.texture_n();
        if n * n != self.texture_spp || n > MAX_TEXTURE_N {
            return Err(format!(
                "adaptive_texture_spp must be 0 or a square number up to {}, got {}",
                MAX_TEXTURE_N * MAX_TEXTURE_N,
                self.texture_spp
            ));
        }
        Ok(())
    }

    /// The settings in words, for reports.
    pub fn summary(&self) -> String {
        format!(
            "threshold {}, depth {}, {} rule, jitter {}, texture {} spp",
            self.threshold, self.depth, self.rule, self.jitter, self.texture_spp
        )
    }
}
