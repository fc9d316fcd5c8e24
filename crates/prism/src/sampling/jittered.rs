//! Jittered (stratified) sampling: the pixel cut into n×n strata with one uniform random
//! point in each. Keeps the grid's even coverage and turns its aliasing into noise.

use crate::math::hash::uniform;
use crate::math::Vec2;

/// Hash dimensions of the jitter; distinct from the random pattern's so that the two
/// patterns do not share numbers.
const DIM_X: u32 = 2;
const DIM_Y: u32 = 3;

pub(super) fn jittered(px: u32, py: u32, n: u32, seed: u64, out: &mut Vec<Vec2>) {
    for j in 0..n {
        for i in 0..n {
            let k = j * n + i;
            out.push(Vec2::new(
                in_stratum(i, n, uniform(px, py, k, DIM_X, seed)),
                in_stratum(j, n, uniform(px, py, k, DIM_Y, seed)),
            ));
        }
    }
}

/// The point a fraction `u` ∈ (0, 1) into stratum `i` of `n`, kept inside the stratum
/// after rounding (i + u could round up onto the next stratum's border).
fn in_stratum(i: u32, n: u32, u: f32) -> f32 {
    let lo = i as f32 / n as f32;
    let hi = (i + 1) as f32 / n as f32;
    let below_hi = f32::from_bits(hi.to_bits() - 1);
    (lo + u * (hi - lo))
        .clamp(lo, below_hi)
        .max(f32::EPSILON / 2.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_point_at_the_top_of_a_stratum_stays_in_it() {
        for n in 1..40 {
            for i in 0..n {
                let x = in_stratum(i, n, crate::math::hash::BELOW_ONE);
                let (lo, hi) = (i as f32 / n as f32, (i + 1) as f32 / n as f32);
                assert!(x >= lo && x < hi, "n {n} stratum {i}: {x}");
                assert!(x > 0.0 && x < 1.0);
            }
        }
    }
}
