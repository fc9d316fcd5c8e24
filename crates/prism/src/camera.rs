//! The pinhole camera: eye, look-at point, up vector and field of view.

use crate::math::{Ray, Vec3};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub eye: Vec3,
    pub look_at: Vec3,
    /// Need not be unit or perpendicular to the view direction, only not parallel to it.
    pub up: Vec3,
    /// Full field of view in degrees across the shorter image side (the vertical one for
    /// landscape images; both for square images, as NFF's `angle`).
    pub fov_degrees: f32,
}

#[derive(Debug, thiserror::Error, PartialEq)]
pub enum CameraError {
    #[error("the camera's eye and look-at point coincide")]
    NoViewDirection,
    #[error("the camera's up vector is parallel to its view direction")]
    UpParallel,
    #[error("the field of view must be between 0 and 180 degrees, got {0}")]
    FieldOfView(f32),
}

impl Camera {
    pub fn validate(&self) -> Result<(), CameraError> {
        let fwd = (self.look_at - self.eye)
            .try_normalize()
            .ok_or(CameraError::NoViewDirection)?;
        fwd.cross(self.up)
            .try_normalize()
            .ok_or(CameraError::UpParallel)?;
        if !(self.fov_degrees > 0.0 && self.fov_degrees < 180.0) {
            return Err(CameraError::FieldOfView(self.fov_degrees));
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
        let half = (self.fov_degrees.to_radians() * 0.5).tan();
        let short = width.min(height).max(1) as f32;
        // World units per pixel on the plane at distance 1.
        let pixel = 2.0 * half / short;
        Ok(CameraRays {
            eye: self.eye,
            forward,
            right: right * pixel,
            up: up * pixel,
            half_size: (width as f32 * 0.5, height as f32 * 0.5),
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
}

impl CameraRays {
    /// The ray through film position (x, y) in pixels, x to the right and y down from the
    /// top-left corner of the image.
    pub fn ray(&self, x: f32, y: f32) -> Ray {
        let dx = x - self.half_size.0;
        let dy = self.half_size.1 - y;
        let dir = (self.forward + dx * self.right + dy * self.up).normalize();
        Ray::new(self.eye, dir)
    }
}
