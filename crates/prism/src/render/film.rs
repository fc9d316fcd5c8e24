//! The film: a width × height grid of linear RGB pixels, row-major from the top-left.

use crate::math::Color;

#[derive(Clone, Debug, PartialEq)]
pub struct Film {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<Color>,
}

impl Film {
    pub fn new(width: u32, height: u32) -> Self {
        Film {
            width,
            height,
            pixels: vec![Color::ZERO; width as usize * height as usize],
        }
    }

    /// A black film, or an out-of-memory error instead of an abort when it cannot be had.
    pub fn try_new(width: u32, height: u32) -> Result<Self, super::RenderError> {
        let n = width as usize * height as usize;
        Ok(Film {
            width,
            height,
            pixels: super::memory::try_filled(n, Color::ZERO, "film")?,
        })
    }

    /// A film of this size whose pixels are not allocated yet: a placeholder for the one a
    /// reconstruction pass will build.
    pub(crate) fn unallocated(width: u32, height: u32) -> Self {
        Film {
            width,
            height,
            pixels: Vec::new(),
        }
    }

    pub fn get(&self, x: u32, y: u32) -> Color {
        self.pixels[y as usize * self.width as usize + x as usize]
    }

    pub fn set(&mut self, x: u32, y: u32, c: Color) {
        let w = self.width as usize;
        self.pixels[y as usize * w + x as usize] = c;
    }
}
