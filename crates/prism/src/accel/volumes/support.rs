//! What fitting needs to know about a shape, exactly and in f64: its support function
//! (the largest `n·x` over the shape, which gives k-DOP, OBB and hull slabs), the farthest
//! distance from a point (for bounding spheres), and a few representative points (for
//! the principal axes of an OBB).
//!
//! A truncated cone, open or capped, lies in the convex hull of its two end discs, so the
//! discs stand for it; every other shape is bounded by its own features.

use super::slab::pad_outward;
use crate::geometry::{Geometry, Shape};
use glam::DVec3;

/// A disc: centre, unit normal, radius.
struct Disc {
    center: DVec3,
    normal: DVec3,
    radius: f64,
}

impl Disc {
    fn support(&self, n: DVec3) -> f64 {
        // The disc extends r·|n projected into its plane| beyond its centre.
        let along = n.dot(self.normal);
        let across = (n.length_squared() - along * along).max(0.0).sqrt();
        n.dot(self.center) + self.radius * across
    }

    fn farthest(&self, p: DVec3) -> f64 {
        let q = p - self.center;
        let h = q.dot(self.normal);
        let rho = (q.length_squared() - h * h).max(0.0).sqrt();
        (h * h + (rho + self.radius).powi(2)).sqrt()
    }
}

/// A primitive's bounding features in f64: up to eight points, a ball, or two discs.
enum Features {
    Points([DVec3; 8], usize),
    Ball { center: DVec3, radius: f64 },
    Discs([Disc; 2]),
}

fn features(geometry: &Geometry, prim: u32) -> Features {
    let shape = &geometry.primitives[prim as usize].shape;
    match shape {
        Shape::Triangle { mesh, index } => {
            let [a, b, c] = geometry.meshes[*mesh as usize].vertices(*index);
            let mut p = [DVec3::ZERO; 8];
            p[..3].copy_from_slice(&[a.as_dvec3(), b.as_dvec3(), c.as_dvec3()]);
            Features::Points(p, 3)
        }
        Shape::Sphere(s) => Features::Ball {
            center: s.center.as_dvec3(),
            radius: s.radius.abs() as f64,
        },
        Shape::Box(b) => Features::Points(corners(b.min.as_dvec3(), b.max.as_dvec3()), 8),
        Shape::Cone(c) => {
            let axis = (c.apex - c.base).as_dvec3().normalize();
            Features::Discs([
                Disc {
                    center: c.base.as_dvec3(),
                    normal: axis,
                    radius: c.base_radius as f64,
                },
                Disc {
                    center: c.apex.as_dvec3(),
                    normal: axis,
                    radius: c.apex_radius as f64,
                },
            ])
        }
        // Unbounded shapes never reach a hierarchy; anything bounded falls back to its box.
        Shape::Plane(_) => match shape.bounds(&geometry.meshes) {
            Some(b) => Features::Points(corners(b.min.as_dvec3(), b.max.as_dvec3()), 8),
            None => Features::Points([DVec3::ZERO; 8], 0),
        },
    }
}

fn corners(lo: DVec3, hi: DVec3) -> [DVec3; 8] {
    std::array::from_fn(|i| {
        DVec3::new(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        )
    })
}

/// The largest `n·x` over the primitive.
pub(super) fn support(geometry: &Geometry, prim: u32, n: DVec3) -> f64 {
    match features(geometry, prim) {
        Features::Points(p, k) => p[..k].iter().map(|p| n.dot(*p)).fold(f64::MIN, f64::max),
        Features::Ball { center, radius } => n.dot(center) + radius * n.length(),
        Features::Discs(d) => d[0].support(n).max(d[1].support(n)),
    }
}

/// The slab `[lo, hi]` of `n·x` over the primitives, rounded outward to f32 and padded
/// by `pad_outward` for contents of magnitude `scale`: one face pair of a k-DOP or an OBB.
pub(super) fn fit_slab(geometry: &Geometry, prims: &[u32], n: DVec3, scale: f64) -> (f32, f32) {
    let hi = prims
        .iter()
        .map(|&p| support(geometry, p, n))
        .fold(f64::MIN, f64::max);
    let lo = prims
        .iter()
        .map(|&p| -support(geometry, p, -n))
        .fold(f64::MAX, f64::min);
    pad_outward(lo, hi, scale * n.abs().element_sum())
}

/// The largest distance from `p` to a point of the primitive.
pub(super) fn farthest(geometry: &Geometry, prim: u32, p: DVec3) -> f64 {
    match features(geometry, prim) {
        Features::Points(q, k) => q[..k].iter().map(|q| q.distance(p)).fold(0.0, f64::max),
        Features::Ball { center, radius } => center.distance(p) + radius,
        Features::Discs(d) => d[0].farthest(p).max(d[1].farthest(p)),
    }
}

/// Points whose spread describes the primitive's shape: vertices, box corners, the axis
/// extremes of a sphere, points on the rims of a cone's discs.
pub(super) fn sample_points(geometry: &Geometry, prim: u32, out: &mut Vec<DVec3>) {
    match features(geometry, prim) {
        Features::Points(p, k) => out.extend_from_slice(&p[..k]),
        Features::Ball { center, radius } => {
            for axis in [DVec3::X, DVec3::Y, DVec3::Z] {
                out.extend([center + radius * axis, center - radius * axis]);
            }
        }
        Features::Discs(discs) => {
            for d in discs {
                let u = d.normal.any_orthonormal_vector();
                let v = d.normal.cross(u);
                out.extend([
                    d.center + d.radius * u,
                    d.center - d.radius * u,
                    d.center + d.radius * v,
                    d.center - d.radius * v,
                ]);
            }
        }
    }
}
