//! Infinite planes: floors that run to the horizon. Unbounded, so accelerators keep them in
//! a separate list that every ray tests.

use super::{ShapeHit, SurfacePoint};
use crate::math::robust::gamma;
use crate::math::{Frame, Ray, Vec2, Vec3};

/// An infinite plane through a point, facing the z axis of its frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane {
    /// A point on the plane; the origin of its uv parameters.
    pub point: Vec3,
    frame: Frame,
}

impl Plane {
    /// A plane through `point` facing `normal` (any length but zero).
    pub fn new(point: Vec3, normal: Vec3) -> Option<Self> {
        let n = normal.try_normalize()?;
        Some(Plane {
            point,
            frame: Frame::from_z(n),
        })
    }

    /// The unit normal (the side the plane faces).
    pub fn normal(&self) -> Vec3 {
        self.frame.z
    }

    /// The hit with `0 < t < t_max`, from either side.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<ShapeHit> {
        let n = self.frame.z;
        let denom = n.dot(ray.dir);
        if denom == 0.0 {
            return None;
        }
        let t = n.dot(self.point - ray.origin) / denom;
        (t > 0.0 && t < t_max).then_some(ShapeHit { t, u: 0.0, v: 0.0 })
    }

    /// The point, normals and uv (coordinates in the plane's frame) of a hit.
    pub fn surface(&self, ray: &Ray, hit: &ShapeHit) -> SurfacePoint {
        let n = self.frame.z;
        let q = ray.at(hit.t);
        // Project back onto the plane so the error is relative to the coordinates only.
        let p = q - n * n.dot(q - self.point);
        let p_error = gamma(8) * (p.abs() + self.point.abs());
        let local = p - self.point;
        let uv = Vec2::new(local.dot(self.frame.x), local.dot(self.frame.y));
        SurfacePoint::flat(p, p_error, n, uv)
    }
}
