//! The exact checkerboard reference (prism_lab::reference): closed cases it must get exactly,
//! scenes it must refuse, and agreement with brute force, where very many jittered samples
//! per pixel converge to the same area averages.

use prism::camera::{Camera, Projection};
use prism::math::{Color, Vec3};
use prism::render::render;
use prism::sampling::SamplerKind;
use prism::scene::builtin;
use prism::RenderOptions;
use prism_lab::reference::{checkerboard, ReferenceError};
use std::sync::atomic::AtomicBool;

/// The built-in checkerboard seen from straight above, 8×8 pixels covering exactly the
/// squares x, z ∈ [−4, 4] (plus `shift` along x): the image is a known pattern.
fn overhead(shift: f32) -> prism::Scene {
    let mut scene = builtin::find("checkerboard").unwrap();
    scene.camera = Camera {
        eye: Vec3::new(shift, 1.0, 0.0),
        look_at: Vec3::new(shift, 0.0, 0.0),
        up: Vec3::Z,
        // tan(fov/2) = 4: the 8-pixel image spans 8 units at height 1.
        fov_degrees: 2.0 * 4f32.atan().to_degrees(),
        projection: Projection::Perspective,
    };
    scene
}

#[test]
fn pixels_aligned_with_the_squares_are_exactly_black_or_white() {
    let r = checkerboard(&overhead(0.0), 8, 8, 1e-6).unwrap();
    for y in 0..8 {
        for x in 0..8 {
            let v = r.film.get(x, y);
            assert!(
                (v.x - 1.0).abs() < 1e-5 || v.x.abs() < 1e-5,
                "pixel ({x}, {y}) = {v}"
            );
            // Neighbours alternate.
            if x > 0 {
                assert!((v.x - r.film.get(x - 1, y).x).abs() > 0.99);
            }
        }
    }
    assert_eq!(r.error_bound, 0.0, "no horizon, no approximation");
}

#[test]
fn pixels_straddling_two_squares_are_exactly_grey() {
    let r = checkerboard(&overhead(0.5), 8, 8, 1e-6).unwrap();
    for v in &r.film.pixels {
        assert!((v.x - 0.5).abs() < 1e-5, "{v}");
    }
}

#[test]
fn scenes_beyond_the_closed_form_are_refused() {
    let whitted = builtin::find("whitted").unwrap();
    assert!(matches!(
        checkerboard(&whitted, 8, 8, 1e-4),
        Err(ReferenceError::Unsupported(_))
    ));
    // A rolled camera: rows no longer run along the squares.
    let mut rolled = builtin::find("checkerboard").unwrap();
    rolled.camera.up = Vec3::new(0.3, 1.0, 0.0);
    assert!(matches!(
        checkerboard(&rolled, 8, 8, 1e-4),
        Err(ReferenceError::Unsupported(_))
    ));
    let plain = builtin::find("checkerboard").unwrap();
    assert_eq!(
        checkerboard(&plain, 8, 8, 0.0).unwrap_err(),
        ReferenceError::Tolerance(0.0)
    );
}

#[test]
fn the_exact_reference_agrees_with_a_very_high_sample_render() {
    let scene = builtin::find("checkerboard").unwrap();
    let (w, h) = (64, 36);
    let tolerance = 1e-6;
    let reference = checkerboard(&scene, w, h, tolerance).unwrap();
    assert!(reference.error_bound <= tolerance * 1.000_001);
    let options = RenderOptions {
        width: w,
        height: h,
        samples: 48,
        sampler: SamplerKind::Jittered,
        ..scene.options.clone()
    };
    let prepared = scene.prepare(&options.accel);
    let film = render(&prepared, &options, &|_| {}, &AtomicBool::new(false))
        .unwrap()
        .film;
    let far = reference.far_field();
    assert!(far.iter().filter(|&&f| f).count() > 100, "a far field");
    let (mut near_worst, mut n_far) = (0.0f32, 0usize);
    let (mut far_bias, mut far_err2, mut far_signal2) = (0.0f64, 0.0f64, 0.0f64);
    for y in 0..h {
        for x in 0..w {
            let (a, b) = (film.get(x, y), reference.film.get(x, y));
            if far[(y * w + x) as usize] {
                n_far += 1;
                far_bias += (a.x - b.x) as f64;
                far_err2 += ((a.x - b.x) as f64).powi(2);
                far_signal2 += ((a.x - 0.5) as f64).powi(2);
            } else {
                // 2304 stratified samples resolve an edge to a few thousandths.
                near_worst = near_worst.max((a - b).abs().max_element());
            }
        }
    }
    assert!(
        near_worst < 0.01,
        "near field: worst difference {near_worst}"
    );
    // Far field: the render's noise averages out (no bias), and the reference explains
    // most of the render's departure from flat grey, which a wrong reference would not.
    let n = n_far as f64;
    let (bias, rms) = (far_bias / n, (far_err2 / n).sqrt());
    assert!(
        bias.abs() < 3.0 * rms / n.sqrt(),
        "far field bias {bias}, rms {rms}"
    );
    let signal = (far_signal2 / n).sqrt();
    assert!(
        rms < 0.5 * signal,
        "far field: rms {rms} against signal {signal}"
    );
}

#[test]
fn sky_pixels_are_the_background() {
    let scene = builtin::find("checkerboard").unwrap();
    let r = checkerboard(&scene, 32, 18, 1e-4).unwrap();
    assert_eq!(r.film.get(5, 0), Color::new(0.55, 0.7, 0.9));
    assert_eq!(r.squares[5], 0.0);
}
