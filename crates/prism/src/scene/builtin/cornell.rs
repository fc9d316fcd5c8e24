//! A Cornell box lit by one point light below the ceiling, with a mirror sphere and a glass
//! sphere: every Whitted effect in a closed room.

use super::staging::stage;
use crate::camera::Camera;
use crate::geometry::{generate, Shape, Sphere};
use crate::light::Light;
use crate::math::{Color, Vec3};
use crate::scene::Scene;
use crate::shading::Material;

pub(super) fn cornell() -> Scene {
    let camera = Camera::perspective(
        Vec3::new(0.5, 0.5, -1.35),
        Vec3::new(0.5, 0.5, 0.5),
        Vec3::Y,
        38.0,
    );
    let mut scene = stage(camera, (512, 512), Color::ZERO, 0.15);

    let wall = |scene: &mut Scene, name: &str, color: Color| {
        scene.add_material(Material::matte(name, color, 1.0, 0.85))
    };
    let white = wall(&mut scene, "white", Color::splat(0.75));
    let red = wall(&mut scene, "red", Color::new(0.75, 0.1, 0.1));
    let green = wall(&mut scene, "green", Color::new(0.12, 0.6, 0.12));
    let mirror = scene.add_material(
        Material::matte("mirror", Color::splat(0.9), 0.0, 0.0)
            .glossy(0.8, 300.0)
            .reflecting(0.9),
    );
    let glass = scene.add_material(
        Material::matte("glass", Color::ONE, 0.0, 0.0)
            .glossy(0.8, 300.0)
            .glass(Color::ONE, 1.5),
    );

    let v = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
    // Walls face into the box. Looking along +z with +y up, +x is on the image's left.
    // Each is its corners on the unit cube, in order, as [x, y, z] each 0 or 1.
    let walls = [
        ([[0, 0, 0], [0, 0, 1], [1, 0, 1], [1, 0, 0]], white), // floor
        ([[0, 1, 0], [1, 1, 0], [1, 1, 1], [0, 1, 1]], white), // ceiling
        ([[0, 0, 1], [0, 1, 1], [1, 1, 1], [1, 0, 1]], white), // back
        ([[1, 0, 0], [1, 0, 1], [1, 1, 1], [1, 1, 0]], red),   // left
        ([[0, 0, 0], [0, 1, 0], [0, 1, 1], [0, 0, 1]], green), // right
    ];
    for (corners, m) in walls {
        let [a, b, c, d] = corners.map(|[x, y, z]: [u8; 3]| v(x.into(), y.into(), z.into()));
        scene
            .geometry
            .add_mesh(generate::quad(a, b, c, d, 1.0, 1.0), m);
    }
    scene
        .geometry
        .add(Shape::Sphere(Sphere::new(v(0.68, 0.2, 0.62), 0.2)), mirror);
    scene
        .geometry
        .add(Shape::Sphere(Sphere::new(v(0.3, 0.18, 0.32), 0.18)), glass);
    scene.lights = vec![Light::Point {
        position: v(0.5, 0.93, 0.45),
        color: Color::splat(0.85),
    }];
    scene
}
