//! PNG's 8-bit levels of film values without a power function per channel: the same
//! bytes as `Transfer::encode8`, found from a table (a large image's levels took longer
//! than its PNG compression, and the live viewer encodes every frame).

use prism::transfer::Transfer;

/// The 8-bit encoding of a transfer as 255 thresholds: the level of a value is the number
/// of thresholds at or below it. Exactly `Transfer::encode8` (which is monotonic), found
/// once by bisection. A value's level starts from a table indexed by its bits (each entry
/// 2^16 floats, 1/128 of a binade, so rarely more than one threshold apart) and steps past
/// the thresholds at or below it: a load and a comparison or two a channel, where a binary
/// search of the thresholds took eight dependent branches (3-5 ms of a 640×360 frame on
/// two cores) and a power function more.
pub struct Levels {
    transfer: Transfer,
    thresholds: [f32; 255],
    /// Per bucket of the non-negative floats below 2.0 by their bits, the level of its
    /// smallest value.
    start: Box<[u8]>,
}

/// Bits of a float below its bucket's index.
const BUCKET_SHIFT: u32 = 16;
/// The buckets of the non-negative floats below 2.0 (whose bits are below 2.0's); every
/// threshold is at most 2.0, so every value from 2.0 up has level 255.
const BUCKETS: usize = (0x4000_0000 >> BUCKET_SHIFT) as usize;

impl Levels {
    /// The table of `transfer` (a few thousand evaluations of it).
    pub fn new(transfer: Transfer) -> Self {
        let mut thresholds = [0.0; 255];
        for (k, t) in thresholds.iter_mut().enumerate() {
            let level = k as u8 + 1;
            // Positive floats order as their bits do: bisect the bits for the smallest
            // value that encodes to `level` or more.
            let (mut lo, mut hi) = (0u32, 2.0f32.to_bits());
            while lo < hi {
                let mid = lo + (hi - lo) / 2;
                if transfer.encode8(f32::from_bits(mid)) >= level {
                    hi = mid;
                } else {
                    lo = mid + 1;
                }
            }
            *t = f32::from_bits(lo);
        }
        let start = (0..BUCKETS as u32)
            .map(|b| {
                let v = f32::from_bits(b << BUCKET_SHIFT);
                thresholds.partition_point(|&t| t <= v) as u8
            })
            .collect();
        Levels {
            transfer,
            thresholds,
            start,
        }
    }

    /// `Transfer::encode8(v)` of this table's transfer, bit for bit.
    #[inline]
    pub fn encode8(&self, v: f32) -> u8 {
        // Negative values, -0.0 and NaN index past the table, as do values from 2.0 up.
        let Some(&start) = self.start.get((v.to_bits() >> BUCKET_SHIFT) as usize) else {
            return if v >= 2.0 { 255 } else { 0 };
        };
        let mut level = start;
        while level < 255 && self.thresholds[level as usize] <= v {
            level += 1;
        }
        level
    }

    /// The transfer this table encodes.
    pub fn transfer(&self) -> Transfer {
        self.transfer
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_threshold_encoder_is_the_transfers_own() {
        for transfer in [Transfer::Srgb, Transfer::Display] {
            let e = Levels::new(transfer);
            let mut v = -0.1f32;
            while v < 1.2 {
                assert_eq!(e.encode8(v), transfer.encode8(v), "{transfer:?} {v}");
                v += 1.0e-5;
            }
            for t in e.thresholds {
                assert_eq!(e.encode8(t), transfer.encode8(t));
                let below = f32::from_bits(t.to_bits() - 1);
                assert_eq!(e.encode8(below), transfer.encode8(below));
            }
            assert_eq!(e.encode8(f32::NAN), transfer.encode8(f32::NAN));
            assert_eq!(e.encode8(f32::INFINITY), 255);
            // Every bucket's first and last float, and a stride through all of them, up
            // past 2.0 where the table ends; the signs and specials.
            let mut bits = 0u32;
            while bits < 0x4080_0000 {
                for b in [bits, bits.saturating_sub(1), bits | 0xffff] {
                    let v = f32::from_bits(b);
                    assert_eq!(e.encode8(v), transfer.encode8(v), "{transfer:?} {v:e}");
                }
                bits += 0x1_0000;
            }
            for b in (0..0x4080_0000u32).step_by(997) {
                let v = f32::from_bits(b);
                assert_eq!(e.encode8(v), transfer.encode8(v), "{transfer:?} {v:e}");
            }
            for v in [
                -0.0,
                -1e-30,
                -1.0,
                f32::NEG_INFINITY,
                -f32::NAN,
                f32::MAX,
                2.0,
                1.0,
            ] {
                assert_eq!(e.encode8(v), transfer.encode8(v), "{transfer:?} {v:e}");
            }
        }
    }
}
