//! Haines' sphereflake (the SPD "balls" database, re-derived): a sphere with nine spheres of
//! a third its radius on it, recursively. Level n has (9^(n+1) − 1)/8 spheres.

use super::staging::stage;
use crate::camera::Camera;
use crate::geometry::{generate, Shape, Sphere};
use crate::light::Light;
use crate::math::{Color, Frame, Vec3};
use crate::scene::Scene;
use crate::shading::Material;

/// Haines' sphereflake (SPD) of the given recursion level: a mirror sphere with nine smaller ones
/// around it, recursively; level n has (9^(n+1) − 1)/8 spheres.
pub fn sphereflake(level: u32) -> Scene {
    let camera = Camera::perspective(Vec3::new(2.1, 1.3, 1.7), Vec3::ZERO, Vec3::Z, 45.0);
    let mut scene = stage(camera, (512, 512), Color::new(0.078, 0.361, 0.753), 0.15);
    let floor = scene.add_material(Material::matte(
        "floor",
        Color::new(1.0, 0.75, 0.33),
        0.5,
        0.8,
    ));
    let balls = scene.add_material(
        Material::matte("balls", Color::new(1.0, 0.9, 0.7), 0.5, 0.5)
            .glossy(0.5, 3.0827)
            .reflecting(0.5),
    );
    let s = 12.0;
    scene.geometry.add_mesh(
        generate::quad(
            Vec3::new(s, s, -0.5),
            Vec3::new(-s, s, -0.5),
            Vec3::new(-s, -s, -0.5),
            Vec3::new(s, -s, -0.5),
            1.0,
            1.0,
        ),
        floor,
    );
    add_flake(&mut scene, balls, Vec3::ZERO, 0.5, Vec3::Z, level);
    let light = Color::splat(1.0 / 3f32.sqrt());
    scene.lights = [
        Vec3::new(4.0, 3.0, 2.0),
        Vec3::new(1.0, -4.0, 4.0),
        Vec3::new(-3.0, 1.0, 5.0),
    ]
    .map(|position| Light::Point {
        position,
        color: light,
    })
    .to_vec();
    scene
}

/// Adds a sphere and, below `level` 0, its nine children: six around its equator (relative
/// to `axis`, the direction from its parent) and three above it.
fn add_flake(scene: &mut Scene, material: u32, center: Vec3, radius: f32, axis: Vec3, level: u32) {
    scene
        .geometry
        .add(Shape::Sphere(Sphere::new(center, radius)), material);
    if level == 0 {
        return;
    }
    let frame = Frame::from_z(axis);
    let child = radius / 3.0;
    let mut dirs = Vec::with_capacity(9);
    for k in 0..6 {
        let phi = k as f32 * std::f32::consts::TAU / 6.0;
        dirs.push(Vec3::new(phi.cos(), phi.sin(), 0.0));
    }
    let elevation = 60f32.to_radians();
    for k in 0..3 {
        let phi = (k as f32 + 0.25) * std::f32::consts::TAU / 3.0;
        dirs.push(Vec3::new(
            elevation.cos() * phi.cos(),
            elevation.cos() * phi.sin(),
            elevation.sin(),
        ));
    }
    for d in dirs {
        let dir = frame.to_world(d).normalize();
        add_flake(
            scene,
            material,
            center + (radius + child) * dir,
            child,
            dir,
            level - 1,
        );
    }
}
