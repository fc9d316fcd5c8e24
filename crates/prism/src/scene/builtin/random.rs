//! Reproducible random numbers for procedural built-in scenes: the same hash the samplers
//! use, so a scene is identical on every run and platform.

use crate::math::hash;

/// Seed that keeps scene randomness apart from sampling's.
const SCENE_SEED: u64 = 0x5eed_5ce7e;

/// A number in (0, 1) for item `i` and dimension `dim`.
pub(super) fn unit(i: u32, dim: u32) -> f32 {
    hash::uniform(i, 0, 0, dim, SCENE_SEED)
}
