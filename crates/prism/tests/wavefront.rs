//! The wavefront path tracer against the one-path-at-a-time tracer: every sample is the
//! same operations on the same random numbers, so images and ray counts are equal bit for
//! bit, whatever the queue's size, the filter, the tile size or the thread count.

use prism::integrator::{CameraBatch, CameraTracer, WavefrontPathTracer};
use prism::math::hash::Stream;
use prism::math::{Color, Ray};
use prism::options::IntegratorKind;
use prism::render::FilterKind;
use prism::render::{
    render, render_with, sampler_method, IntegratorMethod, Progressive, RenderResult, Tile,
};
use prism::sampling::SamplerKind;
use prism::scene::{builtin, PreparedScene};
use prism::Stats;
use prism::{RenderOptions, Scene};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

/// The path tracer with a queue of `0` paths.
struct Queue(usize);

impl IntegratorMethod for Queue {
    fn tracer<'a>(
        &self,
        scene: &'a PreparedScene<'a>,
        options: &RenderOptions,
    ) -> Box<dyn CameraTracer + 'a> {
        Box::new(WavefrontPathTracer::with_capacity(scene, options, self.0))
    }
}

fn options(scene: &Scene) -> RenderOptions {
    RenderOptions {
        // Not whole packets or tiles: the edges' short blocks go through the queue too.
        width: 45,
        height: 30,
        samples: 2,
        sampler: SamplerKind::Jittered,
        integrator: IntegratorKind::Path,
        max_depth: 8,
        threads: 2,
        tile_size: 16,
        ..scene.options.clone()
    }
}

fn rendered(scene: &Scene, o: &RenderOptions) -> RenderResult {
    let prepared = scene.prepare_for(o);
    render(&prepared, o, &|_| {}, &AtomicBool::new(false)).unwrap()
}

fn with_queue(scene: &Scene, o: &RenderOptions, paths: usize) -> RenderResult {
    let prepared = scene.prepare_for(o);
    render_with(
        &prepared,
        o,
        Tile::full(o.width, o.height),
        sampler_method(o.sampler),
        &Queue(paths),
        &|_| {},
        &AtomicBool::new(false),
    )
    .unwrap()
}

/// The two renders have the same pixels and the same rays, per pixel too.
fn assert_same(a: &RenderResult, b: &RenderResult, what: &str) {
    assert_eq!(a.film.pixels, b.film.pixels, "{what}: pixels differ");
    assert_eq!(a.stats.primary_rays, b.stats.primary_rays, "{what}");
    assert_eq!(a.stats.primary_hits, b.stats.primary_hits, "{what}");
    assert_eq!(a.stats.shadow_rays, b.stats.shadow_rays, "{what}");
    assert_eq!(a.stats.reflected_rays, b.stats.reflected_rays, "{what}");
    assert_eq!(a.stats.refracted_rays, b.stats.refracted_rays, "{what}");
    assert_eq!(
        a.rays.camera, b.rays.camera,
        "{what}: camera rays per pixel"
    );
    assert_eq!(a.rays.total, b.rays.total, "{what}: rays per pixel");
}

#[test]
fn the_wavefront_renders_the_one_path_tracers_image_bit_for_bit() {
    for name in [
        "cornell-light",
        "cornell-light-glass",
        "cornell",
        "sphereflake:1",
    ] {
        let scene = builtin::find(name).unwrap();
        let one = RenderOptions {
            wavefront: false,
            ..options(&scene)
        };
        let reference = rendered(&scene, &one);
        let single = rendered(
            &scene,
            &RenderOptions {
                packets: false,
                ..one.clone()
            },
        );
        assert_same(
            &single,
            &reference,
            &format!("{name}: packets against single paths"),
        );
        let wave = RenderOptions {
            wavefront: true,
            ..one
        };
        assert_same(&rendered(&scene, &wave), &reference, name);
        // Some light reached the film: the comparison is of something.
        assert!(reference.film.pixels.iter().any(|c| c.max_element() > 0.01));
    }
}

#[test]
fn the_queues_size_changes_nothing() {
    let scene = builtin::find("cornell-light-glass").unwrap();
    let o = RenderOptions {
        wavefront: false,
        ..options(&scene)
    };
    let reference = rendered(&scene, &o);
    for paths in [1, 3, 64, 100, 5000] {
        assert_same(
            &with_queue(&scene, &o, paths),
            &reference,
            &format!("{paths} paths in flight"),
        );
    }
}

#[test]
fn threads_tiles_and_filters_change_nothing() {
    let scene = builtin::find("cornell-light").unwrap();
    let base = RenderOptions {
        wavefront: true,
        ..options(&scene)
    };
    for filter in [FilterKind::Box, FilterKind::Gaussian] {
        let o = RenderOptions {
            filter,
            ..base.clone()
        };
        let reference = rendered(
            &scene,
            &RenderOptions {
                wavefront: false,
                threads: 1,
                ..o.clone()
            },
        );
        for (threads, tile_size) in [(1, 8), (2, 16), (2, 40)] {
            let r = rendered(
                &scene,
                &RenderOptions {
                    threads,
                    tile_size,
                    ..o.clone()
                },
            );
            assert_same(
                &r,
                &reference,
                &format!("{filter} filter, {threads} threads, tiles of {tile_size}"),
            );
        }
    }
}

#[test]
fn a_different_seed_gives_a_different_image() {
    // The tests above compare renders that could only be equal by sharing the samples'
    // random numbers: another seed must change the wavefront's image.
    let scene = builtin::find("cornell-light").unwrap();
    let o = RenderOptions {
        wavefront: true,
        ..options(&scene)
    };
    let a = rendered(&scene, &o);
    let b = rendered(&scene, &RenderOptions { seed: 7, ..o });
    assert_ne!(a.film.pixels, b.film.pixels);
}

#[test]
fn progressive_passes_through_the_wavefront_add_the_same_samples() {
    // The viewer's path-traced mode: passes of a few samples per pixel, accumulated.
    let scene = builtin::find("cornell-light-glass").unwrap();
    let o = options(&scene);
    let prepared = scene.prepare_for(&o);
    let frames = |wavefront: bool| {
        let o = RenderOptions {
            wavefront,
            ..o.clone()
        };
        let mut p = Progressive::new(o.width, o.height).unwrap();
        let cancel = AtomicBool::new(false);
        let mut rays = 0;
        for spp in [1, 3, 2] {
            rays += p.advance(&prepared, &o, spp, &cancel).unwrap().total_rays();
        }
        (p.film().pixels, rays)
    };
    let (wave, wave_rays) = frames(true);
    let (one, one_rays) = frames(false);
    assert_eq!(wave, one);
    assert_eq!(wave_rays, one_rays);
}

/// Set by `CancelAfter` once its tracer has been asked for its samples.
static CANCEL: AtomicBool = AtomicBool::new(false);
/// The samples `CancelAfter`'s tracer asked for.
static ASKED: AtomicUsize = AtomicUsize::new(0);

/// The wavefront, cancelling the render (`CANCEL`) after `0` samples.
struct CancelAfter(usize);

struct CancellingTracer<'a> {
    inner: WavefrontPathTracer<'a>,
    after: usize,
}

impl CameraTracer for CancellingTracer<'_> {
    fn trace_camera_ray(&self, ray: &Ray, stream: &Stream, stats: &mut Stats) -> Color {
        self.inner.trace_camera_ray(ray, stream, stats)
    }

    fn traces_batches(&self) -> bool {
        true
    }

    fn trace_camera_batch(&self, batch: CameraBatch<'_>, stats: &mut Stats) {
        let sample = batch.sample;
        let mut counting = |i| {
            let asked = ASKED.fetch_add(1, Ordering::Relaxed) + 1;
            if asked > self.after {
                CANCEL.store(true, Ordering::Relaxed);
            }
            sample(i)
        };
        let counted = CameraBatch {
            count: batch.count,
            sample: &mut counting,
            done: batch.done,
        };
        self.inner.trace_camera_batch(counted, stats)
    }
}

impl IntegratorMethod for CancelAfter {
    fn tracer<'a>(
        &self,
        scene: &'a PreparedScene<'a>,
        options: &RenderOptions,
    ) -> Box<dyn CameraTracer + 'a> {
        Box::new(CancellingTracer {
            inner: WavefrontPathTracer::new(scene, options),
            after: self.0,
        })
    }
}

#[test]
fn a_cancel_stops_the_batch_within_the_tile() {
    let scene = builtin::find("cornell-light").unwrap();
    // One tile of 64 × 64 pixels at 16 samples: 65,536 samples in one batch.
    let o = RenderOptions {
        width: 64,
        height: 64,
        samples: 4,
        threads: 1,
        tile_size: 64,
        ..options(&scene)
    };
    let prepared = scene.prepare_for(&o);
    let r = render_with(
        &prepared,
        &o,
        Tile::full(o.width, o.height),
        sampler_method(o.sampler),
        &CancelAfter(1000),
        &|_| {},
        &CANCEL,
    )
    .unwrap();
    assert!(!r.complete);
    // The sample asked after the cancel was refused, and none after it.
    assert_eq!(ASKED.load(Ordering::Relaxed), 1001);
}

#[test]
fn a_tile_of_more_samples_than_a_batch_renders_the_same() {
    // 24 × 24 pixels in one tile (nine blocks) at 256 samples a pixel: 147,456 samples,
    // traced as batches of four, four and one block.
    let scene = builtin::find("cornell-light").unwrap();
    let o = RenderOptions {
        width: 24,
        height: 24,
        samples: 16,
        tile_size: 24,
        threads: 1,
        max_depth: 4,
        ..options(&scene)
    };
    let one = rendered(
        &scene,
        &RenderOptions {
            wavefront: false,
            ..o.clone()
        },
    );
    assert_same(&rendered(&scene, &o), &one, "batches of whole blocks");
}
