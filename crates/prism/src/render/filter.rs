//! Reconstruction filters: how much a sample counts in each pixel whose centre is within
//! the filter's radius. Separable, f(dx)·f(dy); a pixel is the filter-weighted average of
//! the samples around it, so a filter need not integrate to one.

pub use crate::choices::FilterKind;

/// Mitchell–Netravali's B and C: the pair their paper recommends.
const MITCHELL_B: f32 = 1.0 / 3.0;
const MITCHELL_C: f32 = 1.0 / 3.0;

/// A reconstruction filter with its radius fixed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Filter {
    /// The filter's shape.
    pub kind: FilterKind,
    /// Half the support, in pixels: samples further away from a pixel centre do not count there.
    pub radius: f32,
}

impl Filter {
    /// The filter `kind` with `radius`, or its usual radius when none is given.
    pub fn new(kind: FilterKind, radius: Option<f32>) -> Filter {
        Filter {
            kind,
            radius: radius.unwrap_or(kind.default_radius()),
        }
    }

    /// The box over exactly one pixel: samples inside a pixel count only there.
    pub fn is_pixel_box(&self) -> bool {
        self.kind == FilterKind::Box && self.radius == 0.5
    }

    /// The one-dimensional profile at distance `d` (pixels) from a pixel centre. The
    /// support is closed: a sample exactly at the radius counts (pixel corners shared by
    /// four pixels count in all four).
    pub fn profile(&self, d: f32) -> f32 {
        let a = d.abs();
        let r = self.radius;
        if a > r {
            return 0.0;
        }
        match self.kind {
            FilterKind::Box => 1.0,
            FilterKind::Tent => 1.0 - a / r,
            FilterKind::Gaussian => {
                let inv_2s2 = 4.5 / (r * r);
                ((-a * a * inv_2s2).exp() - (-4.5f32).exp()).max(0.0)
            }
            FilterKind::Mitchell => mitchell(2.0 * a / r),
        }
    }

    /// Whether every sample strictly inside a pixel counts in that pixel alone: the box
    /// of radius ½.
    pub fn covers_one_pixel(&self) -> bool {
        self.kind == FilterKind::Box && self.radius == 0.5
    }

    /// How much a sample at offset (dx, dy) pixels from a pixel centre counts in that pixel.
    pub fn weight(&self, dx: f32, dy: f32) -> f32 {
        let fx = self.profile(dx);
        if fx == 0.0 {
            return 0.0;
        }
        fx * self.profile(dy)
    }
}

/// The Mitchell–Netravali cubic on [0, 2] (Mitchell and Netravali 1988, eq. 8).
fn mitchell(x: f32) -> f32 {
    let (b, c) = (MITCHELL_B, MITCHELL_C);
    let x2 = x * x;
    let x3 = x2 * x;
    let v = if x < 1.0 {
        (12.0 - 9.0 * b - 6.0 * c) * x3 + (-18.0 + 12.0 * b + 6.0 * c) * x2 + (6.0 - 2.0 * b)
    } else if x <= 2.0 {
        (-b - 6.0 * c) * x3
            + (6.0 * b + 30.0 * c) * x2
            + (-12.0 * b - 48.0 * c) * x
            + (8.0 * b + 24.0 * c)
    } else {
        0.0
    };
    v / 6.0
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_translates(filter: &Filter, d: f32) -> f32 {
        (-8..=8).map(|k| filter.profile(d + k as f32)).sum()
    }

    #[test]
    fn tent_and_mitchell_translates_sum_to_one() {
        // Both reproduce a constant from unit-spaced samples (partition of unity), so a
        // flat image stays flat under 1 spp at the pixel centres.
        for kind in [FilterKind::Tent, FilterKind::Mitchell] {
            let f = Filter::new(kind, None);
            for i in 0..20 {
                let d = i as f32 / 20.0;
                let s = unit_translates(&f, d);
                assert!((s - 1.0).abs() < 1e-5, "{kind}: {s} at {d}");
            }
        }
    }

    #[test]
    fn profiles_peak_at_zero_and_vanish_beyond_the_radius() {
        for kind in FilterKind::ALL {
            let f = Filter::new(kind, None);
            let peak = f.profile(0.0);
            assert!(peak > 0.0);
            for i in 1..50 {
                assert!(f.profile(i as f32 * 0.05) <= peak);
            }
            assert_eq!(f.profile(f.radius * 1.0001), 0.0, "{kind}");
            assert!(f.profile(f.radius * 0.9999).abs() < 0.05 || kind == FilterKind::Box);
        }
        let m = Filter::new(FilterKind::Mitchell, None);
        assert!(m.profile(1.5) < 0.0, "Mitchell has a negative lobe");
    }

    #[test]
    fn box_support_is_closed() {
        let f = Filter::new(FilterKind::Box, None);
        assert_eq!(f.weight(0.5, -0.5), 1.0);
        assert_eq!(f.weight(0.500_001, 0.0), 0.0);
    }
}
