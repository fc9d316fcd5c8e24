//! The film: a width × height grid of RGB pixels, row-major from the top-left, and what
//! its values mean (linear light, or display values).

use crate::math::Color;
use crate::transfer::Transfer;
use std::borrow::Cow;

/// The rendered image: one RGB value per pixel and the transfer that says what the values mean.
#[derive(Clone, Debug, PartialEq)]
pub struct Film {
    /// Pixels per row.
    pub width: u32,
    /// Rows.
    pub height: u32,
    /// Pixel values, row-major from the top-left.
    pub pixels: Vec<Color>,
    /// How the values reach a display; the renderer copies the render options'.
    pub transfer: Transfer,
}

impl Film {
    /// An empty film of the given size; the renderer fills its pixels.
    pub fn new(width: u32, height: u32) -> Self {
        Film {
            width,
            height,
            pixels: vec![Color::ZERO; width as usize * height as usize],
            transfer: Transfer::Srgb,
        }
    }

    /// Cuts the film to its first `rows` rows: what an interrupted render reached.
    pub fn keep_top_rows(&mut self, rows: u32) {
        self.height = self.height.min(rows);
        self.pixels
            .truncate(self.height as usize * self.width as usize);
    }

    /// The linear light a display shows for each pixel (`Transfer::to_linear`): the film
    /// itself when it is linear, a converted copy when it holds display values.
    pub fn displayed_linear(&self) -> Cow<'_, Film> {
        match self.transfer {
            Transfer::Srgb => Cow::Borrowed(self),
            t => Cow::Owned(Film {
                width: self.width,
                height: self.height,
                pixels: (self.pixels.iter())
                    .map(|c| Color::from_array(c.to_array().map(|v| t.to_linear(v))))
                    .collect(),
                transfer: Transfer::Srgb,
            }),
        }
    }

    /// A black film, or an out-of-memory error instead of an abort when it cannot be had.
    pub fn try_new(width: u32, height: u32) -> Result<Self, super::RenderError> {
        let n = width as usize * height as usize;
        Ok(Film {
            width,
            height,
            pixels: super::memory::try_zeroed(n, "film")?,
            transfer: Transfer::Srgb,
        })
    }

    /// A film of this size whose pixels are not allocated yet: a placeholder for the one a
    /// reconstruction pass will build.
    pub(crate) fn unallocated(width: u32, height: u32) -> Self {
        Film {
            width,
            height,
            pixels: Vec::new(),
            transfer: Transfer::Srgb,
        }
    }

    /// The value of pixel (x, y), y from the top.
    pub fn get(&self, x: u32, y: u32) -> Color {
        self.pixels[y as usize * self.width as usize + x as usize]
    }

    /// Sets pixel (x, y), y from the top.
    pub fn set(&mut self, x: u32, y: u32, c: Color) {
        let w = self.width as usize;
        self.pixels[y as usize * w + x as usize] = c;
    }
}
