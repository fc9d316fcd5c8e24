//! The `[camera]` table to a `Camera`; an invalid camera is blamed on the key that makes
//! it so.

use super::diagnostics::Problem;
use super::schema::CameraDef;
use prism::camera::{Camera, CameraError, Projection};
use std::ops::Range;
use toml::Spanned;

/// The camera, keys left out keeping `defaults`; a problem points at the key that causes it.
pub(super) fn camera(def: Spanned<CameraDef>, defaults: Camera) -> Result<Camera, Problem> {
    let table = def.span();
    let def = def.into_inner();
    let camera = Camera {
        eye: def.eye.as_ref().map_or(defaults.eye, |v| v.get_ref().0),
        look_at: def
            .look_at
            .as_ref()
            .map_or(defaults.look_at, |v| v.get_ref().0),
        up: def.up.as_ref().map_or(defaults.up, |v| v.get_ref().0),
        fov_degrees: def
            .fov
            .as_ref()
            .map_or(defaults.fov_degrees, |v| v.get_ref().0),
        projection: def.orthographic.as_ref().map_or(defaults.projection, |v| {
            Projection::Orthographic {
                size: v.get_ref().0,
            }
        }),
    };
    let span_of = |key: Option<Range<usize>>| key.unwrap_or_else(|| table.clone());
    camera.validate().map_err(|e| {
        let (span, hint) = match e {
            CameraError::NoViewDirection => (
                span_of(def.look_at.as_ref().or(def.eye.as_ref()).map(Spanned::span)),
                "expected look_at to differ from eye",
            ),
            CameraError::UpParallel => (
                span_of(def.up.as_ref().map(Spanned::span)),
                "expected an up vector that is not parallel to look_at − eye",
            ),
            CameraError::FieldOfView(_) => (
                span_of(def.fov.as_ref().map(Spanned::span)),
                "expected fov in degrees, greater than 0 and less than 180",
            ),
            CameraError::OrthographicSize(_) => (
                span_of(def.orthographic.as_ref().map(Spanned::span)),
                "expected orthographic = the view's size across the shorter image side, > 0",
            ),
        };
        Problem::at(span, format!("invalid camera: {e}; {hint}"))
    })?;
    Ok(camera)
}
