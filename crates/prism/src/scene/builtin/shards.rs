//! The kd-tree's bad case: 2 000 large triangles, each spanning about half the scene, in
//! random orientations, all overlapping. Every splitting plane cuts most of them, so a
//! kd-tree (and any spatial subdivision) copies each into many leaves and its references
//! and memory explode, where a BVH just lets its boxes overlap.

use super::random::unit;
use super::staging::stage;
use crate::camera::Camera;
use crate::geometry::TriangleMesh;
use crate::math::{Color, Vec3};
use crate::scene::Scene;
use crate::shading::Material;

const SHARDS: u32 = 2_000;
/// Distance of a shard's corners from its centre, against a scene of half-size 1.
const REACH: f32 = 0.5;

pub(super) fn shards() -> Scene {
    let camera = Camera::perspective(Vec3::new(2.8, -3.6, 2.2), Vec3::ZERO, Vec3::Z, 45.0);
    let mut scene = stage(camera, (480, 360), Color::new(0.08, 0.08, 0.1), 0.15);
    let palette = [
        Color::new(0.8, 0.3, 0.3),
        Color::new(0.3, 0.7, 0.4),
        Color::new(0.3, 0.4, 0.85),
    ];
    let materials: Vec<u32> = palette
        .iter()
        .enumerate()
        .map(|(k, &c)| {
            scene.add_material(Material::matte(&format!("shard{k}"), c, 0.5, 0.8).glossy(0.4, 30.0))
        })
        .collect();
    for (k, &material) in materials.iter().enumerate() {
        scene.geometry.add_mesh(shard_mesh(k as u32, 3), material);
    }
    super::staging::matte_floor(&mut scene, Color::splat(0.5), -1.6);
    scene.lights = super::staging::key_and_fill();
    scene
}

/// Every `of`-th shard, starting at shard `part`: one mesh per colour.
fn shard_mesh(part: u32, of: u32) -> TriangleMesh {
    let mut positions = Vec::new();
    let mut indices = Vec::new();
    for i in (part..SHARDS).step_by(of as usize) {
        let random_point =
            |d: u32| Vec3::new(unit(i, d), unit(i, d + 1), unit(i, d + 2)) * 2.0 - Vec3::ONE;
        let centre = random_point(0) * (1.0 - REACH);
        let k = positions.len() as u32;
        for corner in 0..3 {
            positions.push(centre + REACH * random_point(3 + 3 * corner));
        }
        indices.push([k, k + 1, k + 2]);
    }
    TriangleMesh::new(positions, indices, None, None).expect("shard indices are in range")
}
