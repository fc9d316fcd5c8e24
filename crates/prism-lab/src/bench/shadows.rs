//! Measuring shadow methods (`integrator::ShadowSpec`) on a fixed workload: the shadow rays
//! of a `RaySet`, in pixel order as a render meets them, answered by each method in turns
//! (sample r of every method before sample r + 1 of any), each held to the accelerator's
//! answers. Beside the methods, one ray at a time, the accelerator's any-hit query in
//! packets, as a render traces the shadow rays of the any-hit method (`PacketShadows`).

use super::{MeasureOptions, RaySet};
use prism::accel::PACKET_MAX;
use prism::integrator::{begin_piece, ShadowMethod, ShadowSpec, Shadows};
use prism::math::Ray;
use prism::options::PACKET_EDGE;
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
    let packets = PacketShadows::new(rays);
    let mut results: Vec<ShadowMeasured> = built
        .iter()
        .zip(specs)
        .map(|((shadows, build), spec)| ShadowMeasured {
            build_ms: build.as_secs_f64() * 1e3,
            memory_bytes: shadows
                .buffer_info()
                .iter()
                .flatten()
                .map(|b| b.memory_bytes)
                .sum(),
            notes: shadows
                .unbuilt
                .iter()
                .enumerate()
                .filter_map(|(i, n)| n.as_ref().map(|n| format!("light {i}: {n}")))
                .collect(),
            ..measured(spec.to_string(), answers(shadows, rays), &reference)
        })
        .collect();
    // Beside the methods one ray at a time, the methods as a render traces shadow rays, in
    // packets: any-hit always, and every other method asked for that answers packets.
    let any_hit = Shadows::new(prepared, ShadowSpec::default());
    let mut in_packets: Vec<(String, &Shadows)> =
        vec![(format!("any-hit, packets of {PACKET_MAX}"), &any_hit)];
    for ((shadows, _), spec) in built.iter().zip(specs) {
        if !matches!(spec.method, ShadowMethod::AnyHit | ShadowMethod::Auto) {
            in_packets.push((format!("{spec}, packets of {PACKET_MAX}"), shadows));
        }
    }
    for (method, shadows) in &in_packets {
        results.push(measured(
            method.clone(),
            packets.answers(shadows),
            &reference,
        ));
    }
    let mut samples: Vec<Vec<f64>> = vec![Vec::new(); specs.len() + in_packets.len()];
    let started = Instant::now();
    for _ in 0..options.repeat.max(1) {
        for (i, (shadows, _)) in built.iter().enumerate() {
            samples[i].push(sample(shadows, rays, options));
        }
        for (k, (_, shadows)) in in_packets.iter().enumerate() {
            samples[specs.len() + k].push(packets.sample(shadows, options));
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

/// A method's figures from its answers and their work (no build, no notes; not yet timed),
/// held to the `reference` answers.
fn measured(
    method: String,
    (blocked, stats): (Vec<bool>, Stats),
    reference: &[bool],
) -> ShadowMeasured {
    let n = blocked.len().max(1) as f64;
    ShadowMeasured {
        method,
        build_ms: 0.0,
        memory_bytes: 0,
        rays: blocked.len(),
        blocked: blocked.iter().filter(|&&b| b).count(),
        tests_per_ray: stats.primitive_tests as f64 / n,
        node_visits_per_ray: stats.node_visits as f64 / n,
        cache_hit_rate: stats.shadow_cache_hits as f64 / n,
        fallback_rate: stats.light_buffer_fallbacks as f64 / n,
        mrays_per_s: 0.0,
        mismatch: blocked != reference,
        notes: Vec::new(),
    }
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

/// Million rays per second of `pass`, which traces `rays` rays, over as many passes as
/// last `min_sample`.
fn mrays_per_s(options: &MeasureOptions, rays: usize, mut pass: impl FnMut()) -> f64 {
    let watch = options.clock.start();
    let mut passes = 0u64;
    loop {
        pass();
        passes += 1;
        if watch.elapsed() >= options.min_sample {
            break;
        }
    }
    let secs = watch.elapsed().as_secs_f64().max(1e-9);
    (passes * rays as u64) as f64 / secs / 1e6
}

/// Million rays per second of `shadows`, one ray at a time.
fn sample(shadows: &Shadows, rays: &RaySet, options: &MeasureOptions) -> f64 {
    let mut stats = Stats::default();
    mrays_per_s(options, rays.shadow.len(), || {
        // Each pass starts with an empty cache, as a tile does.
        begin_piece();
        for r in &rays.shadow {
            std::hint::black_box(shadows.blocked(r.light as usize, 1, &r.ray, r.t_max, &mut stats));
        }
    })
}

/// The shadow rays gathered into packets as a render makes them: the rays of one light from
/// one `PACKET_EDGE` × `PACKET_EDGE` block of pixels, at most `PACKET_MAX` to a packet.
struct PacketShadows {
    /// The rays in packet order, their bounds, and each one's index in `RaySet::shadow`.
    rays: Vec<Ray>,
    t_max: Vec<f32>,
    index: Vec<usize>,
    /// Where each packet starts in `rays`, and where the last one ends.
    starts: Vec<usize>,
    /// Each packet's light.
    lights: Vec<usize>,
}

impl PacketShadows {
    fn new(set: &RaySet) -> PacketShadows {
        let edge = PACKET_EDGE;
        let blocks_across = set.width.div_ceil(edge).max(1);
        let block = |pixel: u32| {
            let (x, y) = (pixel % set.width.max(1), pixel / set.width.max(1));
            (y / edge) * blocks_across + x / edge
        };
        let key = |i: usize| (block(set.shadow[i].pixel), set.shadow[i].light);
        // Stable: within a packet the rays keep pixel order, as in a block's camera packet.
        let mut order: Vec<usize> = (0..set.shadow.len()).collect();
        order.sort_by_key(|&i| key(i));
        let mut starts = Vec::new();
        for k in 0..order.len() {
            let full = starts.last().is_some_and(|&s| k - s == PACKET_MAX);
            if k == 0 || key(order[k]) != key(order[k - 1]) || full {
                starts.push(k);
            }
        }
        let lights = starts
            .iter()
            .map(|&k| set.shadow[order[k]].light as usize)
            .collect();
        starts.push(order.len());
        PacketShadows {
            rays: order.iter().map(|&i| set.shadow[i].ray).collect(),
            t_max: order.iter().map(|&i| set.shadow[i].t_max).collect(),
            index: order,
            starts,
            lights,
        }
    }

    /// Answers every packet with `shadows` (from camera-ray hits, depth 1, the cache
    /// starting empty as a tile's does); `blocked[i]` is for `RaySet::shadow[i]`.
    fn trace(&self, shadows: &Shadows, blocked: &mut [bool], stats: &mut Stats) {
        let mut answers = [false; PACKET_MAX];
        begin_piece();
        for (w, &light) in self.starts.windows(2).zip(&self.lights) {
            let (a, b) = (w[0], w[1]);
            shadows.blocked_packet(
                light,
                1,
                &self.rays[a..b],
                &self.t_max[a..b],
                &mut answers[..b - a],
                stats,
            );
            for (k, &answer) in answers[..b - a].iter().enumerate() {
                blocked[self.index[a + k]] = answer;
            }
        }
    }

    fn answers(&self, shadows: &Shadows) -> (Vec<bool>, Stats) {
        let mut stats = Stats::default();
        let mut blocked = vec![false; self.index.len()];
        self.trace(shadows, &mut blocked, &mut stats);
        (blocked, stats)
    }

    /// Million rays per second of the packets (`mrays_per_s`).
    fn sample(&self, shadows: &Shadows, options: &MeasureOptions) -> f64 {
        let mut stats = Stats::default();
        let mut blocked = vec![false; self.index.len()];
        mrays_per_s(options, self.index.len(), || {
            self.trace(shadows, &mut blocked, &mut stats);
            std::hint::black_box(&blocked);
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use prism::accel::AccelSpec;
    use prism::scene::builtin;

    /// Packets hold the rays of one light and one block of pixels, each ray once, and the
    /// packet row answers as every method does.
    #[test]
    fn packets_group_a_block_and_a_light_and_answer_as_single_rays() {
        let scene = builtin::find("pearls").expect("built-in scene");
        let prepared = scene.prepare(&AccelSpec::default());
        let rays = RaySet::generate(&prepared, 40, 30).expect("camera");
        assert!(rays.shadow.len() > 100, "{} shadow rays", rays.shadow.len());
        let packets = PacketShadows::new(&rays);
        let mut seen = vec![false; rays.shadow.len()];
        for w in packets.starts.windows(2) {
            let members = &packets.index[w[0]..w[1]];
            assert!(!members.is_empty() && members.len() <= PACKET_MAX);
            let key = |i: usize| {
                let r = &rays.shadow[i];
                let (x, y) = (r.pixel % rays.width, r.pixel / rays.width);
                (x / PACKET_EDGE, y / PACKET_EDGE, r.light)
            };
            assert!(members.iter().all(|&i| key(i) == key(members[0])));
            assert!(members.windows(2).all(|p| p[0] < p[1]), "pixel order");
            for &i in members {
                assert!(!seen[i]);
                seen[i] = true;
            }
        }
        assert!(seen.iter().all(|&s| s));
        let options = MeasureOptions {
            repeat: 1,
            min_sample: Duration::ZERO,
            ..MeasureOptions::default()
        };
        let specs: Vec<ShadowSpec> = ["any-hit", "light-buffer", "both"]
            .iter()
            .map(|s| s.parse().unwrap())
            .collect();
        let measured = measure_shadow_methods(&prepared, &rays, &specs, &options);
        let methods: Vec<&str> = measured.iter().map(|m| m.method.as_str()).collect();
        assert_eq!(
            methods[3..],
            [
                "any-hit, packets of 64",
                "light-buffer, packets of 64",
                "both, packets of 64"
            ]
        );
        assert!(measured.iter().all(|m| !m.mismatch && m.mrays_per_s > 0.0));
        assert!(measured.iter().all(|m| m.blocked == measured[0].blocked));
        assert!(measured[0].blocked > 0);
    }
}
