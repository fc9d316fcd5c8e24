//! The camera: eye, look-at point, up vector, and either a pinhole's field of view
//! (perspective) or the size of a window of parallel rays (orthographic).

use crate::math::{Ray, Vec3};

/// Where the picture is taken from and how: the eye, the point it looks at, which way is up, and
/// the projection.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// The eye point (perspective) or the centre of the window of rays (orthographic).
    pub eye: Vec3,
    /// The point the view direction aims at.
    pub look_at: Vec3,
    /// Need not be unit or perpendicular to the view direction, only not parallel to it.
    pub up: Vec3,
    /// Full field of view in degrees across the shorter image side (the vertical one for
    /// landscape images; both for square images, as NFF's `angle`). Perspective only.
    pub fov_degrees: f32,
    /// Perspective or orthographic.
    pub projection: Projection,
}

/// How the image maps onto rays.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Projection {
    /// Rays from the eye through an image plane, spanning `fov_degrees`.
    #[default]
    Perspective,
    /// Parallel rays along the view direction, leaving a window centred on the eye that is
    /// `size` world units across the shorter image side (glTF's 2·ymag for a landscape
    /// image). Nothing behind the eye's plane is seen.
    Orthographic {
        /// Width of the window across the shorter image side, in world units.
        size: f32,
    },
}

/// Why a camera cannot make rays.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum CameraError {
    /// Eye and look-at point are the same, so there is no view direction.
    #[error("the camera's eye and look-at point coincide")]
    NoViewDirection,
    /// The up vector gives no sideways direction.
    #[error("the camera's up vector is parallel to its view direction")]
    UpParallel,
    /// A field of view outside (0, 180) degrees.
    #[error("the field of view must be between 0 and 180 degrees, got {0}")]
    FieldOfView(f32),
    /// An orthographic window that is not positive and finite.
    #[error("an orthographic view must be wider than 0 and finite, got {0}")]
    OrthographicSize(f32),
}

impl Camera {
    /// A pinhole at `eye` aiming at `look_at`, `up` upwards, `fov_degrees` across the
    /// shorter image side.
    pub fn perspective(eye: Vec3, look_at: Vec3, up: Vec3, fov_degrees: f32) -> Self {
        Camera {
            eye,
            look_at,
            up,
            fov_degrees,
            projection: Projection::Perspective,
        }
    }

    /// Checks that the camera defines a view: a direction, a sideways axis and a valid field of
    /// view or window.
    pub fn validate(&self) -> Result<(), CameraError> {
        let fwd = (self.look_at - self.eye)
            .try_normalize()
            .ok_or(CameraError::NoViewDirection)?;
        fwd.cross(self.up)
            .try_normalize()
            .ok_or(CameraError::UpParallel)?;
        match self.projection {
            Projection::Perspective => {
                if !(self.fov_degrees > 0.0 && self.fov_degrees < 180.0) {
                    return Err(CameraError::FieldOfView(self.fov_degrees));
                }
            }
            Projection::Orthographic { size } => {
                if !(size > 0.0 && size.is_finite()) {
                    return Err(CameraError::OrthographicSize(size));
                }
            }
        }
        Ok(())
    }

    /// Precomputes the image plane for a `width` × `height` image.
    pub fn setup(&self, width: u32, height: u32) -> Result<CameraRays, CameraError> {
        self.validate()?;
        let forward = (self.look_at - self.eye).normalize();
        // Right-handed: right = forward × up, so +y in the image is `up` and +x is right.
        let right = forward.cross(self.up).normalize();
        let up = right.cross(forward);
        let short = width.min(height).max(1) as f32;
        let (pixel, orthographic) = match self.projection {
            // World units per pixel on the plane at distance 1.
            Projection::Perspective => {
                let half = (self.fov_degrees.to_radians() * 0.5).tan();
                (2.0 * half / short, false)
            }
            // World units per pixel on the window through the eye.
            Projection::Orthographic { size } => (size / short, true),
        };
        Ok(CameraRays {
            eye: self.eye,
            forward,
            right: right * pixel,
            up: up * pixel,
            half_size: (width as f32 * 0.5, height as f32 * 0.5),
            orthographic,
        })
    }
}

/// A camera set up for one image size: turns film positions into rays.
#[derive(Clone, Copy, Debug)]
pub struct CameraRays {
    eye: Vec3,
    forward: Vec3,
    right: Vec3,
    up: Vec3,
    half_size: (f32, f32),
    orthographic: bool,
}

impl CameraRays {
    /// The ray through film position (x, y) in pixels, x to the right and y down from the
    /// top-left corner of the image.
    pub fn ray(&self, x: f32, y: f32) -> Ray {
        let dx = x - self.half_size.0;
        let dy = self.half_size.1 - y;
        let offset = dx * self.right + dy * self.up;
        if self.orthographic {
            return Ray::new(self.eye + offset, self.forward);
        }
        Ray::new(self.eye, (self.forward + offset).normalize())
    }
}

#[cfg(test)]
mod projection_tests {
    use super::*;

    fn camera(projection: Projection) -> Camera {
        Camera {
            eye: Vec3::new(0.0, 0.0, 10.0),
            look_at: Vec3::ZERO,
            up: Vec3::Y,
            fov_degrees: 90.0,
            projection,
        }
    }

    #[test]
    fn orthographic_rays_are_parallel_and_span_the_window() {
        let rays = camera(Projection::Orthographic { size: 4.0 })
            .setup(200, 100)
            .unwrap();
        // 4 units over the 100-pixel height: 0.04 per pixel, centred on the eye.
        let centre = rays.ray(100.0, 50.0);
        assert_eq!(centre.origin, Vec3::new(0.0, 0.0, 10.0));
        assert_eq!(centre.dir, Vec3::NEG_Z);
        let corner = rays.ray(0.0, 0.0);
        assert!((corner.origin - Vec3::new(-4.0, 2.0, 10.0)).length() < 1e-5);
        assert_eq!(corner.dir, Vec3::NEG_Z);
    }

    #[test]
    fn a_perspective_ray_leaves_the_eye_at_the_field_of_view() {
        let rays = camera(Projection::Perspective).setup(100, 100).unwrap();
        let edge = rays.ray(100.0, 50.0);
        assert_eq!(edge.origin, Vec3::new(0.0, 0.0, 10.0));
        // 90° across: the right edge is 45° off the axis.
        assert!((edge.dir - Vec3::new(1.0, 0.0, -1.0).normalize()).length() < 1e-6);
    }

    #[test]
    fn an_empty_window_is_refused() {
        for size in [0.0, -1.0, f32::INFINITY, f32::NAN] {
            let err = camera(Projection::Orthographic { size }).validate();
            assert!(
                matches!(err, Err(CameraError::OrthographicSize(_))),
                "{size}"
            );
        }
    }
}
