//! The octree's bad case: a string of 10 000 pearls along the x axis, through the centre of
//! the scene's bounds. Every pearl straddles the octree's two centre planes along y and z,
//! so cutting the root into octants would copy each pearl into four of them; the build
//! refuses (more references than it saves) and leaves every pearl in the root leaf. A
//! kd-tree or BVH cuts the string along its length instead.

use crate::camera::{Camera, Projection};
use crate::geometry::{Shape, Sphere};
use crate::light::Light;
use crate::math::{Color, Vec3};
use crate::scene::Scene;
use crate::shading::{Material, Texture};

const PEARLS: u32 = 10_000;
const RADIUS: f32 = 0.05;

pub(super) fn pearls() -> Scene {
    let length = PEARLS as f32 * 2.0 * RADIUS;
    let start = -0.5 * length + RADIUS;
    let mut scene = Scene {
        camera: Camera {
            eye: Vec3::new(start - 1.0, -0.9, 0.45),
            look_at: Vec3::new(start + 3.0, 0.0, 0.0),
            up: Vec3::Z,
            fov_degrees: 45.0,
            projection: Projection::Perspective,
        },
        background: Color::new(0.1, 0.1, 0.14),
        ambient: Color::splat(0.15),
        ..Scene::default()
    };
    scene.options.width = 480;
    scene.options.height = 360;
    let pearl = scene.add_material(Material {
        name: "pearl".into(),
        color: Texture::Solid(Color::new(0.95, 0.92, 0.88)),
        ambient: 0.5,
        diffuse: 0.7,
        specular: 0.6,
        shininess: 60.0,
        reflect: 0.2,
        ..Material::default()
    });
    for i in 0..PEARLS {
        let centre = Vec3::new(start + i as f32 * 2.0 * RADIUS, 0.0, 0.0);
        scene
            .geometry
            .add(Shape::Sphere(Sphere::new(centre, RADIUS)), pearl);
    }
    super::staging::matte_floor(&mut scene, Color::new(0.3, 0.2, 0.25), -0.3);
    scene.lights = vec![
        Light::Point {
            position: Vec3::new(start, -3.0, 4.0),
            color: Color::splat(0.7),
        },
        Light::Directional {
            direction: Vec3::new(0.3, 0.5, -1.0).normalize(),
            color: Color::splat(0.3),
        },
    ];
    scene
}
