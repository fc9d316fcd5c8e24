//! The grid's bad case, Haines' "teapot in a stadium": a dense torus knot of 40 000
//! triangles at the centre of a stadium a hundred times its size built from a few hundred
//! large triangles. A uniform grid sized for the whole stadium puts the knot into a
//! handful of cells holding thousands of triangles each, while most cells stay empty.

use super::staging::{key_and_fill_at, stage};
use crate::camera::Camera;
use crate::geometry::{generate, TriangleMesh};
use crate::math::{Color, Vec3};
use crate::scene::Scene;
use crate::shading::Material;

/// Triangles in the knot.
const KNOT: u32 = 40_000;
/// Sections of the stands around the pitch.
const SECTIONS: u32 = 48;

pub(super) fn stadium() -> Scene {
    let camera = Camera::perspective(
        Vec3::new(0.0, -5.0, 2.2),
        Vec3::new(0.0, 0.0, 0.3),
        Vec3::Z,
        45.0,
    );
    let mut scene = stage(camera, (480, 360), Color::new(0.35, 0.5, 0.75), 0.2);
    let knot = scene.add_material(
        Material::matte("knot", Color::new(0.85, 0.45, 0.2), 0.5, 0.8).glossy(0.5, 40.0),
    );
    let pitch = scene.add_material(Material::matte(
        "pitch",
        Color::new(0.2, 0.55, 0.25),
        0.5,
        0.7,
    ));
    let stands = scene.add_material(Material::matte("stands", Color::splat(0.6), 0.5, 0.7));
    scene.geometry.add_mesh(generate::torus_knot(KNOT), knot);
    let ground = -0.75;
    let s = 300.0;
    scene.geometry.add_mesh(
        generate::quad(
            Vec3::new(-s, -s, ground),
            Vec3::new(s, -s, ground),
            Vec3::new(s, s, ground),
            Vec3::new(-s, s, ground),
            1.0,
            1.0,
        ),
        pitch,
    );
    scene.geometry.add_mesh(stands_mesh(ground), stands);
    scene.lights = key_and_fill_at([-3.0, -4.0, 6.0], 0.6, [0.5, 1.0, -1.5], 0.4);
    scene
}

/// A ring of sloping stands from radius 150 at the ground to radius 250 at height 60.
fn stands_mesh(ground: f32) -> TriangleMesh {
    use std::f32::consts::TAU;
    let mut positions = Vec::new();
    for k in 0..SECTIONS {
        let a = k as f32 / SECTIONS as f32 * TAU;
        let (c, s) = (a.cos(), a.sin());
        positions.push(Vec3::new(150.0 * c, 150.0 * s, ground));
        positions.push(Vec3::new(250.0 * c, 250.0 * s, ground + 60.0));
    }
    let mut indices = Vec::new();
    for k in 0..SECTIONS {
        let (i, j) = (2 * k, 2 * ((k + 1) % SECTIONS));
        // Facing the pitch.
        indices.push([i, i + 1, j]);
        indices.push([j, i + 1, j + 1]);
    }
    TriangleMesh::new(positions, indices, None, None).expect("stand indices are in range")
}
