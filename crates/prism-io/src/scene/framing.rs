//! A camera and a light for a scene that is only a mesh (an OBJ or PLY file rendered on its
//! own). Everything is measured from the mesh's bounds, so a model in millimetres and one
//! in kilometres get the same picture: the camera looks at the centre of the bounds from
//! the front (+z), a little right and above, with y up (the convention of most mesh files);
//! a directional light shines from above left.

use super::Scene;
use prism::camera::{Camera, Projection};
use prism::light::Light;
use prism::math::{Color, Vec3};

/// Full field of view, degrees, across the shorter image side.
const FOV_DEGREES: f32 = 40.0;
/// From the centre of the bounds towards the eye.
const VIEW_DIRECTION: Vec3 = Vec3::new(0.35, 0.3, 1.0);
/// The way the light travels: from above left and in front, down towards the scene.
const LIGHT_DIRECTION: Vec3 = Vec3::new(0.6, -1.0, -0.8);

/// Sets the scene's camera, light, ambient light and background so that the geometry
/// fills the view. Fails when the geometry has no extent to frame.
pub(super) fn frame(scene: &mut Scene) -> Result<(), String> {
    let bounds = scene.geometry.world_bounds();
    let radius = 0.5 * bounds.extent().length();
    if bounds.is_empty() || !(radius > 0.0 && radius.is_finite()) {
        return Err(format!(
            "cannot place a camera: the faces span {:?} to {:?}; expected bounds of finite, \
             non-zero size",
            bounds.min, bounds.max
        ));
    }
    let center = bounds.center();
    // The bounding sphere of the box just fits the field of view; the mesh rarely reaches
    // the box's corners, so that leaves a margin.
    let distance = radius / (0.5 * FOV_DEGREES).to_radians().sin();
    let camera = Camera {
        eye: center + VIEW_DIRECTION.normalize() * distance,
        look_at: center,
        up: Vec3::Y,
        fov_degrees: FOV_DEGREES,
        projection: Projection::Perspective,
    };
    camera
        .validate()
        .map_err(|e| format!("cannot place a camera around the faces: {e}"))?;
    scene.camera = camera;
    scene.lights = vec![Light::Directional {
        direction: LIGHT_DIRECTION.normalize(),
        color: Color::splat(0.9),
    }];
    scene.ambient = Color::splat(0.15);
    scene.background = Color::new(0.12, 0.13, 0.16);
    Ok(())
}
