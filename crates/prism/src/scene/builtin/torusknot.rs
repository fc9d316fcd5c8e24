//! A bumpy torus knot of about a million smooth-shaded triangles over a mirror floor: the
//! large-mesh scene for throughput and BVH build measurements.

use super::staging::{key_and_fill_at, stage};
use crate::camera::Camera;
use crate::geometry::{generate, Plane, Shape};
use crate::math::{Color, Vec3};
use crate::scene::Scene;
use crate::shading::Material;

/// A bumpy torus knot mesh of about `triangles` triangles, for large-mesh benchmarks.
pub fn torusknot(triangles: u32) -> Scene {
    let camera = Camera::perspective(
        Vec3::new(0.0, -4.2, 2.6),
        Vec3::new(0.0, 0.0, -0.1),
        Vec3::Z,
        40.0,
    );
    let mut scene = stage(camera, (640, 480), Color::new(0.05, 0.05, 0.08), 0.15);
    let knot = scene.add_material(
        Material::matte("knot", Color::new(0.85, 0.45, 0.2), 0.5, 0.8).glossy(0.5, 40.0),
    );
    let floor =
        scene.add_material(Material::matte("floor", Color::splat(0.5), 0.5, 0.6).reflecting(0.3));
    scene
        .geometry
        .add_mesh(generate::torus_knot(triangles), knot);
    let plane = Plane::new(Vec3::new(0.0, 0.0, -0.75), Vec3::Z).expect("non-zero normal");
    scene.geometry.add(Shape::Plane(Box::new(plane)), floor);
    scene.lights = key_and_fill_at([-3.0, -3.0, 5.0], 0.7, [1.0, 0.5, -1.0], 0.3);
    scene
}
