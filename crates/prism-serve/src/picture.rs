//! A frame's pixels for the page: the image through its transfer (sRGB) into RGBA bytes,
//! or a heat map of the cost or density view; and the PNG file a page saves. The page
//! draws raw RGBA with `putImageData`: at 640×360 that is 0.9 MB a frame over the loopback,
//! against several milliseconds of the render's cores to encode a JPEG or PNG
//! (docs/viewer.md has the measurements).

use crate::controls::View;
use prism::render::{PixelTotals, Progressive};
use prism::transfer::Transfer;
use prism_io::output::heatmap::viridis;

/// The 8-bit encoding of a transfer as 255 thresholds: the level of a value is the number
/// of thresholds at or below it. Exactly `Transfer::encode8` (which is monotonic), found
/// once by bisection. A value's level starts from a table indexed by its bits (each entry
/// 2^16 floats, 1/128 of a binade, so rarely more than one threshold apart) and steps past
/// the thresholds at or below it: a load and a comparison or two a channel, where a binary
/// search of the thresholds took eight dependent branches (3-5 ms of a 640×360 frame on
/// two cores) and a power function more.
pub(crate) struct Encoder {
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

impl Encoder {
    pub(crate) fn new(transfer: Transfer) -> Self {
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
        Encoder {
            transfer,
            thresholds,
            start,
        }
    }

    #[inline]
    fn encode8(&self, v: f32) -> u8 {
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
}

/// The RGBA bytes of what `view` shows of `image`. `encoder` is replaced when the image's
/// transfer differs from its own. The image's encoding runs on the render's threads; a
/// heat map reads its values there and scales and colours them in one pass here.
pub(crate) fn rgba(image: &Progressive, view: View, encoder: &mut Encoder) -> (u32, u32, Vec<u8>) {
    let (width, height) = image.size();
    let frames = image.samples().max(1) as u64;
    let pixels = match view {
        View::Cost => heat(image, |p| ratio(p.node_visits, p.camera_rays)),
        View::Density => heat(image, |p| ratio(p.rays, frames)),
        View::Image => {
            if encoder.transfer != image.transfer() {
                *encoder = Encoder::new(image.transfer());
            }
            let encoder = &*encoder;
            let mut out = vec![[0u8; 4]; image.pixels().len()];
            image.map_pixels(&mut out, |c, _| {
                [
                    encoder.encode8(c.x),
                    encoder.encode8(c.y),
                    encoder.encode8(c.z),
                    255,
                ]
            });
            out
        }
    };
    (width, height, pixels.into_flattened())
}

fn ratio(a: u64, b: u64) -> f32 {
    if b == 0 {
        0.0
    } else {
        (a as f64 / b as f64) as f32
    }
}

/// A heat map of `value(pixel)` from 0 to its largest value, in viridis.
fn heat(image: &Progressive, value: impl Fn(&PixelTotals) -> f32 + Sync) -> Vec<[u8; 4]> {
    let mut values = vec![0.0f32; image.pixels().len()];
    image.map_pixels(&mut values, |_, p| value(p));
    let top = values
        .iter()
        .copied()
        .fold(0.0f32, f32::max)
        .max(f32::MIN_POSITIVE);
    values
        .iter()
        .map(|v| {
            let [r, g, b] = viridis(v / top);
            [r, g, b, 255]
        })
        .collect()
}

/// The PNG file of what the page shows: the image exactly as `prism render` writes it,
/// or the view's heat map.
pub(crate) fn png(image: &Progressive, view: View) -> Result<Vec<u8>, String> {
    let (width, height) = image.size();
    let rgb = match view {
        View::Image => prism_io::output::to_rgb8(&image.film()),
        _ => {
            let mut encoder = Encoder::new(Transfer::Srgb);
            let (_, _, rgba) = rgba(image, view, &mut encoder);
            rgba.chunks_exact(4)
                .flat_map(|p| [p[0], p[1], p[2]])
                .collect()
        }
    };
    prism_io::output::png_rgb8_bytes(&rgb, width, height)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_threshold_encoder_is_the_transfers_own() {
        for transfer in [Transfer::Srgb, Transfer::Display] {
            let e = Encoder::new(transfer);
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
