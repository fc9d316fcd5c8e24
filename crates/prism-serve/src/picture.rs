//! A frame's pixels for the page: the image through its transfer (sRGB) into RGBA bytes,
//! or a heat map of the cost or density view; and the PNG file a page saves. The page
//! draws raw RGBA with `putImageData`: at 640×360 that is 0.9 MB a frame over the loopback,
//! against several milliseconds of the render's cores to encode a JPEG or PNG
//! (docs/viewer.md has the measurements).

use crate::controls::View;
use crate::source::{FrameSource, WorkTotals};
use prism::render::Film;
use prism::transfer::Transfer;
use prism_io::output::heatmap::viridis;

/// The 8-bit encoding of a transfer as 255 thresholds: the level of a value is the number
/// of thresholds at or below it. Exactly `Transfer::encode8` (which is monotonic), found
/// once by bisection, then eight comparisons a channel instead of a power function.
pub(crate) struct Encoder {
    transfer: Transfer,
    thresholds: [f32; 255],
}

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
        Encoder {
            transfer,
            thresholds,
        }
    }

    #[inline]
    fn encode8(&self, v: f32) -> u8 {
        self.thresholds.partition_point(|&t| t <= v) as u8
    }
}

/// The RGBA bytes of what `view` shows of `source`'s image. `encoder` is replaced when
/// the film's transfer differs from its own.
pub(crate) fn rgba(
    source: &dyn FrameSource,
    view: View,
    encoder: &mut Encoder,
) -> (u32, u32, Vec<u8>) {
    let film = source.film();
    match (view, source.work()) {
        (View::Cost, Some(work)) => heat(work, |i| ratio(work.node_visits[i], work.camera[i])),
        (View::Density, Some(work)) => {
            let frames = source.samples().max(1) as u64;
            heat(work, |i| ratio(work.rays[i], frames))
        }
        _ => {
            if encoder.transfer != film.transfer {
                *encoder = Encoder::new(film.transfer);
            }
            (film.width, film.height, image_rgba(&film, encoder))
        }
    }
}

fn ratio(a: u64, b: u64) -> f32 {
    if b == 0 {
        0.0
    } else {
        (a as f64 / b as f64) as f32
    }
}

fn image_rgba(film: &Film, encoder: &Encoder) -> Vec<u8> {
    let mut out = Vec::with_capacity(film.pixels.len() * 4);
    for c in &film.pixels {
        out.extend_from_slice(&[
            encoder.encode8(c.x),
            encoder.encode8(c.y),
            encoder.encode8(c.z),
            255,
        ]);
    }
    out
}

/// A heat map of `value(pixel index)` from 0 to its largest value, in viridis.
fn heat(work: &WorkTotals, value: impl Fn(usize) -> f32) -> (u32, u32, Vec<u8>) {
    let n = work.width as usize * work.height as usize;
    let values: Vec<f32> = (0..n).map(value).collect();
    let top = values
        .iter()
        .copied()
        .fold(0.0f32, f32::max)
        .max(f32::MIN_POSITIVE);
    let mut out = Vec::with_capacity(n * 4);
    for v in values {
        let [r, g, b] = viridis(v / top);
        out.extend_from_slice(&[r, g, b, 255]);
    }
    (work.width, work.height, out)
}

/// The PNG file of what the page shows: the image exactly as `prism render` writes it,
/// or the view's heat map.
pub(crate) fn png(source: &dyn FrameSource, view: View) -> Result<Vec<u8>, String> {
    let (width, height, rgb) = match view {
        View::Image => {
            let film = source.film();
            (film.width, film.height, prism_io::output::to_rgb8(&film))
        }
        _ => {
            let mut encoder = Encoder::new(Transfer::Srgb);
            let (w, h, rgba) = rgba(source, view, &mut encoder);
            (
                w,
                h,
                rgba.chunks_exact(4)
                    .flat_map(|p| [p[0], p[1], p[2]])
                    .collect(),
            )
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
        }
    }
}
