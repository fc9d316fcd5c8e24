//! The pinhole camera as beam tracing sees it, in f64: every beam, primary or secondary, has
//! the eye E as its apex and the film as its image plane, because a secondary beam carries
//! the affine map that takes the real scene into its *virtual* scene (the scene seen in the
//! mirror, or through the glass) instead of moving its apex. Film position (x, y) is the
//! ray E + t·D(x, y) with D affine in (x, y), exactly as `Camera::setup` builds it.

use super::convex::Affine2;
use crate::camera::{Camera, Projection};
use glam::{DVec2, DVec3};

/// The camera for one image size.
#[derive(Clone, Copy, Debug)]
pub(crate) struct View {
    /// The eye: every beam's apex.
    pub(crate) eye: DVec3,
    /// Unit view direction.
    forward: DVec3,
    /// Right and up, scaled to one pixel at distance 1.
    right: DVec3,
    up: DVec3,
    /// D(x, y) = d0 + x·dx + y·dy.
    d0: DVec3,
    dx: DVec3,
    dy: DVec3,
}

/// Why beam tracing cannot see through this camera.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum ViewError {
    /// Only the pinhole has an apex.
    #[error(
        "beam tracing needs a perspective camera; an orthographic one has no apex (use \
         --integrator whitted)"
    )]
    Orthographic,
}

fn d(v: glam::Vec3) -> DVec3 {
    DVec3::new(v.x as f64, v.y as f64, v.z as f64)
}

impl View {
    /// The view of `camera` for a `width` × `height` film; the camera has been validated.
    pub(crate) fn new(camera: &Camera, width: u32, height: u32) -> Result<View, ViewError> {
        if !matches!(camera.projection, Projection::Perspective) {
            return Err(ViewError::Orthographic);
        }
        let eye = d(camera.eye);
        let forward = (d(camera.look_at) - eye).normalize();
        let right = forward.cross(d(camera.up)).normalize();
        let up = right.cross(forward);
        let short = width.min(height).max(1) as f64;
        let pixel = 2.0 * ((camera.fov_degrees as f64).to_radians() * 0.5).tan() / short;
        let (right, up) = (right * pixel, up * pixel);
        let (hw, hh) = (width as f64 * 0.5, height as f64 * 0.5);
        Ok(View {
            eye,
            forward,
            right,
            up,
            d0: forward - hw * right + hh * up,
            dx: right,
            dy: -up,
        })
    }

    /// The (unnormalised) direction through film position `p`; its component along the view
    /// direction is 1, so the t of E + t·D is the depth.
    #[inline]
    pub(crate) fn dir(&self, p: DVec2) -> DVec3 {
        self.d0 + p.x * self.dx + p.y * self.dy
    }

    /// g·D(x, y) as an affine function of film position.
    pub(crate) fn along(&self, g: DVec3) -> Affine2 {
        Affine2 {
            a: g.dot(self.dx),
            b: g.dot(self.dy),
            c: g.dot(self.d0),
        }
    }

    /// The inverse depth 1/t of the plane n·X = k (virtual space) along the ray through
    /// (x, y): affine in film position, positive where the plane lies in front of the eye,
    /// larger where nearer. None for a plane through the eye (seen edge on).
    pub(crate) fn inverse_depth(&self, n: DVec3, k: f64) -> Option<Affine2> {
        let h = k - n.dot(self.eye);
        if h == 0.0 || !h.is_finite() {
            return None;
        }
        let f = self.along(n);
        Some(Affine2 {
            a: f.a / h,
            b: f.b / h,
            c: f.c / h,
        })
    }

    /// Film position of a point in front of the eye (depth > 0).
    pub(crate) fn project(&self, x: DVec3) -> DVec2 {
        let rel = x - self.eye;
        let z = self.forward.dot(rel);
        let px = self.right.dot(rel) / (z * self.right.length_squared());
        let py = self.up.dot(rel) / (z * self.up.length_squared());
        // Inverse of D: x = hw + px, y = hh − py, with d0 = F − hw·R + hh·U.
        let hw = -self.d0.dot(self.right) / self.right.length_squared();
        let hh = self.d0.dot(self.up) / self.up.length_squared();
        DVec2::new(hw + px, hh - py)
    }

    /// The four planes through the eye that bound the beam of the film rectangle
    /// [lo, hi], as (n, c) with n·X + c ≥ 0 inside.
    pub(crate) fn frustum(&self, lo: DVec2, hi: DVec2) -> [(DVec3, f64); 4] {
        let centre = self.dir((lo + hi) * 0.5);
        let plane = |a: DVec3, b: DVec3| {
            let mut n = a.cross(b);
            if n.dot(centre) < 0.0 {
                n = -n;
            }
            (n, -n.dot(self.eye))
        };
        [
            plane(self.dir(DVec2::new(lo.x, lo.y)), self.dy),
            plane(self.dir(DVec2::new(hi.x, lo.y)), self.dy),
            plane(self.dir(DVec2::new(lo.x, lo.y)), self.dx),
            plane(self.dir(DVec2::new(lo.x, hi.y)), self.dx),
        ]
    }
}

/// The part of a 3D polygon where n·X + c ≥ 0 for each plane (Sutherland–Hodgman).
pub(crate) fn clip_polygon(points: &[DVec3], planes: &[(DVec3, f64)]) -> Vec<DVec3> {
    let mut poly = points.to_vec();
    for &(n, c) in planes {
        if poly.len() < 3 {
            return Vec::new();
        }
        let values: Vec<f64> = poly.iter().map(|p| n.dot(*p) + c).collect();
        if values.iter().all(|&v| v >= 0.0) {
            continue;
        }
        let mut out = Vec::with_capacity(poly.len() + 1);
        for i in 0..poly.len() {
            let j = (i + 1) % poly.len();
            let (fp, fq) = (values[i], values[j]);
            if fp >= 0.0 {
                out.push(poly[i]);
            }
            if (fp > 0.0 && fq < 0.0) || (fp < 0.0 && fq > 0.0) {
                out.push(poly[i] + (poly[j] - poly[i]) * (fp / (fp - fq)));
            }
        }
        poly = out;
    }
    if poly.len() < 3 {
        Vec::new()
    } else {
        poly
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn projection_inverts_the_camera_rays() {
        let cam = Camera {
            eye: Vec3::new(1.0, 2.0, 3.0),
            look_at: Vec3::new(0.0, 0.5, -1.0),
            up: Vec3::Y,
            fov_degrees: 40.0,
            projection: Projection::Perspective,
        };
        let view = View::new(&cam, 64, 48).unwrap();
        let rays = cam.setup(64, 48).unwrap();
        for &(x, y) in &[(0.0, 0.0), (10.5, 7.25), (64.0, 48.0)] {
            let p = DVec2::new(x, y);
            let dir = view.dir(p);
            let r = rays.ray(x as f32, y as f32);
            let got = dir.normalize();
            assert!((got - d(r.dir)).length() < 1e-6, "{got} {:?}", r.dir);
            let back = view.project(view.eye + 3.5 * dir);
            assert!((back - p).length() < 1e-9, "{back} {p}");
        }
    }
}
