//! Separable convolution of one image channel, with clamp-to-edge borders: the blur and
//! derivative filters the image metrics are built from.

/// One channel of an image, row-major.
#[derive(Clone, Debug, PartialEq)]
pub struct Plane {
    /// Pixels per row.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// One value per pixel, row-major.
    pub values: Vec<f32>,
}

impl Plane {
    /// A plane of the given size over `values` (width × height of them).
    pub fn new(width: usize, height: usize, values: Vec<f32>) -> Self {
        debug_assert_eq!(values.len(), width * height);
        Plane {
            width,
            height,
            values,
        }
    }

    /// The plane with `f` applied to every value.
    pub fn map(&self, f: impl Fn(f32) -> f32) -> Plane {
        Plane::new(
            self.width,
            self.height,
            self.values.iter().map(|&v| f(v)).collect(),
        )
    }

    /// The plane of `f(a, b)` over corresponding values of two planes of the same size.
    pub fn zip(&self, other: &Plane, f: impl Fn(f32, f32) -> f32) -> Plane {
        let values = self
            .values
            .iter()
            .zip(&other.values)
            .map(|(&a, &b)| f(a, b))
            .collect();
        Plane::new(self.width, self.height, values)
    }

    /// Convolves rows with `kx` and columns with `ky` (odd lengths, centred).
    pub fn convolve(&self, kx: &[f32], ky: &[f32]) -> Plane {
        let (w, h) = (self.width, self.height);
        let pass = |src: &[f32], k: &[f32], along_x: bool| -> Vec<f32> {
            let r = (k.len() / 2) as isize;
            let mut out = vec![0.0f32; w * h];
            for y in 0..h {
                for x in 0..w {
                    let mut acc = 0.0f32;
                    for (i, &kv) in k.iter().enumerate() {
                        let d = i as isize - r;
                        let (sx, sy) = if along_x {
                            ((x as isize + d).clamp(0, w as isize - 1) as usize, y)
                        } else {
                            (x, (y as isize + d).clamp(0, h as isize - 1) as usize)
                        };
                        acc += kv * src[sy * w + sx];
                    }
                    out[y * w + x] = acc;
                }
            }
            out
        };
        let rows = pass(&self.values, kx, true);
        Plane::new(w, h, pass(&rows, ky, false))
    }
}

/// A normalised Gaussian of standard deviation `sigma` (pixels) over ±`radius`.
pub(super) fn gaussian(sigma: f32, radius: usize) -> Vec<f32> {
    let k: Vec<f32> = (0..=2 * radius)
        .map(|i| {
            let x = i as f32 - radius as f32;
            (-x * x / (2.0 * sigma * sigma)).exp()
        })
        .collect();
    let sum: f32 = k.iter().sum();
    k.into_iter().map(|v| v / sum).collect()
}
