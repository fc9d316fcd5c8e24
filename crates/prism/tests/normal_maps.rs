//! Normal maps turn the shading normal in the frame the uvs give a triangle: x along
//! ∂p/∂u, y along ∂p/∂v, z along the normal. A flat quad facing the camera, lit by a
//! directional light, shows exactly the Lambert term of the mapped normal.

use prism::camera::{Camera, Projection};
use prism::geometry::TriangleMesh;
use prism::light::Light;
use prism::math::{Color, Vec2, Vec3};
use prism::render::render;
use prism::shading::{ImageTexture, Material, NormalMap, Texture};
use prism::{RenderOptions, Scene};
use std::sync::atomic::AtomicBool;

/// The centre pixel of a quad in the z = 0 plane facing +z, its u along +x and v along
/// +y (or along −y with `flip_v`), every texel of its normal map `texel`, lit from
/// direction `to_light`; Lambert only, no ambient.
fn lit(texel: Color, scale: f32, to_light: Vec3, flip_v: bool, integrator: &str) -> f32 {
    let mut scene = Scene {
        camera: Camera {
            eye: Vec3::new(0.0, 0.0, 5.0),
            look_at: Vec3::ZERO,
            up: Vec3::Y,
            fov_degrees: 20.0,
            projection: Projection::Perspective,
        },
        background: Color::ZERO,
        ambient: Color::ZERO,
        ..Scene::default()
    };
    let material = scene.add_material(Material {
        color: Texture::Solid(Color::ONE),
        ambient: 0.0,
        diffuse: 1.0,
        normal_map: Some(NormalMap {
            texture: ImageTexture::from_texels(2, 2, vec![texel; 4]),
            scale,
        }),
        ..Material::default()
    });
    let (v0, v1) = if flip_v { (1.0, 0.0) } else { (0.0, 1.0) };
    let mesh = TriangleMesh::new(
        vec![
            Vec3::new(-1.0, -1.0, 0.0),
            Vec3::new(1.0, -1.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(-1.0, 1.0, 0.0),
        ],
        vec![[0, 1, 2], [0, 2, 3]],
        None,
        Some(vec![
            Vec2::new(0.0, v0),
            Vec2::new(1.0, v0),
            Vec2::new(1.0, v1),
            Vec2::new(0.0, v1),
        ]),
    )
    .unwrap();
    scene.geometry.add_mesh(mesh, material);
    scene.lights.push(Light::Directional {
        direction: -to_light.normalize(),
        color: Color::ONE,
    });
    let options = RenderOptions {
        width: 9,
        height: 9,
        min_weight: 0.0,
        integrator: integrator.parse().unwrap(),
        ..RenderOptions::default()
    };
    let prepared = scene.prepare_for(&options);
    let r = render(&prepared, &options, &|_| {}, &AtomicBool::new(false)).unwrap();
    r.film.get(4, 4).x
}

fn close(a: f32, b: f32) -> bool {
    (a - b).abs() < 1e-4
}

#[test]
fn a_normal_map_tilts_the_normal_in_the_uv_frame() {
    let up = Vec3::Z;
    // The flat texel (0.5, 0.5, 1) is the normal itself.
    let flat = lit(Color::new(0.5, 0.5, 1.0), 1.0, up, false, "whitted");
    assert!(close(flat, 1.0), "{flat}");
    // (0.75, 0.5, 1) is (0.5, 0, 1) in the frame: tilted towards +u by atan(1/2).
    let tilted = Color::new(0.75, 0.5, 1.0);
    let from_above = lit(tilted, 1.0, up, false, "whitted");
    assert!(close(from_above, 1.0 / 1.25f32.sqrt()), "{from_above}");
    // Lit from the +x side the tilt faces, brighter; from −x, darker.
    let towards = lit(tilted, 1.0, Vec3::new(1.0, 0.0, 1.0), false, "whitted");
    let away = lit(tilted, 1.0, Vec3::new(-1.0, 0.0, 1.0), false, "whitted");
    let sqrt_2_5 = (2.0f32 * 1.25).sqrt();
    assert!(close(towards, 1.5 / sqrt_2_5), "{towards}");
    assert!(close(away, 0.5 / sqrt_2_5), "{away}");
    // Scale 0 leaves only z: the flat normal again.
    assert!(close(
        lit(tilted, 0.0, Vec3::new(1.0, 0.0, 1.0), false, "whitted"),
        0.5f32.sqrt()
    ));
}

#[test]
fn the_map_s_y_follows_the_direction_v_grows_in() {
    let tilted_y = Color::new(0.5, 0.75, 1.0);
    let from_plus_y = Vec3::new(0.0, 1.0, 1.0);
    let sqrt_2_5 = (2.0f32 * 1.25).sqrt();
    // v along +y: the map's +y tilts towards +y.
    let v_up = lit(tilted_y, 1.0, from_plus_y, false, "whitted");
    assert!(close(v_up, 1.5 / sqrt_2_5), "{v_up}");
    // v along −y (mirrored uvs): the map's +y now tilts towards −y.
    let v_down = lit(tilted_y, 1.0, from_plus_y, true, "whitted");
    assert!(close(v_down, 0.5 / sqrt_2_5), "{v_down}");
}

#[test]
fn the_path_tracer_sees_the_same_normal() {
    // A directional light's sample is deterministic: the path tracer's first bounce
    // gives the Lambert term kd·C/π·E·cos·π = cos for the delta light.
    let tilted = Color::new(0.75, 0.5, 1.0);
    let whitted = lit(tilted, 1.0, Vec3::new(1.0, 0.0, 1.0), false, "whitted");
    let path = lit(tilted, 1.0, Vec3::new(1.0, 0.0, 1.0), false, "path");
    assert!(
        (path - whitted).abs() < 0.02 * whitted,
        "{path} against {whitted}"
    );
}
