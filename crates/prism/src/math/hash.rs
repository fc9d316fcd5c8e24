//! The one source of randomness in a render: a hash of (pixel, sample index, dimension,
//! seed). Nothing carries state from one sample to the next, so a pixel's samples do not
//! depend on which thread renders it, in which order, or in which tile.

/// SplitMix64's finaliser: a bijection on u64 whose output bits each depend on every input
/// bit (Steele, Lea and Flood 2014).
#[inline]
fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// 64 well-mixed bits for one random decision. `dim` separates the decisions of one
/// sample (x jitter, y jitter, pattern choice…); callers name their dimensions.
#[inline]
pub fn hash(px: u32, py: u32, index: u32, dim: u32, seed: u64) -> u64 {
    let h = mix(seed ^ 0x9E37_79B9_7F4A_7C15);
    let h = mix(h ^ (px as u64 | (py as u64) << 32));
    mix(h ^ (index as u64 | (dim as u64) << 32))
}

/// The random numbers of one sample, drawn by dimension: `hash` with the pixel, sample
/// index and seed mixed in once, so that a path tracer's dozens of numbers per sample cost
/// one mix each. `Stream::new(px, py, i, seed).uniform(d)` equals `uniform(px, py, i, d, seed)`.
#[derive(Clone, Copy, Debug)]
pub struct Stream {
    key: u64,
    index: u32,
}

impl Stream {
    /// The stream of sample `index` of pixel (px, py).
    #[inline]
    pub fn new(px: u32, py: u32, index: u32, seed: u64) -> Stream {
        let h = mix(seed ^ 0x9E37_79B9_7F4A_7C15);
        Stream {
            key: mix(h ^ (px as u64 | (py as u64) << 32)),
            index,
        }
    }

    /// The number of dimension `dim`, strictly inside (0, 1).
    #[inline]
    pub fn uniform(&self, dim: u32) -> f32 {
        to_open_unit(mix(self.key ^ (self.index as u64 | (dim as u64) << 32)))
    }
}

/// A uniform number strictly inside (0, 1): 2²³ equally spaced values with a half-step
/// margin at both ends, so a sample never lands on a pixel border.
#[inline]
pub fn uniform(px: u32, py: u32, index: u32, dim: u32, seed: u64) -> f32 {
    to_open_unit(hash(px, py, index, dim, seed))
}

/// The top 23 bits of `bits` as a number in (0, 1); exact in f32.
#[inline]
pub fn to_open_unit(bits: u64) -> f32 {
    ((bits >> 41) as f32 + 0.5) * (1.0 / 8_388_608.0)
}

/// The largest f32 below 1: sample offsets are clamped to it after arithmetic that could
/// round up onto the border.
pub const BELOW_ONE: f32 = 1.0 - f32::EPSILON / 2.0;

/// Clamps a pixel offset into the open unit interval.
#[inline]
pub fn inside_unit(x: f32) -> f32 {
    x.clamp(f32::EPSILON / 2.0, BELOW_ONE)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uniform_stays_strictly_inside_the_unit_interval() {
        assert!(to_open_unit(0) > 0.0);
        assert!(to_open_unit(u64::MAX) < 1.0);
        assert_eq!(to_open_unit(u64::MAX), 1.0 - 1.0 / 16_777_216.0);
    }

    #[test]
    fn uniform_fills_sixteen_bins_evenly() {
        // χ² over 16 bins of 64k draws; 15 degrees of freedom, p = 0.001 at 37.7.
        let mut bins = [0u32; 16];
        let n = 1 << 16;
        for i in 0..n {
            let u = uniform(i % 256, i / 256, 7, 1, 42);
            bins[(u * 16.0) as usize] += 1;
        }
        let expected = n as f64 / 16.0;
        let chi2: f64 = bins
            .iter()
            .map(|&b| (b as f64 - expected).powi(2) / expected)
            .sum();
        assert!(chi2 < 37.7, "χ² = {chi2}: bins {bins:?}");
    }

    #[test]
    fn a_stream_draws_the_numbers_of_uniform() {
        for (px, py, i, d, seed) in [(0, 0, 0, 0, 0), (3, 4, 5, 6, 7), (u32::MAX, 1, 2, 99, 42)] {
            assert_eq!(
                Stream::new(px, py, i, seed).uniform(d),
                uniform(px, py, i, d, seed)
            );
        }
    }

    #[test]
    fn every_key_changes_the_number() {
        let base = hash(3, 4, 5, 6, 7);
        for other in [
            hash(4, 4, 5, 6, 7),
            hash(3, 5, 5, 6, 7),
            hash(3, 4, 6, 6, 7),
            hash(3, 4, 5, 7, 7),
            hash(3, 4, 5, 6, 8),
            hash(4, 3, 5, 6, 7),
        ] {
            assert_ne!(base, other);
        }
    }
}
