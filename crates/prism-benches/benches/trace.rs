//! Criterion benches for the foundation: primary-ray throughput through the scene
//! intersector, full Whitted renders, and BVH build times, on a ~1M-triangle mesh, the
//! sphereflake and the default (Whitted) scene. `bench/run.sh` runs them and summarises the
//! medians; docs/journal/performance.md records the figures.
//!
//! Before the timings, each scene prints one `context:` line (accelerator description and
//! work per ray), which is deterministic and so needs no statistics.

use criterion::{BenchmarkId, Criterion, Throughput};
use prism::accel::{AccelSpec, SceneIntersector};
use prism::camera::{Camera, Projection};
use prism::geometry::generate;
use prism::math::{Ray, Vec3};
use prism::render::render;
use prism::scene::builtin;
use prism::shading::Material;
use prism::{RenderOptions, Scene, Stats};
use rayon::prelude::*;
use std::hint::black_box;
use std::sync::atomic::AtomicBool;
use std::time::Duration;

/// Side of the square image whose camera rays the primary-ray benches trace.
const PRIMARY_SIZE: u32 = 256;

/// Triangles in the big-mesh benches.
const KNOT_TRIANGLES: u32 = 1_000_000;

/// The torus knot mesh, framed by a camera that sees all of it at a slant.
fn knot_scene() -> Scene {
    let mut scene = Scene {
        camera: Camera {
            eye: Vec3::new(0.0, -1.5, 3.6),
            look_at: Vec3::ZERO,
            up: Vec3::Z,
            fov_degrees: 45.0,
            projection: Projection::Perspective,
        },
        ..Scene::default()
    };
    let material = scene.add_material(Material::default());
    scene
        .geometry
        .add_mesh(generate::torus_knot(KNOT_TRIANGLES), material);
    scene
}

/// Every camera ray (one per pixel centre) of a `size` × `size` image, in row order.
fn camera_rays(scene: &Scene, size: u32) -> Vec<Ray> {
    let camera = scene
        .camera
        .setup(size, size)
        .expect("bench cameras are valid");
    (0..size)
        .flat_map(|y| (0..size).map(move |x| (x, y)))
        .map(|(x, y)| camera.ray(x as f32 + 0.5, y as f32 + 0.5))
        .collect()
}

/// Nearest hits for all `rays`, rows of the image spread over the pool's threads; returns
/// the summed counters and the number of hits (so nothing can be optimised away).
fn trace_primary(
    scene: &Scene,
    intersector: &SceneIntersector,
    rays: &[Ray],
    pool: &rayon::ThreadPool,
) -> (Stats, usize) {
    pool.install(|| {
        rays.par_chunks(PRIMARY_SIZE as usize)
            .map(|row| {
                let mut stats = Stats::default();
                let mut hits = 0;
                for ray in row {
                    stats.primary_rays += 1;
                    hits += intersector
                        .intersect(&scene.geometry, ray, f32::INFINITY, &mut stats)
                        .is_some() as usize;
                }
                (stats, hits)
            })
            .reduce(
                || (Stats::default(), 0),
                |(mut s, h), (s2, h2)| {
                    s += s2;
                    (s, h + h2)
                },
            )
    })
}

fn all_threads() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// Thread counts to measure: one, and all (just one entry on a single-core machine).
fn thread_counts() -> Vec<usize> {
    let mut counts = vec![1, all_threads()];
    counts.dedup();
    counts
}

fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("the bench can start its worker threads")
}

fn per_ray(count: u64, rays: u64) -> f64 {
    count as f64 / rays.max(1) as f64
}

fn print_context(name: &str, what: &str, intersector: &SceneIntersector, stats: &Stats) {
    let rays = stats.total_rays();
    eprintln!(
        "context: {name}: {} | {what}: {rays} rays, {:.2} primitive tests/ray, {:.2} node visits/ray",
        intersector.accel.describe(),
        per_ray(stats.primitive_tests, rays),
        per_ray(stats.node_visits, rays),
    );
}

fn primary_rays(c: &mut Criterion) {
    let knot = knot_scene();
    let flake = builtin::sphereflake(4);
    let mut group = c.benchmark_group("primary_rays");
    group
        .sample_size(10)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(4))
        .throughput(Throughput::Elements(
            PRIMARY_SIZE as u64 * PRIMARY_SIZE as u64,
        ));
    for (name, scene) in [("knot_1m", &knot), ("sphereflake_4", &flake)] {
        let intersector = SceneIntersector::build(&scene.geometry, &AccelSpec::default());
        let rays = camera_rays(scene, PRIMARY_SIZE);
        let (stats, hits) = trace_primary(scene, &intersector, &rays, &pool(1));
        print_context(name, "primary rays", &intersector, &stats);
        eprintln!("context: {name}: {hits} of {} primary rays hit", rays.len());
        for threads in thread_counts() {
            let pool = pool(threads);
            group.bench_with_input(
                BenchmarkId::new(name, format!("{threads}t")),
                &threads,
                |b, _| b.iter(|| black_box(trace_primary(scene, &intersector, &rays, &pool))),
            );
        }
    }
    group.finish();
}

/// Full Whitted renders; throughput counts every ray traced (camera, shadow, reflected,
/// refracted), which is fixed for a scene and options, so it is counted once beforehand.
fn whitted_renders(c: &mut Criterion) {
    let flake = builtin::sphereflake(4);
    let default_scene = builtin::find("whitted").expect("the default scene exists");
    let cases = [
        ("sphereflake_4_256", &flake, PRIMARY_SIZE, PRIMARY_SIZE),
        (
            "whitted_default",
            &default_scene,
            default_scene.options.width,
            default_scene.options.height,
        ),
    ];
    let mut group = c.benchmark_group("whitted_render");
    group
        .sample_size(10)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(5));
    let cancel = AtomicBool::new(false);
    for (name, scene, width, height) in cases {
        let prepared = scene.prepare(&AccelSpec::default());
        let mut options = RenderOptions {
            width,
            height,
            ..scene.options.clone()
        };
        let stats = render(&prepared, &options, &|_| {}, &cancel)
            .expect("bench renders succeed")
            .stats;
        print_context(
            name,
            &format!("whitted {width}x{height}"),
            &prepared.intersector,
            &stats,
        );
        group.throughput(Throughput::Elements(stats.total_rays()));
        for threads in thread_counts() {
            options.threads = threads;
            group.bench_with_input(
                BenchmarkId::new(name, format!("{threads}t")),
                &options,
                |b, options| b.iter(|| black_box(render(&prepared, options, &|_| {}, &cancel))),
            );
        }
    }
    group.finish();
}

fn bvh_build(c: &mut Criterion) {
    let knot = knot_scene();
    let flake = builtin::sphereflake(4);
    let mut group = c.benchmark_group("bvh_build");
    group
        .sample_size(10)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(10));
    for (name, scene) in [("knot_1m", &knot), ("sphereflake_4", &flake)] {
        group.throughput(Throughput::Elements(scene.geometry.primitives.len() as u64));
        group.bench_function(name, |b| {
            b.iter(|| SceneIntersector::build(black_box(&scene.geometry), &AccelSpec::default()))
        });
    }
    group.finish();
}

// `criterion_group!` and `criterion_main!` written out: the macros make `pub` functions
// without doc comments, which the workspace's `missing_docs` lint refuses.
fn main() {
    let mut criterion = Criterion::default().configure_from_args();
    primary_rays(&mut criterion);
    whitted_renders(&mut criterion);
    bvh_build(&mut criterion);
    Criterion::default().configure_from_args().final_summary();
}
