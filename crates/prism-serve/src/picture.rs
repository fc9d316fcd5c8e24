//! A frame's pixels for the page: the image through its transfer (sRGB) into RGBA bytes,
//! or a heat map of the cost or density view; and the PNG file a page saves. The page
//! draws raw RGBA with `putImageData`: at 640×360 that is 0.9 MB a frame over the loopback,
//! against several milliseconds of the render's cores to encode a JPEG or PNG
//! (docs/viewer.md has the measurements).

use crate::controls::View;
use prism::render::{PixelTotals, Progressive};
use prism::transfer::Transfer;
use prism_io::output::heatmap::viridis;
pub(crate) use prism_io::output::Levels as Encoder;

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
            if encoder.transfer() != image.transfer() {
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
