//! Uniform random samples: each point anywhere in the pixel, independent of the others.
//! No aliasing, but clumps and holes make it the noisiest pattern.

use crate::math::hash::uniform;
use crate::math::Vec2;

/// Hash dimensions of the random pattern.
const DIM_X: u32 = 0;
const DIM_Y: u32 = 1;

pub(super) fn random(px: u32, py: u32, count: u32, seed: u64, out: &mut Vec<Vec2>) {
    for k in 0..count {
        out.push(Vec2::new(
            uniform(px, py, k, DIM_X, seed),
            uniform(px, py, k, DIM_Y, seed),
        ));
    }
}
