//! The octree's bad case: a string of 10 000 pearls along the x axis, through the centre of
//! the scene's bounds. Every pearl straddles the octree's two centre planes along y and z,
//! so cutting the root into octants would copy each pearl into four of them; the build
//! refuses (more references than it saves) and leaves every pearl in the root leaf. A
//! kd-tree or BVH cuts the string along its length instead.

use super::staging::stage;
use crate::camera::Camera;
use crate::geometry::{Shape, Sphere};
use crate::math::{Color, Vec3};
use crate::scene::Scene;
use crate::shading::Material;

const PEARLS: u32 = 10_000;
const RADIUS: f32 = 0.05;

pub(super) fn pearls() -> Scene {
    let length = PEARLS as f32 * 2.0 * RADIUS;
    let start = -0.5 * length + RADIUS;
    let camera = Camera::perspective(
        Vec3::new(start - 1.0, -0.9, 0.45),
        Vec3::new(start + 3.0, 0.0, 0.0),
        Vec3::Z,
        45.0,
    );
    let mut scene = stage(camera, (480, 360), Color::new(0.1, 0.1, 0.14), 0.15);
    let pearl = scene.add_material(
        Material::matte("pearl", Color::new(0.95, 0.92, 0.88), 0.5, 0.7)
            .glossy(0.6, 60.0)
            .reflecting(0.2),
    );
    for i in 0..PEARLS {
        let centre = Vec3::new(start + i as f32 * 2.0 * RADIUS, 0.0, 0.0);
        scene
            .geometry
            .add(Shape::Sphere(Sphere::new(centre, RADIUS)), pearl);
    }
    super::staging::matte_floor(&mut scene, Color::new(0.3, 0.2, 0.25), -0.3);
    scene.lights = super::staging::key_and_fill_at([start, -3.0, 4.0], 0.7, [0.3, 0.5, -1.0], 0.3);
    scene
}
