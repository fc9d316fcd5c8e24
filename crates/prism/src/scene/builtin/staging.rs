//! What the built-in scenes share: the scene around a camera, and the stage the bad-case
//! scenes stand on (a matte floor plane and a key-and-fill light pair), so each scene file
//! only says what is particular to it.

use crate::camera::Camera;
use crate::geometry::{Plane, Shape};
use crate::light::Light;
use crate::math::{Color, Vec3};
use crate::scene::Scene;
use crate::shading::Material;

/// An empty scene seen through `camera` at `width` × `height` pixels, `background` where
/// rays leave it and an ambient light of `ambient` in every channel.
pub(super) fn stage(
    camera: Camera,
    (width, height): (u32, u32),
    background: Color,
    ambient: f32,
) -> Scene {
    let mut scene = Scene {
        camera,
        background,
        ambient: Color::splat(ambient),
        ..Scene::default()
    };
    scene.options.width = width;
    scene.options.height = height;
    scene
}

/// Adds an endless matte floor of `colour` at height `z`.
pub(super) fn matte_floor(scene: &mut Scene, colour: Color, z: f32) {
    let floor = scene.add_material(Material::matte("floor", colour, 0.5, 0.7));
    let plane = Plane::new(Vec3::new(0.0, 0.0, z), Vec3::Z).expect("non-zero normal");
    scene.geometry.add(Shape::Plane(Box::new(plane)), floor);
}

/// A point light high at the front left and a dimmer directional fill.
pub(super) fn key_and_fill() -> Vec<Light> {
    key_and_fill_at([-3.0, -4.0, 6.0], 0.7, [1.0, 0.5, -1.0], 0.3)
}

/// A point light at `key_at` of grey `key` and a directional fill towards `fill_towards`
/// of grey `fill`: the scenes that place their own.
pub(super) fn key_and_fill_at(
    key_at: [f32; 3],
    key: f32,
    fill_towards: [f32; 3],
    fill: f32,
) -> Vec<Light> {
    vec![
        Light::Point {
            position: Vec3::from(key_at),
            color: Color::splat(key),
        },
        Light::Directional {
            direction: Vec3::from(fill_towards).normalize(),
            color: Color::splat(fill),
        },
    ]
}
