//! Camera motion from the page: orbit around the look-at point, pan both points across
//! the view, zoom the eye towards the look-at point (or shrink an orthographic window).
//! Every result is checked: a motion that would leave a camera prism cannot render (no
//! view direction, up along the view, a coordinate out of range) is refused and the old
//! camera kept.

use crate::limits::MAX_COORDINATE;
use prism::camera::{Camera, Projection};
use prism::math::Vec3;

/// One step of camera motion, as the page sends it after a drag, a wheel turn or a key.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Motion {
    /// Degrees to turn around the look-at point: (to the right about the up axis, upwards).
    pub orbit: [f32; 2],
    /// How far to move eye and look-at point together, in view heights: (right, up).
    pub pan: [f32; 2],
    /// Doublings of closeness: 1 halves the distance to the look-at point, -1 doubles it.
    pub zoom: f32,
}

impl Motion {
    /// Checks that every number is finite and within [`MAX_STEP`].
    pub fn check(&self) -> Result<(), SteerError> {
        for v in self.orbit {
            check("orbit", v, MAX_STEP[0])?;
        }
        for v in self.pan {
            check("pan", v, MAX_STEP[1])?;
        }
        check("zoom", self.zoom, MAX_STEP[2])
    }
}

/// The largest orbit step in degrees, pan step in view heights and zoom step in doublings
/// a message may carry; more is a broken client, not a fast mouse.
pub const MAX_STEP: [f32; 3] = [720.0, 100.0, 20.0];

/// Nearest the eye may come to the look-at point, as a fraction of its first distance, and
/// the farthest, so that zooming stays reversible and finite.
const ZOOM_RANGE: (f32, f32) = (1.0e-4, 1.0e4);

/// Why a camera or a motion was refused.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum SteerError {
    /// A number that is not finite or beyond the limits.
    #[error("{what} must be a finite number within ±{limit}, got {value}")]
    OutOfRange {
        /// Which value.
        what: &'static str,
        /// Its allowed magnitude.
        limit: f32,
        /// What came.
        value: f32,
    },
    /// The result is not a camera prism can render.
    #[error("that camera cannot render: {0}")]
    Camera(#[from] prism::camera::CameraError),
}

fn check(what: &'static str, value: f32, limit: f32) -> Result<(), SteerError> {
    if value.is_finite() && value.abs() <= limit {
        Ok(())
    } else {
        Err(SteerError::OutOfRange { what, limit, value })
    }
}

fn check_point(what: &'static str, p: Vec3) -> Result<(), SteerError> {
    for v in p.to_array() {
        check(what, v, MAX_COORDINATE)?;
    }
    Ok(())
}

/// Checks a camera sent whole by a page: finite coordinates within range, a view direction
/// and an up vector that is not along it, a field of view in (0°, 180°).
pub fn check_camera(camera: &Camera) -> Result<(), SteerError> {
    check_point("eye", camera.eye)?;
    check_point("look_at", camera.look_at)?;
    check_point("up", camera.up)?;
    check("fov", camera.fov_degrees, 180.0)?;
    camera.validate()?;
    Ok(())
}

/// `camera` moved by `motion`; `home` is the scene's own camera, whose distance sets the
/// zoom range. Refused (with the reason) when a value is out of range or the result
/// cannot render.
pub fn apply(camera: &Camera, home: &Camera, motion: &Motion) -> Result<Camera, SteerError> {
    motion.check()?;
    let mut out = *camera;
    let up = camera.up.normalize_or_zero();
    let offset = camera.eye - camera.look_at;
    let distance = offset.length();
    if distance == 0.0 || up == Vec3::ZERO {
        return Err(prism::camera::CameraError::NoViewDirection.into());
    }

    // Orbit: turn the offset about the up axis, then tilt it towards or away from up,
    // never past 1° from the pole so the up vector keeps giving a sideways direction.
    let [yaw, pitch] = motion.orbit.map(f32::to_radians);
    let turned = glam::Quat::from_axis_angle(up, -yaw) * offset;
    let from_up = turned.normalize().dot(up).clamp(-1.0, 1.0).acos();
    let limit = 1.0f32.to_radians();
    let new_from_up = (from_up - pitch).clamp(limit, std::f32::consts::PI - limit);
    let horizontal = (turned - up * turned.dot(up)).normalize_or_zero();
    let offset = if horizontal == Vec3::ZERO {
        turned
    } else {
        (up * new_from_up.cos() + horizontal * new_from_up.sin()) * distance
    };

    // Zoom: the eye slides along the view line (perspective) or the window shrinks
    // (orthographic), within a range set by the scene's own camera.
    let home_distance = (home.eye - home.look_at).length().max(f32::MIN_POSITIVE);
    let factor = (-motion.zoom).exp2();
    let offset = match camera.projection {
        Projection::Perspective => {
            let d = (distance * factor)
                .clamp(home_distance * ZOOM_RANGE.0, home_distance * ZOOM_RANGE.1);
            offset.normalize() * d
        }
        Projection::Orthographic { size } => {
            out.projection = Projection::Orthographic {
                size: (size * factor).clamp(size.min(1.0) * 1.0e-6, 1.0e7),
            };
            offset
        }
    };

    // Pan: both points move across the view by a fraction of the view's height at the
    // look-at point, so a drag moves the scene with the mouse at any distance.
    let forward = -offset.normalize();
    let right = forward.cross(up).normalize_or_zero();
    let screen_up = right.cross(forward);
    let height = match out.projection {
        Projection::Perspective => {
            2.0 * offset.length() * (camera.fov_degrees.to_radians() * 0.5).tan()
        }
        Projection::Orthographic { size } => size,
    };
    let shift = (right * motion.pan[0] + screen_up * motion.pan[1]) * height;
    out.look_at = camera.look_at + shift;
    out.eye = out.look_at + offset;
    check_camera(&out)?;
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera() -> Camera {
        Camera {
            eye: Vec3::new(0.0, 0.0, 10.0),
            look_at: Vec3::ZERO,
            up: Vec3::Y,
            fov_degrees: 45.0,
            projection: Projection::Perspective,
        }
    }

    #[test]
    fn orbiting_keeps_the_distance_and_the_look_at_point() {
        let c = camera();
        let moved = apply(
            &c,
            &c,
            &Motion {
                orbit: [90.0, 30.0],
                ..Motion::default()
            },
        )
        .unwrap();
        assert_eq!(moved.look_at, Vec3::ZERO);
        assert!(((moved.eye - moved.look_at).length() - 10.0).abs() < 1e-4);
        assert!(moved.eye.y > 4.9, "tilted up by 30°: {:?}", moved.eye);
        // A quarter turn to the right puts the eye on the -x side.
        assert!(moved.eye.x < -8.0, "{:?}", moved.eye);
    }

    #[test]
    fn orbiting_stops_short_of_the_pole() {
        let c = camera();
        let moved = apply(
            &c,
            &c,
            &Motion {
                orbit: [0.0, 500.0],
                ..Motion::default()
            },
        )
        .unwrap();
        assert!(moved.validate().is_ok());
        assert!(moved.eye.y < 10.0 && moved.eye.y > 9.9);
    }

    #[test]
    fn zoom_halves_the_distance_and_pan_moves_both_points() {
        let c = camera();
        let z = apply(
            &c,
            &c,
            &Motion {
                zoom: 1.0,
                ..Motion::default()
            },
        )
        .unwrap();
        assert!((z.eye.z - 5.0).abs() < 1e-5);
        let p = apply(
            &c,
            &c,
            &Motion {
                pan: [0.5, 0.0],
                ..Motion::default()
            },
        )
        .unwrap();
        assert!(p.look_at.x > 0.0 && (p.eye.x - p.look_at.x).abs() < 1e-5);
    }

    #[test]
    fn hostile_numbers_are_refused() {
        let c = camera();
        for m in [
            Motion {
                orbit: [f32::NAN, 0.0],
                ..Motion::default()
            },
            Motion {
                pan: [f32::INFINITY, 0.0],
                ..Motion::default()
            },
            Motion {
                zoom: 1.0e30,
                ..Motion::default()
            },
        ] {
            assert!(apply(&c, &c, &m).is_err(), "{m:?}");
        }
        let bad = Camera {
            eye: Vec3::new(f32::NAN, 0.0, 0.0),
            ..c
        };
        assert!(check_camera(&bad).is_err());
        let same = Camera {
            look_at: c.eye,
            ..c
        };
        assert!(check_camera(&same).is_err());
    }
}
