//! Materials whose coefficients change per texel: an emissive texture lights the scene
//! texel by texel, in both integrators. A quad whose texture emits on its left half
//! lights the floor below as a quad of that half alone does (the path tracer's direct
//! light and Whitted's area lights alike), and the floor under its dark half stays dim:
//! one mean emission per material would light both sides alike.

use prism::camera::{Camera, Projection};
use prism::geometry::TriangleMesh;
use prism::math::{Color, Vec2, Vec3};
use prism::options::IntegratorKind;
use prism::render::{render, RenderResult};
use prism::sampling::SamplerKind;
use prism::shading::{ImageTexture, Material};
use prism::{RenderOptions, Scene};
use std::sync::atomic::AtomicBool;

/// Texels across the emissive texture: its left half emits, its right half is dark.
const TEXELS: usize = 64;
const EMISSION: f32 = 4.0;

fn quad(corners: [Vec3; 4]) -> TriangleMesh {
    TriangleMesh::new(
        corners.to_vec(),
        vec![[0, 1, 2], [0, 2, 3]],
        None,
        Some(vec![
            Vec2::new(0.0, 0.0),
            Vec2::new(1.0, 0.0),
            Vec2::new(1.0, 1.0),
            Vec2::new(0.0, 1.0),
        ]),
    )
    .unwrap()
}

/// A floor at y = 0 under an emitter at y = 1 facing down, seen from the front: the
/// emitter spans x from −1 to 1 with its texture's left half emitting (`textured`), or
/// spans x from −1 to 0 emitting everywhere.
fn scene(textured: bool) -> Scene {
    let mut scene = Scene {
        camera: Camera {
            eye: Vec3::new(0.0, 0.5, 4.0),
            look_at: Vec3::ZERO,
            up: Vec3::Y,
            fov_degrees: 40.0,
            projection: Projection::Perspective,
        },
        background: Color::ZERO,
        ambient: Color::ZERO,
        ..Scene::default()
    };
    let floor = scene.add_material(Material::matte("floor", Color::splat(0.8), 0.0, 1.0));
    scene.geometry.add_mesh(
        quad([
            Vec3::new(-2.0, 0.0, -2.0),
            Vec3::new(-2.0, 0.0, 3.0),
            Vec3::new(2.0, 0.0, 3.0),
            Vec3::new(2.0, 0.0, -2.0),
        ]),
        floor,
    );
    let (right, emission_map) = if textured {
        let texels = (0..TEXELS)
            .map(|i| Color::splat(if i < TEXELS / 2 { 1.0 } else { 0.0 }))
            .collect();
        (1.0, Some(ImageTexture::from_texels(TEXELS, 1, texels)))
    } else {
        (0.0, None)
    };
    let lamp = scene.add_material(Material {
        emission: Color::splat(EMISSION),
        emission_map,
        ..Material::matte("lamp", Color::ZERO, 0.0, 0.0)
    });
    scene.geometry.add_mesh(
        quad([
            Vec3::new(-1.0, 1.0, -1.0),
            Vec3::new(right, 1.0, -1.0),
            Vec3::new(right, 1.0, 1.0),
            Vec3::new(-1.0, 1.0, 1.0),
        ]),
        lamp,
    );
    scene
}

const SIZE: u32 = 32;

fn run(scene: &Scene, integrator: IntegratorKind) -> RenderResult {
    let options = RenderOptions {
        width: SIZE,
        height: SIZE,
        integrator,
        min_weight: 0.0,
        sampler: SamplerKind::Jittered,
        ..match integrator {
            IntegratorKind::Path => RenderOptions {
                max_depth: 2,
                samples: 64,
                ..RenderOptions::default()
            },
            _ => RenderOptions {
                max_depth: 1,
                samples: 4,
                area_samples: 64,
                ..RenderOptions::default()
            },
        }
    };
    let prepared = scene.prepare_for(&options);
    render(&prepared, &options, &|_| {}, &AtomicBool::new(false)).unwrap()
}

/// The mean red value over the floor's pixels below the image's centre, in its left
/// (x < 0) or right quarter.
fn floor_mean(r: &RenderResult, left: bool) -> f64 {
    let columns = if left {
        0..SIZE / 4
    } else {
        3 * SIZE / 4..SIZE
    };
    let mut sum = 0.0;
    let mut n = 0.0;
    for y in SIZE / 2 + 2..SIZE {
        for x in columns.clone() {
            sum += r.film.get(x, y).x as f64;
            n += 1.0;
        }
    }
    sum / n
}

#[test]
fn an_emissive_texture_lights_the_floor_texel_by_texel() {
    let (textured, half) = (scene(true), scene(false));
    for integrator in [IntegratorKind::Path, IntegratorKind::Whitted] {
        let (a, b) = (run(&textured, integrator), run(&half, integrator));
        for left in [true, false] {
            let (t, h) = (floor_mean(&a, left), floor_mean(&b, left));
            assert!(
                (t - h).abs() < 0.04 * h,
                "{integrator:?}, left {left}: textured {t:.5} against the half quad's {h:.5}"
            );
        }
        let (lit, dim) = (floor_mean(&a, true), floor_mean(&a, false));
        assert!(
            lit > 1.5 * dim && dim > 0.0,
            "{integrator:?}: under the emitting half {lit:.5}, under the dark half {dim:.5}"
        );
    }
}
