//! The bad case for axis-aligned boxes: a haystack of 10 000 long, thin triangles lying
//! along the cube's diagonals. Each one's bounding box is a cube around it that is almost
//! all empty, so box-bounded hierarchies and cells find "hits" everywhere and test far more
//! triangles than a ray comes near.

use super::random::unit;
use super::staging::stage;
use crate::camera::Camera;
use crate::geometry::TriangleMesh;
use crate::math::{Color, Vec3};
use crate::scene::Scene;
use crate::shading::Material;

const NEEDLES: u32 = 10_000;
const LENGTH: f32 = 1.2;
const WIDTH: f32 = 0.02;

pub(super) fn slivers() -> Scene {
    let camera = Camera::perspective(
        Vec3::new(3.2, -4.0, 2.4),
        Vec3::new(0.0, 0.0, -0.2),
        Vec3::Z,
        40.0,
    );
    let mut scene = stage(camera, (480, 360), Color::new(0.05, 0.05, 0.08), 0.15);
    let straw = scene.add_material(
        Material::matte("straw", Color::new(0.9, 0.8, 0.4), 0.5, 0.8).glossy(0.3, 20.0),
    );
    scene.geometry.add_mesh(needles(), straw);
    super::staging::matte_floor(&mut scene, Color::splat(0.45), -1.8);
    scene.lights = super::staging::key_and_fill();
    scene
}

/// Needles from random points in [-1, 1]³ along one of the four cube diagonals.
fn needles() -> TriangleMesh {
    let diagonals = [
        Vec3::new(1.0, 1.0, 1.0),
        Vec3::new(-1.0, 1.0, 1.0),
        Vec3::new(1.0, -1.0, 1.0),
        Vec3::new(-1.0, -1.0, 1.0),
    ]
    .map(Vec3::normalize);
    let mut positions = Vec::with_capacity(3 * NEEDLES as usize);
    let mut indices = Vec::with_capacity(NEEDLES as usize);
    for i in 0..NEEDLES {
        let start = Vec3::new(unit(i, 0), unit(i, 1), unit(i, 2)) * 2.0 - Vec3::ONE;
        let d = diagonals[(unit(i, 3) * 4.0) as usize % 4];
        // A side direction across the needle, turned by a random angle about it.
        let side = d.any_orthonormal_vector();
        let angle = unit(i, 4) * std::f32::consts::TAU;
        let across = side * angle.cos() + d.cross(side) * angle.sin();
        let start = start - 0.5 * LENGTH * d;
        let k = positions.len() as u32;
        positions.extend([start, start + LENGTH * d, start + WIDTH * across]);
        indices.push([k, k + 1, k + 2]);
    }
    TriangleMesh::new(positions, indices, None, None).expect("needle indices are in range")
}
