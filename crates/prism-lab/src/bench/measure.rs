//! Measuring one method on one scene's `RaySet`: build time (median of several builds when
//! a build is cheap, the methods built in turns), what was built, and for primary rays (nearest hit), shadow rays
//! (any hit) and incoherent rays (nearest hit) the node visits and primitive tests per ray and the throughput (median of the
//! repetitions, the methods timed in turns).

use super::rays::{RaySet, ShadowRay};
use super::Clock;
use prism::accel::{AccelInfo, AccelSpec, SceneIntersector};
use prism::geometry::Geometry;
use prism::math::Ray;
use prism::scene::Scene;
use prism::stats::Stats;
use rayon::prelude::*;
use serde::Serialize;
use std::time::Duration;

/// Rays per piece of work handed to a thread: large enough that scheduling costs nothing
/// next to the tracing.
const CHUNK: usize = 1024;

/// How long and how often a measurement runs, and on which clock.
#[derive(Clone, Debug)]
pub struct MeasureOptions {
    /// Timed repetitions of each ray kind (at least 1); the median counts.
    pub repeat: usize,
    /// Builds are repeated while the builds so far took less than this in all.
    pub build_budget: Duration,
    /// Builds at most.
    pub max_builds: usize,
    /// Repetitions stop early once they have taken this long in all, so a hopeless method
    /// on a large scene does not hold the whole matrix up.
    pub trace_budget: Duration,
    /// A timed repetition runs as many passes as it takes to last about this long, so that
    /// passes of a few milliseconds are not lost in timer and scheduler noise.
    pub min_sample: Duration,
    /// What the times are read from: process CPU time keeps single-threaded figures
    /// steady on a shared machine; with several threads it sums them, so wall time is
    /// the honest choice there.
    pub clock: Clock,
}

impl Default for MeasureOptions {
    fn default() -> Self {
        MeasureOptions {
            repeat: 5,
            build_budget: Duration::from_millis(500),
            max_builds: 5,
            trace_budget: Duration::from_secs(3),
            min_sample: Duration::from_millis(30),
            clock: Clock::ProcessCpu,
        }
    }
}

/// Primary or shadow rays traced with one method.
#[derive(Clone, Debug, Default, Serialize)]
pub struct RayKindResult {
    /// Rays in the set.
    pub rays: usize,
    /// Rays that hit (primary) or were blocked (shadow).
    pub hits: usize,
    /// Mean acceleration-structure node visits per ray.
    pub node_visits_per_ray: f64,
    /// Mean ray–primitive tests per ray.
    pub primitive_tests_per_ray: f64,
    /// Median time of one pass over all the rays.
    pub seconds: f64,
    /// Millions of rays per second, from the median time.
    pub mrays_per_s: f64,
    /// Passes timed.
    pub repetitions: usize,
}

/// Everything measured for one method on one scene.
#[derive(Clone, Debug, Serialize)]
pub struct Measured {
    /// The structure's figures: nodes, memory, depth.
    pub accel: AccelInfo,
    /// Median build time.
    pub build_ms: f64,
    /// Builds timed.
    pub builds: usize,
    /// The camera rays.
    pub primary: RayKindResult,
    /// The shadow rays.
    pub shadow: RayKindResult,
    /// The incoherent rays.
    pub incoherent: RayKindResult,
    /// What the method answered (an untimed pass), to compare with the reference's.
    pub primary_digest: super::HitDigest,
    /// What the method answered for the shadow rays.
    pub shadow_digest: super::HitDigest,
    /// What the method answered for the incoherent rays.
    pub incoherent_digest: super::HitDigest,
}

/// Builds every method in `specs` over `scene`, in turns as the rays (`build_in_turns`),
/// then times them on `rays` in turns: sample
/// r of every method before sample r + 1 of any, so that a slow spell on a shared machine
/// falls on all methods alike and the ratios between them hold. On the current rayon pool.
/// `progress` hears each method's index as its build starts. A BVH's `build=auto` is
/// told one pass over `rays` (`RaySet::len`), so it picks as it would for a render that
/// traces them.
pub fn measure_all(
    scene: &Scene,
    specs: &[AccelSpec],
    rays: &RaySet,
    options: &MeasureOptions,
    progress: impl Fn(usize),
) -> Vec<Measured> {
    let expected = vec![rays.len() as f64; specs.len()];
    measure_all_expecting(scene, specs, &expected, rays, options, progress)
}

/// As `measure_all`, with the `build=auto` of `specs[i]` told `expected_rays[i]` rays
/// instead: a render of several passes over the rays (`prism bench --auto-passes`).
pub fn measure_all_expecting(
    scene: &Scene,
    specs: &[AccelSpec],
    expected_rays: &[f64],
    rays: &RaySet,
    options: &MeasureOptions,
    progress: impl Fn(usize),
) -> Vec<Measured> {
    assert_eq!(specs.len(), expected_rays.len(), "one ray count per spec");
    let specs: Vec<AccelSpec> = (specs.iter().zip(expected_rays))
        .map(|(spec, &rays)| spec.with_expected_rays(rays))
        .collect();
    let built = build_in_turns(scene, &specs, options, progress);
    let geometry = &scene.geometry;
    let primary_passes: Vec<_> = built
        .iter()
        .map(|(intersector, _)| move || trace_primary(intersector, geometry, &rays.primary))
        .collect();
    let primary = interleaved(options, rays.primary.len(), &primary_passes);
    let shadow_passes: Vec<_> = built
        .iter()
        .map(|(intersector, _)| move || trace_shadow(intersector, geometry, &rays.shadow))
        .collect();
    let shadow = interleaved(options, rays.shadow.len(), &shadow_passes);
    let incoherent_passes: Vec<_> = built
        .iter()
        .map(|(intersector, _)| move || trace_primary(intersector, geometry, &rays.incoherent))
        .collect();
    let incoherent = interleaved(options, rays.incoherent.len(), &incoherent_passes);
    built
        .into_iter()
        .zip(primary.into_iter().zip(shadow).zip(incoherent))
        .map(
            |((intersector, mut build_times), ((primary, shadow), incoherent))| Measured {
                primary_digest: super::digest::primary(&intersector, geometry, &rays.primary),
                shadow_digest: super::digest::shadow(&intersector, geometry, &rays.shadow),
                incoherent_digest: super::digest::primary(&intersector, geometry, &rays.incoherent),
                accel: intersector.accel.info(),
                build_ms: median(&mut build_times),
                builds: build_times.len(),
                primary,
                shadow,
                incoherent,
            },
        )
        .collect()
}

/// Builds every spec once (`progress` hears its index), then again in rounds, every spec
/// once a round while its builds so far took less than the budget, up to `max_builds`: so
/// that a slow spell on a shared machine falls on all builders alike, as the rays do. The
/// first trees, and each spec's build times in ms.
fn build_in_turns(
    scene: &Scene,
    specs: &[AccelSpec],
    options: &MeasureOptions,
    progress: impl Fn(usize),
) -> Vec<(SceneIntersector, Vec<f64>)> {
    let timed = |spec: &AccelSpec| {
        let start = options.clock.start();
        let built = SceneIntersector::build(&scene.geometry, spec);
        (built, start.elapsed())
    };
    let mut built: Vec<(SceneIntersector, Vec<f64>, Duration)> = (specs.iter().enumerate())
        .map(|(i, spec)| {
            progress(i);
            let (tree, took) = timed(spec);
            (tree, vec![took.as_secs_f64() * 1e3], took)
        })
        .collect();
    for _ in 1..options.max_builds.max(1) {
        for (spec, (_, times, spent)) in specs.iter().zip(&mut built) {
            if *spent < options.build_budget {
                let (tree, took) = timed(spec);
                drop(tree);
                times.push(took.as_secs_f64() * 1e3);
                *spent += took;
            }
        }
    }
    built
        .into_iter()
        .map(|(tree, times, _)| (tree, times))
        .collect()
}

/// For each method's `pass`: counts the work of one pass, then times up to `repeat`
/// samples (within the budget), each of enough passes to last `min_sample`, taking the
/// methods in turns; reports the median time of a pass.
fn interleaved<F: Fn() -> (usize, Stats)>(
    options: &MeasureOptions,
    rays: usize,
    passes: &[F],
) -> Vec<RayKindResult> {
    struct Run {
        hits: usize,
        stats: Stats,
        passes: usize,
        times: Vec<f64>,
        spent: Duration,
    }
    let mut runs: Vec<Run> = passes
        .iter()
        .map(|pass| {
            let start = options.clock.start();
            let (hits, stats) = std::hint::black_box(pass());
            let first = start.elapsed();
            let passes = if first.is_zero() {
                1000
            } else {
                (options.min_sample.as_secs_f64() / first.as_secs_f64()).ceil() as usize
            }
            .clamp(1, 1000);
            let mut times = Vec::new();
            if passes == 1 && first >= options.trace_budget {
                // One pass took the whole budget: it is the only sample there will be.
                times.push(first.as_secs_f64());
            }
            Run {
                hits,
                stats,
                passes,
                times,
                spent: first,
            }
        })
        .collect();
    for _ in 0..options.repeat.max(1) {
        for (run, pass) in runs.iter_mut().zip(passes) {
            let wanted = run.times.len() < options.repeat.max(1)
                && (run.times.is_empty() || run.spent < options.trace_budget);
            if !wanted {
                continue;
            }
            let start = options.clock.start();
            for _ in 0..run.passes {
                std::hint::black_box(pass());
            }
            let took = start.elapsed();
            run.times.push(took.as_secs_f64() / run.passes as f64);
            run.spent += took;
        }
    }
    let per_ray = |n: u64| {
        if rays == 0 {
            0.0
        } else {
            n as f64 / rays as f64
        }
    };
    runs.into_iter()
        .map(|mut run| {
            let seconds = median(&mut run.times);
            RayKindResult {
                rays,
                hits: run.hits,
                node_visits_per_ray: per_ray(run.stats.node_visits),
                primitive_tests_per_ray: per_ray(run.stats.primitive_tests),
                seconds,
                mrays_per_s: if seconds > 0.0 {
                    rays as f64 / seconds / 1e6
                } else {
                    0.0
                },
                repetitions: run.times.len(),
            }
        })
        .collect()
}

fn trace_primary(
    intersector: &SceneIntersector,
    geometry: &Geometry,
    rays: &[Ray],
) -> (usize, Stats) {
    count_hits(rays, |ray, stats| {
        intersector
            .intersect(geometry, ray, f32::INFINITY, stats)
            .is_some()
    })
}

fn trace_shadow(
    intersector: &SceneIntersector,
    geometry: &Geometry,
    rays: &[ShadowRay],
) -> (usize, Stats) {
    count_hits(rays, |s, stats| {
        intersector.occluded(geometry, &s.ray, s.t_max, stats)
    })
}

/// The rays of `items` that `hit` says hit, tested in chunks in parallel, and the
/// statistics of all the tests.
fn count_hits<T: Sync>(items: &[T], hit: impl Fn(&T, &mut Stats) -> bool + Sync) -> (usize, Stats) {
    items
        .par_chunks(CHUNK)
        .map(|chunk| {
            let mut stats = Stats::default();
            let n = chunk.iter().filter(|item| hit(item, &mut stats)).count();
            (n, stats)
        })
        .reduce(
            || (0, Stats::default()),
            |(a, mut s), (b, t)| {
                s += t;
                (a + b, s)
            },
        )
}

fn median(values: &mut [f64]) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    values.sort_by(f64::total_cmp);
    let n = values.len();
    if n % 2 == 1 {
        values[n / 2]
    } else {
        0.5 * (values[n / 2 - 1] + values[n / 2])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The pearls scene, its rays at `width` × `height`, `bvh:build=auto` and options for
    /// one quick build and pass.
    fn auto_on_pearls(width: u32, height: u32) -> (Scene, RaySet, AccelSpec, MeasureOptions) {
        let scene = prism::scene::builtin::find("pearls").expect("built-in scene");
        let prepared = scene.prepare(&AccelSpec::default());
        let rays = RaySet::generate(&prepared, width, height).expect("camera");
        let auto: AccelSpec = "bvh:build=auto".parse().expect("a valid spec");
        let options = MeasureOptions {
            repeat: 1,
            max_builds: 1,
            min_sample: Duration::ZERO,
            ..MeasureOptions::default()
        };
        (scene, rays, auto, options)
    }

    /// `build=auto` chooses for the bench's own rays, not for none (which always picked
    /// the fastest build).
    #[test]
    fn auto_is_built_for_the_rays_the_bench_traces() {
        let (scene, rays, auto, options) = auto_on_pearls(40, 30);
        let measured = measure_all(&scene, &[auto], &rays, &options, |_| {});
        let method = &measured[0].accel.method;
        assert!(rays.len() > 1200, "{} rays", rays.len());
        assert!(
            method.contains(&format!("and {} expected rays", rays.len())),
            "{method}"
        );
    }

    /// Told more rays, `auto` is built for them: the bench's rows for renders of many
    /// passes (`--auto-passes`).
    #[test]
    fn auto_is_built_for_the_rays_it_is_told() {
        let (scene, rays, auto, options) = auto_on_pearls(8, 6);
        let specs = [auto.clone(), auto];
        let measured = measure_all_expecting(&scene, &specs, &[10.0, 5e6], &rays, &options, |_| {});
        for (m, told) in measured
            .iter()
            .zip(["and 10 expected rays", "and 5000000 expected rays"])
        {
            assert!(m.accel.method.contains(told), "{}", m.accel.method);
        }
    }

    #[test]
    fn the_median_is_the_middle_value() {
        assert_eq!(median(&mut [3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&mut [4.0, 1.0, 2.0, 3.0]), 2.5);
        assert_eq!(median(&mut []), 0.0);
    }
}
