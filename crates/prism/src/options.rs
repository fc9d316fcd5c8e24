//! Render options: the one home of every setting. The scene file, the CLI and the library
//! API all fill this struct; anything they leave out keeps the default documented here.

use crate::accel::AccelKind;
use serde::{Deserialize, Serialize};

/// Largest accepted `max_depth`.
pub const MAX_DEPTH_LIMIT: u32 = 256;

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RenderOptions {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Samples per pixel along each axis: n gives an n×n grid of subpixel centres
    /// (1 = one ray through the pixel centre).
    pub samples: u32,
    /// Maximum ray-tree depth; the eye ray has depth 1, so 5 allows four bounces.
    pub max_depth: u32,
    /// Adaptive depth control: a reflected or refracted ray whose weight in the pixel (the
    /// product of reflection and transmission weights from the eye) is below this is not
    /// traced. 0 traces every ray up to `max_depth`.
    pub min_weight: f32,
    /// Follow the SPD testing procedure's ray-tree rules (Haines, SPD rules 8 and 9): every
    /// hit on a surface with Ks > 0 or T > 0 spawns a reflection ray, and every hit on a
    /// transmitter a refraction ray, whatever their weight; `min_weight` is ignored.
    pub spd_rules: bool,
    /// Worker threads; 0 uses every core.
    pub threads: usize,
    /// Seed for every random decision (none yet with regular sampling; kept so a render is
    /// a pure function of scene, options and seed).
    pub seed: u64,
    /// The acceleration structure for ray queries.
    pub accel: AccelKind,
    /// Edge length of the square tiles handed to worker threads.
    pub tile_size: u32,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            width: 640,
            height: 480,
            samples: 1,
            max_depth: 5,
            min_weight: 0.0,
            spd_rules: false,
            threads: 0,
            seed: 0,
            accel: AccelKind::Bvh,
            tile_size: 16,
        }
    }
}

impl RenderOptions {
    /// Checks ranges; the message names the option as the CLI and scene file spell it.
    pub fn validate(&self) -> Result<(), String> {
        if self.width == 0 || self.height == 0 {
            return Err(format!(
                "image size must be at least 1×1, got {}×{}",
                self.width, self.height
            ));
        }
        if self.width > 65536 || self.height > 65536 {
            return Err(format!(
                "image size {}×{} is larger than the 65536×65536 limit",
                self.width, self.height
            ));
        }
        if self.samples == 0 || self.samples > 64 {
            return Err(format!(
                "samples must be between 1 and 64 per axis, got {}",
                self.samples
            ));
        }
        // The integrator recurses once per bounce; beyond this, contributions are far below
        // 8-bit precision anyway and deep recursion would exhaust worker stacks.
        if self.max_depth == 0 || self.max_depth > MAX_DEPTH_LIMIT {
            return Err(format!(
                "max_depth must be between 1 (the eye ray alone) and {MAX_DEPTH_LIMIT}, got {}",
                self.max_depth
            ));
        }
        if !(0.0..=1.0).contains(&self.min_weight) {
            return Err(format!(
                "min_weight must be between 0 and 1, got {}",
                self.min_weight
            ));
        }
        if self.tile_size == 0 {
            return Err("tile_size must be at least 1".into());
        }
        Ok(())
    }
}
