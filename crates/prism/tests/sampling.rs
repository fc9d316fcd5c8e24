//! Rendering with every sampler and filter: the default grid keeps the renderer's original
//! arithmetic bit for bit; shared samples (corners, adaptive) are traced exactly once;
//! every sampler is bit-identical for any thread count and tile size; filters keep a flat
//! image flat; adaptive depth control with a zero threshold changes nothing.

use crate::common::film_bits;
use prism::camera::{Camera, Projection};
use prism::geometry::{generate, Plane, Shape};
use prism::integrator::Whitted;
use prism::light::Light;
use prism::math::{Color, Vec3};
use prism::render::{render, FilterKind, RenderResult};
use prism::sampling::adaptive::{Square, Visit};
use prism::sampling::{AdaptiveSpec, Sampler, SamplerKind};
use prism::scene::builtin;
use prism::shading::{Material, Texture};
use prism::{RenderOptions, Scene, Stats};
use std::cell::RefCell;
use std::collections::{HashMap, HashSet};
use std::sync::atomic::AtomicBool;

fn run(scene: &Scene, options: &RenderOptions) -> RenderResult {
    let prepared = scene.prepare(&options.accel);
    render(&prepared, options, &|_| {}, &AtomicBool::new(false)).unwrap()
}

fn small(scene: &Scene, width: u32, height: u32) -> RenderOptions {
    RenderOptions {
        width,
        height,
        ..scene.options.clone()
    }
}

#[test]
fn the_grid_with_the_pixel_box_keeps_the_original_arithmetic() {
    let scene = builtin::find("whitted").unwrap();
    let options = RenderOptions {
        samples: 3,
        ..small(&scene, 40, 30)
    };
    // Packets change only the traversal counts (tests/packets.rs); the counts are held to
    // the original loop's without them.
    let result = run(
        &scene,
        &RenderOptions {
            packets: false,
            ..options.clone()
        },
    );
    let packed = run(&scene, &options);
    assert!(
        film_bits(&packed.film) == film_bits(&result.film),
        "packets change the image"
    );
    // The loop the renderer had before sampling patterns existed.
    let prepared = scene.prepare(&options.accel);
    let camera = scene.camera.setup(40, 30).unwrap();
    let integrator = Whitted::new(&prepared, &options);
    let (n, inv_n) = (3u32, 1.0 / 3.0f32);
    let weight = 1.0 / (n * n) as f32;
    let mut stats = Stats::default();
    for y in 0..30 {
        for x in 0..40 {
            let mut sum = Color::ZERO;
            for j in 0..n {
                for i in 0..n {
                    let fx = x as f32 + (i as f32 + 0.5) * inv_n;
                    let fy = y as f32 + (j as f32 + 0.5) * inv_n;
                    sum += integrator.trace_camera_ray(&camera.ray(fx, fy), &mut stats);
                }
            }
            let expected = sum * weight;
            let got = result.film.get(x, y);
            assert!(
                got.to_array().map(f32::to_bits) == expected.to_array().map(f32::to_bits),
                "pixel ({x}, {y}): {got} against {expected}"
            );
        }
    }
    assert_eq!(stats, result.stats);
}

#[test]
fn corners_are_shared_so_a_pixel_costs_about_two_camera_rays() {
    let scene = builtin::find("cornell").unwrap();
    let (w, h) = (37u64, 23u64);
    let options = RenderOptions {
        sampler: SamplerKind::Corners,
        ..small(&scene, w as u32, h as u32)
    };
    let r = run(&scene, &options);
    assert_eq!(r.stats.primary_rays, w * h + (w + 1) * (h + 1));
    let per_pixel = r.rays.mean_camera();
    assert!(
        (per_pixel - 2.0).abs() < 0.1,
        "{per_pixel} camera rays per pixel"
    );
    let counted: u64 = r.rays.camera.iter().map(|&c| c as u64).sum();
    assert_eq!(
        counted, r.stats.primary_rays,
        "the density view counts every ray once"
    );
}

/// Adaptive sampling replayed independently: every pixel's quadtree walked in full, with a
/// cache that traces a lattice point the first time any pixel asks for it. Returns the
/// lattice points traced, the splits, the points the pixels would trace without sharing,
/// and the pixels that took the stratified pass.
fn replay_adaptive(scene: &Scene, options: &RenderOptions) -> (usize, u64, usize, u64) {
    let Sampler::Adaptive(rule) = Sampler::new(options) else {
        panic!("adaptive options")
    };
    let prepared = scene.prepare(&options.accel);
    let camera = scene.camera.setup(options.width, options.height).unwrap();
    let integrator = Whitted::new(&prepared, options);
    let steps = rule.steps();
    let (wl, hl) = (options.width * steps, options.height * steps);
    let cache: RefCell<HashMap<(u32, u32), Color>> = RefCell::default();
    let stats = RefCell::new(Stats::default());
    let lookup = |x: u32, y: u32| {
        if x > wl || y > hl {
            return None;
        }
        let mut cache = cache.borrow_mut();
        Some(*cache.entry((x, y)).or_insert_with(|| {
            let (fx, fy) = rule.position(x, y);
            let ray = camera.ray(fx / steps as f32, fy / steps as f32);
            integrator.trace_camera_ray(&ray, &mut stats.borrow_mut())
        }))
    };
    let (mut splits, mut unshared, mut stratified) = (0u64, 0usize, 0u64);
    for py in 0..options.height {
        for px in 0..options.width {
            let mut own = HashSet::new();
            rule.walk(
                Square::pixel(px, py, steps),
                rule.depth,
                &lookup,
                &mut |sq, v| {
                    own.extend(sq.corners());
                    match v {
                        Visit::Split => splits += 1,
                        Visit::Stratified(_) => stratified += 1,
                        _ => {}
                    }
                },
            );
            unshared += own.len();
        }
    }
    let traced = cache.borrow().len();
    (traced, splits, unshared, stratified)
}

#[test]
fn adaptive_sampling_traces_each_lattice_point_once() {
    for (name, w, h, depth, texture_spp) in [
        ("whitted", 30, 22, 2, 25),
        ("checkerboard", 32, 18, 3, 25),
        ("checkerboard", 32, 18, 3, 0),
    ] {
        let scene = builtin::find(name).unwrap();
        let options = RenderOptions {
            sampler: SamplerKind::Adaptive,
            adaptive: AdaptiveSpec {
                depth,
                texture_spp,
                ..AdaptiveSpec::default()
            },
            ..small(&scene, w, h)
        };
        let r = run(&scene, &options);
        let (traced, splits, unshared, stratified) = replay_adaptive(&scene, &options);
        let name = format!("{name}, texture spp {texture_spp}");
        // Stratified samples belong to one pixel: texture_spp each, on top of the lattice.
        assert_eq!(r.stats.adaptive_stratified, stratified, "{name}: textured");
        assert_eq!(
            r.stats.primary_rays,
            traced as u64 + stratified * texture_spp as u64,
            "{name}: camera rays"
        );
        if name.starts_with("checkerboard") {
            assert_eq!(stratified > 0, texture_spp > 0, "{name}: the far field");
        }
        assert_eq!(r.stats.adaptive_splits, splits, "{name}: splits");
        assert!(splits > 0, "{name}: something was refined");
        let corners = ((w + 1) * (h + 1)) as u64;
        assert!(
            r.stats.primary_rays > corners,
            "{name}: refined beyond the corners"
        );
        // Without sharing, every pixel would trace its own corners and edge points.
        assert!(
            unshared > traced + corners as usize,
            "{name}: sharing saves rays ({unshared} unshared, {traced} traced)"
        );
    }
}

#[test]
fn adaptive_sampling_with_a_threshold_of_one_traces_only_the_corners() {
    let scene = builtin::find("whitted").unwrap();
    for depth in [0, 3] {
        let options = RenderOptions {
            sampler: SamplerKind::Adaptive,
            adaptive: AdaptiveSpec {
                threshold: 1.0,
                depth,
                ..AdaptiveSpec::default()
            },
            ..small(&scene, 20, 15)
        };
        let r = run(&scene, &options);
        assert_eq!(r.stats.primary_rays, 21 * 16, "depth {depth}");
        assert_eq!(r.stats.adaptive_splits, 0);
    }
}

#[test]
fn every_sampler_and_filter_is_bit_identical_for_any_threads_and_tiles() {
    let scene = builtin::find("whitted").unwrap();
    for sampler in SamplerKind::ALL {
        for filter in [FilterKind::Box, FilterKind::Mitchell] {
            let options = |threads, tile_size| RenderOptions {
                sampler,
                filter,
                samples: 2,
                adaptive: AdaptiveSpec {
                    depth: 2,
                    ..AdaptiveSpec::default()
                },
                threads,
                tile_size,
                seed: 9,
                ..small(&scene, 33, 21)
            };
            let reference = run(&scene, &options(1, 16));
            for (threads, tile) in [(2, 7), (2, 1), (1, 64)] {
                let r = run(&scene, &options(threads, tile));
                assert!(
                    film_bits(&r.film) == film_bits(&reference.film),
                    "{sampler} / {filter}: image differs with {threads} threads, {tile}-pixel tiles"
                );
                assert_eq!(r.stats, reference.stats, "{sampler} / {filter}: statistics");
                assert_eq!(
                    r.rays, reference.rays,
                    "{sampler} / {filter}: rays per pixel"
                );
            }
        }
    }
}

#[test]
fn the_stratified_pass_is_bit_identical_for_any_threads_and_tiles() {
    // The checkerboard's far field is textured: its pixels take the stratified pass.
    let scene = builtin::find("checkerboard").unwrap();
    for filter in [FilterKind::Box, FilterKind::Mitchell] {
        let options = |threads, tile_size| RenderOptions {
            sampler: SamplerKind::Adaptive,
            filter,
            threads,
            tile_size,
            seed: 4,
            ..small(&scene, 48, 27)
        };
        let reference = run(&scene, &options(1, 16));
        assert!(reference.stats.adaptive_stratified > 0);
        for (threads, tile) in [(2, 7), (2, 1)] {
            let r = run(&scene, &options(threads, tile));
            assert!(
                film_bits(&r.film) == film_bits(&reference.film),
                "{filter}: image"
            );
            assert_eq!(r.stats, reference.stats, "{filter}: statistics");
            assert_eq!(r.rays, reference.rays, "{filter}: rays per pixel");
        }
    }
}

#[test]
fn a_flat_image_stays_flat_under_every_sampler_and_filter() {
    // Nothing to hit: every ray returns the background, so every weighted average of
    // samples, up to the image's edges, must give it back.
    let mut scene = Scene {
        background: Color::new(0.3, 0.5, 0.7),
        ..Scene::default()
    };
    scene.options.width = 13;
    scene.options.height = 9;
    for sampler in SamplerKind::ALL {
        for filter in FilterKind::ALL {
            for radius in [None, Some(3.0)] {
                let options = RenderOptions {
                    sampler,
                    filter,
                    filter_radius: radius,
                    samples: 2,
                    ..scene.options.clone()
                };
                let r = run(&scene, &options);
                for p in &r.film.pixels {
                    assert!(
                        (*p - scene.background).abs().max_element() < 1e-6,
                        "{sampler} / {filter} radius {radius:?}: {p}"
                    );
                }
            }
        }
    }
}

#[test]
fn a_zero_weight_threshold_traces_the_static_ray_tree() {
    let scene = builtin::find("whitted").unwrap();
    let with = |min_weight| {
        run(
            &scene,
            &RenderOptions {
                min_weight,
                ..small(&scene, 48, 36)
            },
        )
    };
    let zero = with(0.0);
    assert_eq!(zero.stats.pruned_rays, 0);
    assert_eq!(zero.stats.pruned_shadow_rays, 0);
    // A threshold below every product of weights in the scene prunes no reflected or
    // refracted ray either: the zero threshold is the static depth limit, not a special
    // case. It does prune the shadow rays of the glass's faintest highlights (below
    // 1e-30, which cannot change a pixel), one shadow ray each; the image is the same.
    let tiny = with(1e-30);
    assert!(film_bits(&tiny.film) == film_bits(&zero.film));
    assert_eq!(tiny.stats.pruned_rays, 0);
    assert!(tiny.stats.pruned_shadow_rays > 0);
    assert_eq!(
        tiny.stats.shadow_rays + tiny.stats.pruned_shadow_rays,
        zero.stats.shadow_rays
    );
    let rays = |s: &Stats| [s.primary_rays, s.reflected_rays, s.refracted_rays];
    assert_eq!(rays(&tiny.stats), rays(&zero.stats));
    // The default prunes, saves at least the pruned rays, and changes the image little.
    let default = with(RenderOptions::default().min_weight);
    assert!(default.stats.pruned_rays > 0 && default.stats.pruned_shadow_rays > 0);
    let saved = zero.stats.total_rays() - default.stats.total_rays();
    let pruned = default.stats.pruned_rays + default.stats.pruned_shadow_rays;
    assert!(saved >= pruned, "saved {saved}, pruned {pruned}");
    let c = prism_lab::metrics::compare(&zero.film, &default.film, None, 67.0).unwrap();
    assert!(c.flip < 0.01 && c.rmse < 2e-3, "{c:?}");
    // Higher thresholds trace fewer rays.
    let mut last = zero.stats.total_rays();
    for t in [0.001, 0.01, 0.1, 0.5] {
        let n = with(t).stats.total_rays();
        assert!(n <= last, "threshold {t}: {n} rays after {last}");
        last = n;
    }
    assert!(last < zero.stats.total_rays());
}

#[test]
fn a_light_that_cannot_change_a_pixel_by_min_weight_casts_no_shadow_ray() {
    // A white Lambert floor that fills the view, lit straight from above (n·l = 1): a
    // light of 0.003 could add at most 0.003 to a camera ray's pixel, below the default
    // min_weight of 1/255, so it casts no shadow ray; one of 0.005 could add more and
    // casts its rays. The faint light gets through as much as the tested (bright) one:
    // all of it in the open, none of it under a roof over half of the floor.
    let floor_under = |lights: &[f32]| {
        let mut scene = Scene {
            // Below the roof, looking down at the floor.
            camera: Camera {
                eye: Vec3::new(0.0, 0.5, 1.0),
                look_at: Vec3::ZERO,
                up: Vec3::Y,
                fov_degrees: 30.0,
                projection: Projection::Perspective,
            },
            ambient: Color::ZERO,
            background: Color::ZERO,
            lights: (lights.iter())
                .map(|&c| Light::Directional {
                    direction: -Vec3::Y,
                    color: Color::splat(c),
                })
                .collect(),
            ..Scene::default()
        };
        let white = scene.add_material(Material {
            name: "white".into(),
            color: Texture::Solid(Color::ONE),
            ambient: 0.0,
            diffuse: 1.0,
            ..Material::default()
        });
        let plane = Plane::new(Vec3::ZERO, Vec3::Y).unwrap();
        scene.geometry.add(Shape::Plane(Box::new(plane)), white);
        // The roof: a square above the floor's x < 0 half, wider than the view.
        let roof = generate::quad(
            Vec3::new(-100.0, 1.0, -100.0),
            Vec3::new(-100.0, 1.0, 100.0),
            Vec3::new(0.0, 1.0, 100.0),
            Vec3::new(0.0, 1.0, -100.0),
            1.0,
            1.0,
        );
        scene.geometry.add_mesh(roof, white);
        scene
    };
    let (dim, faint_but_enough, bright) = (0.003, 0.005, 0.5);
    for packets in [true, false] {
        let render_of = |scene: &Scene, min_weight: f32| {
            let options = RenderOptions {
                width: 16,
                height: 12,
                threads: 1,
                min_weight,
                packets,
                ..scene.options.clone()
            };
            run(scene, &options)
        };
        let default_weight = RenderOptions::default().min_weight;
        let adaptive = render_of(&floor_under(&[dim, bright]), default_weight);
        let exact = render_of(&floor_under(&[dim, bright]), 0.0);
        let hits = adaptive.stats.primary_hits;
        assert_eq!(hits, 16 * 12, "the floor fills the view");
        assert_eq!(adaptive.stats.shadow_rays, hits);
        assert_eq!(adaptive.stats.pruned_shadow_rays, hits);
        assert_eq!(exact.stats.shadow_rays, 2 * hits);
        assert_eq!(exact.stats.pruned_shadow_rays, 0);
        // The estimate is right on both sides: in the open the image is the exact one
        // (up to the order of the sum), under the roof black.
        let (mut open, mut shaded) = (0, 0);
        for (a, e) in adaptive.film.pixels.iter().zip(&exact.film.pixels) {
            if e.x > bright {
                assert_eq!(*e, Color::splat(dim + bright));
                assert!((*a - *e).abs().max_element() <= 1e-6, "{a} against {e}");
                open += 1;
            } else {
                assert_eq!(*e, Color::ZERO);
                assert_eq!(*a, Color::ZERO, "packets {packets}");
                shaded += 1;
            }
        }
        assert!(open > 0 && shaded > 0, "{open} open, {shaded} shaded");
        // Just above the threshold the light is tested.
        let enough = render_of(&floor_under(&[faint_but_enough, bright]), default_weight);
        assert_eq!(enough.stats.shadow_rays, 2 * hits);
        assert_eq!(enough.stats.pruned_shadow_rays, 0);
    }
}

#[test]
fn the_spd_preset_takes_one_grid_ray_per_pixel_whatever_the_sampling_options() {
    let mut scene = builtin::find("whitted").unwrap();
    let mut options = RenderOptions {
        sampler: SamplerKind::Adaptive,
        filter: FilterKind::Mitchell,
        filter_radius: Some(3.0),
        samples: 4,
        ..RenderOptions::default()
    };
    prism::preset::apply_spd(&mut scene, &mut options);
    assert_eq!(
        (
            options.sampler,
            options.filter,
            options.filter_radius,
            options.samples
        ),
        (SamplerKind::Grid, FilterKind::Box, None, 1)
    );
    assert_eq!(options.min_weight, 0.0);
}

#[test]
fn adaptive_pixels_without_splatting_match_the_splatted_ones() {
    // With the pixel box (radius ½) each adaptive pixel is the weighted mean of its own
    // samples, summed directly; a box a hair wider goes through the fixed-point splat
    // buffers. Without the stratified pass every sample is the centre of a lattice
    // square, at least 1/16 pixel inside its pixel, so the wider box adds nothing and
    // both must give the same means up to rounding.
    let scene = builtin::find("whitted").unwrap();
    let mut options = small(&scene, 64, 48);
    options.sampler = SamplerKind::Adaptive;
    options.adaptive.texture_spp = 0;
    options.filter = FilterKind::Box;
    let direct = run(&scene, &options);
    options.filter_radius = Some(0.5 + 1e-4);
    let splatted = run(&scene, &options);
    assert_eq!(direct.stats.total_rays(), splatted.stats.total_rays());
    for (i, (a, b)) in direct
        .film
        .pixels
        .iter()
        .zip(&splatted.film.pixels)
        .enumerate()
    {
        for c in 0..3 {
            let err = (a[c] - b[c]).abs();
            assert!(
                err <= 1e-6 * a[c].abs().max(b[c].abs()).max(1e-3),
                "pixel {i}: {a} direct, {b} splatted"
            );
        }
    }
}

#[test]
fn a_cancelled_lattice_render_stops_without_panicking() {
    // Cancelled after the 1st, 10th, 25th or 30th row of work: in the corners pass, in the
    // adaptive sampler's even or odd rows (the corners pattern's centres), or never (100).
    // The render says whether it is complete, and its pixels are finite (black, or their
    // corners' mean where known).
    let scene = builtin::find("whitted").unwrap();
    let prepared = scene.prepare(&scene.options.accel);
    for sampler in [SamplerKind::Adaptive, SamplerKind::Corners] {
        for filter in [FilterKind::Box, FilterKind::Mitchell] {
            for after in [1, 10, 25, 30, 100] {
                let options = RenderOptions {
                    sampler,
                    filter,
                    threads: 2,
                    ..small(&scene, 24, 18)
                };
                let cancel = AtomicBool::new(false);
                let done = std::sync::atomic::AtomicU32::new(0);
                let on_tile = |_| {
                    if done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1 >= after {
                        cancel.store(true, std::sync::atomic::Ordering::Relaxed);
                    }
                };
                let r = render(&prepared, &options, &on_tile, &cancel).unwrap();
                let name = format!("{sampler} / {filter}, cancelled after {after} rows");
                // 19 corner rows, then 9 even and 9 odd rows (or 18 rows of centres).
                assert_eq!(r.complete, after == 100, "{name}");
                assert!(
                    r.film.pixels.iter().all(|c| c.is_finite()),
                    "{name}: pixels"
                );
            }
        }
    }
}
