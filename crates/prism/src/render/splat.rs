//! Splatting samples into pixels with exact, order-free sums.
//!
//! A sample adds weight·f(d)·L and weight·f(d) to every pixel whose centre is within the
//! filter radius, so near a tile's edge it also lands in pixels of other tiles. Floating-
//! point sums depend on the order of their terms; these sums are fixed-point integers
//! (2⁻⁶⁰ units in 128 bits), whose addition is associative. Each term is computed the
//! same way wherever the sample is traced, so the image is bit-identical for any thread
//! count, tile size and tile order.

use super::film::Film;
use super::filter::Filter;
use super::Tile;
use crate::math::{Color, Vec2};

/// 2⁶⁰: the fixed-point unit. Values up to 2⁶⁷ ≈ 1.5·10²⁰ fit, and 10⁻¹⁰ keeps 30 bits.
const SCALE: f64 = (1u64 << 60) as f64;

/// Fixed-point sums of one pixel: weighted R, G, B and the weight.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct PixelSum([i128; 4]);

impl PixelSum {
    fn add(&mut self, terms: [i128; 4]) {
        for (s, t) in self.0.iter_mut().zip(terms) {
            *s = s.saturating_add(t);
        }
    }
}

/// The fixed-point value of `v`; the cast saturates, and NaN becomes 0.
fn fixed(v: f64) -> i128 {
    (v * SCALE) as i128
}

/// The sums of a rectangle of pixels `[x0, x1) × [y0, y1)`, in image coordinates.
pub(super) struct SplatBuffer {
    x0: u32,
    y0: u32,
    width: u32,
    height: u32,
    sums: Vec<PixelSum>,
}

impl SplatBuffer {
    /// Covers the pixels of `[x0, x1) × [y0, y1)` grown by the filter's reach, clipped to
    /// the `image` size.
    pub(super) fn around(
        filter: &Filter,
        image: (u32, u32),
        x0: u32,
        y0: u32,
        x1: u32,
        y1: u32,
    ) -> Self {
        let m = filter.radius.ceil() as u32;
        let (bx0, by0) = (x0.saturating_sub(m), y0.saturating_sub(m));
        let (bx1, by1) = ((x1 + m).min(image.0), (y1 + m).min(image.1));
        SplatBuffer {
            x0: bx0,
            y0: by0,
            width: bx1 - bx0,
            height: by1 - by0,
            sums: vec![PixelSum::default(); ((bx1 - bx0) * (by1 - by0)) as usize],
        }
    }

    /// Adds a sample at `offset` ∈ [0, 1]² within pixel (px, py), counting `weight` (its
    /// share of area; 1 for equal samples). Pixels outside the buffer are skipped: the
    /// buffer must cover the filter's reach of every sample it takes.
    pub(super) fn add(
        &mut self,
        filter: &Filter,
        px: u32,
        py: u32,
        offset: Vec2,
        weight: f32,
        value: Color,
    ) {
        let r = filter.radius as f64;
        let range = |p: u32, o: f32, lo: u32, len: u32| {
            let centre = p as f64 + o as f64 - 0.5;
            let first = ((centre - r).ceil().max(lo as f64)) as u32;
            let last = ((centre + r).floor().min((lo + len) as f64 - 1.0)) as i64;
            (first, last)
        };
        let (qx0, qx1) = range(px, offset.x, self.x0, self.width);
        let (qy0, qy1) = range(py, offset.y, self.y0, self.height);
        // Distances as small integers plus (offset − ½): the same bits in every tile.
        let (dx0, dy0) = (offset.x - 0.5, offset.y - 0.5);
        for qy in qy0 as i64..=qy1 {
            let fy = filter.profile((py as i64 - qy) as f32 + dy0);
            if fy == 0.0 {
                continue;
            }
            for qx in qx0 as i64..=qx1 {
                let fx = filter.profile((px as i64 - qx) as f32 + dx0);
                if fx == 0.0 {
                    continue;
                }
                let w = weight as f64 * (fx * fy) as f64;
                let i = (qy as u32 - self.y0) * self.width + (qx as u32 - self.x0);
                self.sums[i as usize].add([
                    fixed(w * value.x as f64),
                    fixed(w * value.y as f64),
                    fixed(w * value.z as f64),
                    fixed(w),
                ]);
            }
        }
    }
}

/// The sums of a rectangle of the image (the whole image, or a region and the filter's
/// reach around it), into which finished buffers are merged in any order.
pub(super) struct FilmSums {
    area: Tile,
    sums: Vec<PixelSum>,
}

impl FilmSums {
    /// Zero sums over `area`, or an out-of-memory error instead of an abort.
    pub(super) fn try_new(area: Tile) -> Result<Self, super::RenderError> {
        let n = area.pixel_count() as usize;
        Ok(FilmSums {
            area,
            sums: super::memory::try_filled(n, PixelSum::default(), "filter sums")?,
        })
    }

    /// Adds a buffer's sums; the part of it outside this area is dropped.
    pub(super) fn merge(&mut self, buffer: &SplatBuffer) {
        let own = Tile {
            x0: buffer.x0,
            y0: buffer.y0,
            x1: buffer.x0 + buffer.width,
            y1: buffer.y0 + buffer.height,
        };
        let Some(common) = own.intersection(&self.area) else {
            return;
        };
        let n = common.width() as usize;
        for y in common.y0..common.y1 {
            let src = ((y - buffer.y0) * buffer.width + (common.x0 - buffer.x0)) as usize;
            let dst =
                ((y - self.area.y0) * self.area.width() + (common.x0 - self.area.x0)) as usize;
            for (d, s) in self.sums[dst..dst + n]
                .iter_mut()
                .zip(&buffer.sums[src..src + n])
            {
                d.add(s.0);
            }
        }
    }

    /// Each pixel of `part` (within this area) as its weighted average; black where no
    /// sample counted.
    pub(super) fn into_film(self, part: Tile) -> Result<Film, super::RenderError> {
        let mut film = Film::try_new(part.width(), part.height())?;
        for y in part.y0..part.y1 {
            for x in part.x0..part.x1 {
                let i = (y - self.area.y0) as usize * self.area.width() as usize
                    + (x - self.area.x0) as usize;
                let [r, g, b, w] = self.sums[i].0;
                if w != 0 {
                    let w = w as f64;
                    film.set(
                        x - part.x0,
                        y - part.y0,
                        Color::new(
                            (r as f64 / w) as f32,
                            (g as f64 / w) as f32,
                            (b as f64 / w) as f32,
                        ),
                    );
                }
            }
        }
        Ok(film)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::filter::FilterKind;

    #[test]
    fn a_corner_sample_counts_in_all_four_pixels_under_the_box() {
        let f = Filter::new(FilterKind::Box, None);
        let mut buf = SplatBuffer::around(&f, (4, 4), 1, 1, 2, 2);
        buf.add(&f, 1, 1, Vec2::ZERO, 1.0, Color::ONE);
        let mut film = FilmSums::try_new(Tile::full(4, 4)).unwrap();
        film.merge(&buf);
        let film = film.into_film(Tile::full(4, 4)).unwrap();
        let lit: Vec<(u32, u32)> = (0..16)
            .map(|i| (i % 4, i / 4))
            .filter(|&(x, y)| film.get(x, y) == Color::ONE)
            .collect();
        assert_eq!(lit, vec![(0, 0), (1, 0), (0, 1), (1, 1)]);
    }

    #[test]
    fn sums_do_not_depend_on_order() {
        let f = Filter::new(FilterKind::Mitchell, None);
        let samples: Vec<(u32, u32, Vec2, Color)> = (0..200)
            .map(|i| {
                let t = i as f32 * 0.618_034;
                (
                    i % 5,
                    (i / 5) % 5,
                    Vec2::new(t.fract(), (t * 1.7).fract()),
                    Color::new(t.sin().abs() * 3.0, 0.1 / (1.0 + t), 1e-7 * t),
                )
            })
            .collect();
        let render = |order: &mut dyn Iterator<Item = &(u32, u32, Vec2, Color)>| {
            let mut film = FilmSums::try_new(Tile::full(5, 5)).unwrap();
            for &(x, y, o, c) in order {
                let mut buf = SplatBuffer::around(&f, (5, 5), x, y, x + 1, y + 1);
                buf.add(&f, x, y, o, 1.0, c);
                film.merge(&buf);
            }
            film.into_film(Tile::full(5, 5)).unwrap()
        };
        let forward = render(&mut samples.iter());
        let backward = render(&mut samples.iter().rev());
        assert_eq!(forward, backward);
    }
}
