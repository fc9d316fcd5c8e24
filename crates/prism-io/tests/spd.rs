//! The Standard Procedural Databases (../shared/scenes/spd, beside the repository): every
//! file loads with the primitive counts its text implies, and the SPD testing procedure's
//! ray counts agree with the reference counts in SPD's Readme within the 10 % it allows.
//! Skipped, with a message on the terminal, where the shared folder is absent (a user's
//! clone); under CI a missing folder fails the tests instead.

use crate::common;

use prism::geometry::{Shape, ShapeKind};
use prism::render::render;
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;

fn spd_dir() -> Option<PathBuf> {
    common::shared_data("scenes/spd")
}

/// Spheres, cones and triangles an NFF text describes (an n-gon is n − 2 triangles),
/// counted independently of the loader.
fn expected_counts(text: &str) -> [usize; 3] {
    let tokens: Vec<&str> = text
        .lines()
        .map(|l| l.split('#').next().unwrap_or(""))
        .flat_map(str::split_whitespace)
        .collect();
    let (mut spheres, mut cones, mut triangles) = (0, 0, 0);
    for (i, t) in tokens.iter().enumerate() {
        match *t {
            "s" => spheres += 1,
            "c" => cones += 1,
            "p" | "pp" => triangles += tokens[i + 1].parse::<usize>().unwrap() - 2,
            _ => {}
        }
    }
    [spheres, cones, triangles]
}

#[test]
fn every_spd_file_loads_with_its_primitives() {
    let Some(dir) = spd_dir() else { return };
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "nff"))
        .collect();
    files.sort();
    assert!(
        files.len() >= 7,
        "expected the SPD scenes in {}",
        dir.display()
    );
    for path in files {
        let scene = prism_io::scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
        let text = std::fs::read_to_string(&path).unwrap();
        let [spheres, cones, triangles] = expected_counts(&text);
        let count = |kind: ShapeKind| {
            scene
                .geometry
                .primitives
                .iter()
                .filter(|p| p.shape.kind() == kind)
                .count()
        };
        let name = path.display();
        assert_eq!(count(ShapeKind::Sphere), spheres, "{name}: spheres");
        assert_eq!(count(ShapeKind::Cone), cones, "{name}: cones");
        // Zero-area triangles of fan-like degenerate polygons may be dropped; SPD files
        // have none, so the counts must agree exactly.
        assert_eq!(count(ShapeKind::Triangle), triangles, "{name}: triangles");
        assert!(scene
            .geometry
            .primitives
            .iter()
            .all(|p| !matches!(p.shape, Shape::Plane(_))));
    }
}

/// SPD Readme reference counts at 513×513 corner rays, depth 5:
/// (file, eye rays that hit, reflected, refracted, shadow).
const REFERENCE: &[(&str, u64, u64, u64, u64)] = &[
    ("balls", 263169, 175095, 0, 954368),
    ("gears", 245086, 304643, 207564, 2246955),
    ("mount", 173125, 354769, 354769, 412922),
    ("rings", 263169, 315236, 0, 1085002),
    ("teapot_s12", 161120, 225248, 0, 407656),
    ("tetra", 49788, 0, 0, 46112),
    ("tree", 169836, 0, 0, 1097419),
];

#[test]
fn spd_procedure_ray_counts_match_the_reference() {
    let Some(dir) = spd_dir() else { return };
    for &(name, eye, reflect, refract, shadow) in REFERENCE {
        let mut scene = prism_io::scene::load(&dir.join(format!("{name}.nff"))).unwrap();
        let mut options = scene.options.clone();
        prism::preset::apply_spd(&mut scene, &mut options);
        assert_eq!((options.width, options.height), (513, 513));
        let prepared = scene.prepare(&options.accel);
        let s = render(&prepared, &options, &|_| {}, &AtomicBool::new(false))
            .unwrap()
            .stats;
        assert_eq!(s.primary_rays, 513 * 513);
        for (what, ours, reference) in [
            ("eye-hit", s.primary_hits, eye),
            ("reflected", s.reflected_rays, reflect),
            ("refracted", s.refracted_rays, refract),
            ("shadow", s.shadow_rays, shadow),
        ] {
            let tolerance = reference / 10;
            assert!(
                ours.abs_diff(reference) <= tolerance,
                "{name}: {what} rays {ours}, SPD reference {reference} (±10 %)"
            );
        }
    }
}
