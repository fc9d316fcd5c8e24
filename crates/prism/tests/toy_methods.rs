//! Samplers and integrators are methods behind one trait each (`render::SamplerMethod`,
//! `render::IntegratorMethod`): a toy of each, declared in this file alone, renders
//! through `render::render_with` like the library's own, and is held to them.

use prism::integrator::CameraTracer;
use prism::math::hash::Stream;
use prism::math::{Color, Ray, Vec2};
use prism::render::{
    render, render_tiled, render_with, sampler_method, IntegratorMethod, Job, PixelSamples,
    RenderError, RenderResult, SamplerMethod, Tile, Traced,
};
use prism::sampling::SamplerKind;
use prism::scene::{builtin, PreparedScene};
use prism::{RenderOptions, Scene, Stats};
use std::sync::atomic::AtomicBool;

/// The toy sampler: `n` samples along the pixel's diagonal, at `shift` + (i + ½)/n.
struct Diagonal {
    n: u32,
    shift: f32,
}

impl PixelSamples for Diagonal {
    fn count(&self) -> u32 {
        self.n
    }

    fn offsets(&self, _px: u32, _py: u32, out: &mut Vec<Vec2>) {
        for i in 0..self.n {
            let s = self.shift + (i as f32 + 0.5) / self.n as f32;
            out.push(Vec2::new(s, s));
        }
    }
}

impl SamplerMethod for Diagonal {
    fn render(&self, job: &Job, _options: &RenderOptions) -> Result<Traced, RenderError> {
        job.render_pixels(self)
    }
}

/// The toy integrator: the distance to the first hit as a grey, 1 / (1 + t); black on a
/// miss.
struct Depth;

struct DepthTracer<'a> {
    scene: &'a PreparedScene<'a>,
}

impl CameraTracer for DepthTracer<'_> {
    fn trace_camera_ray(&self, ray: &Ray, _stream: &Stream, stats: &mut Stats) -> Color {
        stats.primary_rays += 1;
        let s = self.scene;
        match s
            .intersector
            .intersect(&s.scene.geometry, ray, f32::INFINITY, stats)
        {
            Some(hit) => Color::splat(1.0 / (1.0 + hit.t)),
            None => Color::ZERO,
        }
    }
}

impl IntegratorMethod for Depth {
    fn tracer<'a>(
        &self,
        scene: &'a PreparedScene<'a>,
        _options: &RenderOptions,
    ) -> Box<dyn CameraTracer + 'a> {
        Box::new(DepthTracer { scene })
    }
}

fn options(scene: &Scene, threads: usize) -> RenderOptions {
    RenderOptions {
        width: 37,
        height: 23,
        threads,
        tile_size: 8,
        ..scene.options.clone()
    }
}

fn with(
    scene: &Scene,
    options: &RenderOptions,
    region: Tile,
    sampler: &dyn SamplerMethod,
    integrator: &dyn IntegratorMethod,
) -> RenderResult {
    let prepared = scene.prepare_for(options);
    render_with(
        &prepared,
        options,
        region,
        sampler,
        integrator,
        &|_| {},
        &AtomicBool::new(false),
    )
    .unwrap()
}

fn whitted() -> &'static dyn IntegratorMethod {
    prism::render::integrator_method(prism::options::IntegratorKind::Whitted)
}

fn full(o: &RenderOptions) -> Tile {
    Tile::full(o.width, o.height)
}

#[test]
fn a_toy_sampler_renders_as_the_library_pattern_it_equals() {
    let scene = builtin::find("whitted").unwrap();
    let base = options(&scene, 2);
    let prepared = scene.prepare_for(&base);
    let library = |sampler, samples| {
        let o = RenderOptions {
            sampler,
            samples,
            ..base.clone()
        };
        render(&prepared, &o, &|_| {}, &AtomicBool::new(false)).unwrap()
    };
    // One sample at the centre is the centre sampler, bit for bit, statistics too.
    let one = Diagonal { n: 1, shift: 0.0 };
    let toy = with(&scene, &base, full(&base), &one, whitted());
    let centre = library(SamplerKind::Centre, 1);
    assert_eq!(toy.film.pixels, centre.film.pixels);
    assert_eq!(toy.stats.primary_rays, centre.stats.primary_rays);
    // Two along the diagonal are not the 2 × 2 grid, and a shifted sample is not the centre:
    // the comparison can fail.
    let two = with(
        &scene,
        &base,
        full(&base),
        &Diagonal { n: 2, shift: 0.0 },
        whitted(),
    );
    assert_eq!(two.stats.primary_rays, 2 * 37 * 23);
    assert_ne!(two.film.pixels, library(SamplerKind::Grid, 2).film.pixels);
    let shifted = Diagonal { n: 1, shift: 0.25 };
    let moved = with(&scene, &base, full(&base), &shifted, whitted());
    assert_ne!(moved.film.pixels, centre.film.pixels);
}

#[test]
fn a_toy_sampler_is_deterministic_and_renders_regions() {
    let scene = builtin::find("whitted").unwrap();
    let toy = Diagonal { n: 3, shift: 0.0 };
    let one = with(
        &scene,
        &options(&scene, 1),
        full(&options(&scene, 1)),
        &toy,
        whitted(),
    );
    let two = options(&scene, 2);
    let both = with(&scene, &two, full(&two), &toy, whitted());
    assert_eq!(one.film.pixels, both.film.pixels);
    let region = Tile {
        x0: 5,
        y0: 3,
        x1: 30,
        y1: 17,
    };
    let part = with(&scene, &two, region, &toy, whitted());
    for y in region.y0..region.y1 {
        for x in region.x0..region.x1 {
            assert_eq!(
                part.film.get(x - region.x0, y - region.y0),
                both.film.get(x, y),
                "pixel ({x}, {y})"
            );
        }
    }
}

#[test]
fn a_toy_integrator_renders_through_every_sampler() {
    let scene = builtin::find("cornell").unwrap();
    let o = options(&scene, 2);
    let centre = sampler_method(SamplerKind::Centre);
    let r = with(&scene, &o, full(&o), centre, &Depth);
    // Each pixel is 1 / (1 + t) of its centre ray's first hit, black where it misses.
    let prepared = scene.prepare_for(&o);
    let camera = scene.camera.setup(o.width, o.height).unwrap();
    let (mut stats, mut hits) = (Stats::default(), 0);
    for y in 0..o.height {
        for x in 0..o.width {
            let ray = camera.ray(x as f32 + 0.5, y as f32 + 0.5);
            let expected = match prepared.intersector.intersect(
                &scene.geometry,
                &ray,
                f32::INFINITY,
                &mut stats,
            ) {
                Some(hit) => {
                    hits += 1;
                    Color::splat(1.0 / (1.0 + hit.t))
                }
                None => Color::ZERO,
            };
            assert_eq!(r.film.get(x, y), expected, "pixel ({x}, {y})");
        }
    }
    assert!(hits > 37 * 23 / 2, "{hits} hits");
    assert_eq!(r.stats.primary_rays, 37 * 23);
    assert_eq!(r.stats.shadow_rays, 0, "the toy traces no shadow rays");
    // The lattice samplers drive it too, and refuse a region as for any integrator.
    let adaptive = sampler_method(SamplerKind::Adaptive);
    let refined = with(&scene, &o, full(&o), adaptive, &Depth);
    assert!(refined.stats.primary_rays > (38 * 24) as u64);
    let prepared = scene.prepare_for(&o);
    let region = Tile {
        x0: 0,
        y0: 0,
        x1: 4,
        y1: 4,
    };
    let err = render_with(
        &prepared,
        &o,
        region,
        adaptive,
        &Depth,
        &|_| {},
        &AtomicBool::new(false),
    )
    .err()
    .expect("a lattice sampler renders whole images only");
    assert!(err.to_string().contains("renders no region"), "{err}");
}

/// The default `IntegratorMethod::render` is `render_tiled` with the method's tracer.
#[test]
fn the_tiled_render_is_the_default() {
    let scene = builtin::find("whitted").unwrap();
    let o = options(&scene, 2);
    let prepared = scene.prepare_for(&o);
    let sampler = sampler_method(SamplerKind::Jittered);
    let tiled = render_tiled(
        &prepared,
        &o,
        full(&o),
        sampler,
        Depth.tracer(&prepared, &o),
        &|_| {},
        &AtomicBool::new(false),
    )
    .unwrap();
    let by_method = with(&scene, &o, full(&o), sampler, &Depth);
    assert_eq!(tiled.film.pixels, by_method.film.pixels);
}
