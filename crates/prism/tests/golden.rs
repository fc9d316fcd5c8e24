//! Golden images: each built-in scene rendered small and compared with a reviewed PNG in
//! tests/golden/. Rendering is deterministic, so differences come only from floating-point
//! behaviour across platforms; the tolerances allow that and nothing larger.
//!
//! Regenerate on purpose with `scripts/bless-golden.sh` (PRISM_BLESS=1), then look at the
//! images before committing them.

use prism::render::render;
use prism::scene::builtin;
use prism_io::output::to_rgb8;
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;

/// Mean absolute difference per channel, in 8-bit levels.
const MAX_MEAN_DIFF: f64 = 0.5;
/// Share of channels allowed to differ by more than `LARGE_DIFF` levels (edge pixels whose
/// centre ray flips between two surfaces).
const MAX_LARGE_SHARE: f64 = 0.002;
const LARGE_DIFF: u8 = 24;

fn golden_path(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/golden")
        .join(format!("{}.png", name.replace(':', "-")))
}

fn check(name: &str, width: u32, height: u32, samples: u32) {
    let scene = builtin::find(name).expect("built-in exists");
    check_scene(name, scene, width, height, samples);
}

/// A scene file from the repository, rendered with its own settings but the given size.
fn check_file(relative: &str, golden: &str, width: u32, height: u32, samples: u32) {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(relative);
    let scene = prism_io::scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
    check_scene(golden, scene, width, height, samples);
}

fn check_scene(name: &str, scene: prism::Scene, width: u32, height: u32, samples: u32) {
    let mut options = scene.options.clone();
    options.width = width;
    options.height = height;
    options.samples = samples;
    let prepared = scene.prepare(&options.accel);
    let result = render(&prepared, &options, &|_| {}, &AtomicBool::new(false)).unwrap();
    let actual = to_rgb8(&result.film);
    let path = golden_path(name);

    if std::env::var_os("PRISM_BLESS").is_some() {
        image::save_buffer(&path, &actual, width, height, image::ColorType::Rgb8).unwrap();
        eprintln!("blessed {}", path.display());
        return;
    }
    let expected = image::open(&path)
        .unwrap_or_else(|e| panic!("{}: {e}; run scripts/bless-golden.sh", path.display()))
        .to_rgb8();
    assert_eq!(
        (expected.width(), expected.height()),
        (width, height),
        "{name}: golden image size"
    );
    let expected = expected.into_raw();
    let diffs: Vec<u8> = actual
        .iter()
        .zip(&expected)
        .map(|(a, b)| a.abs_diff(*b))
        .collect();
    let mean = diffs.iter().map(|&d| d as f64).sum::<f64>() / diffs.len() as f64;
    let large = diffs.iter().filter(|&&d| d > LARGE_DIFF).count() as f64 / diffs.len() as f64;
    assert!(
        mean <= MAX_MEAN_DIFF && large <= MAX_LARGE_SHARE,
        "{name}: differs from {}: mean {mean:.3} levels (limit {MAX_MEAN_DIFF}), \
         {:.3}% channels off by > {LARGE_DIFF} (limit {:.3}%)",
        path.display(),
        large * 100.0,
        MAX_LARGE_SHARE * 100.0
    );
}

#[test]
fn whitted() {
    check("whitted", 160, 120, 2);
}

#[test]
fn cornell() {
    check("cornell", 128, 128, 2);
}

#[test]
fn sphereflake() {
    check("sphereflake:2", 128, 128, 1);
}

#[test]
fn checkerboard() {
    check("checkerboard", 160, 90, 3);
}

// One per scene-file format: each loader's output, as pictures.

#[test]
fn toml_shapes() {
    check_file(
        "../../scenes/shapes.toml",
        "format-toml-shapes",
        160,
        120,
        2,
    );
}

#[test]
fn nff_small() {
    check_file("tests/data/small.nff", "format-nff", 160, 120, 2);
}

#[test]
fn obj_gems() {
    check_file("../../scenes/meshes/gems.obj", "format-obj", 160, 120, 2);
}

#[test]
fn ply_torus() {
    check_file("../../scenes/meshes/torus.ply", "format-ply", 160, 120, 2);
}

#[test]
fn gltf_spheres() {
    check_file("../../scenes/spheres.gltf", "format-gltf", 160, 107, 2);
}

#[test]
fn toml_with_mesh_includes() {
    check_file(
        "../../scenes/mesh-room.toml",
        "format-toml-includes",
        160,
        120,
        2,
    );
}
