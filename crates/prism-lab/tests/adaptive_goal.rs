//! The adaptive-sampling goal (docs/sampling.md), on the one scene with an exact reference: on the
//! built-in checkerboard at its own size, the adaptive sampler at its default settings
//! reaches the RMSE of 16-spp jittered sampling with at most 35 % of its rays (every ray
//! counts; the checkerboard has no lights, so all rays are camera rays). The default scene
//! needs a rendered reference and is measured by scripts/adaptive-goal.sh instead.

use prism::render::{render, RenderResult};
use prism::sampling::SamplerKind;
use prism::scene::builtin;
use prism::RenderOptions;
use prism_lab::metrics::compare;
use prism_lab::reference::{checkerboard, DEFAULT_TOLERANCE};
use std::sync::atomic::AtomicBool;

fn run(scene: &prism::Scene, options: &RenderOptions) -> RenderResult {
    let prepared = scene.prepare(&options.accel);
    render(&prepared, options, &|_| {}, &AtomicBool::new(false)).unwrap()
}

#[test]
#[cfg_attr(
    debug_assertions,
    ignore = "renders 640×360 three ways; run with cargo test --release"
)]
fn adaptive_sampling_reaches_jittered_16_with_at_most_35_percent_of_the_rays() {
    let scene = builtin::find("checkerboard").unwrap();
    let base = scene.options.clone();
    let exact = checkerboard(&scene, base.width, base.height, DEFAULT_TOLERANCE).unwrap();
    let measure = |options: RenderOptions| {
        let r = run(&scene, &options);
        let rmse = compare(&exact.film, &r.film, None, 67.0).unwrap().rmse;
        (rmse, r.stats.total_rays())
    };
    let (jittered_rmse, jittered_rays) = measure(RenderOptions {
        sampler: SamplerKind::Jittered,
        samples: 4,
        ..base.clone()
    });
    let (adaptive_rmse, adaptive_rays) = measure(RenderOptions {
        sampler: SamplerKind::Adaptive,
        ..base.clone()
    });
    let share = adaptive_rays as f64 / jittered_rays as f64;
    assert!(
        adaptive_rmse <= jittered_rmse && share <= 0.35,
        "adaptive: RMSE {adaptive_rmse:.5} with {:.0} % of the rays; jittered 16: {jittered_rmse:.5}",
        100.0 * share
    );
    // Without the stratified pass, texture is subdivided: more rays for the same error,
    // which is why the pass exists.
    let (_, subdivided_rays) = measure(RenderOptions {
        sampler: SamplerKind::Adaptive,
        adaptive: prism::sampling::AdaptiveSpec {
            texture_spp: 0,
            ..base.adaptive
        },
        ..base
    });
    assert!(subdivided_rays > adaptive_rays, "{subdivided_rays} rays");
}
