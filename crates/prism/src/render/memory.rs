//! The memory a render needs, known before it starts, and the fallible allocation of its
//! big buffers. An image of 65536 × 65536 pixels needs hundreds of gigabytes; the process
//! must refuse it with a message that names the bytes, not abort inside the allocator.
//! Zeroed buffers come from the allocator's zeroed memory (`try_zeroed`, the module's one
//! unsafe call, listed with the workspace's exceptions in Cargo.toml).

#![allow(unsafe_code)]

use super::RenderError;
use crate::options::RenderOptions;

/// Bytes per pixel of the buffers every render holds: the film (RGB f32) and the per-pixel
/// ray counts of the density and cost views (two u32, four u64).
pub(crate) const FILM_BYTES: u64 = 12;
pub(crate) const RAY_COUNT_BYTES: u64 = 40;
/// Exact fixed-point sums of a pixel under a filter wider than the pixel: four i128.
pub(crate) const SPLAT_SUM_BYTES: u64 = 64;
/// A pixel corner of the lattice samplers (one per pixel, and a row and a column more):
/// its colour.
pub(crate) const CORNER_BYTES: u64 = 12;
/// The corners sampler's centre sample per pixel (Option<Color>).
pub(crate) const CENTRE_BYTES: u64 = 16;
/// The adaptive sampler's display-encoded colour of each corner, next to the colour.
pub(crate) const ENCODED_CORNER_BYTES: u64 = 12;
/// A point the adaptive sampler traced on a horizontal pixel edge, kept by an even row for
/// the odd row across the edge: (lattice x, colour). At most 2·(2^depth − 1) per pixel of
/// an even row; one per pixel is the usual order of magnitude. Nothing else of the
/// refinement outlives the row that traces it.
pub(crate) const EDGE_POINT_BYTES: u64 = 16;
/// Bytes per primitive of a prepared scene with its default BVH: the primitive, its box,
/// the binary and the 4-wide nodes. A rough figure: other structures may need more.
pub const ACCEL_BYTES_PER_PRIMITIVE: u64 = 160;

/// What a render will allocate, part by part.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct MemoryEstimate {
    /// (what, bytes), in the order a reader would list them.
    pub parts: Vec<(&'static str, u64)>,
}

impl MemoryEstimate {
    /// The sum of the parts.
    pub fn total(&self) -> u64 {
        self.parts.iter().map(|&(_, b)| b).sum()
    }

    /// Adds a part (a caller's own buffers: encoded output, extra views).
    pub fn add(&mut self, what: &'static str, bytes: u64) {
        self.parts.push((what, bytes));
    }

    /// "film 51.5 GB, ray counts 103 GB, …".
    pub fn breakdown(&self) -> String {
        self.parts
            .iter()
            .filter(|&&(_, b)| b > 0)
            .map(|&(what, b)| format!("{what} {}", format_bytes(b)))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// The memory `render` will need for `options`, before any of it is allocated: film, ray
/// counts and the sampler's buffers (the acceleration structure is the caller's: it is
/// built before the render starts).
pub fn estimate(options: &RenderOptions) -> MemoryEstimate {
    let pixels = options.width as u64 * options.height as u64;
    let mut e = MemoryEstimate::default();
    let box_pixel = super::Filter::new(options.filter, options.filter_radius).is_pixel_box();
    let sampler = super::sampler_method(options.sampler);
    // The per-pixel samplers write their tiles straight into the film (or into the sums,
    // which become the film); the lattice samplers assemble it once more from theirs.
    e.add("film", pixels * FILM_BYTES * sampler.films());
    if options.per_pixel_rays {
        e.add("ray counts", pixels * RAY_COUNT_BYTES);
    }
    sampler.memory(options, box_pixel, &mut e);
    e
}

/// A vector of `n` copies of `value`, or an out-of-memory error naming `what` and the bytes
/// it would have taken.
pub(crate) fn try_filled<T: Clone>(
    n: usize,
    value: T,
    what: &'static str,
) -> Result<Vec<T>, RenderError> {
    let mut v = Vec::new();
    v.try_reserve_exact(n)
        .map_err(|_| RenderError::OutOfMemory {
            what,
            bytes: (n as u64).saturating_mul(std::mem::size_of::<T>() as u64),
        })?;
    v.resize(n, value);
    Ok(v)
}

/// A type whose all-zero bit pattern is a valid value (its zero), so that a buffer of
/// them may come zeroed from the allocator.
///
/// # Safety
///
/// Implement it only for types of which every byte zero is a valid value.
pub(crate) unsafe trait ZeroBits: Copy {}

// SAFETY: integers and floats of all zero bits are 0 and 0.0; `Color` (glam's `Vec3`) is
// three f32.
unsafe impl ZeroBits for u32 {}
unsafe impl ZeroBits for u64 {}
unsafe impl ZeroBits for crate::math::Color {}

/// A vector of `n` zeros straight from the allocator's zeroed memory, or an out-of-memory
/// error naming `what` and the bytes it would have taken. Unlike `try_filled` nothing is
/// written here: a large buffer comes as fresh pages the system zeroes when they are first
/// touched, so a render of 20000 × 20000 pixels starts its tiles at once instead of first
/// writing gigabytes of zeros (seconds in which Ctrl-C could not stop it), and a render
/// stopped early gives back only the pages its tiles touched.
pub(crate) fn try_zeroed<T: ZeroBits>(n: usize, what: &'static str) -> Result<Vec<T>, RenderError> {
    let out_of_memory = || RenderError::OutOfMemory {
        what,
        bytes: (n as u64).saturating_mul(std::mem::size_of::<T>() as u64),
    };
    let layout = std::alloc::Layout::array::<T>(n).map_err(|_| out_of_memory())?;
    if layout.size() == 0 {
        return Ok(Vec::new());
    }
    // SAFETY: the layout's size is not zero (checked above).
    let ptr = unsafe { std::alloc::alloc_zeroed(layout) }.cast::<T>();
    if ptr.is_null() {
        return Err(out_of_memory());
    }
    // SAFETY: `ptr` comes from the global allocator with the layout of `n` values of `T`
    // (so capacity `n` and `T`'s alignment), and all its `n` values are zero bits, which
    // `ZeroBits` promises are valid values of `T`.
    Ok(unsafe { Vec::from_raw_parts(ptr, n, n) })
}

/// Bytes in decimal units with three significant digits: "812 MB", "51.5 GB".
pub fn format_bytes(bytes: u64) -> String {
    const UNITS: [&str; 5] = ["B", "kB", "MB", "GB", "TB"];
    let mut v = bytes as f64;
    let mut unit = 0;
    while v >= 1000.0 && unit + 1 < UNITS.len() {
        v /= 1000.0;
        unit += 1;
    }
    if unit == 0 {
        format!("{bytes} B")
    } else if v >= 100.0 {
        format!("{v:.0} {}", UNITS[unit])
    } else if v >= 10.0 {
        format!("{v:.1} {}", UNITS[unit])
    } else {
        format!("{v:.2} {}", UNITS[unit])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::choices::SamplerKind;

    #[test]
    fn the_largest_image_is_estimated_in_hundreds_of_gigabytes() {
        let options = RenderOptions {
            width: 65536,
            height: 65536,
            ..RenderOptions::default()
        };
        let e = estimate(&options);
        // The film and the ray counts: 52 bytes a pixel.
        assert!(e.total() >= 65536 * 65536 * 52, "{e:?}");
        assert!(
            e.breakdown().starts_with("film 51.5 GB, ray counts 172 GB"),
            "{}",
            e.breakdown()
        );
        // Without the counts, the film alone.
        let film_only = RenderOptions {
            per_pixel_rays: false,
            ..options
        };
        assert_eq!(estimate(&film_only).breakdown(), "film 51.5 GB");
    }

    #[test]
    fn a_wide_filter_and_the_lattice_samplers_need_their_sums() {
        let base = RenderOptions {
            width: 100,
            height: 100,
            ..RenderOptions::default()
        };
        let box_total = estimate(&base).total();
        let tent = RenderOptions {
            filter: crate::render::FilterKind::Tent,
            ..base.clone()
        };
        assert_eq!(
            estimate(&tent).total(),
            box_total + 10_000 * SPLAT_SUM_BYTES
        );
        let corners = RenderOptions {
            sampler: SamplerKind::Corners,
            ..base
        };
        assert!(estimate(&corners).total() > estimate(&tent).total());
    }

    /// That an allocation of half the address space failed with the out-of-memory error
    /// naming the buffer and its bytes, rather than aborting.
    #[track_caller]
    fn assert_out_of_memory(r: Result<Vec<u64>, RenderError>) {
        match r {
            Err(RenderError::OutOfMemory { what, bytes }) => {
                assert_eq!(what, "test buffer");
                assert!(bytes > 1 << 62);
            }
            other => panic!(
                "expected an out-of-memory error, got {:?}",
                other.map(|v| v.len())
            ),
        }
    }

    #[test]
    fn an_impossible_vector_is_an_error_not_an_abort() {
        assert_out_of_memory(try_filled(usize::MAX / 2, 0u64, "test buffer"));
    }

    #[test]
    fn zeroed_vectors_are_zeros_and_an_impossible_one_is_an_error() {
        let v: Vec<crate::math::Color> = try_zeroed(100_003, "test buffer").unwrap();
        assert_eq!(v.len(), 100_003);
        assert!(v.iter().all(|c| *c == crate::math::Color::ZERO));
        let mut counts: Vec<u64> = try_zeroed(5, "test buffer").unwrap();
        counts.push(7);
        assert_eq!(counts, [0, 0, 0, 0, 0, 7]);
        assert!(try_zeroed::<u32>(0, "test buffer").unwrap().is_empty());
        assert_out_of_memory(try_zeroed::<u64>(usize::MAX / 2, "test buffer"));
    }

    #[test]
    fn bytes_read_as_people_write_them() {
        assert_eq!(format_bytes(999), "999 B");
        assert_eq!(format_bytes(1_500), "1.50 kB");
        assert_eq!(format_bytes(51_539_607_552), "51.5 GB");
        assert_eq!(format_bytes(274_877_906_944), "275 GB");
    }
}
