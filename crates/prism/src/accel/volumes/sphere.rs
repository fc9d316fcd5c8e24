//! Bounding spheres: the cheapest test to store (16 bytes) and among the loosest for long
//! thin contents. Fitted around the better of two centres (the node box's centre and the
//! mean of the contents' sample points) with the exact farthest distance from it, so
//! spheres, boxes and cones below are bounded exactly, not through their boxes.

use super::slab::{round_up, ROUNDINGS};
use super::support::{farthest, sample_points};
use super::volume::Volume;
use crate::geometry::Geometry;
use crate::math::robust::gamma;
use crate::math::{Aabb, TraceRay, Vec3};
use glam::DVec3;

/// A bounding sphere.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoundingSphere {
    /// Centre.
    pub center: Vec3,
    /// Radius, padded outward.
    pub radius: f32,
}

/// Per ray: the origin's 1-norm, which bounds the rounding of `o − c`.
#[derive(Clone, Copy, Debug)]
pub struct SphereRay {
    origin_norm: f32,
}

impl BoundingSphere {
    /// Surface area, for the SAH and tightness figures.
    pub fn surface_area(&self) -> f32 {
        4.0 * std::f32::consts::PI * self.radius * self.radius
    }
}

impl Volume for BoundingSphere {
    type Ray = SphereRay;

    #[inline(always)]
    fn prepare(ray: &TraceRay) -> SphereRay {
        SphereRay {
            origin_norm: ray.ray.origin.abs().element_sum(),
        }
    }

    #[inline(always)]
    fn hit(&self, ray: &SphereRay, trace: &TraceRay, t_max: f32) -> Option<f32> {
        let d = trace.ray.dir;
        let f = trace.ray.origin - self.center;
        let b = f.dot(d);
        // The offset of the centre from the ray's line, as in `Sphere::intersect`.
        let l = f - b * d;
        // Everything computed from f is off by a few ulps of |o| + |c| + |f|; |c| is in
        // the stored radius already.
        let slack = gamma(ROUNDINGS) * (f.abs().element_sum() + ray.origin_norm);
        let r = self.radius + slack;
        let disc = r * r - l.length_squared();
        if disc < 0.0 {
            return None;
        }
        let h = disc.sqrt();
        let t_enter = ((-b - h - slack) * (1.0 - gamma(4))).max(0.0);
        let t_exit = (-b + h + slack).min(t_max) * (1.0 + gamma(4));
        (t_enter <= t_exit).then_some(t_enter)
    }

    fn contains(&self, p: Vec3) -> bool {
        p.as_dvec3().distance(self.center.as_dvec3()) <= self.radius as f64
    }

    fn fit(geometry: &Geometry, prims: &[u32], bounds: &Aabb) -> Self {
        let box_center = bounds.center().as_dvec3();
        let mut points = Vec::new();
        for &p in prims {
            sample_points(geometry, p, &mut points);
        }
        let mean = points.iter().sum::<DVec3>() / points.len().max(1) as f64;
        let radius_about = |c: DVec3| {
            prims
                .iter()
                .map(|&p| farthest(geometry, p, c))
                .fold(0.0, f64::max)
        };
        let (center, radius) = [box_center, mean]
            .into_iter()
            .filter(|c| c.is_finite())
            .map(|c| {
                // The centre is stored in f32: measure from the rounded one.
                let c = c.as_vec3().as_dvec3();
                (c, radius_about(c))
            })
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .unwrap_or((box_center, radius_about(box_center)));
        let scale = center.abs().element_sum() + radius;
        BoundingSphere {
            center: center.as_vec3(),
            radius: round_up(radius + gamma(ROUNDINGS) as f64 * scale),
        }
    }
}
