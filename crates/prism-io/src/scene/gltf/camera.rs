//! The view: the first camera among the scene's nodes, or a default camera that frames
//! the scene's bounds.
//!
//! A glTF camera looks down its node's −Z axis with +Y up. A perspective one's `yfov` is its
//! vertical field of view; an orthographic one's `xmag` and `ymag` are half the width and
//! height of its window. Prism's camera takes eye, look-at point, up vector and the field of
//! view (or the window's size) across the shorter image side, which for a portrait image is
//! the horizontal one.

use glam::{DAffine3, DVec3};
use gltf::json::Root;
use prism::camera::{Camera, Projection};
use prism::math::{Aabb, Vec3};
use prism::options::RenderOptions;

/// The default camera's field of view, in degrees.
const DEFAULT_FOV_DEGREES: f32 = 40.0;
/// The default camera looks at the scene from the front (+Z), slightly from above.
const DEFAULT_VIEW_FROM: Vec3 = Vec3::new(0.0, 0.3, 1.0);
/// Room left around the bounding sphere in the default view.
const DEFAULT_MARGIN: f32 = 1.1;

/// The camera for the scene; `options` gets the image size a camera's aspectRatio asks for.
pub(super) fn camera(
    root: &Root,
    placed: Option<(usize, DAffine3)>,
    bounds: Aabb,
    options: &mut RenderOptions,
) -> Result<Camera, String> {
    match placed {
        Some((index, world)) => from_node(root, index, &world, bounds, options)
            .map_err(|e| format!("camera {index}: {e}")),
        None => Ok(framing(bounds)),
    }
}

fn from_node(
    root: &Root,
    index: usize,
    world: &DAffine3,
    bounds: Aabb,
    options: &mut RenderOptions,
) -> Result<Camera, String> {
    let camera = root
        .cameras
        .get(index)
        .ok_or_else(|| format!("does not exist (the file has {})", root.cameras.len()))?;
    let (fov, projection) = match (&camera.perspective, &camera.orthographic) {
        (Some(p), _) => (perspective_fov(p, options)?, Projection::Perspective),
        (None, Some(o)) => (0.0, orthographic(o, options)?),
        (None, None) => {
            return Err("expected a 'perspective' or an 'orthographic' object".into());
        }
    };
    let mut camera = pose(world, bounds)?;
    camera.fov_degrees = fov.to_degrees();
    camera.projection = projection;
    Ok(camera)
}

/// Shapes the image to `aspect` (width / height), keeping its longer side.
fn shape_image(aspect: f32, options: &mut RenderOptions) {
    let long = options.width.max(options.height) as f32;
    let (w, h) = if aspect >= 1.0 {
        (long, long / aspect)
    } else {
        (long * aspect, long)
    };
    options.width = (w.round() as u32).max(1);
    options.height = (h.round() as u32).max(1);
}

/// The field of view across the shorter image side, in radians.
fn perspective_fov(
    p: &gltf::json::camera::Perspective,
    options: &mut RenderOptions,
) -> Result<f32, String> {
    let yfov = p.yfov;
    if !(yfov > 0.0 && yfov < std::f32::consts::PI) {
        return Err(format!(
            "yfov is {yfov}; expected an angle in radians between 0 and π"
        ));
    }
    if let Some(a) = p.aspect_ratio {
        if !(a > 0.0 && a.is_finite()) {
            return Err(format!("aspectRatio is {a}; expected a number > 0"));
        }
        shape_image(a, options);
    }
    let aspect = options.width as f32 / options.height as f32;
    // Portrait images: prism's field of view spans the width, the shorter side.
    Ok(if aspect >= 1.0 {
        yfov
    } else {
        2.0 * (aspect * (yfov * 0.5).tan()).atan()
    })
}

/// An orthographic window: the image takes its shape, and the projection its size across
/// the shorter side.
fn orthographic(
    o: &gltf::json::camera::Orthographic,
    options: &mut RenderOptions,
) -> Result<Projection, String> {
    let (x, y) = (o.xmag.abs(), o.ymag.abs());
    if !(x > 0.0 && x.is_finite() && y > 0.0 && y.is_finite()) {
        return Err(format!(
            "xmag {} and ymag {}; expected non-zero finite half-sizes of the view",
            o.xmag, o.ymag
        ));
    }
    shape_image(x / y, options);
    Ok(Projection::Orthographic {
        size: 2.0 * x.min(y),
    })
}

/// Eye, look-at point and up vector from the camera node's world transform.
fn pose(world: &DAffine3, bounds: Aabb) -> Result<Camera, String> {
    let eye = world.translation.as_vec3();
    let forward = world.transform_vector3(DVec3::NEG_Z).try_normalize();
    let up = world.transform_vector3(DVec3::Y).try_normalize();
    let (Some(forward), Some(up)) = (forward, up) else {
        return Err("its node's transform leaves it no view direction or up vector".into());
    };
    if !eye.is_finite() {
        return Err("its node places it at infinity".into());
    }
    // Only the direction to look_at matters; a distance on the scene's own scale keeps
    // eye + forward·distance from rounding back onto the eye.
    let distance = [
        bounds.center().distance(eye),
        bounds.extent().length(),
        eye.length(),
    ]
    .into_iter()
    .filter(|d| d.is_finite())
    .fold(0.0f32, f32::max);
    let distance = if distance > 0.0 { distance } else { 1.0 };
    Ok(Camera {
        eye,
        look_at: eye + forward.as_vec3() * distance,
        up: up.as_vec3(),
        fov_degrees: DEFAULT_FOV_DEGREES,
        projection: Projection::Perspective,
    })
}

/// The camera of a scene without one: looking at the centre of the bounds from the front
/// and slightly above, far enough back that the bounding sphere fits the view.
fn framing(bounds: Aabb) -> Camera {
    if bounds.is_empty() {
        return prism::scene::Scene::default().camera;
    }
    let center = bounds.center();
    let radius = 0.5 * bounds.extent().length();
    let radius = if radius > 0.0 && radius.is_finite() {
        radius
    } else {
        // A single point: any distance shows it; pick one on its own scale.
        center.length().max(1.0)
    };
    let half_fov = (DEFAULT_FOV_DEGREES * 0.5).to_radians();
    let distance = DEFAULT_MARGIN * radius / half_fov.sin();
    Camera {
        eye: center + DEFAULT_VIEW_FROM.normalize() * distance,
        look_at: center,
        up: Vec3::Y,
        fov_degrees: DEFAULT_FOV_DEGREES,
        projection: Projection::Perspective,
    }
}
