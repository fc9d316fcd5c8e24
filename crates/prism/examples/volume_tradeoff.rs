//! The tightness / test-cost trade-off of BVH node bounding volumes, side by side: for each
//! scene and each `NodeVolume`, on the same SAH tree, the node tests and primitive tests
//! per primary ray, single-thread Mrays/s (median of several passes), build time, memory,
//! and the tightness figure (chance that a line meeting a node's box meets its volume).
//!
//! `cargo run --release --example volume_tradeoff [-- SIZE [PASSES [big]]]`; `big` adds
//! the 1M-triangle torus knot.

use prism::accel::volumes::{build_measurable, NodeVolume};
use prism::accel::{Accel, Bvh, BvhOptions};
use prism::camera::{Camera, Projection};
use prism::geometry::{Geometry, TriangleMesh};
use prism::math::{TraceRay, Vec3};
use prism::scene::builtin;
use prism::shading::Material;
use prism::{Scene, Stats};
use std::time::Instant;

/// Long thin triangles all slanted along the cube diagonal: each one's box is a cube
/// around a sliver, the case where boxes are poor and oriented volumes shine.
fn diagonal_slivers(count: u32) -> Scene {
    let mut scene = Scene {
        camera: Camera {
            eye: Vec3::new(4.0, -3.0, 2.5),
            look_at: Vec3::ZERO,
            up: Vec3::Z,
            fov_degrees: 40.0,
            projection: Projection::Perspective,
        },
        ..Scene::default()
    };
    let material = scene.add_material(Material::default());
    let along = Vec3::ONE.normalize();
    let across = Vec3::new(1.0, -1.0, 0.0).normalize();
    let mut state = 0x2545_F491_4F6C_DD1Du64;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 40) as f32 / (1u64 << 24) as f32
    };
    let mut positions = Vec::new();
    let mut indices = Vec::new();
    for i in 0..count {
        let a = Vec3::new(next(), next(), next()) * 2.0 - Vec3::ONE;
        let len = 0.3 + 0.5 * next();
        let b = a + len * along;
        let c = a.lerp(b, next()) + 0.004 * across;
        positions.extend([a, b, c]);
        indices.push([3 * i, 3 * i + 1, 3 * i + 2]);
    }
    let mesh = TriangleMesh::new(positions, indices, None, None).expect("valid indices");
    scene.geometry.add_mesh(mesh, material);
    scene
}

fn camera_rays(scene: &Scene, size: u32) -> Vec<TraceRay> {
    let camera = scene.camera.setup(size, size).expect("valid camera");
    (0..size)
        .flat_map(|y| (0..size).map(move |x| (x, y)))
        .map(|(x, y)| TraceRay::new(camera.ray(x as f32 + 0.5, y as f32 + 0.5)))
        .collect()
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Counters of one pass, and the median single-thread Mrays/s over `passes` more.
fn trace(accel: &dyn Accel, g: &Geometry, rays: &[TraceRay], passes: usize) -> (Stats, f64) {
    let mut stats = Stats::default();
    for r in rays {
        std::hint::black_box(accel.intersect(g, r, f32::INFINITY, &mut stats));
    }
    let times: Vec<f64> = (0..passes.max(1))
        .map(|_| {
            let mut s = Stats::default();
            let start = Instant::now();
            for r in rays {
                std::hint::black_box(accel.intersect(g, r, f32::INFINITY, &mut s));
            }
            start.elapsed().as_secs_f64()
        })
        .collect();
    (stats, rays.len() as f64 / median(times) / 1e6)
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let size: u32 = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(256);
    let passes: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(5);
    let big = args.iter().any(|a| a == "big");
    let mut scenes: Vec<(String, Scene)> = ["whitted", "cornell", "sphereflake"]
        .iter()
        .map(|n| (n.to_string(), builtin::find(n).expect("built-in")))
        .collect();
    scenes.push(("torusknot-100k".into(), builtin::torusknot(100_000)));
    if big {
        scenes.push(("torusknot-1M".into(), builtin::torusknot(1_000_000)));
    }
    scenes.push(("diagonal-slivers".into(), diagonal_slivers(20_000)));

    let mut notes = Vec::new();
    println!(
        "| scene | volume | build ms | MiB | node tests/ray | prim tests/ray | Mrays/s | tightness |"
    );
    println!("|---|---|---:|---:|---:|---:|---:|---:|");
    for (name, scene) in &scenes {
        let g = &scene.geometry;
        let prims: Vec<u32> = (0..g.primitives.len() as u32)
            .filter(|&p| g.bounds(p).is_some())
            .collect();
        let rays = camera_rays(scene, size);
        // The plain BVH (two-children SIMD nodes) for reference: the same tree and boxes.
        {
            let start = Instant::now();
            let bvh = Bvh::build(g, prims.clone(), &BvhOptions::default());
            let build_ms = start.elapsed().as_secs_f64() * 1e3;
            let (stats, mrays) = trace(&bvh, g, &rays, passes);
            let n = rays.len() as f64;
            println!(
                "| {name} | bvh (plain) | {build_ms:.0} | {:.1} | {:.1} | {:.2} | {mrays:.2} | 1 |",
                bvh.memory_bytes() as f64 / (1024.0 * 1024.0),
                stats.node_visits as f64 / n,
                stats.primitive_tests as f64 / n,
            );
        }
        for volume in NodeVolume::ALL {
            let start = Instant::now();
            let accel = build_measurable(g, prims.clone(), &BvhOptions::default(), volume);
            let build_ms = start.elapsed().as_secs_f64() * 1e3;
            let info = accel.accel().info();
            let (stats, mrays) = trace(accel.accel(), g, &rays, passes);
            let n = rays.len() as f64;
            let tightness = accel.tightness(g, 2000, 256);
            if volume == NodeVolume::Hull {
                notes.push(format!("{name}: {}", info.method));
            }
            println!(
                "| {name} | {} | {build_ms:.0} | {:.1} | {:.1} | {:.2} | {:.2} | {:.3} |",
                volume.name(),
                info.memory_bytes as f64 / (1024.0 * 1024.0),
                stats.node_visits as f64 / n,
                stats.primitive_tests as f64 / n,
                mrays,
                tightness,
            );
        }
    }
    println!();
    for n in notes {
        println!("{n}");
    }
}
