//! KHR_lights_punctual lights as prism lights, and the light a scene without any gets.
//!
//! glTF lights are physical: a point light's intensity is in candela and falls off with
//! the inverse square of distance; a directional light's is in lux. Prism's lights have no
//! falloff: a light's colour is the irradiance it gives a surface facing it. Each light
//! therefore gets the irradiance it delivers at the centre of the scene's bounds
//! (intensity/d² for point and spot lights, the intensity for directional ones), and all
//! of them are scaled together so those irradiances add up to 1. Relative brightness is
//! kept, and the absolute units (which exporters choose very differently) do not decide
//! whether the image is black or white: an automatic exposure.

use glam::{DAffine3, DVec3};
use gltf::json::extensions::scene::khr_lights_punctual::Type;
use gltf::json::validation::Checked;
use gltf::json::Root;
use prism::camera::Camera;
use prism::light::Light;
use prism::math::{Aabb, Color, Vec3};

/// Point lights closer to the reference point than this fraction of the scene's size are
/// treated as being this far, so one light inside an object cannot take all the exposure.
const MIN_DISTANCE_FRACTION: f32 = 0.05;

/// Rec. 709 luminance, to weigh coloured lights in the exposure.
fn luminance(c: Color) -> f32 {
    c.dot(Vec3::new(0.2126, 0.7152, 0.0722))
}

/// Light `index` where `world` places it, its colour in glTF units (colour × intensity).
fn place(root: &Root, index: usize, world: &DAffine3) -> Result<Light, String> {
    let lights = root
        .extensions
        .as_ref()
        .and_then(|e| e.khr_lights_punctual.as_ref())
        .map_or(&[][..], |l| &l.lights[..]);
    let light = lights.get(index).ok_or_else(|| {
        format!(
            "light {index} does not exist (the file has {} KHR_lights_punctual lights)",
            lights.len()
        )
    })?;
    let color = Color::from(light.color) * light.intensity;
    if !color.is_finite() || color.min_element() < 0.0 {
        return Err(format!(
            "light {index}: expected a colour and intensity ≥ 0, got colour {:?} and \
             intensity {}",
            light.color, light.intensity
        ));
    }
    let kind = match light.type_ {
        Checked::Valid(k) => k,
        Checked::Invalid => return Err(format!("light {index} has an invalid type")),
    };
    match kind {
        Type::Point => Ok(Light::Point {
            position: position(index, world)?,
            color,
        }),
        Type::Spot => {
            // KHR_lights_punctual's defaults: inner 0, outer π/4; 0 ≤ inner < outer ≤ π/2.
            let spot = light.spot.as_ref();
            let inner = spot.map_or(0.0, |s| s.inner_cone_angle);
            let outer = spot.map_or(std::f32::consts::FRAC_PI_4, |s| s.outer_cone_angle);
            if !(0.0 <= inner && inner <= outer && outer <= std::f32::consts::FRAC_PI_2) {
                return Err(format!(
                    "light {index}: cone angles inner {inner} and outer {outer}; expected \
                     0 ≤ inner ≤ outer ≤ π/2 (radians)"
                ));
            }
            Ok(Light::Spot {
                position: position(index, world)?,
                direction: direction(index, world)?,
                color,
                cos_inner: inner.cos(),
                cos_outer: outer.cos(),
            })
        }
        Type::Directional => Ok(Light::Directional {
            direction: direction(index, world)?,
            color,
        }),
    }
}

fn position(index: usize, world: &DAffine3) -> Result<Vec3, String> {
    let position = world.translation.as_vec3();
    if !position.is_finite() {
        return Err(format!("light {index}: its node places it at infinity"));
    }
    Ok(position)
}

/// Directional and spot lights shine along their node's −Z axis.
fn direction(index: usize, world: &DAffine3) -> Result<Vec3, String> {
    world
        .transform_vector3(DVec3::NEG_Z)
        .try_normalize()
        .map(|d| d.as_vec3())
        .ok_or_else(|| format!("light {index}: its node's transform leaves it no direction"))
}

/// The lights the scene's nodes place, exposed for a scene within `bounds`.
pub(super) fn lights(
    root: &Root,
    placed: &[(usize, DAffine3)],
    bounds: Aabb,
) -> Result<Vec<Light>, String> {
    let mut lights = placed
        .iter()
        .map(|(index, world)| place(root, *index, world))
        .collect::<Result<Vec<_>, _>>()?;
    let (center, size) = if bounds.is_empty() {
        (Vec3::ZERO, 0.0)
    } else {
        (bounds.center(), bounds.extent().length())
    };
    let min_distance = f64::from(MIN_DISTANCE_FRACTION * size);
    // Irradiance at the centre per unit of each light's colour. In f64: candela over
    // squared millimetres can exceed f32's range before the exposure brings it back.
    let falloff = |l: &Light| match l.position() {
        Some(position) => {
            let d = f64::from(position.distance(center)).max(min_distance);
            if d > 0.0 {
                1.0 / (d * d)
            } else {
                1.0
            }
        }
        None => 1.0,
    };
    let total: f64 = lights
        .iter()
        .map(|l| f64::from(luminance(l.color())) * falloff(l))
        .sum();
    // A total of 0 means every light is black; they stay black.
    let exposure = if total > 0.0 { 1.0 / total } else { 0.0 };
    for l in &mut lights {
        let scale = (exposure * falloff(l)) as f32;
        *l.color_mut() *= scale;
    }
    Ok(lights)
}

/// The light of a scene that defines none: white, directional, coming over the viewer's
/// left shoulder (45° above the view direction, a little from the left).
pub(super) fn default_light(camera: &Camera) -> Light {
    let forward = (camera.look_at - camera.eye).normalize_or(Vec3::NEG_Z);
    let right = forward.cross(camera.up).normalize_or(Vec3::X);
    let up = right.cross(forward);
    Light::Directional {
        direction: (forward - up + 0.5 * right).normalize(),
        color: Color::ONE,
    }
}
