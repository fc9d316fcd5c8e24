//! The stage the bad-case scenes stand on: a matte floor plane and a key-and-fill light
//! pair, so each scene file only says what is particular to it.

use crate::geometry::{Plane, Shape};
use crate::light::Light;
use crate::math::{Color, Vec3};
use crate::scene::Scene;
use crate::shading::{Material, Texture};

/// Adds an endless matte floor of `colour` at height `z`.
pub(super) fn matte_floor(scene: &mut Scene, colour: Color, z: f32) {
    let floor = scene.add_material(Material {
        name: "floor".into(),
        color: Texture::Solid(colour),
        ambient: 0.5,
        diffuse: 0.7,
        ..Material::default()
    });
    let plane = Plane::new(Vec3::new(0.0, 0.0, z), Vec3::Z).expect("non-zero normal");
    scene.geometry.add(Shape::Plane(Box::new(plane)), floor);
}

/// A point light high at the front left and a dimmer directional fill.
pub(super) fn key_and_fill() -> Vec<Light> {
    vec![
        Light::Point {
            position: Vec3::new(-3.0, -4.0, 6.0),
            color: Color::splat(0.7),
        },
        Light::Directional {
            direction: Vec3::new(1.0, 0.5, -1.0).normalize(),
            color: Color::splat(0.3),
        },
    ]
}
