//! Measuring shadow methods (`integrator::ShadowSpec`) on a fixed workload: the shadow rays
//! of a `RaySet`, in pixel order as a render meets them, answered by each method in turns
//! (sample r of every method before sample r + 1 of any), each held to the accelerator's
//! answers.

use super::{MeasureOptions, RaySet};
use prism::integrator::{begin_piece, ShadowSpec, Shadows};
use prism::scene::PreparedScene;
use prism::stats::Stats;
use serde::Serialize;
use std::time::{Duration, Instant};

/// One shadow method's figures on one scene.
#[derive(Clone, Debug, Serialize)]
pub struct ShadowMeasured {
    /// The shadow method, as `--shadows` writes it.
    pub method: String,
    /// Time to build its light buffers (0 without).
    pub build_ms: f64,
    /// Bytes its light buffers hold.
    pub memory_bytes: usize,
    /// Shadow rays traced.
    pub rays: usize,
    /// Rays found blocked.
    pub blocked: usize,
    /// Mean ray–primitive tests per shadow ray.
    pub tests_per_ray: f64,
    /// Mean acceleration-structure node visits per shadow ray.
    pub node_visits_per_ray: f64,
    /// Share of the rays the shadow cache answered alone.
    pub cache_hit_rate: f64,
    /// Share of the rays a light buffer handed to the accelerator (passing near the light).
    pub fallback_rate: f64,
    /// Median of the timed samples.
    pub mrays_per_s: f64,
    /// Whether any ray's answer differs from the accelerator's (the first method's).
    pub mismatch: bool,
    /// Lights that kept the accelerator, and why.
    pub notes: Vec<String>,
}

/// Times `specs` on `rays.shadow` over `prepared` (whose accelerator is the reference).
pub fn measure_shadow_methods(
    prepared: &PreparedScene,
    rays: &RaySet,
    specs: &[ShadowSpec],
    options: &MeasureOptions,
) -> Vec<ShadowMeasured> {
    let built: Vec<(Shadows, Duration)> = specs
        .iter()
        .map(|&spec| {
            let start = Instant::now();
            let shadows = Shadows::new(prepared, spec);
            (shadows, start.elapsed())
        })
        .collect();
    let reference = answers(&Shadows::new(prepared, ShadowSpec::default()), rays).0;
    let mut results: Vec<ShadowMeasured> = built
        .iter()
        .zip(specs)
        .map(|((shadows, build), spec)| {
            let (blocked, stats) = answers(shadows, rays);
            let n = rays.shadow.len().max(1) as f64;
            ShadowMeasured {
                method: spec.to_string(),
                build_ms: build.as_secs_f64() * 1e3,
                memory_bytes: shadows
                    .buffer_info()
                    .iter()
                    .flatten()
                    .map(|b| b.memory_bytes)
                    .sum(),
                rays: rays.shadow.len(),
                blocked: blocked.iter().filter(|&&b| b).count(),
                tests_per_ray: stats.primitive_tests as f64 / n,
                node_visits_per_ray: stats.node_visits as f64 / n,
                cache_hit_rate: stats.shadow_cache_hits as f64 / n,
                fallback_rate: stats.light_buffer_fallbacks as f64 / n,
                mrays_per_s: 0.0,
                mismatch: blocked != reference,
                notes: shadows
                    .unbuilt
                    .iter()
                    .enumerate()
                    .filter_map(|(i, n)| n.as_ref().map(|n| format!("light {i}: {n}")))
                    .collect(),
            }
        })
        .collect();
    let mut samples: Vec<Vec<f64>> = vec![Vec::new(); specs.len()];
    let started = Instant::now();
    for _ in 0..options.repeat.max(1) {
        for (i, (shadows, _)) in built.iter().enumerate() {
            samples[i].push(sample(shadows, rays, options));
        }
        if started.elapsed() > options.trace_budget {
            break;
        }
    }
    for (r, mut s) in results.iter_mut().zip(samples) {
        s.sort_by(f64::total_cmp);
        r.mrays_per_s = s[s.len() / 2];
    }
    results
}

/// Every ray's answer, and the work they took.
fn answers(shadows: &Shadows, rays: &RaySet) -> (Vec<bool>, Stats) {
    let mut stats = Stats::default();
    begin_piece();
    let blocked = rays
        .shadow
        .iter()
        .map(|r| shadows.blocked(r.light as usize, 1, &r.ray, r.t_max, &mut stats))
        .collect();
    (blocked, stats)
}

/// Million rays per second over as many passes as last `min_sample`.
fn sample(shadows: &Shadows, rays: &RaySet, options: &MeasureOptions) -> f64 {
    let watch = options.clock.start();
    let mut passes = 0u64;
    let mut stats = Stats::default();
    loop {
        // Each pass starts with an empty cache, as a tile does.
        begin_piece();
        for r in &rays.shadow {
            std::hint::black_box(shadows.blocked(r.light as usize, 1, &r.ray, r.t_max, &mut stats));
        }
        passes += 1;
        if watch.elapsed() >= options.min_sample {
            break;
        }
    }
    let secs = watch.elapsed().as_secs_f64().max(1e-9);
    (passes * rays.shadow.len() as u64) as f64 / secs / 1e6
}
