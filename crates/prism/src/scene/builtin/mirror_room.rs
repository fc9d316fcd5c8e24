//! A closed room of flat walls (2 units wide) with a tilted mirror in front of the back
//! wall, lit by a point light at the eye: polygons only, so the beam tracer
//! (`--integrator beam`) renders it exactly, and no shadow the eye sees, directly or in the
//! mirror, so every pixel piece's light is smooth (the beam tests and
//! `examples/beam_vs_supersampling.rs` compare supersampling against it).

use crate::camera::Camera;
use crate::geometry::TriangleMesh;
use crate::light::Light;
use crate::math::{Color, Vec3};
use crate::scene::Scene;
use crate::shading::Material;

pub(super) fn mirror_room() -> Scene {
    let mut s = Scene {
        camera: Camera::perspective(
            Vec3::new(0.0, 1.0, 3.2),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::Y,
            50.0,
        ),
        background: Color::new(0.1, 0.1, 0.1),
        ambient: Color::ONE,
        lights: vec![Light::Point {
            position: Vec3::new(0.0, 1.0, 3.2),
            color: Color::splat(0.9),
        }],
        ..Scene::default()
    };
    let mut material = |name: &str, c: Color, ambient: f32, diffuse: f32, reflect: f32| {
        s.add_material(Material::matte(name, c, ambient, diffuse).reflecting(reflect))
    };
    let white = material("white", Color::splat(0.75), 0.2, 0.8, 0.0);
    let red = material("red", Color::new(0.75, 0.1, 0.1), 0.2, 0.8, 0.0);
    let green = material("green", Color::new(0.1, 0.75, 0.1), 0.2, 0.8, 0.0);
    let mirror = material("mirror", Color::splat(0.1), 0.1, 0.1, 0.8);
    let v = Vec3::new;
    // Floor, ceiling, left and right wall of the room between depths z0 and z1, each
    // wound to face into the room.
    let shell = |z0: f32, z1: f32| {
        [
            [v(-1., 0., z0), v(1., 0., z0), v(1., 0., z1), v(-1., 0., z1)],
            [v(-1., 2., z0), v(-1., 2., z1), v(1., 2., z1), v(1., 2., z0)],
            [
                v(-1., 0., z0),
                v(-1., 0., z1),
                v(-1., 2., z1),
                v(-1., 2., z0),
            ],
            [v(1., 0., z0), v(1., 2., z0), v(1., 2., z1), v(1., 0., z1)],
        ]
    };
    let [floor, ceiling, left, right] = shell(-1.0, 1.0);
    let [floor_behind, ceiling_behind, left_behind, right_behind] = shell(1.0, 3.5);
    let quads = [
        // The room in front of the camera: floor, ceiling, back wall, left and right.
        (floor, white),
        (ceiling, white),
        (
            [
                v(-1., 0., -1.),
                v(-1., 2., -1.),
                v(1., 2., -1.),
                v(1., 0., -1.),
            ],
            white,
        ),
        (left, red),
        (right, green),
        // The wall behind the camera, which the mirror shows, and the room up to it.
        (
            [
                v(-1., 0., 3.5),
                v(1., 0., 3.5),
                v(1., 2., 3.5),
                v(-1., 2., 3.5),
            ],
            white,
        ),
        (left_behind, red),
        (right_behind, green),
        (floor_behind, white),
        (ceiling_behind, white),
        // The mirror, a little in front of the back wall, tilted so its image is not the
        // room straight back.
        (
            [
                v(-0.6, 0.4, -0.97),
                v(0.6, 0.4, -0.9),
                v(0.6, 1.6, -0.9),
                v(-0.6, 1.6, -0.97),
            ],
            mirror,
        ),
    ];
    for (corners, material) in quads {
        let mesh = TriangleMesh::new(corners.to_vec(), vec![[0, 1, 2], [0, 2, 3]], None, None)
            .expect("four finite corners");
        s.geometry.add_mesh(mesh, material);
    }
    s.options.max_depth = 3;
    s
}
