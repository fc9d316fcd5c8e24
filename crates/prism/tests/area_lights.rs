//! Emitting surfaces light Whitted's render as area lights: the shadow rays to points on
//! them estimate the direct light the path tracer finds on its first bounce, so the two
//! images agree (up to the ambient term, which the scene here has none of); without the
//! area lights the room would be dark. Renders are deterministic for any thread count.

use prism::options::IntegratorKind;
use prism::render::{render, RenderResult};
use prism::scene::builtin;
use prism::{RenderOptions, Scene};
use std::sync::atomic::AtomicBool;

fn run(scene: &Scene, options: &RenderOptions) -> RenderResult {
    let prepared = scene.prepare_for(options);
    render(&prepared, options, &|_| {}, &AtomicBool::new(false)).unwrap()
}

/// The mean of each channel over the pixels of rows `rows`.
fn mean(r: &RenderResult, rows: std::ops::Range<u32>) -> [f64; 3] {
    let w = r.film.width;
    let mut sum = [0.0f64; 3];
    let mut n = 0.0;
    for y in rows {
        for x in 0..w {
            let c = r.film.get(x, y);
            sum[0] += c.x as f64;
            sum[1] += c.y as f64;
            sum[2] += c.z as f64;
            n += 1.0;
        }
    }
    sum.map(|s| s / n)
}

fn options(scene: &Scene, integrator: IntegratorKind) -> RenderOptions {
    RenderOptions {
        width: 48,
        height: 48,
        integrator,
        min_weight: 0.0,
        ..scene.options.clone()
    }
}

#[test]
fn whitted_area_lights_give_the_path_tracers_direct_light() {
    let scene = builtin::find("cornell-light").unwrap();
    // Direct light only: the camera ray and one bounce to the lights.
    let path = run(
        &scene,
        &RenderOptions {
            max_depth: 2,
            samples: 16,
            sampler: prism::sampling::SamplerKind::Jittered,
            ..options(&scene, IntegratorKind::Path)
        },
    );
    let whitted = run(
        &scene,
        &RenderOptions {
            max_depth: 1,
            samples: 4,
            sampler: prism::sampling::SamplerKind::Jittered,
            area_samples: 64,
            ..options(&scene, IntegratorKind::Whitted)
        },
    );
    // The whole image, and its top and bottom halves (the ceiling and the floor, lit
    // from very different angles).
    for rows in [0..48, 0..24, 24..48] {
        let (p, w) = (mean(&path, rows.clone()), mean(&whitted, rows.clone()));
        for c in 0..3 {
            let rel = (w[c] - p[c]).abs() / p[c];
            assert!(
                rel < 0.03,
                "rows {rows:?}, channel {c}: Whitted {:.5} against the path tracer's {:.5}",
                w[c],
                p[c]
            );
        }
    }
    // Without area lights only the light itself shows; the floor is black: the check
    // can fail.
    let dark = run(
        &scene,
        &RenderOptions {
            max_depth: 1,
            area_samples: 0,
            ..options(&scene, IntegratorKind::Whitted)
        },
    );
    let (d, p) = (mean(&dark, 24..48), mean(&path, 24..48));
    assert!(d[0] < 0.01 * p[0], "{d:?} against {p:?}");
    assert!(
        whitted.stats.shadow_rays > 48 * 48 * 4 * 32,
        "{}",
        whitted.stats.shadow_rays
    );
}

#[test]
fn area_lights_are_deterministic_and_the_same_in_packets() {
    let scene = builtin::find("cornell-light").unwrap();
    let base = RenderOptions {
        max_depth: 3,
        area_samples: 9,
        threads: 1,
        ..options(&scene, IntegratorKind::Whitted)
    };
    let one = run(&scene, &base);
    for o in [
        RenderOptions {
            threads: 2,
            tile_size: 5,
            ..base.clone()
        },
        RenderOptions {
            packets: false,
            ..base.clone()
        },
    ] {
        let r = run(&scene, &o);
        assert_eq!(r.film.pixels, one.film.pixels, "{o:?}");
    }
    // The same at any scale: the shadow rays stop short of the light by a relative margin.
    for factor in [1e-3, 1e3] {
        let scaled = scene.scaled(factor).unwrap();
        let r = run(&scaled, &RenderOptions { ..base.clone() });
        let (a, b) = (mean(&r, 0..48), mean(&one, 0..48));
        for c in 0..3 {
            assert!(
                (a[c] - b[c]).abs() <= 0.01 * b[c],
                "scale {factor}: {a:?} against {b:?}"
            );
        }
    }
}
