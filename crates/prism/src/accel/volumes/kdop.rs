//! k-DOPs (discrete oriented polytopes): the intersection of k/2 slabs along fixed
//! directions. 14-DOP: the 3 axes and the 4 cube diagonals; 26-DOP adds the 6 edge
//! directions. The directions are integer vectors, so `n·x` is a sum of ± coordinates.
//!
//! The ray prepares `n·o` and `1/(n·d)` for all directions once; a node test is then k/2
//! subtract-multiply pairs, as cheap per slab as an AABB's.

use super::slab::{finish, SlabAxis};
use super::support::fit_slab;
use super::volume::{magnitude, Volume};
use crate::geometry::Geometry;
use crate::math::{Aabb, TraceRay, Vec3};

/// All 13 directions; a `Dop<N>` uses the first N.
pub const DIRECTIONS: [Vec3; 13] = [
    Vec3::new(1.0, 0.0, 0.0),
    Vec3::new(0.0, 1.0, 0.0),
    Vec3::new(0.0, 0.0, 1.0),
    Vec3::new(1.0, 1.0, 1.0),
    Vec3::new(1.0, 1.0, -1.0),
    Vec3::new(1.0, -1.0, 1.0),
    Vec3::new(-1.0, 1.0, 1.0),
    Vec3::new(1.0, 1.0, 0.0),
    Vec3::new(1.0, -1.0, 0.0),
    Vec3::new(1.0, 0.0, 1.0),
    Vec3::new(1.0, 0.0, -1.0),
    Vec3::new(0.0, 1.0, 1.0),
    Vec3::new(0.0, 1.0, -1.0),
];

/// A k-DOP with N = k/2 slabs: `lo[i] ≤ DIRECTIONS[i]·x ≤ hi[i]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dop<const N: usize> {
    /// Lower bound along each direction.
    pub lo: [f32; N],
    /// Upper bound along each direction.
    pub hi: [f32; N],
}

/// The 14-DOP: the three axes and the four cube diagonals.
pub type Dop14 = Dop<7>;
/// The 26-DOP: the 14-DOP's directions and the six face diagonals.
pub type Dop26 = Dop<13>;

/// A ray prepared for N directions.
#[derive(Clone, Copy, Debug)]
pub struct DopRay<const N: usize> {
    axes: [SlabAxis; N],
    relative: f32,
}

impl<const N: usize> Dop<N> {
    /// The slab distances `(lo, hi)` along direction `i`, for comparing tightness.
    pub fn slab(&self, i: usize) -> (f32, f32) {
        (self.lo[i], self.hi[i])
    }
}

impl<const N: usize> Volume for Dop<N> {
    type Ray = DopRay<N>;

    #[inline(always)]
    fn prepare(ray: &TraceRay) -> DopRay<N> {
        let mut relative: f32 = 0.0;
        let axes = std::array::from_fn(|i| {
            let (axis, r) = SlabAxis::new(DIRECTIONS[i], ray.ray.origin, ray.ray.dir);
            relative = relative.max(r);
            axis
        });
        DopRay { axes, relative }
    }

    #[inline(always)]
    fn hit(&self, ray: &DopRay<N>, _trace: &TraceRay, t_max: f32) -> Option<f32> {
        let (mut enter, mut exit) = (f32::NEG_INFINITY, f32::INFINITY);
        for i in 0..N {
            let (a, b) = ray.axes[i].clip(self.lo[i], self.hi[i]);
            enter = enter.max(a);
            exit = exit.min(b);
        }
        finish(enter, exit, t_max, ray.relative)
    }

    fn contains(&self, p: Vec3) -> bool {
        let p = p.as_dvec3();
        (0..N).all(|i| {
            let x = DIRECTIONS[i].as_dvec3().dot(p);
            self.lo[i] as f64 <= x && x <= self.hi[i] as f64
        })
    }

    fn fit(geometry: &Geometry, prims: &[u32], bounds: &Aabb) -> Self {
        let scale = magnitude(bounds);
        let mut dop = Dop {
            lo: [0.0; N],
            hi: [0.0; N],
        };
        for (i, n) in DIRECTIONS[..N].iter().enumerate() {
            (dop.lo[i], dop.hi[i]) = fit_slab(geometry, prims, n.as_dvec3(), scale);
        }
        dop
    }

    const MERGES: bool = true;

    fn merge(a: &Self, b: &Self) -> Self {
        Dop {
            lo: std::array::from_fn(|i| a.lo[i].min(b.lo[i])),
            hi: std::array::from_fn(|i| a.hi[i].max(b.hi[i])),
        }
    }
}
