//! Heat-map figures: a per-pixel quantity (rays per pixel, an error) in a perceptually
//! uniform colour map, with a colour bar, tick labels and a caption.

use super::glyphs::{draw_text, text_height, text_width};

/// Viridis (van der Walt and Smith, matplotlib 2015) at nine evenly spaced stops.
const VIRIDIS: [[u8; 3]; 9] = [
    [68, 1, 84],
    [71, 44, 122],
    [59, 81, 139],
    [44, 113, 142],
    [33, 144, 141],
    [39, 173, 129],
    [92, 200, 99],
    [170, 220, 50],
    [253, 231, 37],
];

const BACKGROUND: [u8; 3] = [24, 24, 24];
const INK: [u8; 3] = [235, 235, 235];

/// The colour of `t` ∈ [0, 1], interpolated between the stops.
pub fn viridis(t: f32) -> [u8; 3] {
    let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
    let x = t * (VIRIDIS.len() - 1) as f32;
    let i = (x as usize).min(VIRIDIS.len() - 2);
    let f = x - i as f32;
    let (a, b) = (VIRIDIS[i], VIRIDIS[i + 1]);
    [0, 1, 2].map(|k| (a[k] as f32 + (b[k] as f32 - a[k] as f32) * f + 0.5) as u8)
}

/// An RGB8 image, rows from the top.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Rgb8 {
    /// Pixels per row.
    pub width: u32,
    /// Rows.
    pub height: u32,
    /// Three bytes (R, G, B) per pixel, row-major.
    pub data: Vec<u8>,
}

/// A heat map of `values` (width × height, row-major) from 0 to `top` (the largest value
/// when None), with a colour bar on the right and `caption` below. Small images are
/// enlarged by a whole factor so the labels stay readable.
pub fn heatmap(values: &[f32], width: u32, height: u32, top: Option<f32>, caption: &str) -> Rgb8 {
    let largest = values
        .iter()
        .copied()
        .filter(|v| v.is_finite())
        .fold(0.0f32, f32::max);
    let top = top.unwrap_or(largest).max(f32::MIN_POSITIVE);
    let zoom = (240 / height.max(1)).clamp(1, 16);
    let (mw, mh) = (width * zoom, height * zoom);
    let s = (mh / 240).clamp(1, 4);
    let ticks = ticks(top);
    let label_w = ticks
        .iter()
        .map(|&t| text_width(&label(t), s))
        .max()
        .unwrap_or(0);
    let (margin, bar_w) = (6 * s, 12 * s);
    let panel = margin + bar_w + 4 * s + label_w + margin;
    let footer = text_height(s) + 2 * margin;
    let size = (mw + panel, mh.max(80) + footer);
    let mut img = vec![0u8; (size.0 * size.1 * 3) as usize];
    for p in img.chunks_mut(3) {
        p.copy_from_slice(&BACKGROUND);
    }
    let put = |img: &mut Vec<u8>, x: u32, y: u32, c: [u8; 3]| {
        let k = ((y * size.0 + x) * 3) as usize;
        img[k..k + 3].copy_from_slice(&c);
    };
    for y in 0..mh {
        for x in 0..mw {
            let v = values[((y / zoom) * width + x / zoom) as usize];
            put(&mut img, x, y, viridis(v / top));
        }
    }
    // The colour bar, top = `top`, with ticks.
    let (bx, by0, by1) = (mw + margin, margin, mh.max(80) - margin);
    let bar_h = (by1 - by0).max(1);
    for y in by0..by1 {
        let t = 1.0 - (y - by0) as f32 / bar_h as f32;
        for x in bx..bx + bar_w {
            put(&mut img, x, y, viridis(t));
        }
    }
    for &t in &ticks {
        let y = by1 - ((t / top) * bar_h as f32).round() as u32;
        for x in bx + bar_w..bx + bar_w + 3 * s {
            for dy in 0..s {
                put(&mut img, x, (y + dy).min(size.1 - 1), INK);
            }
        }
        let ty = y.saturating_sub(text_height(s) / 2);
        draw_text(&mut img, size, bx + bar_w + 4 * s, ty, &label(t), s, INK);
    }
    draw_text(&mut img, size, margin, mh.max(80) + margin, caption, s, INK);
    Rgb8 {
        width: size.0,
        height: size.1,
        data: img,
    }
}

/// Round tick values from 0 to `top`: steps of 1, 2 or 5 times a power of ten, at most six.
fn ticks(top: f32) -> Vec<f32> {
    let raw = top as f64 / 5.0;
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * mag)
        .find(|&s| s >= raw)
        .unwrap_or(10.0 * mag);
    (0..)
        .map(|i| (i as f64 * step) as f32)
        .take_while(|&t| t <= top * 1.000_001)
        .collect()
}

/// A tick label: as few digits as the value needs.
pub fn label(v: f32) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let a = v.abs();
    if (1e-3..1e5).contains(&a) {
        let s = format!("{v:.4}");
        let s = s.trim_end_matches('0').trim_end_matches('.');
        s.to_string()
    } else {
        format!("{v:.0e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_are_round_and_within_the_range() {
        assert_eq!(ticks(81.0), vec![0.0, 20.0, 40.0, 60.0, 80.0]);
        assert_eq!(ticks(2.0), vec![0.0, 0.5, 1.0, 1.5, 2.0]);
        assert_eq!(label(0.25), "0.25");
        assert_eq!(label(40.0), "40");
    }

    #[test]
    fn the_map_runs_from_dark_purple_to_yellow() {
        assert_eq!(viridis(0.0), VIRIDIS[0]);
        assert_eq!(viridis(1.0), VIRIDIS[8]);
        assert_eq!(viridis(f32::NAN), VIRIDIS[0]);
    }

    #[test]
    fn a_heatmap_holds_the_image_the_bar_and_the_caption() {
        let values: Vec<f32> = (0..64).map(|i| i as f32).collect();
        let img = heatmap(&values, 8, 8, None, "RAYS PER PIXEL");
        assert!(
            img.width > 8 * 16 && img.height > 8 * 16,
            "enlarged 16 times"
        );
        assert_eq!(img.data.len() as u32, img.width * img.height * 3);
        // The top-left pixel is the lowest value, the enlarged bottom-right the highest.
        assert_eq!(&img.data[0..3], &VIRIDIS[0]);
    }
}
