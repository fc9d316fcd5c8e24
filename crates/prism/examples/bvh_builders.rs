//! Side-by-side figures for the BVH builders, with and without reinsertion, on the
//! 1M-triangle torus knot and the sphereflake: build time (median of several builds), SAH
//! cost, node visits and primitive tests per primary ray, and primary-ray throughput (median of several passes over a 512² camera image on
//! all threads). Run with `cargo run --release --example bvh_builders [scene...]`.

use prism::accel::{Accel, Bvh, BvhBuilder, BvhOptions};
use prism::math::TraceRay;
use prism::scene::builtin;
use prism::{Scene, Stats};
use rayon::prelude::*;
use std::time::Instant;

const SIZE: u32 = 512;
const BUILDS: usize = 5;
const PASSES: usize = 5;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn measure(name: &str, scene: &Scene) {
    let g = &scene.geometry;
    let prims: Vec<u32> = (0..g.primitives.len() as u32)
        .filter(|&i| g.bounds(i).is_some())
        .collect();
    let camera = scene
        .camera
        .setup(SIZE, SIZE)
        .expect("built-in cameras are valid");
    let rays: Vec<TraceRay> = (0..SIZE * SIZE)
        .map(|i| TraceRay::new(camera.ray((i % SIZE) as f32 + 0.5, (i / SIZE) as f32 + 0.5)))
        .collect();
    println!(
        "{name}: {} bounded primitives, {} threads",
        prims.len(),
        rayon::current_num_threads()
    );
    println!(
        "{:<28} {:>10} {:>9} {:>7} {:>10} {:>8} {:>8} {:>9}",
        "builder", "build ms", "SAH", "depth", "nodes", "nodes/r", "prims/r", "Mrays/s"
    );
    let mut variants: Vec<(String, BvhOptions)> = Vec::new();
    for builder in BvhBuilder::ALL {
        for reinsert in [false, true] {
            let options = BvhOptions {
                builder,
                reinsert,
                ..BvhOptions::default()
            };
            let name = format!("{builder}{}", if reinsert { " + reinsert" } else { "" });
            variants.push((name, options));
        }
    }
    // What the parallel build buys: the same trees on one thread.
    for builder in BvhBuilder::ALL {
        let options = BvhOptions {
            builder,
            parallel_threshold: usize::MAX,
            ..BvhOptions::default()
        };
        variants.push((format!("{builder}, serial build"), options));
    }
    {
        for (name, options) in variants {
            let mut times = Vec::new();
            let mut bvh = None;
            for _ in 0..BUILDS {
                let start = Instant::now();
                let built = Bvh::build(g, prims.clone(), &options);
                times.push(start.elapsed().as_secs_f64() * 1e3);
                bvh = Some(built);
            }
            let bvh = bvh.expect("built at least once");
            let info = bvh.info();
            // Work per ray is deterministic, so it shows what the tree buys even on a
            // machine too busy for steady timings.
            let mut work = Stats::default();
            for r in &rays {
                bvh.intersect(g, r, f32::INFINITY, &mut work);
            }
            let per_ray = |count: u64| count as f64 / rays.len() as f64;
            let mut rates = Vec::new();
            let mut hits = 0;
            for _ in 0..PASSES {
                let start = Instant::now();
                hits = rays
                    .par_chunks(SIZE as usize)
                    .map(|row| {
                        let mut stats = Stats::default();
                        row.iter()
                            .filter(|r| bvh.intersect(g, r, f32::INFINITY, &mut stats).is_some())
                            .count()
                    })
                    .sum::<usize>();
                rates.push(rays.len() as f64 / start.elapsed().as_secs_f64() / 1e6);
            }
            println!(
                "{:<28} {:>10.1} {:>9.2} {:>7} {:>10} {:>8.1} {:>8.1} {:>9.2}   ({hits} hits)",
                name,
                median(times),
                info.sah_cost.unwrap_or(f64::NAN),
                info.depth,
                info.nodes,
                per_ray(work.node_visits),
                per_ray(work.primitive_tests),
                median(rates),
            );
        }
    }
}

fn main() {
    let names: Vec<String> = std::env::args().skip(1).collect();
    let names = if names.is_empty() {
        vec!["torusknot".to_string(), "sphereflake".to_string()]
    } else {
        names
    };
    for name in names {
        match builtin::find(&name) {
            Some(scene) => measure(&name, &scene),
            None => eprintln!("no built-in scene '{name}'"),
        }
    }
}
