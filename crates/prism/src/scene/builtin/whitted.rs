//! A homage to the picture in Whitted's 1980 paper: a red and yellow checkerboard, a mirror
//! sphere behind a hollow glass sphere, two point lights and a blue sky.

use super::staging::stage;
use crate::camera::Camera;
use crate::geometry::{generate, Shape, Sphere};
use crate::light::Light;
use crate::math::{Color, Vec3};
use crate::scene::Scene;
use crate::shading::{Checker, CheckerSpace, Material, Texture};

pub(super) fn whitted() -> Scene {
    let camera = Camera::perspective(
        Vec3::new(0.0, 1.3, -5.0),
        Vec3::new(0.0, 0.9, 0.0),
        Vec3::Y,
        42.0,
    );
    let mut scene = stage(camera, (640, 480), Color::new(0.12, 0.28, 0.75), 0.2);

    let floor = scene.add_material(Material {
        name: "checkerboard".into(),
        color: Texture::Checker(Checker {
            a: Color::new(0.9, 0.1, 0.05),
            b: Color::new(0.95, 0.85, 0.1),
            size: 1.0,
            space: CheckerSpace::Uv,
        }),
        ambient: 0.6,
        diffuse: 0.8,
        ..Material::default()
    });
    let mirror = scene.add_material(
        Material::matte("mirror", Color::splat(0.7), 0.1, 0.15)
            .glossy(0.6, 80.0)
            .reflecting(0.8),
    );
    let glass = scene.add_material(
        Material::matte("glass", Color::splat(1.0), 0.0, 0.0)
            .glossy(0.7, 200.0)
            .reflecting(0.05)
            .glass(Color::splat(0.95), 1.5),
    );

    // A finite board, as in the original, so the sky shows below its far edge.
    let (x0, x1, z0, z1) = (-4.0, 4.0, -3.0, 13.0);
    scene.geometry.add_mesh(
        generate::quad(
            Vec3::new(x0, 0.0, z0),
            Vec3::new(x0, 0.0, z1),
            Vec3::new(x1, 0.0, z1),
            Vec3::new(x1, 0.0, z0),
            z1 - z0,
            x1 - x0,
        ),
        floor,
    );
    scene.geometry.add(
        Shape::Sphere(Sphere::new(Vec3::new(-0.9, 1.25, 1.6), 0.9)),
        mirror,
    );
    // The hollow glass sphere: an outer wall and an inner wall whose normals face inward,
    // so a ray inside the glass leaves it through the inner wall.
    // The camera looks along +z with +y up, so +x is on the left of the image.
    let glass_center = Vec3::new(0.55, 1.0, -1.2);
    scene
        .geometry
        .add(Shape::Sphere(Sphere::new(glass_center, 0.75)), glass);
    scene.geometry.add(
        Shape::Sphere(Sphere {
            center: glass_center,
            radius: 0.68,
            inside_out: true,
        }),
        glass,
    );

    scene.lights = vec![
        Light::Point {
            position: Vec3::new(-4.0, 7.0, -6.0),
            color: Color::splat(0.7),
        },
        Light::Point {
            position: Vec3::new(5.0, 6.0, -3.0),
            color: Color::splat(0.5),
        },
    ];
    scene
}
