//! Textures for the diffuse colour: constant, procedural checkerboards (in uv or solid in
//! space) and images.

use crate::math::{Color, Vec2, Vec3};
use crate::transfer::srgb_decode;
use std::sync::Arc;

/// Where a material's diffuse colour comes from.
#[derive(Clone, Debug, PartialEq)]
pub enum Texture {
    /// One colour everywhere.
    Solid(Color),
    /// A procedural checkerboard.
    Checker(Checker),
    /// An image mapped by the surface's uv.
    Image(ImageTexture),
}

/// Where a checkerboard's squares are laid out.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CheckerSpace {
    /// Squares in the surface's (u, v) parameters.
    Uv,
    /// Cubes in world space: a solid texture, continuous across shapes.
    Solid,
}

/// A checkerboard of two colours.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Checker {
    /// Colour of the squares with even parity (including the one at the origin).
    pub a: Color,
    /// Colour of the squares with odd parity.
    pub b: Color,
    /// Edge length of one square (or cube), in uv or world units.
    pub size: f32,
    /// Squares in uv or cubes in space.
    pub space: CheckerSpace,
}

impl Checker {
    /// The colour at uv `uv` or point `p`, whichever the layout uses.
    pub fn eval(&self, uv: Vec2, p: Vec3) -> Color {
        let parity = match self.space {
            CheckerSpace::Uv => {
                let c = (uv / self.size).floor();
                c.x as i64 + c.y as i64
            }
            CheckerSpace::Solid => {
                let c = (p / self.size).floor();
                c.x as i64 + c.y as i64 + c.z as i64
            }
        };
        if parity.rem_euclid(2) == 0 {
            self.a
        } else {
            self.b
        }
    }
}

/// An image in linear RGB, sampled bilinearly with wrap-around; (0,0) is the bottom left
/// of the image so that uv = (u, v) reads like a graph.
#[derive(Clone, Debug, PartialEq)]
pub struct ImageTexture {
    width: usize,
    height: usize,
    texels: Arc<Vec<Color>>,
    /// Repetitions of the image per unit of uv.
    pub scale: Vec2,
}

impl ImageTexture {
    /// Converts 8-bit RGB values in rows from the top, sRGB-encoded as PNG and JPEG colour
    /// images hold them, to linear texels. The decoding of image files lives in prism-io;
    /// this is the part every source of texels shares.
    pub fn from_srgb8(width: usize, height: usize, rgb: &[u8]) -> Self {
        assert_eq!(rgb.len(), width * height * 3, "three bytes per texel");
        let lut: Vec<f32> = (0..256).map(|i| srgb_decode(i as f32 / 255.0)).collect();
        let texels = rgb
            .chunks_exact(3)
            .map(|p| Color::new(lut[p[0] as usize], lut[p[1] as usize], lut[p[2] as usize]))
            .collect();
        Self::from_texels(width, height, texels)
    }

    /// The same image with every texel multiplied by `factor` (a tint, such as glTF's
    /// baseColorFactor).
    pub fn tinted(&self, factor: Color) -> Self {
        self.map_texels(|t| t * factor)
    }

    /// The same image with `f` applied to every texel.
    pub fn map_texels(&self, f: impl Fn(Color) -> Color) -> Self {
        ImageTexture {
            texels: Arc::new(self.texels.iter().map(|&t| f(t)).collect()),
            ..self.clone()
        }
    }

    /// Texels in rows from the top, linear RGB.
    pub fn from_texels(width: usize, height: usize, texels: Vec<Color>) -> Self {
        assert_eq!(texels.len(), width * height, "texel count must match size");
        ImageTexture {
            width,
            height,
            texels: Arc::new(texels),
            scale: Vec2::ONE,
        }
    }

    /// Its width and height in texels.
    pub fn size(&self) -> (usize, usize) {
        (self.width, self.height)
    }

    /// The mean of its texels: the mean of `eval` over a whole repetition of the image
    /// (bilinear interpolation with wrap-around weighs every texel alike).
    pub fn mean(&self) -> Color {
        // f64: a large image's texels sum without losing the last ones.
        let sum = self.texels.iter().fold([0.0f64; 3], |s, t| {
            [s[0] + t.x as f64, s[1] + t.y as f64, s[2] + t.z as f64]
        });
        let n = self.texels.len().max(1) as f64;
        Color::new(
            (sum[0] / n) as f32,
            (sum[1] / n) as f32,
            (sum[2] / n) as f32,
        )
    }

    /// The bilinearly interpolated colour at `uv`, wrapping around at the edges.
    pub fn eval(&self, uv: Vec2) -> Color {
        if self.width == 0 || self.height == 0 {
            return Color::ZERO;
        }
        let uv = uv * self.scale;
        let x = uv.x.rem_euclid(1.0) * self.width as f32 - 0.5;
        let y = (1.0 - uv.y.rem_euclid(1.0)) * self.height as f32 - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let texel = |xi: f32, yi: f32| {
            let xi = (xi as i64).rem_euclid(self.width as i64) as usize;
            let yi = (yi as i64).rem_euclid(self.height as i64) as usize;
            self.texels[yi * self.width + xi]
        };
        let top = texel(x0, y0).lerp(texel(x0 + 1.0, y0), fx);
        let bottom = texel(x0, y0 + 1.0).lerp(texel(x0 + 1.0, y0 + 1.0), fx);
        top.lerp(bottom, fy)
    }
}

impl Texture {
    /// Whether `eval` reads its uv argument (so a surface point needs its uv computed).
    pub fn reads_uv(&self) -> bool {
        match self {
            Texture::Solid(_) => false,
            Texture::Checker(c) => c.space == CheckerSpace::Uv,
            Texture::Image(_) => true,
        }
    }

    /// The colour at uv `uv` and point `p`.
    pub fn eval(&self, uv: Vec2, p: Vec3) -> Color {
        match self {
            Texture::Solid(c) => *c,
            Texture::Checker(c) => c.eval(uv, p),
            Texture::Image(img) => img.eval(uv),
        }
    }
}
