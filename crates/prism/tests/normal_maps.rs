//! Normal maps turn the shading normal in the frame the uvs give a triangle: x along
//! ∂p/∂u, y along ∂p/∂v, z along the normal; or, where the mesh has tangents, in theirs:
//! x along the tangent, y = w · (z × x). A flat quad facing the camera, lit by a
//! directional light, shows exactly the Lambert term of the mapped normal.

use prism::camera::{Camera, Projection};
use prism::geometry::TriangleMesh;
use prism::light::Light;
use prism::math::{Color, Vec2, Vec3, Vec4};
use prism::render::{render, Film};
use prism::shading::{ImageTexture, Material, NormalMap, Texture};
use prism::{RenderOptions, Scene};
use std::sync::atomic::AtomicBool;

/// The centre pixel of a quad in the z = 0 plane facing +z, its u along +x and v along
/// +y (or along −y with `flip_v`), every texel of its normal map `texel`, lit from
/// direction `to_light`; Lambert only, no ambient.
fn lit(texel: Color, scale: f32, to_light: Vec3, flip_v: bool, integrator: &str) -> f32 {
    let film = lit_quad(texel, scale, to_light, flip_v, integrator, None, 1.0, false);
    film.get(4, 4).x
}

/// The quad of `lit` with every vertex's tangent `tangent` (where given), scaled by
/// `size` about the origin (the camera keeps its view) and mirrored in x (`mirror`) after
/// the tangents are set; the whole image.
#[allow(clippy::too_many_arguments)]
fn lit_quad(
    texel: Color,
    scale: f32,
    to_light: Vec3,
    flip_v: bool,
    integrator: &str,
    tangent: Option<Vec4>,
    size: f32,
    mirror: bool,
) -> Film {
    let mut scene = Scene {
        camera: Camera {
            eye: Vec3::new(0.0, 0.0, 5.0 * size),
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
    let mut mesh = match tangent {
        Some(t) => mesh.with_tangents(vec![t; 4]).unwrap(),
        None => mesh,
    };
    mesh.transform(|p| p * size, |n| n);
    if mirror {
        mesh.transform(|p| Vec3::new(-p.x, p.y, p.z), |n| Vec3::new(-n.x, n.y, n.z));
        mesh.reverse_winding();
    }
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
    r.film
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

/// The centre pixel of the quad whose tangents are `tangent`, lit from `to_light`.
fn lit_tangent(texel: Color, tangent: Vec4, to_light: Vec3) -> f32 {
    lit_quad(
        texel,
        1.0,
        to_light,
        false,
        "whitted",
        Some(tangent),
        1.0,
        false,
    )
    .get(4, 4)
    .x
}

#[test]
fn tangents_give_the_frame_instead_of_the_uvs() {
    // (0.75, 0.5, 1) tilts towards the frame's +x; the tangent runs +y, the uvs' u +x.
    let tilted = Color::new(0.75, 0.5, 1.0);
    let from_plus_y = Vec3::new(0.0, 1.0, 1.0);
    let sqrt_2_5 = (2.0f32 * 1.25).sqrt();
    let along_y = Vec4::new(0.0, 1.0, 0.0, 1.0);
    let towards = lit_tangent(tilted, along_y, from_plus_y);
    assert!(close(towards, 1.5 / sqrt_2_5), "{towards}");
    let aside = lit_tangent(tilted, along_y, Vec3::new(1.0, 0.0, 1.0));
    assert!(close(aside, 1.0 / sqrt_2_5), "{aside}");
    // The uv frame tilts it towards +x instead.
    let uv_frame = lit(tilted, 1.0, from_plus_y, false, "whitted");
    assert!(close(uv_frame, 1.0 / sqrt_2_5), "{uv_frame}");
    // A tangent not quite in the surface is made orthogonal to the normal first.
    let leaning = lit_tangent(tilted, Vec4::new(0.0, 1.0, 3.0, 1.0), from_plus_y);
    assert!(close(leaning, towards), "{leaning}");
}

#[test]
fn handedness_minus_one_mirrors_the_maps_y() {
    let tilted_y = Color::new(0.5, 0.75, 1.0);
    let from_plus_y = Vec3::new(0.0, 1.0, 1.0);
    let sqrt_2_5 = (2.0f32 * 1.25).sqrt();
    let right = lit_tangent(tilted_y, Vec4::new(1.0, 0.0, 0.0, 1.0), from_plus_y);
    assert!(close(right, 1.5 / sqrt_2_5), "{right}");
    let left = lit_tangent(tilted_y, Vec4::new(1.0, 0.0, 0.0, -1.0), from_plus_y);
    assert!(close(left, 0.5 / sqrt_2_5), "{left}");
}

#[test]
fn tangents_survive_transforms() {
    let tilted = Color::new(0.75, 0.6, 1.0);
    let tangent = Some(Vec4::new(0.6, 0.8, 0.0, 1.0));
    let to_light = Vec3::new(0.3, 1.0, 1.0);
    let at = |size: f32| {
        lit_quad(
            tilted, 1.0, to_light, false, "whitted", tangent, size, false,
        )
    };
    let unit = at(1.0);
    for size in [1e-3, 1e3] {
        let scaled = at(size);
        for (a, b) in unit.pixels.iter().zip(&scaled.pixels) {
            assert!((*a - *b).abs().max_element() < 1e-4, "size {size}: {a} {b}");
        }
    }
    // Mirrored in x, the tangent runs −x and the handedness turns around, so the map's
    // +x tilts towards −x and its y still towards +y.
    let sqrt_2_5 = (2.0f32 * 1.25).sqrt();
    let t = Some(Vec4::new(1.0, 0.0, 0.0, 1.0));
    let mirrored = |texel: Color, to_light: Vec3| {
        lit_quad(texel, 1.0, to_light, false, "whitted", t, 1.0, true)
            .get(4, 4)
            .x
    };
    let minus_x = mirrored(Color::new(0.75, 0.5, 1.0), Vec3::new(-1.0, 0.0, 1.0));
    assert!(close(minus_x, 1.5 / sqrt_2_5), "{minus_x}");
    let plus_y = mirrored(Color::new(0.5, 0.75, 1.0), Vec3::new(0.0, 1.0, 1.0));
    assert!(close(plus_y, 1.5 / sqrt_2_5), "{plus_y}");
}
