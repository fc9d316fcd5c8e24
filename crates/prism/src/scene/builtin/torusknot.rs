//! A bumpy torus knot of about a million smooth-shaded triangles over a mirror floor: the
//! large-mesh scene for throughput and BVH build measurements.

use crate::camera::{Camera, Projection};
use crate::geometry::{generate, Plane, Shape};
use crate::light::Light;
use crate::math::{Color, Vec3};
use crate::scene::Scene;
use crate::shading::{Material, Texture};

/// A bumpy torus knot mesh of about `triangles` triangles, for large-mesh benchmarks.
pub fn torusknot(triangles: u32) -> Scene {
    let mut scene = Scene {
        camera: Camera {
            eye: Vec3::new(0.0, -4.2, 2.6),
            look_at: Vec3::new(0.0, 0.0, -0.1),
            up: Vec3::Z,
            fov_degrees: 40.0,
            projection: Projection::Perspective,
        },
        background: Color::new(0.05, 0.05, 0.08),
        ambient: Color::splat(0.15),
        ..Scene::default()
    };
    scene.options.width = 640;
    scene.options.height = 480;
    let knot = scene.add_material(Material {
        name: "knot".into(),
        color: Texture::Solid(Color::new(0.85, 0.45, 0.2)),
        ambient: 0.5,
        diffuse: 0.8,
        specular: 0.5,
        shininess: 40.0,
        ..Material::default()
    });
    let floor = scene.add_material(Material {
        name: "floor".into(),
        color: Texture::Solid(Color::splat(0.5)),
        ambient: 0.5,
        diffuse: 0.6,
        reflect: 0.3,
        ..Material::default()
    });
    scene
        .geometry
        .add_mesh(generate::torus_knot(triangles), knot);
    let plane = Plane::new(Vec3::new(0.0, 0.0, -0.75), Vec3::Z).expect("non-zero normal");
    scene.geometry.add(Shape::Plane(Box::new(plane)), floor);
    scene.lights = vec![
        Light::Point {
            position: Vec3::new(-3.0, -3.0, 5.0),
            color: Color::splat(0.7),
        },
        Light::Directional {
            direction: Vec3::new(1.0, 0.5, -1.0).normalize(),
            color: Color::splat(0.3),
        },
    ];
    scene
}
