//! Oriented bounding boxes: three slabs along the principal axes of the node's contents.
//! Tighter than a box for slanted contents, but the axes differ per node, so the ray's
//! `n·o` and `1/(n·d)` cannot be shared across nodes: each test costs three dot-product
//! pairs and three divisions more than a k-DOP slab.
//!
//! The extents come from the shapes' support functions along the stored f32 axes, so the
//! box contains its contents whatever the axes are; where the principal axes would give a
//! larger box than the world axes, the world axes are kept.

use super::pca::principal_axes;
use super::slab::{finish, SlabAxis};
use super::support::{fit_slab, sample_points};
use super::volume::{magnitude, Volume};
use crate::geometry::Geometry;
use crate::math::{Aabb, TraceRay, Vec3};

/// An oriented bounding box: `lo[i] ≤ axes[i]·x ≤ hi[i]` for its three axes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Obb {
    /// Unit axes (orthogonal up to f32 rounding, which costs nothing in safety).
    pub axes: [Vec3; 3],
    /// Lower bound along each axis.
    pub lo: [f32; 3],
    /// Upper bound along each axis.
    pub hi: [f32; 3],
}

impl Obb {
    /// Surface area, for the SAH and tightness figures.
    pub fn surface_area(&self) -> f32 {
        let e: [f32; 3] =
            std::array::from_fn(|i| (self.hi[i] - self.lo[i]) / self.axes[i].length());
        2.0 * (e[0] * e[1] + e[1] * e[2] + e[2] * e[0])
    }

    fn along(geometry: &Geometry, prims: &[u32], axes: [Vec3; 3], scale: f64) -> Obb {
        let mut obb = Obb {
            axes,
            lo: [0.0; 3],
            hi: [0.0; 3],
        };
        for (i, a) in axes.iter().enumerate() {
            (obb.lo[i], obb.hi[i]) = fit_slab(geometry, prims, a.as_dvec3(), scale);
        }
        obb
    }
}

impl Volume for Obb {
    type Ray = ();

    #[inline(always)]
    fn prepare(_ray: &TraceRay) {}

    #[inline(always)]
    fn hit(&self, _: &(), trace: &TraceRay, t_max: f32) -> Option<f32> {
        let (o, d) = (trace.ray.origin, trace.ray.dir);
        let (mut enter, mut exit, mut relative) = (f32::NEG_INFINITY, f32::INFINITY, 0.0f32);
        for i in 0..3 {
            let (axis, r) = SlabAxis::new(self.axes[i], o, d);
            let (a, b) = axis.clip(self.lo[i], self.hi[i]);
            enter = enter.max(a);
            exit = exit.min(b);
            relative = relative.max(r);
        }
        finish(enter, exit, t_max, relative)
    }

    fn contains(&self, p: Vec3) -> bool {
        let p = p.as_dvec3();
        (0..3).all(|i| {
            let x = self.axes[i].as_dvec3().dot(p);
            self.lo[i] as f64 <= x && x <= self.hi[i] as f64
        })
    }

    fn fit(geometry: &Geometry, prims: &[u32], bounds: &Aabb) -> Self {
        let scale = magnitude(bounds);
        let mut points = Vec::new();
        for &p in prims {
            sample_points(geometry, p, &mut points);
        }
        let axes = principal_axes(&points).map(|a| a.as_vec3().normalize_or(Vec3::X));
        let world = Obb::along(geometry, prims, [Vec3::X, Vec3::Y, Vec3::Z], scale);
        let principal = Obb::along(geometry, prims, axes, scale);
        if principal.surface_area() < world.surface_area() {
            principal
        } else {
            world
        }
    }
}
