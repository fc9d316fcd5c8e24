//! The beam tracer (docs/beam-tracing.md): every pixel's fragments cover it exactly once; on the
//! checkerboard the beam image is the analytic exact reference; on polygon scenes (a
//! Cornell box with flat walls and a mirror, a mirror corner, SPD tetra) jittered
//! supersampling converges to the beam image; the same picture at 1e-3 and 1e3; curved
//! shapes and exploding beam trees are refused with messages.

use crate::common;

use prism::camera::{Camera, Projection};
use prism::geometry::TriangleMesh;
use prism::math::{Color, Vec3};
use prism::options::{IntegratorKind, RenderOptions};
use prism::render::{render, render_beam, BeamRender, Film, RenderError};
use prism::sampling::SamplerKind;
use prism::scene::{builtin, Scene};
use prism::shading::Material;
use std::sync::atomic::AtomicBool;

/// Coverage of a pixel by the view beam's fragments, background included, is 1 to within
/// this (f64 clipping; slivers under 1e-14 px² are dropped).
const COVERAGE_TOLERANCE: f64 = 1e-9;

fn beam(scene: &Scene, width: u32, height: u32, tolerance: f64) -> Result<BeamRender, RenderError> {
    let prepared = scene.prepare(&scene.options.accel);
    let options = RenderOptions {
        width,
        height,
        integrator: IntegratorKind::Beam,
        ..scene.options.clone()
    };
    render_beam(
        &prepared,
        &options,
        tolerance,
        &|_| {},
        &AtomicBool::new(false),
    )
}

fn jittered(scene: &Scene, width: u32, height: u32, n: u32) -> Film {
    let prepared = scene.prepare(&scene.options.accel);
    let options = RenderOptions {
        width,
        height,
        sampler: SamplerKind::Jittered,
        samples: n,
        seed: 7,
        ..scene.options.clone()
    };
    render(&prepared, &options, &|_| {}, &AtomicBool::new(false))
        .unwrap()
        .film
}

fn assert_covered(r: &BeamRender, what: &str) {
    for (i, &c) in r.coverage.iter().enumerate() {
        assert!(
            (c - 1.0).abs() <= COVERAGE_TOLERANCE,
            "{what}: pixel {i} is covered {c} times"
        );
    }
}

fn quad(scene: &mut Scene, corners: [Vec3; 4], material: u32) {
    let mesh = TriangleMesh::new(corners.to_vec(), vec![[0, 1, 2], [0, 2, 3]], None, None).unwrap();
    scene.geometry.add_mesh(mesh, material);
}

/// The built-in `mirror-room`: flat walls and a tilted mirror, lit from the eye, so no
/// shadow the eye sees, directly or in the mirror, and every pixel piece's light is smooth:
/// its centroid's value is the piece's mean to second order (shadow boundaries inside a
/// piece are point-sampled; tetra has those).
fn cornell() -> Scene {
    builtin::find("mirror-room").expect("a built-in")
}

/// Two mirrors meeting at a right angle over a coloured floor: rays and beams reflect
/// twice (the beam tree reaches depth 3), lit by ambient light only so every value is a
/// constant per polygon and the beam image is exact.
fn mirror_corner() -> Scene {
    let mut s = Scene {
        camera: Camera {
            eye: Vec3::new(1.6, 1.3, 1.9),
            look_at: Vec3::new(-0.2, 0.4, -0.2),
            up: Vec3::Y,
            fov_degrees: 55.0,
            projection: Projection::Perspective,
        },
        background: Color::new(0.2, 0.3, 0.5),
        ambient: Color::ONE,
        ..Scene::default()
    };
    let flat = |s: &mut Scene, name: &str, c: Color| {
        s.add_material(Material {
            name: name.into(),
            color: prism::shading::Texture::Solid(c),
            ambient: 1.0,
            diffuse: 0.0,
            ..Material::default()
        })
    };
    let a = flat(&mut s, "a", Color::new(0.9, 0.8, 0.2));
    let b = flat(&mut s, "b", Color::new(0.1, 0.4, 0.8));
    let c = flat(&mut s, "c", Color::new(0.8, 0.2, 0.3));
    let mirror = s.add_material(Material {
        name: "mirror".into(),
        color: prism::shading::Texture::Solid(Color::ZERO),
        ambient: 0.0,
        diffuse: 0.0,
        reflect: 0.9,
        ..Material::default()
    });
    let v = Vec3::new;
    quad(
        &mut s,
        [
            v(-1., 0., -1.),
            v(-1., 0., 1.),
            v(1., 0., 1.),
            v(1., 0., -1.),
        ],
        a,
    );
    // A tile pattern on the floor: two triangles of other colours.
    let tri = |s: &mut Scene, p: [Vec3; 3], m: u32| {
        let mesh = TriangleMesh::new(p.to_vec(), vec![[0, 1, 2]], None, None).unwrap();
        s.geometry.add_mesh(mesh, m);
    };
    tri(
        &mut s,
        [v(-0.8, 0.01, -0.2), v(0.3, 0.01, 0.6), v(0.5, 0.01, -0.7)],
        b,
    );
    tri(
        &mut s,
        [v(-0.9, 0.02, 0.3), v(-0.2, 0.02, 0.9), v(-0.1, 0.02, 0.1)],
        c,
    );
    quad(
        &mut s,
        [
            v(-1., 0., -1.),
            v(1., 0., -1.),
            v(1., 1.5, -1.),
            v(-1., 1.5, -1.),
        ],
        mirror,
    );
    quad(
        &mut s,
        [
            v(-1., 0., -1.),
            v(-1., 1.5, -1.),
            v(-1., 1.5, 1.),
            v(-1., 0., 1.),
        ],
        mirror,
    );
    s.options.max_depth = 4;
    s
}

/// RMSE of jittered n × n against the beam image for growing n: it must fall roughly as
/// a Monte Carlo estimate does (at least 2.5× from 4 to 64 spp, where 1/√spp gives 4×)
/// and end small.
fn assert_converges(scene: &Scene, what: &str, width: u32, height: u32, floor: f64) {
    let exact = beam(scene, width, height, 1e-4).unwrap();
    assert_covered(&exact, what);
    let errors: Vec<f64> = [2, 4, 8]
        .iter()
        .map(|&n| {
            let film = jittered(scene, width, height, n);
            prism_lab::metrics::rmse(&film, &exact.film, None).unwrap()
        })
        .collect();
    eprintln!("{what}: RMSE at 4, 16, 64 spp: {errors:?}");
    if let Some(dir) = std::env::var_os("BEAM_DUMP") {
        let dir = std::path::PathBuf::from(dir);
        prism_io::output::write_image(&dir.join(format!("{what}-beam.png")), &exact.film).unwrap();
        let film = jittered(scene, width, height, 8);
        prism_io::output::write_image(&dir.join(format!("{what}-jit.png")), &film).unwrap();
        let diff = Film {
            pixels: film
                .pixels
                .iter()
                .zip(&exact.film.pixels)
                .map(|(a, b)| (*a - *b).abs() * 4.0)
                .collect(),
            ..film.clone()
        };
        prism_io::output::write_image(&dir.join(format!("{what}-diff.png")), &diff).unwrap();
    }
    assert!(
        errors[0] > errors[1] && errors[1] > errors[2],
        "{what}: {errors:?}"
    );
    assert!(errors[2] * 2.5 < errors[0], "{what}: {errors:?}");
    assert!(errors[2] < floor, "{what}: {errors:?}");
}

#[test]
fn the_checkerboard_beam_image_is_the_analytic_reference() {
    let scene = builtin::find("checkerboard").unwrap();
    let (w, h) = (48, 27);
    let tolerance = 2e-3;
    let r = beam(&scene, w, h, tolerance).unwrap();
    assert_covered(&r, "checkerboard");
    let bound = r.error_bound();
    assert!(bound <= tolerance, "bound {bound}");
    let exact = prism_lab::reference::checkerboard(&scene, w, h, 1e-6).unwrap();
    let mut worst: f64 = 0.0;
    for (a, b) in r.film.pixels.iter().zip(&exact.film.pixels) {
        worst = worst.max((*a - *b).abs().max_element() as f64);
    }
    // Within the two bounds and f32 rounding of values up to 1.
    assert!(worst <= bound + 1e-6 + 1e-6, "worst {worst}, bound {bound}");
    // Not a tautology: the far field does differ from one ray per pixel.
    let centre = jittered(&scene, w, h, 1);
    let sampled = prism_lab::metrics::rmse(&centre, &exact.film, None).unwrap();
    assert!(sampled > 10.0 * worst, "{sampled} {worst}");
}

#[test]
fn jittered_supersampling_converges_to_the_beam_image_of_the_cornell_box() {
    let scene = cornell();
    let r = beam(&scene, 64, 64, 1e-4).unwrap();
    // The mirror spawned beams, and they reached the room behind the camera.
    assert!(
        r.stats.reflected_rays > 0 && r.deepest == 2,
        "{}",
        r.deepest
    );
    assert_converges(&scene, "cornell", 64, 64, 0.005);
}

#[test]
fn jittered_supersampling_converges_to_the_beam_image_of_a_mirror_corner() {
    let scene = mirror_corner();
    let r = beam(&scene, 64, 48, 1e-4).unwrap();
    assert!(r.deepest >= 3, "{}", r.deepest);
    assert_converges(&scene, "mirror corner", 64, 48, 0.005);
}

#[test]
fn jittered_supersampling_converges_to_the_beam_image_of_spd_tetra() {
    let Some(dir) = common::shared_data("scenes/spd") else {
        return;
    };
    let scene = prism_io::scene::load(&dir.join("tetra.nff")).unwrap();
    // Shadow boundaries inside a pixel are sampled at piece centroids, so the floor is
    // higher than where nothing is shadowed.
    assert_converges(&scene, "tetra", 48, 48, 0.01);
}

#[test]
fn the_beam_image_is_the_same_at_every_scale() {
    for scene in [cornell(), mirror_corner()] {
        let base = beam(&scene, 40, 40, 1e-4).unwrap();
        for factor in [1e-3, 1e3] {
            let scaled = scene.scaled(factor).unwrap();
            let r = beam(&scaled, 40, 40, 1e-4).unwrap();
            assert_covered(&r, "scaled");
            let diff = prism_lab::metrics::rmse(&base.film, &r.film, None).unwrap();
            if diff >= 1e-4 {
                let bad: Vec<(usize, Color, Color)> = (0..base.film.pixels.len())
                    .filter(|&i| {
                        (base.film.pixels[i] - r.film.pixels[i]).abs().max_element() > 1e-3
                    })
                    .map(|i| (i, base.film.pixels[i], r.film.pixels[i]))
                    .take(5)
                    .collect();
                eprintln!(
                    "{factor}: {bad:?} stats {:?} {:?}",
                    base.stats.beams, r.stats.beams
                );
            }
            assert!(diff < 1e-4, "scale {factor}: RMSE {diff}");
        }
    }
}

#[test]
fn curved_shapes_are_refused_with_a_message() {
    let scene = builtin::find("whitted").unwrap();
    let err = beam(&scene, 16, 16, 1e-4)
        .err()
        .expect("spheres are refused");
    let text = err.to_string();
    assert!(
        text.contains("planar polygons") && text.contains("sphere"),
        "{text}"
    );
}

#[test]
fn a_beam_tree_past_its_budget_stops_with_a_message() {
    let scene = cornell();
    let prepared = scene.prepare(&scene.options.accel);
    let options = RenderOptions {
        width: 32,
        height: 32,
        ..scene.options.clone()
    };
    let mut tracer = prism::integrator::beam::BeamTracer::new(&prepared, &options, 1e-4).unwrap();
    tracer.budget = 3;
    let mut stats = Default::default();
    let err = tracer.trace_tile((0, 0, 16, 16), &mut stats).unwrap_err();
    assert!(err.to_string().contains("grew past 3 fragments"), "{err}");
}

#[test]
fn the_render_entry_point_renders_beams_when_asked() {
    let scene = mirror_corner();
    let prepared = scene.prepare(&scene.options.accel);
    let options = RenderOptions {
        width: 24,
        height: 16,
        integrator: IntegratorKind::Beam,
        ..scene.options.clone()
    };
    let via_render = render(&prepared, &options, &|_| {}, &AtomicBool::new(false)).unwrap();
    let direct = beam(&scene, 24, 16, prism::integrator::beam::DEFAULT_TOLERANCE).unwrap();
    assert_eq!(via_render.film.pixels, direct.film.pixels);
    assert!(via_render.stats.beams > 0);
}
